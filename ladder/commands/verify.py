"""`ladder verify FILE`: prove a program's properties (its PROPERTIES section,
or the `property` lines of a scenario file) for every input sequence
(lang/verify, docs/verify.md). Exit 0 when none fails, 1 when one fails or
the program has errors, 2 when the file cannot be read or verified or the
solver is not installed."""

from __future__ import annotations

import io
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ._common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, add_encoding, has_errors, load, report, write_output


def register(subparsers) -> None:
    from lang.verify import DEFAULT_BOUND, DEFAULT_TIMEOUT_S

    parser = subparsers.add_parser(
        "verify", help="prove a program's properties for every input sequence",
        description="Prove the properties of a program's PROPERTIES section (or of a scenario file's `property` "
                    "lines) for every input sequence, by bounded model checking and k-induction. A property that "
                    "fails gets a counterexample: a scenario file `ladder test` replays, and a VCD. Exit 0 when no "
                    "property fails, 1 when one does, 2 when the file cannot be read or verified.")
    parser.add_argument("file", metavar="FILE", help="a program with a PROPERTIES section, or a scenario file")
    parser.add_argument("--bound", type=int, default=DEFAULT_BOUND, metavar="N",
                        help=f"scans to search from power-up and longest induction (default {DEFAULT_BOUND})")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S, metavar="SECONDS",
                        help=f"time for all the properties together (default {DEFAULT_TIMEOUT_S:g} s)")
    parser.add_argument("--junit", metavar="OUT.xml", help="also write the results as JUnit XML")
    parser.add_argument("--out", metavar="DIR",
                        help="where to write the counterexamples (default: the folder of FILE)")
    add_encoding(parser)
    parser.set_defaults(func=run)


@dataclass
class Goal:
    """A program and the properties to prove on it, with the file each comes from."""

    program_path: str
    properties: list  # lang.properties.Property
    source: str  # the file the properties are written in


def run(args) -> int:
    from lang.verify import SolverMissing

    if args.bound < 1 or args.timeout <= 0:
        print("ladder verify: error: --bound must be at least 1 and --timeout positive", file=sys.stderr)
        return EXIT_USAGE
    goals, status = _goals(args)
    if goals is None:
        return status
    cases: list[dict[str, Any]] = []
    for goal in goals:
        try:
            result = _verify(goal, args, cases)
        except SolverMissing as missing:
            print(f"ladder verify: error: {missing}", file=sys.stderr)
            return EXIT_USAGE
        status = max(status, result)
    if args.junit:
        from .test import _junit

        if not write_output(args.junit, _junit([{"name": args.file, "cases": cases}])):
            return EXIT_USAGE
    return status


def _goals(args) -> tuple[list[Goal] | None, int]:
    """What to prove, or None and the exit status after the problems are printed."""
    from lang.properties import PropertyError, parse_property, read_properties
    from lang.sim.scenario import ScenarioError, parse_scenarios

    path = args.file
    if Path(path).suffix != ".scn":
        loaded = load(path, args.encoding)
        if loaded is None:
            return None, EXIT_USAGE
        if _refused(path, loaded):
            return None, EXIT_PROBLEMS
        properties = read_properties(loaded.program)[0]
        if not properties:
            print(f"{path}: error: no property to prove (write them in a PROPERTIES section, docs/verify.md)",
                  file=sys.stderr)
            return None, EXIT_USAGE
        return [Goal(path, properties, path)], EXIT_OK
    try:
        scenarios = parse_scenarios(Path(path).read_text(encoding="utf-8"), path)
    except (OSError, UnicodeDecodeError) as problem:
        print(f"{path}: error: {getattr(problem, 'strerror', None) or problem}", file=sys.stderr)
        return None, EXIT_USAGE
    except ScenarioError as problem:
        print(problem, file=sys.stderr)
        return None, EXIT_USAGE
    goals: dict[str, Goal] = {}
    bad = []
    for scenario in scenarios:
        for number, column, text in scenario.properties:
            try:
                prop = parse_property(text, number - 1, column)
            except PropertyError as problem:
                bad.append(problem)
                continue
            program = str(scenario.program)
            goals.setdefault(program, Goal(program, [], path)).properties.append(prop)
    for unread in bad:
        line, col = unread.span.line + 1, unread.span.col + 1
        print(f"{path}:{line}:{col}: error LD215 {unread}", file=sys.stderr)
    if bad:
        return None, EXIT_PROBLEMS
    if not goals:
        print(f"{path}: error: no `property` line to prove (docs/verify.md)", file=sys.stderr)
        return None, EXIT_USAGE
    return list(goals.values()), EXIT_OK


