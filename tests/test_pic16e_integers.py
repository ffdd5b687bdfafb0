"""The integer patterns on the enhanced mid-range core, operation by
operation in gpsim beside the simulator: test_pic16_integers.py's programs
(every combination of destination and operand widths with the edge values
of each width) built for the PIC16F1824 (run as gpsim's p16f1825) on its
internal oscillator at 16 MHz, the nearest to the 20 MHz crystal there. The
patterns are the PIC16's, with ADDWFC, SUBWFB, LSLF, LSRF and ASRF where the
enhanced core has them: each test there runs here unchanged, but those whose
one program outgrows the part (the literal operands' and the overflow flag's
need 290 to 353 bytes of RAM or 4121 words; the PIC16F1824 has 256 and
4096): their patterns are the variables' ones with constant bytes, which the
random programs (test_pic16e_random.py) also draw."""

from __future__ import annotations

import pytest
import test_pic16_integers as pic16
from builders import program
from test_pic18_integers import TESTS as ALL

TOO_LARGE = {pic16.test_binary_operations_with_a_literal, pic16.test_the_overflow_flag}
TESTS = [(test, args) for test, args in ALL if test not in TOO_LARGE]

pytestmark = [pytest.mark.slow, pic16.needs_gpsim]


@pytest.mark.parametrize("test,args", TESTS, ids=[f"{t.__name__[5:]}{''.join(f'-{a}' for a in args)}" for t, args in TESTS])
def test_the_integer_patterns_on_the_pic16f1824(test, args, monkeypatch, tmp_path):
    monkeypatch.setattr(pic16, "MCU", "Microchip PIC16F1824 14-Pin PDIP, SOIC, TSSOP")
    monkeypatch.setattr(pic16, "program", lambda *rungs, **settings: program(*rungs, **{**settings,
                                                                                      "crystal_hz": 16_000_000}))
    test(*args, tmp_path)
