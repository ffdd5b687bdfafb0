"""The enhanced mid-range PIC16 parts' facts (lang/devices/pic12f1840.json,
pic16f1512/1516/1527/1824/1827.json) against gputils and LDmicro: the
same checks as the mid-range parts' (tests/test_pic16_parts.py: every SFR
and named bit of the header, RAM from __MAXRAM/__BADRAM and the linker
script's banks, memory sizes, configuration fields from the header's
symbols), and LDmicro 5.4.1.1's own MCU table (mcutable.h): its name for
the part, its configuration words, its I/O pins with their package
numbers, its A/D channels and its UART pins."""

from __future__ import annotations

import re
import tarfile
from functools import cache
from pathlib import Path

import pytest
import test_pic16_parts as base

from compiler.pic16.part import Part
from lang.devices import find_device, is_known_ldmicro_name
from lang.families import FAMILIES, compiled

LDMICRO_SOURCE = Path(__file__).parent / "../../shared/tools/ldmicro/ldmicro-5.4.1.1-src.tar.gz"

# part -> LDmicro's name, its pin table, A/D table, UART pins (RX, TX: package pin numbers)
PARTS = {
    "pic12f1840": ("Microchip PIC12F1840 8-pin packages", "Pic8Pin_", "Pic8PinAdcPinInfo"),
    "pic16f1512": ("Microchip PIC16F1512 28-Pin SPDIP, SOIC, SSOP", "Pic28Pin_SPDIP_SOIC_SSOP", "Pic16F1512AdcPinInfo"),
    "pic16f1516": ("Microchip PIC16F1516 28-Pin SPDIP, SOIC, SSOP", "Pic28Pin_SPDIP_SOIC_SSOP", "Pic16F1512AdcPinInfo"),
    "pic16f1527": ("Microchip PIC16F1527 64-Pin packages", "Pic16F1527IoPinInfo", "Pic16F1527AdcPinInfo"),
    "pic16f1824": ("Microchip PIC16F1824 14-Pin PDIP, SOIC, TSSOP", "Pic14PinIoInfo", "Pic16F1824AdcPinInfo"),
    "pic16f1827": ("Microchip PIC16F1827 18-Pin PDIP, SOIC", "Pic16f1827IoPinInfo", "Pic16F1827AdcPinInfo"),
}


@cache
def ldmicro_source(name: str) -> str:
    with tarfile.open(LDMICRO_SOURCE) as archive:
        member = next(m for m in archive.getmembers() if m.name.endswith(f"ldmicro/{name}"))
        file = archive.extractfile(member)
        assert file is not None
        return file.read().decode("latin-1")


def mcutable() -> str:
    return ldmicro_source("mcutable.h")


def _table(name: str) -> str:
    body = re.search(rf"\b{name}\[\]\s*=\s*\{{(.*?)\n\}};", mcutable(), re.S)
    assert body, name
    return "\n".join(line.split("//")[0] for line in body.group(1).splitlines() if not line.strip().startswith("//"))


def _entry(ldmicro_name: str) -> str:
    """The part's entry of SupportedMcus_, up to the next one."""
    text = mcutable()
    start = text.index(f'"{ldmicro_name}"')
    return text[start:text.index("\n    {", start)]


def ldmicro_config(ldmicro_name: str) -> list[int]:
    """The configuration word(s) of the entry, evaluated as LDmicro's C does
    (CONFIG2 in the high 16 bits)."""
    entry = re.sub(r"//[^\n]*", "", re.sub(r"/\*.*?\*/", "", _entry(ldmicro_name), flags=re.S))
    expression = re.search(r"EnhancedMidrangeCore14bit,\s*\d+,\s*(.*?),\s*(?:Pic\w+|nullptr)\s*,", entry, re.S)
    assert expression, ldmicro_name
    value = eval(expression.group(1).replace("\n", " "))  # integer literals, shifts and ORs only
    return [value & 0xFFFF, value >> 16 & 0xFFFF]


@pytest.mark.parametrize("part", sorted(PARTS))
def test_ldmicro_names_and_build(part):
    device = find_device(part)
    name = PARTS[part][0]
    assert is_known_ldmicro_name(name) and find_device(name) == device
    assert find_device(part.upper()) == device and compiled(device)
    assert part in FAMILIES["pic16"].parts and Part.of(device).facts["core"] == "enhanced"


