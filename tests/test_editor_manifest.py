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
    # both entries (desktop and browser) register their commands through the shared activate.ts
    source = "\n".join(p.read_text() for p in (EXT / "src").rglob("*.ts"))
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


def _bundle_module():
    spec = importlib.util.spec_from_file_location("bundle", EXT / "scripts" / "bundle.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_packaging_bundles_the_server_first():
    assert MANIFEST["scripts"]["vscode:prepublish"].startswith("npm run bundle && ")
    ignore = (EXT / ".vscodeignore").read_text().splitlines()
    assert {"!bundled/tool/lsp_server.py", "!bundled/tool/python.json", "!bundled/libs/**", "**/__pycache__/**"} <= set(ignore)


def test_bundle_reads_the_minimum_python():
    bundle = _bundle_module()
    assert bundle.minimum_python(">=3.11") == "3.11"
    assert bundle.minimum_python(">= 3.12, <4") == "3.12"
    with pytest.raises(bundle.BundleError, match=r"requires-python '<4' names no lower bound"):
        bundle.minimum_python("<4")


def _wheel(libs: Path, name: str, tags: str, purelib: str = "true") -> None:
    info = libs / f"{name}.dist-info"
    info.mkdir(parents=True)
    (info / "WHEEL").write_text(f"Wheel-Version: 1.0\nRoot-Is-Purelib: {purelib}\n{tags}\n")


def test_bundle_refuses_compiled_code(tmp_path):
    bundle = _bundle_module()
    _wheel(tmp_path, "lark-1.3.1", "Tag: py3-none-any")
    bundle.check_pure(tmp_path)
    _wheel(tmp_path, "rpds_py-0.20.0", "Tag: cp311-cp311-win_amd64", purelib="false")
    with pytest.raises(bundle.BundleError, match=r"rpds_py-0.20.0.dist-info is not a pure-Python wheel \(cp311-cp311-win_amd64\)"):
        bundle.check_pure(tmp_path)
    (tmp_path / "rpds_py-0.20.0.dist-info").joinpath("WHEEL").write_text("Root-Is-Purelib: true\nTag: py3-none-any\n")
    (tmp_path / "rpds").mkdir()
    (tmp_path / "rpds" / "rpds.cp311-win_amd64.pyd").write_bytes(b"MZ")
    with pytest.raises(bundle.BundleError, match=r"compiled code in the bundle: rpds/rpds.cp311-win_amd64.pyd"):
        bundle.check_pure(tmp_path)


def test_bundle_prunes_what_the_server_never_reads(tmp_path):
    bundle = _bundle_module()
    files = {
        "bin/ladder": "", "lark/__init__.py": "", "lark/__pyinstaller/hook.py": "", "lark/grammars/common.lark": "",
        "intelhex/__init__.py": "", "intelhex/test.py": "", "cattrs/tests/test_x.py": "", "cattrs/__pycache__/x.pyc": "",
        "ladder/commands/test.py": "", "lang/__pycache__/model.cpython-311.pyc": "",
        "pygls-2.1.1.dist-info/METADATA": "Name: pygls\nVersion: 2.1.1\n\n# pygls\n\nThe long README\n",
        "pygls-2.1.1.dist-info/RECORD": "", "pygls-2.1.1.dist-info/INSTALLER": "",
        "pygls-2.1.1.dist-info/licenses/LICENSE.txt": "Apache", "intelhex-2.3.0.dist-info/LICENSE.txt": "BSD",
        "intelhex-2.3.0.dist-info/top_level.txt": "intelhex",
    }
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    bundle.prune(tmp_path, {"ladder", "lang"})
    left = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    assert left == ["intelhex-2.3.0.dist-info/LICENSE.txt", "intelhex/__init__.py", "ladder/commands/test.py",
                    "lark/__init__.py", "lark/grammars/common.lark", "pygls-2.1.1.dist-info/METADATA",
                    "pygls-2.1.1.dist-info/licenses/LICENSE.txt"]
    assert (tmp_path / "pygls-2.1.1.dist-info" / "METADATA").read_text() == "Name: pygls\nVersion: 2.1.1\n"


def test_bundle_reports_a_pyproject_it_cannot_use(tmp_path, capsys, monkeypatch):
    bundle = _bundle_module()
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "textladder"\nversion = "0.1.0"\n')
    libs = tmp_path / "vscode-extension" / "bundled" / "libs"
    libs.mkdir(parents=True)
    (libs / "kept.py").write_text("")
    monkeypatch.setattr(bundle, "REPO", tmp_path)
    monkeypatch.setattr(bundle, "LIBS", libs)
    assert bundle.main() == 1
    assert capsys.readouterr().err == "bundle: pyproject.toml has no 'requires-python'\n"
    assert (libs / "kept.py").exists()  # an earlier bundle is left as it was
