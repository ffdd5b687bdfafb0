"""Fast checks of the editor clients' static files (no editor, no Node): the VS Code manifest,
the grammars against their generator, the file-type rules. The real-editor tests are slow
(tests/test_editor_neovim.py, tests/test_editor_vscode.py)."""

from __future__ import annotations

import importlib.util
import json
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
EXT = REPO / "vscode-extension"
MANIFEST = json.loads((EXT / "package.json").read_text())


def test_engine_within_code_server_4_100():
    engine = MANIFEST["engines"]["vscode"].lstrip("^~>=")
    assert tuple(int(p) for p in engine.split(".")[:2]) <= (1, 100)
    # the API types must not be newer than the engine, or the code may use what 1.100 lacks
    assert MANIFEST["devDependencies"]["@types/vscode"].lstrip("^~") == engine


def test_commands_are_declared_and_do_not_clash_with_the_servers():
    contributes = MANIFEST["contributes"]
    declared = {c["command"] for c in contributes["commands"]}
    # vscode-languageclient registers the server's own commands (ladder.*) itself
    assert not any(c.startswith("ladder.") for c in declared)
    used = {k["command"] for k in contributes["keybindings"]}
    for entries in contributes["menus"].values():
        used |= {e["command"] for e in entries}
    assert used <= declared
    source = (EXT / "src" / "extension.ts").read_text()
    registered = set(re.findall(r"reg\('([\w.]+)'", source))
    assert declared == registered


def test_server_settings_are_contributed():
    props = MANIFEST["contributes"]["configuration"]["properties"]
    for key in ("ladder.compileOnSave", "ladder.encoding", "ladder.diagnosticsDelayMs",
                "ladder.server.command", "ladder.server.pythonPath"):
        assert key in props


@pytest.mark.parametrize("first_line, language", [
    ("LDmicro export text.", "ladder"),
    ("LDmicro0.2", "ldmicro"),
    ("LDmicro0.1", "ldmicro"),
    ("OUTPUT_FORMAT(\"elf32-avr\")", None),
    ("/* linker script */", None),
])
def test_first_line_rules(first_line, language):
    found = [lang["id"] for lang in MANIFEST["contributes"]["languages"]
             if lang.get("firstLine") and re.search(lang["firstLine"], first_line)]
    assert found == ([language] if language else [])


def test_ld_is_not_claimed_by_extension():
    for lang in MANIFEST["contributes"]["languages"]:
        assert ".ld" not in lang.get("extensions", []) and ".txt" not in lang.get("extensions", [])


def test_grammars_match_their_generator(tmp_path, monkeypatch):
    spec = importlib.util.spec_from_file_location("gen_grammar", EXT / "scripts" / "gen_grammar.py")
    source = (EXT / "scripts" / "gen_grammar.py").read_text()
    # run the generator into a temporary folder
    out = tmp_path / "syntaxes"
    out.mkdir()
    code = source.replace('os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "syntaxes", '
                          '"%s.tmLanguage.json" % fn)', f'os.path.join({str(out)!r}, "%s.tmLanguage.json" % fn)')
    assert code != source
    exec(compile(code, str(spec.origin), "exec"), {"__name__": "gen_grammar", "__file__": str(spec.origin)})
    for name in ("ladder", "ldmicro"):
        assert (out / f"{name}.tmLanguage.json").read_text() == (EXT / "syntaxes" / f"{name}.tmLanguage.json").read_text(), \
            f"syntaxes/{name}.tmLanguage.json is stale: run python3 scripts/gen_grammar.py"


def test_grammar_regexes_compile():
    """Oniguruma is not Python's re, but the grammars use only what both read the same way."""
    def walk(node):
        if isinstance(node, dict):
            for key in ("match", "begin", "end"):
                if key in node:
                    re.compile(node[key])
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)
    for name in ("ladder", "ldmicro"):
        walk(json.loads((EXT / "syntaxes" / f"{name}.tmLanguage.json").read_text()))


def test_neovim_ftdetect_and_module_present():
    ftdetect = (REPO / "editors" / "neovim" / "ftdetect" / "ladder.vim").read_text()
    assert "'^LDmicro export text'" in ftdetect and "*.ld" in ftdetect
    module = (REPO / "editors" / "neovim" / "lua" / "ladder" / "init.lua").read_text()
    for command in ("LadderSimStart", "LadderSimStop", "LadderSimStep", "LadderSimToggle", "LadderSimSet",
                    "LadderSimRunFor", "LadderSimRunUntil", "LadderSimRealtime", "LadderSimReset"):
        assert f"'{command}'" in module
    assert "ladder/simulationState" in module
