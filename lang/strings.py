"""FORMATTED_STRING: the text's escapes, and the per-scan sender that LDmicro's
compiled code implements (one character per scan while the UART is ready)."""

from __future__ import annotations

from dataclasses import dataclass

from .numbers import cdiv

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


def make_sender(fmt: Format):
    """The element's per-scan function. Its state (`one` edge memory, `busy`
    still sending, `seq` position, `conv` the value being converted, `lead`
    suppressing leading zeros) lives in the simulator's slots."""
    steps = fmt.steps
    count = len(steps)
    digits = fmt.digits
    signed = fmt.signed

    def send(now_us, power, var, one, busy, seq, conv, lead, uart):
        if power:
            if not one:
                one, seq, busy = True, 0, True
        else:
            one = False
        if busy and seq < count and uart.ready(now_us):
            kind, arg = steps[seq]
            if kind == "c":
                byte = arg
            elif kind == "s":
                # the sign position also loads the absolute value to convert
                byte, conv = (45, -var) if var < 0 else (32, var)
            else:
                if arg == 0:
                    if not signed:
                        conv = var
                    lead = True
                scale = 10 ** (digits - arg - 1)
                quotient = cdiv(conv, scale)
                conv -= quotient * scale
                byte = (quotient + 48) & 0xFF
                if arg != digits - 1:
                    # all but the last digit: leading zeros become blanks
                    if byte == 48:
                        if lead:
                            byte = 32
                    else:
                        lead = False
            uart.send(now_us, byte)
            seq += 1
        if seq < count:
            out = busy
        else:
            out = busy = False
        return out, one, busy, seq, conv, lead

    return send
