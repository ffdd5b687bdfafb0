"""Small helpers the rules share: how to name an element, a rung, an operand's
place in the source, and the value range of a variable of a given size."""

from __future__ import annotations

from functools import lru_cache

from ..diagnostics import Fix, Related, Rename, report
from ..families import compiled
from ..hardware import baud_facts
from ..index import Use
from ..instructions import COUNTERS, EOL_KINDS, INSTRUCTIONS, TIMERS
from ..labels import describe, label, token
from ..model import Element, Parallel, Series, Span, iter_elements
from ..numbers import cdiv
from ..roles import CYCLE_DUTY_PIN, ROLES, role
from ..storage import variable_of
from ..strings import ESCAPES, HEX
from ..values import format_delay, is_literal, literal_value

# What a rule's diagnostics depend on, its module's SCOPE (lang.checks.incremental
# re-runs a rule after an edit on what the edit touched, by its scope):
# RUNGS: each diagnostic on a rung is a function of that rung alone (and the
#   settings and variable sizes, never the pins; the program's names only for
#   the renames a fix offers), so the rule runs on the index of the changed rungs;
# NAMES: each is a function of one name's uses and marks, whole, so the rule runs
#   on the index of the names the changed rungs use;
# PROGRAM (a module without SCOPE): anything else; it runs on the whole index.
# A rule whose diagnostics fall in two scopes has `CHECKS`, its check function
# for each scope, instead of `check` and `SCOPE`.
RUNGS = "rungs"
NAMES = "names"
PROGRAM = "program"

UART_KINDS = ("UART_SEND", "UART_RECV", "UART_SEND_READY", "UART_RECV_AVAIL", "FORMATTED_STRING")


def first_uart_use(index) -> Element | None:
    """The first UART instruction of a program whose compiled part has UART
    facts (where the baud rate rules speak), or None."""
    device = index.device
    if not index.pins_matter or not compiled(device) or baud_facts(device) is None:
        return None
    uses = index.of_kind(*UART_KINDS)
    return uses[0][1] if uses else None

# Names the compiler writes itself (§4.2): never "read but never written".
GENERATED = frozenset({"ROverflowFlagV", "RUartRecvErrorFlag", "RUartSendErrorFlag", CYCLE_DUTY_PIN})


def rung_no(index: int) -> str:
    """Rungs are numbered from 1 in messages, as LDmicro and the drawing do."""
    return f"rung {index + 1}"


def arg_span(element: Element, field: str) -> Span | None:
    """Where an operand sits, or the element when the reader did not say."""
    span = element.arg_spans.get(field)
    return span if span is not None else element.span


@lru_cache(maxsize=4096)
def literal_or_none(text: str) -> int | None:
    """The value of a well-formed literal; None for names and malformed ones."""
    if not is_literal(text):
        return None
    try:
        return literal_value(text)
    except ValueError:
        return None


def is_decimal(text: str) -> bool:
    """A literal written in decimal (hex, binary, octal and characters may use
    the unsigned range of a variable, as LDmicro's hex variants allow)."""
    body = text.lstrip("+-").lower()
    if text.startswith("'"):
        return False
    return not (body.startswith(("0x", "0b", "0o")) or (len(body) > 1 and body.startswith("0")))


def var_size(program, name: str) -> int | None:
    """A variable's size in bytes (2 unless the VAR LIST says otherwise), or
    None when the VAR LIST gives no integer size (a table's, or nonsense)."""
    size = program.var_sizes.get(name, 2)
    return size if isinstance(size, int) and 1 <= size <= 4 else None


def signed_range(size: int) -> tuple[int, int]:
    bits = 8 * size
    return -(1 << (bits - 1)), (1 << (bits - 1)) - 1


def fits(value: int, size: int, decimal: bool) -> bool:
    low, high = signed_range(size)
    if low <= value <= high:
        return True
    return not decimal and 0 <= value <= (1 << (8 * size)) - 1


def range_text(size: int, decimal: bool) -> str:
    low, high = signed_range(size)
    text = f"{low} to {high}"
    if not decimal:
        text += f" (or 0 to {(1 << (8 * size)) - 1} written in hex)"
    return text


def mark_text(mark) -> str:
    """How a varflags Mark is named in messages: 'the TON timer of rung 2'."""
    from .varflags import ANY, PWM, RES, TABLE

    where = rung_no(mark.rung)
    if mark.flag in TIMERS:
        return f"the {mark.flag} timer of {where}"
    if mark.flag in COUNTERS:
        return f"the {mark.flag} counter of {where}"
    if mark.flag == PWM:
        return f"the SET PWM of {where}"
    if mark.flag == RES:
        return f"the RES of {where}"
    if mark.flag == TABLE:
        return f"the {label(mark.element)} table of {where}"
    assert mark.flag == ANY
    return f"{label(mark.element)} in {where}"


