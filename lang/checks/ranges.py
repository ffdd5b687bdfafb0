"""What a name can hold and what a condition can give, as far as the
program's own writes say: the sound, deliberately simple value analysis
behind LD217 (a zone that is always off), LD316 (a comparison that cannot
change) and LD317 (a divisor that can be zero).

A variable holds its start value 0 and whatever the program writes into it.
When every write is a MOV of a constant, those constants and 0 are all it
can hold; any other write (arithmetic, a counter, an A/D reading, a UART,
PERSIST loading the EEPROM) may leave any value of its size, and so may a
Modbus master writing a name the I/O table gives a Modbus address.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product

from ..instructions import RELATIONS
from ..labels import token
from ..model import Element, Parallel, Series
from ..numbers import wrap
from .common import GENERATED, literal_or_none, signed_range, variable_of_uses

_TESTS = {
    "EQU": lambda a, b: a == b, "NEQ": lambda a, b: a != b, "GRT": lambda a, b: a > b,
    "GEQ": lambda a, b: a >= b, "LES": lambda a, b: a < b, "LEQ": lambda a, b: a <= b,
}
_PAIRS = 256  # value pairs tried one by one before falling back on the bounds


@dataclass(frozen=True)
class Values:
    """The values a name or a constant can have: `low`..`high` (a name's
    whole range), and when known exactly, `exact`. `assigned` are the
    constants the program's MOVs write (for a name only ever set to
    constants), `writer` the first element that can leave any value in it
    (rung, element: for messages)."""

    low: int
    high: int
    exact: frozenset[int] | None = None
    assigned: frozenset[int] | None = None
    writer: tuple[int, Element] | None = None

    @staticmethod
    def of(values: frozenset[int]) -> Values:
        return Values(min(values), max(values), values)


def reading(index, kinds: tuple[str, ...], fields: tuple[str, ...]) -> list[tuple[int, Element]]:
    """(rung, element) of each element of `kinds` whose operand in one of
    `fields` is one of the index's names, once, in program order: for a rule
    that is a function of those names' uses (NAMES), on the whole program's
    index or on that of a few names."""
    if index.uses is index.names:  # the whole program's: its elements by kind, without a walk of every use
        return [(rung, element) for rung, element in index.of_kind(*kinds)
                if any(token(element.args.get(field)) in index.uses for field in fields)]
    found: dict[int, tuple[int, Element]] = {}
    for uses in index.uses.values():
        for use in uses:
            if use.element.kind in kinds and use.field in fields:
                found.setdefault(id(use.element), (use.rung, use.element))
    return sorted(found.values(), key=lambda pair: pair[0])


def values_of(program, index, operand: str) -> Values | None:
    """The values of an operand (a constant or an integer variable), or None
    for a bit, a name nothing writes (LD131 reports it) or a malformed one."""
    # kept for the index's life: a variable compared in a thousand rungs is looked at once
    known = index.cache.setdefault("values_of", {})
    if operand not in known:
        known[operand] = _values_of(program, index, operand)
    return known[operand]


def _values_of(program, index, operand: str) -> Values | None:
    number = literal_or_none(operand)
    if number is not None:
        return Values.of(frozenset((number,)))
    if not operand or operand[0] == "$":
        return None
    uses = index.names.get(operand, ())
    bit, size = variable_of_uses(program, index, operand)
    writes = [use for use in uses if use.writes]
    if bit or not writes or operand in GENERATED or not isinstance(size, int) or not 1 <= size <= 4:
        return None
    low, high = signed_range(size)
    pin = program.pins.get(operand)
    if pin is not None and (pin.modbus_slave or pin.modbus_register):
        return Values(low, high)
    assigned = set()
    for use in writes:
        source = literal_or_none(str(use.element.args.get("src"))) if use.element.kind == "MOVE" else None
        if source is None:
            return Values(low, high, writer=(use.rung, use.element))
        assigned.add(wrap(source, size))
    return Values(low, high, frozenset(assigned | {0}), frozenset(assigned))


def compare(kind: str, a: Values, b: Values) -> bool | None:
    """The result a comparison always gives, or None when it can change."""
    test = _TESTS[kind]
    if a.exact is not None and b.exact is not None and len(a.exact) * len(b.exact) <= _PAIRS:
        results = {test(x, y) for x, y in product(a.exact, b.exact)}
        return results.pop() if len(results) == 1 else None
    if kind in ("EQU", "NEQ"):
        disjoint = a.high < b.low or b.high < a.low
        return (kind == "NEQ") if disjoint else None
    # an order holds for every pair of the two ranges when it holds at the four corners, and
    # fails for every pair when it fails at all four
    if test(a.low, b.high) and test(a.high, b.low) and test(a.low, b.low) and test(a.high, b.high):
        return True
    if not (test(a.low, b.high) or test(a.high, b.low) or test(a.low, b.low) or test(a.high, b.high)):
        return False
    return None


def comparison_result(program, index, element: Element) -> bool | None:
    """What a comparison element always gives, or None."""
    a = values_of(program, index, str(element.args.get("op1")))
    b = values_of(program, index, str(element.args.get("op2")))
    if a is None or b is None:
        return None
    for constant, other in ((a, b), (b, a)):
        if constant.low == constant.high != other.low and not other.low <= constant.low <= other.high:
            return None  # a constant outside the variable's range: LD301's, or hex the code truncates
    return compare(element.kind, a, b)


def _never_written_bit(index, name: str) -> bool:
    """An internal relay or output nothing writes: it stays 0."""
    return name[:1] in ("R", "Y") and name not in GENERATED and not any(use.writes for use in index.names.get(name, ()))


def constant_power(program, index, node) -> bool | None:
    """Whether a circuit given power always passes it on (True), never does
    (False), or depends on the scan (None)."""
    if isinstance(node, Series):
        results = [constant_power(program, index, item) for item in node.items]
        if False in results:
            return False
        return True if all(result is True for result in results) else None
    if isinstance(node, Parallel):
        results = [constant_power(program, index, branch) for branch in node.branches]
        if True in results:
            return True
        return False if all(result is False for result in results) else None
    kind = node.kind
    if kind in ("SHORT", "LABEL"):
        return True
    if kind == "OPEN":
        return False
    if kind == "CONTACTS":
        name = str(node.args.get("name", ""))
        if _never_written_bit(index, name):
            return bool(node.args.get("negated"))
        return None
    if kind in RELATIONS:
        return comparison_result(program, index, node)
    return None


def condition_of(program, index, circuit: Series) -> bool | None:
    """The constant condition of a rung that ends in one element (GOTO,
    MASTER RLY): what the elements before it always give, or None."""
    return constant_power(program, index, Series(circuit.items[:-1]))
