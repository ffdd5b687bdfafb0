"""Running a compiled PIC16 program in gpsim beside the simulator, scan for
scan (compiler.run.record.record_pic16 makes the recording: after each scan,
at 0.9 cycle, every file register the compared names live in and the PC);
the comparison takes every name both sides have. A PC outside the wait loop
there means the scan is longer than the cycle allows (CycleOverrun): the
values are a scan's half-done work, not a result to compare.
"""

from __future__ import annotations

from pathlib import Path

from hypothesis import assume
from test_compiler_harness import Event, compared_names, mismatches, simulate

import compiler
from compiler.errors import CompileError
from compiler.run.record import CycleOverrun, erase_eeprom, pic_part, record_pic16  # noqa: F401  (shared with other tests)


def differential(program, events: list[Event], scans: int, tmp_path: Path, target: str | None = None) -> list[str]:
    """Mismatches between the simulator and the compiled PIC image, as text.
    Inputs the stimulus does not set at scan 0 are driven low from the start,
    as the simulator has them (a PIC pin with a pull-up would read high)."""
    given = {e.name for e in events if e.scan == 0}
    events = [Event(0, n, 0) for n in sorted(program.pins) if n[0] == "X" and n not in given] + list(events)
    build = compiler.build(program, target)
    hex_path = tmp_path / "program.hex"
    build.write(hex_path)
    part = pic_part(build.device)
    erase_eeprom(hex_path, part.eeprom, part.eeprom_hex)
    program = build.program
    names = compared_names(program, build)
    expected = simulate(program, events, scans, names)
    actual = record_pic16(build, hex_path, events, scans, names).rows
    return mismatches(expected, actual, names)


def follows_the_simulator(case, folder: Path) -> None:
    """A random program (test_compiler_random's case) in gpsim beside the
    simulator: no mismatch; one too large for the part or whose scan
    outlasts the cycle at the board's crystal is not compared."""
    from test_compiler_random import too_large

    try:
        problems = differential(case.program, case.events, case.scans, folder)
    except CompileError as problem:
        assume(not too_large(problem))
        raise
    except CycleOverrun:
        assume(False)
    assert problems == [], "\n".join(problems)
