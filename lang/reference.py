"""How each instruction is typed, from the instruction table: its drawing,
its operands, its `.ld` line and an example program. The reader's LD003 asks
here for the drawings closest to one it cannot read; `python -m
lang.reference > docs/elements.md` writes the reference page (a test keeps it
current and parses every example)."""

from __future__ import annotations

import difflib
import re
import sys
from functools import cache, lru_cache

from .instructions import INSTRUCTIONS, Instruction
from .model import Element, Program
from .roles import role

# instructions with no drawing of their own (an empty rung's placeholder)
_UNDRAWN = {"PLACEHOLDER"}
_WORD = re.compile(r"[A-Za-z]{2,}")


@cache
def examples() -> dict[str, Element]:
    """One element of each instruction, with the values LDmicro's editor gives a new one."""
    keys = [key for key in INSTRUCTIONS if key not in _UNDRAWN]
    # one program of a rung per instruction: one parse, not one each (4.4 ms against 7.6)
    program, problems = _read_example_rungs([INSTRUCTIONS[key].example for key in keys])
    found: list[list[Element]] = [[] for _ in program.rungs]
    for index, element in program.elements():
        found[index].append(element)
    if problems or len(found) != len(keys) or any(len(elements) != 1 for elements in found):
        return {key: _example(key) for key in keys}  # read one by one: the one that fails is named
    return {key: elements[0] for key, elements in zip(keys, found)}


def _example(key: str) -> Element:
    line = INSTRUCTIONS[key].example
    program, problems = _read_example_rungs([line])
    elements = [element for _, element in program.elements()]
    if problems or len(elements) != 1:
        raise ValueError(f"the example line of {key} does not read: {line!r}")
    return elements[0]


def _read_example_rungs(lines: list[str]) -> tuple[Program, list]:
    from .ldfile import read_ld

    return read_ld("LDmicro0.2\n\nPROGRAM\n" + "".join(f"RUNG\n  {line}\nEND\n" for line in lines))


@cache
def drawings() -> dict[str, tuple[str, str]]:
    """(name line, glyph) of each instruction's example."""
    from .textform.writer import element_text

    return {key: element_text(element)[:2] for key, element in examples().items()}


def closest(glyph: str, top: str = "", limit: int = 3) -> list[str]:
    """The instructions whose drawing is nearest to an unreadable one: those
    whose glyph shares a word with it (`CTU` in `[CTU >=5]`), then the most
    alike by their characters."""
    words = {w.upper() for w in _WORD.findall(glyph)}
    drawn_words, by_text = _known()
    same_word = [key for key, drawn in drawn_words.items() if words & drawn or key in words]
    alike = [by_text[m] for m in difflib.get_close_matches(glyph.strip(), list(by_text), n=limit, cutoff=0.5)]
    ordered = list(dict.fromkeys(same_word + alike))
    return ordered[:limit]


@cache
def _known() -> tuple[dict[str, set[str]], dict[str, str]]:
    """Each instruction's words in its drawing, and each drawing's instruction."""
    known = drawings()
    words = {key: {w.upper() for w in _WORD.findall(drawn)} for key, (_, drawn) in known.items()}
    return words, {drawn.strip(): key for key, (_, drawn) in known.items() if drawn.strip()}


def prepare() -> None:
    """Builds what `suggestion` compares a drawing with (the examples read and
    drawn: 5 to 25 ms), ahead of the first unreadable drawing: the server does
    it once it is idle after an open, not in the first edit that needs it."""
    _known()


# a damaged or foreign file repeats its unreadable glyphs thousands of times: each is matched once
@lru_cache(maxsize=4096)
def suggestion(glyph: str, top: str = "") -> str:
    """`; did you mean ...?` naming the closest drawings, or nothing."""
    keys = closest(glyph, top)
    if not keys:
        return ""
    shown = [f"`{drawings()[key][1].strip()}` ({INSTRUCTIONS[key].title})" for key in keys]
    return "; did you mean " + " or ".join(shown) + "? (docs/elements.md shows every drawing)"


def example_program(key: str) -> Program:
    """A one-rung program using the instruction: a contact before it, and a
    coil after it when it does not end the rung itself (a comment alone)."""
    from .ldfile import read_ld

    line = INSTRUCTIONS[key].example
    body = [line] if key == "COMMENT" else \
        ["CONTACTS Xbutton 0 0", line] + ([] if INSTRUCTIONS[key].eol else ["COIL Ylamp 0 0 0 0"])
    program, _ = read_ld("LDmicro0.2\n\nPROGRAM\nRUNG\n" + "".join(f"  {item}\n" for item in body) + "END\n")
    return program


def _operands(instruction: Instruction) -> list[str]:
    rows = []
    for field in instruction.fields:
        where = "drawn" if field.drawn else "in DETAILS"
        names = (", a name starting with " + " or ".join(f"{p} ({role(p)[0]})" for p in field.prefixes)
                 if field.prefixes else "")
        rows.append(f"| `{field.name}` | {field.kind}{names} | {where} |")
    return rows


def render() -> str:
    """docs/elements.md."""
    from .textform.writer import render_program

    parts = ["# Elements: how each instruction is typed", "",
             "<!-- Generated by `python -m lang.reference > docs/elements.md` from the instruction table "
             "(lang/instructions.py); edit the table, not this page. -->", "",
             "Each element is drawn as LDmicro 5.4's text export draws it: its names and values on the line "
             "above, its glyph on the rung's wire. An element LDmicro's editor would not draw that way is "
             "reported as LD003 with the closest drawings. Values shown are those LDmicro's editor gives a "
             "new element; the `.ld` line is how LDmicro's project file stores it.", ""]
    by_category: dict[str, list[str]] = {}
    for key, instruction in INSTRUCTIONS.items():
        if key not in _UNDRAWN:
            by_category.setdefault(instruction.category, []).append(key)
    for category, keys in by_category.items():
        parts += [f"## {category}", ""]
        for key in keys:
            instruction = INSTRUCTIONS[key]
            top, glyph = drawings()[key]
            line = INSTRUCTIONS[key].example
            diagram = render_program(example_program(key)).split("LADDER DIAGRAM:\n", 1)[1]
            diagram = diagram.split("\n\n", 1)[0]
            parts += [f"### {key}: {instruction.title}", "", instruction.doc, "",
                      f"Drawn `{glyph.strip()}`" + (f" under `{top.strip()}`" if top.strip() else "") +
                      f"; in a `.ld` file `{line}`.", ""]
            if instruction.fields:
                parts += ["| operand | kind | where |", "|---|---|---|", *_operands(instruction), ""]
            parts += ["```", diagram, "```", ""]
    return "\n".join(parts)


if __name__ == "__main__":
    sys.stdout.write(render())
