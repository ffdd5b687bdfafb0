"""Properties of the checks on random valid programs (tests/generators.py):
they never crash, every diagnostic has a registered code and a severity, and
programs built the way LDmicro's editor allows break no shape or prefix rule."""

from __future__ import annotations

from generators import programs
from hypothesis import HealthCheck, given, settings

from lang.checks import check_program
from lang.codes import CODES

# rules the generator respects by construction: end-of-line placement and the
# table's prefixes for contacts, coils, timers, counters, RES, SET PWM and pins
RESPECTED = {"LD101", "LD102", "LD103", "LD104", "LD105", "LD106", "LD107", "LD112", "LD201", "LD202"}


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs())
def test_checks_never_crash_on_valid_programs(program):
    found = check_program(program)
    for d in found:
        assert d.code in CODES
        assert d.severity in ("error", "warning")
        assert d.message
    assert not [d for d in found if d.code in RESPECTED], [d.message for d in found if d.code in RESPECTED]


def test_odd_operands_do_not_crash():
    from lang.model import Element, Program, Rung, Series

    odd = [
        Element("NOT_AN_INSTRUCTION", {}),
        Element("CTU", {"name": 5, "max": 10, "init": None}),
        Element("TON", {"name": "T1", "delay": "(none)"}),
        Element("MOVE", {}),
        Element("LOOK_UP_TABLE", {"dest": "y", "index": "i", "values": (1, "2", "x"), "table": None}),
        Element("PIECEWISE_LINEAR", {"dest": "y", "index": "i", "points": ((0, 0), ("5", "x")), "table": ""}),
        Element("SHIFT_REGISTER", {"name": "r", "stages": "many"}),
        Element("FORMATTED_STRING", {"var": None, "text": None}),
        Element("COIL", {"name": "", "type": None}),
    ]
    program = Program(rungs=[Rung(Series([element])) for element in odd])
    program.settings.mcu = "Atmel AVR ATmega328 28-PDIP"
    program.var_sizes = {"y": 0, "r0": 129, "x": "two"}
    program.rungs.append(Rung(Series([Element("MOVE", {"dest": "y", "src": "300"}),
                                      Element("SHL", {"dest": "y", "op1": "x", "op2": "40"})])))
    check_program(program)
