"""Editor support that knows no LSP (rust-analyzer's `ide` layer): every
feature an editor offers, as functions on plain values (a document read and
checked, `ide.document.Document`; positions as 0-based lines and character
columns) that answer with frozen dataclasses and enums of their own:
completion, hover, semantic tokens, the outline's symbols and folds,
navigation and rename, code actions, formatting, conversion, the simulation
session; beneath them the analysis of each version of a document (read and
checked again for what an edit changed, results kept per rung), the
incremental reader, locating elements and names in the text, edits and fixes
as text edits, the symbol view of names. The
language server (`lsp/`) only converts these to the protocol and carries
them (transport, settings, scheduling); `ladder check --fix` uses the fixes."""
