"""Device pin data: consistency, LDmicro's own exports, name lookup, datasheet spot checks."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from lang.devices import (
    Device,
    all_devices,
    find_device,
    is_known_ldmicro_name,
    part_names,
)

DEVICES_DIR = Path(__file__).resolve().parents[1] / "lang" / "devices"
SHARED = Path(__file__).resolve().parents[2] / "shared"
EXPORTS = SHARED / "corpus" / "ldmicro-export"

EXPECTED_PARTS = [
    "atmega8", "atmega16", "atmega32", "atmega64", "atmega128", "atmega162",
    "atmega328p", "atmega1284p", "atmega2560", "atmega48", "atmega88", "atmega168", "atmega164p", "atmega324p",
    "atmega644p", "atmega32u4", "at90usb647", "attiny85", "attiny10",
    "pic16f628", "pic16f628a",
    "pic16f72", "pic16f876", "pic16f876a", "pic16f877", "pic16f877a",
    "pic16f88", "pic16f819", "pic16f886", "pic16f887", "pic12f675", "pic12f683",
    "pic12f1840", "pic16f1512", "pic16f1516", "pic16f1527", "pic16f1824", "pic16f1827",
    "pic18f4520", "pic18f2520", "pic10f200", "pic10f202",
]
# LDmicro lists only the non-A parts and, of the PIC18s, the PIC18F4520: these have no LDmicro name
NOT_IN_LDMICRO = {"pic16f628a", "pic16f876a", "pic16f877a", "pic18f2520"}
PORT_BIT = {"avr": re.compile(r"^P[A-L][0-7]$"), "pic16": re.compile(r"^(R[A-G]|GP)[0-7]$"),
            "pic18": re.compile(r"^R[A-E][0-7]$"), "pic10": re.compile(r"^GP[0-3]$")}


def _doc(part: str) -> dict:
    return json.loads((DEVICES_DIR / f"{part}.json").read_text(encoding="utf-8"))


# ------------------------------------------------------------------ consistency


def test_all_expected_parts_present():
    assert part_names() == sorted(EXPECTED_PARTS)


def test_one_device_per_package_sorted():
    devices = all_devices()
    expected = sum(len(_doc(p)["packages"]) for p in EXPECTED_PARTS)
    assert len(devices) == expected
    keys = [(d.part, d.package) for d in devices]
    assert keys == sorted(keys) and len(set(keys)) == len(keys)


@pytest.mark.parametrize("part", EXPECTED_PARTS)
def test_part_file_is_consistent(part):
    doc = _doc(part)
    assert doc["part"] == part
    assert doc["family"] in PORT_BIT
    assert {"part", "title", "family", "aliases", "memory", "packages", "io", "adc", "pwm", "uart"} <= set(doc)
    assert all(a == a.lower() for a in doc["aliases"])
    assert {"flash", "ram", "eeprom"} <= set(doc["memory"])
    port_bit = PORT_BIT[doc["family"]]
    io = doc["io"]
    used = set()
    for package in doc["packages"]:
        numbers = sorted(int(n) for n in package["pins"])
        assert numbers == list(range(1, len(numbers) + 1)), package["package"]
        io_names = [n for n in package["pins"].values() if port_bit.match(n)]
        assert len(io_names) == len(set(io_names)), f"port bit on two pins in {package['package']}"
        assert set(io_names) <= set(io), set(io_names) - set(io)
        used |= set(io_names)
        assert bool(package["ldmicro_names"]) == (part not in NOT_IN_LDMICRO), package["package"]
        assert set(package.get("labels", {})) <= set(io_names)
    # io lists exactly the port bits some package brings out
    assert set(io) == used
    for bit, entry in io.items():
        assert port_bit.match(bit)
        assert entry["label"] == bit or entry["label"].startswith(bit + " ")
    all_pin_names = {n for p in doc["packages"] for n in p["pins"].values()}
    assert set(doc["adc"]) <= all_pin_names
    assert len(set(doc["adc"].values())) == len(doc["adc"])
    assert set(doc["pwm"]) <= set(io)
    assert set(doc["uart"]) in (set(), {"rx", "tx"})
    assert set(doc["uart"].values()) <= set(io)


@pytest.mark.parametrize("device", all_devices(), ids=lambda d: f"{d.part}:{d.package}")
def test_device_loads(device: Device):
    assert bool(device.ldmicro_name) == (device.part not in NOT_IN_LDMICRO)
    assert sorted(device.pins) == list(range(1, len(device.pins) + 1))
    io = device.data["io"]
    for pin in device.io_pins():
        assert pin.name in io
        assert pin.name == f"{pin.name[0]}{pin.port}{pin.bit}"
        assert pin.label.startswith(pin.name)
        assert device.pin(pin.name) is pin
        assert device.pin(pin.name.lower()) is pin
        assert device.pin(pin.number) is pin
        assert device.pin(str(pin.number)) is pin
    for pin in device.pins.values():
        if not pin.is_io:
            assert pin.label == "" and pin.bit is None
    # the UART and every PWM output sit on a pin of this package
    for bit in [*device.uart.values(), *device.pwm]:
        assert device.pin(bit) is not None and device.pin(bit).is_io


def test_ldmicro_names_of_parts_are_in_the_name_list():
    for part in EXPECTED_PARTS:
        for package in _doc(part)["packages"]:
            for name in package["ldmicro_names"]:
                assert is_known_ldmicro_name(name), name


def test_every_short_name_finds_its_own_part():
    """No alias is shared: an A part's names never answer for the non-A part."""
    owners = {}
    for part in EXPECTED_PARTS:
        doc = _doc(part)
        for name in [part, doc["title"].lower(), *doc["aliases"]]:
            assert owners.setdefault(name, part) == part, f"{name} of {part} and {owners[name]}"
            assert find_device(name).part == part, name


