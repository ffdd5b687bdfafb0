"""Fuzzing the text reader and the checks: corpus exports damaged the way a
hand edit or a bad paste would (tests/mutations.py); any exception, and any
diagnostic without a location, is a crash. Run on demand:
`python benchmarks/fuzz_textform.py [--seconds S] [--inputs N] [--seed K] [--workers W]`."""

from __future__ import annotations

import random
import sys

from fuzzing import fuzz, options  # sets sys.path for the imports below

# isort: split
from corpus import EXPORTS
from mutations import mutate

from lang.checks import check_program
from lang.loader import checkable, checked
from lang.textform.reader import read_text

TEXTS = [path.read_text(encoding="cp1252") for path in sorted(EXPORTS.glob("*.txt"))]


def make(rng: random.Random) -> str:
    return mutate(rng.choice(TEXTS), rng, rng.randint(1, 8))


def trial(text: str) -> None:
    program, problems = read_text(text)
    unlocated = [p for p in problems if p.span is None]
    if unlocated:
        raise AssertionError(f"diagnostic without a location: {unlocated[0]}")
    if checkable(program, problems):  # a program whose broken rungs are all it lacks is checked too
        checked(program, check_program(program))


if __name__ == "__main__":
    sys.exit(fuzz("textform", make, trial, options(__doc__)))
