"""The C output run on the host beside the simulator: a program's C, built
with the host's compiler and compiler.run.c's harness, under a stimulus, and
compared with the simulator on every name after every scan."""

from __future__ import annotations

from pathlib import Path

from test_compiler_harness import Event, mismatches, simulate

import compiler
from compiler.run.record import record_c
from lang.model import Program
from lang.sim import Simulator


def compared_names(program: Program, sources) -> list[str]:
    """Every name both sides have but the inputs (the stimulus) and `#`
    registers (hardware on an MCU, plain variables in the simulator)."""
    return sorted(n for n in Simulator(program).variables() if n in sources.symbols and n[0] not in "X#")


def run_c(program: Program, events: list[Event], scans: int, folder: Path, names: list[str] | None = None,
          sanitize: bool = True) -> tuple[list[str], list[dict[str, int]]]:
    """The watched names and their values after each scan of the C build."""
    if names is None:
        names = compared_names(program, compiler.build_c(program, "program", "program.ladder"))
    return names, record_c(program, events, scans, names, folder, sanitize).rows


def differential(program: Program, events: list[Event], scans: int, folder: Path, sanitize: bool = True) -> list[str]:
    names, actual = run_c(program, events, scans, folder, sanitize=sanitize)
    assert len(actual) == scans, f"the C harness gave {len(actual)} samples for {scans} scans"
    return mismatches(simulate(program, events, scans, names), actual, names)
