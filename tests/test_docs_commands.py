"""Every shell command in README.md and docs/*.md works as written.

Each document's `sh` blocks run in document order, each block as one bash
script (`set -e`), in a scratch folder of the document's own where `ladder`
is the test venv's and the repository's examples are copied twice over:
as the folder `examples/` and, beside it, each file (`conveyor.ladder`).
A block a `<!-- doc-test: file NAME -->` comment names is written there as
NAME when the reading reaches it; one marked `<!-- doc-test: output -->` must
be what the shell block before it prints (tests/doc_blocks.py has the
conventions).

Not run, but checked:
* a block marked `<!-- doc-test: hardware -->` (flashing a chip): its syntax,
  and that each programmer command writes a HEX file the steps before it made;
* the commands that are CI's own steps: the README's install command (.ci/run's
  package step runs it, verbatim, in the unpacked sdist), `bash .ci/run`, the
  test suite (`python -m pytest`), the extension's build (`npm`, `code`, a `cd`
  into a folder of the checkout), the venv's activation: the files and folders
  they name must exist in the checkout.

A block needing simavr or gpsim (`simavr`, `gpsim`, `ladder test --on avr` or
`pic16`) runs in the test marked slow, one needing Debian's Arduino core
(`arduino-builder`, or `arduino-cli`, which Debian 12 does not have) in the
test marked arduino: the fast test leaves those blocks out. `.ci/run` installs
simavr and gpsim in its first step, the Arduino core in the Arduino step.
"""

import difflib
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from doc_blocks import OTHER_SHELLS, SHELL, Block, Command, blocks, first_command

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = [README, *sorted((ROOT / "docs").glob("*.md"))]
# generated from tests/diagnostics/, whose commands and outputs test_checks_registry.py runs and compares
TRANSCRIPTS = ROOT / "docs" / "diagnostics.md"

PROGRAMMERS = ("avrdude", "pk2cmd", "ipecmd", "minipro")
CI_COMMAND = re.compile(r"(^|[\s)])bash \.ci/run(\s|$)")
INSTALL_COMMAND = re.compile(r"pip install \.(\s|$)")
# the checkout's own workflows, which CI runs in steps of its own
CHECKOUT_PROGRAMS = ("npm", "code")
ACTIVATE_PROGRAMS = (".", "source")
SLOW_PROGRAMS = ("simavr", "gpsim")
ARDUINO_PROGRAMS = ("arduino-builder", "arduino-cli")


def _words(command: Command) -> list[str]:
    try:
        return shlex.split(command.text, comments=True)
    except ValueError:
        return command.text.split()


def _need(command: Command) -> str:
    """'fast', 'slow' or 'arduino': which test runs the command."""
    words = _words(command)
    program = words[0] if words else ""
    if program in ARDUINO_PROGRAMS:
        return "arduino"
    on = [words[i + 1] for i, word in enumerate(words[:-1]) if word == "--on"]
    if program in SLOW_PROGRAMS or (program == "ladder" and any(target in ("avr", "pic16") for target in on)):
        return "slow"
    return "fast"


def _name(path: Path) -> str:
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else path.name


def _checked_not_run(block: Block, command: Command, folder: Path) -> bool:
    """True for CI's own steps (after checking what they name exists)."""
    words = _words(command)
    where = f"{_name(block.path)}:{command.line}"
    if CI_COMMAND.search(command.text):
        assert (ROOT / ".ci" / "run").is_file(), f"{where}: names .ci/run, which does not exist"
        return True
    if INSTALL_COMMAND.search(command.text):
        readme = first_command(README)
        assert command.text == readme or readme.startswith(command.text + " && "), \
            f"{where}: an install of the checkout is the README's first command (or its start), which .ci/run runs"
        assert "doc_blocks.py --first-command README.md" in (ROOT / ".ci" / "run").read_text(encoding="utf-8"), \
            f"{where}: .ci/run's package step no longer runs the README's first command"
        return True
    if words[:3] == ["python", "-m", "pytest"]:
        named = [word for word in words if word.startswith("tests/")]
        for pattern in named:
            assert list(ROOT.glob(pattern)), f"{where}: no test file {pattern}"
        return True
    if words[:1] == ["cd"] and len(words) == 2 and not (folder / words[1]).is_dir() and (ROOT / words[1]).is_dir():
        return True
    if words and words[0] in ACTIVATE_PROGRAMS:
        assert words[1:] == [".venv/bin/activate"], f"{where}: activates no venv the install made: {command.text}"
        return True
    if words and words[0] in CHECKOUT_PROGRAMS:
        for word in words[1:]:
            if "/" in word and not word.startswith("-"):
                assert (ROOT / word).exists(), f"{where}: {word} is not in the checkout"
        return True
    return False


