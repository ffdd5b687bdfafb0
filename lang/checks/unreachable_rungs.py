"""LD217: rungs that never do anything: after a GOTO that jumps on every scan
(up to the next place a jump can land), or in a master relay zone whose
MASTER RLY is always false."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex
from ..instructions import JUMPS
from ..labels import token
from ..model import Element, Program
from .common import literal_or_none, node_span, rung_no
from .ranges import condition_of

CODE = rule_code(__name__)
# A rule of the whole program: a GOTO's reach ends at a LABEL anywhere below it.


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    return _after_goto(program, index) + _zones_off(program, index)


def _span(program: Program, rung: int):
    return node_span(program.rungs[rung].circuit) or program.rungs[rung].span


def _rungs_text(first: int, last: int, verb: str) -> str:
    """'rung 4 runs' or 'rungs 4 to 6 run'."""
    return f"{rung_no(first)} {verb}s" if first == last else f"rungs {first + 1} to {last + 1} {verb}"


def _live(program: Program, first: int, end: int) -> list[int]:
    """The rungs of first..end-1 that would do something (not comments)."""
    return [n for n in range(first, end) if program.rungs[n].circuit.items and not program.rungs[n].is_comment]


def _always_true(program: Program, index: ProgramIndex, rung: int, element: Element) -> bool:
    """The rung of `element` gives it power on every scan it runs: it ends the
    rung's top series and what comes before it always passes power."""
    circuit = program.rungs[rung].circuit
    return bool(circuit.items) and circuit.items[-1] is element and condition_of(program, index, circuit) is True


def _after_goto(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    count = len(program.rungs)
    # where a jump may land: a LABEL, a rung number a GOTO names, a subroutine's start or end
    landings = {rung for rung, _ in index.of_kind("LABEL", "SUBPROG", "ENDSUB")}
    for _, element in index.of_kind("GOTO"):
        number = literal_or_none(token(element.args.get("label")))
        if number is not None:  # clamped as LDmicro does (lang.semantics.lower.Jumps)
            landings.add(min(max(number, 1), count + 1) - 1)
    # a master relay zone may take the GOTO's power away
    first_relay = min((rung for rung, _ in index.of_kind("MASTER_RELAY")), default=count)
    found = []
    reached = -1  # the last rung already reported
    for rung, element in index.of_kind("GOTO"):
        if rung <= reached or rung >= first_relay or not _always_true(program, index, rung, element):
            continue
        end = min((landing for landing in landings if landing > rung), default=count)
        live = _live(program, rung + 1, end)
        if not live:
            continue
        reached = live[-1]
        found.append(report(
            CODE,
            f"{_rungs_text(live[0], live[-1], 'never run')}: the GOTO '{token(element.args.get('label'))}' in "
            f"{rung_no(rung)} jumps on every scan and no LABEL lets a jump land before "
            f"{rung_no(end) if end < count else 'the end of the program'}",
            _span(program, live[0]),
            *((Related(element.span, "this GOTO always jumps"),) if element.span is not None else ()),
        ))
    return found


def _zones_off(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    if any(index.of_kind(*JUMPS, "LABEL")):
        return []  # a jump decides which MASTER RLY runs: the zones are not in rung order
    relays = index.of_kind("MASTER_RELAY")
    found = []
    possible = {True}  # the master relay's states at this point of the scan ($mcr is set at its start)
    for at, (rung, element) in enumerate(relays):
        after = set()
        if True in possible:
            # an open relay copies the rung's state; a cleared one is always set again
            condition = condition_of(program, index, program.rungs[rung].circuit) \
                if program.rungs[rung].circuit.items[-1] is element else None
            after |= {True, False} if condition is None else {condition}
        if False in possible:
            after.add(True)
        possible = after
        if possible != {False}:
            continue
        end = relays[at + 1][0] if at + 1 < len(relays) else len(program.rungs)
        live = _live(program, rung + 1, end)
        if live:
            found.append(report(
                CODE,
                f"the MASTER RLY in {rung_no(rung)} is always false, so {_rungs_text(live[0], live[-1], 'run')} "
                "unpowered on every scan, as if their conditions were false",
                element.span,
            ))
    return found
