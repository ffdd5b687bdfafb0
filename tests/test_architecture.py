"""The layering (docs/architecture.md), checked on the imports of every
module: `lang` never imports the compiler; a back end sees `ir.Code` and a
`Machine` (the C back end a `Unit`), never the ladder program, the checks or
the front end; only the language server knows the protocol."""

from __future__ import annotations

import ast
from pathlib import Path

from compiler.backend import BACKENDS
from lang.families import FAMILIES

ROOT = Path(__file__).resolve().parents[1]
NOT_BACK_ENDS = {"run"}  # the compiler's subpackages that are not a family's back end


def _imports(path: Path, package: str) -> set[str]:
    """Absolute names of the modules a file imports (relative ones resolved)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[:len(package.split(".")) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            found.add(module)
            found.update(f"{module}.{alias.name}" for alias in node.names)
    return found


def _package_of(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts if path.name == "__init__.py" else parts[:-1]).removesuffix(".__init__")


def _offenders(folder: Path, forbidden: tuple[str, ...]) -> dict[str, list[str]]:
    found = {}
    for path in sorted(folder.rglob("*.py")):
        bad = sorted(m for m in _imports(path, _package_of(path))
                     if any(m == f or m.startswith(f + ".") for f in forbidden))
        if bad:
            found[str(path.relative_to(ROOT))] = bad
    return found


def back_end_folders() -> list[Path]:
    return [path.parent for path in sorted((ROOT / "compiler").glob("*/__init__.py"))
            if path.parent.name not in NOT_BACK_ENDS]


# each layer and the layers above it, which it must never import (docs/architecture.md)
LAYERS = {
    "lang": ("compiler", "ide", "lsp", "ladder"),
    "compiler": ("ide", "lsp", "ladder"),
    "ide": ("compiler", "lsp", "ladder"),
    "lsp": ("ladder",),
}


def test_each_layer_imports_only_the_layers_below_it():
    for layer, above in LAYERS.items():
        assert _offenders(ROOT / layer, above) == {}, layer


def test_only_the_language_server_knows_the_protocol():
    # rust-analyzer's rule: one package speaks LSP; what an editor offers is ide/'s, on plain values
    for package in ("lang", "compiler", "ide", "ladder"):
        assert _offenders(ROOT / package, ("pygls", "lsprotocol")) == {}, package


def test_the_command_line_reaches_the_language_server_only_to_start_it():
    offenders = _offenders(ROOT / "ladder", ("lsp",))
    assert set(offenders) <= {"ladder/commands/lsp.py"}, offenders


def test_back_ends_see_only_the_machine_and_the_intermediate_code():
    assert back_end_folders(), "no back end found"
    forbidden = ("lang.model", "lang.checks", "lang.loader", "lang.ldfile", "lang.textform", "lang.semantics.lower",
                 "compiler.optimise")
    for folder in back_end_folders():
        assert _offenders(folder, forbidden) == {}, folder.name


def test_every_back_end_folder_is_a_family_and_every_part_family_registers_its_back_end():
    # a family with parts builds images (compiler.backend.BACKENDS); C, with none, writes source (compiler.c)
    assert {folder.name for folder in back_end_folders()} == set(FAMILIES)
    assert set(BACKENDS) == {key for key, family in FAMILIES.items() if family.parts}
    for family, backend in BACKENDS.items():
        assert backend.family == family and backend.delay_loop_cycles > 0
        assert type(backend).__module__.split(".")[:2] == ["compiler", family]
        assert backend.flow.__name__ == f"compiler.{family}.flow" and backend.flow.CLOCKS_PER_CYCLE > 0


def test_the_scan_budget_reaches_a_family_only_through_its_back_end():
    # the decoder of a family's program memory comes with its back end (Backend.flow): budget.py names no family
    path = ROOT / "compiler" / "budget.py"
    imported = _imports(path, "compiler")
    assert "importlib" not in imported
    assert not [m for m in imported for family in FAMILIES if m.startswith(f"compiler.{family}")]


def _runtime_imports(path: Path, package: str) -> set[str]:
    """The modules a file imports when it runs, at its top or in a function; not those under
    `if TYPE_CHECKING:`, which are for the type checker only."""
    found = set()
    pending = list(ast.parse(path.read_text(encoding="utf-8")).body)
    while pending:
        node = pending.pop()
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            continue
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[:len(package.split(".")) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            found.add(module)
            found.update(f"{module}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        pending.extend(ast.iter_child_nodes(node))
    return found


def _function_imports(path: Path, package: str) -> set[str]:
    """The modules a file imports inside its functions."""
    functions = [node for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
                 if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))]
    found = set()
    for function in functions:
        for node in ast.walk(function):
            if isinstance(node, ast.ImportFrom):
                base = package.split(".")[:len(package.split(".")) - node.level + 1] if node.level else []
                found.add(".".join(base + ([node.module] if node.module else [])))
            elif isinstance(node, ast.Import):
                found.update(alias.name for alias in node.names)
    return found


def test_the_pic16_routines_build_on_its_integer_patterns_and_not_the_other_way_round():
    # routines.py writes the subroutines with integers.py's byte arithmetic; integers.py calls them by name
    folder = ROOT / "compiler" / "pic16"
    integers, routines = folder / "integers.py", folder / "routines.py"
    assert "compiler.pic16.routines" not in _runtime_imports(integers, "compiler.pic16")
    assert "compiler.pic16.integers" in _imports(routines, "compiler.pic16")
    for path in folder.glob("*.py"):
        inside = _function_imports(path, "compiler.pic16")
        assert not inside & {"compiler.pic16.integers", "compiler.pic16.routines"}, path.name


def test_the_language_server_has_no_import_cycles():
    modules = {f"lsp.{p.stem}": p for p in (ROOT / "lsp").glob("*.py") if p.stem != "__init__"}
    edges = {name: {m for m in _runtime_imports(path, "lsp") if m in modules} - {name}
             for name, path in modules.items()}
    visiting, done = set(), set()

    def visit(name: str, trail: list[str]) -> None:
        assert name not in visiting, " -> ".join(trail + [name])
        if name in done:
            return
        visiting.add(name)
        for other in sorted(edges[name]):
            visit(other, trail + [name])
        visiting.discard(name)
        done.add(name)

    for name in sorted(modules):
        visit(name, [])


def test_features_reach_each_other_through_the_servers_typed_services():
    for path in (ROOT / "lsp").glob("*.py"):
        assert "extensions[" not in path.read_text() and "extensions.get(" not in path.read_text(), path.name


def test_the_compiler_shares_semantics_through_lang_not_the_simulator():
    # what both need (integer arithmetic, format strings, storage sizes, timer periods) is in lang
    # proper; only compiler/run, which checks scenarios on firmware, drives the simulator itself
    offenders = _offenders(ROOT / "compiler", ("lang.sim",))
    assert all(path.startswith("compiler/run/") for path in offenders), offenders


def test_one_lowering_defines_each_instruction_for_the_simulator_and_every_back_end():
    # lang.semantics knows neither of its users; both reach the instructions only through it
    assert _offenders(ROOT / "lang" / "semantics", ("lang.sim", "lang.checks", "compiler")) == {}
    for path in (ROOT / "lang" / "sim" / "compile.py", ROOT / "compiler" / "__init__.py"):
        assert "lang.semantics.lower.lower_program" in _imports(path, _package_of(path)), path


def test_target_names_only_the_part_a_build_is_for():
    """"target" once named five things; now it is the part a build is for
    (`--target PART`, `compiler.target_device`, the LD5xx rules on its
    peripherals) and, as in any compiler, where a jump goes. The families are
    `lang.families`, the back ends' seam `compiler.backend`, what an op writes
    `ir.Place`, the lowering's builder for a part `PartBuilder`."""
    found = []
    for package in ("lang", "compiler", "ide", "lsp", "ladder"):
        for path in sorted((ROOT / package).rglob("*.py")):
            where = str(path.relative_to(ROOT))
            if path.stem in ("target", "targets"):
                found.append(where)
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                named = [node.name] if isinstance(node, ast.ClassDef) else \
                    [t.id for t in node.targets if isinstance(t, ast.Name)] if isinstance(node, ast.Assign) else []
                found += [f"{where}: {name}" for name in named if "Target" in name]
    assert found == []
