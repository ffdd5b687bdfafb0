"""`ladder test FILE...`: run scenario files (docs/testing.md) against the
simulator, or with `--on avr|pic16|pic18|pic10|c` against the compiled program (the HEX
in simavr or gpsim, the C built on the host: compiler.run.record); print each
failure with a timing diagram; exit 1 on any failure, 2 when a file cannot be
read or a tool the run needs is missing."""

from __future__ import annotations

import copy
import io
import sys
import time
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

from ._common import EXIT_OK, EXIT_USAGE, write_output
from ._common import EXIT_PROBLEMS as EXIT_FAILED


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "test", help="run test scenarios against the simulator",
        description="Run scenario files: each names its program, drives inputs over simulated time and "
                    "checks outputs. Exit 0 when every expectation holds, 1 otherwise.")
    parser.add_argument("files", nargs="+", metavar="FILE")
    parser.add_argument("--junit", metavar="OUT.xml", help="also write the results as JUnit XML")
    parser.add_argument("--on", choices=("avr", "pic16", "pic18", "pic10", "c"),
                        help="run the scenarios on the compiled program instead of the simulator: the AVR HEX "
                             "in simavr, the PIC16, PIC18 or PIC10 HEX in gpsim, or the C built with the host's "
                             "compiler")
    parser.set_defaults(func=run)


def run(args) -> int:
    if args.on:
        from compiler.run.firmware import missing_tool

        problem = missing_tool(args.on)
        if problem:
            print(f"ladder test: error: --on {args.on}: {problem}", file=sys.stderr)
            return EXIT_USAGE
    suites = [_run_file(path, args.on) for path in args.files]
    failed = sum(1 for suite in suites for case in suite["cases"] if case["failures"] or case["error"])
    total = sum(len(suite["cases"]) for suite in suites)
    print(f"{total - failed} passed, {failed} failed")
    status = EXIT_USAGE if any(suite.get("unreadable") for suite in suites) else \
        EXIT_FAILED if failed else EXIT_OK
    if args.junit and not write_output(args.junit, _junit(suites)):
        return EXIT_USAGE
    return status


def _run_file(path: str, on: str | None) -> dict:
    from lang.sim.scenario import ScenarioError, parse_scenarios

    suite: dict[str, Any] = {"name": path, "cases": []}
    try:
        scenarios = parse_scenarios(Path(path).read_text(encoding="utf-8"), path)
    except (OSError, UnicodeDecodeError) as problem:
        suite["unreadable"] = True
        return _broken(suite, path, f"{path}: error: {getattr(problem, 'strerror', None) or problem}")
    except ScenarioError as problem:
        return _broken(suite, path, str(problem))
    if not scenarios:
        return _broken(suite, path, f"{path}: error: no scenario in this file (each starts with a "
                                    "`scenario NAME` line)")
    for scenario in scenarios:
        started = time.perf_counter()
        case: dict[str, Any] = {"name": scenario.name, "failures": [], "error": None}
        case["error"], case["failures"] = _run_scenario(scenario, on)
        case["seconds"] = time.perf_counter() - started
        _print_case(path, case)
        suite["cases"].append(case)
    return suite


def _run_scenario(scenario, on: str | None) -> tuple[str | None, list[str]]:
    from lang.diagnostics import ERROR
    from lang.loader import load_path
    from lang.sim import SimulationError, Simulator
    from lang.sim.scenario import run_scenario

    program_path = str(scenario.program)
    try:
        program, diagnostics = load_path(program_path)
    except OSError as problem:
        return f"{scenario.path}:{scenario.line}: error: {program_path}: {problem.strerror or problem}", []
    errors = [d.format(program_path) for d in diagnostics if d.severity == ERROR]
    if errors:
        return "\n".join(errors), []
    try:
        sim = Simulator(program)
    except SimulationError as problem:
        return "\n".join(d.format(program_path) for d in problem.diagnostics), []
    # the runner marks the scenario's checks as it goes: the firmware's run gets a fresh copy
    failures = run_scenario(copy.deepcopy(scenario) if on else scenario, sim)
    if on:
        from compiler.run.firmware import run_on

        return run_on(on, scenario, program, program_path, failures)
    return None, [failure.format(scenario.path) for failure in failures]


def _broken(suite: dict, path: str, message: str) -> dict:
    case = {"name": Path(path).stem, "failures": [], "error": message, "seconds": 0.0}
    _print_case(path, case)
    suite["cases"].append(case)
    return suite


def _print_case(path: str, case: dict) -> None:
    if case["error"] or case["failures"]:
        print(f"FAIL {path}: {case['name']}")
        for text in ([case["error"]] if case["error"] else []) + case["failures"]:
            print("  " + text.replace("\n", "\n  "))
    else:
        print(f"ok   {path}: {case['name']}")
    sys.stdout.flush()


def _junit(suites: list[dict]) -> bytes:
    """JUnit XML: one test case per scenario, with an <error> when the run
    could not be made and one <failure> holding every failed expectation,
    each with its line (CI readers count one failure a test case)."""
    root = ElementTree.Element("testsuites")
    for suite in suites:
        failures = sum(1 for c in suite["cases"] if c["failures"])
        errors = sum(1 for c in suite["cases"] if c["error"])
        node = ElementTree.SubElement(root, "testsuite", name=suite["name"], tests=str(len(suite["cases"])),
                                      failures=str(failures), errors=str(errors))
        for case in suite["cases"]:
            item = ElementTree.SubElement(node, "testcase", classname=suite["name"], name=case["name"],
                                          time=f"{case.get('seconds', 0.0):.3f}")
            if case["error"]:
                ElementTree.SubElement(item, "error", message=case["error"].splitlines()[0]).text = case["error"]
            if case["failures"]:
                count = len(case["failures"])
                message = case["failures"][0].splitlines()[0] + (f" (and {count - 1} more)" if count > 1 else "")
                ElementTree.SubElement(item, "failure", message=message).text = "\n\n".join(case["failures"])
    out = io.BytesIO()
    ElementTree.ElementTree(root).write(out, encoding="utf-8", xml_declaration=True)
    return out.getvalue()
