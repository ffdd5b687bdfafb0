"""Pin data of the microcontrollers textladder knows, one JSON file per part.

Each ``<part>.json`` holds the datasheet pinout of every package LDmicro offers
for that part, the LDmicro names of those packages (the ``MICRO=`` line of an
``.ld`` file), and which port bits LDmicro can use for the ADC, PWM and UART.
A package may carry a ``labels`` table: LDmicro prints a few pin names
differently per package (ATmega328 28-PDIP "PB0 PCINT0/CLKO/ICP1" but 32-pin
"PB0 PCINT0/ICP1/CLKO"), and the export text must match it.

``adc`` keys are pin names rather than strictly port bits: the 32-pin AVRs have
analog-only pins ADC6/ADC7 with no port bit behind them.

A Pin's ``port`` is one letter: "B" is PORTB/DDRB/PINB on an AVR, PORTB/TRISB
on a PIC. The 8-pin PIC12F parts have one port, GPIO (direction TRISIO), whose
pins are GP0..GP5: its letter is "P", as LDmicro numbers it (its 16th port).
A part that LDmicro does not list (the PIC16F877A and other A variants) has
empty ``ldmicro_names``; it is found by its short names only.

``reserved_pins`` names the I/O pins the chip may give to its oscillator,
reset input or programming interface, each with when it does: ``field``,
``mask`` and ``values`` (a PIC: the configuration word ANDed with the mask
is one of the values, gputils' symbols), ``clock_hz_internal`` (an AVR's
crystal pins: taken unless the crystal setting is one of these internal
oscillator frequencies; ``clock_source`` says what takes them otherwise,
when not a crystal on XTAL1/XTAL2: the ATtiny10's CLKI) or ``fuse`` (taken unless that fuse, which the build
does not write, is programmed). The check LD413 reads it.

Compilers may add their own top-level keys to the files; ``Device.data`` keeps
the whole document for them.
"""

from __future__ import annotations

import difflib
import json
import re
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

__all__ = [
    "Pin",
    "Device",
    "find_device",
    "all_devices",
    "packages_of",
    "part_names",
    "is_known_ldmicro_name",
]

_DIR = Path(__file__).resolve().parent
_NAMES_FILE = "ldmicro_names.json"
# "PB0", "RA5", "PL7": port letter then bit number; "GP3": the PIC12F's GPIO.
_PORT_BIT = re.compile(r"^(?:[PR]([A-L])|G(P))([0-7])$")


@dataclass(frozen=True)
class Pin:
    number: int
    name: str
    port: str | None
    bit: int | None
    label: str
    functions: tuple[str, ...] = ()
    # MCLR pins that double as an input (RE3, RA5, GP3): no output driver
    input_only: bool = False

    @property
    def is_io(self) -> bool:
        return self.port is not None

    @property
    def port_bit(self) -> tuple[str, int]:
        """An I/O pin's port letter and bit number."""
        if self.port is None or self.bit is None:
            raise ValueError(f"{self.name} is not an input/output pin")
        return self.port, self.bit


@dataclass(frozen=True)
class Device:
    part: str
    title: str
    family: str
    package: str
    ldmicro_name: str
    # Identity is (part, package); the tables are left out of ==/hash so a
    # Device can be a dict key.
    memory: dict = field(compare=False)
    pins: dict[int, Pin] = field(compare=False, repr=False)
    adc: dict[str, int] = field(compare=False, repr=False)
    pwm: dict[str, str] = field(compare=False, repr=False)
    uart: dict[str, str] = field(compare=False, repr=False)
    data: dict = field(compare=False, repr=False)

    def pin(self, ref: int | str) -> Pin | None:
        """A pin by package number (3 or "3") or by name ("pd2", "RB0", "AREF")."""
        if isinstance(ref, int):
            return self.pins.get(ref)
        text = ref.strip()
        if text.isdigit():
            return self.pins.get(int(text))
        wanted = text.upper()
        # Names like GND repeat; the lowest pin number answers.
        for number in sorted(self.pins):
            if self.pins[number].name.upper() == wanted:
                return self.pins[number]
        return None

    def adc_channel(self, pin: Pin) -> int | None:
        return self.adc.get(pin.name)

    def pwm_unit(self, pin: Pin) -> str | None:
        return self.pwm.get(pin.name)

    def io_pins(self) -> list[Pin]:
        return [self.pins[n] for n in sorted(self.pins) if self.pins[n].is_io]


def _norm(text: str) -> str:
    return " ".join(text.split()).lower()


