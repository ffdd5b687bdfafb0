"""The native compiler: a ladder program to an Intel HEX image, for every
family in `lang.targets.FAMILIES`.

    Program --checks--> lower (compiler.lower) --> intermediate code (compiler.ir)
            --> optimise (compiler.optimise) --> the family's back end (compiler.target)
            --> compiler.image.Image --> Intel HEX + listing

`build(program, target)` selects the part, runs the checks as for a build and
refuses a program with errors; every problem is a located diagnostic (codes
LD7xx, compiler.errors). docs/compiler.md describes the decisions.
"""

from __future__ import annotations

import importlib
from dataclasses import replace

from lang.checks import check_program
from lang.config import NONE, Severities
from lang.devices import Device, find_device
from lang.diagnostics import ERROR, Diagnostic
from lang.model import Program
from lang.targets import FAMILIES, compiled, family_of, parts_text
from lang.textform.writer import render_rung

from .budget import overrun_warning, scan_budget
from .c import CSources, Unit, generate
from .errors import MOVED_PIN, NO_TARGET, CompileError, fail, note
from .image import Build
from .lower import lower_program
from .optimise import optimise
from .target import BACKENDS, machine_for

# Each registers its back end on import; the lead adds "compiler.pic16".
_BACKEND_MODULES = ("compiler.avr", "compiler.pic16")


def target_device(program: Program, target: str | None) -> Device:
    """The part to compile for: `target`, else the program's; LD701 when no
    registered back end compiles it."""
    name = target or program.settings.mcu
    device = find_device(name) if name else None
    if device is None or not compiled(device):
        what = f"'{name}'" if name else "no part"
        raise fail(NO_TARGET, f"cannot compile for {what}: ladder build compiles for {parts_text()}")
    family = family_of(device)
    if family.key not in BACKENDS:
        raise fail(NO_TARGET, f"cannot compile for '{name}': the {family.title} back end is not installed "
                              "(no module registered it)")
    return device


def retarget(program: Program, device: Device) -> Program:
    """The program with the part selected; pins by port name carry over,
    package pin numbers are looked up on the new part's package."""
    return replace(program, settings=replace(program.settings, mcu=device.ldmicro_name or device.part))


def build(program: Program, target: str | None = None, severities: Severities = NONE) -> Build:
    """Compile; CompileError with located diagnostics when it cannot (or
    when the project's `severities` make a warning an error)."""
    device = target_device(program, target)
    backend = BACKENDS[device.family]
    moved = _moved_pins(program, device)
    program = retarget(program, device)
    problems = [d for d in check_program(program, True, severities) if d.severity == ERROR]
    if problems:
        raise CompileError(problems)
    code = optimise(lower_program(program, device, backend.delay_loop_cycles))
    image = backend.compile(code, machine_for(program, device))
    budget = scan_budget(program, device, image)
    overrun = overrun_warning(program, budget)
    warnings = severities.apply(moved + image.warnings + ([overrun] if overrun else []), building=True)
    if any(d.severity == ERROR for d in warnings):
        raise CompileError([d for d in warnings if d.severity == ERROR])
    return Build(program, device, image, warnings, budget)


def build_c(program: Program, stem: str, source: str, severities: Severities = NONE) -> CSources:
    """Portable C for the program, whatever its part (`ladder build --emit
    c`); CompileError as for `build`."""
    problems = [d for d in check_program(program, True, severities, family="c") if d.severity == ERROR]
    if problems:
        raise CompileError(problems)
    code = optimise(lower_program(program, None, 1, FAMILIES["c"]))
    unit = Unit(stem, source, lambda index: render_rung(program.rungs[index], index + 1, 0),
                program.settings.cycle_us)
    return generate(code, unit)


def _moved_pins(program: Program, device: Device) -> list[Diagnostic]:
    """Warnings for package pin numbers that are another port bit on the new part."""
    old = find_device(program.settings.mcu) if program.settings.mcu else None
    if old is None or old == device:
        return []
    found = []
    for name, assignment in program.pins.items():
        if not isinstance(assignment.pin, int):
            continue
        before, after = old.pin(assignment.pin), device.pin(assignment.pin)
        if before is not None and after is not None and before.name != after.name:
            found.append(note(MOVED_PIN, f"'{name}' at pin {assignment.pin} is {after.name} on the "
                                         f"{device.title} ({device.package}), {before.name} on the "
                                         f"{old.title}", assignment))
    return found


for _module in _BACKEND_MODULES:
    importlib.import_module(_module)
