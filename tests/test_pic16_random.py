"""Random compilable programs on PIC16 boards (test_compiler_random.py's
generator, its PIC16_BOARDS), built, run in gpsim under a random stimulus and
compared with the simulator on every name after every scan
(pic16_harness.py). benchmarks/compiler_fuzz.py --family pic16 runs the same
for as long as it is given. A program whose scan outlasts the cycle at the
board's crystal (heavy 32-bit arithmetic at 4 MHz) is not compared."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from pic16_harness import follows_the_simulator
from test_compiler_harness import IN_CI
from test_compiler_random import PIC16_BOARDS, cases

from compiler.run import gpsim

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")


@needs_gpsim
@pytest.mark.slow
@settings(max_examples=15, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases(PIC16_BOARDS))
def test_random_programs_follow_the_simulator_on_pic16(case, tmp_path_factory):
    follows_the_simulator(case, tmp_path_factory.mktemp("random"))
