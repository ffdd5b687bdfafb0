"""A text with reading errors is read rung by rung: every broken rung gets
its located errors, and the checks still speak about the rungs that read, so
one pass shows every problem (docs/format.md, "Reading errors")."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lsprotocol import types
from test_lsp_actions import actions_at, edits_of
from test_lsp_incremental import apply, edits
from test_lsp_support import Doc, apply_edits, lsp_fixture, new_uri

from ide.incremental import IncrementalReader
from ladder.cli import main
from lang.checks import Checker, check_program
from lang.loader import checkable, checked, load_file
from lang.textform.reader import TextReader, read_text
from lang.textform.rungs import UnreadRung

# six problems of six kinds, one a rung: a missing wire (rung 1), an unknown
# drawing (2), a timer without its T (3), a relay nobody writes (4), a coil on
# an input (5) and a `+` a column right of its connector (6)
SIX = """LDmicro export text.
for 'Atmel AVR ATmega328 28-PDIP', 16 MHz crystal, 10.000 ms cycle time

LADDER DIAGRAM:
    ||                                                                    ||
    ||     Xstart            Xstop                             Rrun       ||
0001|+-------] [------+-------]/[----------       --------------( )-------||
    ||                |                                                   ||
    ||      Rrun      |                                                   ||
    |+-------] [------+                                                   ||
    ||                                                                    ||
    ||      Rrun                                              Ymotor      ||
0002||-------] [--------------[?]-------------------------------( )-------||
    ||                                                                    ||
    ||      Rrun             delay                             Yhorn      ||
0003||-------] [-----------[TON 2 s]----------------------------( )-------||
    ||                                                                    ||
    ||     Rghost                                              Ylamp      ||
0004||-------] [------------------------------------------------( )-------||
    ||                                                                    ||
    ||      Rrun                                               Xstop      ||
0005||-------] [------------------------------------------------( )-------||
    ||                                                                    ||
    ||     Xstart                                             Rlatch      ||
0006|+-------] [------+-----------------------------------------( )-------||
    ||                |                                                   ||
    ||     Rlatch     |                                                   ||
    |+-------] [-------+                                                  ||
    ||                                                                    ||
    ||------[END]---------------------------------------------------------||

I/O ASSIGNMENT:
  Name                       | Type               | Pin | Port | Pin name
 ----------------------------+--------------------+-----+------+-----------
  Xstart                     | digital in         |   4 | PD2   | PD2 PCINT18/INT0
  Xstop                      | digital in         |   5 | PD3   | PD3 PCINT19/OC2B/INT1
  Yhorn                      | digital out        |  18 | PB4   | PB4 MISO/PCINT4
  Ymotor                     | digital out        |  19 | PB5   | PB5 SCK/PCINT5
  Ylamp                      | digital out        |  17 | PB3   | PB3
"""

client = lsp_fixture()

SIX_REPORT = [
    "{path}:7:44: error LD004 this branch stops before reaching a junction",
    "{path}:13:31: error LD003 no instruction is drawn like '[?]'",
    "{path}:15:30: warning LD104 TON timer 'delay' in rung 3: timer names start with T (e.g. 'Tdelay')",
    "{path}:18:12: warning LD130 internal relay 'Rghost' is read by contact in rung 4 but no coil ever writes it: "
    "it is always 0",
    "{path}:21:64: error LD102 coil 'Xstop' in rung 5 writes an input pin: X names can only be read; "
    "write an output (Y) or a relay (R)",
    "{path}:28:24: error LD014 move '+' to column 23, under the '+' of line 25",
]


def _write(tmp_path: Path, text: str, name: str = "six.ladder") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_check_reports_the_six_problems_in_one_pass(tmp_path, capsys):
    path = _write(tmp_path, SIX)
    assert main(["check", str(path)]) == 1
    assert capsys.readouterr().out.splitlines() == [line.format(path=path) for line in SIX_REPORT]


def test_a_broken_rung_keeps_its_place():
    """Rung 5's message says rung 5 although rungs 1 and 2 could not be read:
    each broken rung stands in its place, with what it could recognise."""
    program, _ = read_text(SIX)
    assert len(program.rungs) == 6
    assert [isinstance(rung, UnreadRung) for rung in program.rungs] == [True, True, False, False, False, True]
    names = [[element.args.get("name") for element in rung.elements()] for rung in program.rungs[:2]]
    assert names == [["Xstart", "Xstop", "Rrun", "Rrun"], ["Rrun", "Ymotor"]]


def test_a_name_written_only_by_a_broken_rung_is_not_called_never_written():
    program, problems = read_text(SIX)
    assert checkable(program, problems)
    messages = [d.message for d in checked(program, check_program(program))]
    assert not [m for m in messages if "'Rrun'" in m]


def test_the_checks_say_nothing_inside_a_broken_rung(tmp_path, capsys):
    """A half-read rung is not what was drawn: its timer named 'delay' waits
    until the wire is mended."""
    broken = SIX.replace("[TON 2 s]----------------------------( )", "[TON 2 s]----------           -------( )")
    path = _write(tmp_path, broken)
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out
    assert f"{path}:16:47: error LD004 " in out
    assert "LD104" not in out


def test_an_error_outside_the_diagram_still_stops_the_checks(tmp_path, capsys):
    """A broken I/O table or header leaves the program too incomplete to
    check without false alarms (every X would have no pin)."""
    path = _write(tmp_path, SIX.replace("|   4 | PD2", "|   ? | PD2"))
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out
    assert "LD002" in out and "LD004" in out and "LD014" in out
    assert "LD104" not in out and "LD102" not in out


def test_a_detail_of_an_element_a_broken_rung_lost_is_no_second_error():
    """DETAILS may name an element whose drawing is broken: the rung's error
    says what is wrong, and the checks still run."""
    text = SIX.replace("[TON 2 s]", "[TOX 2 s]") + "\nDETAILS:\n  TON delay: adjust -1\n"
    program, problems = read_text(text)
    assert [p.code for p in problems] == ["LD004", "LD003", "LD003", "LD014"]
    assert checkable(program, problems)
    mended, problems = read_text(text.replace("[TOX 2 s]", "[TON 2 s]").replace("[?]", "---"))
    timer = next(e for _, e in mended.elements() if e.kind == "TON")
    assert timer.args["adjust"] == -1


def test_fmt_leaves_a_file_with_a_broken_rung_as_it_is(tmp_path, capsys):
    path = _write(tmp_path, SIX)
    assert main(["fmt", str(path)]) == 1
    assert path.read_text(encoding="utf-8") == SIX
    err = capsys.readouterr().err
    assert all(code in err for code in ("LD004", "LD003", "LD014"))


@pytest.mark.parametrize("command", [["convert", "{path}", "{out}"], ["build", "{path}", "-o", "{out}"],
                                     ["sim", "{path}", "--for", "1s"]])
def test_convert_build_and_sim_refuse_and_name_every_broken_rung(tmp_path, capsys, command):
    path = _write(tmp_path, SIX)
    out = tmp_path / ("six.ld" if command[0] == "convert" else "six.hex")
    assert main([part.format(path=path, out=out) for part in command]) != 0
    printed = capsys.readouterr()
    shown = printed.out + printed.err
    assert all(f"{path}:{line}:" in shown for line in (7, 13, 28)), shown
    assert not out.exists()


def test_fix_moves_the_misplaced_glyph_and_leaves_the_rest(tmp_path, capsys):
    path = _write(tmp_path, SIX)
    assert main(["check", "--fix", str(path)]) == 1
    assert f"{path}: fixed: move '+' to column 23" in capsys.readouterr().err
    assert path.read_text(encoding="utf-8") == SIX.replace("[-------+  ", "[------+   ")


def test_fix_moves_the_glyph_first_then_makes_the_checks_fixes(tmp_path, capsys):
    """Once the move leaves no reading error, the checks' fixes that need no
    choice follow (a rename must see every use of the name)."""
    path = _write(tmp_path, SIX.replace("[?]", "---").replace("]/[----------       ----", "]/[-----------------------"))
    assert main(["check", "--fix", str(path)]) == 1
    printed = capsys.readouterr()
    assert printed.err.splitlines() == [f"{path}: fixed: move '+' to column 23",
                                        f"{path}: fixed: Rename 'delay' to 'Tdelay' (timer)"]
    assert [line.split(" ")[2] for line in printed.out.splitlines()] == ["LD130", "LD102"]


def test_a_rung_broken_then_mended_reads_as_a_fresh_reader_reads_it():
    reader = TextReader()
    reader.read(SIX)
    mended = SIX.replace("[?]", "---").replace("[-------+  ", "[------+   ").replace(
        "]/[----------       ----", "]/[-----------------------")
    program, problems = reader.read(mended)
    assert reader.last_mode == "window" or reader.last_mode == "full"
    assert (program, problems) == read_text(mended)
    assert not any(isinstance(rung, UnreadRung) for rung in program.rungs)
    assert [p.code for p in problems] == []


def _as_ladder_check(text: str) -> list[str]:
    program, problems = read_text(text)
    found = checked(program, check_program(program)) if checkable(program, problems) else []
    return sorted(d.format("f") for d in problems + found)


@settings(max_examples=80, suppress_health_check=[HealthCheck.too_slow], deadline=None)
@given(data=st.data())
def test_edits_of_a_broken_program_are_checked_as_a_fresh_check_does(data):
    """The editor's way (the text re-read where it changed, the checks run
    again on what an edit can change) gives what `ladder check` gives, after
    edits that break rungs and mend them."""
    reader, checker = IncrementalReader("ladder"), Checker()
    text = SIX
    for step in [None, *data.draw(edits(SIX))]:
        text = text if step is None else apply(text, step)
        program, problems = reader.read(text)
        found = checked(program, checker.check(program, reader.moved)) if checkable(program, problems) else []
        assert sorted(d.format("f") for d in problems + found) == _as_ladder_check(text)


def test_a_loaded_file_with_broken_rungs_is_checkable(tmp_path):
    loaded = load_file(_write(tmp_path, SIX))
    assert checkable(loaded.program, loaded.diagnostics)


def test_the_misplaced_glyph_s_message_follows_its_rung_when_lines_are_added_above():
    reader = TextReader()
    reader.read(SIX)
    blank = "    ||                                                                    ||\n"
    moved = SIX.replace(blank, blank * 2, 1)
    program, problems = reader.read(moved)
    assert reader.last_mode == "window"
    assert (program, problems) == read_text(moved)
    assert problems[-1].format("f") == "f:29:24: error LD014 move '+' to column 23, under the '+' of line 26"
    assert problems[-1].fixes[0].change.span.line == 28


@pytest.mark.asyncio(loop_scope="module")
async def test_the_editor_shows_every_problem_and_moves_the_glyph(client):
    doc = Doc(client, new_uri(), SIX)
    found = sorted(await doc.diagnostics(), key=lambda d: d.range.start.line)
    assert [(d.range.start.line + 1, d.code) for d in found] == [
        (7, "LD004"), (13, "LD003"), (15, "LD104"), (18, "LD130"), (21, "LD102"), (28, "LD014")]
    misplaced = found[-1]
    actions = await actions_at(client, doc, misplaced.range.start, misplaced.range.end, [misplaced],
                               only=["quickfix"])
    assert [a.title for a in actions] == ["move '+' to column 23"]
    doc.replace_all(apply_edits(doc.text, edits_of(actions[0], doc.uri)))
    mended = sorted(await doc.diagnostics(), key=lambda d: d.range.start.line)
    assert [d.code for d in mended] == ["LD004", "LD003", "LD104", "LD130", "LD102"]
    # a broken rung is not redrawn from what could be read of it; a rung that reads is
    in_broken = await actions_at(client, doc, types.Position(line=12, character=14))
    in_good = await actions_at(client, doc, types.Position(line=15, character=14))
    assert not [a.title for a in in_broken if a.title.startswith("Delete")]
    assert "Delete contact 'Rrun'" in [a.title for a in in_good]
