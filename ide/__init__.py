"""Editor support that knows no LSP (rust-analyzer's `ide` layer): the
incremental reader of a document being edited, locating elements and names
in its text, edits and fixes as text edits, the symbol view of names, the
outline and the conditions of a simulation's watch view. The language server
(`lsp/`) adapts these to the protocol; `ladder check --fix` uses the fixes."""
