"""Shared set-up of the real-editor tests (tests/test_editor_*.py): paths, programs, the server check.

The tests need tools that the fast suite does not: Neovim (Debian), Node with the npm packages of
vscode-extension/ and tests/e2e/ (code-server, playwright-core), Chromium (Debian). `.ci/run`
installs all of them before its editor step. Outside CI a missing tool skips the test; in CI
(`CI` set) it fails, so that a missing install step cannot pass unnoticed.
"""

from __future__ import annotations

import functools
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from compiler.run.record import Event, record_pins

REPO = Path(__file__).resolve().parents[2]
E2E = REPO / "tests" / "e2e"
EXTENSION = REPO / "vscode-extension"
NEOVIM_PLUGIN = REPO / "editors" / "neovim"
OUT = Path(os.environ.get("LADDER_E2E_OUT", REPO / "build" / "editor-e2e"))

# The Python that runs `-m ladder lsp`. LADDER_LSP_PYTHON replaces it (e.g. with a stand-in
# server while developing the clients).
SERVER_PYTHON = os.environ.get("LADDER_LSP_PYTHON", sys.executable)

HEADER = "LDmicro export text.\nfor 'Atmel AVR ATmega328 28-PDIP', 16 MHz crystal, 10.000 ms cycle time\n\n"

IO_TABLE = (
    "I/O ASSIGNMENT:\n"
    "  Name                       | Type               | Pin | Port | Pin name\n"
    " ----------------------------+--------------------+-----+------+-----------\n"
)

# rung 1: a coil on the X input Xlamp (LD102, reported on line 6, where the name is drawn)
LAMP_BAD = (
    HEADER
    + "LADDER DIAGRAM:\n"
    "    ||                                                                    ||\n"
    "    ||     Xstart                                              Xlamp      ||\n"
    "0001||-------] [------------------------------------------------( )-------||\n"
    "    ||                                                                    ||\n"
    "    ||                                                                    ||\n"
    "    ||                                                                    ||\n"
    "   1||------[END]---------------------------------------------------------||\n"
    "    ||                                                                    ||\n"
    "    ||                                                                    ||\n"
    "\n"
    + IO_TABLE
    + "  Xstart                     | digital in         |   4 | PD2   | PD2 PCINT18/INT0\n"
    "  Xlamp                      | digital in         |   5 | PD3   | PD3 PCINT19/OC2B/INT1\n"
)
BAD_LINE = 5  # 0-based line of "Xlamp" on the name line
BAD_NAME = "Xlamp"


def lamp_fixed(text: str = LAMP_BAD) -> str:
    """The same program with the coil on an output: no diagnostic."""
    return text.replace("Xlamp                      | digital in  ", "Ylamp                      | digital out ").replace(
        "Xlamp", "Ylamp")


# LAMP_BAD with Xlamp listed as an output: renaming it Ylamp everywhere (Replace All) fixes it
LAMP_BAD_RENAMED_FIXES = LAMP_BAD.replace("Xlamp                      | digital in ",
                                          "Xlamp                      | digital out")
# formatting renumbers the rung and adds the VAR LIST section
MESSY = lamp_fixed().replace("0001||", "0009||")


def ladder(*args: str, text: str | None = None) -> str:
    """`ladder ARGS` of this checkout (the native reference for what an editor shows): its standard
    output, the test failing on an error."""
    done = subprocess.run([sys.executable, "-m", "ladder", *args], input=text, capture_output=True, text=True,
                          timeout=60, cwd=REPO)
    assert done.returncode == 0, done.stderr
    return done.stdout


def lamp_in_simavr(hex_path: Path) -> list[int]:
    """The fixed lamp program's HEX run in simavr: Ylamp after each of five scans, Xstart low for
    two, then high."""
    events = [Event(0, "Xstart", 0), Event(2, "Xstart", 1)]
    recording = record_pins(hex_path, "atmega328p", 16_000_000, 10_000, events, 5, {"Xstart": "PD2", "Ylamp": "PD3"})
    return [row["Ylamp"] for row in recording.rows]


def require(condition: bool, what: str) -> None:
    if condition:
        return
    if os.environ.get("CI"):
        pytest.fail(f"{what} (.ci/run installs it before the editor step)")
    pytest.skip(what)


