"""What a name is and where it is used: its role from its first letter, its
pin assignment on the selected part, the places that write and read it, and
the names an operand may take. Hover, completion and the quick fixes of the
language server ask here; nothing in this module knows about LSP.
"""

from __future__ import annotations

from bisect import bisect_left, insort
from dataclasses import dataclass
from weakref import WeakKeyDictionary

from lang.checks.common import GENERATED
from lang.index import ProgramIndex, Use
from lang.instructions import INSTRUCTIONS, Field
from lang.labels import describe
from lang.model import Program
from lang.roles import BIT_PREFIXES, PIN_PREFIXES, role
from lang.values import is_literal


def is_name(text: str) -> bool:
    """An operand that names a variable, not a constant."""
    return bool(text) and not is_literal(text) and text != "(none)"


@dataclass(frozen=True)
class PinInfo:
    pin: int | str  # as assigned: package pin number or port bit
    number: int | None  # package pin number, when the part's data knows it
    port: str  # port bit such as "PD2" ("" when unknown)
    label: str  # the datasheet's pin name ("PD2 PCINT18/INT0")
    part: str  # the part's title ("" without pin data)


def pin_of(program: Program, name: str) -> PinInfo | None:
    """The pin assigned to a name, resolved on the selected part if it has data."""
    assignment = program.pins.get(name)
    if assignment is None:
        return None
    device = None
    if program.settings.mcu:
        from lang.devices import find_device

        device = find_device(program.settings.mcu)
    pin = device.pin(assignment.pin) if device else None
    if pin is None or device is None:
        return PinInfo(assignment.pin, assignment.pin if isinstance(assignment.pin, int) else None, "", "",
                       f"{device.title} {device.package}" if device else "")
    return PinInfo(assignment.pin, pin.number, pin.name if pin.is_io else "", pin.label or pin.name,
                   f"{device.title} {device.package}")


@dataclass(frozen=True)
class NameUses:
    name: str
    writes: tuple[Use, ...]
    reads: tuple[Use, ...]
    uses: tuple[Use, ...]  # every use in evaluation order


def uses_of(index: ProgramIndex, name: str) -> NameUses:
    uses = tuple(index.uses.get(name, ()))
    return NameUses(name, tuple(u for u in uses if u.writes),
                    tuple(u for u in uses if u.reads), uses)


def known(program: Program, index: ProgramIndex, word: str) -> bool:
    """A name the program uses, assigns a pin or gives a size."""
    return word in index.uses or word in program.pins or word in program.var_sizes


def describe_use(use: Use) -> str:
    """"rung 3 (TON 'Tdly')"."""
    return f"rung {use.rung + 1} ({describe(use.element)})"


def summary(program: Program, index: ProgramIndex, name: str) -> list[str]:
    """Lines describing a name: role, pin, where written and read."""
    short, sentence = role(name)
    lines = [f"`{name}`: {sentence}."]
    if name in GENERATED:
        lines.append("The compiler writes this name itself.")
    pin = pin_of(program, name)
    if pin is not None:
        where = f"pin {pin.number}" if pin.number is not None else f"pin {pin.pin}"
        if pin.port:
            where += f" ({pin.label})" if pin.label and pin.label != pin.port else f" ({pin.port})"
        if pin.part:
            where += f" of the {pin.part}"
        lines.append(f"Assigned to {where}.")
    elif name[:1] in PIN_PREFIXES and len(name) > 1:
        lines.append("No pin assigned." if program.settings.mcu else "No pin assigned (no part selected).")
    found = uses_of(index, name)
    if found.writes:
        lines.append("Written in " + _places(found.writes) + ".")
    elif found.uses:
        lines.append("Never written by the program.")
    if found.reads:
        lines.append("Read in " + _places(found.reads) + ".")
    size = program.var_sizes.get(name)
    if size:
        lines.append(f"{size} bytes (VAR LIST).")
    return lines


def _places(uses: tuple[Use, ...], limit: int = 8) -> str:
    shown = [describe_use(u) for u in uses[:limit]]
    if len(uses) > limit:
        shown.append(f"{len(uses) - limit} more")
    return ", ".join(shown)


# --- what an operand may be --------------------------------------------------------

def field_of(kind: str, field_name: str) -> Field | None:
    instruction = INSTRUCTIONS.get(kind)
    if instruction is None:
        return None
    for f in instruction.fields:
        if f.name == field_name:
            return f
    return None


def allowed_prefixes(kind: str, field_name: str) -> str:
    """First letters a name in this operand may start with ("" = any)."""
    f = field_of(kind, field_name)
    return f.prefixes if f is not None else ""