def _hex_written(words: list[str]) -> str | None:
    """The HEX file a programmer's command line writes to the chip."""
    program, arguments = words[0], words[1:]
    for i, word in enumerate(arguments):
        if program == "avrdude" and word == "-U" and i + 1 < len(arguments):
            memory, _, rest = arguments[i + 1].partition(":")
            if memory == "flash" and rest.startswith("w:"):
                return rest[2:].rsplit(":", 1)[0] if rest.count(":") > 1 else rest[2:]
        if program in ("pk2cmd", "ipecmd") and word.startswith("-F"):
            return word[2:] or (arguments[i + 1] if i + 1 < len(arguments) else None)
        if program == "minipro" and word == "-w" and i + 1 < len(arguments):
            return arguments[i + 1]
    return None


_PART_FLAG = {"avrdude": "-p", "pk2cmd": "-P", "ipecmd": "-P", "minipro": "-p"}


def _check_hardware_block(block: Block, folder: Path) -> None:
    where = f"{_name(block.path)}:{block.line}"
    syntax = subprocess.run(["bash", "-n"], input=block.text, capture_output=True, text=True)
    assert syntax.returncode == 0, f"{where}: not valid shell:\n{syntax.stderr}"
    for command in block.commands():
        words = _words(command)
        if not words or words[0] not in PROGRAMMERS:
            continue
        place = f"{_name(block.path)}:{command.line}"
        flag = _PART_FLAG[words[0]]
        assert any(word.startswith(flag) for word in words[1:]), f"{place}: {words[0]} without the part ({flag}): {command.text}"
        hex_file = _hex_written(words)
        assert hex_file, f"{place}: {words[0]} writes no HEX file: {command.text}"
        assert (folder / hex_file).is_file(), \
            f"{place}: {words[0]} writes {hex_file}, which the document's steps before it do not make: {command.text}"


def _script(block: Block, skipped: set[int]) -> str:
    """The block as a script whose line N+2 is the block's line N; the lines of the
    commands not run become no-ops, so the numbers stay."""
    lines = block.text.splitlines()
    body = [":" if block.line + i in skipped else line for i, line in enumerate(lines)]
    return "set -eo pipefail\ntrap 'echo \"doc-test-line $LINENO\" >&2' ERR\n" + "\n".join(body) + "\n"


def _run_block(document: Path, block: Block, folder: Path, needs: set[str]) -> str | None:
    """Runs the commands of the block a test with `needs` runs; their output, or None when none ran."""
    skipped: set[int] = set()
    for command in block.commands():
        if _words(command)[:1] and _words(command)[0] in PROGRAMMERS:
            pytest.fail(f"{_name(document)}:{command.line}: `{command.text}` needs a board: "
                        "mark its block <!-- doc-test: hardware -->", pytrace=False)
        if _checked_not_run(block, command, folder) or _need(command) not in needs:
            skipped |= set(range(command.line, command.last_line + 1))
    if all(command.line in skipped for command in block.commands()):
        return None
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    result = subprocess.run(["bash", "-c", _script(block, skipped)], cwd=folder, env=env, input="",
                            capture_output=True, text=True, timeout=600)
    if result.returncode != 0:
        marks = re.findall(r"doc-test-line (\d+)", result.stderr)
        line = block.line + int(marks[-1]) - 3 if marks else block.line
        failed = next((c.text for c in block.commands() if c.line <= line <= c.last_line), block.text)
        pytest.fail(f"{_name(document)}:{line}: `{failed}` exited {result.returncode}\n"
                    f"--- stdout\n{result.stdout[-3000:]}\n--- stderr\n{result.stderr[-3000:]}", pytrace=False)
    return result.stdout


