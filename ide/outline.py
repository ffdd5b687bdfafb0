"""A rung in one line of text, and the outline of a program: what the
language server shows when hovering a rung, in document symbols (`Symbol`:
the sections of a text file, each rung with its comment or logic, the names
it writes) and in folding (`Fold`: per rung, per section). `rung_logic` writes the power flow as a Boolean expression, e.g.
`Ymotor := (Xstart | Rrun) & !Xstop`.

Notation: `&` series, `|` parallel, `!` a normally closed contact; an element
that transforms its input is written like a function of it (`TON[Tdly, 2 s](Xa)`,
`OSR(Xa)`); outputs are statements joined by `; ` (`Ya := ...`, `if ...: Cn := Cn + 1`).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from lang.instructions import RELATIONS
from lang.labels import label as instruction_label
from lang.loader import TEXT_KIND
from lang.model import Element, Node, Program, Rung, Series, Span
from lang.textform.writer import comment_text
from lang.values import format_delay

from .document import Document

MAX_LENGTH = 400

# precedence: 3 atom, 2 and, 1 or
_TRUE = ("1", 3)
_FALSE = ("0", 3)


def _and(a: tuple[str, int], b: tuple[str, int]) -> tuple[str, int]:
    if a == _TRUE:
        return b
    if b == _TRUE:
        return a
    if _FALSE in (a, b):
        return _FALSE
    left = a[0] if a[1] >= 2 else f"({a[0]})"
    right = b[0] if b[1] >= 2 else f"({b[0]})"
    return f"{left} & {right}", 2


def _or(items: list[tuple[str, int]]) -> tuple[str, int]:
    items = [i for i in items if i != _FALSE]
    if not items:
        return _FALSE
    if _TRUE in items:
        return _TRUE
    if len(items) == 1:
        return items[0]
    return " | ".join(i[0] for i in items), 1


def _call(name: str, p: tuple[str, int]) -> tuple[str, int]:
    return f"{name}({p[0]})", 3


def _value(element: Element, field: str) -> str:
    value = element.args.get(field)
    if field == "delay" and isinstance(value, int):
        return format_delay(value)
    return "" if value is None else str(value)


def _guard(p: tuple[str, int], action: str) -> str:
    return action if p == _TRUE else f"if {p[0]}: {action}"


def _math_symbol(element: Element) -> str:
    glyph = element.spec.glyph
    center = getattr(glyph, "center", None)
    return center.text.strip() if center is not None else element.kind


def _action(element: Element, p: tuple[str, int]) -> str | None:
    """The statement of an output element, or None for one that only passes power."""
    kind, args = element.kind, element.args
    if kind == "COIL":
        name = _value(element, "name")
        kind_of_coil = str(args.get("type", " "))
        if kind_of_coil == "/":
            return f"{name} := !{p[0] if p[1] >= 3 else '(' + p[0] + ')'}"
        if kind_of_coil == "S":
            return _guard(p, f"{name} := 1")
        if kind_of_coil == "R":
            return _guard(p, f"{name} := 0")
        if kind_of_coil == "T":
            return f"toggle {name} on each rise of {p[0]}"
        return f"{name} := {p[0]}"
    if kind == "MOVE":
        return _guard(p, f"{_value(element, 'dest')} := {_value(element, 'src')}")
    if kind in ("ADD", "SUB", "MUL", "DIV", "MOD", "AND", "OR", "XOR", "SHL", "SHR", "SR0", "ROL", "ROR"):
        return _guard(p, f"{_value(element, 'dest')} := {_value(element, 'op1')} {_math_symbol(element)} "
                         f"{_value(element, 'op2')}")
    if kind in ("NEG", "NOT"):
        return _guard(p, f"{_value(element, 'dest')} := {_math_symbol(element)}{_value(element, 'op1')}")
    if kind == "RES":
        return _guard(p, f"reset {_value(element, 'name')}")
    if element.spec.eol:
        return _guard(p, _element_text(element))
    return None


def _element_text(element: Element) -> str:
    """`TON[Tdly, 2 s]`: the instruction and its drawn operands."""
    shown = [_value(element, f.name) for f in element.spec.fields
             if f.drawn and f.kind not in ("flag", "edge", "coil") and _value(element, f.name)]
    word = instruction_label(element) if element.kind != "CONTACTS" else "contact"
    word = word.replace(" ", "_") if " " in word and not shown else word
    return f"{word}[{', '.join(shown)}]" if shown else word


def _element(element: Element, p: tuple[str, int], actions: list[str], at_end: bool) -> tuple[str, int]:
    kind, args = element.kind, element.args
    if kind == "CONTACTS":
        name = _value(element, "name")
        return _and(p, (("!" + name) if args.get("negated") else name, 3))
    if kind == "SHORT" or kind in ("LABEL", "COMMENT", "PLACEHOLDER"):
        return p
    if kind == "OPEN":
        return _FALSE
    if kind in RELATIONS:
        op = RELATIONS[kind]
        return _and(p, (f"({_value(element, 'op1')} {op} {_value(element, 'op2')})", 3))
    if kind in ("IF_BIT_SET", "IF_BIT_CLEAR"):
        test = "bit" if kind == "IF_BIT_SET" else "!bit"
        return _and(p, (f"{test}({_value(element, 'var')}, {_value(element, 'bit')})", 3))
    action = _action(element, p)
    if action is not None:
        actions.append(action)
        return p
    out = _call(_element_text(element), p)
    if at_end:
        actions.append(out[0])
    return out


def _node(node: Node, p: tuple[str, int], actions: list[str], at_end: bool) -> tuple[str, int]:
    if isinstance(node, Element):
        return _element(node, p, actions, at_end)
    if isinstance(node, Series):
        last = len(node.items) - 1
        for position, item in enumerate(node.items):
            p = _node(item, p, actions, at_end and position == last)
        return p
    before = len(actions)
    outs = [_node(branch, p, actions, at_end) for branch in node.branches]
    result = _or(outs)
    if at_end and len(actions) == before:
        actions.append(result[0])
    return result


def rung_logic(rung: Rung) -> str:
    """The rung's logic in one line; a comment rung gives its text."""
    if rung.is_comment:
        return "; " + comment_text(rung).replace("\n", " ")
    if not rung.circuit.items:
        return "(empty rung)"
    actions: list[str] = []
    out = _node(rung.circuit, _TRUE, actions, True)
    text = "; ".join(actions) if actions else out[0]
    if len(text) > MAX_LENGTH:
        text = text[:MAX_LENGTH - 1] + "…"
    return text


