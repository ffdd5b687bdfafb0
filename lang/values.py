"""Values as LDmicro writes them: integer literals, delays and frequencies with
SI prefixes, escaped strings, and 8-bit code pages read without losing a byte."""

from __future__ import annotations

import codecs
import re
from decimal import Decimal

# --- integer literals ------------------------------------------------------

_CHAR_ESCAPES = {
    "a": 7, "b": 8, "e": 27, "f": 12, "n": 10, "r": 13, "t": 9, "v": 11,
    "\\": 92, "'": 39, '"': 34, "?": 63,
}


def is_literal(token: str) -> bool:
    """LDmicro's rule: a literal starts with a digit, a sign and a digit, or a quote."""
    if not token:
        return False
    if token[0].isdigit():
        return True
    if token[0] in "+-" and len(token) > 1 and token[1].isdigit():
        return True
    return token[0] == "'"


_DIGITS = frozenset("0123456789")


def is_literal_fast(text: str) -> bool:
    """is_literal for the symbol table's hot loop (text is not empty; ASCII digits)."""
    first = text[0]
    if first in _DIGITS or first == "'":
        return True
    return (first == "-" or first == "+") and len(text) > 1 and text[1] in _DIGITS


def literal_value(token: str) -> int:
    """The value of an integer literal; ValueError with a reason if malformed."""
    if token.startswith("'"):
        if len(token) < 3 or not token.endswith("'"):
            raise ValueError(f"bad character literal {token}")
        body = token[1:-1]
        if len(body) == 1:
            return ord(body)
        if body.startswith("\\"):
            if len(body) == 2 and body[1] in _CHAR_ESCAPES:
                return _CHAR_ESCAPES[body[1]]
            if re.fullmatch(r"\\x[0-9A-Fa-f]{1,2}", body):
                return int(body[2:], 16)
        raise ValueError(
            f"expected one character or one simple escape in single quotes: {token}"
        )
    sign = -1 if token.startswith("-") else 1
    digits = token.lstrip("+-")
    lower = digits.lower()
    try:
        if lower.startswith("0x"):
            return sign * int(lower[2:], 16)
        if lower.startswith("0b"):
            return sign * int(lower[2:], 2)
        if lower.startswith("0o"):
            return sign * int(lower[2:], 8)
        if len(lower) > 1 and lower.startswith("0"):
            return sign * int(lower[1:], 8)
        return sign * int(lower, 10)
    except ValueError:
        raise ValueError(f"bad number {token}") from None


def as_int(value: object) -> int:
    """An element's integer operand as int() reads it: the readers keep an
    int, or the text they could not read as one."""
    return int(value if isinstance(value, int) else str(value))


_NAME_RE = re.compile(r"[A-Za-z_$#@][A-Za-z0-9_$#@\[\].]*\Z")


def is_name(token: str) -> bool:
    return bool(_NAME_RE.match(token))


# --- SI quantities: delays in microseconds, frequencies in hertz ------------

_PREFIX_EXP = {"G": 9, "M": 6, "k": 3, "": 0, "m": -3, "u": -6, "n": -9, "p": -12}


def _si_prefix(value: float) -> tuple[str, int]:
    """LDmicro's choice of prefix (no centi or deci)."""
    magnitude = abs(value)
    if magnitude == 0 or 1 <= magnitude < 1e3:
        return "", 0
    for prefix, exp in (("G", 9), ("M", 6), ("k", 3)):
        if magnitude >= 10.0**exp:
            return prefix, exp
    for prefix, exp in (("m", -3), ("u", -6), ("n", -9)):
        if magnitude >= 10.0**exp:
            return prefix, exp
    return "p", -12


def _format_g6(value: Decimal) -> str:
    """`%.6g`, widened to as many digits as the value needs: never lossy."""
    text = f"{float(value):.6g}"
    if Decimal(text) == value:
        return text
    exact = format(value.normalize(), "f")
    return exact


def format_si(value: Decimal, unit: str) -> str:
    """A quantity in base units as LDmicro draws it, e.g. 0.1 s -> '100 ms'."""
    prefix, exp = _si_prefix(float(value))
    scaled = value.scaleb(-exp)
    return f"{_format_g6(scaled)} {prefix}{unit}"


