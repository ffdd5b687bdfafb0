"""`ladder sim FILE`: run a program in the simulator and print what changes.

One line per change of a watched signal, `TIME NAME VALUE` (TIME in ms), by
time then name; a signal that is not 0 after the first scan prints at time 0.
The UART (`--watch uart`) prints one line a message (lang/sim/uart.py),
`TIME uart "text"` at the time of the scan that sent its first byte, once
the message is complete: the lines after that time wait for it.
"""

from __future__ import annotations

import io
import sys

from ._common import EXIT_OK, EXIT_USAGE, write_output
from ._common import EXIT_PROBLEMS as EXIT_ERROR

DEFAULT_DURATION_US = 10_000_000


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "sim", help="simulate a program and print its signals' changes",
        description="Simulate a program scan by scan (scan k at k x cycle time). Prints `TIME NAME VALUE` "
                    "for every change of a watched signal; all X, Y and R names when --watch is not given.")
    parser.add_argument("file", metavar="FILE")
    length = parser.add_mutually_exclusive_group()
    length.add_argument("--for", dest="duration", metavar="DURATION",
                        help="simulated time to run: 500ms, 2.5s, or a bare number of ms (default 10s)")
    length.add_argument("--cycles", type=int, metavar="N", help="number of scans to run")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE[@TIME]",
                        help="set an input, variable or ADC reading, from the first scan at or after TIME "
                             "(default 0); repeatable")
    parser.add_argument("--watch", action="append", default=[], metavar="NAME,...",
                        help="signals to print, `uart` for what the UART sends (default: every X, Y and R "
                             "name, and the UART when the program sends)")
    parser.add_argument("--vcd", metavar="OUT.vcd", help="also write the watched signals as a VCD file")
    parser.add_argument("--plot", action="store_true", help="also print a text timing diagram")
    parser.add_argument("--encoding", help="encoding of LDmicro files (default cp1252)")
    parser.set_defaults(func=run)


def _settings(texts: list[str]) -> list[tuple[int, str, int]]:
    from lang.sim.scenario import parse_time
    from lang.values import literal_value

    settings = []
    for text in texts:
        assignment, _, when = text.partition("@")
        name, eq, value = assignment.partition("=")
        if not eq or not name.strip():
            raise ValueError(f"--set {text!r}: expected NAME=VALUE[@TIME]")
        settings.append((parse_time(when) if when else 0, name.strip(), literal_value(value.strip())))
    return sorted(settings, key=lambda s: s[0])


def run(args) -> int:
    from lang.diagnostics import ERROR
    from lang.loader import load_path
    from lang.sim import SimulationError, Simulator
    from lang.sim.scenario import parse_time
    from lang.sim.trace import UART, Trace, diagram
    from lang.sim.vcd import write_vcd

    try:
        settings = _settings(args.set)
        duration = parse_time(args.duration) if args.duration else DEFAULT_DURATION_US
    except ValueError as bad:
        print(f"ladder sim: error: {bad}", file=sys.stderr)
        return EXIT_USAGE
    if args.cycles is not None and args.cycles < 0:
        print("ladder sim: error: --cycles must not be negative", file=sys.stderr)
        return EXIT_USAGE
    try:
        program, diagnostics = load_path(args.file, args.encoding)
    except OSError as problem:
        print(f"{args.file}: error: {problem.strerror or problem}", file=sys.stderr)
        return EXIT_USAGE
    errors = [d for d in diagnostics if d.severity == ERROR]
    if errors:
        for d in errors:
            print(d.format(args.file), file=sys.stderr)
        return EXIT_ERROR
    try:
        sim = Simulator(program)
    except SimulationError as problem:
        for d in problem.diagnostics:
            print(d.format(args.file), file=sys.stderr)
        return EXIT_ERROR

    named = [n.strip() for group in args.watch for n in group.split(",") if n.strip()]
    uart = UART in named if named else sim.compiled.sends_uart
    watched = [n for n in named if n != UART]
    # a `#0x23` name the program has no variable of is a register of its raw register access
    unknown = [n for n in watched + [s[1] for s in settings] if not sim.knows(n)]
    if unknown:
        print(f"ladder sim: error: {args.file} has no signal named {', '.join(sorted(set(unknown)))}",
              file=sys.stderr)
        return EXIT_USAGE
    if not named:
        watched = sorted(n for n in sim.bits() if n[:1] in "XYR")
    trace = Trace.watching(sim, watched, uart)
    scans = args.cycles if args.cycles is not None else -(-duration // sim.cycle_us)
    status = _simulate(sim, trace, settings, scans, args.file)
    if args.plot and scans:
        print(diagram(trace))
    if args.vcd:
        out = io.StringIO()
        write_vcd(trace, out)
        if not write_output(args.vcd, out.getvalue().encode("ascii")):
            return EXIT_USAGE
    return status


def _simulate(sim, trace, settings, scans: int, path: str) -> int:
    from lang.sim import SimulationError

    pending = 0
    lines = _Lines(trace)
    for scan in range(scans):
        now = scan * sim.cycle_us
        while pending < len(settings) and settings[pending][0] <= now:
            _, name, value = settings[pending]
            try:
                sim.set(name, value)
            except ValueError as bad:
                lines.flush()
                print(f"ladder sim: error: --set {name}: {bad}", file=sys.stderr)
                return EXIT_USAGE
            pending += 1
        try:
            sim.step()
        except SimulationError as problem:
            trace.record(sim)
            lines.flush()
            for d in problem.diagnostics:
                print(d.format(path), file=sys.stderr)
            return EXIT_ERROR
        lines.scan(now, trace.record(sim))
    lines.flush()
    return EXIT_OK


class _Lines:
    """The lines printed, in time order: a UART message prints at the time
    of its first byte once complete, so the lines after it wait for it."""

    def __init__(self, trace):
        from lang.sim.uart import Messages

        self.trace = trace
        self.messages = Messages(trace.byte_time_us, trace.cycle_us)
        self.seen = 0  # the trace's UART bytes grouped so far
        self.held: list[tuple[int, str, str]] = []  # (time, name, value)

    def scan(self, now: int, changed: list[tuple[str, int]]) -> None:
        self.held += [(now, name, str(value)) for name, value in changed]
        sent = self.trace.uart or []
        done = [message for byte in sent[self.seen:] for message in self.messages.add(byte)]
        self.seen = len(sent)
        self._note(done + self.messages.idle(now + self.trace.cycle_us))
        waiting = self.messages.open.scan_us if self.messages.open is not None else None
        self._print(lambda time: waiting is None or time < waiting)

    def flush(self) -> None:
        self._note(self.messages.close())
        self._print(lambda time: True)

    def _note(self, messages) -> None:
        from lang.sim.trace import UART
        from lang.sim.uart import show_bytes

        self.held += [(m.scan_us, UART, show_bytes(bytes(m.data))) for m in messages]

    def _print(self, due) -> None:
        from lang.sim.trace import format_time

        ready = sorted(line for line in self.held if due(line[0]))
        if not ready:
            return
        self.held = [line for line in self.held if not due(line[0])]
        sys.stdout.write("".join(f"{format_time(t, self.trace.cycle_us)} {name} {value}\n"
                                 for t, name, value in ready))