def _refused(path: str, loaded) -> bool:
    """Whether the program has errors, reading or checks' (printed): as `ladder check`
    and `ladder build`, no proof about a program that would not be built."""
    from lang.checks import check_program
    from lang.diagnostics import ERROR
    from lang.loader import checkable, checked

    diagnostics = list(loaded.diagnostics)
    if checkable(loaded.program, diagnostics):
        diagnostics += checked(loaded.program, check_program(loaded.program))
    if not has_errors(diagnostics):
        return False
    report(path, [d for d in diagnostics if d.severity == ERROR], sys.stderr)
    return True


def _verify(goal: Goal, args, cases: list[dict[str, Any]]) -> int:
    from lang.properties import name_span
    from lang.sim import SimulationError, Simulator
    from lang.verify import verdict, verify
    from lang.verify.prover import FAILS

    loaded = load(goal.program_path, args.encoding)
    if loaded is None:
        return EXIT_USAGE
    program = loaded.program
    # a program file's errors were reported with its properties (_goals); a scenario's program's here
    if goal.source != goal.program_path and _refused(goal.program_path, loaded):
        return EXIT_PROBLEMS
    try:
        known = Simulator(program).variables()
    except SimulationError as problem:
        report(goal.program_path, problem.diagnostics, sys.stderr)
        return EXIT_USAGE
    unknown = [(prop, name) for prop in goal.properties for name in prop.names() if name not in known]
    for prop, name in unknown:
        span = name_span(prop, name)
        print(f"{goal.source}:{span.line + 1}:{span.col + 1}: error LD216 the property reads "
              f"'{name}', which the program does not use", file=sys.stderr)
    if unknown:
        return EXIT_PROBLEMS
    try:
        results = verify(program, goal.properties, args.bound, args.timeout)
    except SimulationError as problem:
        report(goal.program_path, problem.diagnostics, sys.stderr)
        return EXIT_USAGE
    status = EXIT_OK
    out = Path(args.out) if args.out else Path(goal.source).parent
    for number, result in enumerate(results, 1):
        prop = result.prop
        where = f"{goal.source}:{prop.span.line + 1}"
        print(f"{where}: {verdict(result, program.settings.cycle_us)}: {prop.text}")
        case: dict[str, Any] = {"name": prop.text, "failures": [], "error": None, "seconds": result.seconds}
        if result.witness is not None:
            files = _write_witness(program, goal, result, out / f"{Path(goal.program_path).stem}-property{number}")
            if files is None:
                return EXIT_USAGE
            print("  " + files)
            if result.verdict == FAILS:
                case["failures"].append(f"{where}: {verdict(result, program.settings.cycle_us)}: {prop.text}; {files}")
        elif result.verdict == FAILS:
            case["failures"].append(f"{where}: {verdict(result, program.settings.cycle_us)}: {prop.text}")
        if result.verdict == FAILS:
            status = EXIT_PROBLEMS
        cases.append(case)
    return status


def _write_witness(program, goal: Goal, result, stem: Path) -> str | None:
    """Write the scenario and the VCD; what to tell the user about them (None
    when a file could not be written)."""
    from lang.verify.counterexample import replays, scenario_text, write_run

    scenario, vcd = stem.with_suffix(".scn"), stem.with_suffix(".vcd")
    reference = os.path.relpath(Path(goal.program_path).resolve(), stem.parent.resolve())
    text, line = scenario_text(Path(reference).as_posix(), result.prop, result.witness, program.settings.cycle_us)
    dump = io.StringIO()
    write_run(program, result.prop, result.witness, dump)
    if not (write_output(scenario, text.encode("utf-8")) and write_output(vcd, dump.getvalue().encode("ascii"))):
        return None
    kind = "witness" if result.prop.kind == "reachable" else "counterexample"
    told = f"{kind}: {scenario} (ladder test replays it), {vcd}"
    if not replays(program, text, str(scenario), line, result.prop, result.witness):
        told += ("\n  note: the simulator does not decide the scenario as the prover did"
                 + (": it starts with the EEPROM erased" if result.witness.eeprom else ""))
    return told