def require_server() -> None:
    """`<python> -m ladder lsp` must start and answer `initialize`."""
    caps, log = _initialize()
    if caps is None:
        pytest.fail(f"`ladder lsp` did not answer initialize:\n{log}")


@functools.cache
def _initialize() -> tuple[dict | None, str]:
    """Starts the server, sends `initialize`, returns (capabilities or None, log)."""
    try:
        proc = subprocess.Popen([SERVER_PYTHON, "-m", "ladder", "lsp"], stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=REPO)
    except OSError as exc:
        return None, str(exc)

    def send(msg: dict) -> None:
        body = json.dumps(msg).encode()
        proc.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        proc.stdin.flush()

    def receive(deadline: float) -> dict | None:
        headers = {}
        while True:
            if time.monotonic() > deadline:
                return None
            line = proc.stdout.readline()
            if not line:
                return None
            line = line.strip()
            if not line:
                break
            key, _, value = line.decode().partition(":")
            headers[key.strip().lower()] = value.strip()
        return json.loads(proc.stdout.read(int(headers["content-length"])))

    caps = None
    try:
        send({"jsonrpc": "2.0", "id": 1, "method": "initialize",
              "params": {"processId": os.getpid(), "rootUri": None, "capabilities": {}}})
        deadline = time.monotonic() + 30
        while (msg := receive(deadline)) is not None:
            if msg.get("id") == 1:
                caps = (msg.get("result") or {}).get("capabilities")
                break
        if caps is not None:
            send({"jsonrpc": "2.0", "id": 2, "method": "shutdown"})
            send({"jsonrpc": "2.0", "method": "exit"})
    except (OSError, ValueError, KeyError):
        caps = None
    finally:
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    return caps, proc.stderr.read().decode(errors="replace")[-2000:]


def server_capabilities() -> dict | None:
    return _initialize()[0]


def server_commands() -> set[str]:
    caps = server_capabilities() or {}
    return set((caps.get("executeCommandProvider") or {}).get("commands") or [])


def missing_features() -> list[str]:
    """The features the editor tests use that the server does not advertise."""
    caps = server_capabilities() or {}
    missing = [name for name, key in (("diagnostics", "textDocumentSync"), ("hover", "hoverProvider"),
                                      ("formatting", "documentFormattingProvider")) if not caps.get(key)]
    needed = {"ladder.sim.start", "ladder.sim.step", "ladder.sim.toggle", "ladder.sim.stop"}
    if not needed <= server_commands():
        missing.append("simulation")
    return missing


def require_feature(name: str) -> None:
    if name in missing_features():
        pytest.fail(f"the server does not advertise {name}")


def driver_result(cmd: list[str], environ: dict[str, str] | None = None) -> dict:
    """Runs a Node driver of tests/e2e and returns the result it prints as its last JSON line,
    failing with the driver's error, screenshot and log when a step failed."""
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=240, env=environ)
    sys.stderr.write(proc.stderr)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("{")]
    assert lines, f"no result from {Path(cmd[1]).name} (exit {proc.returncode}):\n{proc.stdout}\n{proc.stderr}"
    result = json.loads(lines[-1])
    print(json.dumps(result.get("timings")))
    assert result["ok"], f"{result.get('error')}\nscreenshot: {result.get('screenshot')}\nlog: {proc.stderr[-3000:]}"
    return result


def which(name: str) -> str | None:
    return shutil.which(name)


def require_extension_packages() -> None:
    require(which("npm") is not None, "npm is not installed")
    require((EXTENSION / "node_modules" / ".bin" / "vsce").exists(),
            "vscode-extension/node_modules is missing (npm ci in vscode-extension/)")


@functools.cache
def package_vsix() -> Path:
    """vscode-extension/textladder.vsix, packaged once a session (`npm run package`: the desktop
    server in bundled/ and the browser entry in out/web/); the tests of both read it."""
    require_extension_packages()
    # `npm run bundle` and the browser build run python3 with pip: this Python comes first on PATH
    path = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    out = subprocess.run(["npm", "run", "package"], cwd=EXTENSION, capture_output=True, text=True, timeout=300,
                         env={**os.environ, "PATH": path, "PYTHON": sys.executable})
    assert out.returncode == 0, out.stdout + out.stderr
    vsix = EXTENSION / "textladder.vsix"
    assert vsix.exists()
    return vsix
