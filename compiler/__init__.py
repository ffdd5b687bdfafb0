"""The native compiler: a ladder program to an Intel HEX image, for every
family in `lang.families.FAMILIES`.

    Program --checks--> lower (lang.semantics.lower) --> intermediate code (lang.semantics.ir)
            --> flatten, optimise (compiler.optimise) --> the family's back end (compiler.backend)
            --> compiler.image.Image --> Intel HEX + listing

`build(program, target)` selects the part, runs the checks as for a build and
refuses a program with errors; every problem is a located diagnostic (codes
LD7xx, compiler.errors). docs/compiler.md describes the decisions.
"""

from __future__ import annotations

import importlib
from dataclasses import replace

from lang.checks import check_program
from lang.codes import code
from lang.config import NONE, Severities
from lang.devices import Device, find_device
from lang.diagnostics import ERROR, Diagnostic, error
from lang.families import FAMILIES, Family, compiled, family_of, parts_text
from lang.model import Program
from lang.semantics.errors import LoweringError
from lang.semantics.lower import lower_program
from lang.semantics.operands import PWM_FULL
from lang.textform.writer import render_rung

from .backend import BACKENDS, Backend, first_use, machine_for
from .budget import overrun_warning, scan_budget
from .c import CSources, Unit, generate
from .c.arduino import BOARDS, Board, Sketch, SketchPin, ino
from .errors import FLASH_FULL, MOVED_PIN, NO_TARGET, NOT_COMPILED, RAM_FULL, CompileError, fail, lowering_failed, note
from .image import Build
from .optimise import optimise

OTHER_CHIP = code("LD715")
SIZES = (FLASH_FULL, RAM_FULL)


def target_device(program: Program, target: str | None) -> Device:
    """The part to compile for: `target`, else the program's; LD701 when no
    registered back end compiles it."""
    name = target or program.settings.mcu
    device = find_device(name) if name else None
    if device is None or not compiled(device):
        what = f"'{name}'" if name else "no part"
        raise fail(NO_TARGET, f"cannot compile for {what}: ladder build compiles for {parts_text()}")
    family = family_of(device)
    assert family is not None  # compiled() found it
    if family.key not in BACKENDS:
        raise fail(NO_TARGET, f"cannot compile for '{name}': the {family.title} back end is not installed "
                              "(no module registered it)")
    return device


def retarget(program: Program, device: Device) -> Program:
    """The program with the part selected; pins by port name carry over,
    package pin numbers are looked up on the new part's package. A
    ConfigurationWord is its own family's encoding: it does not carry over
    to another family's part (a PIC16's word is no PIC18's CONFIG1)."""
    settings = replace(program.settings, mcu=device.ldmicro_name or device.part)
    own = find_device(program.settings.mcu) if program.settings.mcu else None
    if own is not None and own.family != device.family:
        settings = replace(settings, config_word=0)
    return replace(program, settings=settings)


def build(program: Program, target: str | None = None, severities: Severities = NONE) -> Build:
    """Compile; CompileError with located diagnostics when it cannot (or
    when the project's `severities` make a warning an error)."""
    device = target_device(program, target)
    backend = BACKENDS[device.family]
    moved = _moved_pins(program, device)
    program = retarget(program, device)
    checked = check_program(program, True, severities)
    problems = [d for d in checked if d.severity == ERROR]
    if problems:
        raise CompileError(problems)
    # the build's own warnings that the checks report from the part's data (LD709, LD714)
    noted = [d for d in checked if d.code[2] == "7"]
    image = _image(program, device, backend)
    budget = scan_budget(program, device, image, backend.flow)
    overrun = overrun_warning(program, budget)
    warnings = severities.apply(moved + noted + image.warnings + ([overrun] if overrun else []), building=True)
    if any(d.severity == ERROR for d in warnings):
        raise CompileError([d for d in warnings if d.severity == ERROR])
    return Build(program, device, image, warnings, budget)


def size_problems(program: Program) -> list[Diagnostic]:
    """Whether the program fits its part: the compiler's LD703 (flash) and
    LD704 (RAM) for the program's own part, from the real compile (lowering,
    optimiser and back end; no scan budget, no image written), placed on the
    part's name, as `build` places them. `ladder check` runs it
    after the checks found no error; [] when the part is none a back end
    compiles or the compile stops on a problem `ladder build` reports."""
    try:
        device = target_device(program, None)
        _image(retarget(program, device), device, BACKENDS[device.family])
    except CompileError as problem:
        return [d for d in problem.diagnostics if d.code in SIZES]
    return []


