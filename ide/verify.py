"""`ladder verify` in the editor (docs/verify.md): the code lenses of the
PROPERTIES section, the prover run on one version of a document, each
property's result as a finding on its line, and the input sequence that
breaks a property (or reaches a `reachable` one) as a replay for the
simulation (ide.session.Replay), to step through scan by scan.

A verification belongs to the version it was run on: its findings are
placed with that version's lines and name the values of that version's
program. The server decides what an edit does to it (docs/lsp-protocol.md:
any edit drops it)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from enum import Enum
from typing import TYPE_CHECKING

from lang.diagnostics import ERROR, Related
from lang.loader import TEXT_KIND
from lang.model import Program, Span
from lang.properties import Property, property_lines, read_properties

from .document import Document
from .session import Replay

if TYPE_CHECKING:
    from lang.verify.prover import Result

SCENARIO_PATH = "counterexample.scn"  # the name a replay's scenario is read under (for its messages)
INPUT_LINES = 8  # the inputs of a counterexample a finding's message lists


class VerifyError(ValueError):
    """Nothing could be verified; the message is for the user."""


class Severity(Enum):
    INFORMATION = "information"
    WARNING = "warning"
    ERROR = "error"


class LensKind(Enum):
    VERIFY = "verify"  # every property, or the one on `property_line`
    STEP = "step"  # through the counterexample (or witness) of the property on `property_line`


@dataclass(frozen=True)
class Lens:
    line: int
    title: str
    kind: LensKind
    property_line: int | None = None


@dataclass(frozen=True)
class Outcome:
    """One property's result, with what the simulator says of its input
    sequence when there is one: the scenario file `ladder verify` writes, the
    values of the property's names after the scan that decides it, and
    whether the simulator decides it there as the prover did."""

    result: Result
    scenario: str = ""
    values: tuple[tuple[str, int], ...] = ()
    replays: bool = True

    @property
    def prop(self) -> Property:
        return self.result.prop


@dataclass(frozen=True)
class Verification:
    outcomes: tuple[Outcome, ...]
    cycle_us: int
    only: int | None  # the line of the one property verified, None for all

    def at(self, line: int) -> Outcome | None:
        return next((o for o in self.outcomes if o.prop.span.line == line), None)


@dataclass(frozen=True)
class Finding:
    """A property's result, shown on its line."""

    span: Span
    severity: Severity
    message: str
    related: tuple[Related, ...]
    steppable: bool  # an input sequence to step through


def sequence_kind(prop: Property) -> str:
    """What an input sequence found for the property is called."""
    return "witness" if prop.kind == "reachable" else "counterexample"


def header_line(document: Document) -> int | None:
    """The line of the PROPERTIES title, None when the document has no property."""
    if document.kind != TEXT_KIND or not property_lines(document.program):
        return None
    return document.program.properties[0].line - 1  # the section's lines start under its title


def lenses(document: Document, verification: Verification | None, running: bool) -> list[Lens]:
    """"Verify" on the PROPERTIES title (with the last results' count),
    "Verify this property" on each property, and "Step through the
    counterexample" on each that has one."""
    header = header_line(document)
    if header is None:
        return []
    title = "Verifying…" if running else "Verify"
    if verification is not None and verification.only is None and not running:
        title = f"Verify again ({summary(verification)})"
    found = [Lens(header, title, LensKind.VERIFY)]
    properties, _ = read_properties(document.program)
    for prop in properties:
        line = prop.span.line
        found.append(Lens(line, "Verify this property", LensKind.VERIFY, line))
        outcome = verification.at(line) if verification is not None else None
        if outcome is not None and outcome.scenario:
            found.append(Lens(line, f"Step through the {sequence_kind(prop)}", LensKind.STEP, line))
    return found


def summary(verification: Verification) -> str:
    """`3 proved, 1 fails, 1 not proved`."""
    from lang.verify.prover import FAILS, PROVED

    counts = {PROVED: 0, FAILS: 0}
    for outcome in verification.outcomes:
        if outcome.result.verdict in counts:
            counts[outcome.result.verdict] += 1
    unknown = len(verification.outcomes) - counts[PROVED] - counts[FAILS]
    parts = [f"{counts[PROVED]} proved"] + [f"{counts[FAILS]} fails"] * bool(counts[FAILS]) + \
        [f"{unknown} not proved"] * bool(unknown)
    return ", ".join(parts)


def ready(document: Document, line: int | None = None) -> list[Property]:
    """The properties to prove (only the one on `line` if given); VerifyError
    when there is none or the program has errors."""
    if header_line(document) is None:
        raise VerifyError("no property to verify: write them in a PROPERTIES section (docs/verify.md)")
    if document.has_errors or any(d.severity == ERROR for d in document.checks):
        raise VerifyError("the program has errors; fix them before verifying it")
    properties, _ = read_properties(document.program)
    if line is not None:
        properties = [p for p in properties if p.span.line == line]
        if not properties:
            raise VerifyError(f"line {line + 1} holds no property")
    return properties