def _run_document(document: Path, folder: Path, needs: set[str]) -> None:
    """Runs the document's blocks a test with `needs` runs, and compares the outputs it shows."""
    shutil.copytree(ROOT / "examples", folder / "examples")
    for example in (ROOT / "examples").iterdir():
        if example.is_file():
            shutil.copy2(example, folder / example.name)
    output: str | None = None  # of the last shell block run
    for block in blocks(document):
        if block.file_name:
            (folder / block.file_name).parent.mkdir(parents=True, exist_ok=True)
            (folder / block.file_name).write_text(block.text, encoding="utf-8")
        elif block.shows_output:
            if output is not None and block.text != output:
                diff = "".join(difflib.unified_diff(block.text.splitlines(True), output.splitlines(True),
                                                    "the document shows", "the commands print"))
                pytest.fail(f"{_name(document)}:{block.line}: the output shown is not what the commands above "
                            f"print:\n{diff}", pytrace=False)
        elif block.info == SHELL and block.hardware:
            _check_hardware_block(block, folder)
            output = None
        elif block.info == SHELL:
            output = _run_block(document, block, folder, needs)


def _needs_of(document: Path) -> set[str]:
    return {_need(command) for block in blocks(document) if block.info == SHELL and not block.hardware
            for command in block.commands()}


def _documents(need: str) -> list[Path]:
    return [document for document in DOCS if need in _needs_of(document)]


def test_shell_blocks_are_marked_sh():
    for document in DOCS:
        if document == TRANSCRIPTS:
            continue
        for block in blocks(document):
            assert block.info not in OTHER_SHELLS, \
                f"{_name(document)}:{block.line}: a shell block is marked `{block.info}`: the docs mark them `{SHELL}`"


@pytest.mark.parametrize("document", _documents("fast"), ids=_name)
def test_the_commands_work(document, tmp_path):
    _run_document(document, tmp_path, {"fast"})


@pytest.mark.slow
@pytest.mark.parametrize("document", _documents("slow"), ids=_name)
def test_the_commands_that_need_the_simulators_work(document, tmp_path):
    _run_document(document, tmp_path, {"fast", "slow"})


@pytest.mark.arduino
@pytest.mark.parametrize("document", _documents("arduino"), ids=_name)
def test_the_commands_that_need_the_arduino_core_work(document, tmp_path):
    _run_document(document, tmp_path, {"fast", "slow", "arduino"})


def test_a_failing_command_names_its_document_and_line(tmp_path):
    document = tmp_path / "guide.md"
    folder = tmp_path / "run"
    folder.mkdir()
    document.write_text("Intro\n\n```sh\nladder --help > /dev/null\nladder check nothing-here.ladder\n```\n", encoding="utf-8")
    with pytest.raises(pytest.fail.Exception) as failure:
        _run_document(document, folder, {"fast"})
    assert str(failure.value).startswith("guide.md:5: `ladder check nothing-here.ladder` exited 2")


def test_a_flash_names_the_hex_file_the_steps_before_it_made(tmp_path):
    block = Block(README, 10, SHELL, "avrdude -c usbasp -p m328p -U flash:w:blink.hex:i\n", "hardware")
    with pytest.raises(AssertionError, match="writes blink.hex, which the document's steps before it do not make"):
        _check_hardware_block(block, tmp_path)
    (tmp_path / "blink.hex").write_text(":00000001FF\n")
    _check_hardware_block(block, tmp_path)


def test_an_output_shown_is_compared_with_what_the_commands_print(tmp_path):
    document = tmp_path / "guide.md"
    folder = tmp_path / "run"
    folder.mkdir()
    document.write_text("```sh\nladder sim conveyor.ladder --for 1s --set Xstart=1 --watch Rrun\n```\n\n"
                        "<!-- doc-test: output -->\n```text\n0 Rrun 0\n```\n", encoding="utf-8")
    with pytest.raises(pytest.fail.Exception) as failure:
        _run_document(document, folder, {"fast"})
    assert str(failure.value).startswith("guide.md:7: the output shown is not what the commands above print")
    assert "-0 Rrun 0\n+0 Rrun 1" in str(failure.value)
