"""`ladder test --on avr|pic16|pic18|pic10|c`: a scenario run on the compiled program.

The scenario's stimulus is known before it runs (inputs, A/D readings and
UART bytes at given times), so the compiled program is run once under it,
its values recorded after every scan (compiler.run.record), and the
scenario's checks are then evaluated on that recording by the same runner
as on the simulator (`FirmwareSim`). A check that fails on the firmware but
holds on the simulator says so: that is where the two part.

What the firmware cannot be given is a located failure, not a silent gap: a
`set` of anything but an input or an A/D reading (the MCU's memory is not
written from outside), an input with no pin on the part. The firmware then
runs up to the first such action, every expectation decided before it is
reported as usual, and each one after it as not checked: the firmware's run
is no longer the scenario's.
"""

from __future__ import annotations

import copy
import tempfile
from pathlib import Path

from lang.model import Program
from lang.sim.scenario import Action, Failure, RunStopped, Scenario, run_scenario
from lang.sim.trace import format_time

from . import c as c_run
from . import gpsim
from . import simavr as sa
from .record import Event, FirmwareError, FirmwareSim, Recording, erase_eeprom, pic_part, record_avr, record_c, record_pic16

TITLES = {"avr": "the AVR image in simavr", "pic16": "the PIC16 image in gpsim", "pic18": "the PIC18 image in gpsim",
          "pic10": "the PIC10 image in gpsim",
          "c": "the C built on this machine"}


def missing_tool(on: str) -> str | None:
    """Why `--on` cannot run here (naming the Debian package), or None."""
    if on == "avr":
        return sa.missing()
    if on in ("pic16", "pic18", "pic10"):
        return None if gpsim.available() else "gpsim is not installed (Debian package: gpsim)"
    return None if c_run.available() else f"no C compiler (Debian package: {c_run.DEBIAN_PACKAGES})"


def stimulus(scenario: Scenario, cycle_us: int, actions: list[Action] | None = None) -> tuple[list[Event], int]:
    """The scenario's actions (or `actions`) as events before the scans they
    come before, and how many scans it runs (as lang.sim.scenario.run_scenario
    does)."""
    events = []
    for action in scenario.actions if actions is None else actions:
        scan = -(-action.time_us // cycle_us)
        if isinstance(action.value, bytes):
            events += [Event(scan, "uart", byte) for byte in action.value]
        else:
            events.append(Event(scan, action.name, action.value))
    return events, -(-scenario.run_until_us // cycle_us) + 1


def _unsupported(on: str, scenario: Scenario, program: Program, cycle_us: int) -> list[tuple[Action, Failure]]:
    found = []
    for action in scenario.actions:
        when = format_time(action.time_us, cycle_us)
        if action.kind == "set" and on != "c" and action.name[:1] not in ("X", "A"):
            found.append((action, Failure(action.line, when, action.name, "",
                                          f"cannot set {action.name} on {TITLES[on]}: only inputs and A/D readings "
                                          "come from outside the MCU")))
        elif action.kind == "set" and on != "c" and action.name not in program.pins:
            found.append((action, Failure(action.line, when, action.name, "",
                                          f"{action.name} has no pin on the part, so {TITLES[on]} cannot be "
                                          "given it")))
    return found


def _cut(on: str, scenario: Scenario, unsupported: list[tuple[Action, Failure]],
         cycle_us: int) -> tuple[list[Action], int | None, RunStopped | None]:
    """The actions the firmware is given, and when an action it cannot be
    given comes first, the scan it stops before and why."""
    if not unsupported:
        return scenario.actions, None, None
    first = min((action for action, _ in unsupported), key=lambda a: (a.time_us, a.line))
    stop_scan = -(-first.time_us // cycle_us)
    given = [a for a in scenario.actions if -(-a.time_us // cycle_us) < stop_scan]
    why = (f"the run on {TITLES[on]} stops before the scan at {format_time(stop_scan * cycle_us, cycle_us)} ms, "
           f"where line {first.line} cannot be given to it")
    return given, stop_scan, RunStopped(why)


def record(on: str, program: Program, events: list[Event], scans: int, wanted: set[str]) -> Recording:
    if on == "c":
        return record_c(program, events, scans)
    import compiler

    build = compiler.build(program)
    if build.device.family != on:
        raise FirmwareError(f"the program's part, the {build.device.title}, is not {on.upper()}: "
                            f"ladder test --on {on} runs programs for {on.upper()} parts")
    names = sorted(n for n in wanted if n in build.image.symbols and n[0] != "#")
    with tempfile.TemporaryDirectory(prefix="textladder-test-") as folder:
        hex_path = Path(folder) / "program.hex"
        build.write(hex_path)
        if on == "avr":
            return record_avr(build, hex_path, events, scans, names)[0]
        part = pic_part(build.device)
        erase_eeprom(hex_path, part.eeprom, part.eeprom_hex)
        # the simulator starts an input at 0; a PIC pin with a pull-up would read 1
        given = {e.name for e in events if e.scan == 0}
        low = [Event(0, n, 0) for n in sorted(program.pins) if n[0] == "X" and n not in given]
        return record_pic16(build, hex_path, low + events, scans, names)


def run_on(on: str, scenario: Scenario, program: Program, program_path: str,
           model_failures: list[Failure]) -> tuple[str | None, list[str]]:
    """(an error that stopped the run, the failures as text) of the scenario
    on the compiled program; `model_failures` are the simulator's, to tell
    where the two part."""
    from compiler.errors import CompileError

    cycle = program.settings.cycle_us
    if on != "c" and not program.settings.mcu:
        return f"{scenario.path}:{scenario.line}: error: {program_path} selects no part: {TITLES[on]} needs one", []
    unsupported = _unsupported(on, scenario, program, cycle)
    given, stop_scan, stop = _cut(on, scenario, unsupported, cycle)
    events, scans = stimulus(scenario, cycle, given)
    # the simulator starts every input at 0: so do the pins, which a part's pull-ups would
    # otherwise hold at 1 (a normally closed stop button the scenario never presses)
    set_first = {event.name for event in events if event.scan == 0}
    events = [Event(0, name, 0) for name in sorted(program.pins) if name[:1] == "X" and name not in set_first] + events
    scans = scans if stop_scan is None else min(scans, stop_scan)
    # every signal an expectation reads, those of a compound condition included
    wanted = {a.name for a in scenario.actions} | {c.name for c in scenario.checks} \
        | {name for c in scenario.checks for name in c.signals()}
    try:
        recording = record(on, program, events, scans, wanted) if scans else Recording(sorted(wanted), [])
        failures = run_scenario(copy.deepcopy(scenario), FirmwareSim(program, recording, stop))
    except CompileError as problem:
        return "\n".join(d.format(program_path) for d in problem.diagnostics), []
    except (FirmwareError, c_run.CRunError, sa.HarnessError, RuntimeError) as problem:
        return f"{scenario.path}:{scenario.line}: error: {TITLES[on]}: {problem}", []
    on_model = {failure.line for failure in model_failures}
    texts = []
    for failure in failures:
        text = failure.format(scenario.path)
        if failure.checked and failure.line not in on_model:
            first, _, chart = text.partition("\n")
            text = first + f" (on {TITLES[on]}; the simulator passes this check)" + ("\n" + chart if chart else "")
        texts.append((failure.line, text))
    texts += [(failure.line, failure.format(scenario.path)) for _, failure in unsupported]
    return None, [text for _, text in sorted(texts, key=lambda t: t[0])]