def mark_related(marks, limit: int = 4):
    """Related entries for the earlier uses a conflict is with."""
    related = []
    for mark in marks[:limit]:
        span = mark.element.arg_spans.get(mark.field) or mark.element.span
        if span is not None:
            related.append(Related(span, f"'{mark.name}' used here by {mark_text(mark)}"))
    return related


def first_element(node) -> Element | None:
    """The first element of a circuit in evaluation order."""
    return next(iter_elements(node), None)


def node_span(node) -> Span | None:
    """A node's span, or its first element's when the reader gave none."""
    if node.span is not None:
        return node.span
    element = first_element(node)
    return element.span if element is not None else None


def node_text(node) -> str:
    """'TON', 'coil', or 'a parallel block' for messages."""
    if isinstance(node, Element):
        return describe(node)
    return "a parallel block" if isinstance(node, Parallel) else "a series block"


def terminal(node) -> Element | None:
    """The end-of-line element a circuit ends in (any branch of a parallel), or None."""
    # a list of nodes still to look at, first branch first: a rung may nest hundreds deep
    pending = [node]
    while pending:
        node = pending.pop()
        if isinstance(node, Element):
            if node.kind in EOL_KINDS:
                return node
        elif isinstance(node, Series):
            if node.items:
                pending.append(node.items[-1])
        elif isinstance(node, Parallel):
            pending.extend(reversed(node.branches))
    return None


def table_of(element: Element, field: str) -> list:
    """A LUT's values or a PWL's points (the readers keep a list)."""
    found = element.args.get(field)
    return list(found) if isinstance(found, (list, tuple)) else []


def table_numbers(values) -> list[int] | None:
    """Table entries as integers, or None if one is not a well-formed constant
    (LD304 reports those)."""
    numbers = []
    for value in values:
        if isinstance(value, int):
            numbers.append(value)
            continue
        number = literal_or_none(str(value))
        if number is None:
            return None
        numbers.append(number)
    return numbers


TIMED = TIMERS + ("TIME2COUNT",)


def timer_periods(program, index) -> list[tuple]:
    """(rung, element, delay_us, adjust, P, Padj) for every timer with a
    constant delay, as LDmicro's TestTimerPeriod computes them (P = delay /
    cycle, Padj = (delay + adjust * cycle) / cycle, C integer division).
    P and Padj are None when the cycle time is 0 or less."""
    cached = index.cache.get("timer_periods")
    if cached is not None:
        return cached
    cycle = program.settings.cycle_us
    found = []
    for rung, element in index.of_kind(*TIMED):
        delay = element.args.get("delay")
        if not isinstance(delay, int):
            continue
        try:
            adjust = int(element.args.get("adjust") or 0)
        except (TypeError, ValueError):
            adjust = 0
        period: int | None = None
        adjusted: int | None = None
        if cycle and cycle > 0:
            period = cdiv(delay, cycle)
            adjusted = cdiv(delay + adjust * cycle, cycle)
        found.append((rung, element, delay, adjust, period, adjusted))
    index.cache["timer_periods"] = found
    return found


def timer_text(element: Element) -> str:
    """'TON 'Tdelay'' for messages."""
    return f"{element.kind} '{token(element.args.get('name'))}'"


def delay_text(microseconds: int) -> str:
    return format_delay(microseconds)




def scan_format(text: str) -> tuple[list[str], list[tuple[str, str]]]:
    """LDmicro's reading of a formatted string (intcode.cpp, FORMATTED_STRING):
    the interpolations found (`\\3`, `\\-5`...) and the bad escapes, each as
    (the sequence, what is wrong)."""
    interpolations: list[str] = []
    bad: list[tuple[str, str]] = []
    i, n = 0, len(text)
    while i < n:
        if text[i] != "\\":
            i += 1
            continue
        nxt = text[i + 1] if i + 1 < n else ""
        if nxt.isdigit() or nxt == "-":
            j = i + 1 + (nxt == "-")
            digit = text[j] if j < n else ""
            sequence = text[i:j + 1]
            interpolations.append(sequence)
            if not digit.isdigit() or digit == "0" or digit > "5":
                bad.append((sequence, "after \\ a digit count must be 1 to 5 (\\3, \\-3); "
                                      "for a literal backslash write \\\\"))
            i = j + 1
        elif nxt == "x":
            if text[i + 2:i + 3] in HEX and text[i + 3:i + 4] in HEX and i + 3 < n:
                i += 4
            else:
                bad.append((text[i:i + 4], "the correct form is \\xAB, two hex digits"))
                i += 2
        elif nxt in ESCAPES and nxt:
            i += 2
        else:
            bad.append((text[i:i + 2], "unknown escape; for a literal backslash write \\\\"))
            i += 2
    return interpolations, bad


# --- pins ------------------------------------------------------------------------


def pin_text(assignment) -> str:
    pin = assignment.pin
    return f"pin {pin}" if isinstance(pin, int) or str(pin).isdigit() else str(pin)


def is_analog(index, name: str) -> bool:
    """An A/D input: an A name, or one a READ ADC reads into."""
    return name.startswith("A") or _named_by(index, name, "READ_ADC")