def takes_name(kind: str, field_name: str) -> bool:
    f = field_of(kind, field_name)
    return f is not None and f.kind in ("bit", "var", "operand", "delay", "label")


def candidates(program: Program, index: ProgramIndex, kind: str | None, field_name: str | None,
               typed: str = "") -> list[str]:
    """Names already used in the program that fit an operand, filtered by the
    prefixes the operand allows and by what is typed; labels for label fields."""
    prefixes = allowed_prefixes(kind, field_name) if kind and field_name else ""
    f = field_of(kind, field_name) if kind and field_name else None
    if f is not None and f.kind == "label":
        labels = {str(e.args.get("label")) for _, e in index.elements
                  if e.kind in ("LABEL", "SUBPROG") and e.args.get("label")}
        names = sorted(filter(_offered, labels))
    else:
        names = _known_names(program, index)
    allowed = set(prefixes) if prefixes else None
    if f is not None and f.kind == "bit":
        allowed = set(BIT_PREFIXES) & allowed if allowed is not None else set(BIT_PREFIXES)
    if typed:
        # the names are sorted: those starting with what is typed are one run of them
        names = names[bisect_left(names, typed):bisect_left(names, typed + "\U0010ffff")]
    return _starting_with(names, allowed) if allowed is not None else list(names)


# symbol table -> (the program it was last asked for, the names it had, those that are
# names to offer, sorted)
_NAMES: WeakKeyDictionary[ProgramIndex, tuple[Program, set[str], list[str]]] = WeakKeyDictionary()


def _known_names(program: Program, index: ProgramIndex) -> list[str]:
    """Every name the program uses, assigns a pin or sizes, sorted: kept
    from one version to the next, the names that came or went put in or
    taken out (completion is asked while typing, and a program of 18,000
    rungs has 36,000 names: sorting them takes longer than the edit), and
    kept as they are while the program is the same (the set of them alone
    takes 3 ms to make)."""
    kept = _NAMES.get(index)
    if kept is not None and kept[0] is program and index.program is program:
        return kept[2]
    every = index.uses.keys() | program.pins.keys() | program.var_sizes.keys()
    if kept is None:
        names = sorted(n for n in every if _offered(n))
    elif kept[1] == every:
        names = kept[2]
    else:
        names = kept[2][:]
        for gone in kept[1] - every:
            if _offered(gone):
                del names[bisect_left(names, gone)]
        for new in every - kept[1]:
            if _offered(new):
                insort(names, new)
    _NAMES[index] = (program, every, names)
    return names


def _starting_with(names: list[str], firsts: set[str]) -> list[str]:
    """The sorted `names` whose first character is one of `firsts`: one run
    of them for each (a filter of 36,000 names took 2.6 ms)."""
    found: list[str] = []
    for first in sorted(firsts):
        found += names[bisect_left(names, first):bisect_left(names, chr(ord(first) + 1))]
    return found


def _offered(name: str) -> bool:
    return is_name(name) and not name.startswith("$")


# --- what the header and the I/O table may hold ---------------------------------------

def part_candidates() -> list[tuple[str, str]]:
    """(LDmicro part name, description) for every part with pin data."""
    from lang.devices import all_devices

    return [(d.ldmicro_name, f"{d.title} {d.package}, {len(d.io_pins())} I/O pins")
            for d in all_devices() if d.ldmicro_name]


def pin_candidates(program: Program, name: str = "") -> list[tuple[int, str, str]]:
    """(package pin number, port bit or pin name, datasheet label) of the pins
    of the selected part that fit a name: A/D pins for A names, PWM pins for P
    names, I/O pins otherwise; pins already assigned to another name last."""
    if not program.settings.mcu:
        return []
    from lang.devices import find_device

    device = find_device(program.settings.mcu)
    if device is None:
        return []
    if name[:1] == "A":
        pins = [p for p in device.pins.values() if device.adc_channel(p) is not None]
    elif name[:1] == "P":
        pins = [p for p in device.io_pins() if device.pwm_unit(p) is not None]
    else:
        pins = device.io_pins()
    taken = set()
    for other, assignment in program.pins.items():
        if other != name:
            pin = device.pin(assignment.pin)
            if pin is not None:
                taken.add(pin.number)
    pins = sorted(pins, key=lambda p: (p.number in taken, p.number))
    return [(p.number, p.name, p.label or p.name) for p in pins]


def unassigned_io_names(program: Program, index: ProgramIndex) -> list[str]:
    """X, Y, A and P names the program uses that have no I/O row yet."""
    return sorted(n for n in index.uses if n[:1] in PIN_PREFIXES and len(n) > 1 and n not in program.pins)
