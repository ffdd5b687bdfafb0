"""`ladder sim FILE`: run a program in the simulator and print what changes.

One line per change of a watched signal, `TIME NAME VALUE` (TIME in ms), by
time then name; a signal that is not 0 after the first scan prints at time 0.
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
                        help="signals to print (default: every X, Y and R name)")
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
    from lang.sim.trace import Trace, diagram
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

    watched = [n.strip() for group in args.watch for n in group.split(",") if n.strip()]
    known = sim.variables()
    unknown = [n for n in watched + [s[1] for s in settings] if n not in known]
    if unknown:
        print(f"ladder sim: error: {args.file} has no signal named {', '.join(sorted(set(unknown)))}",
              file=sys.stderr)
        return EXIT_USAGE
    if not watched:
        watched = sorted(n for n in sim.bits() if n[:1] in "XYR")
    trace = Trace.watching(sim, watched)
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
    out = sys.stdout
    for scan in range(scans):
        now = scan * sim.cycle_us
        while pending < len(settings) and settings[pending][0] <= now:
            _, name, value = settings[pending]
            try:
                sim.set(name, value)
            except ValueError as bad:
                print(f"ladder sim: error: --set {name}: {bad}", file=sys.stderr)
                return EXIT_USAGE
            pending += 1
        try:
            sim.step()
        except SimulationError as problem:
            trace.record(sim)
            for d in problem.diagnostics:
                print(d.format(path), file=sys.stderr)
            return EXIT_ERROR
        for line in _lines(trace, trace.record(sim), now):
            out.write(line + "\n")
    return EXIT_OK


def _lines(trace, changed, now: int) -> list[str]:
    from lang.sim.trace import format_time

    stamp = format_time(now, trace.cycle_us)
    return [f"{stamp} {name} {value}" for name, value in sorted(changed)]

