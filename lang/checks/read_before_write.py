"""LD133: an internal relay or variable read in a rung above every rung that
writes it: that read sees the value of the previous scan."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex, Use
from ..labels import label, token
from ..model import Program
from ..roles import ROLES
from ..values import is_literal
from .common import GENERATED, NAMES, literal_or_none, rung_no

CODE = rule_code(__name__)
# A function of each name's uses, the rungs they are in and the order the rungs
# run in, which the whole program's jumps decide (`index.whole`; an edit that
# changes a jump is checked whole, lang.checks.incremental).
SCOPE = NAMES


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    whole = index.whole
    flow = whole.cache.get("flow")
    if not isinstance(flow, _Flow):
        flow = whole.cache["flow"] = _Flow(whole)
    found = []
    reads: dict[int, set[str]] = {}  # a rung's read names, walked once for every name it holds
    for name, uses in index.uses.items():
        if not _lags(name):
            continue
        first_write = next((use for use in uses if use.writes), None)
        if first_write is None:
            continue  # never written: LD130, LD131
        read = uses[0]
        if read.rung >= first_write.rung or not read.reads:
            continue
        if flow.reorders(uses, read.rung, first_write.rung) or _only_set(uses) or \
                _edge_memory(program, name, read, uses, reads):
            continue
        found.append(report(
            CODE,
            f"'{name}' is read in {rung_no(read.rung)} before {rung_no(first_write.rung)} writes it: "
            f"the {label(read.element)} in {rung_no(read.rung)} sees the value of the previous scan",
            read.span,
            *((Related(first_write.span, f"'{name}' is first written here"),) if first_write.span else ()),
        ))
    return found


def _lags(name: str) -> bool:
    """An internal relay or an integer variable: names the program keeps in
    RAM for itself (inputs, timers, counters and outputs have rules of their own)."""
    if not name or name in GENERATED or name.startswith("$") or is_literal(name):
        return False
    return name[0] == "R" or name[0] not in ROLES


def _only_set(uses: list[Use]) -> bool:
    """Only ever set by (S) coils: a flag that says something is done, which
    rungs above read to do it until then (the lag is what they expect)."""
    return all(use.element.kind == "COIL" and use.element.args.get("type") == "S" for use in uses if use.writes)


def _edge_memory(program: Program, name: str, read: Use, uses: list[Use], reads: dict[int, set[str]]) -> bool:
    """The reading rung also reads a name that the rungs writing `name` read:
    it compares a signal with its copy of the previous scan (an edge memory,
    the idiom this lag is for)."""
    sources = set().union(*(_rung_reads(program, use.rung, reads) for use in uses if use.writes)) - {name}
    return not _rung_reads(program, read.rung, reads).isdisjoint(sources)


def _rung_reads(program: Program, rung: int, reads: dict[int, set[str]]) -> set[str]:
    found = reads.get(rung)
    if found is None:
        found = reads[rung] = {token(v) for element in program.rungs[rung].elements() for v in _read_names(element)}
    return found


def _read_names(element) -> list[str]:
    if element.kind == "CONTACTS":
        return [str(element.args.get("name", ""))]
    return [str(element.args[field]) for field in ("op1", "op2", "src") if field in element.args]


class _Flow:
    """Where the rungs do not run in their order: subroutine bodies (called
    from anywhere) and the rungs a backward GOTO runs again."""

    def __init__(self, index: ProgramIndex):
        ends = {token(e.args.get("label")): rung for rung, e in index.of_kind("ENDSUB")}
        # a SUBPROG without its ENDSUB (LD205) runs to the end of the program
        self.bodies = [(rung, ends.get(token(e.args.get("label")), len(index.program.rungs)))
                       for rung, e in index.of_kind("SUBPROG")]
        labels = {token(e.args.get("label")): rung for rung, e in index.of_kind("LABEL")}
        self.loops = []
        for rung, element in index.of_kind("GOTO"):
            target = token(element.args.get("label"))
            number = literal_or_none(target)
            back = labels.get(target) if number is None else number - 1
            if back is not None and back <= rung:
                self.loops.append((back, rung))

    def reorders(self, uses: list[Use], read: int, write: int) -> bool:
        if any(start <= use.rung <= end for use in uses for start, end in self.bodies):
            return True
        return any(back <= read and rung >= write for back, rung in self.loops)
