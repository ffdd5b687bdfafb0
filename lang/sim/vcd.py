"""A Trace as a Value Change Dump file (IEEE 1364), which GTKWave opens:
bits as 1-bit wires, integers as two's-complement vectors of their size."""

from __future__ import annotations

from typing import TextIO

from .trace import Trace


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


def write_vcd(trace: Trace, out: TextIO, scope: str = "ladder") -> None:
    ids = {name: _identifier(i) for i, name in enumerate(trace.names)}
    out.write("$version textladder simulator $end\n$timescale 1 us $end\n")
    out.write(f"$scope module {scope} $end\n")
    for name in trace.names:
        width = trace.widths[name]
        kind = "wire" if width == 1 else "integer"
        out.write(f"$var {kind} {width} {ids[name]} {name} $end\n")
    out.write("$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n")
    for name in trace.names:
        out.write(_value(trace.value_at(name, 0), trace.widths[name], ids[name]) + "\n")
    out.write("$end\n")
    events = sorted((t, name, v) for name in trace.names for t, v in trace.changes[name] if t > 0)
    current = 0
    for time_us, name, value in events:
        if time_us != current:
            out.write(f"#{time_us}\n")
            current = time_us
        out.write(_value(value, trace.widths[name], ids[name]) + "\n")
    if trace.end_us > current:
        out.write(f"#{trace.end_us}\n")