def _build(doc: dict, package: dict) -> Device:
    io = doc["io"]
    overrides = package.get("labels", {})
    pins: dict[int, Pin] = {}
    for number, name in package["pins"].items():
        m = _PORT_BIT.match(name)
        if name in io and m:
            entry = io[name]
            pins[int(number)] = Pin(
                number=int(number),
                name=name,
                port=m.group(1) or m.group(2),
                bit=int(m.group(3)),
                label=overrides.get(name, entry["label"]),
                functions=tuple(entry.get("functions", ())),
                input_only=entry.get("input_only", False),
            )
        else:
            pins[int(number)] = Pin(int(number), name, None, None, "", ())
    names = package.get("ldmicro_names", [])
    return Device(
        part=doc["part"],
        title=doc["title"],
        family=doc["family"],
        package=package["package"],
        ldmicro_name=names[0] if names else "",
        memory=dict(doc.get("memory", {})),
        pins=pins,
        adc=dict(doc.get("adc", {})),
        pwm=dict(doc.get("pwm", {})),
        uart=dict(doc.get("uart", {})),
        data=doc,
    )


@cache
def _documents() -> dict[str, dict]:
    docs = {}
    for path in sorted(_DIR.glob("*.json")):
        if path.name == _NAMES_FILE:
            continue
        doc = json.loads(path.read_text(encoding="utf-8"))
        docs[doc["part"]] = doc
    return docs


@cache
def _device(part: str, package_name: str) -> Device:
    """One package's device, built when first asked for: a program names one
    part, and the editor's first check waited 3 ms for all 48 packages to be built."""
    doc = _documents()[part]
    return _build(doc, next(p for p in doc["packages"] if p["package"] == package_name))


@cache
def _index() -> tuple[dict[str, str], dict[str, tuple[str, str]]]:
    """(short name or alias -> part, LDmicro name -> (part, package))."""
    short: dict[str, str] = {}
    ldmicro: dict[str, tuple[str, str]] = {}
    for part, doc in _documents().items():
        for alias in [part, doc["title"], *doc.get("aliases", [])]:
            short.setdefault(_norm(alias), part)
        for package in doc["packages"]:
            for name in package.get("ldmicro_names", []):
                ldmicro[_norm(name)] = (part, package["package"])
    return short, ldmicro


def _package_matches(package: dict, wanted: str) -> bool:
    names = [package["package"], *package.get("package_aliases", [])]
    return any(_norm(n) == wanted for n in names)


@cache
def find_device(name: str) -> Device | None:
    """A device by LDmicro name, short name or alias, optionally "part:package".

    Case and repeated blanks do not matter; a bare part name gives the first
    package of its file.
    """
    short, ldmicro = _index()
    key = _norm(name)
    if key in ldmicro:
        return _device(*ldmicro[key])
    part_text, _, package_text = key.partition(":")
    part = short.get(part_text.strip())
    if part is None:
        return None
    packages = _documents()[part]["packages"]
    if not package_text.strip():
        return _device(part, packages[0]["package"])
    wanted = _norm(package_text)
    for package in packages:
        if _package_matches(package, wanted):
            return _device(part, package["package"])
    return None


def all_devices() -> list[Device]:
    """One Device per (part, package), sorted by part then package."""
    return [_device(part, package["package"]) for part, doc in sorted(_documents().items())
            for package in sorted(doc["packages"], key=lambda p: p["package"])]


def packages_of(part: str) -> list[Device]:
    """Every package of a part (its device-file key), in the file's order."""
    return [_device(part, package["package"]) for package in _documents()[part]["packages"]]


def part_names() -> list[str]:
    return sorted(_documents())


@cache
def _ldmicro_names() -> frozenset[str]:
    doc = json.loads((_DIR / _NAMES_FILE).read_text(encoding="utf-8"))
    return frozenset(_norm(n) for n in [*doc["names"], *doc.get("legacy", [])])


def is_known_ldmicro_name(name: str) -> bool:
    """True if LDmicro's MCU table lists this name, whether or not we have its pins.

    Lets a caller tell "known to LDmicro but without pin data here" (find_device
    gives None, this gives True) from a name nobody knows.
    """
    return _norm(name) in _ldmicro_names()


def similar_parts(name: str, limit: int = 3) -> list[str]:
    """Known part names closest to a misspelt one (LDmicro's names first)."""
    known = [d.ldmicro_name for d in all_devices() if d.ldmicro_name] + part_names()
    lowered = {k.lower(): k for k in known}
    return [lowered[m] for m in difflib.get_close_matches(name.lower(), list(lowered), n=limit, cutoff=0.5)]
