"""Our two sections after LDmicro's: SETTINGS (program settings the export's
header line does not carry) and DETAILS (element parameters the drawing does
not show: LUT values, PWL points, timer adjust, UART byte counts, ...).
With them, `.ld -> .ladder -> .ld` loses nothing. Only what differs from
LDmicro's defaults is written, so most programs have neither section."""

from __future__ import annotations

import re
from dataclasses import fields as dataclass_fields
from functools import cache, lru_cache
from itertools import compress, count
from operator import attrgetter, is_not
from typing import Any

from .. import codes
from ..diagnostics import Diagnostic, error
from ..instructions import INSTRUCTIONS, Instruction
from ..model import Element, PinAssignment, Program, Rung, Series, Settings, Span
from .rungs import UnreadRung
from .sections import Section

# key in the file -> (Settings attribute, kind)
SETTING_KEYS = {
    "baud rate": ("baud", "int"),
    "cycle timer": ("cycle_timer", "int"),
    "cycle duty output": ("cycle_duty", "bool"),
    "configuration word": ("config_word", "hex"),
    "SPI rate": ("spi_rate", "int"),
    "I2C rate": ("i2c_rate", "int"),
    "compiled": ("compiled", "str"),
    "compiler": ("compiler", "str"),
    "LDmicro file version": ("ld_version", "str"),
}
PULLUP_PREFIX = "pull-ups "
# a name's Modbus address, which LDmicro keeps with its pin but its export does not show
MODBUS_PREFIX = "Modbus "
_MODBUS_RE = re.compile(r"slave (\d+), address (\d+)")

NAME_KINDS = ("var", "bit", "label", "token", "name")


# --- SETTINGS ----------------------------------------------------------------

def write_settings(program: Program) -> list[str]:
    defaults = Settings()
    lines = []
    for key, (attribute, kind) in SETTING_KEYS.items():
        value = getattr(program.settings, attribute)
        if value == getattr(defaults, attribute):
            continue
        if kind == "bool":
            text = "yes" if value else "no"
        elif kind == "hex":
            text = f"0x{value:X}"
        else:
            text = str(value)
        lines.append(f"  {key}: {text}")
    for port, mask in program.pullups.items():
        lines.append(f"  {PULLUP_PREFIX}{port}: 0x{mask:X}")
    for pin in program.pins.values():
        if pin.modbus_slave or pin.modbus_register:
            lines.append(f"  {MODBUS_PREFIX}{pin.name}: slave {pin.modbus_slave}, address {pin.modbus_register}")
    return lines


def read_settings(section: Section, program: Program, problems: list[Diagnostic]) -> None:
    for number, text in section.lines:
        said = _setting(text)
        if said is None:
            continue
        kind, first, second, third = said
        if kind == "problem":
            problems.append(error(codes.SECTION, first, Span.at(number, 0, len(text))))
        elif kind == "pullup":
            program.pullups[first] = second
        elif kind == "modbus":
            pin = program.pins.setdefault(first, PinAssignment(
                first, 0, span=Span.at(number, second, second + len(first))))
            pin.modbus_slave, pin.modbus_register = third
        else:
            setattr(program.settings, first, second)


# a line is parsed again only when its text changes (each edit reads the whole section: a
# Modbus slave's SETTINGS hold a line for each of its thousands of addresses)
@lru_cache(maxsize=16384)
def _setting(text: str) -> tuple[str, Any, Any, Any] | None:
    """What a SETTINGS line says: None for a blank line, ("problem", message,
    ...), ("pullup", port, mask, ...), ("modbus", name, its column, (slave,
    register)) or ("setting", attribute, value, ...)."""
    if not text.strip():
        return None
    key, colon, value = text.strip().partition(":")
    key, value = key.strip(), value.strip()
    if not colon:
        return "problem", "expected `key: value`", None, None
    try:
        if key.startswith(PULLUP_PREFIX):
            return "pullup", key[len(PULLUP_PREFIX):].strip(), int(value, 0), None
        if key.startswith(MODBUS_PREFIX):
            name = key[len(MODBUS_PREFIX):].strip()
            address = _MODBUS_RE.fullmatch(value)
            if not address or not name:
                return "problem", (f"bad Modbus address {value!r} for {name!r}: expected "
                                   "`Modbus NAME: slave N, address N`"), None, None
            column = text.find(name, text.index(MODBUS_PREFIX) + len(MODBUS_PREFIX))
            return "modbus", name, column, (int(address.group(1)), int(address.group(2)))
        if key not in SETTING_KEYS:
            return "problem", f"unknown setting {key!r}; known: " + ", ".join(SETTING_KEYS), None, None
        attribute, kind = SETTING_KEYS[key]
        assert attribute in _SETTINGS
        if kind == "bool":
            if value not in ("yes", "no"):
                raise ValueError(value)
            parsed: object = value == "yes"
        elif kind in ("int", "hex"):
            parsed = int(value, 0)
        else:
            parsed = value
        return "setting", attribute, parsed, None
    except ValueError:
        return "problem", f"bad value {value!r} for {key!r}", None, None


