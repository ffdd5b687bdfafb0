"""What a program's storage is, as LDmicro's compiler makes it: which names
are bits, how many bytes each integer takes, which counter RES resets, the
random seed, a timer's period in scans, where the PERSIST variables sit in
the EEPROM. The simulator, the compiler's front end and the checks build on
these."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator

from .instructions import COUNTERS, INSTRUCTIONS, TIMERS
from .model import Element, Program
from .numbers import byte_needed
from .values import is_literal, literal_value

# the arithmetic overflow flag, a bit the compiler writes
OVERFLOW = "ROverflowFlagV"
# an integer variable the VAR LIST gives no size (LDmicro's default)
DEFAULT_SIZE = 2
# LDmicro seeds a name that has an SRAND element with C rand() at start-up; 1 makes runs repeat
DEFAULT_SEED = 1


class TimerError(ValueError):
    """A delay LDmicro refuses (TestTimerPeriod)."""


def timer_period(cycle_us: int, delay: int, adjust: int, name: str) -> int:
    """LDmicro's period in scans: (delay + adjust*cycle) // cycle, with its
    checks (TestTimerPeriod)."""
    cycle = cycle_us
    if cycle <= 0:
        raise TimerError(f"Timer '{name}': the cycle time must be positive to count a delay in scans")
    if delay <= 0:
        raise TimerError(f"Timer '{name}': delay cannot be zero or negative")
    plain = delay // cycle
    if plain <= 0:
        raise TimerError(f"Timer '{name}' = {delay / 1000:.3f} ms is shorter than "
                         f"the cycle time ({cycle / 1000:.3f} ms)")
    if plain + adjust <= 0:
        raise TimerError(f"Timer '{name}': total timer delay cannot be zero or "
                         "negative; increase the adjust value")
    if plain <= adjust:
        raise TimerError(f"Timer '{name}': an adjust as large as the delay is "
                         "meaningless; decrease the adjust value")
    return (delay + cycle * adjust) // cycle


# (instruction, operand) of the table's bit operands (contacts, coils...)
BIT_FIELDS = frozenset((key, f.name) for key, spec in INSTRUCTIONS.items() for f in spec.fields if f.kind == "bit")


def bit_operand(element: Element, field: str) -> bool:
    """Whether the element makes the name in its operand `field` a bit: a bit
    operand, or the name of a PWM output that SET PWM drives or RES stops."""
    if (element.kind, field) in BIT_FIELDS:
        return True
    return field == "name" and element.kind in ("SET_PWM", "RES") and str(element.args.get("name", "")).startswith("P")


def _declared(element: Element, cycle_us: int) -> Iterator[tuple[str, int | None]]:
    """(name, size) of what the element makes of a name: None for a bit, the
    bytes of a timer or counter sized to its values."""
    for field in element.spec.fields:
        if element.args.get(field.name) and bit_operand(element, field.name):
            yield str(element.args[field.name]), None
    delay = element.args.get("delay")
    if element.kind in TIMERS and isinstance(delay, int) and cycle_us > 0:
        yield str(element.args["name"]), min(4, byte_needed(delay // cycle_us))
    if element.kind in COUNTERS:
        init, limit = str(element.args.get("init", "0")), str(element.args["max"])
        if is_literal(init) and is_literal(limit):
            try:
                values = [literal_value(init), literal_value(limit)]
            except ValueError:
                return
            yield str(element.args["name"]), max(byte_needed(v) for v in values)


def variable_names(program: Program) -> tuple[set[str], dict[str, int]]:
    """Bit names, and the sizes LDmicro gives integer variables: VAR LIST
    sizes, with timers and counters sized to their values."""
    bits = {OVERFLOW}
    sizes = dict(program.var_sizes)
    cycle = program.settings.cycle_us
    for _, element in program.elements():
        for name, size in _declared(element, cycle):
            if size is None:
                bits.add(name)
            else:
                sizes[name] = size
    return bits, sizes


def variable_of(program: Program, name: str, users: Iterable[Element]) -> tuple[bool, int]:
    """What `variable_names` makes of one name, from the elements that use it
    (in program order), without reading the rest of the program: whether it
    is a bit, and its size as an integer."""
    bit = name == OVERFLOW
    size = program.var_sizes.get(name, DEFAULT_SIZE)
    cycle = program.settings.cycle_us
    for element in users:
        for declared, declared_size in _declared(element, cycle):
            if declared != name:
                continue
            if declared_size is None:
                bit = True
            else:
                size = declared_size
    return bit, size


def counter_defs(program: Program) -> dict[str, Element]:
    """For RES C...: the first counter of that name, searching CTU, CTD, CTC
    then CTR elements (LDmicro's order)."""
    by_kind: dict[str, dict[str, Element]] = {kind: {} for kind in COUNTERS}
    for _, element in program.elements():
        if element.kind in by_kind:
            by_kind[element.kind].setdefault(str(element.args["name"]), element)
    found: dict[str, Element] = {}
    for kind in COUNTERS:
        for name, element in by_kind[kind].items():
            found.setdefault(name, element)
    return found


def eeprom_layout(persists: Iterable[Element],
                  variable: Callable[[str], tuple[bool, int]]) -> list[tuple[Element, int, int]]:
    """(PERSIST element, first EEPROM address, address after it) of each
    PERSIST (in program order) of an integer variable: each gets its
    variable's bytes after the previous one's. `variable` says of a name
    whether it is a bit and its size (`variable_names`, `variable_of`)."""
    layout = []
    address = 0
    for element in persists:
        name = str(element.args.get("var", ""))
        if not name or is_literal(name):
            continue  # no variable to keep (LD303 and the lowering say so)
        bit, size = variable(name)
        if bit:
            continue  # the lowering refuses it first
        layout.append((element, address, address + size))
        address += size
    return layout


def eeprom_refusal(needed: int, eeprom_bytes: int) -> str | None:
    """Why PERSIST variables needing `needed` bytes up to the end of one do
    not fit an EEPROM of `eeprom_bytes`, or None when they do."""
    if needed <= eeprom_bytes:
        return None
    return f"the PERSIST variables need {needed} bytes of EEPROM; the part has {eeprom_bytes}"
