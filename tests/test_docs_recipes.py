"""The recipes of docs/architecture.md (its `## Recipes` section: adding a check
rule, an instruction, a part, a back end) name the files to touch and the
tests to run. Every path they name in backticks exists, and every module they
run with `python -m`, so a file moved or renamed fails here instead of
sending the next contributor to a file that is not there."""

from __future__ import annotations

import glob
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "architecture.md"
SHARED = "../shared/"  # LDmicro's programs beside the checkout, as the corpus tests read them
# a word is a path of the tree when it starts with one of the tree's top-level folders or files
# (hidden ones are tool caches and the contributor's .venv, except CI's .ci): other words with a
# slash are a figure (152/4096 bytes), a system file or a path inside another package's files
TREE = frozenset(p.name for p in ROOT.iterdir() if not p.name.startswith(".") or p.name == ".ci")


def recipes(text: str) -> str:
    """The `## Recipes` section: from its heading to the next second-level heading."""
    start = text.index("\n## Recipes\n")
    end = text.find("\n## ", start + 1)
    return text[start:] if end < 0 else text[start:end]


def named(section: str) -> tuple[list[str], list[str]]:
    """The tree's paths and the modules run with `python -m` that the section's
    backticked spans name."""
    paths, modules = [], []
    prose = re.sub(r"```.*?```", "", section, flags=re.DOTALL)  # code blocks are the doc tests' business
    for span in re.findall(r"`([^`]+)`", prose):  # a span may run over a line break
        words = [word.strip("(),;:") for word in span.split()]
        for before, word in zip([""] + words, words):
            if before == "-m" and span.split("-m")[0].rstrip().endswith(("python", "python3")):
                modules.append(word)
            elif "/" in word and (word.split("/")[0] in TREE or word.startswith(SHARED)):
                paths.append(word)
    return paths, modules


def missing(section: str, shared_present: bool) -> list[str]:
    """What the section names that the tree does not hold; a `<placeholder>`
    stands for any name (`compiler/<family>/`, `tests/diagnostics/<code>.ladder`)."""
    paths, modules = named(section)
    paths += [module.replace(".", "/") + ".py" for module in modules]
    absent = []
    for path in paths:
        if path.startswith(SHARED) and not shared_present:
            continue
        if not glob.glob(str(ROOT / re.sub(r"<[^>]+>", "*", path))):
            absent.append(path)
    return absent


def test_the_recipes_for_a_check_rule_and_an_instruction_are_there():
    section = recipes(DOC.read_text(encoding="utf-8"))
    assert "\n### Adding a check rule\n" in section
    assert "\n### Adding an instruction\n" in section
    paths, modules = named(section)
    assert "lang/codes.toml" in paths and "lang/instructions.py" in paths
    assert "lang.codes_doc" in modules and "lang.reference" in modules


def test_every_path_and_module_a_recipe_names_exists():
    section = recipes(DOC.read_text(encoding="utf-8"))
    assert missing(section, (ROOT / SHARED).is_dir()) == []


def test_a_path_or_module_that_is_not_there_is_reported():
    text = ("\n## Recipes\n\n1. Edit `lang/checks/<rule>.py` and `lang/checks/comon.py` (not "
            "`/usr/share/gputils/header/p*.inc` nor `lkr/*_g.lkr`: `152/4096` bytes), run "
            "`.venv/bin/python -m lang.codes_dock > docs/diagnostics.md` and "
            "`.venv/bin/pytest -q tests/test_checks_registry.py -m slow`; see `tests/<name>.nothing`.\n"
            "\n## Next section\n\n`lang/gone.py`\n")
    # the next section's path is not the recipes' business
    assert missing(recipes(text), True) == ["lang/checks/comon.py", "tests/<name>.nothing", "lang/codes_dock.py"]
