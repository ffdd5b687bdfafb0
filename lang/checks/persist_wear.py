"""LD330: a PERSIST variable that can change on every scan, so that PERSIST
writes the EEPROM on every scan and wears it out.

PERSIST writes only when the variable differs from its EEPROM copy
(docs/semantics.md), so what wears the EEPROM is a persistent variable that
changes scan after scan: one that an instruction feeds back into itself (ADD
and SUB with itself, NOT, NEG, XOR, rotations), a timer's count, an A/D
reading, a random number, or a copy of one of those (MOV, arithmetic, a
table), or a counter that counts on every scan (its `-` and `o` edges), each
on a rung that is not a one-shot's: a rung behind OSR, OSF, UART RECV or a
TON that its own rung resets (or behind a contact on a relay that only such a
rung's coil writes) runs once per event or period, which the rule leaves
alone. Counters on an edge and shift
registers step on edges and are left alone too."""

from __future__ import annotations

from dataclasses import dataclass

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex, Use
from ..instructions import COUNTERS, TIMERS
from ..labels import label, token
from ..model import Element, Parallel, Program, Series, iter_elements
from ..trampoline import run
from ..values import format_delay
from .common import arg_span, literal_or_none, rung_no

CODE = rule_code(__name__)

ENDURANCE = 100_000  # write cycles per EEPROM byte: the guaranteed minimum of the AVR and PIC datasheets
# elements that pass power for one scan per event: an edge of their input, a received byte
EVENTS = ("OSR", "OSF", "UART_RECV")
# instructions that feed their destination back into itself: they change it on every scan they run
# unless the other operand leaves it as it is (0 for ADD, SUB, XOR and the rotations)
SELF_FED = {"ADD": ("op1", "op2"), "SUB": ("op1", "op2"), "XOR": ("op1", "op2"), "ROL": ("op1",),
            "ROR": ("op1",), "NOT": ("op1",), "NEG": ("op1",)}
# instructions whose written value moves on its own from scan to scan
RUNNING = {**{kind: "counts the time in '{}' on every scan while it runs" for kind in TIMERS},
           "READ_ADC": "reads the A/D converter into '{}', whose last bits change from scan to scan",
           "RANDOM": "draws a new number into '{}' on every scan"}
# a counter counts on every scan with its input 1 (`-`) or 0 (`o`), otherwise on an edge
EVERY_SCAN_COUNT = {"-": "1", "o": "0"}
# instructions that write on edges or on events, whatever their sources do
STEPPED = frozenset(("SHIFT_REGISTER", "UART_RECV", "PERSIST", "RES", "QUAD_ENCOD"))


@dataclass(frozen=True)
class Change:
    """Why a name changes on every scan: the instruction that changes it."""

    rung: int
    element: Element
    why: str
    origin: Change | None = None  # for a copy: the instruction that changes what it copies

    def text(self) -> str:
        said = f"the {label(self.element)} in {rung_no(self.rung)} {self.why}"
        if self.origin is None:
            return said
        return f"{said}, and the {label(self.origin.element)} in {rung_no(self.origin.rung)} {self.origin.why}"


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    persists = index.of_kind("PERSIST")
    if not persists:
        return []
    gates = _Gates(program, index)
    found = []
    for rung, element in persists:
        name = token(element.args.get("var"))
        if not name or gates.edge(rung, element):
            continue
        change = gates.change(name)
        if change is None:
            continue
        found.append(report(
            CODE,
            f"'{name}' is kept in EEPROM by the PERSIST in {rung_no(rung)}, and {change.text()}: PERSIST "
            "writes it back each time it differs, "
            f"{_wear(program, index)}; change it on an edge (a one-shot, OSR, in front of the "
            f"{label(change.element)}), or persist a copy taken less often",
            arg_span(element, "var"),
            *([Related(change.element.span, f"the {label(change.element)} that changes '{name}' on every scan")]
              if change.element.span is not None else []),
        ))
    return found


def _wear(program: Program, index: ProgramIndex) -> str:
    """How often the EEPROM is written, and how long it lasts at that rate."""
    cycle = program.settings.cycle_us
    device = index.device
    write_us = device.data.get(device.family, {}).get("eeprom_write_us") if device is not None else None
    every = max(cycle, write_us or 0)
    if every <= 0:
        return (f"on every scan, as fast as the scan runs (no cycle time); an EEPROM byte lasts "
                f"{ENDURANCE:,} writes (the datasheets' guaranteed minimum)")
    rate = 1_000_000 / every
    paced = f"one every {format_delay(cycle)} scan" if every == cycle else \
        f"one per {format_delay(every)} write of the {device.title}'s EEPROM"
    return (f"up to {rate:g} writes a second ({paced}), so the {ENDURANCE:,} writes an EEPROM byte is "
            f"guaranteed (the datasheets' minimum) last about {_duration(ENDURANCE / rate)}")


def _duration(seconds: float) -> str:
    for unit, length in (("days", 86400), ("hours", 3600), ("minutes", 60)):
        if seconds >= 2 * length:
            return f"{seconds / length:.0f} {unit}"
    return f"{seconds:.0f} seconds"


