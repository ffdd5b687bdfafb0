"""Build model Programs in tests without a reader, and run the checks on them.

`el("TON", name="T1", delay=100000)` fills the operands it is not given with
the instruction table's defaults; `contact`, `coil`, `timer`... are shorthands.
`program(...)` takes rungs (lists or Series of items) and gives every element,
operand and pin assignment a distinct span, so a test can assert where a
diagnostic points: `span_of(el, "name")` is the span of an operand.
"""

from __future__ import annotations

from lang.checks import check_program
from lang.diagnostics import Diagnostic
from lang.instructions import INSTRUCTIONS
from lang.model import Element, Parallel, PinAssignment, Program, Rung, Series, Settings, Span, iter_elements


def el(_kind: str, **args) -> Element:
    kind = _kind  # counters have an operand called "kind"
    spec = INSTRUCTIONS[kind]
    full = {}
    for f in spec.fields:
        full[f.name] = args.pop(f.name) if f.name in args else f.default
    if args:
        raise TypeError(f"{kind} has no operands {sorted(args)}")
    return Element(kind, full)


def contact(name: str, negated: int = 0, set1: int = 0) -> Element:
    return el("CONTACTS", name=name, negated=negated, set1=set1)


def coil(name: str, type: str = " ") -> Element:
    return el("COIL", name=name, type=type)


def timer(kind: str, name: str, delay, adjust: int = 0) -> Element:
    return el(kind, name=name, delay=delay, adjust=adjust)


def counter(key: str, name: str, max, init="0", edge: str = "/") -> Element:
    return el(key, name=name, max=str(max), init=str(init), kind=edge)


def move(dest: str, src) -> Element:
    return el("MOVE", dest=dest, src=str(src))


def par(*branches) -> Parallel:
    return Parallel([b if not isinstance(b, list) else Series(b) for b in branches])


def ser(*items) -> Series:
    return Series(list(items))


def _circuit(items) -> Series:
    if isinstance(items, Series):
        return items
    if isinstance(items, (Element, Parallel)):
        return Series([items])
    return Series(list(items))


def program(*rungs, mcu: str | None = None, pins: dict | None = None, sizes: dict | None = None,
            cycle_us: int = 10000, **settings) -> Program:
    """A program whose rung i holds the given items. Spans: element k of rung
    i (in evaluation order) is line i, columns 100*k .. 100*k+50; its operand
    j sits at columns 100*k+10*j+1 .. +9. Pin assignments are on lines 1000+."""
    built = []
    for line, items in enumerate(rungs):
        circuit = _circuit(items)
        rung = Rung(circuit, span=Span(line, 0, line, 10000))
        for k, element in enumerate(iter_elements(circuit)):
            element.span = Span(line, 100 * k, line, 100 * k + 50)
            element.arg_spans = {
                f.name: Span(line, 100 * k + 10 * j + 1, line, 100 * k + 10 * j + 9)
                for j, f in enumerate(element.spec.fields)
            }
        built.append(rung)
    assignments = {}
    for n, (name, pin) in enumerate((pins or {}).items()):
        assignments[name] = PinAssignment(name, pin, span=Span(1000 + n, 4, 1000 + n, 4 + len(name)))
    return Program(
        settings=Settings(mcu=mcu, cycle_us=cycle_us, **settings),
        rungs=built,
        pins=assignments,
        var_sizes=dict(sizes or {}),
    )


def span_of(element: Element, field: str | None = None) -> Span:
    return element.span if field is None else element.arg_spans[field]


# --- running the checks -----------------------------------------------------------


def found(program, code: str) -> list[Diagnostic]:
    return [d for d in check_program(program) if d.code == code]


def one(program, code: str) -> Diagnostic:
    hits = found(program, code)
    assert len(hits) == 1, f"expected one {code}, got {[d.message for d in hits]}"
    return hits[0]


def none(program, code: str) -> None:
    hits = found(program, code)
    assert not hits, f"unexpected {code}: {[d.message for d in hits]}"


def words(diagnostic: Diagnostic, *expected: str) -> None:
    for word in expected:
        assert word in diagnostic.message, f"{word!r} not in {diagnostic.message!r}"


# an ATmega328P program with an instruction no back end compiles (SPI, LDmicro's C back ends only: LD501 when built)
NOT_COMPILED_LD = """LDmicro0.2
MICRO=Atmel AVR ATmega328 28-PDIP
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Xa at 4 0 0
END

PROGRAM
RUNG
  CONTACTS Xa 0 0
  SPI SPI1 s d Master 0 8 MSB 1000000
END
"""
