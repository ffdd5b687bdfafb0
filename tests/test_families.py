"""The registry of the families `ladder build` compiles for (lang/families.py)."""

from __future__ import annotations

import dataclasses

from lang.devices import all_devices, find_device, part_names
from lang.families import FAMILIES, compiled, compiled_parts, family_of, parts_text
from lang.instructions import LAYERS


def test_families_are_the_instruction_tables_family_supports():
    assert set(FAMILIES) == set(LAYERS) - {"parse", "check", "sim"}
    for key, family in FAMILIES.items():
        assert family.key == key and len(set(family.parts)) == len(family.parts)
    # every family compiles for parts but C, which writes source for none
    assert [key for key, family in FAMILIES.items() if not family.parts] == ["c"]


def test_every_device_file_belongs_to_a_family_that_compiles_it():
    for device in all_devices():
        assert family_of(device) is FAMILIES[device.family]
        assert compiled(device), device.part


def test_the_avr_family_is_ldmicros_avrs():
    assert FAMILIES["avr"].parts == ("atmega8", "atmega16", "atmega32", "atmega64", "atmega128", "atmega162",
                                     "atmega328p", "atmega1284p", "atmega2560", "atmega48", "atmega88", "atmega168",
                                     "atmega164p", "atmega324p", "atmega644p", "atmega32u4", "at90usb647",
                                     "attiny85", "attiny10")
    assert compiled(find_device("atmega328p")) and compiled(find_device("Microchip PIC16F877 40-PDIP"))


def test_parts_text_names_only_parts_with_a_device_file(monkeypatch):
    text = parts_text()
    assert text.startswith("AVR: ATmega8, ATmega16, ATmega32, ATmega64, ATmega128, ATmega162, ATmega328P, "
                           "ATmega1284P, ATmega2560, ATmega48, ATmega88, ATmega168, ATmega164P, ATmega324P, "
                           "ATmega644P, ATmega32U4, AT90USB647, ATtiny85, ATtiny10; PIC16: ")
    expected = "; ".join(f"{family.title}: " + ", ".join(find_device(p).title for p in compiled_parts(family))
                         for family in FAMILIES.values() if family.parts)
    assert text == expected
    known = set(part_names())
    assert all(set(compiled_parts(family)) <= known for family in FAMILIES.values())
    # a part listed before its device file exists changes nothing
    avr = FAMILIES["avr"]
    monkeypatch.setitem(FAMILIES, "avr", dataclasses.replace(avr, parts=avr.parts + ("atmega4809",)))
    assert parts_text() == text