def is_pwm(index, name: str) -> bool:
    """A PWM output: a P name, or one a SET PWM drives."""
    return name.startswith("P") or _named_by(index, name, "SET_PWM")


def _named_by(index, name: str, kind: str) -> bool:
    # a set of the kind's few elements, not a walk of the name's uses (thousands, for a shared pin)
    key = f"named by {kind}"
    names = index.cache.get(key)
    if names is None:
        names = index.cache[key] = {element.args.get("name") for _, element in index.of_kind(kind)}
    return name in names


def pwm_outputs(program, index) -> list[tuple]:
    """(rung, SET PWM element, PWM unit, frequency) of each SET PWM whose
    name sits on a PWM pin of a part a back end compiles, in program order;
    [] when the pins do not matter (no part, or C). The rules about an
    unassigned name, a pin without PWM or a frequency that is no number say
    what the others lack."""
    cached = index.cache.get("pwm_outputs")
    if cached is not None:
        return cached
    found = []
    device = index.device
    if index.pins_matter and compiled(device):
        for rung, element in index.of_kind("SET_PWM"):
            assignment = program.pins.get(token(element.args.get("name")))
            pin = device.pin(assignment.pin) if assignment is not None and assignment.assigned else None
            unit = device.pwm.get(pin.name) if pin is not None else None
            freq = literal_or_none(str(element.args.get("freq")))
            if unit is not None and freq is not None:
                found.append((rung, element, unit, freq))
    index.cache["pwm_outputs"] = found
    return found


def variable_of_uses(program, index, name: str) -> tuple[bool, int]:
    """Whether the lowering makes `name` a bit, and its size as an integer
    (lang.storage.variable_of), from the elements that use it."""
    return variable_of(program, name, (use.element for use in index.names.get(name, ())))


def used_pins(program, index) -> list[tuple]:
    """(name, assignment, Pin or None) for every assigned pin of a name the
    program uses, with the selected part's data; [] without a part we know."""
    cached = index.cache.get("used_pins")
    if cached is not None:
        return cached
    device = index.device
    found = []
    if device is not None:
        for name, assignment in program.pins.items():
            if name in index.uses and assignment.assigned:
                found.append((name, assignment, device.pin(assignment.pin)))
    index.cache["used_pins"] = found
    return found


def read_never_written(index) -> list[tuple[str, Use]]:
    """(name, its first read) for every name that is read but that nothing
    writes, compiler-generated and truncated names left out. Worked out once
    an index (LD101 and LD102 both ask), each use's access compared as it is
    (an open asks it of every use of every name)."""
    cached = index.cache.get("read never written")
    if cached is not None:
        return cached
    found = []
    for name, uses in index.uses.items():
        if name in GENERATED or name.endswith("~"):
            continue
        first_read = None
        for use in uses:
            access = use.access
            if access == "write" or access == "rw":
                break
            if first_read is None and access == "read":
                first_read = use
        else:
            if first_read is not None:
                found.append((name, first_read))
    index.cache["read never written"] = found
    return found


def prefix_fixes(index, element: Element, field_name: str) -> tuple[Fix, ...]:
    """Renames of an operand's name to each first letter its instruction
    allows, in the table's order: a role letter is replaced (`Xlamp` on a
    coil: `Ylamp`, `Rlamp`, `Mlamp`), anything else gets one in front
    (`delay` on a timer: `Tdelay`). Names the program already uses are not
    offered: the rename would merge two things."""
    name = token(element.args.get(field_name))
    spec = INSTRUCTIONS.get(element.kind)
    field = next((f for f in spec.fields if f.name == field_name), None) if spec else None
    if field is None or not field.prefixes or not name or is_literal(name):
        return ()
    body = name[1:] if name[0] in ROLES and len(name) > 1 else name
    return tuple(Fix(f"Rename '{name}' to '{p + body}' ({role(p)[0]})", Rename(name, p + body))
                 for p in field.prefixes if p + body != name and p + body not in index.names)


def offering(name: str) -> set[str]:
    """The names whose `prefix_fixes` may offer a rename to `name` (with the
    first letter replaced or put in front), and so change when it comes into
    use or goes out of it."""
    if len(name) < 2:
        return set()
    body = name[1:]
    return ({letter + body for letter in ROLES} | {body}) - {name}


def misnamed(index, code: str, kinds, letter: str, noun: str):
    """Warnings for the elements of `kinds` whose name does not start with
    `letter` (a timer not named T..., a counter not named C...)."""
    found = []
    # kind by kind: the index's list of each, not a walk of every element for a few kinds
    # (the diagnostics are sorted by position in the end, and each has its own)
    for rung, element in (pair for kind in kinds for pair in index.of_kind(kind)):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and not name.startswith(letter):
            found.append(report(
                code,
                f"{element.kind} {noun} '{name}' in {rung_no(rung)}: {noun} names start with {letter} "
                f"(e.g. '{letter}{name}')",
                arg_span(element, "name"),
                fixes=prefix_fixes(index, element, "name"),
            ))
    return found
