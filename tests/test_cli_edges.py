"""The command line at its edges: outputs that cannot be written, files that
exist, characters a code page lacks, stdin, wrong arguments. One rule each:
`path: error: ...`, exit 2 for what the user must change in the command,
never a traceback, never half a file."""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path
from xml.etree import ElementTree

import pytest

from ladder.cli import main
from lang.ldfile import read_ld

FIXTURES = Path(__file__).parent / "diagnostics"
SAMPLES = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "ldmicro" / "sample"


def run(capsys, *argv) -> tuple[int, str, str]:
    try:
        status = main([str(a) for a in argv])
    except SystemExit as stop:  # argparse's own usage errors
        status = stop.code
    out, err = capsys.readouterr()
    return status, out, err


@pytest.fixture
def program(tmp_path) -> Path:
    assert main(["new", "--part", "atmega328p", str(tmp_path / "lamp.ladder")]) == 0
    return tmp_path / "lamp.ladder"


OUTPUTS = [
    ["sim", "{p}", "--cycles", "3", "--vcd", "{d}/x.vcd"],
    ["new", "--part", "atmega8", "{d}/x.ladder"],
    ["convert", "{p}", "{d}/x.ld"],
    ["build", "{p}", "-o", "{d}/x.hex"],
    ["build", "{p}", "--emit", "c", "-o", "{d}/x.c"],
]


@pytest.mark.parametrize("argv", OUTPUTS)
def test_an_output_in_folders_that_do_not_exist_creates_them(capsys, tmp_path, program, argv):
    argv = [a.format(p=program, d=tmp_path / "new" / "folders") for a in argv]
    status, _, err = run(capsys, *argv)
    assert status == 0, err
    assert (tmp_path / "new" / "folders" / Path(argv[-1]).name).is_file()


@pytest.mark.parametrize("argv", OUTPUTS)
def test_an_output_that_cannot_be_written_is_one_clear_error(capsys, tmp_path, program, argv):
    """A folder in the path is a file: nothing can make it a folder."""
    (tmp_path / "afile").write_text("", encoding="utf-8")
    argv = [a.format(p=program, d=tmp_path / "afile" / "sub") for a in argv]
    status, _, err = run(capsys, *argv)
    assert status == 2
    assert re.search(r"afile(/sub)?: error: cannot write: (Not a directory|File exists)", err), err
    assert "Traceback" not in err


def _blink_scenario(tmp_path) -> Path:
    scenario = tmp_path / "s.scn"
    scenario.write_text(f"program {SAMPLES / 'blink.ld'}\n\nscenario off\nat 0 set Xbutton = 1\n"
                        "at 50 ms expect Cwhich = 0\n", encoding="utf-8")
    return scenario


def test_junit_in_a_folder_that_does_not_exist(capsys, tmp_path):
    status, _, err = run(capsys, "test", _blink_scenario(tmp_path), "--junit", tmp_path / "reports" / "ci" / "r.xml")
    assert status == 0, err
    ElementTree.parse(tmp_path / "reports" / "ci" / "r.xml")


def test_junit_that_cannot_be_written(capsys, tmp_path):
    (tmp_path / "afile").write_text("", encoding="utf-8")
    status, _, err = run(capsys, "test", _blink_scenario(tmp_path), "--junit", tmp_path / "afile" / "r.xml")
    assert status == 2 and "error: cannot write" in err


def test_fmt_goes_on_after_a_read_only_file(capsys, tmp_path):
    jagged = "LDmicro export text.\n\nLADDER DIAGRAM:\n    ||      Xa          Ya     ||\n" \
             "0001||-----] [--------( )------||\n"
    first, second = tmp_path / "a.ladder", tmp_path / "b.ladder"
    for path in (first, second):
        path.write_text(jagged, encoding="utf-8")
    first.chmod(0o444)
    try:
        status, _, err = run(capsys, "fmt", first, second)
    finally:
        first.chmod(0o644)
    assert status == 2 and f"{first}: error: cannot write: the file is read-only" in err
    assert first.read_text(encoding="utf-8") == jagged
    assert second.read_text(encoding="utf-8") != jagged


