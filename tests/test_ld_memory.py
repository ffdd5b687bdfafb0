"""Reading a large `.ld` file takes memory in proportion to the program it
holds: the reader never builds the whole file's parse tree (that tree made a
35,000-rung program take 400 MB), and the model keeps its spans small."""

from __future__ import annotations

import sys
import tracemalloc
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from shapes import chain_timers_parallels as chain

from lang.ldfile import read_ld

RUNGS = 2000
# bytes a rung at the peak of reading: about 3,600 (Python 3.11); 10,500 when
# the whole file's tree was built, 4,200 with a __dict__ on every Span
PEAK_PER_RUNG = 4500


def test_reading_peak_memory_grows_with_the_program_only():
    text = chain(RUNGS)
    read_ld(chain(1))  # the parser is built once, outside the measure
    tracemalloc.start()
    try:
        program, diagnostics = read_ld(text)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert diagnostics == [] and len(program.rungs) == RUNGS
    assert peak / RUNGS < PEAK_PER_RUNG, f"{peak / RUNGS:.0f} bytes a rung at the peak of reading"
