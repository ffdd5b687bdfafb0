"""Pins given by port bit in the text form (`PB5`, `RB0`) go into an `.ld`
file as the package pin numbers of the program's part, the only form
LDmicro's IO LIST holds (it reads `Yled at PB5` as pin 0, "not assigned");
a port bit the `.ld` cannot hold is a located error and nothing is written.
LDmicro itself compiles what we write: tests/test_ldmicro_pins.py."""

from __future__ import annotations

import pytest
from builders import coil, contact, el, program

from ladder.cli import main
from lang.devices import Device, all_devices
from lang.ldfile import read_ld, write_ld
from lang.textform.reader import read_text
from lang.textform.writer import render_program


def _mcu(device: Device) -> str:
    # a part LDmicro does not list (the PIC16F877A, one package) is named by its title
    return device.ldmicro_name or device.title


def _through_the_text_form(prog):
    """The program as a user writes it (.ladder), then converted to .ld and read back."""
    text_program, problems = read_text(render_program(prog))
    assert not problems, problems
    written = []
    ld_text = write_ld(text_program, diagnostics=written)
    assert written == []
    back, problems = read_ld(ld_text)
    assert not problems, problems
    return ld_text, back


@pytest.mark.parametrize("device", all_devices(), ids=lambda d: f"{d.part}-{d.package}")
def test_every_port_bit_of_every_part_is_written_as_its_package_pin(device):
    pins = device.io_pins()
    names = [f"X{pin.name}" for pin in pins]
    prog = program(*[[contact(name), coil("Rseen")] for name in names], mcu=_mcu(device),
                   pins={name: pin.name for name, pin in zip(names, pins)})
    ld_text, back = _through_the_text_form(prog)
    for name, pin in zip(names, pins):
        assert f"    {name} at {pin.number} 0 0\n" in ld_text
        number = back.pins[name].pin
        assert number == pin.number and device.pin(number).port_bit == pin.port_bit


def test_the_pwm_output_p_on_a_port_bit_gets_its_pin():
    """SET_PWM's classic name P on PB7 (OC2 of the ATmega128), pin 17."""
    prog = program([contact("Xgo"), el("SET_PWM", duty="50", freq=1000, name="P")],
                   mcu="Atmel AVR ATmega128 64-TQFP", pins={"Xgo": "PE2", "P": "PB7"})
    ld_text, back = _through_the_text_form(prog)
    assert "    P at 17 0 0\n" in ld_text and "    Xgo at 4 0 0\n" in ld_text
    assert back.pins["P"].pin == 17


def test_a_pin_name_with_alternate_functions_is_found_by_its_port_bit():
    """The device file's pin RC2 is labelled "RC2 CCP1"; the text form gives RC2."""
    prog = program([contact("Xint"), coil("Pccp")], mcu="Microchip PIC16F877 40-PDIP",
                   pins={"Xint": "rb0", "Pccp": "RC2"})
    ld_text, _ = _through_the_text_form(prog)
    assert "    Xint at 33 0 0\n" in ld_text and "    Pccp at 17 0 0\n" in ld_text


def test_package_pin_numbers_stay_numbers_both_ways():
    ld = ("LDmicro0.2\nMICRO=Atmel AVR ATmega328 28-PDIP\n\nIO LIST\n    Xa at 4 0 0\nEND\n\n"
          "PROGRAM\nRUNG 1\n  CONTACTS Xa 0 0\n  COIL Yb 0 0 0 0\nEND\n")
    prog, _ = read_ld(ld)
    text = render_program(prog)
    assert "| digital in         |   4 | PD2" in text
    assert read_text(text)[0].pins["Xa"].pin == 4


def test_an_ld_file_holding_a_port_bit_is_written_back_with_the_number():
    """Files textladder wrote before it looked port bits up (`Yled at PB5`)."""
    prog, problems = read_ld("LDmicro0.2\nMICRO=Atmel AVR ATmega328 28-PDIP\n\nIO LIST\n    Yled at PB5\nEND\n\n"
                             "PROGRAM\nRUNG 1\n  COIL Yled 0 0 0 0\nEND\n")
    assert not problems
    assert "    Yled at 19 0 0\n" in write_ld(prog, diagnostics=[])


