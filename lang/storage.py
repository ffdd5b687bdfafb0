"""What a program's storage is, as LDmicro's compiler makes it: which names
are bits, how many bytes each integer takes, which counter RES resets, the
random seed, a timer's period in scans. The simulator and the compiler's
front end both build on these."""

from __future__ import annotations

from .instructions import COUNTERS, TIMERS
from .model import Element, Program
from .numbers import byte_needed
from .values import is_literal, literal_value

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


def variable_names(program: Program) -> tuple[set[str], dict[str, int]]:
    """Bit names, and the sizes LDmicro gives integer variables: VAR LIST
    sizes, with timers and counters sized to their values."""
    bits = {"ROverflowFlagV"}
    sizes = dict(program.var_sizes)
    cycle = program.settings.cycle_us
    for _, element in program.elements():
        for field in element.spec.fields:
            if field.kind == "bit" and element.args.get(field.name):
                bits.add(str(element.args[field.name]))
        if element.kind in ("SET_PWM", "RES") and str(element.args.get("name", "")).startswith("P"):
            bits.add(str(element.args["name"]))
        delay = element.args.get("delay")
        if element.kind in TIMERS and isinstance(delay, int) and cycle > 0:
            sizes[str(element.args["name"])] = min(4, byte_needed(delay // cycle))
        if element.kind in COUNTERS:
            init, limit = str(element.args.get("init", "0")), str(element.args["max"])
            if is_literal(init) and is_literal(limit):
                try:
                    values = [literal_value(init), literal_value(limit)]
                except ValueError:
                    continue
                sizes[str(element.args["name"])] = max(byte_needed(v) for v in values)
    return bits, sizes


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
