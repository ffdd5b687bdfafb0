"""Damaging a drawing the way a hand edit or a bad paste would: characters
replaced, deleted or inserted, lines swapped (used by the fuzz test and the
time-boxed fuzz benchmark); and faults planted in a program's model (a contact
negated or removed, a rung dropped, a timer shortened, a coil swapped), used by
the mutant suite of `ladder verify`."""

from __future__ import annotations

import random
from collections.abc import Iterator

from lang.model import Element, Node, Parallel, Program, Rung, Series, children, rung_circuit

GLYPH_CHARS = "-+| []{}()/\\o^~X;\""


def mutate(text: str, rng: random.Random, count: int) -> str:
    lines = text.splitlines()
    start = lines.index("LADDER DIAGRAM:") + 1 if "LADDER DIAGRAM:" in lines else 0
    if start >= len(lines):
        return text
    for _ in range(count):
        number = rng.randrange(start, len(lines))
        line = lines[number]
        col = rng.randrange(len(line) + 1)
        edit = rng.choice(["replace", "delete", "insert", "swap-lines"])
        glyph = rng.choice(GLYPH_CHARS)
        if edit == "replace" and line:
            line = line[:col] + glyph + line[col + 1:]
        elif edit == "delete":
            line = line[:col] + line[col + 1:]
        elif edit == "insert":
            line = line[:col] + glyph + line[col:]
        else:
            other = rng.randrange(start, len(lines))
            lines[other], line = line, lines[other]
        lines[number] = line
    return "\n".join(lines)


# Faults planted in a program's model, as a wrong edit of the drawing would: each
# finds its element in the first rung with the coil named that has one, and changes it in place.

def _walk(node: Node, parent: Series | Parallel | None = None) -> Iterator[tuple[Element, Series | Parallel | None]]:
    if isinstance(node, Element):
        yield node, parent
        return
    for child in children(node):
        yield from _walk(child, node)


def _named(element: Element) -> str | None:
    name = element.args.get("name", element.args.get("op1"))
    return name if isinstance(name, str) else None


def _rungs_of(program: Program, coil: str) -> Iterator[Rung]:
    """The rungs with a coil of that name (of any kind: ( ), (/), (S), (R))."""
    for rung in program.rungs:
        if any(element.kind == "COIL" and _named(element) == coil for element, _ in _walk(rung.circuit)):
            yield rung


def _find(program: Program, coil: str, kind: str, name: str) -> tuple[Rung, Element, Series | Parallel]:
    """The first element of that kind and name in a rung that has the coil."""
    for rung in _rungs_of(program, coil):
        for element, parent in _walk(rung.circuit):
            if element.kind == kind and _named(element) == name and parent is not None:
                return rung, element, parent
    raise LookupError(f"no {kind} {name} in a rung of {coil}")


def negate_contact(program: Program, coil: str, contact: str) -> None:
    _, element, _ = _find(program, coil, "CONTACTS", contact)
    element.args["negated"] = 0 if element.args["negated"] else 1


def remove_element(program: Program, coil: str, kind: str, name: str) -> None:
    """A contact or comparison taken out of the rung: the wire closes where it was."""
    rung, element, parent = _find(program, coil, kind, name)
    assert isinstance(parent, Series), "taking a branch out of a parallel is another fault"
    parent.items = [node for node in parent.items if node is not element]
    rung.circuit = rung_circuit(rung.circuit)


def drop_rung(program: Program, coil: str) -> None:
    program.rungs.remove(next(_rungs_of(program, coil)))


def set_operand(program: Program, name: str, operand: str, value: object) -> None:
    """A timer's delay, a counter's limit...: every element of that name with the operand gets the new value."""
    for _, element in program.elements():
        if element.args.get("name") == name and operand in element.args:
            element.args[operand] = value


def swap_coil(program: Program, coil: str, other: str) -> None:
    """The rung that should drive one coil drives another."""
    _, element, _ = _find(program, coil, "COIL", coil)
    element.args["name"] = other