def _image(program: Program, device: Device, backend: Backend):
    """The back end's image of the checked program; flash and RAM the part
    lacks are placed on where the program names the part (the compiler
    names no element for them)."""
    code = optimise(_lower(program, device, backend.delay_loop_cycles), backend.rungs_by_jumps)
    try:
        return backend.compile(code, machine_for(program, device))
    except CompileError as problem:
        raise CompileError([replace(d, span=program.settings.mcu_span) if d.code in SIZES and d.span is None
                            else d for d in problem.diagnostics]) from None


def _lower(program: Program, device: Device | None, delay_loop_cycles: int, family: Family | None = None):
    try:
        return lower_program(program, device, delay_loop_cycles, family)
    except LoweringError as problem:
        raise lowering_failed(problem) from None


def build_c(program: Program, stem: str, source: str, severities: Severities = NONE) -> CSources:
    """Portable C for the program, whatever its part (`ladder build --emit
    c`); CompileError as for `build`."""
    problems = [d for d in check_program(program, True, severities, family="c") if d.severity == ERROR]
    if problems:
        raise CompileError(problems)
    code = optimise(_lower(program, None, 1, FAMILIES["c"]))
    unit = Unit(stem, source, lambda index: render_rung(program.rungs[index], index + 1, 0),
                program.settings.cycle_us)
    return generate(code, unit)


def build_arduino(program: Program, stem: str, source: str, board: str, severities: Severities = NONE,
                  keep_port_bits: bool = False) -> tuple[CSources, str, list[Diagnostic]]:
    """The program's C, the sketch file that runs it on an Arduino board
    (`ladder build --emit arduino`) and the build's warnings; CompileError as
    for `build`, also for a name with no pin, a pin that is not on the
    board's headers or cannot do what the name needs (A/D, PWM), or a pin of
    a program drawn for another chip than the board's (LD715: a warning for
    a port bit with `keep_port_bits`)."""
    sources = build_c(program, stem, source, severities)
    found = BOARDS[board]
    pins, problems, moved = [], [], []
    hooks = " ".join(sources.hooks)
    wanted = [(n, kind) for n, (kind, _) in sources.symbols.items() if kind in ("input", "output")]
    wanted += [(n, "adc") for n in sources.symbols if f"Read_Ub_{n}(" in hooks and n[:1] == "A"]
    wanted += [(n, "pwm") for n in sources.symbols if f"Write_Ub_{n}(" in hooks and n[:1] == "P"]
    for name, kind in sorted(wanted):
        other_chip = _other_chip(program, found, name, keep_port_bits)
        if other_chip is not None and other_chip.severity == ERROR:
            problems.append(other_chip)
            continue
        moved += [other_chip] if other_chip is not None else []
        try:
            pins.append(_board_pin(program, found, name, kind))
        except CompileError as problem:
            problems += problem.diagnostics
    moved = severities.apply(moved, building=True)
    problems += [d for d in moved if d.severity == ERROR]
    if problems:
        raise CompileError(problems)
    sketch = Sketch(found, tuple(pins), program.settings.cycle_us, program.settings.baud)
    return sources, ino(stem, source, sources, sketch), moved