class _Gates:
    """Which elements run only on an edge, and which names change on every
    scan, for one program (each rung's gating worked out once)."""

    def __init__(self, program: Program, index: ProgramIndex):
        self.program = program
        self.index = index
        self.gated: dict[int, set[int]] = {}
        self.pulses: dict[str, bool] = {}

    def edge(self, rung: int, element: Element) -> bool:
        """The element runs on one scan per event: every path to it passes a one-shot."""
        if rung not in self.gated:
            self.gated[rung] = self._gated(self.program.rungs[rung].circuit)
        return id(element) in self.gated[rung]

    def change(self, name: str) -> Change | None:
        """The first instruction that can change `name` on every scan, or None."""
        return run(self._change(name, frozenset()))

    def _change(self, name: str, seen: frozenset[str]):
        # a generator for lang.trampoline: a chain of copies may be thousands of names long
        seen = seen | {name}
        for use in self.index.uses.get(name, ()):
            if not use.writes or use.element.kind in STEPPED or self.edge(use.rung, use.element):
                continue
            found = yield self._changes(use, seen)
            if found is not None:
                return found
        return None

    def _changes(self, use: Use, seen: frozenset[str]):
        element = use.element
        if element.kind in RUNNING:
            return Change(use.rung, element, RUNNING[element.kind].format(use.name))
        if element.kind in COUNTERS:
            level = EVERY_SCAN_COUNT.get(str(element.args.get("kind")))
            return None if level is None else \
                Change(use.rung, element, f"counts in '{use.name}' on every scan its input is {level}")
        sources = [(field, token(element.args.get(field))) for field in _read_fields(element)]
        fed = SELF_FED.get(element.kind)
        if fed is not None and any(value == use.name for field, value in sources if field in fed):
            rest = [value for field, value in sources if field in fed and value != use.name]
            if not any(literal_or_none(value) == 0 for value in rest):
                return Change(use.rung, element, f"computes '{use.name}' from itself on every scan its rung is on")
        for _, value in sources:
            if value in seen or literal_or_none(value) is not None:
                continue
            source = yield self._change(value, seen)
            if source is not None:
                return Change(use.rung, element, f"copies '{value}' into '{use.name}'", source.origin or source)
        return None

    def _pulse(self, name: str) -> bool:
        """A relay that only coils behind a one-shot write: on for one scan per event."""
        if name not in self.pulses:
            self.pulses[name] = False  # a relay that feeds its own one-shot is no pulse
            writes = [use for use in self.index.uses.get(name, ()) if use.writes]
            self.pulses[name] = bool(writes) and all(
                use.element.kind == "COIL" and use.element.args.get("type", " ") == " "
                and self.edge(use.rung, use.element) for use in writes)
        return self.pulses[name]

    def _passes_edge(self, element: Element, resetting: set[int]) -> bool:
        if element.kind in EVENTS or id(element) in resetting:
            return True
        return element.kind == "CONTACTS" and not element.args.get("negated") and \
            self._pulse(token(element.args.get("name")))

    def _gated(self, circuit: Series) -> set[int]:
        """The ids of the elements of a rung that every path reaches through a one-shot."""
        through: dict[int, bool] = {}
        run(self._through(circuit, through, _self_resetting(circuit)))
        gated: set[int] = set()
        pending: list[tuple[object, bool]] = [(circuit, False)]
        while pending:
            node, behind = pending.pop()
            if isinstance(node, Element):
                if behind:
                    gated.add(id(node))
            elif isinstance(node, Series):
                for item in node.items:
                    pending.append((item, behind))
                    behind = behind or through[id(item)]
            elif isinstance(node, Parallel):
                pending.extend((branch, behind) for branch in node.branches)
        return gated

    def _through(self, node, through: dict[int, bool], resetting: set[int]):
        """Whether every path through `node` passes a one-shot, for it and each node inside."""
        if isinstance(node, Element):
            result = self._passes_edge(node, resetting)
        elif isinstance(node, Series):
            result = False
            for item in node.items:
                result = (yield self._through(item, through, resetting)) or result
        else:
            result = bool(node.branches)
            for branch in node.branches:
                result = (yield self._through(branch, through, resetting)) and result
        through[id(node)] = result
        return result


def _self_resetting(circuit: Series) -> set[int]:
    """The ids of the TONs of a rung that resets them: the rung's coil writes a
    relay that a negated contact of the rung reads (`[/Rtick]--[TON]--(Rtick)`),
    so the TON passes power for one scan per period, an event like a one-shot."""
    elements = list(iter_elements(circuit))
    coils = {token(e.args.get("name")) for e in elements if e.kind == "COIL" and e.args.get("type", " ") == " "}
    negated = {token(e.args.get("name")) for e in elements if e.kind == "CONTACTS" and e.args.get("negated")}
    if not coils & negated:
        return set()
    return {id(e) for e in elements if e.kind == "TON"}


def _read_fields(element: Element) -> list[str]:
    return [field.name for field in element.spec.fields if field.access == "read"]
