"""The ladder language server (`ladder lsp`): LSP over stdio, built with pygls.
Glue only: every answer comes from lang/. See docs/lsp.md and docs/lsp-protocol.md."""