def _other_chip(program: Program, board: Board, name: str, keep_port_bits: bool) -> Diagnostic | None:
    """LD715 for a pin of a program drawn for another chip than the board's:
    a package pin number of that chip means nothing on the board's; a port
    bit exists on both but is another header pin (PD2: D2 on the Uno, D19 on
    the Mega), so the wiring drawn does not carry over unless the user says
    to keep the port bits."""
    own = find_device(program.settings.mcu) if program.settings.mcu else None
    assignment = program.pins.get(name)
    if own is None or own.part == board.part or assignment is None or not assignment.assigned:
        return None
    chip = find_device(board.part)
    assert chip is not None  # boards.json names parts by their device files
    homes = [b for b in BOARDS.values() if b.part == own.part]
    fits = f"build with --board {' or '.join(b.key for b in homes)}" if homes else ""
    if isinstance(assignment.pin, int):
        pin = own.pin(assignment.pin)
        ways = [fits] if fits else []
        if pin is not None and pin.is_io:
            ways.append(f"give it by port bit ({pin.name}) and build with --keep-port-bits")
        return error(OTHER_CHIP, f"'{name}' is at pin {assignment.pin} of the {own.title} ({own.package}), a package "
                                 f"pin number, which means nothing on the {board.title}'s {chip.title}: "
                                 f"{', or '.join(ways) or 'give it a pin of the board'}", assignment.span)
    text = assignment.pin.upper()
    if own.pin(text) is None:
        return None  # not a port bit of the program's chip (a header name): _board_pin reads it
    number = board.number(text)
    if number is None:
        lacks = (f"the {board.title} does not bring out" if chip.pin(text) is not None
                 else f"the {board.title}'s {chip.title} does not have")
        return error(OTHER_CHIP, f"'{name}' is at {text}, a port bit of the {own.title}, which {lacks}"
                                 f"{f': {fits}' if fits else ''}", assignment.span)
    home_number = homes[0].number(text) if homes else None
    before = f"{homes[0].label(home_number)} on the {homes[0].title}" if home_number is not None else ""
    if keep_port_bits:
        return note(OTHER_CHIP, f"'{name}': {text} → {board.label(number)} on the {board.title}"
                                f"{f' (was {before})' if before else ''}", assignment)
    return error(OTHER_CHIP, f"'{name}' is at {text}, a port bit of the {own.title}: {board.label(number)} on the "
                             f"{board.title}{f', {before}' if before else ''}; {fits + ', or ' if fits else ''}"
                             f"add --keep-port-bits to use {board.label(number)}", assignment.span)


def _board_pin(program: Program, board: Board, name: str, kind: str) -> SketchPin:
    where = first_use(program, name)
    assignment = program.pins.get(name)
    if assignment is None or assignment.pin in (0, "", None):
        mcu = find_device(board.part)
        assert mcu is not None  # boards.json names parts by their device files
        raise fail(NOT_COMPILED, f"'{name}' has no pin: give it one of the {board.title}'s (D2, A0) or a port "
                                 f"bit of its {mcu.title} (PD2)", where)
    number = None
    if isinstance(assignment.pin, str):
        number = board.number(assignment.pin)
    else:
        # a package pin number of the program's own part
        own = find_device(program.settings.mcu) if program.settings.mcu else None
        pin = own.pin(assignment.pin) if own is not None else None
        number = board.number(pin.name) if pin is not None else None
    if number is None:
        raise fail(NOT_COMPILED, f"'{name}' is on pin {assignment.pin}, which is not one of the {board.title}'s",
                   assignment)
    if kind == "adc" and not board.is_analog(number):
        raise fail(NOT_COMPILED, f"'{name}' is on {board.label(number)}, which is not an analog input of the "
                                 f"{board.title} (A0..A{board.analog_count - 1})", assignment)
    if kind == "pwm" and number not in board.pwm:
        raise fail(NOT_COMPILED, f"'{name}' is on {board.label(number)}, which has no PWM on the {board.title} "
                                 f"({', '.join(board.label(n) for n in sorted(board.pwm))})", assignment)
    if kind in ("input", "output") and number >= len(board.pins):
        raise fail(NOT_COMPILED, f"'{name}' is on {board.label(number)}, an analog-only input of the "
                                 f"{board.title}", assignment)
    port_bit = board.pins[number] if number < len(board.pins) else ""
    # LDmicro turns on an input's pull-up unless the PULL-UP LIST clears its bit (a port absent: all on)
    mask = program.pullups.get(port_bit[:2], 0xFF) if port_bit else 0
    full = next((PWM_FULL.get(str(e.args.get("resolution") or "0-100%"), 100) for _, e in program.elements()
                 if e.kind == "SET_PWM" and e.args.get("name") == name), 100)
    return SketchPin(name, kind, number, port_bit, bool(mask >> int(port_bit[2:]) & 1) if port_bit else False, full)


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


# each family that compiles for parts has its back end in compiler.<family>, which registers itself on import
for _family in FAMILIES.values():
    if _family.parts:
        importlib.import_module(f"{__name__}.{_family.key}")
