"""FORMATTED_STRING: the text's escapes, read into the steps the lowering
sends one per scan while the UART is ready (lang/semantics/lower/io.py)."""

from __future__ import annotations

from dataclasses import dataclass

ESCAPES = {"a": 7, "b": 8, "e": 27, "f": 12, "n": 10, "r": 13, "t": 9, "v": 11,
            "'": 39, '"': 34, "?": 63, "\\": 92}
HEX = "0123456789abcdefABCDEF"


@dataclass(frozen=True)
class Format:
    """The characters to send: ("c", byte), ("s", None) for the sign
    position, ("d", i) for the i-th digit of the interpolated variable."""

    steps: tuple
    digits: int  # 0 when no variable is interpolated
    signed: bool


def parse_format(text: str) -> Format:
    """LDmicro's escapes: \\1..\\5 (digits) and \\-1..\\-5 (with a sign
    position), \\a \\b \\e \\f \\n \\r \\t \\v \\' \\" \\? \\\\, \\xHH; \\0
    is skipped and the character after it read as an escape. ValueError with
    LDmicro's message for anything else."""
    steps: list = []
    digits = -1
    signed = False
    i = 0
    while i < len(text):
        ch = text[i]
        nxt = text[i + 1] if i + 1 < len(text) else ""
        if ch == "\\" and (nxt.isdigit() or nxt == "-") and nxt != "0":
            if digits >= 0:
                raise ValueError("Multiple escapes (\\0-9) present in format string, not allowed.")
            i += 1
            if text[i] == "-":
                signed = True
                steps.append(("s", None))
                i += 1
            count = text[i] if i < len(text) else ""
            if not count.isdigit() or not "1" <= count <= "5":
                raise ValueError("Bad escape sequence following \\; for a literal backslash, use \\\\")
            digits = int(count)
            steps.extend(("d", d) for d in range(digits))
            i += 1
        elif ch == "\\":
            i += 1
            while i < len(text) and text[i] == "0":
                i += 1
            esc = text[i] if i < len(text) else ""
            if esc in ESCAPES:
                steps.append(("c", ESCAPES[esc]))
                i += 1
            elif esc in ("x", "X"):
                pair = text[i + 1:i + 3]
                if len(pair) != 2 or any(c not in HEX for c in pair):
                    raise ValueError("Bad escape: correct form is \\xAB.")
                steps.append(("c", int(pair, 16)))
                i += 3
            else:
                raise ValueError(f"Bad escape '\\{esc}'")
        else:
            code = ord(ch)
            steps.append(("c", code if code < 256 else ord("?")))
            i += 1
    return Format(tuple(steps), max(digits, 0), signed)
