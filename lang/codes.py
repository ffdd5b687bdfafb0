"""Every diagnostic code with its one-line documentation (`ladder explain CODE`).

Codes are stable: LD0xx reading a file, LD1xx names and prefixes, LD2xx
program structure, LD3xx values and timing, LD4xx pins and parts, LD5xx what
a layer or target cannot do. Checks register their own code beside their rule.
"""

from __future__ import annotations

from dataclasses import dataclass

DOCS_URL = "https://textladder.invalid/docs/diagnostics.md#"


@dataclass(frozen=True)
class Code:
    code: str
    summary: str
    doc: str

    @property
    def url(self) -> str:
        return DOCS_URL + self.code.lower()


CODES: dict[str, Code] = {}


def register(code: str, summary: str, doc: str) -> str:
    if code in CODES and CODES[code].summary != summary:
        raise ValueError(f"diagnostic code {code} registered twice")
    CODES[code] = Code(code, summary, doc)
    return code


# reading the text form and LDmicro files
UNREADABLE = register("LD001", "unreadable file",
                      "The file is not text in the expected encoding, or not a ladder program at all.")
SECTION = register("LD002", "malformed section",
                   "A section after the diagram (I/O ASSIGNMENT, VAR LIST, SETTINGS, DETAILS) has a line "
                   "that cannot be read.")
UNKNOWN_ELEMENT = register("LD003", "unknown element",
                           "The drawing has text that is no instruction of the table, or an instruction "
                           "whose name line does not fit it (e.g. `{MOV` with a coil's glyph).")
BROKEN_WIRE = register("LD004", "broken wire",
                       "A wire or element is not connected on its left, or a branch stops before reaching "
                       "a junction or the right rail.")
BAD_JUNCTION = register("LD005", "misaligned junction",
                        "A `+` junction has no `|` connector above or below it, or a vertical connector "
                        "does not end in a `+` junction on a symbol line: the branches do not meet.")
NOT_SERIES_PARALLEL = register("LD006", "not a series/parallel circuit",
                               "The rung's wires form a shape (such as a bridge) that LDmicro cannot "
                               "represent: every rung must be series and parallel blocks.")
STRAY_TEXT = register("LD007", "text with no element under it",
                      "A name or value on a name line sits above no element of the symbol line below it.")
BAD_VALUE = register("LD008", "bad operand value",
                     "An operand has the wrong form: a delay that is not a time, a number that is not "
                     "an integer, a name with characters LDmicro does not allow.")
LD_SYNTAX = register("LD009", "malformed .ld line",
                     "A line of an LDmicro .ld file cannot be read: an unknown keyword, missing fields, "
                     "or a PROGRAM block that is not closed.")
TRUNCATED = register("LD010", "truncated name",
                     "The name ends in `~`: LDmicro cut it when exporting, so the full name is lost. "
                     "Write the whole name (look it up in the .ld file).")
EMPTY_BRANCH = register("LD011", "branch without element",
                        "A parallel branch is a bare wire; draw a SHORT (`+------+`) if a short circuit "
                        "is meant.")
