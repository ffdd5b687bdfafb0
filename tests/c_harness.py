"""The C output run on the host beside the simulator: a program's C, built
with the host's compiler and compiler.run.c's harness, under a stimulus, and
compared with the simulator on every name after every scan."""

from __future__ import annotations

from pathlib import Path

from test_compiler_harness import Event, mismatches, simulate

import compiler
from compiler.run import c as c_run
from lang.model import Program
from lang.sim import Simulator


def compared_names(program: Program, sources) -> list[str]:
    """Every name both sides have but the inputs (the stimulus) and `#`
    registers (hardware on an MCU, plain variables in the simulator)."""
    return sorted(n for n in Simulator(program).variables() if n in sources.symbols and n[0] not in "X#")


def script(events: list[Event], scans: int) -> list[str]:
    """The harness's commands: each scan's events, the scan, its values."""
    lines = []
    for scan in range(scans):
        for event in events:
            if event.scan == scan:
                lines.append(f"uart {event.value}" if event.name == "uart" else f"set {event.name} {event.value}")
        lines += ["run 1", "show"]
    return lines


def run_c(program: Program, events: list[Event], scans: int, folder: Path, names: list[str] | None = None,
          sanitize: bool = True) -> tuple[list[str], list[dict[str, int]]]:
    """The watched names and their values after each scan of the C build."""
    sources = compiler.build_c(program, "program", "program.ladder")
    names = compared_names(program, sources) if names is None else names
    built = c_run.build(sources, "program", names, program.settings.cycle_us, program.settings.baud, folder,
                        sanitize=sanitize)
    rows = [line.split()[1:] for line in built.run(script(events, scans)) if line.startswith("@values")]
    return names, [dict(zip(names, map(int, row))) for row in rows]


def differential(program: Program, events: list[Event], scans: int, folder: Path, sanitize: bool = True) -> list[str]:
    names, actual = run_c(program, events, scans, folder, sanitize=sanitize)
    assert len(actual) == scans, f"the C harness gave {len(actual)} samples for {scans} scans"
    return mismatches(simulate(program, events, scans, names), actual, names)
