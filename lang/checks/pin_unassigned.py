"""LD407: an I/O name with no pin while a part is selected (not when the
program is compiled to C, whose runtime owns the pins). The bare name P of a
classic two-field SET PWM, which LDmicro's loader gives it, needs one too:
LDmicro 5.4 refuses it ("'P' is not assigned") and no back end can guess it."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import NAMES, is_analog, is_pwm

CODE = rule_code(__name__)
SCOPE = NAMES

_WHAT = {"X": "input", "Y": "output", "A": "A/D input", "P": "PWM output"}


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    if not index.pins_matter:
        return []
    found = []
    for name in index.uses:
        analog = is_analog(index, name)
        if name[:1] not in ("X", "Y") and not analog and not is_pwm(index, name):
            continue
        if name.endswith("~"):
            continue  # LD010
        assignment = program.pins.get(name)
        if assignment is not None and assignment.assigned:
            continue
        uses = [u for u in index.uses[name] if u.access != "table"]
        if not uses:
            continue
        first = uses[0]
        what = _WHAT.get(name[0]) or ("A/D input" if analog else "PWM output")
        found.append(report(
            CODE,
            f"{what} '{name}' has no pin: assign it a pin of the {index.device.title} "
            f"(first used in rung {first.rung + 1})",
            first.span,
        ))
    return found