def test_convert_never_replaces_a_file_unasked_nor_its_input(capsys, tmp_path, program):
    target = tmp_path / "lamp.ld"
    assert run(capsys, "convert", program, target)[0] == 0
    before = target.read_bytes()
    status, _, err = run(capsys, "convert", program, target)
    assert status == 2 and "exists; use --force" in err and target.read_bytes() == before
    assert run(capsys, "convert", program, target, "--force")[0] == 0
    status, _, err = run(capsys, "convert", target, target, "--force")
    assert status == 2 and "the output is the input" in err and target.read_bytes() == before


def test_a_character_the_code_page_lacks_is_a_located_error(capsys, tmp_path):
    shutil.copy(FIXTURES / "LD012.ladder", tmp_path)
    status, _, err = run(capsys, "convert", tmp_path / "LD012.ladder", tmp_path / "out.ld")
    assert status == 1 and "LD012.ladder:6:30: error LD012 '電' (U+96FB)" in err
    assert not (tmp_path / "out.ld").exists()
    assert run(capsys, "convert", tmp_path / "LD012.ladder", tmp_path / "out.ld", "--output-encoding", "utf-8")[0] == 0
    status, _, err = run(capsys, "convert", tmp_path / "LD012.ladder", tmp_path / "x.ld", "--output-encoding", "bogus")
    assert status == 2 and "unknown encoding 'bogus'" in err


def test_long_ld_lines_are_warnings_with_a_location(capsys, tmp_path):
    source = tmp_path / "long.ld"
    source.write_text("LDmicro0.2\nPROGRAM\nRUNG 1\n  COMMENT " + "x" * 600 + "\nEND\n", encoding="ascii")
    status, _, err = run(capsys, "convert", source, tmp_path / "long.ladder")
    assert status == 0
    status, _, err = run(capsys, "convert", tmp_path / "long.ladder", tmp_path / "back.ld")
    assert status == 0 and re.search(r"long\.ladder:\d+:\d+: warning LD009 \.ld line \d+ is 610 bytes", err)


def test_new_writes_a_real_ld_file_for_every_part_family(capsys, tmp_path):
    for part in ("atmega8", "pic16f628", "pic12f675", "pic12f683"):
        target = tmp_path / f"{part}.ld"
        assert run(capsys, "new", "--part", part, target)[0] == 0
        program, problems = read_ld(target.read_text(encoding="cp1252"))
        assert target.read_bytes().startswith(b"LDmicro0.2\r\n") and problems == []
        assert run(capsys, "build", target)[0] == 0, part


def test_check_reads_stdin(capsys, monkeypatch, program):
    import io

    monkeypatch.setattr("sys.stdin", io.StringIO(program.read_text(encoding="utf-8").replace("Ylamp", "Xlamp")))
    status, out, _ = run(capsys, "check", "-")
    assert status == 1 and out.startswith("<stdin>:") and "LD102" in out


def test_version_and_a_bad_target_are_usage_matters(capsys, program):
    status, out, _ = run(capsys, "--version")
    assert status == 0 and re.fullmatch(r"ladder \S+\n", out)
    status, _, err = run(capsys, "build", program, "--target", "foo")
    assert status == 2 and "--target foo: unknown part" in err and "ATmega328P" in err


def test_the_plot_axis_labels_never_overlap(capsys):
    status, out, _ = run(capsys, "sim", SAMPLES / "blink.ld", "--for", "50ms", "--plot", "--set", "Xbutton=1")
    axis = next(line for line in out.splitlines() if line.startswith("time (ms)"))
    assert axis.split()[2:] == ["0", "20"]


def _scenario(tmp_path, body: str) -> Path:
    path = tmp_path / "s.scn"
    path.write_text(f"program {SAMPLES / 'blink.ld'}\n\n{body}", encoding="utf-8")
    return path