_SETTINGS = {f.name for f in dataclass_fields(Settings)}


# --- DETAILS --------------------------------------------------------------------

def identity(element: Element) -> str:
    """What names an element in DETAILS: its first drawn name (none for a
    comment: `COMMENT #3` is the third)."""
    name = _identity_field(element.kind)
    return "" if name is None else str(element.args[name])


@cache
def _identity_field(kind: str) -> str | None:
    """The field `identity` reads, looked up once an instruction (an open
    names every element of the program)."""
    drawn = [f for f in INSTRUCTIONS[kind].fields if f.drawn]
    for f in drawn:
        if f.kind in NAME_KINDS:
            return f.name
    return drawn[0].name if drawn and drawn[0].kind != "text" else None


def undrawn(element: Element) -> dict[str, object]:
    """The element's parameters the drawing does not show, where not default."""
    return {
        f.name: element.args.get(f.name, f.default)
        for f in element.spec.fields
        if not f.drawn and element.args.get(f.name, f.default) != f.default
    }


def _format_value(value: object) -> str:
    if isinstance(value, tuple):
        flat: list[object] = []
        for item in value:
            flat.extend(item if isinstance(item, tuple) else (item,))
        return " ".join(str(v) for v in flat)
    if value == "":
        return '""'
    return str(value)


def write_details(program: Program) -> list[str]:
    """The DETAILS lines: one for a name whose elements share their details,
    else one for each rung holding one of them, by the rung's number as the
    formatter draws it (`#n` after it for the n-th of that rung's when they
    differ there too)."""
    groups: dict[tuple[str, str], list[tuple[int, dict[str, object]]]] = {}
    for index, element in program.elements():
        if any(not f.drawn for f in element.spec.fields):
            groups.setdefault((element.kind, identity(element)), []).append((index, undrawn(element)))
    lines = []
    for (kind, name), found in groups.items():
        if not any(extra for _, extra in found):
            continue
        label = f"{kind} {name}".rstrip()
        if all(extra == found[0][1] for _, extra in found):
            lines.append(_detail_line(label, found[0][1]))
            continue
        by_rung: dict[int, list[dict[str, object]]] = {}
        for index, extra in found:
            by_rung.setdefault(index, []).append(extra)
        for index, extras in by_rung.items():
            where = f"{label} in rung {index + 1}"
            if all(extra == extras[0] for extra in extras):
                if extras[0]:
                    lines.append(_detail_line(where, extras[0]))
                continue
            for occurrence, extra in enumerate(extras, 1):
                if extra:
                    lines.append(_detail_line(f"{where} #{occurrence}", extra))
    return lines


def _detail_line(label: str, extra: dict[str, object]) -> str:
    return f"  {label}: " + ", ".join(f"{k} {_format_value(v)}" for k, v in extra.items())


# `<INSTRUCTION> <name> in rung <N> #<n>: <values>`, the name, the rung and the occurrence
# optional (a comment has no name: `COMMENT in rung 4: ...`)
_DETAIL_RE = re.compile(
    r"\s*(?P<kind>[A-Z0-9_]+)(?:\s+(?!(?:in\s+rung\s+\d+\s*)?(?:#\d+\s*)?:)(?P<name>.*?))?"
    r"(?:\s+in\s+rung\s+(?P<rung>\d+))?(?:\s+#(?P<n>\d+))?\s*:\s*(?P<rest>.*?)\s*\Z")


ElementNames = list[tuple[tuple[str, str], int]]
# where DETAILS puts values in one rung: (element's position in the rung, (field, value) pairs), in DETAILS order
Placed = tuple[tuple[int, tuple[tuple[str, object], ...]], ...]
# an element a DETAILS line names: (id of its rung's circuit, its position in the rung); a
# circuit keeps its identity when its rung moves, so a rung added above changes no target
ElementAt = tuple[int, int]


def element_names(rung: Rung) -> ElementNames:
    """((instruction, identity), position in the rung) of each element: what a DETAILS line names."""
    return [((element.kind, identity(element)), position) for position, element in enumerate(rung.elements())]


