"""How messages, the outline and the listings name an instruction: the word
LDmicro draws (`MOV`, `T2CNT`, `set coil`), and with its main operand
(`coil 'Ya'`, `TON 'T1'`)."""

from __future__ import annotations

from .instructions import INSTRUCTIONS
from .model import Element

# How messages name an instruction: the word LDmicro draws, not the model key.
_LABELS = {
    "CONTACTS": "contact",
    "COIL": "coil",
    "MOVE": "MOV",
    "LOOK_UP_TABLE": "LUT",
    "PIECEWISE_LINEAR": "PWL",
    "READ_ADC": "READ ADC",
    "SET_PWM": "SET PWM",
    "TIME2COUNT": "T2CNT",
    "TIME2DELAY": "T2DLY",
    "SEED_RANDOM": "SRAND",
    "RANDOM": "RAND",
    "MASTER_RELAY": "MASTER RLY",
    "SHIFT_REGISTER": "SHIFT REG",
    "FORMATTED_STRING": "formatted string",
    "UART_SEND": "UART SEND",
    "UART_RECV": "UART RECV",
    "UART_SEND_READY": "UART SEND ready test",
    "UART_RECV_AVAIL": "UART RECV available test",
    "PLACEHOLDER": "empty rung",
    "IF_BIT_SET": "IF BIT SET",
    "IF_BIT_CLEAR": "IF BIT CLR",
    "SET_BIT": "SET BIT",
    "CLEAR_BIT": "CLR BIT",
}
_COIL_WORDS = {" ": "coil", "/": "negated coil", "S": "set coil", "R": "reset coil", "T": "toggle coil"}


def label(element: Element) -> str:
    """The instruction as messages name it: 'TON', 'coil', 'set coil', 'MOV'."""
    if element.kind == "COIL":
        return _COIL_WORDS.get(str(element.args.get("type", " ")), "coil")
    return _LABELS.get(element.kind, element.kind.replace("_", " "))


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