def _unwritable(mcu: str, pins: dict):
    prog = program([contact("Xa"), coil("Yb")], mcu=mcu, pins=pins)
    problems = []
    write_ld(prog, diagnostics=problems)
    return prog, problems


@pytest.mark.parametrize("mcu, pin, code, words", [
    ("", "PB5", "LD013", "the program names no part"),
    ("St ARM STM32F40X 144-LQFP", "PB2", "LD013", "no pin table for 'St ARM STM32F40X"),
    ("Microchip PIC16F628 18-PDIP or 18-SOIC", "PD2", "LD402", "PD2, which the PIC16F628 (18-PDIP) does not have"),
    ("Microchip PIC16F628 18-PDIP or 18-SOIC", "D13", "LD402", "D13, which the PIC16F628 (18-PDIP) does not have"),
    ("Atmel AVR ATmega328 28-PDIP", "ADC6", "LD402",
     "ADC6, which the ATmega328P has only in its 32-TQFP package, not in the 28-PDIP of the program"),
])
def test_a_port_bit_the_ld_file_cannot_hold_is_a_located_error(mcu, pin, code, words):
    prog, problems = _unwritable(mcu, {"Xa": pin, "Yb": 0})
    assert [(d.code, d.severity, d.span) for d in problems] == [(code, "error", prog.pins["Xa"].span)]
    assert words in problems[0].message and "'Xa'" in problems[0].message


def test_write_ld_without_a_diagnostics_list_refuses_rather_than_writing_pin_0():
    prog = program([contact("Xa")], pins={"Xa": "PB5"})
    with pytest.raises(ValueError, match="'Xa' is at PB5"):
        write_ld(prog)


NO_PART = """\
LDmicro export text.
no MCU assigned, 16 MHz crystal, 10.000 ms cycle time

LADDER DIAGRAM:
    ||     Xstart           Ymotor      ||
0001||-------] [--------------( )-------||
    ||                                  ||
   1||------[END]-----------------------||

I/O ASSIGNMENT:
  Name                       | Type               | Pin | Port | Pin name
 ----------------------------+--------------------+-----+------+-----------
  Xstart                     | digital in         | PD2 |       |
  Ymotor                     | digital out        | PB5 |       |
"""


def test_convert_refuses_and_writes_nothing(tmp_path, capsys):
    source = tmp_path / "motor.ladder"
    source.write_text(NO_PART, encoding="utf-8")
    assert main(["convert", str(source), str(tmp_path / "motor.ld")]) == 1
    err = capsys.readouterr().err.splitlines()
    assert [line.split(" error ")[0] for line in err] == [f"{source}:13:3:", f"{source}:14:3:"]
    assert all(" LD013 " in line for line in err)
    assert not (tmp_path / "motor.ld").exists()
    header = "for 'Atmel AVR ATmega328 28-PDIP', 16 MHz crystal, 10.000 ms cycle time"
    source.write_text(NO_PART.replace("no MCU assigned, 16 MHz crystal, 10.000 ms cycle time", header),
                      encoding="utf-8")
    assert main(["convert", str(source), str(tmp_path / "motor.ld")]) == 0
    written = (tmp_path / "motor.ld").read_bytes()
    assert b"    Xstart at 4 0 0\r\n    Ymotor at 19 0 0\r\n" in written


@pytest.mark.parametrize("mcu, written", [
    ("atmega328p", "Atmel AVR ATmega328 28-PDIP"),
    ("m328p:32-TQFP", "Atmel AVR ATmega328 32-Pin packages"),
    ("PIC16F887:44-TQFP", "Microchip PIC16F887 44-TQFP"),
    ("Atmel AVR ATmega8 32-Pin packages", "Atmel AVR ATmega8 32-Pin packages"),
    ("PIC16F877A", "PIC16F877A"),  # LDmicro does not list it: it says so itself when it opens the file
])
def test_the_part_is_written_by_the_name_ldmicro_knows_it_by(mcu, written):
    prog = program([contact("Xa")], mcu=mcu, pins={"Xa": 0})
    assert f"\nMICRO={written}\n" in write_ld(prog, diagnostics=[])


def test_a_pin_left_empty_is_written_unassigned():
    prog = program([contact("Xa")], mcu="", pins={"Xa": ""})
    assert "    Xa at 0 0 0\n" in write_ld(prog, diagnostics=[])
