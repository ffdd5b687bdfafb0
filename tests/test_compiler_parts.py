"""The nine AVR parts: their facts against avr-libc's headers, every part
found by LDmicro's name and short name, a program built for each whose
listing GNU avr-as reassembles to the same bytes (the static check of the
two parts simavr has no core for), and those two run as a sibling build."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from test_compiler_encoding import needs_avr_gcc, reassemble
from test_compiler_harness import Event, differential, load, needs_simavr

import compiler
from compiler.avr import part as avr_part
from compiler.avr.part import Part
from lang.devices import find_device
from lang.model import PinAssignment

AVR_INCLUDE = Path("/usr/lib/avr/include/avr")
HEADERS = {"atmega8": "iom8.h", "atmega16": "iom16.h", "atmega32": "iom32.h", "atmega64": "iom64.h",
           "atmega128": "iom128.h", "atmega162": "iom162.h", "atmega328p": "iom328p.h",
           "atmega1284p": "iom1284p.h", "atmega2560": "iom2560.h", "atmega48": "iom48.h", "atmega88": "iom88.h",
           "atmega168": "iom168.h", "atmega164p": "iom164p.h", "atmega324p": "iom324p.h", "atmega644p": "iom644p.h",
           "atmega32u4": "iom32u4.h", "at90usb647": "iousb647.h", "attiny85": "iotn85.h"}
LDMICRO_NAMES = {"atmega8": "Atmel AVR ATmega8 28-PDIP", "atmega16": "Atmel AVR ATmega16 40-PDIP",
                 "atmega32": "Atmel AVR ATmega32 40-PDIP", "atmega64": "Atmel AVR ATmega64 64-TQFP",
                 "atmega128": "Atmel AVR ATmega128 64-TQFP", "atmega162": "Atmel AVR ATmega162 40-PDIP",
                 "atmega328p": "Atmel AVR ATmega328 28-PDIP", "atmega1284p": "Atmel AVR ATmega1284 40-PDIP",
                 "atmega2560": "Atmel AVR ATmega2560 100-TQFP", "atmega48": "Atmel AVR ATmega48 28-PDIP",
                 "atmega88": "Atmel AVR ATmega88 28-PDIP", "atmega168": "Atmel AVR ATmega168 28-PDIP",
                 "atmega164p": "Atmel AVR ATmega164 40-PDIP", "atmega324p": "Atmel AVR ATmega324 40-PDIP",
                 "atmega644p": "Atmel AVR ATmega644 40-PDIP", "atmega32u4": "Atmel AVR ATmega32U4 44-Pin packages",
                 "at90usb647": "Atmel AVR AT90USB647 64-TQFP", "attiny85": "Atmel AVR ATtiny85 8-Pin packages"}
needs_headers = pytest.mark.skipif(not AVR_INCLUDE.is_dir(), reason="avr-libc not installed")


def _header(name: str) -> tuple[dict[str, int], dict[str, int], str]:
    text = (AVR_INCLUDE / name).read_text()
    registers = {"SPL": 0x5D, "SPH": 0x5E, "SREG": 0x5F}  # avr/common.h
    for m in re.finditer(r"#\s*define\s+(\w+)\s+_SFR_(IO|MEM)(?:8|16)\s*\((0[xX][0-9A-Fa-f]+)\)", text):
        registers.setdefault(m.group(1), int(m.group(3), 16) + (0x20 if m.group(2) == "IO" else 0))
    bits = {m.group(1): int(m.group(2)) for m in re.finditer(r"#\s*define\s+(\w+)\s+(\d)\b", text)}
    return registers, bits, text


def _constant(text: str, name: str) -> int:
    m = re.search(rf"#\s*define\s+{name}\s+\(?(0[xX][0-9A-Fa-f]+|\d+)", text)
    if m is None and name == "RAMEND":  # (RAMSTART + RAMSIZE - 1) on the ATmega32U4
        return _constant(text, "RAMSTART") + _constant(text, "RAMSIZE") - 1
    return int(m.group(1), 0)


@needs_headers
@pytest.mark.parametrize("part", sorted(HEADERS))
def test_part_facts_match_avr_libc(part):
    avr = find_device(part).data["avr"]
    registers, bits, text = _header(HEADERS[part])
    for name, address in avr["registers"].items():
        assert registers[name] == address, name
    assert avr["flash"] == _constant(text, "FLASHEND") + 1
    assert avr["eeprom"] == _constant(text, "E2END") + 1
    # the datasheets: 3.4 ms on the parts whose EEPROM has the EEPM mode bits, 8.5 ms on the older ones
    assert avr["eeprom_write_us"] == (3400 if "EEPM0" in bits else 8500)
    assert avr["ram"]["start"] == _constant(text, "RAMSTART")
    assert avr["ram"]["start"] + avr["ram"]["size"] - 1 == _constant(text, "RAMEND")
    cycle = avr["cycle_timer"]
    for flag in {"OCF1A", "TOV0"} & set(cycle):  # Timer1's compare match, the ATtiny85's Timer0 overflow
        assert bits[flag] == cycle[flag]
    assert bits.get("WDCE", bits.get("WDTOE")) == avr["watchdog"]["WDCE"] and bits["WDE"] == avr["watchdog"]["WDE"]
    sleep = avr["sleep"]
    assert sleep["power_down"] == 1 << bits["SE"] | 1 << bits["SM1"]
    # the bit positions the back end takes as the same on every part
    suffix = avr["uart"]["UDR"][-1] if "uart" in avr else ""  # the USART's number: UDR0, UDR1 (UDR: none)
    for name, value in (("TXC", avr_part.TXC), ("UDRE", avr_part.UDRE), ("RXC", avr_part.RXC),
                        ("U2X", avr_part.U2X), ("RXEN", avr_part.RXEN), ("TXEN", avr_part.TXEN)):
        if "uart" in avr:
            assert bits.get(name + suffix, bits.get(name)) == value, name
    if "TCCR1B" in avr["registers"]:
        assert bits["WGM12"] == avr_part.WGM12
    if "adc" in avr:
        assert bits["ADSC"] == avr_part.ADSC and bits["ADEN"] == avr_part.ADEN
    assert bits["EERE"] == avr_part.EERE and bits.get("EEWE", bits.get("EEPE")) == avr_part.EEWE
    assert bits.get("EEMWE", bits.get("EEMPE")) == avr_part.EEMWE
    if "MUX5" in avr.get("adc", {}):
        assert bits["MUX5"] == avr["adc"]["MUX5"][1]
    for unit, pwm in avr["pwm"].items():
        if "ocr" in pwm:
            timer, channel = pwm["timer"], unit[3:]
            assert pwm["com"] == 1 << bits[f"COM{timer}{channel}1"]
            if "top" in pwm:  # the ATtiny85's Timer1: PWM mode counting to OCR1C
                assert pwm["fast"] == 1 << bits[f"PWM{timer}{channel}"]
            else:
                assert pwm["fast"] == 1 << bits[f"WGM{timer}0"] | 1 << bits[f"WGM{timer}1"]


@pytest.mark.parametrize("part", sorted(LDMICRO_NAMES))
def test_parts_are_found_by_ldmicro_and_short_names(part):
    assert Part.of(find_device(LDMICRO_NAMES[part])).mmcu == part
    assert compiler.target_device(load("sample/traffic.ld"), part).part == part


@needs_avr_gcc
@pytest.mark.parametrize("part", sorted(LDMICRO_NAMES))
def test_listing_reassembles_to_the_same_bytes(part, tmp_path):
    program = load("sample/ctu_ctd_ctc.ld")
    # its outputs by port name, which every part has
    for name, port in zip(sorted(program.pins), ("PB0", "PB1", "PB2", "PB3", "PB4")):
        program.pins[name] = PinAssignment(name, port)
    build = compiler.build(program, part)
    assert reassemble(build.image.listing, part, tmp_path) == build.image.program_bytes()


@needs_avr_gcc
def test_a_large_program_with_long_jumps_and_tables_reassembles(tmp_path):
    program = load("sample/swatch2.ld")
    device = find_device(program.settings.mcu)
    for name, assignment in program.pins.items():  # by port name, to move it
        program.pins[name] = PinAssignment(name, device.pin(assignment.pin).name)
    for part in ("atmega2560", "atmega8", "at90usb647"):
        build = compiler.build(program, part)
        assert reassemble(build.image.listing, part, tmp_path) == build.image.program_bytes()


@needs_simavr
@pytest.mark.slow
def test_atmega162_and_64_run_as_sibling_builds(tmp_path):
    """simavr has no ATmega162 or ATmega64 core. The ATmega64's image of a
    program is byte for byte the ATmega128's (same I/O map), which runs; the
    ATmega162's integers.ld runs built for the ATmega16 with the same port
    bits (Xa PB0, Yno PD6, Yok PA2, by port name)."""
    traffic = load("sample/traffic.ld")
    sibling = compiler.build(traffic, "atmega128").image.program_bytes()
    assert compiler.build(traffic, "atmega64").image.program_bytes() == sibling
    program = load("reg/tests/integers.ld")
    native = compiler.build(program)
    assert native.device.part == "atmega162"
    for name, port in (("Xa", "PB0"), ("Yno", "PD6"), ("Yok", "PA2")):
        program.pins[name] = PinAssignment(name, port)
    events = [Event(0, "Xa", 0), Event(30, "Xa", 1), Event(60, "Xa", 0)]
    assert differential(program, events, 100, tmp_path, target="atmega16") == []


def test_the_avr_gcc_tools_are_installed():
    """.ci/run installs gcc-avr: the listing checks must never pass by not running."""
    assert shutil.which("avr-gcc") and shutil.which("avr-objcopy")
