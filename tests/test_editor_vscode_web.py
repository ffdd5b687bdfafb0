"""The VS Code extension's browser entry (what VS Code for the Web and vscode.dev run) in a real VS
Code: code-server 4.100.3 (VS Code 1.100.3) with the extension forced into the web worker
extension host by the user setting `"remote.extensionKind": {"textladder.textladder": ["web"]}`,
driven by Chromium through playwright-core (tests/e2e/vscode_web_e2e.js). Its language server is
the one on Pyodide in a Web Worker (docs/browser.md); nothing of Python runs on the machine for it.

Slow: runs in the editor step of .ci/run. Leaves screenshots in build/editor-e2e/web-extension/.
"""

from __future__ import annotations

import json
import shutil
import sys
import zipfile
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "e2e"))
import editor_env as env  # noqa: E402

pytestmark = pytest.mark.slow

OUT = env.OUT / "web-extension"
WEB_FILES = ("worker.js", "site.zip", "pyodide/pyodide.asm.wasm", "pyodide/python_stdlib.zip",
             "pyodide/pyodide-lock.json")


@pytest.fixture(scope="module")
def vsix() -> Path:
    return env.package_vsix()


def test_the_vsix_carries_the_browser_entry_and_pyodide(vsix):
    with zipfile.ZipFile(vsix) as z:
        names = set(z.namelist())
        manifest = json.loads(z.read("extension/package.json"))
        site = zipfile.ZipFile(z.open("extension/out/web/site.zip"))
        modules = set(site.namelist())
    assert manifest["browser"] == "./out/web/extension.js" and manifest["main"] == "./out/extension.js"
    assert {"extension/out/web/extension.js", *(f"extension/out/web/{name}" for name in WEB_FILES)} <= names
    # the server of the browser, precompiled; the command line and the native simulators' runners left out
    assert {"lsp/worker.pyc", "lsp/server.pyc", "compiler/c/boards.json"} <= modules
    assert not any(m.startswith(("ladder/", "compiler/run/")) for m in modules)
    size = vsix.stat().st_size
    print(f"textladder.vsix: {size / 1e6:.2f} MB")
    assert size < 12_000_000


@pytest.fixture(scope="module")
def web_run(vsix, tmp_path_factory) -> dict:
    """One code-server session of tests/e2e/vscode_web_e2e.js; the tests below read its result."""
    env.require((env.E2E / "node_modules" / ".bin" / "code-server").exists(),
                "tests/e2e/node_modules is missing (npm ci in tests/e2e/)")
    env.require(Path("/usr/bin/chromium").exists() or env.which("chromium") is not None,
                "Chromium is not installed (apt-get install chromium)")
    ws = tmp_path_factory.mktemp("vscode-web") / "workspace"
    ws.mkdir()
    (ws / "lamp.ladder").write_text(env.LAMP_BAD_RENAMED_FIXES)
    (ws / "messy.ladder").write_text(env.MESSY)
    shutil.copy(env.REPO / "examples" / "conveyor.ladder", ws / "conveyor.ladder")
    shutil.rmtree(OUT, ignore_errors=True)
    OUT.mkdir(parents=True)
    cmd = [env.which("node"), str(env.E2E / "vscode_web_e2e.js"), "--vsix", str(vsix), "--workspace", str(ws),
           "--bad", "lamp.ladder", "--fmt", "messy.ladder", "--sim", "conveyor.ladder", "--out", str(OUT)]
    return {**env.driver_result(cmd), "workspace": ws}


def test_the_browser_entry_runs_in_the_web_worker_extension_host(web_run):
    """Only the browser entry names this server; the Node extension host never activates the extension."""
    assert ("starting the language server: textladder on Pyodide in a Web Worker "
            "(the browser entry of the extension)") in web_run["output"]
    assert "ladder: started {" in web_run["output"]  # the worker's own start-up line (web/src/serve.js)
    remote = list((OUT / "code-server-logs").rglob("remoteexthost.log"))
    assert remote, "no log of code-server's Node extension host"
    # the host lists every installed extension at its start; it activates only those it runs
    assert not any("_doActivateExtension textladder.textladder" in log.read_text() for log in remote)


def test_a_diagnostic_appears_and_goes_when_fixed(web_run):
    problems = "\n".join(web_run["problems"])
    assert "LD102" in problems and env.BAD_NAME in problems and f"Ln {env.BAD_LINE + 1}," in problems
    assert "No problems have been detected" in web_run["fixed"]


def test_build_hex_writes_an_image_that_runs_in_simavr(web_run):
    """Build HEX on the fixed program: the image, written beside it, lights Ylamp once Xstart is high."""
    assert "wrote lamp.hex" in web_run["built"], web_run["built"]
    assert env.lamp_in_simavr(web_run["workspace"] / "lamp.hex") == [0, 0, 1, 1, 1]


def test_hover(web_run):
    assert web_run["hover"].startswith("Xstop: a digital input pin")


def test_completion_offers_the_other_inputs_on_a_contact(web_run):
    """On the contact Xstop: the program's X names (VS Code keeps those that match the word typed)."""
    assert any(row.startswith("Xstart") for row in web_run["completion"]), web_run["completion"]


def test_format_document_gives_what_ladder_fmt_gives(web_run):
    saved = (web_run["workspace"] / "messy.ladder").read_text()
    assert saved != env.MESSY and saved == env.ladder("fmt", "-", text=env.MESSY)


def test_a_simulation_paints_the_coil_of_the_toggled_input(web_run):
    assert "scan" in web_run["statusBar"]
    assert "( )" in web_run["energized"] and "] [" in web_run["energized"]


def test_conversion_to_ld_writes_the_file_beside_the_program(web_run, tmp_path):
    """Written through the workspace's file system; LDmicro's format as `ladder convert` writes it."""
    assert "Ladder: wrote conveyor.ld" in web_run["converted"]
    written = (web_run["workspace"] / "conveyor.ld").read_bytes()
    native = tmp_path / "conveyor.ld"
    env.ladder("convert", str(env.REPO / "examples" / "conveyor.ladder"), str(native))
    assert written == native.read_bytes()
