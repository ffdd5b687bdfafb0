"""LDmicro 5.4.1.1 compiles the `.ld` files we write for programs whose pins
the text form gives by port bit (PB5, RD0, RC2): the writer puts the package
pin numbers of the part in the IO LIST, as LDmicro needs (it read `Yled at
PB5` as pin 0 and refused, "Must assign pins for all I/O"), and the part by
LDmicro's name for it when the text names it by ours. Pins with
alternate functions (INT0, MOSI, ADC0, OC1B, CCP2) and a PWM output on each
part. LDmicro's own image then drives the output when the input is driven
(simavr, gpsim): the numbers name the pins the text meant.

LDmicro is found at /opt/ldmicro/ldmicro (or LDMICRO=); these tests run in
the LDmicro step of .ci/run (marker `ldmicro`)."""

from __future__ import annotations

from pathlib import Path

import pytest
from builders import coil, contact, el, program
from ldmicro_oracle import ldmicro_compile

from compiler.run import gpsim, simavr
from lang.ldfile import write_ld
from lang.textform.reader import read_text
from lang.textform.writer import render_program

pytestmark = pytest.mark.ldmicro


# part: (Xa, Xb, Yled, Yb, the PWM output P); LDmicro's PIC16 PWM needs Timer0 for the cycle
PARTS = {
    "Atmel AVR ATmega328 28-PDIP": {"Xa": "PD2", "Xb": "PD4", "Yled": "PB5", "Yb": "PC0", "P": "PD6"},
    # one of our names, written as LDmicro's ("Atmel AVR ATmega328 32-Pin packages")
    "atmega328p:32-TQFP": {"Xa": "PD2", "Xb": "PD4", "Yled": "PB5", "Yb": "PC0", "P": "PD6"},
    "Atmel AVR ATmega16 40-PDIP": {"Xa": "PD2", "Xb": "PA0", "Yled": "PB5", "Yb": "PD4", "P": "PD7"},
    "Microchip PIC16F877 40-PDIP": {"Xa": "RB0", "Xb": "RA0", "Yled": "RD0", "Yb": "RC1", "P": "RC2"},
    "Microchip PIC16F628 18-PDIP or 18-SOIC": {"Xa": "RB0", "Xb": "RA0", "Yled": "RB5", "Yb": "RA2", "P": "RB3"},
}


def _written(mcu: str, pins: dict[str, str], folder: Path) -> Path:
    """The program as a user writes it in the text form, converted to .ld."""
    avr = "AVR" in mcu or mcu.startswith("atmega")
    prog = program([contact("Xa"), coil("Yled")], [contact("Xb"), coil("Yb")],
                   [contact("Xa"), el("SET_PWM", duty="50", freq=1000, name="P")],
                   mcu=mcu, pins=pins, crystal_hz=16_000_000 if avr else 4_000_000, cycle_timer=1 if avr else 0)
    text_program, problems = read_text(render_program(prog))
    assert not problems, problems
    refused: list = []
    ld_text = write_ld(text_program, diagnostics=refused)
    assert not refused, refused
    path = folder / "pins.ld"
    path.write_bytes(ld_text.replace("\n", "\r\n").encode("cp1252"))
    return path


@pytest.mark.parametrize("mcu", sorted(PARTS))
def test_ldmicro_compiles_pins_given_by_port_bit(mcu, tmp_path):
    source = _written(mcu, PARTS[mcu], tmp_path)
    image = tmp_path / "pins.hex"
    done = ldmicro_compile(source, image)
    assert done.returncode == 0 and "Compiled okay" in done.stdout, done.stdout + done.stderr
    assert image.stat().st_size > 0 and image.read_text().startswith(":")


def _run(image: Path, mcu: str, pins: dict[str, str]):
    """LDmicro's image with Xa low, then high from 100 ms, its Yled pin watched."""
    inputs = [(0, pins["Xa"], 0), (0, pins["Xb"], 0), (100, pins["Xa"], 1)]
    if "AVR" in mcu:
        if not simavr.available():
            pytest.skip("simavr's harness cannot be built here")
        return simavr.simulate_avr(image, simavr.core_name(mcu), 16_000_000, 200, inputs=inputs, watch=[pins["Yled"]])
    if not gpsim.available():
        pytest.skip("gpsim is not installed")
    return gpsim.run_pic(image, gpsim.processor_name(mcu.split()[1]), 4_000_000, inputs=inputs, watch=[pins["Yled"]],
                         until_ms=200, timeout=120)


@pytest.mark.parametrize("mcu", ["Atmel AVR ATmega328 28-PDIP", "Microchip PIC16F877 40-PDIP"])
def test_ldmicros_image_drives_the_pin_the_text_named(mcu, tmp_path):
    pins = PARTS[mcu]
    source = _written(mcu, pins, tmp_path)
    image = tmp_path / "pins.hex"
    ldmicro_compile(source, image, check=True)
    run = _run(image, mcu, pins)
    assert run.level_at(pins["Yled"], 90) == 0 and run.level_at(pins["Yled"], 199) == 1
