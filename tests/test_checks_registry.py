"""The check package as a whole: every rule listed, one code per rule, every
registered code documented, results sorted, and fast enough for the
language server."""

from __future__ import annotations

import importlib
import pkgutil
import re
import time
from pathlib import Path

from builders import coil, contact, counter, el, move, par, program, timer

import lang
import lang.checks
from lang.checks import RULES, check_program
from lang.codes import CODES

DOCS = Path(__file__).resolve().parents[1] / "docs" / "diagnostics.md"
_HELPERS = {"common", "index", "varflags"}


def _import_everything() -> None:
    """Import every module of lang/ and compiler/ so that every code is registered."""
    import compiler

    for package, prefix in ((lang, "lang."), (compiler, "compiler.")):
        for module in pkgutil.walk_packages(package.__path__, prefix):
            importlib.import_module(module.name)


def test_every_rule_module_is_listed():
    modules = {m.name for m in pkgutil.iter_modules(lang.checks.__path__)} - _HELPERS
    listed = {rule.__name__.rsplit(".", 1)[1] for rule in RULES}
    assert modules == listed


def test_one_code_per_rule():
    codes = [rule.CODE for rule in RULES]
    assert len(codes) == len(set(codes))
    for rule in RULES:
        assert rule.CODE in CODES, rule.__name__
        assert callable(rule.check)


def test_every_registered_code_has_a_section_in_the_docs():
    _import_everything()
    text = DOCS.read_text(encoding="utf-8")
    sections = dict(re.findall(r"^## (LD\d{3})\n(.*?)(?=^## |\Z)", text, flags=re.M | re.S))
    missing = sorted(set(CODES) - set(sections))
    assert not missing, f"docs/diagnostics.md has no section for {missing}"
    for code, body in sections.items():
        assert code in CODES, f"docs/diagnostics.md documents {code}, which no module registers"
        assert f"**{CODES[code].summary}**" in body, f"{code}: the summary in the docs differs from the registry"
        assert " ".join(CODES[code].doc.split()) in " ".join(body.split()), \
            f"{code}: the text in the docs differs from the registry's"
        assert "Example" in body, f"{code}: no example"


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
