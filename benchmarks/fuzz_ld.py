"""Fuzzing LDmicro's format: corpus `.ld` files with lines damaged, dropped,
repeated and cut, read, checked and written back; any exception is a crash,
and so is a file that reads without errors but does not read back the same
after writing. Run on demand:
`python benchmarks/fuzz_ld.py [--seconds S] [--inputs N] [--seed K] [--workers W]`."""

from __future__ import annotations

import random
import sys

from fuzzing import ROOT, fuzz, options

from lang.checks import check_program
from lang.ldfile import read_ld, write_ld

CORPUS = ROOT.parent / "shared" / "corpus"
TEXTS = [path.read_bytes().decode("cp1252", errors="replace") for path in sorted(CORPUS.rglob("*.ld"))]
TOKENS = ["PARALLEL", "SERIES", "END", "RUNG", "CONTACTS", "COIL", "0", "1", "-1", "(none)", "\\", "\"",
          "99999999999", "Xa", "\t", "  ", "\x00", "é"]


def make(rng: random.Random) -> str:
    lines = rng.choice(TEXTS).splitlines()
    for _ in range(rng.randint(1, 6)):
        at = rng.randrange(len(lines) + 1)
        edit = rng.choice(["token", "drop", "repeat", "cut", "swap"])
        if edit == "token" and at < len(lines):
            words = lines[at].split(" ")
            words[rng.randrange(len(words))] = rng.choice(TOKENS)
            lines[at] = " ".join(words)
        elif edit == "drop" and at < len(lines):
            del lines[at]
        elif edit == "repeat" and at < len(lines):
            lines.insert(at, lines[at])
        elif edit == "cut":
            lines = lines[:at]
        elif lines:
            other = rng.randrange(len(lines))
            at = min(at, len(lines) - 1)
            lines[at], lines[other] = lines[other], lines[at]
    return "\n".join(lines) + "\n"


def trial(text: str) -> None:
    program, problems = read_ld(text)
    if any(p.severity == "error" for p in problems):
        return
    check_program(program)
    warned: list = []
    again, problems = read_ld(write_ld(program, diagnostics=warned))
    if any(p.severity == "error" for p in problems):
        raise AssertionError(f"what was written does not read back: {problems[0]}")
    if warned:
        return  # the writer said what the file cannot keep (a control character in the 0.1 dialect)
    if [(e.kind, e.args) for _, e in again.elements()] != [(e.kind, e.args) for _, e in program.elements()]:
        raise AssertionError("what was written reads back as another program")


if __name__ == "__main__":
    sys.exit(fuzz("ld", make, trial, options(__doc__)))
