"""Random programs (test_compiler_random.py's generator, its C board) as C:
built with the host's compiler under -fsanitize=undefined,address, run under
a random stimulus and compared with the simulator on every name after every
scan. benchmarks/compiler_fuzz.py --family c runs the same for as long as it
is given."""

from __future__ import annotations

import pytest
from c_harness import differential
from hypothesis import HealthCheck, given, settings
from test_compiler_random import C_BOARDS, cases

from compiler.run import c as c_run

needs_cc = pytest.mark.skipif(not c_run.available(), reason="no C compiler (Debian: gcc)")


@needs_cc
@settings(max_examples=12, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases(C_BOARDS))
def test_random_programs_in_c_follow_the_simulator(case, tmp_path_factory):
    problems = differential(case.program, case.events, case.scans, tmp_path_factory.mktemp("c"))
    assert problems == [], "\n".join(problems)
