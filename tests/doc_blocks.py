"""The shell blocks of README.md and docs/*.md, as tests/test_docs_commands.py
runs them and .ci/run's package step takes the README's first command.

A fence with the info string `sh` is a shell block. An HTML comment on the
line just before a fence says more about it:

* `<!-- doc-test: hardware -->` before an `sh` block: it needs a board or a
  programmer, so it is only checked, not run;
* `<!-- doc-test: file NAME -->` before any block: the block is a file the
  reader is told to write, and the test writes it as NAME (in the document's
  folder) at that point of the document.
* `<!-- doc-test: output -->` before any block: the block is what the shell
  block before it prints (its standard output), and the test compares the two.

`python tests/doc_blocks.py --first-command README.md` prints the first
command of the document's first shell block.
"""

import re
import sys
from dataclasses import dataclass
from pathlib import Path

SHELL = "sh"
# info strings of shell blocks written some other way: the docs are normalised to `sh`
OTHER_SHELLS = ("bash", "shell", "console", "zsh")
_FENCE = re.compile(r"^(```+|~~~+)\s*([\w+-]*)")
_DIRECTIVE = re.compile(r"^<!--\s*doc-test:\s*(.*?)\s*-->\s*$")


@dataclass(frozen=True)
class Block:
    path: Path
    line: int  # of the block's first line inside the fence (1-based)
    info: str
    text: str
    directive: str  # what the `doc-test:` comment before the fence says, or ""

    @property
    def hardware(self) -> bool:
        return self.directive == "hardware"

    @property
    def shows_output(self) -> bool:
        return self.directive == "output"

    @property
    def file_name(self) -> str | None:
        word, _, name = self.directive.partition(" ")
        return name.strip() if word == "file" and name.strip() else None

    def commands(self) -> list["Command"]:
        """Each command: comments and blank lines go, a line ending in a
        backslash carries on on the next."""
        found: list[Command] = []
        pending: list[str] = []
        start = 0
        for number, line in enumerate(self.text.splitlines(), self.line):
            if not pending and (not line.strip() or line.lstrip().startswith("#")):
                continue
            if not pending:
                start = number
            if line.endswith("\\"):
                pending.append(line[:-1])
                continue
            found.append(Command(start, number, " ".join(part.strip() for part in (*pending, line))))
            pending = []
        if pending:
            found.append(Command(start, start + len(pending) - 1, " ".join(part.strip() for part in pending)))
        return found


@dataclass(frozen=True)
class Command:
    line: int  # its first and last line in the document
    last_line: int
    text: str


def blocks(path: Path) -> list[Block]:
    """Every fenced block of a Markdown file, in order."""
    lines = path.read_text(encoding="utf-8").splitlines()
    found: list[Block] = []
    index = 0
    while index < len(lines):
        match = _FENCE.match(lines[index])
        if not match:
            index += 1
            continue
        fence, info = match.groups()
        before = _DIRECTIVE.match(lines[index - 1]) if index else None
        end = index + 1
        while end < len(lines) and not lines[end].startswith(fence):
            end += 1
        found.append(Block(path, index + 2, info, "\n".join(lines[index + 1:end]) + "\n",
                           before.group(1) if before else ""))
        index = end + 1
    return found


def first_command(path: Path) -> str:
    shell = [block for block in blocks(path) if block.info == SHELL]
    if not shell or not shell[0].commands():
        raise SystemExit(f"{path}: no shell block with a command")
    return shell[0].commands()[0].text


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] != "--first-command":
        raise SystemExit("usage: python tests/doc_blocks.py --first-command FILE.md")
    print(first_command(Path(sys.argv[2])))