@pytest.mark.parametrize("part", sorted(PARTS))
def test_pins_are_ldmicros(part):
    """Each I/O pin at LDmicro's package number; A/D channels and UART pins as LDmicro's table."""
    name, pins, adc = PARTS[part]
    device = find_device(part)
    for port, bit, number in re.findall(r"\{\s*'(\w)',\s*(\d+),\s*(\d+)", _table(pins)):
        assert device.pin(int(number)).name == f"R{port}{bit}", number
    for number, channel in re.findall(r"\{\s*(\w+),\s*(\w+)\s*\}", _table(adc)):
        assert device.adc_channel(device.pin(int(number))) == int(channel, 0), number
    rx, tx = re.search(r"\n\s*\{\s*(\d+),\s*(\d+)\s*\},", _entry(name)).groups()
    assert (device.data["uart"]["rx"], device.data["uart"]["tx"]) == (device.pin(int(rx)).name, device.pin(int(tx)).name)


@base.needs_gputils
def test_the_pic16f1824_pwm_pins_are_ldmicros_with_the_steering_bits_of_the_header():
    """LDmicro's PWM table offers pins 5 and 6 (RC5, RC4) on timer 1, its
    CCP1 (pic16.cpp: CCPR1L, CCP1CON), and 7 and 8 (RC3, RC2) on CCP2; an
    enhanced CCP in single-output mode drives P1A (RC5) or P1B (RC4), P2A
    (RC3) or P2B (RC2), as the pins' labels say, by the STRxA/STRxB bits of
    PSTRxCON (STRxA at reset)."""
    device = find_device("pic16f1824")
    rows = re.findall(r"\{\s*(\d+),\s*(\d+),", _table("Pic16F1824PwmPinInfo"))
    assert {device.pin(int(number)).name: f"CCP{timer}" for number, timer in rows} == device.pwm
    facts = Part.of(device).facts
    h = base.header(facts["processor"])
    for unit in ("CCP1", "CCP2"):
        steering = facts["pwm"][unit]["steering"]
        assert steering["register"] in h.registers
        # the pin's label names its output (LDmicro's: "RC4 P1B/TX/CK")
        outputs = {pin: re.search(rf"\bP{unit[-1]}([AB])\b", device.pin(pin).label)
                   for pin, u in device.pwm.items() if u == unit}
        assert steering["pins"] == {pin: h.bits[steering["register"]][f"STR{unit[-1]}{found.group(1)}"]
                                    for pin, found in outputs.items()}
        assert steering["reset"] == 1 << h.bits[steering["register"]][f"STR{unit[-1]}A"]


@pytest.mark.parametrize("part", sorted(PARTS))
def test_config_words_are_ldmicros(part):
    words = [value for _, value in Part.of(find_device(part)).config_words]
    assert words == ldmicro_config(PARTS[part][0])


@pytest.mark.parametrize("part", sorted(PARTS))
def test_the_internal_oscillator_is_set_as_ldmicro_sets_it(part):
    """OSCCON for each clock as LDmicro's pic16.cpp writes it (SPLLEN:IRCF at
    bit 3) on the parts it sets it for: those whose configuration word selects
    the internal oscillator."""
    facts = Part.of(find_device(part))
    code = ldmicro_source("pic16.cpp")
    sets = re.search(r'McuAs\(" PIC16F1824 "\).*?switch\(Prog.mcuClock\)(.*?)default:', code, re.S)
    assert sets
    ldmicro = {int(hz): int(value, 16) << 3 for hz, value in re.findall(r"case (\d+):\s*spllen_ircf = (0x[0-9A-F]+);",
                                                                    sets.group(1))}
    fosc = facts.config_field("FOSC")
    assert (fosc.symbol == "_FOSC_INTOSC") == (part in ("pic12f1840", "pic16f1824", "pic16f1827"))
    intosc = facts.feature("intosc")
    assert ({int(hz): value for hz, value in intosc["settings"].items()} if intosc else None) == (
        ldmicro if fosc.symbol == "_FOSC_INTOSC" else None)


@base.needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
@pytest.mark.parametrize("check", ["test_registers_and_bits_are_the_headers", "test_ram_is_inside_the_headers_memory",
                                   "test_ram_is_the_linker_scripts", "test_config_fields_are_the_headers_symbols"])
def test_memory_map_and_config_are_gputils(part, check):
    getattr(base, check)(part)


@base.needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
def test_memory_sizes_are_the_linker_scripts(part):
    """Program words (below the configuration space at 0x8000), pages of 2048
    words, data EEPROM (none on the PIC16F151x: LD705 for PERSIST there)."""
    data, device = base.pic16(part), find_device(part)
    script = base.linker_script(data["processor"])
    assert data["flash_words"] == max(s[-1] for s in script.code.values() if s[0] < 0x8000) + 1
    for name, span in script.code.items():
        if name.startswith("page"):
            assert span[0] // data["page_words"] == span[-1] // data["page_words"], name
    assert data["eeprom"] == len(script.code.get("eedata", ())) == device.memory["eeprom"]
    assert ("eeprom" in data["features"]) == (data["eeprom"] > 0)
