"""Random compilable programs on the enhanced mid-range parts gpsim models
(test_compiler_random.py's generator: every instruction the PIC16 compiles
but the peripherals, unused variables pushing the program's own into BSR's
other banks), built, run in gpsim under a random stimulus and compared with
the simulator on every name after every scan (pic16_harness.py): the
PIC12F1840 on its internal oscillator, the PIC16F1824 (gpsim's p16f1825,
its 8K-word sibling with the same pins) on a crystal. The slow run draws
300 programs; a sample of three runs with the fast tests. A program whose
scan outlasts the cycle at the board's clock is not compared."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from pic16_harness import follows_the_simulator
from test_compiler_harness import IN_CI
from test_compiler_random import _pic16, cases

from compiler.run import gpsim

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")

# inputs on pins a gpsim pull-up module drives, not the MCLR pin RA3 (LDmicro's configuration makes
# it an input, but gpsim 0.31 restarts these parts on its edges), outputs on the others; ballast
# beyond the first banks of RAM
PIC16E_BOARDS = (
    _pic16("pic12f1840", "Microchip PIC12F1840 8-pin packages", ("RA4", "RA1"), ("RA0", "RA2", "RA5"),
           4_000_000, 30),
    _pic16("pic16f1824", "Microchip PIC16F1824 14-Pin PDIP, SOIC, TSSOP", ("RA4", "RC0", "RC1", "RA0"),
           ("RA1", "RA2", "RC2", "RC3", "RC4", "RA5"), 16_000_000, 30),
)


@needs_gpsim
@settings(max_examples=3, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases(PIC16E_BOARDS))
def test_a_sample_of_random_programs_follows_the_simulator(case, tmp_path_factory):
    follows_the_simulator(case, tmp_path_factory.mktemp("random"))


@needs_gpsim
@pytest.mark.slow
@settings(max_examples=300, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(case=cases(PIC16E_BOARDS))
def test_random_programs_follow_the_simulator_on_the_enhanced_core(case, tmp_path_factory):
    follows_the_simulator(case, tmp_path_factory.mktemp("random"))
