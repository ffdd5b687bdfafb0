"""The integer patterns on the PIC18, operation by operation in gpsim beside
the simulator: test_pic16_integers.py's programs (every combination of
destination and operand widths with the edge values of each width) built
for the PIC18F4520. The patterns are the PIC16's, but the PIC18 runs them
with flags of its own (INCF, DECF and the rotations also set C or N) and a
hardware multiplier: each test there runs here unchanged on the other core."""

from __future__ import annotations

import pytest
import test_pic16_integers as pic16

pytestmark = [pytest.mark.slow, pic16.needs_gpsim]

TESTS = ([(pic16.test_binary_operations_of_variables, (kind,)) for kind in pic16.BINARY]
         + [(pic16.test_binary_operations_with_a_literal, (kind,)) for kind in pic16.BINARY]
         + [(pic16.test_the_overflow_flag, (kind,)) for kind in ("ADD", "SUB")]
         + [(pic16.test_comparisons, (literal,)) for literal in (False, True)]
         + [(pic16.test_negation_and_complement, ())]
         + [(pic16.test_shifts_by_a_variable_and_by_literals, (kind,)) for kind in ("SHL", "SHR", "SR0", "ROL", "ROR")]
         + [(pic16.test_bit_numbers, ()), (pic16.test_conversions, ())])


@pytest.mark.parametrize("test,args", TESTS, ids=[f"{t.__name__[5:]}{''.join(f'-{a}' for a in args)}" for t, args in TESTS])
def test_the_integer_patterns_on_the_pic18f4520(test, args, monkeypatch, tmp_path):
    monkeypatch.setattr(pic16, "MCU", "Microchip PIC18F4520 40-PDIP")
    test(*args, tmp_path)
