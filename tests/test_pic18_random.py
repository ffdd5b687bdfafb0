"""Random compilable programs on the PIC18 boards (test_compiler_random.py's
generator, its PIC18_BOARDS: every instruction the PIC18 compiles but the
peripherals, unused variables pushing the program's own into BSR's other
banks), built, run in gpsim under a random stimulus and compared with the
simulator on every name after every scan (pic16_harness.py). The slow run
draws 300 programs; a sample of three runs with the fast tests.
benchmarks/compiler_fuzz.py --family pic18 runs the same for as long as it
is given. A program whose scan outlasts the cycle at the board's crystal is
not compared."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from pic16_harness import follows_the_simulator
from test_compiler_harness import IN_CI
from test_compiler_random import PIC18_BOARDS, cases

from compiler.run import gpsim

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")


@needs_gpsim
@settings(max_examples=3, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases(PIC18_BOARDS))
def test_a_sample_of_random_programs_follows_the_simulator(case, tmp_path_factory):
    follows_the_simulator(case, tmp_path_factory.mktemp("random"))


@needs_gpsim
@pytest.mark.slow
@settings(max_examples=300, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(case=cases(PIC18_BOARDS))
def test_random_programs_follow_the_simulator_on_pic18(case, tmp_path_factory):
    follows_the_simulator(case, tmp_path_factory.mktemp("random"))