# ------------------------------------------------------------------ LDmicro's exports


def _export_rows():
    """(mcu, file, pin, port, pin name) for every pin row of every real export."""
    rows = []
    for path in sorted(EXPORTS.glob("*.txt")):
        text = path.read_text(encoding="utf-8", errors="replace")
        m = re.search(r"^for '([^']+)',", text, re.M)
        if not m or "I/O ASSIGNMENT:" not in text:
            continue
        section = text.split("I/O ASSIGNMENT:", 1)[1].split("VAR LIST:", 1)[0]
        for line in section.splitlines():
            cells = line.split("|")
            if len(cells) < 5:
                continue
            pin, port, name = cells[2].strip(), cells[3].strip(), cells[4].strip()
            if pin.isdigit() and port:
                rows.append((m.group(1), path.name, int(pin), port, name))
    return rows


def test_exports_match_pin_data():
    assert EXPORTS.is_dir(), f"no LDmicro exports at {EXPORTS}"
    rows = _export_rows()
    checked = 0
    mcus_with_data = set()
    for mcu, filename, number, port, name in rows:
        device = find_device(mcu)
        if device is None:
            assert is_known_ldmicro_name(mcu), mcu
            continue
        mcus_with_data.add(mcu)
        pin = device.pin(number)
        where = f"{filename}: pin {number} of {mcu}"
        assert pin is not None and pin.is_io, where
        assert pin.name == port, where
        assert pin.label == name, where
        checked += 1
    assert checked >= 50
    assert {
        "Atmel AVR ATmega8 28-PDIP",
        "Atmel AVR ATmega16 40-PDIP",
        "Atmel AVR ATmega128 64-TQFP",
        "Atmel AVR ATmega162 40-PDIP",
        "Atmel AVR ATmega328 28-PDIP",
        "Atmel AVR ATmega328 32-Pin packages",
        "Microchip PIC16F876 28-PDIP or 28-SOIC",
        "Microchip PIC16F877 40-PDIP",
    } <= mcus_with_data


# ------------------------------------------------------------------ name lookup


