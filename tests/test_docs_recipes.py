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
NOT_IN_THE_TREE = (".venv/",)  # the contributor's virtual environment, which the recipes' commands use


def recipes(text: str) -> str:
    """The `## Recipes` section: from its heading to the next second-level heading."""
    start = text.index("\n## Recipes\n")
    end = text.find("\n## ", start + 1)
    return text[start:] if end < 0 else text[start:end]


def named(section: str) -> tuple[list[str], list[str]]:
    """The paths (words with a `/`) and the modules run with `python -m` in the
    section's backticked spans."""
    paths, modules = [], []
    prose = re.sub(r"```.*?```", "", section, flags=re.DOTALL)  # code blocks are the doc tests' business
    for span in re.findall(r"`([^`]+)`", prose):  # a span may run over a line break
        words = [word.strip("(),;:") for word in span.split()]
        for before, word in zip([""] + words, words):
            if before == "-m" and span.split("-m")[0].rstrip().endswith(("python", "python3")):
                modules.append(word)
            elif "/" in word and "://" not in word and not word.startswith(NOT_IN_THE_TREE):
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
    text = ("\n## Recipes\n\n1. Edit `lang/checks/<rule>.py` and `lang/chekcs/common.py`, run "
            "`.venv/bin/python -m lang.codes_dock > docs/diagnostics.md` and "
            "`.venv/bin/pytest -q tests/test_checks_registry.py -m slow`; see `tests/<name>.nothing`.\n"
            "\n## Next section\n\n`lang/gone.py`\n")
    # the next section's path is not the recipes' business
    assert missing(recipes(text), True) == ["lang/chekcs/common.py", "tests/<name>.nothing", "lang/codes_dock.py"]