def format_delay(microseconds: int) -> str:
    return format_si(Decimal(microseconds).scaleb(-6), "s")


def format_frequency(hertz: int) -> str:
    return format_si(Decimal(hertz), "Hz")


SI_NUMBER = r"[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"
DELAY_RE = re.compile(rf"({SI_NUMBER})\s*([GMkmunp]?)s\Z")
FREQ_RE = re.compile(rf"({SI_NUMBER})\s*([GMkmunp]?)Hz\Z")


def _parse_si(text: str, pattern: re.Pattern, scale: int, what: str) -> int:
    match = pattern.match(text.strip())
    if not match:
        raise ValueError(f"bad {what} {text!r}")
    value = Decimal(match.group(1)).scaleb(_PREFIX_EXP[match.group(2)] + scale)
    if value != value.to_integral_value():
        raise ValueError(f"{what} {text!r} is not a whole number of {'microseconds' if scale else 'hertz'}")
    return int(value)


def parse_delay(text: str) -> int:
    """'1.5 s' -> 1500000 (microseconds)."""
    return _parse_si(text, DELAY_RE, 6, "delay")


def parse_frequency(text: str) -> int:
    """'1 kHz' -> 1000."""
    return _parse_si(text, FREQ_RE, 0, "frequency")


# --- escaped strings in .ld files -------------------------------------------

_WRITE_ESCAPES = {7: "\\a", 8: "\\b", 27: "\\e", 12: "\\f", 10: "\\n", 13: "\\r", 9: "\\t", 11: "\\v"}
_READ_ESCAPES = {"a": "\a", "b": "\b", "e": "\x1b", "f": "\f", "n": "\n", "r": "\r",
                 "t": "\t", "v": "\v", "'": "'", '"': '"', "?": "?", "\\": "\\"}


def escape_ld(text: str, space_as_x20: bool) -> str:
    """LDmicro's escaping for a token in a .ld line. Comments keep spaces;
    strings write them as \\x20 so the token has no blank. Characters above
    0x7F are written raw (LDmicro's own \\xFFFFFFxx form does not read back)."""
    if text == "":
        return "(none)"
    out = []
    for ch in text:
        code = ord(ch)
        if ch == "\\":
            out.append("\\\\")
        elif ch == " " and space_as_x20:
            out.append("\\x20")
        elif code in _WRITE_ESCAPES:
            out.append(_WRITE_ESCAPES[code])
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\x{code:X}")
        else:
            out.append(ch)
    return "".join(out)


_ESCAPE_RE = re.compile(r"\\(x[fF]{6}[0-9A-Fa-f]{2}|x[0-9A-Fa-f]{1,2}|.)", re.S)


def unescape_ld(token: str, codepage: str = "cp1252") -> str:
    """Decode an escaped .ld token; `(none)` is the empty string. Also reads
    \\xHH and LDmicro's sign-extended \\xFFFFFFHH as the byte HH."""
    if token == "(none)":
        return ""

    def replace(match: re.Match) -> str:
        body = match.group(1)
        if body[0] in "xX" and len(body) > 1:
            return bytes([int(body[-2:] if len(body) > 3 else body[1:], 16)]).decode(
                codepage_codec(codepage)
            )
        return _READ_ESCAPES.get(body, "\\" + body)

    return _ESCAPE_RE.sub(replace, token)


# --- 8-bit code pages without loss --------------------------------------------

def _lossless_decode(error: UnicodeError):
    # bytes a code page leaves undefined (0x81 in cp1252...) become the C1
    # control with the same number, and are written back as that byte
    if isinstance(error, UnicodeDecodeError):
        chunk = error.object[error.start:error.end]
        return "".join(chr(b) for b in chunk), error.end
    if isinstance(error, UnicodeEncodeError):
        text = error.object[error.start:error.end]
        if all(ord(c) < 0x100 for c in text):
            return bytes(ord(c) for c in text), error.end
    raise error


codecs.register_error("ladder-lossless", _lossless_decode)


def codepage_codec(name: str) -> str:
    codecs.lookup(name)  # raises LookupError for an unknown encoding
    return name


def decode_bytes(data: bytes, encoding: str) -> str:
    return data.decode(encoding, errors="ladder-lossless")


def encode_text(text: str, encoding: str) -> bytes:
    return text.encode(encoding, errors="ladder-lossless")
