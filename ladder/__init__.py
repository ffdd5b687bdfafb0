"""The `ladder` command: the edge where files, arguments and exit codes live."""
