"""Writing a file whole or not at all: every command and the language server
write through here, so an interrupted or failed write never leaves half a
file where the user's file was."""

from __future__ import annotations

import os
from pathlib import Path


def write_whole(path: str | Path, data: bytes) -> None:
    """Write `data` to a temporary file beside `path`, then rename it over
    `path`; OSError naming `path` when the folder or the file cannot be
    written (nothing is changed then)."""
    path = Path(path)
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        if path.exists():
            mode = path.stat().st_mode
            # a file marked read-only stays as it is, for root too (who may write anything)
            if path.is_dir() or not mode & 0o222 or not os.access(path, os.W_OK):
                raise PermissionError(13, "Is a directory" if path.is_dir() else "the file is read-only")
        else:
            mode = None
        temporary.write_bytes(data)
        if mode is not None:
            os.chmod(temporary, mode & 0o7777)
        os.replace(temporary, path)
    except OSError as problem:
        raise OSError(problem.errno, problem.strerror or str(problem), str(path)) from None
    finally:
        temporary.unlink(missing_ok=True)