@pytest.mark.parametrize(
    "name, part, package",
    [
        ("Atmel AVR ATmega328 28-PDIP", "atmega328p", "28-PDIP"),
        ("atmel avr atmega328 32-pin packages", "atmega328p", "32-TQFP"),
        ("  Atmel AVR  ATmega128 64-TQFP ", "atmega128", "64-TQFP"),
        ("Microchip PIC16F877 40-PDIP", "pic16f877", "40-PDIP"),
        ("Microchip PIC16F628 18-PDIP or 18-SOIC", "pic16f628", "18-PDIP"),
        ("Microchip PIC16F72 28-Pin PDIP, SOIC, SSOP", "pic16f72", "28-PDIP"),
        ("Microchip PIC12F675 8-pin packages", "pic12f675", "8-PDIP"),
        ("microchip pic12f683 8-PIN PACKAGES", "pic12f683", "8-PDIP"),
        ("Microchip PIC16F887 44-TQFP", "pic16f887", "44-TQFP"),
        ("Atmel AVR ATmega1284 40-PDIP", "atmega1284p", "40-PDIP"),
        ("atmega328p", "atmega328p", "28-PDIP"),
        ("ATmega328P", "atmega328p", "28-PDIP"),
        ("atmega328", "atmega328p", "28-PDIP"),
        ("m328p", "atmega328p", "28-PDIP"),
        ("atmega328p:32-TQFP", "atmega328p", "32-TQFP"),
        ("ATMEGA328P:32-tqfp", "atmega328p", "32-TQFP"),
        ("atmega328p: 32-Pin packages", "atmega328p", "32-TQFP"),
        ("atmega32:44-tqfp", "atmega32", "44-TQFP"),
        ("pic16f877", "pic16f877", "40-PDIP"),
        ("16f877", "pic16f877", "40-PDIP"),
        ("pic16f877a", "pic16f877a", "40-PDIP"),
        ("P16F877A", "pic16f877a", "40-PDIP"),
        ("PIC16F628", "pic16f628", "18-PDIP"),
        ("16f628a", "pic16f628a", "18-PDIP"),
        ("pic16f876a:28-soic", "pic16f876a", "28-PDIP"),
        ("12f675:8-soic", "pic12f675", "8-PDIP"),
        ("pic16f887:44-TQFP", "pic16f887", "44-TQFP"),
        ("pic16f876:28-soic", "pic16f876", "28-PDIP"),
    ],
)
def test_find_device(name, part, package):
    device = find_device(name)
    assert device is not None, name
    assert (device.part, device.package) == (part, package)


def test_finding_one_part_builds_that_package_only():
    """A program names one part: the editor's first check builds its pins,
    not every package's."""
    from lang import devices

    devices._device.cache_clear()
    find_device.cache_clear()
    found = find_device("Atmel AVR ATmega8 28-PDIP")
    assert found is not None and (found.part, found.package) == ("atmega8", "28-PDIP")
    assert devices._device.cache_info().currsize == 1


def test_find_device_unknown():
    assert find_device("atmega9999") is None
    assert find_device("atmega328p:99-BGA") is None
    assert find_device("") is None
    assert find_device("St ARM STM32F40X 144-LQFP") is None


def test_ldmicro_name_of_device():
    assert find_device("atmega328p").ldmicro_name == "Atmel AVR ATmega328 28-PDIP"
    assert find_device("atmega328p:32-tqfp").ldmicro_name == "Atmel AVR ATmega328 32-Pin packages"
    assert find_device("pic16f877").ldmicro_name == "Microchip PIC16F877 40-PDIP"
    assert find_device("pic16f877a").ldmicro_name == ""


def test_known_ldmicro_names_without_data():
    for name in [
        "St ARM STM32F40X 144-LQFP",
        "ESP8266",
        "PC LPT COM",
    ]:
        assert is_known_ldmicro_name(name), name
        assert find_device(name) is None
    assert not is_known_ldmicro_name("Atmel AVR ATmega9999 28-PDIP")
    assert not is_known_ldmicro_name("atmega328p")


def test_devices_are_comparable_and_hashable():
    a = find_device("atmega328p")
    assert a == find_device("Atmel AVR ATmega328 28-PDIP")
    assert a != find_device("atmega328p:32-TQFP")
    assert len({a, find_device("ATmega328P")}) == 1


# ------------------------------------------------------------------ datasheet spot checks


def _names(device: Device, numbers) -> list[str]:
    return [device.pin(n).name for n in numbers]


def test_atmega128_tqfp_pinout():
    d = find_device("atmega128")
    assert _names(d, range(2, 10)) == [f"PE{i}" for i in range(8)]
    assert _names(d, range(10, 18)) == [f"PB{i}" for i in range(8)]
    assert _names(d, range(25, 33)) == [f"PD{i}" for i in range(8)]
    assert _names(d, range(35, 43)) == [f"PC{i}" for i in range(8)]
    assert _names(d, range(44, 52)) == [f"PA{i}" for i in range(7, -1, -1)]
    assert _names(d, range(54, 62)) == [f"PF{i}" for i in range(7, -1, -1)]
    assert d.adc_channel(d.pin("PF0")) == 0 and d.adc_channel(d.pin(54)) == 7
    assert d.uart == {"rx": "PD2", "tx": "PD3"}
    assert d.pwm_unit(d.pin("PB7")) == "OC2"


