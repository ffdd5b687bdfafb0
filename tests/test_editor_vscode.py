"""The VS Code extension in a real VS Code: code-server 4.100.3 (VS Code 1.100.3) driven by
Chromium through playwright-core (tests/e2e/vscode_e2e.js).

The extension runs the language server it carries (bundled/), with the Python it finds: the
session below gives code-server a PATH on which the only Python is a fresh, bare virtual
environment's, without textladder, and no `ladder`. It ends with a program that sends on the
UART (TICKER), whose messages the watch view lists.

Slow: runs in the editor step of .ci/run (`pytest -m slow tests/test_editor_*.py`), which installs
the npm packages first. Leaves screenshots in build/editor-e2e/ (LADDER_E2E_OUT).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "e2e"))
import editor_env as env  # noqa: E402

pytestmark = pytest.mark.slow

# Sends "tick N\r\n" (N in three digits) every 220 ms: a FORMATTED_STRING on Rosc, a 200 ms oscillator
TICKER = (
    env.HEADER
    + "LADDER DIAGRAM:\n"
    "    ||                                                   ||\n"
    "    ||      Rosc             Tosc             Rosc       ||\n"
    "0001||-------] [---------[TON 200 ms]----------(/)-------||\n"
    "    ||                                                   ||\n"
    "    ||                                                   ||\n"
    "    ||      Rosc            _     _     {ADD      cnt:=} ||\n"
    "0002||-------] [---------[_/ OSR_/ \\_]--{cnt     +    1}-||\n"
    "    ||                                                   ||\n"
    "    ||                                                   ||\n"
    "    ||      Rosc                      cnt                ||\n"
    '0003||-------] [----------------{"tick \\3\\r\\n"}----------||\n'
    "    ||                                                   ||\n"
    "    ||                                                   ||\n"
    "    ||                                                   ||\n"
    "   3||------[END]----------------------------------------||\n"
    "    ||                                                   ||\n"
    "    ||                                                   ||\n"
    "\n"
    + env.IO_TABLE
)


def _npm(*args: str, cwd: Path, timeout: int = 300) -> subprocess.CompletedProcess:
    return subprocess.run(["npm", *args], cwd=cwd, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def vsix() -> Path:
    return env.package_vsix()


def test_grammar_tests_pass():
    """vscode-tmgrammar-test over vscode-extension/test/grammar (also part of `npm test`)."""
    env.require_extension_packages()
    out = _npm("run", "test:grammar", cwd=env.EXTENSION)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "failed" not in out.stdout
    assert out.stdout.count("run successfuly") >= 3, out.stdout


def test_python_lookup_unit_tests_pass():
    """The Python lookup's unit tests (vscode-extension/test/unit, node's test runner; also part of `npm test`):
    the Windows cases (py launcher, .exe, backslashes, spaces, the Store's alias) run on any machine."""
    env.require_extension_packages()
    out = _npm("run", "test:unit", cwd=env.EXTENSION)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "# fail 0" in out.stdout and re.search(r"^# pass [1-9]", out.stdout, re.M), out.stdout


def test_vsix_contents(vsix):
    with zipfile.ZipFile(vsix) as z:
        names = set(z.namelist())
        manifest = json.loads(z.read("extension/package.json"))
    assert {"extension/out/extension.js", "extension/syntaxes/ladder.tmLanguage.json",
            "extension/syntaxes/ldmicro.tmLanguage.json", "extension/package.json",
            "extension/bundled/tool/lsp_server.py"} <= names
    assert not any(n.startswith("extension/node_modules/") for n in names), "the bundle needs no node_modules"
    assert not any(n.startswith("extension/src/") for n in names)
    # the engine must stay at or below the VS Code of code-server 4.100.3
    engine = manifest["engines"]["vscode"].lstrip("^~>=")
    major, minor = (int(p) for p in engine.split(".")[:2])
    assert (major, minor) <= (1, 100)


def test_vsix_carries_the_server(vsix):
    """textladder (with its data files) and its pure-Python dependencies, without caches or tests."""
    project = tomllib.loads((env.REPO / "pyproject.toml").read_text())["project"]
    with zipfile.ZipFile(vsix) as z:
        names = z.namelist()
        python = json.loads(z.read("extension/bundled/tool/python.json"))
    libs = {n.split("/")[3] for n in names if n.startswith("extension/bundled/libs/")}
    assert {"lang", "compiler", "ide", "lsp", "ladder", "lark", "intelhex", "pygls", "lsprotocol", "cattrs",
            "attrs"} <= libs
    assert f"textladder-{project['version']}.dist-info" in libs
    # the data files the wheel ships
    assert any(n.startswith("extension/bundled/libs/lang/devices/") and n.endswith(".json") for n in names)
    assert "extension/bundled/libs/compiler/c/boards.json" in names
    assert not any("__pycache__" in n or n.endswith((".pyc", ".so", ".pyd")) for n in names)
    assert not any("/tests/" in n or (n.endswith("/test.py") and "/ladder/commands/" not in n) for n in names)
    assert not any(n.endswith(("/RECORD", "/INSTALLER", "/direct_url.json")) for n in names)
    assert python["requiresPython"] == project["requires-python"]
    # the desktop's part: the browser entry's (out/web/, tests/test_editor_vscode_web.py) is Pyodide's
    with zipfile.ZipFile(vsix) as z:
        desktop = sum(i.compress_size for i in z.infolist() if not i.filename.startswith("extension/out/web/"))
    assert desktop < 2_000_000


def _node_only(root: Path) -> str:
    """A folder with node in it, and nothing else: code-server is a node script."""
    nodes = root / "node"
    nodes.mkdir()
    node = env.which("node")
    assert node is not None
    (nodes / "node").symlink_to(node)
    return str(nodes)


@pytest.fixture(scope="module")
def bare_path(tmp_path_factory) -> str:
    """A PATH whose only Python is a fresh virtual environment's, with nothing installed, and no `ladder`."""
    root = tmp_path_factory.mktemp("bare")
    venv = root / "venv"
    made = subprocess.run([getattr(sys, "_base_executable", sys.executable), "-m", "venv", "--without-pip", str(venv)],
                          capture_output=True, text=True, timeout=60)
    assert made.returncode == 0, made.stderr
    path = os.pathsep.join([str(venv / "bin"), _node_only(root)])
    python = shutil.which("python3", path=path)
    assert python == str(venv / "bin" / "python3")
    imported = subprocess.run([python, "-c", "import lang, pygls"], capture_output=True, text=True, cwd=root,
                              env={"PATH": path})
    assert imported.returncode != 0 and "ModuleNotFoundError" in imported.stderr
    assert shutil.which("ladder", path=path) is None and shutil.which("python", path=path) is not None
    return path


@pytest.fixture(scope="module")
def code_server_run(vsix, bare_path, tmp_path_factory):
    """One code-server session (tests/e2e/vscode_e2e.js); the tests below read its results."""
    env.require((env.E2E / "node_modules" / ".bin" / "code-server").exists(),
                "tests/e2e/node_modules is missing (npm ci in tests/e2e/)")
    env.require(Path("/usr/bin/chromium").exists() or env.which("chromium") is not None,
                "Chromium is not installed (apt-get install chromium)")
    env.require_server()
    env.require_feature("diagnostics")

    ws = tmp_path_factory.mktemp("vscode") / "workspace"
    ws.mkdir()
    bad = ws / "lamp.ladder"
    bad.write_text(env.LAMP_BAD)
    sim = ws / "conveyor.ladder"
    shutil.copy(env.REPO / "examples" / "conveyor.ladder", sim)
    (ws / "program.ld").write_text("LDmicro0.2\nMICRO=Atmel AVR ATmega328 28-PDIP\n\nPROGRAM\nRUNG\n"
                                   "  CONTACTS Xa 0 0\n  COIL Yb 0 0 0 0\nEND\n")
    (ws / "linker.ld").write_text('OUTPUT_FORMAT("elf32-avr")\nSECTIONS\n{\n  .text : { *(.text) }\n}\n')
    (ws / "export.txt").write_text(env.lamp_fixed())
    (ws / "notes.txt").write_text("LDmicro is a ladder logic compiler.\n")
    ticker = ws / "ticker.ladder"
    ticker.write_text(TICKER)
    shutil.rmtree(env.OUT, ignore_errors=True)  # no screenshot of an earlier run
    env.OUT.mkdir(parents=True, exist_ok=True)
    return _vscode_e2e(vsix, ws, bad, sim, env.OUT, bare_path, "--detect", "program.ld,linker.ld,export.txt,notes.txt",
                       "--uart", str(ticker))


def _vscode_e2e(vsix: Path, ws: Path, bad: Path, sim: Path, out: Path, path: str, *more: str) -> dict:
    """One code-server session of tests/e2e/vscode_e2e.js, with `path` as its PATH; its result."""
    cmd = [env.which("node"), str(env.E2E / "vscode_e2e.js"), "--vsix", str(vsix), "--workspace", str(ws),
           "--bad", str(bad), "--sim", str(sim), "--out", str(out), *more]
    # VSCODE_CLI: the environment comes from a shell already, so the server does not replace it with
    # a login shell's (whose PATH, from /etc/profile, would bring back /usr/bin's Python)
    return env.driver_result(cmd, {**os.environ, "PATH": path, "VSCODE_CLI": "1"})


def test_the_bundled_server_runs_with_the_python_on_path(code_server_run, bare_path):
    """The "Ladder" output channel names the server started: the bundled one, by the bare venv's Python."""
    logs = list((env.OUT / "code-server-logs").rglob("*Ladder.log"))
    assert logs, "no log of the Ladder output channel"
    text = "\n".join(log.read_text() for log in logs)
    python = shutil.which("python3", path=bare_path)
    assert f"starting the language server: {python} " in text, text
    assert "bundled/tool/lsp_server.py (the bundled server, Python 3." in text and "from PATH)" in text, text


def test_problems_panel(code_server_run):
    # the file is recognised as ladder
    assert "Ladder" in code_server_run["languageId"]
    # Problems panel: the LD102 diagnostic of lamp.ladder, on the line where Xlamp is drawn
    problems = "\n".join(code_server_run["problems"])
    assert "LD102" in problems and env.BAD_NAME in problems
    assert f"Ln {env.BAD_LINE + 1}," in problems
    assert Path(code_server_run["screenshot"]).exists()


def test_languages_by_first_line(code_server_run):
    langs = code_server_run["languages"]
    assert langs["program.ld"] == "LDmicro program"
    assert langs["export.txt"] == "Ladder (LDmicro text)"
    assert "Ladder" not in langs["linker.ld"] and "LDmicro" not in langs["linker.ld"]
    assert langs["notes.txt"] == "Plain Text"


def test_hover(code_server_run):
    env.require_feature("hover")
    assert "Xstop" in code_server_run["hover"]


def test_simulation(code_server_run):
    env.require_feature("simulation")
    # F10 ran a scan; the status bar shows it
    assert "scan" in code_server_run["statusBar"]
    # elements painted red after Xstart was toggled on with its code lens: a contact and a coil
    energized = code_server_run["energized"]
    assert any("[" in t for t in energized), energized
    assert any("(" in t for t in energized), energized
    # the live values come after the end of their line, and every right rail stays in one column
    live = code_server_run["liveValues"]
    assert len(live["rails"]) == 1 and "Xstart=1" in live["hint"], live
    # the watch view lists the inputs with their values
    assert any(row.startswith("Xstart") for row in code_server_run["watch"]), code_server_run["watch"]
    assert code_server_run["screenshot"].endswith("vscode-simulation.png")
    assert "Toggle Xstop" in code_server_run["hoverSim"]


def test_the_watch_view_shows_what_the_uart_sent(code_server_run, tmp_path):
    """TICKER run for a second ("Run Simulation For…"): the watch view counts the bytes sent and lists
    the messages as `ladder sim --watch uart` prints them, each with its time, the latest first."""
    env.require_feature("simulation")
    uart = code_server_run["uart"]
    assert "1.010 s" in uart["statusBar"], uart
    rows = uart["rows"]
    at = next((i for i, row in enumerate(rows) if row["label"].startswith("UART sent")), None)
    assert at is not None, rows
    assert rows[at]["label"] == "UART sent (50 bytes)"
    messages = rows[at + 1:]
    assert all(row["level"] == rows[at]["level"] + 1 for row in messages), rows
    assert [(row["description"], row["label"]) for row in messages[:2]] == [
        ("880 ms", '"tick   5\\r\\n"'), ("660 ms", '"tick   4\\r\\n"')]
    program = tmp_path / "ticker.ladder"
    program.write_text(TICKER)
    sim = subprocess.run([sys.executable, "-m", "ladder", "sim", str(program), "--for", "1s", "--watch", "uart"],
                         capture_output=True, text=True, timeout=60)
    assert sim.returncode == 0, sim.stderr
    printed = [line.split(" uart ") for line in sim.stdout.splitlines()]
    assert [(row["description"], row["label"]) for row in messages] == [(f"{t} ms", text) for t, text in printed[::-1]]


def test_without_python_a_notification_says_what_to_install(code_server_run, vsix, tmp_path_factory):
    """No Python on PATH at all (and no setting): opening a program tells the user to install one."""
    root = tmp_path_factory.mktemp("no-python")
    path = _node_only(root)
    assert shutil.which("python3", path=path) is None and shutil.which("python", path=path) is None
    ws = root / "workspace"
    ws.mkdir()
    bad = ws / "lamp.ladder"
    bad.write_text(env.LAMP_BAD)
    result = _vscode_e2e(vsix, ws, bad, bad, env.OUT / "no-python", path, "--no-python")
    minimum = tomllib.loads((env.REPO / "pyproject.toml").read_text())["project"]["requires-python"].lstrip(">=")
    notification = result["notification"]
    assert f"The ladder language server needs Python {minimum} or newer" in notification, notification
    assert "Neither python3 nor python is on PATH" in notification
    assert "https://www.python.org/downloads/" in notification
    assert "Download Python" in notification and "Open Settings" in notification, notification
