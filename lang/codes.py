"""The registry of diagnostic codes: one row per code in `codes.toml`.

Codes are stable: LD0xx reading a file, LD1xx names and prefixes, LD2xx
program structure, LD3xx values and timing, LD4xx pins and parts, LD5xx what
a target cannot do, LD6xx simulation faults, LD7xx building. Each row gives the
code's summary and documentation (`ladder explain`, docs/diagnostics.md), its
default severity, the check module that reports it, and the review every error
gets: whether LDmicro accepts a program with the problem and, if it does, the
defect that makes it an error here. Modules name their codes with `code()` or
`rule_code()`, so a code used anywhere has a row.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from importlib import resources

GROUPS = {
    "0": "reading a file",
    "1": "names and prefixes",
    "2": "program structure",
    "3": "values and timing",
    "4": "pins and parts",
    "5": "what the target cannot do",
    "6": "simulation",
    "7": "building",
}
# How LDmicro 5.4 treats a program with the problem (None: not a property of a
# program LDmicro compiles, e.g. a text-form reading error or a simulation fault).
LDMICRO_VERDICTS = ("accepts", "complains", "refuses", "crashes")


@dataclass(frozen=True)
class Code:
    code: str
    summary: str
    doc: str
    severity: str
    rule: str | None = None
    fixable: bool = False
    ldmicro: str | None = None
    ldmicro_says: str | None = None
    defect: str | None = None

    @property
    def group(self) -> str:
        return GROUPS[self.code[2]]

    @property
    def configurable(self) -> bool:
        """Whether users may change its severity: not for reading errors (the
        program would silently miss what could not be read) nor for
        simulation faults (the run stops whatever the setting)."""
        return self.code[2] not in "06"


def _load() -> dict[str, Code]:
    rows = tomllib.loads(resources.files(__package__).joinpath("codes.toml").read_text(encoding="utf-8"))
    return {code: Code(code, " ".join(row.pop("summary").split()), " ".join(row.pop("doc").split()), **row)
            for code, row in rows.items()}


CODES: dict[str, Code] = _load()
_BY_RULE = {row.rule: row.code for row in CODES.values() if row.rule}


def code(name: str) -> str:
    """`name`, checked to have a row in the registry."""
    if name not in CODES:
        raise KeyError(f"diagnostic code {name} has no row in lang/codes.toml")
    return name


def rule_code(module: str) -> str:
    """The code of the check rule in `module` (its row names the module)."""
    return _BY_RULE[module.rsplit(".", 1)[1]]


def rules() -> list[str]:
    """The check modules, in code order."""
    return sorted(_BY_RULE, key=lambda rule: _BY_RULE[rule])


# reading the text form and LDmicro files
UNREADABLE = code("LD001")
SECTION = code("LD002")
UNKNOWN_ELEMENT = code("LD003")
BROKEN_WIRE = code("LD004")
BAD_JUNCTION = code("LD005")
NOT_SERIES_PARALLEL = code("LD006")
STRAY_TEXT = code("LD007")
BAD_VALUE = code("LD008")
LD_SYNTAX = code("LD009")
TRUNCATED = code("LD010")
EMPTY_BRANCH = code("LD011")
