"""Recording signals scan by scan, and showing them: change lines and a
text timing diagram readable in a terminal. The UART's output is recorded
byte by byte, apart from the signals, when it is watched."""

from __future__ import annotations

from dataclasses import dataclass, field

from .runtime import Simulator
from .uart import SentByte, messages, show_bytes

UART = "uart"  # the name that watches the UART's output (as in a scenario's `expect uart`)


def format_time(time_us: int, cycle_us: int) -> str:
    """Milliseconds, with as many decimals as the cycle time needs."""
    decimals = 0
    step = cycle_us
    while step % 1000 and decimals < 3:
        step *= 10
        decimals += 1
    return f"{time_us / 1000:.{decimals}f}"


@dataclass
class Trace:
    """Each watched signal's changes as (time_us, value); a signal starts at
    0, so a first value that differs from 0 is a change at its scan's time."""

    cycle_us: int
    names: list[str]
    widths: dict[str, int]  # 1 for bits, 8 x bytes for integers
    changes: dict[str, list[tuple[int, int]]] = field(default_factory=dict)
    end_us: int = 0  # the time after the last recorded scan
    last: dict[str, int] = field(default_factory=dict)
    uart: list[SentByte] | None = None  # every byte sent, when the UART is watched
    byte_time_us: float = 0.0  # a byte's frame at the program's baud rate

    @classmethod
    def watching(cls, sim: Simulator, names: list[str], uart: bool = False) -> Trace:
        widths = {n: sim.width(n) for n in names}
        return cls(sim.cycle_us, list(names), widths, {n: [] for n in names}, uart=[] if uart else None,
                   byte_time_us=sim.peripherals.uart.byte_time_us)

    def record(self, sim: Simulator) -> list[tuple[str, int]]:
        """After a scan: note and return the watched signals that changed
        (and note the bytes it sent, when the UART is watched)."""
        time_us = (sim.scan_count - 1) * sim.cycle_us
        if self.uart is not None:
            self.uart += sim.peripherals.uart.sent[len(self.uart):]
        changed = []
        for name in self.names:
            value = sim.value(name)
            if self.last.get(name, 0) != value:
                self.changes[name].append((time_us, value))
                self.last[name] = value
                changed.append((name, value))
        self.end_us = sim.scan_count * sim.cycle_us
        return changed

    def value_at(self, name: str, time_us: int) -> int:
        value = 0
        for when, new in self.changes[name]:
            if when > time_us:
                break
            value = new
        return value

    def lines(self) -> list[str]:
        """`TIME NAME VALUE` for every change, by time then name."""
        events = sorted((t, n, v) for n in self.names for t, v in self.changes[n])
        return [f"{format_time(t, self.cycle_us)} {n} {v}" for t, n, v in events]


def diagram(trace: Trace, names: list[str] | None = None, start_us: int = 0,
            end_us: int | None = None, width: int = 60) -> str:
    """A timing diagram: bits as `_` (0) and `#` (1), `|` where a bit changes
    inside one column; integers as their values where they change; the UART,
    when the trace has it, as the messages it sent, from the column of each
    one's first byte (cut short where the next one starts)."""
    names = names if names is not None else trace.names
    end_us = trace.end_us if end_us is None else end_us
    cycle = trace.cycle_us
    scans = max(1, (end_us - start_us + cycle - 1) // cycle)
    per_column = -(-scans // width)
    columns = -(-scans // per_column)
    label = max([len(n) for n in names] + [len(UART) if trace.uart is not None else 0, 9])
    spans = [(start_us + c * per_column * cycle, start_us + (c + 1) * per_column * cycle) for c in range(columns)]
    rows = [_axis(trace, spans, label)]
    for name in names:
        if trace.widths.get(name, 1) == 1:
            rows.append(name.ljust(label) + " " + "".join(_bit_cell(trace, name, a, b) for a, b in spans))
        else:
            rows.append(name.ljust(label) + " " + _int_row(trace, name, spans))
    if trace.uart is not None:
        rows.append(UART.ljust(label) + " " + _uart_row(trace, spans))
    return "\n".join(row.rstrip() for row in rows)


def _values_in(trace: Trace, name: str, start: int, end: int) -> set[int]:
    values = {trace.value_at(name, start)}
    values.update(v for t, v in trace.changes[name] if start < t < end)
    return values


def _bit_cell(trace: Trace, name: str, start: int, end: int) -> str:
    values = _values_in(trace, name, start, end)
    if len(values) > 1:
        return "|"
    return "#" if values.pop() else "_"


def _int_row(trace: Trace, name: str, spans) -> str:
    texts = []
    previous = None
    for c, (_start, end) in enumerate(spans):
        value = trace.value_at(name, end - 1)
        if value != previous or c == 0:
            texts.append((c, f"|{value}" if c else str(value)))
            previous = value
    return _placed(texts, len(spans))


def _uart_row(trace: Trace, spans) -> str:
    by_column: dict[int, bytearray] = {}
    for message in messages(trace.uart or [], trace.byte_time_us, trace.cycle_us):
        column = next((c for c, (start, end) in enumerate(spans) if start <= message.scan_us < end), None)
        if column is not None:
            by_column.setdefault(column, bytearray()).extend(message.data)
    return _placed([(c, show_bytes(bytes(data))) for c, data in sorted(by_column.items())], len(spans))


def _placed(texts: list[tuple[int, str]], columns: int) -> str:
    """Each text from its column on, the next one writing over its end."""
    cells = [" "] * columns
    for column, text in texts:
        for i, ch in enumerate(text[:columns - column]):
            cells[column + i] = ch
    return "".join(cells)


def _axis(trace: Trace, spans, label: int) -> str:
    """Times at the start, middle and end columns, each left out when it would
    run into the one before (a short plot has room for fewer)."""
    cells = [" "] * len(spans)
    free = 0  # the first cell a label may take
    for c in sorted({0, len(spans) // 2, len(spans) - 1}):
        text = format_time(spans[c][0], trace.cycle_us)
        position = max(0, min(c, len(spans) - len(text)))
        if position < free:
            continue
        cells[position:position + len(text)] = text
        free = position + len(text) + 1
    return "time (ms)".ljust(label) + " " + "".join(cells)