def rung_title(program: Program, index: int) -> str:
    """"Rung 3" or "Rung 3: <first comment line>"."""
    rung = program.rungs[index]
    if rung.is_comment:
        first = comment_text(rung).split("\n")[0].strip()
        return f"Rung {index + 1}: ; {first}" if first else f"Rung {index + 1}"
    return f"Rung {index + 1}"


def outputs(rung: Rung) -> list[Element]:
    """The elements of a rung that write something (coils, MOV, RES...)."""
    found = []
    for element in rung.elements():
        for f in element.spec.fields:
            if f.access in ("write", "rw") and element.args.get(f.name):
                found.append(element)
                break
    return found


# --- symbols and folding ---------------------------------------------------------------------

class Kind(Enum):
    SECTION = "section"
    RUNG = "rung"
    COMMENT = "comment"  # a comment rung
    COIL = "coil"  # a name a coil writes
    OUTPUT = "output"  # a name another element writes (MOV, RES...)


@dataclass(frozen=True)
class Symbol:
    name: str
    detail: str | None
    kind: Kind
    span: Span  # all of it
    selection: Span  # what names it
    children: tuple[Symbol, ...] = ()


@dataclass(frozen=True)
class Fold:
    first: int
    last: int  # lines
    comment: bool  # a comment rung (else a region)


SECTION_NAMES = {"header": "Header"}


def _lines(document: Document, first: int, last: int) -> Span:
    return Span(first, 0, last, len(document.line(last)))


def _written(element: Element) -> str:
    for f in element.spec.fields:
        if f.access in ("write", "rw") and element.args.get(f.name):
            return str(element.args[f.name])
    return element.kind


def rung_symbol(document: Document, index: int) -> Symbol | None:
    """A drawn rung's symbol, with the names it writes (None: not drawn)."""
    extent = document.locator.rung_lines(index)
    if extent is None:
        return None
    first, last = extent
    rung = document.program.rungs[index]
    children = []
    for element in outputs(rung):
        span = element.span
        if span is None:
            continue
        name_span = next((element.arg_spans[f.name] for f in element.spec.fields
                          if f.access in ("write", "rw") and f.name in element.arg_spans), span)
        children.append(Symbol(_written(element), element.spec.title,
                               Kind.COIL if element.kind == "COIL" else Kind.OUTPUT, span, name_span))
    return Symbol(rung_title(document.program, index), "comment" if rung.is_comment else rung_logic(rung),
                  Kind.COMMENT if rung.is_comment else Kind.RUNG, _lines(document, first, last),
                  Span.at(first, 0, len(document.line(first))), tuple(children))


def section_symbols(document: Document) -> list[Symbol]:
    """The sections of a text file (none for a .ld file), the header if it
    holds anything, without children: the rungs go into the one whose lines
    hold them."""
    if document.kind != TEXT_KIND:
        return []
    found = []
    for title, first, last in document.locator.sections:
        if title == "header" and not any(document.line(n).strip() for n in range(first, last + 1)):
            continue
        found.append(Symbol(SECTION_NAMES.get(title, title), None, Kind.SECTION, _lines(document, first, last),
                            Span.at(first, 0, len(document.line(first)))))
    return found


def rung_fold(document: Document, index: int) -> Fold | None:
    """A drawn rung's folding range (None: one line, or not drawn)."""
    extent = document.locator.rung_lines(index)
    if extent is None or extent[1] <= extent[0]:
        return None
    return Fold(extent[0], extent[1], document.program.rungs[index].is_comment)


def section_folds(document: Document) -> list[Fold]:
    """One per section of a text file but the header, without its blank lines at the end."""
    found = []
    if document.kind == TEXT_KIND:
        for title, first, last in document.locator.sections:
            while last > first and not document.line(last).strip():
                last -= 1
            if title != "header" and last > first:
                found.append(Fold(first, last, False))
    return found
