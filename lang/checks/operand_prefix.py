"""LD112: a pin operand of QUAD ENCOD, PULSER, STEPPER or NPULSE with the wrong prefix."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import COUNTERS, INSTRUCTIONS, TIMERS
from ..labels import label, token
from ..model import Program
from ..values import is_literal
from .common import RUNGS, arg_span, prefix_fixes, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS

# contacts, coils, timers, counters, RES, SET PWM and READ ADC have rules of their own
_OWN_RULE = frozenset(("CONTACTS", "COIL", "RES", "SET_PWM", "READ_ADC") + TIMERS + COUNTERS)
_FIELDS = {
    key: tuple((f.name, f.prefixes) for f in spec.fields if f.prefixes)
    for key, spec in INSTRUCTIONS.items()
    if key not in _OWN_RULE and any(f.prefixes for f in spec.fields)
}
_LETTERS = {"X": "X (input pin)", "Y": "Y (output pin)", "R": "R (internal relay)"}


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for kind, fields in _FIELDS.items():
        for rung, element in index.of_kind(kind):
            for field, prefixes in fields:
                name = token(element.args.get(field))
                if not name or is_literal(name) or name[0] in prefixes:
                    continue
                allowed = " or ".join(_LETTERS.get(p, p) for p in prefixes)
                found.append(report(
                    CODE,
                    f"{label(element)} operand '{field}' = '{name}' in {rung_no(rung)} must start with {allowed}",
                    arg_span(element, field),
                    fixes=prefix_fixes(index, element, field),
                ))
    return found
