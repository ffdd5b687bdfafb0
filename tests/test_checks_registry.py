"""The registry and the check package: every rule has a row, every code a
reviewed row, a fixture whose output is checked and a generated page;
results sorted, and fast enough for the language server."""

from __future__ import annotations

import os
import pkgutil
import re
import shlex
import shutil
import time
from pathlib import Path

import pytest
from builders import coil, contact, counter, el, move, par, program, timer

import lang
import lang.checks
from ladder.cli import main
from lang.checks import RULES, check_program
from lang.codes import CODES, LDMICRO_VERDICTS
from lang.codes_doc import expected_of, fixture_of, render

DOCS = Path(__file__).resolve().parents[1] / "docs" / "diagnostics.md"
_HELPERS = {"common", "incremental", "ranges", "varflags"}


def test_every_rule_module_has_a_row():
    modules = {m.name for m in pkgutil.iter_modules(lang.checks.__path__)} - _HELPERS
    listed = {rule.__name__.rsplit(".", 1)[1] for rule in RULES}
    assert modules == listed


def test_one_code_per_rule():
    codes = [rule.CODE for rule in RULES]
    assert len(codes) == len(set(codes))
    for rule in RULES:
        assert CODES[rule.CODE].rule == rule.__name__.rsplit(".", 1)[1]
        assert callable(getattr(rule, "check", None)) or all(map(callable, rule.CHECKS.values()))


def test_every_code_used_in_the_sources_has_a_row():
    root = Path(lang.__file__).resolve().parents[1]
    used = set()
    for package in ("lang", "compiler", "lsp", "ladder"):
        for path in (root / package).rglob("*.py"):
            used |= set(re.findall(r'code\("(LD\d{3})"\)', path.read_text(encoding="utf-8")))
    assert used <= set(CODES)
    rules = {c.code for c in CODES.values() if c.rule}
    unused = sorted(set(CODES) - used - rules)
    assert not unused, f"rows no module reports: {unused}"


def test_every_error_says_what_ldmicro_does_and_why_it_is_an_error():
    # A program LDmicro compiles is an error here only when the row names the defect.
    for code in CODES.values():
        assert code.severity in ("error", "warning", "info"), code.code
        assert code.ldmicro in (None, *LDMICRO_VERDICTS), code.code
        if code.code[2] in "12345":
            assert code.ldmicro is not None or code.code == "LD107", f"{code.code}: no LDmicro verdict"
        if code.severity == "error" and code.ldmicro in ("accepts", "complains"):
            assert code.defect, f"{code.code}: an error LDmicro compiles needs its defect named"


def test_the_docs_are_generated_from_the_registry_and_the_fixtures():
    assert DOCS.read_text(encoding="utf-8") == render(), \
        "docs/diagnostics.md is stale: python -m lang.codes_doc > docs/diagnostics.md"


@pytest.mark.parametrize("code", sorted(CODES))
def test_each_code_has_a_fixture_whose_output_is_checked(code, tmp_path, monkeypatch, capsys):
    """The fixture's command, run again on a copy of the fixture's files,
    prints what its .out file holds (LADDER_BLESS=1 rewrites the .out files
    after a deliberate change)."""
    fixture = fixture_of(code)
    expected = expected_of(fixture)
    command = expected.read_text(encoding="utf-8").splitlines()[0]
    argv = shlex.split(command)
    assert argv[:2] == ["$", "ladder"] and argv[3].startswith(code), command
    for sibling in fixture.parent.glob(f"{code}.*"):
        shutil.copy(sibling, tmp_path)
    monkeypatch.chdir(tmp_path)
    main(argv[2:])
    printed = capsys.readouterr()
    got = f"{command}\n{printed.out}{printed.err}"
    if os.environ.get("LADDER_BLESS"):
        expected.write_text(got, encoding="utf-8")
    assert got == expected.read_text(encoding="utf-8")
    assert f" {CODES[code].severity} {code} " in got or code == "LD501", \
        f"{fixture.name} does not show {code} at its default severity"


def test_diagnostics_are_sorted_by_position():
    prog = program([contact("Tbad"), coil("Xin")], [contact("Xa"), move("5", 1)], [el("PLACEHOLDER")])
    found = check_program(prog)
    assert [d.code for d in found] == ["LD101", "LD131", "LD102", "LD303", "LD212"]
    keys = [(d.span.line, d.span.col) for d in found]
    assert keys == sorted(keys)


def _big_program(rungs: int):
    def rung(i):
        k = i % 5
        if k == 0:
            return [contact(f"X{i % 40}"), contact(f"R{i}", 1), timer("TON", f"T{i}", 100000), coil(f"R{i + 1}")]
        if k == 1:
            return [par([contact(f"R{i}")], [contact(f"X{i % 40}"), contact(f"Y{i % 30}", 1)]),
                    counter("CTU", f"C{i}", 10), coil(f"Y{i % 30}")]
        if k == 2:
            return [el("GEQ", op1=f"C{i - 1}", op2="5"),
                    par([move(f"v{i}", i)], [el("ADD", dest=f"w{i}", op1=f"v{i}", op2="1")])]
        if k == 3:
            return [contact(f"R{i - 2}"), el("OSR"),
                    par([coil(f"R{i}", "S")], [el("RES", name=f"C{i - 2}")], [coil(f"M{i % 10}")])]
        return [el("EQU", op1=f"w{i - 2}", op2="3"), contact(f"R{i - 1}"), timer("TOF", f"T{i}", 50000),
                coil(f"R{i + 2}")]

    return program(*[rung(i) for i in range(rungs)], mcu="Atmel AVR ATmega2560 100-TQFP")


def test_two_thousand_rungs_check_quickly():
    # The language server re-checks after each edit; on a quiet machine the
    # whole check of this program takes a few tens of milliseconds. The bound
    # here only catches a rule that went quadratic, not noise on a busy CI.
    prog = _big_program(2000)
    best = min(_timed(prog) for _ in range(3))
    assert best < 1.0, f"checking 2000 rungs took {best:.3f} s"


def _timed(prog) -> float:
    start = time.process_time()
    check_program(prog)
    return time.process_time() - start
