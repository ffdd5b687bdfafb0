"""textladder's language server from the libraries bundled with the VS Code extension.

The extension runs this file with the Python it found (docs/editors.md, "Which Python runs the
server"). The bundled libraries come first on sys.path, so that whatever that Python has installed
(another textladder, an older pygls, a package also called `lang`) cannot shadow them.
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "libs"))

from ladder.cli import main  # noqa: E402

sys.exit(main(["lsp"]))
