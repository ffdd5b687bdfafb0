"""The families of parts `ladder build` compiles for, as data.

A family's key is the support-column key of the instruction table
(`lang.instructions.LAYERS`) and the `family` of its device files
(`lang/devices/*.json`). Its `parts` are the device-file part keys its back
end compiles (`compiler/avr/`, `compiler/pic16/`, `compiler/pic18/`,
`compiler/pic10/`). The compiler, the checks,
the command line and the language server all read this table; `lang` never
imports the compiler (docs/architecture.md).

A listed part without a device file yet is left out of everything shown:
only parts with pin data can be selected.
"""

from __future__ import annotations

from dataclasses import dataclass

from .devices import Device, find_device, part_names


@dataclass(frozen=True)
class Family:
    key: str  # instruction table support key and device files' "family"
    title: str  # for messages: "the AVR back end"
    parts: tuple[str, ...]  # device-file part keys the family's back end compiles


FAMILIES: dict[str, Family] = {
    family.key: family
    for family in (
        Family("avr", "AVR", ("atmega8", "atmega16", "atmega32", "atmega64", "atmega128", "atmega162",
                              "atmega328p", "atmega1284p", "atmega2560", "atmega48", "atmega88", "atmega168",
                              "atmega164p", "atmega324p", "atmega644p", "atmega32u4", "at90usb647", "attiny85", "attiny10")),
        Family("pic16", "PIC16", ("pic16f628", "pic16f628a", "pic16f876", "pic16f876a", "pic16f877",
                                  "pic16f877a", "pic16f88", "pic16f819", "pic16f886", "pic16f887",
                                  "pic16f72", "pic12f675", "pic12f683",
                                  # the enhanced mid-range core (`core` in their device files: compiler/pic16/enhanced/)
                                  "pic12f1840", "pic16f1512", "pic16f1516", "pic16f1527", "pic16f1824", "pic16f1827")),
        Family("pic18", "PIC18", ("pic18f4520", "pic18f2520")),
        Family("pic10", "PIC10", ("pic10f200", "pic10f202")),
        # portable C (`ladder build --emit c`): no part of its own, the program's pins are the user's runtime's
        Family("c", "C", ()),
    )
}


def family_of(device: Device) -> Family | None:
    return FAMILIES.get(device.family)


def compiled(device: Device) -> bool:
    """True when `ladder build` compiles for the device's part."""
    family = family_of(device)
    return family is not None and device.part in family.parts


def compiled_parts(family: Family) -> list[str]:
    """The family's parts that have a device file, in the family's order."""
    known = set(part_names())
    return [part for part in family.parts if part in known]


def parts_text() -> str:
    """`AVR: ATmega8, ATmega16, ...; PIC16: PIC16F628A, ...` for messages and --help."""
    groups = []
    for family in FAMILIES.values():
        devices = [find_device(part) for part in compiled_parts(family)]
        titles = [device.title for device in devices if device is not None]
        if titles:
            groups.append(f"{family.title}: {', '.join(titles)}")
    return "; ".join(groups)
