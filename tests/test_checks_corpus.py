"""The real LDmicro programs of the corpus: LDmicro compiled (or at least
loaded) them, so the name and structure rules must not call them broken,
except where a file really is broken. Each exception is listed with the reason.

Rules about pins, parts and targets (LD4xx, LD5xx) and about timer values are
left out of the "no error" test: those depend on which back end compiles the
program (LDmicro's C back ends take SPI/I2C that its AVR code generator does
not), and some samples were never meant to be compiled.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from lang import ldfile
from lang.checks import check_program

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus"
FILES = sorted(CORPUS.rglob("*.ld"))


# name and structure rules: LD010, LD1xx, LD2xx
def _is_name_or_structure(code: str) -> bool:
    return code == "LD010" or code.startswith(("LD1", "LD2"))


# Samples that really are broken, with the errors they must give and why.
KNOWN_BROKEN = {
    # catalog.ld is LDmicro's element catalogue export: every element with the
    # editor's default names, so one name Tnew serves seven timer kinds and a
    # T2CNT, and one rung is an empty PLACEHOLDER. LDmicro would refuse to
    # compile it ("TOF: variable can only be used for RES elsewhere",
    # "Empty row").
    "ldmicro-export/catalog.ld": {"LD120", "LD122", "LD212"},
}


def _id(path: Path) -> str:
    return path.relative_to(CORPUS).as_posix()


@pytest.mark.skipif(not FILES, reason="no corpus beside the repository")
@pytest.mark.parametrize("path", FILES, ids=_id)
def test_corpus_has_no_name_or_structure_errors(path):
    program, _ = ldfile.read_ld_bytes(path.read_bytes())  # the reader's own findings are its tests' business
    errors = {d.code for d in check_program(program)
              if d.severity == "error" and _is_name_or_structure(d.code)}
    assert errors == KNOWN_BROKEN.get(_id(path), set())


@pytest.mark.skipif(not FILES, reason="no corpus beside the repository")
def test_corpus_checks_do_not_crash_and_stay_located():
    for path in FILES:
        program, _ = ldfile.read_ld_bytes(path.read_bytes())
        for d in check_program(program):
            # only the part-level diagnostics have no place in the file
            assert d.span is not None or d.code in ("LD408", "LD409"), (path, d)