_rung_circuit = attrgetter("circuit")


class ElementIndex:
    """The elements a DETAILS line can name, kept from one read to the next
    and brought up to date for the rungs whose circuit changed, by
    id(circuit): each rung's `element_names` and drawn number (None:
    unnumbered), the elements of each (instruction, name) and the rungs drawn
    with each number; and each circuit's rung index."""

    def __init__(self) -> None:
        self.circuits: list[Series] = []  # by rung index (they stay alive while compared: ids stay theirs)
        self.where: dict[int, int] = {}  # id(circuit) -> rung index
        self._names: dict[int, ElementNames] = {}
        self._numbers: dict[int, int | None] = {}
        self._groups: dict[tuple[str, str], set[ElementAt]] = {}
        self._numbered: dict[int, set[int]] = {}

    def update(self, rungs: list[Rung], numbers: list[int | None]) -> set[object]:
        """Brings the index up to the rungs, `numbers` their drawn numbers;
        the (instruction, name) groups and rung numbers that changed."""
        circuits = list(map(_rung_circuit, rungs))
        old = self.circuits
        if len(circuits) == len(old):
            at = list(compress(count(), map(is_not, old, circuits)))
            gone, came = [old[index] for index in at], at
        else:
            # rungs added or removed: the rungs between the first and the last that differ
            # (those above and below keep their circuits, moved)
            shorter = min(len(old), len(circuits))
            first = next(compress(count(), map(is_not, old, circuits)), shorter)
            last = next(compress(count(), map(is_not, reversed(old), reversed(circuits))), shorter)
            last = min(last, shorter - first)
            gone, came = old[first:len(old) - last], list(range(first, len(circuits) - last))
        changed: set[object] = set()
        for circuit in gone:
            key = id(circuit)
            for name, position in self._names.pop(key):
                changed.add(name)
                group = self._groups[name]
                group.discard((key, position))
                if not group:
                    del self._groups[name]
            number = self._numbers.pop(key)
            if number is not None:
                changed.add(number)
                self._numbered[number].discard(key)
                if not self._numbered[number]:
                    del self._numbered[number]
        for index in came:
            key = id(circuits[index])
            self._names[key] = names = element_names(rungs[index])
            for name, position in names:
                changed.add(name)
                self._groups.setdefault(name, set()).add((key, position))
            number = self._numbers[key] = numbers[index]
            if number is not None:
                changed.add(number)
                self._numbered.setdefault(number, set()).add(key)
        if len(circuits) == len(old):
            for circuit in gone:
                del self.where[id(circuit)]
            self.where.update((id(circuits[index]), index) for index in came)
        else:
            self.where = dict(zip(map(id, circuits), count()))
        self.circuits = circuits
        return changed

    def targets(self, key: tuple[str, str], rung: int | None, occurrence: int | None) -> tuple[ElementAt, ...]:
        """The elements a DETAILS line names, in program order: those of `key`
        in the rungs drawn with number `rung` (None: in every rung), the
        `occurrence`-th of them in each (None: all); with no rung, the
        `occurrence`-th of the whole program (the older form)."""
        if rung is None:
            found = self._groups.get(key, set())
        else:
            found = {(circuit, position) for circuit in self._numbered.get(rung, ())
                     for named, position in self._names[circuit] if named == key}
        where = self.where
        ordered = sorted(found, key=lambda target: (where[target[0]], target[1]))
        if occurrence is None:
            return tuple(ordered)
        if rung is None:
            return tuple(ordered[occurrence - 1:occurrence])
        by_rung: dict[int, list[ElementAt]] = {}
        for target in ordered:
            by_rung.setdefault(target[0], []).append(target)
        return tuple(chosen for targets in by_rung.values() for chosen in targets[occurrence - 1:occurrence])


# what one DETAILS line does: its text, what its targets depend on (None: not a detail
# line), the elements it reaches, its values or what is wrong with them
_LinePlan = tuple[str, "tuple[str, str] | int | None", tuple[ElementAt, ...], "tuple[tuple[str, object], ...] | str"]


