"""The checks: one rule per module, one diagnostic code per rule.

Each rule module has `CODE = rule_code(__name__)` (its row in the registry,
`lang/codes.toml`, names the module) and `check(program, index)` returning its
diagnostics. `RULES` is built from the registry; `check_program` builds the shared
`ProgramIndex` once and runs every rule on it; a `Checker` checks a program
again after an edit (`incremental`). docs/diagnostics.md documents every code.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from ..codes import rules
from ..config import NONE, Severities
from ..diagnostics import Diagnostic
from ..index import ProgramIndex
from ..model import Program

# Every rule, in code order: the registry (lang/codes.toml) names each code's module.
RULES: tuple[ModuleType, ...] = tuple(importlib.import_module(f"{__name__}.{rule}") for rule in rules())

from .incremental import Checker, position  # noqa: E402 (it reads RULES)

__all__ = ["RULES", "Checker", "ProgramIndex", "check_program", "position"]


def check_program(program: Program, for_build: bool = False, severities: Severities = NONE,
                  family: str | None = None) -> list[Diagnostic]:
    """Every rule's diagnostics for the program at the project's chosen
    severities, sorted by position; `for_build` when it is about to be
    compiled (`ladder build`, compile on save), where a rule may be stricter
    (LD501) and no error is lowered; `family` when it is compiled for another
    family than its part's (C)."""
    return Checker(for_build, family).check(program, severities=severities)
