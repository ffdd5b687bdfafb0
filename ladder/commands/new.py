"""`ladder new --part PART FILE`: a minimal valid program to start from."""

from __future__ import annotations

import sys
from pathlib import Path

from lang.devices import find_device
from lang.ldfile import write_ld_bytes
from lang.model import Element, PinAssignment, Program, Rung, Series, Settings
from lang.textform.writer import render_program

from ._common import EXIT_OK, EXIT_USAGE, write_output


def register(subparsers) -> None:
    parser = subparsers.add_parser("new", help="write a minimal program for a part",
                                   description="Write a minimal valid program (a push button lighting a "
                                               "lamp) for a part; `ladder parts` lists the parts.")
    parser.add_argument("--part", required=True, help="part name, e.g. atmega328p or pic16f877a")
    parser.add_argument("file", metavar="FILE", help="FILE.ladder (the text form) or FILE.ld (LDmicro's format)")
    parser.add_argument("--force", action="store_true", help="overwrite an existing file")
    parser.set_defaults(func=run)


def starter_program(part: str) -> Program | None:
    device = find_device(part)
    if device is None:
        return None
    # I/O pins with no crystal or reset role, those with no UART, ADC or PWM
    # role to clash with later first (an 8-pin PIC has none of those)
    busy = ("XTAL", "TOSC", "OSC", "RESET", "MCLR")
    free = sorted((pin for pin in device.io_pins() if not any(word in pin.label for word in busy)),
                  key=lambda pin: bool(pin.functions))
    inputs = free[0]
    outputs = next(pin for pin in free[1:] if "Input Only" not in pin.label)
    comment = Element("COMMENT", {"text": f"{device.title}: Xbutton lights Ylamp", "line_ends": ()})
    contact = Element("CONTACTS", {"name": "Xbutton", "negated": 0, "set1": 0})
    coil = Element("COIL", {"name": "Ylamp", "type": " "})
    return Program(
        settings=Settings(mcu=device.ldmicro_name or device.title, crystal_hz=16000000 if device.family == "avr" else 4000000),
        rungs=[Rung(Series([comment])), Rung(Series([contact, coil]))],
        pins={"Xbutton": PinAssignment("Xbutton", inputs.number), "Ylamp": PinAssignment("Ylamp", outputs.number)},
    )


def run(args) -> int:
    program = starter_program(args.part)
    if program is None:
        print(f"ladder new: unknown part {args.part!r}; `ladder parts` lists them", file=sys.stderr)
        return EXIT_USAGE
    target = Path(args.file)
    if target.exists() and not args.force:
        print(f"ladder new: {args.file} exists; use --force to overwrite it", file=sys.stderr)
        return EXIT_USAGE
    if target.suffix.lower() == ".ld":
        data = write_ld_bytes(program)
    else:
        data = render_program(program).encode("utf-8")
    return EXIT_OK if write_output(target, data) else EXIT_USAGE
