"""Reading a large `.ld` file takes memory in proportion to the program it
holds: the reader never builds the whole file's parse tree (that tree made a
35,000-rung program take 400 MB), and the model keeps its spans small."""

from __future__ import annotations

import tracemalloc

from lang.ldfile import read_ld

RUNGS = 2000
# bytes a rung at the peak of reading: about 3,600 (Python 3.11); 10,500 when
# the whole file's tree was built, 4,200 with a __dict__ on every Span
PEAK_PER_RUNG = 4500


def chain(rungs: int) -> str:
    """Each rung reads the relay the one before wrote, through a contact and a
    timer; every fourth rung has a parallel branch."""
    lines = ["LDmicro0.2", "MICRO=Atmel AVR ATmega2560 100-TQFP", "CYCLE=10000 us at Timer1, YPlcCycleDuty:0",
             "CRYSTAL=16000000 Hz", "", "IO LIST", "    Xstart at 2 0 0", "END", "", "PROGRAM"]
    for i in range(rungs):
        source = "Xstart" if i == 0 else f"R{i - 1}"
        lines.append(f"RUNG {i + 1}")
        if i % 4 == 3:
            lines += ["  PARALLEL", f"    CONTACTS {source} 0 0", f"    CONTACTS R{i - 2} 1 0", "  END"]
        else:
            lines.append(f"  CONTACTS {source} 0 0")
        lines += [f"  TON T{i} 100000 0", f"  COIL R{i} 0 0 0 0", "END"]
    return "\n".join(lines) + "\n"


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