class Planner:
    """What the DETAILS section puts on each rung it names, by id(circuit),
    kept from one read to the next: a line is looked up again only when its
    text changed or what it names did (an edit of one rung changes the
    groups of that rung's elements and that rung's number; a line naming
    its rung by number depends on that number only; a rung added or removed
    changes those of its own elements and number, and no other's)."""

    def __init__(self) -> None:
        self._lines: list[_LinePlan] = []
        self.looked_up = 0  # lines looked up by the last plan (tests)

    def plan(self, section: Section, rungs: list[Rung], problems: list[Diagnostic], index: ElementIndex,
             changed: set[object]) -> dict[int, Placed]:
        """`index`: the rungs' ElementIndex (the reader keeps it up to date);
        `changed`: what `ElementIndex.update` said changed since the last plan."""
        old = self._lines if len(self._lines) == len(section.lines) else []
        lines: list[_LinePlan] = []
        plan: dict[int, list[tuple[int, tuple[tuple[str, object], ...]]]] = {}
        unread = None
        self.looked_up = 0
        for at, (number, text) in enumerate(section.lines):
            kept = old[at] if old else None
            if kept is not None and kept[0] == text and kept[1] not in changed:
                line = kept
            else:
                line = _line_plan(text, index)
                self.looked_up += 1
            lines.append(line)
            _, depends, targets, values = line
            if depends is None:
                if text.strip():
                    problems.append(error(codes.SECTION, "expected `<INSTRUCTION> <name>: <field> <value>, ...`",
                                          Span.at(number, 0, len(text))))
                continue
            if not targets:
                if unread is None:
                    unread = any(isinstance(rung, UnreadRung) for rung in rungs)
                if not unread:
                    problems.append(error(codes.SECTION, "no element of the diagram matches this detail",
                                          Span.at(number, 0, len(text))))
                # else its element may be in a rung that could not be read: that rung's errors say so
                continue
            if isinstance(values, str):
                problems.append(error(codes.SECTION, values, Span.at(number, 0, len(text))))
                continue
            for circuit, position in targets:
                plan.setdefault(circuit, []).append((position, values))
        self._lines = lines
        return {circuit: tuple(placed) for circuit, placed in plan.items()}


def _line_plan(text: str, index: ElementIndex) -> _LinePlan:
    parsed = _parse_line(text) if text.strip() else None
    if parsed is None:
        return text, None, (), ()
    key, rung, occurrence, values = parsed
    return text, key if rung is None else rung, index.targets(key, rung, occurrence), values


def name_columns(text: str) -> tuple[int, int] | None:
    """Where a DETAILS line writes the name of the element it names (start
    and end column), None when it names none: the words of `in rung N` and
    the values are no names."""
    match = _DETAIL_RE.match(text)
    if not match or match.group("kind") not in INSTRUCTIONS or not match.group("name"):
        return None
    return match.span("name")


# a DETAILS line is parsed again only when its text changes (each edit reads the whole section)
@lru_cache(maxsize=16384)
def _parse_line(text: str) -> tuple[tuple[str, str], int | None, int | None,
                                    tuple[tuple[str, object], ...] | str] | None:
    """((instruction, name), rung number, occurrence, the values or what is
    wrong with them) of a DETAILS line, None when it is not one."""
    match = _DETAIL_RE.match(text)
    if not match or match.group("kind") not in INSTRUCTIONS:
        return None
    instruction = INSTRUCTIONS[match.group("kind")]
    rung = int(match.group("rung")) if match.group("rung") else None
    occurrence = int(match.group("n")) if match.group("n") else None
    try:
        values: tuple[tuple[str, object], ...] | str = tuple(_parse_values(instruction, match.group("rest")).items())
    except ValueError as problem:
        values = str(problem)
    return (instruction.key, match.group("name") or ""), rung, occurrence, values


def set_details(rung: Rung, placed: Placed) -> Rung:
    """The rung with its DETAILS values set, in place: the reader gives it a
    copy (read rungs come from its cache, shared with earlier versions, which
    must not keep them)."""
    elements = list(rung.elements())
    for position, values in placed:
        elements[position].args.update(values)
    return rung


def _parse_values(instruction: Instruction, rest: str) -> dict[str, object]:
    values: dict[str, object] = {}
    for item in filter(None, (part.strip() for part in rest.split(","))):
        name, _, text = item.partition(" ")
        text = text.strip()
        try:
            field = instruction.get_field(name)
        except KeyError:
            raise ValueError(f"{instruction.key} has no detail {name!r}") from None
        if field.drawn:
            raise ValueError(f"{name!r} is drawn in the diagram; change it there")
        if text == '""':
            values[name] = ""
        elif field.kind == "values":
            values[name] = tuple(text.split())
        elif field.kind == "points":
            numbers = text.split()
            if len(numbers) % 2:
                raise ValueError("points come in x y pairs")
            values[name] = tuple(zip(numbers[0::2], numbers[1::2]))
        elif field.kind in ("int", "flag"):
            values[name] = int(text, 0)
        else:
            values[name] = text
    return values
