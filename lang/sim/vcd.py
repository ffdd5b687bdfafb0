"""A Trace as a Value Change Dump file (IEEE 1364), which GTKWave opens:
bits as 1-bit wires, integers as two's-complement vectors of their size.

The UART, when watched, is an 8-bit wire named `uart` that holds each byte
for its frame (from its start bit to the end of its stop bit, at the baud
rate) and is high-impedance (`z`) while the transmitter is idle: every viewer
reads a wire, and each byte is a box of its own even when two equal bytes
follow each other after a pause (GTKWave shows the boxes as characters with
Data Format > ASCII).
"""

from __future__ import annotations

from typing import TextIO

from .trace import UART, Trace

IDLE = "bzzzzzzzz"


def _identifier(index: int) -> str:
    # VCD identifiers are strings of printable ASCII characters ! to ~
    chars = []
    index += 1
    while index:
        index, digit = divmod(index - 1, 94)
        chars.append(chr(33 + digit))
    return "".join(chars)


def _value(value: int, width: int, ident: str) -> str:
    if width == 1:
        return f"{value & 1}{ident}"
    return f"b{value & ((1 << width) - 1):b} {ident}"


def _uart_events(trace: Trace, ident: str) -> list[tuple[int, int, str]]:
    """(time, order, change) of the UART wire: a byte at its frame's start,
    idle at its end unless the next frame starts then."""
    events = []
    sent = trace.uart or []
    for i, byte in enumerate(sent):
        start = round(byte.start_us)
        end = round(byte.start_us + trace.byte_time_us)
        events.append((start, 1, f"b{byte.byte:08b} {ident}"))
        if i + 1 == len(sent) or round(sent[i + 1].start_us) > end:
            events.append((end, 0, f"{IDLE} {ident}"))
    return events


def write_vcd(trace: Trace, out: TextIO, scope: str = "ladder") -> None:
    ids = {name: _identifier(i) for i, name in enumerate(trace.names)}
    uart_id = _identifier(len(trace.names))
    out.write("$version textladder simulator $end\n$timescale 1 us $end\n")
    out.write(f"$scope module {scope} $end\n")
    for name in trace.names:
        width = trace.widths[name]
        kind = "wire" if width == 1 else "integer"
        out.write(f"$var {kind} {width} {ids[name]} {name} $end\n")
    if trace.uart is not None:
        out.write(f"$var wire 8 {uart_id} {UART} $end\n")
    out.write("$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n")
    for name in trace.names:
        out.write(_value(trace.value_at(name, 0), trace.widths[name], ids[name]) + "\n")
    if trace.uart is not None:
        out.write(f"{IDLE} {uart_id}\n")
    out.write("$end\n")
    events = [(t, 2, _value(v, trace.widths[name], ids[name]))
              for name in trace.names for t, v in trace.changes[name] if t > 0]
    if trace.uart is not None:
        events += _uart_events(trace, uart_id)
    current = 0
    for time_us, _, line in sorted(events, key=lambda e: (e[0], e[1])):
        if time_us != current:
            out.write(f"#{time_us}\n")
            current = time_us
        out.write(line + "\n")
    if trace.end_us > current:
        out.write(f"#{trace.end_us}\n")