def test_scenario_failures_speak_the_scenario_language(capsys, tmp_path):
    path = _scenario(tmp_path, "scenario talk\nat 0 set Xbutton = 1\nat 100 ms expect uart \"x\"\n"
                               "at 100 ms expect Cwhich = 3\nat 200 ms expect Cwhich = 4\n")
    status, out, _ = run(capsys, "test", path, "--junit", tmp_path / "r.xml")
    assert status == 1
    assert 'expected UART output "x", got nothing' in out and "b'" not in out
    case = ElementTree.parse(tmp_path / "r.xml").getroot().find("testsuite/testcase")
    failures = case.findall("failure")
    assert len(failures) == 1 and "(and 2 more)" in failures[0].get("message")


def test_an_empty_scenario_file_fails(capsys, tmp_path):
    status, out, _ = run(capsys, "test", _scenario(tmp_path, "# nothing yet\n"))
    assert status == 1 and "no scenario in this file" in out


@pytest.mark.skipif(os.name != "posix", reason="file modes")
def test_a_written_file_keeps_its_mode(capsys, tmp_path, program):
    program.chmod(0o640)
    program.write_text(program.read_text(encoding="utf-8").replace("||\n", "   ||\n", 1), encoding="utf-8")
    run(capsys, "fmt", program)
    assert program.stat().st_mode & 0o777 == 0o640


def _rails(text: str) -> set[int]:
    return {len(line) for line in text.splitlines() if line.rstrip().endswith("||")}


def test_fmt_gives_a_hand_typed_diagram_one_width(capsys, tmp_path):
    source = tmp_path / "jagged.ladder"
    source.write_text("LDmicro export text.\n\nLADDER DIAGRAM:\n"
                      "    ||      Xa          Ya     ||\n0001||-----] [--------( )------||\n\n"
                      "    ||      Xlongername         T1               Ylongeroutput    ||\n"
                      "0002||-----] [-------------[TON 100 ms]-----------( )-------||\n\n"
                      "   2||------[END]--||\n", encoding="utf-8")
    assert run(capsys, "fmt", source)[0] == 0
    once = source.read_text(encoding="utf-8")
    assert len(_rails(once)) == 1
    assert run(capsys, "fmt", "--check", source)[0] == 0  # a second pass changes nothing


def test_the_new_template_has_one_width(capsys, program):
    assert len(_rails(program.read_text(encoding="utf-8"))) == 1
    assert run(capsys, "fmt", "--check", program)[0] == 0


def _nested(depth: int) -> str:
    """A rung whose parallel holds a series holding a parallel... `depth` deep."""
    lines, indent = ["LDmicro0.2", "", "PROGRAM", "RUNG 1"], "  "
    for level in range(depth):
        lines += [indent + "PARALLEL", indent + "  SERIES", indent + f"    CONTACTS Xa{level} 0 0"]
        indent += "    "
    lines.append(indent + "CONTACTS Xz 0 0")
    for level in reversed(range(depth)):
        indent = indent[:-4]
        lines += [indent + "  END", indent + f"  CONTACTS Xb{level} 0 0", indent + "END"]
    return "\n".join(lines + ["  COIL Yout 0 0 0 0", "END", ""])


def test_two_hundred_nested_parallels_pass_every_command(capsys, tmp_path):
    source = tmp_path / "deep.ld"
    source.write_text(_nested(200), encoding="ascii")
    text = tmp_path / "deep.ladder"
    for argv in (["check", source], ["convert", source, text], ["check", text], ["fmt", text],
                 ["convert", text, tmp_path / "back.ld"], ["sim", text, "--cycles", "2"], ["dump", source]):
        status, _, err = run(capsys, *argv)
        assert status == 0 and "Traceback" not in err, (argv, err[-300:])
    def elements(text):
        return [(e.kind, e.args) for _, e in read_ld(text)[0].elements()]

    assert elements((tmp_path / "back.ld").read_text(encoding="cp1252")) == elements(_nested(200))