def run(program: Program, properties: list[Property], bound: int, timeout_s: float,
        line: int | None = None) -> Verification:
    """Prove `ready`'s properties of the document's program; `line` as given
    to `ready`. VerifyError when the program cannot be modelled or the solver
    is not installed. Slow (up to `timeout_s` seconds of solving, and the
    simulator's replay of each input sequence found): it reads only the
    program, so that the server can run it out of the way of its requests."""
    from lang.sim import SimulationError
    from lang.verify import SolverMissing, verify

    try:
        results = verify(program, properties, bound, timeout_s)
    except SolverMissing as missing:
        raise VerifyError(str(missing)) from None
    except SimulationError as problem:
        raise VerifyError("cannot verify the program: " + "; ".join(d.message for d in problem.diagnostics)) from None
    cycle_us = program.settings.cycle_us
    return Verification(tuple(_outcome(program, result, cycle_us) for result in results), cycle_us, line)


def _outcome(program: Program, result: Result, cycle_us: int) -> Outcome:
    from lang.sim import SimulationError, Simulator
    from lang.verify.counterexample import feed, replays, scenario_text

    witness = result.witness
    if witness is None:
        return Outcome(result)
    prop = result.prop
    text, decided = scenario_text("program.ladder", prop, witness, cycle_us)
    sim = Simulator(program)
    try:
        for _ in feed(sim, witness):
            pass
    except SimulationError:
        return Outcome(result, text, (), False)
    values = tuple((name, sim.value(name)) for name in prop.names())
    return Outcome(result, text, values, replays(program, text, SCENARIO_PATH, decided, prop, witness))


def merged(before: Verification | None, after: Verification) -> Verification:
    """A verification of one property added to one of every property (of the same version)."""
    if before is None or after.only is None:
        return after
    kept = tuple(o for o in before.outcomes if o.prop.span.line != after.only)
    outcomes = tuple(sorted(kept + after.outcomes, key=lambda o: o.prop.span.line))
    return Verification(outcomes, after.cycle_us, before.only if before.only is None else after.only)


def findings(document: Document, verification: Verification) -> list[Finding]:
    """Each property's result on its line: proved (or reached) is
    information, holding up to the bound a warning, failing an error; an
    input sequence's values after the deciding scan are related places (the
    elements that write the names)."""
    from lang.verify import verdict
    from lang.verify.prover import FAILS, PROVED, UNKNOWN

    found = []
    for outcome in verification.outcomes:
        result, prop = outcome.result, outcome.prop
        message = f"{verdict(result, verification.cycle_us)}: {prop.text}"
        if result.verdict == UNKNOWN:
            message += "; a longer input sequence might break it (verify with a larger bound)"
        severity = {PROVED: Severity.INFORMATION, FAILS: Severity.ERROR}.get(result.verdict, Severity.WARNING)
        related: tuple[Related, ...] = ()
        if outcome.scenario:
            message += "\n" + _inputs(outcome.scenario)
            if not outcome.replays:
                message += "\nnote: the simulator does not decide this input sequence as the prover did" + \
                           (": it starts with the EEPROM erased" if result.witness and result.witness.eeprom else "")
            related = _related(document, outcome, verification.cycle_us)
        found.append(Finding(prop.span, severity, message, related, bool(outcome.scenario)))
    return found


def _inputs(scenario: str) -> str:
    """The `at T set`/`uart` lines of a counterexample's scenario, the first ones."""
    lines = [line for line in scenario.splitlines() if line.startswith("at ") and " expect " not in line]
    shown = lines[:INPUT_LINES] + ([f"… and {len(lines) - INPUT_LINES} more"] if len(lines) > INPUT_LINES else [])
    return "the inputs from power-up: " + "; ".join(shown) if shown else "no input needed"


def _related(document: Document, outcome: Outcome, cycle_us: int) -> tuple[Related, ...]:
    """Each name the property reads, with its value after the deciding scan,
    at the element that writes it (else the first that uses it)."""
    from lang.sim.trace import format_time

    witness = outcome.result.witness
    assert witness is not None
    after = f"after scan {witness.scan + 1} ({format_time(witness.scan * cycle_us, cycle_us)} ms)"
    found = []
    for name, value in outcome.values:
        uses = document.index.names.get(name, [])
        use = next((u for u in uses if u.writes and u.span is not None), None) or \
            next((u for u in uses if u.span is not None), None)
        found.append(Related(use.span if use is not None and use.span is not None else outcome.prop.span,
                             f"{name} = {value} {after}"))
    if witness.trigger is not None:
        found.append(Related(outcome.prop.span, f"the trigger held after scan {witness.trigger + 1} "
                                                f"({format_time(witness.trigger * cycle_us, cycle_us)} ms)"))
    return tuple(found)


def replay(verification: Verification, line: int) -> Replay:
    """The input sequence of the property on `line`, for the simulation."""
    from lang.sim.scenario import parse_scenarios

    outcome = verification.at(line)
    if outcome is None or not outcome.scenario:
        raise VerifyError(f"line {line + 1} has no counterexample: verify its property first")
    scenario = parse_scenarios(outcome.scenario, SCENARIO_PATH)[0]
    return replace(Replay.of(scenario), name=f"{sequence_kind(outcome.prop)} for `{outcome.prop.text}`")
