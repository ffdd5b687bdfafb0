"""The native compiler: a ladder program to an Intel HEX image for an AVR.

    Program --check--> lower (compiler.lower) --> intermediate code (compiler.ir)
            --> optimise (compiler.optimise) --> AVR back end (compiler.avr)
            --> words + listing --> Intel HEX (intelhex)

`build(program, target)` runs the checks first and refuses a program with
errors; every problem is a located diagnostic (codes LD7xx, compiler.errors).
docs/compiler.md describes the decisions.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, replace

from intelhex import IntelHex

from lang.devices import Device, find_device
from lang.diagnostics import ERROR, Diagnostic
from lang.model import Program

from .errors import MOVED_PIN, NO_TARGET, CompileError, fail, note

SUPPORTED = ("atmega8", "atmega16", "atmega32", "atmega64", "atmega128", "atmega162", "atmega328p",
             "atmega1284p", "atmega2560")


@dataclass
class Build:
    program: Program  # as compiled (with the target part)
    part: object  # compiler.avr.part.Part
    words: list[int]
    listing: str
    ram_bytes: int
    warnings: list[Diagnostic]
    symbols: dict  # name -> compiler.avr.Symbol: where each bit and variable lives
    labels: dict  # listing label -> word address in flash

    @property
    def flash_bytes(self) -> int:
        return 2 * len(self.words)

    def image(self) -> bytes:
        return b"".join(w.to_bytes(2, "little") for w in self.words)

    def write(self, hex_path) -> None:
        """The HEX file, and the listing beside it (same stem, .lst)."""
        from pathlib import Path

        hex_path = Path(hex_path)
        hex_path.write_text(self.hex())
        hex_path.with_suffix(".lst").write_text(self.listing)

    def hex(self) -> str:
        data = IntelHex()
        data.frombytes(self.image(), offset=0)
        out = io.StringIO()
        data.write_hex_file(out, byte_count=16)
        return out.getvalue()

    def summary(self) -> str:
        """`PART: flash N/M bytes (P%), RAM N/M bytes (P%)`"""
        part = self.part
        ram = part.avr["ram"]["size"]
        return (f"{part.title}: flash {self.flash_bytes}/{part.flash} bytes "
                f"({100 * self.flash_bytes / part.flash:.1f}%), RAM {self.ram_bytes}/{ram} bytes "
                f"({100 * self.ram_bytes / ram:.1f}%)")


def target_device(program: Program, target: str | None) -> Device:
    name = target or program.settings.mcu
    device = find_device(name) if name else None
    if device is None or device.part not in SUPPORTED:
        what = f"'{name}'" if name else "no part"
        raise fail(NO_TARGET, f"cannot compile for {what}: the AVR back end compiles for "
                              "ATmega8, 16, 32, 64, 128, 162, 328P, 1284P and 2560")
    return device


def retarget(program: Program, device: Device) -> Program:
    """The program with the part selected; pins by port name carry over,
    package pin numbers are looked up on the new part's package."""
    return replace(program, settings=replace(program.settings, mcu=device.ldmicro_name or device.part))


def build(program: Program, target: str | None = None) -> Build:
    """Compile; CompileError with located diagnostics when it cannot."""
    from lang.checks import check_program

    from .avr import compile_avr
    from .avr.part import Part
    from .lower import lower_program
    from .optimise import optimise

    device = target_device(program, target)
    moved = _moved_pins(program, device)
    program = retarget(program, device)
    problems = [d for d in check_program(program, for_build=True) if d.severity == ERROR]
    if problems:
        raise CompileError(problems)
    code = optimise(lower_program(program, device))
    image = compile_avr(code, Part.of(device), program, _pwm_elements(program, device))
    return Build(program, image.part, image.words, image.listing, image.ram_bytes, moved + image.warnings,
                 image.symbols, image.labels)


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


def _pwm_elements(program: Program, device: Device) -> dict:
    """The first SET PWM of each PWM unit, to locate its diagnostics."""
    found = {}
    for _, element in program.elements():
        if element.kind == "SET_PWM":
            assignment = program.pins.get(str(element.args.get("name")))
            pin = device.pin(assignment.pin) if assignment else None
            if pin is not None and pin.name in device.pwm:
                found.setdefault(device.pwm[pin.name], element)
    return found
