"""A counterexample (or a reachable property's witness) as the files a user
runs again: a scenario file that `ladder test` replays on the simulator,
failing at the scan where the property fails, and a Value Change Dump of
the run, recorded from the simulator itself."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TextIO

from ..model import Program
from ..properties import Property
from ..sim import Simulator
from ..sim.scenario import Not, parse_scenarios, run_scenario
from ..sim.trace import Trace, format_time
from ..sim.uart import show_bytes
from ..sim.vcd import write_vcd
from .prover import Witness


def _at(scan: int, cycle_us: int) -> str:
    return f"{format_time(scan * cycle_us, cycle_us)} ms"


def expectation(prop: Property, witness: Witness, cycle_us: int) -> str:
    """The scenario line that fails where the property fails (for a
    reachable property, that holds where it is reached)."""
    end = _at(witness.scan, cycle_us)
    if prop.kind == "always":
        return f"from 0 to {end} expect {prop.condition}"
    if prop.kind == "never":
        return f"from 0 to {end} expect {Not(prop.condition)}"
    if prop.kind == "reachable":
        return f"at {end} expect {prop.condition}"
    assert witness.trigger is not None
    return f"sometime from {_at(witness.trigger, cycle_us)} to {end} expect {prop.condition}"


def scenario_text(program_ref: str, prop: Property, witness: Witness, cycle_us: int) -> tuple[str, int]:
    """The scenario file, and the line of the expectation that decides it."""
    reached = prop.kind == "reachable"
    lines = [f"# ladder verify: {'a witness' if reached else 'a counterexample'} for `{prop.text}`",
             f"# the property {'holds' if reached else 'fails'} at {_at(witness.scan, cycle_us)} "
             f"(scan {witness.scan + 1} from power-up)"]
    if witness.eeprom:
        stored = ", ".join(f"{value} at address {address}" for address, value in sorted(witness.eeprom.items()))
        lines.append(f"# the EEPROM holds at power-up: {stored} (the simulator starts it erased)")
    lines += [f"program {program_ref}", f"scenario {prop.text}"]
    previous: dict[str, int] = {}
    for scan, inputs in enumerate(witness.inputs):
        changed = {name: value for name, value in inputs.items() if scan == 0 or previous.get(name) != value}
        if changed:
            lines.append(f"at {_at(scan, cycle_us)} set " + ", ".join(f"{n} = {v}" for n, v in changed.items()))
        if scan < len(witness.uart) and witness.uart[scan]:
            lines.append(f"at {_at(scan, cycle_us)} uart {show_bytes(witness.uart[scan])}")
        previous = inputs
    lines.append(expectation(prop, witness, cycle_us))
    return "\n".join(lines) + "\n", len(lines)


def replays(program: Program, text: str, path: str, line: int, prop: Property, witness: Witness) -> bool:
    """Whether the simulator, running the scenario, decides the expectation on
    `line` as the prover did at the witness's scan: fails it there, or (a
    reachable property's witness) passes it."""
    scenario = parse_scenarios(text, path)[0]
    failures = run_scenario(scenario, Simulator(program))
    time = format_time(witness.scan * program.settings.cycle_us, program.settings.cycle_us)
    decided = [f for f in failures if f.line == line and f.checked and f.time_ms == time]
    others = [f for f in failures if f.line != line]
    if prop.kind == "reachable":
        return not failures
    return bool(decided) and not others


def feed(sim: Simulator, witness: Witness) -> Iterator[int]:
    """Run the witness's input sequence from power-up on `sim`, yielding
    after each scan its number (0 first); a fault raises SimulationError."""
    for scan, inputs in enumerate(witness.inputs):
        for name, value in inputs.items():
            sim.set(name, value)
        if scan < len(witness.uart):
            sim.uart_receive(witness.uart[scan])
        sim.step()
        yield scan


def write_run(program: Program, prop: Property, witness: Witness, out: TextIO) -> None:
    """The VCD of the witness's run in the simulator: the inputs and every
    name the property reads."""
    sim = Simulator(program)
    known = sim.variables()
    names = sorted({*witness.inputs[0], *prop.names()} & known.keys()) if witness.inputs else prop.names()
    trace = Trace.watching(sim, names)
    for _ in feed(sim, witness):
        trace.record(sim)
    write_vcd(trace, out)
