"""LD132: a bit written by coils in more than one rung, one of them a plain
coil (Rockwell's "duplicate destructive bit")."""

from __future__ import annotations

from itertools import islice

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex
from ..labels import label
from ..model import Program
from .common import NAMES, rung_no

CODE = rule_code(__name__)
SCOPE = NAMES

SHOWN = 4  # rungs named in the message, other coils given as related places
PLAIN = (" ", "/")  # `( )` and `(/)` write the bit on every scan; S, R and T only on their condition


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, uses in index.uses.items():
        if len(uses) < 2:
            continue  # most names: one use, no two coils (an open asks it of every name)
        coils = [use for use in uses if use.element.kind == "COIL"]
        written = {use.rung for use in coils} if len(coils) > 1 else ()
        if len(written) < 2:
            continue
        first = next((use for use in coils if use.element.args.get("type", " ") in PLAIN), None)
        if first is None:
            continue  # set and reset coils in different rungs: a latch
        # the first few only: a pinned output of thousands of copies has thousands of coils
        others = list(islice((use for use in coils if use.rung != first.rung), SHOWN))
        numbers = sorted(written)
        rungs = [str(rung + 1) for rung in numbers[:SHOWN + 1]]
        listed = f"{', '.join(rungs[:-1])} and {rungs[-1]}" if len(numbers) <= SHOWN else \
            f"{', '.join(rungs[:SHOWN])} and {len(numbers) - SHOWN} more"
        found.append(report(
            CODE,
            f"'{name}' is written by coils in rungs {listed}; the "
            f"{label(first.element)} in {rung_no(first.rung)} writes it on every scan, so on each scan only "
            "the coil that comes last counts",
            first.span,
            # the first few: a name written in thousands of rungs must not make a diagnostic as long
            *(Related(use.span, f"the {label(use.element)} in {rung_no(use.rung)} also writes '{name}'")
              for use in others if use.span is not None),
        ))
    return found