def test_atmega64_shares_the_atmega128_pinout():
    a, b = find_device("atmega64"), find_device("atmega128")
    assert {n: p.name for n, p in a.pins.items()} == {n: p.name for n, p in b.pins.items()}


def test_pic16f876_pinout():
    d = find_device("pic16f876")
    assert _names(d, range(2, 8)) == [f"RA{i}" for i in range(6)]
    assert _names(d, range(11, 19)) == [f"RC{i}" for i in range(8)]
    assert _names(d, range(21, 29)) == [f"RB{i}" for i in range(8)]
    assert not d.pin(1).is_io and not d.pin(8).is_io and not d.pin(20).is_io
    assert d.uart == {"rx": "RC7", "tx": "RC6"}
    assert d.adc_channel(d.pin("RA5")) == 4 and d.adc_channel(d.pin("RA4")) is None


def test_atmega328p_pdip():
    d = find_device("atmega328p")
    for channel in range(6):
        pin = d.pin(23 + channel)
        assert pin.name == f"PC{channel}"
        assert d.adc_channel(pin) == channel
        assert f"ADC{channel}" in pin.functions
    assert d.pin(2).name == "PD0" and d.pin(3).name == "PD1"
    assert d.uart == {"rx": "PD0", "tx": "PD1"}
    assert "RXD" in d.pin("PD0").functions and "TXD" in d.pin("PD1").functions
    assert d.pin("pd2").number == 4 and "INT0" in d.pin("PD2").functions
    assert d.pin(7).name == "VCC" and d.pin(8).name == "GND" and d.pin("gnd").number == 8
    assert d.pwm_unit(d.pin("PB1")) == "OC1A" and d.pwm_unit(d.pin("PB3")) == "OC2A"
    assert d.pwm_unit(d.pin("PD2")) is None and d.adc_channel(d.pin("PD2")) is None
    assert len(d.io_pins()) == 22


def test_atmega328p_32pin_analog_only_inputs():
    d = find_device("atmega328p:32-TQFP")
    adc6 = d.pin(19)
    assert adc6.name == "ADC6" and not adc6.is_io
    assert d.adc_channel(adc6) == 6 and d.adc_channel(d.pin(22)) == 7
    assert [d.pin(n).name for n in (30, 31, 32, 1, 2)] == ["PD0", "PD1", "PD2", "PD3", "PD4"]


@pytest.mark.parametrize("part", ["pic16f877", "pic16f877a"])
def test_pic16f877_pinout(part):
    d = find_device(part)
    assert _names(d, range(33, 41)) == [f"RB{i}" for i in range(8)]
    assert _names(d, (8, 9, 10)) == ["RE0", "RE1", "RE2"]
    assert _names(d, (25, 26)) == ["RC6", "RC7"]
    assert d.pwm == {"RC1": "CCP2", "RC2": "CCP1"}
    assert d.adc_channel(d.pin("RE2")) == 7


def test_pic16f72_pinout():
    d = find_device("pic16f72")
    assert _names(d, range(2, 8)) == [f"RA{i}" for i in range(6)]
    assert _names(d, range(11, 19)) == [f"RC{i}" for i in range(8)]
    assert _names(d, range(21, 29)) == [f"RB{i}" for i in range(8)]
    assert d.pwm == {"RC2": "CCP1"} and d.uart == {}
    assert d.adc_channel(d.pin("RA5")) == 4


@pytest.mark.parametrize("part", ["pic12f675", "pic12f683"])
def test_pic12f_gpio_pinout(part):
    """GP0..GP5 on pins 7..2, port "P" (GPIO) as LDmicro numbers it."""
    d = find_device(part)
    assert _names(d, range(7, 1, -1)) == [f"GP{i}" for i in range(6)]
    assert [(p.port, p.bit) for p in map(d.pin, range(7, 1, -1))] == [("P", i) for i in range(6)]
    assert not d.pin(1).is_io and not d.pin(8).is_io
    assert d.pin("gp3").label == "GP3 _MCLR (Input Only)"
    assert [d.adc_channel(d.pin(f"GP{i}")) for i in range(6)] == [0, 1, 2, None, 3, None]
    assert d.pwm == {} and d.uart == {}


def test_pic16f887_44tqfp_uart_by_port_bit():
    d = find_device("pic16f887:44-tqfp")
    assert d.pin("RC6").number == 44 and d.pin("RC7").number == 1
    assert d.uart == {"rx": "RC7", "tx": "RC6"}
