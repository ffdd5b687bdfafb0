"""LDmicro's I/O list: every name of a program that takes a pin or a Modbus
address, in the order LDmicro keeps it.

LDmicro builds this list from the drawing whenever the program changes and
saves it as the `.ld` file's IO LIST, assigned or not (an unassigned name is
`at 0 0 0`). Which names it takes, and as what, is a fact of each operand
(the instruction table's `Field.io`); the list is ordered by LDmicro's I/O
type number, then by name as `strcmp` orders it.
"""

from __future__ import annotations

from typing import NamedTuple

from .labels import token
from .model import Program
from .roles import CYCLE_DUTY_PIN
from .values import is_literal_fast

# LDmicro's numbers for the I/O types it lists; they order the list
DIG_INPUT, DIG_OUTPUT, READ_ADC, PWM_OUTPUT = 7, 8, 9, 12
MODBUS_CONTACT, MODBUS_COIL, MODBUS_HREG = 21, 22, 23
MODBUS_TYPES = (MODBUS_CONTACT, MODBUS_COIL, MODBUS_HREG)
COUNTER = 5  # never listed, but an IO LIST line of a C name reads as one
UNLISTED = 99  # a pin the user gave a name LDmicro does not list: kept, last

TYPE_NAMES = {DIG_INPUT: "digital in", DIG_OUTPUT: "digital out", READ_ADC: "adc input",
              PWM_OUTPUT: "PWM out", MODBUS_CONTACT: "modbus contact", MODBUS_COIL: "modbus coil",
              MODBUS_HREG: "modbus Hreg", COUNTER: "counter", UNLISTED: "general var",
              32: "SPI MOSI", 33: "SPI MISO", 34: "SPI SCK", 35: "SPI _SS", 36: "I2C SCL", 37: "I2C SDA"}

# a bus name's pins: the name with these suffixes
BUS_PINS = {"spi": (("_MOSI", 32), ("_MISO", 33), ("_SCK", 34), ("__SS", 35)),
            "i2c": (("_SCL", 36), ("_SDA", 37))}
# an operand's name that LDmicro types by its first letter (other letters are not listed)
_BY_LETTER = {
    "bit": {"X": DIG_INPUT, "Y": DIG_OUTPUT, "P": PWM_OUTPUT, "I": MODBUS_CONTACT, "M": MODBUS_COIL},
    "auto": {"X": DIG_INPUT, "Y": DIG_OUTPUT, "A": READ_ADC, "M": MODBUS_COIL, "H": MODBUS_HREG},
}
_ANY_LETTER = {"adc": READ_ADC, "pwm": PWM_OUTPUT}
# how LDmicro reads an IO LIST line back: a bus pin by its suffix, anything else by its letter
_READ_LETTER = {**_BY_LETTER["bit"], **_BY_LETTER["auto"], "C": COUNTER}


class Io(NamedTuple):
    type: int
    name: str

    @property
    def type_name(self) -> str:
        return TYPE_NAMES[self.type]


def _bus_type(name: str) -> int | None:
    for suffixes in BUS_PINS.values():
        for suffix, io_type in suffixes:
            if suffix in name:
                return io_type
    return None


def bus_pin(name: str) -> bool:
    """A pin an SPI or I2C bus takes (`SPI1_MOSI`), named after its bus."""
    return _bus_type(name) is not None


def listed_type(name: str) -> int | None:
    """The type LDmicro gives an IO LIST line's name when it reads the file
    (None: it skips the line)."""
    bus = _bus_type(name)
    return bus if bus is not None else _READ_LETTER.get(name[:1])


def _named(value: object) -> str:
    name = token(value)
    # LDmicro refuses a name with '-' in its list (it asks for '_')
    return "" if not name or is_literal_fast(name) or "-" in name else name


def used_io(program: Program) -> set[Io]:
    """The I/O LDmicro's list takes from the drawing and the settings."""
    found: set[Io] = set()
    for _, element in program.elements():
        for field in element.spec.fields:
            if not field.io:
                continue
            name = _named(element.args.get(field.name))
            if not name:
                continue
            if field.io in BUS_PINS:
                found.update(Io(io_type, name + suffix) for suffix, io_type in BUS_PINS[field.io])
            elif field.io in _ANY_LETTER:
                found.add(Io(_ANY_LETTER[field.io], name))
            elif name[0] in _BY_LETTER[field.io]:
                found.add(Io(_BY_LETTER[field.io][name[0]], name))
    if program.settings.cycle_duty:
        found.add(Io(DIG_OUTPUT, CYCLE_DUTY_PIN))
    return found


def io_list(program: Program, encoding: str = "cp1252") -> list[Io]:
    """LDmicro's list, then each pin the program keeps for a name it no
    longer uses (LDmicro would forget it; we keep what the user assigned):
    by type, then by the name's bytes."""
    found = used_io(program)
    used = {io.name for io in found}
    for name in program.pins:
        if name not in used:
            io_type = listed_type(name)
            found.add(Io(UNLISTED if io_type is None else io_type, name))
    return sorted(found, key=lambda io: (io.type, io.name.encode(encoding, "replace")))
