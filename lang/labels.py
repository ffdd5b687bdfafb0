"""How messages, the outline and the listings name an instruction: the word
LDmicro draws (`MOV`, `T2CNT`, `set coil`), and with its main operand
(`coil 'Ya'`, `TON 'T1'`)."""

from __future__ import annotations

from .instructions import INSTRUCTIONS
from .model import Element

_COIL_WORDS = {" ": "coil", "/": "negated coil", "S": "set coil", "R": "reset coil", "T": "toggle coil"}


def label(element: Element) -> str:
    """The instruction as messages name it: 'TON', 'coil', 'set coil', 'MOV'."""
    if element.kind == "COIL":
        return _COIL_WORDS.get(str(element.args.get("type", " ")), "coil")
    spec = INSTRUCTIONS.get(element.kind)
    return spec.label if spec is not None else element.kind.replace("_", " ")


_NAMED = {
    key: next((f.name for f in spec.fields if f.kind in ("bit", "var", "label")), None)
    for key, spec in INSTRUCTIONS.items()
}


def describe(element: Element) -> str:
    """The instruction and its main operand: "coil 'Ya'", "TON 'T1'", "OSR"."""
    field = _NAMED.get(element.kind)
    value = token(element.args.get(field)) if field else ""
    return f"{label(element)} '{value}'" if value else label(element)


def token(value: object) -> str:
    """An operand as source text ('' for none)."""
    if value is None:
        return ""
    text = str(value)
    return "" if text == "(none)" else text
