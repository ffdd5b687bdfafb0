"""Read and write LDmicro `.ld` project files (ldmicro-formats.md §3).

Reading: the grammar `ld.lark` gives the file's structure (header keys, the
IO LIST / VAR LIST / PULL-UP LIST sections, PROGRAM, RUNG / PARALLEL / SERIES
blocks, element lines split into a keyword and tokens); this module maps each
element line onto the instruction table, applies LDmicro's legacy defaults
(§2, §3.7), reads the header values (§3.3, §3.4) and normalises every rung
(§0.3). Bad input never raises: every problem is a located diagnostic and the
program holds everything that could be read.

Writing: LDmicro 5.4.1.1's own output (`SaveProjectToFile`), in the 0.2 form
or in 5.4's "Save as 0.1" form (long element forms, `RUNG` without a number,
FORMATTED_STRING as character codes, no COMPILER / PULL-UP LIST / VAR LIST).
A file in that form survives `.ld -> .ladder -> .ld` byte for byte but for the
few details the program model does not keep; any other file comes back in that
form (the README's "LDmicro's files" lists both, tests/test_ldfile_bytes.py
checks them on the corpus).

Choices where LDmicro's behaviour is not worth copying (see the report in
docs/):
* Keywords must match exactly (LDmicro compares prefixes, so `OSCX` is OSC).
* A rung starts at a line whose first word starts with `RUNG` (LDmicro takes
  any line that contains `RUNG` anywhere).
* A FORMATTED_STRING or STRING is read in the numeric (0.1) form only when
  all its tokens are integers, so a 0.2 text that starts with a digit is not
  mistaken for character codes; the writer escapes a leading digit or sign
  as `\\xHH` so LDmicro does not mistake it either.
* Comment trailing blanks are written as `\\x20` (LDmicro would lose them).
* The writer keeps CONTACTS `set1` as the model has it (LDmicro forces 0 for
  names that do not start with X), and writes every assigned pin to the IO
  LIST in both dialects (LDmicro's 0.1 writer keeps only X, Y and A names).
* A pin the text form gives by port bit (`PB5`) is written as its package
  pin number, the only form LDmicro reads there; one with no pin table to
  look it up in is an error (LD013, LD402) and the caller writes nothing.
* Lenient where LDmicro fails to load but the meaning is plain: trailing
  fields that have a default in the instruction table may be left out of any
  element line (`CONTACTS Xa`, `UART_SEND v 2`, a BUS without its bit list);
  0.1 character codes 128..255 (and LDmicro's negative ones) are read as
  characters of the code page instead of 'X'.
"""

from __future__ import annotations

import re
import threading
from collections.abc import Iterable
from pathlib import Path
from typing import Protocol, cast

from lark import Lark, Token, Transformer, Tree
from lark.exceptions import LarkError

from .codes import BAD_VALUE, LD_SYNTAX, UNREADABLE, code
from .devices import find_device, is_known_ldmicro_name, packages_of
from .diagnostics import Diagnostic, error, warning
from .instructions import INSTRUCTIONS, LD_KEYWORDS, Field, Instruction
from .iolist import io_list, listed_type
from .model import (
    Element,
    Node,
    Parallel,
    PinAssignment,
    Program,
    Rung,
    Series,
    Span,
    rung_circuit,
)
from .trampoline import Call, run
from .values import decode_bytes, encode_text, escape_ld, is_literal, literal_value, unescape_ld

__all__ = [
    "read_ld",
    "read_ld_bytes",
    "write_ld",
    "write_ld_bytes",
    "element_line",
    "package_pins",
    "ldmicro_part_name",
    "line_limit_diagnostics",
    "MAX_LINE_BYTES",
    "MAX_LIST_LINE_BYTES",
]

# §3.1: LDmicro reads program and header lines into 512-byte buffers and the
# lines of the three lists into 64-byte buffers (terminating NUL included).
MAX_LINE_BYTES = 511
MAX_LIST_LINE_BYTES = 63
MAX_NAME_BYTES = 63  # MAX_NAME_LEN 64
MAX_ENTRIES = 63  # MAX_ELEMENTS_IN_SUBCKT 64: the loader fails at the 64th entry
MAX_LUT_VALUES = 64

PORT_BIT_PIN = code("LD013")
PIN_NOT_ON_PART = code("LD402")

_GRAMMAR_PATH = Path(__file__).with_name("ld.lark")
_PARSER: Lark | None = None

_Children = list[Tree | Token]


class _Tok(Protocol):
    """A token as lark's lexer makes it: it always has a position (lark's
    Token type leaves the position optional, for tokens made by hand)."""

    @property
    def type(self) -> str: ...
    @property
    def value(self) -> str: ...
    @property
    def line(self) -> int: ...
    @property
    def column(self) -> int: ...
    @property
    def end_line(self) -> int: ...
    @property
    def end_column(self) -> int: ...


def _tok(node: Tree | Token) -> _Tok:
    """A child that the grammar makes a token."""
    return cast(_Tok, node)


class _Inline(Transformer):
    """The parser's callbacks: each header item, rung and stray line goes to
    the reader as soon as the parser has reduced it, and its tree is dropped.
    The tree of a whole file holds a dozen objects a line, more memory than
    the program read from it, and all of them at once."""

    def __init__(self) -> None:
        super().__init__()
        # the reader whose text is being parsed, set for the parse only; one per
        # thread, as the parser is shared
        self.current = threading.local()

    @property
    def reader(self) -> _Reader:
        return self.current.reader

    def header(self, children: _Children) -> None:
        self.reader.header_item(children)

    version = micro = cycle = crystal = baud = compiled = compiler = other = header
    io_list = var_list = pullup_list = header

    def program_head(self, children: _Children) -> None:
        self.reader.program_head(children)

    def rung(self, children: _Children) -> None:
        self.reader.rung(children)

    def stray(self, children: _Children) -> None:
        self.reader.stray(children)


_INLINE = _Inline()


def _parser() -> Lark:
    global _PARSER
    if _PARSER is None:
        _PARSER = Lark(
            _GRAMMAR_PATH.read_text(encoding="utf-8"),
            parser="lalr",
            lexer="contextual",
            maybe_placeholders=False,
            transformer=_INLINE,
            # the grammar's tables, built once and kept in the temporary folder by Lark: 2 ms to
            # load against 21 ms to build, in each process that reads an .ld file
            cache=True,
        )
    return _PARSER


# ==================================================================================
# reading
# ==================================================================================

# at most 40 digits: Python refuses to convert very long digit strings
_INT_RE = re.compile(r"[+-]?[0-9]{1,40}\Z")
_SPACE = " \t\r\f\v"  # C isspace() without the newline
_EDGES = ("/", "\\", "-", "o")

# header values, with sscanf's "a blank in the format matches any blanks"
_I = r"\s*([+-]?[0-9]{1,40})"
_CYCLE_FORMS = (
    re.compile(rf"CYCLE={_I}\s*us\s*at\s*Timer{_I},\s*YPlcCycleDuty:{_I},"
               r"\s*ConfigurationWord\(s\):\s*(?:0[xX])?([0-9A-Fa-f]+)"),
    re.compile(rf"CYCLE={_I}\s*us\s*at\s*Timer{_I},\s*YPlcCycleDuty:{_I},\s*WDTE:{_I}"),
    re.compile(rf"CYCLE={_I}\s*us\s*at\s*Timer{_I},\s*YPlcCycleDuty:{_I}"),
    re.compile(rf"CYCLE={_I}"),
)
_CRYSTAL_RE = re.compile(rf"CRYSTAL={_I}")
_BAUD_FORMS = (
    re.compile(rf"BAUD={_I}\s*Hz,\s*RATE={_I}\s*Hz,\s*SPEED={_I}\s*Hz"),
    re.compile(rf"BAUD={_I}\s*Hz,\s*RATE={_I}\s*Hz"),
    re.compile(rf"BAUD={_I}"),
)
_IO_RE = re.compile(r"[ \t]*(\S+)[ \t]+at[ \t]+(\S+)(?:[ \t]+(\S+))?(?:[ \t]+(\S+))?")
_DIGITS_RE = re.compile(r"[0-9]{1,40}")
_VAR_RE = re.compile(r"[ \t]*([+-]?[0-9]{1,40})[ \t]+bytes[ \t]+(\S+)((?:[ \t].*)?)\Z")
_VAR_LEGACY_RE = re.compile(r"[ \t]*(\S+)[ \t]+signed[ \t]+([+-]?[0-9]{1,40})[ \t]+bit variable\Z")
_PULLUP_RE = re.compile(r"[ \t]*(\S)(\S):[ \t]*0[xX]([0-9A-Fa-f]+)")


def read_ld(text: str, *, encoding: str = "cp1252") -> tuple[Program, list[Diagnostic]]:
    """Read the text of a `.ld` file. `encoding` is the code page that `\\xHH`
    escapes and 0.1 character codes refer to. Never raises on bad input."""
    return _Reader(text, encoding).read()


def read_ld_bytes(data: bytes, encoding: str = "cp1252") -> tuple[Program, list[Diagnostic]]:
    """Read a `.ld` file's bytes (LDmicro writes the ANSI code page)."""
    return read_ld(decode_bytes(data, encoding), encoding=encoding)


def _normalise_text(text: str) -> tuple[list[str], str]:
    """Lines with trailing blanks stripped (§3.1), and the text the grammar reads."""
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = [line.rstrip(_SPACE) for line in text.split("\n")]
    if lines and lines[-1] == "":
        lines.pop()
    return lines, "".join(line + "\n" for line in lines)


class _Reader:
    def __init__(self, text: str, encoding: str):
        self.lines, self.text = _normalise_text(text)
        self.encoding = encoding
        self.diags: list[Diagnostic] = []
        self.program = Program()
        self.settings = self.program.settings
        self.seen_micro = False
        self.seen_program = False
        self.first_line_warned = -1

    # --- helpers ---------------------------------------------------------------------

    def line_text(self, index: int) -> str:
        return self.lines[index] if 0 <= index < len(self.lines) else ""

    def line_span(self, tok: _Tok) -> Span:
        """From the token to the end of its line."""
        index = tok.line - 1
        return Span(index, tok.column - 1, index, max(len(self.line_text(index)), tok.column))

    @staticmethod
    def tok_span(tok: _Tok) -> Span:
        return Span(tok.line - 1, tok.column - 1, tok.end_line - 1, tok.end_column - 1)

    def quoted(self, tok: _Tok) -> str:
        return repr(self.line_text(tok.line - 1).strip())[1:-1]

    def err(self, code: str, message: str, span: Span | None) -> None:
        self.diags.append(error(code, message, span))

    def warn(self, code: str, message: str, span: Span | None) -> None:
        self.diags.append(warning(code, message, span))

    # --- the whole file ----------------------------------------------------------------

    def read(self) -> tuple[Program, list[Diagnostic]]:
        try:
            self.read_text()
        except RecursionError:
            self.err(UNREADABLE, "blocks nested too deeply to read", Span.at(0, 0))
        except Exception as exc:  # never raise on bad input; tests assert this never happens
            self.err(UNREADABLE, f"internal error while reading the .ld file: "
                     f"{type(exc).__name__}: {exc}", Span.at(0, 0))
        self.diags.sort(key=lambda d: (d.span.line, d.span.col) if d.span else (-1, -1))
        return self.program, self.diags

    def read_text(self) -> None:
        """The parser hands each part to this reader as it reads it (_Inline)."""
        self.check_first_line()
        _INLINE.current.reader = self
        try:
            _parser().parse(self.text)
        except LarkError as exc:  # the grammar accepts every text; this is a safety net
            # a file the parser gives up on is not read at all, not even the part before
            self.program = Program()
            self.settings = self.program.settings
            line = getattr(exc, "line", 1) or 1
            self.diags = [error(UNREADABLE, f"cannot read the file as an LDmicro .ld file: {exc}",
                                Span.at(max(line - 1, 0), 0))]
            return
        finally:
            del _INLINE.current.reader
        if not self.seen_program:
            self.err(UNREADABLE, "no PROGRAM line: this is not an LDmicro .ld file "
                     "(or it is cut short before its program)",
                     Span.at(max(len(self.lines) - 1, 0), 0))

    def check_first_line(self) -> None:
        for index, line in enumerate(self.lines):
            if line.strip():
                if not line.startswith("LDmicro"):
                    self.first_line_warned = index
                    self.warn(LD_SYNTAX, f"the file does not start with an LDmicro version line "
                              f"(LDmicro0.1 or LDmicro0.2): {line.strip()[:60]!r}",
                              Span(index, 0, index, len(line)))
                return

    # --- header (§3.3) ------------------------------------------------------------------

    def header_item(self, children: _Children) -> None:
        tok = _tok(children[0])
        kind = tok.type
        if kind in ("IO_LIST", "VAR_LIST", "PULLUP_LIST"):
            self.column_zero(tok)
            self.section(tok, children[1:])
            return
        value = tok.value
        span = self.line_span(tok)
        if kind == "OTHER":
            if value.strip() and tok.line - 1 != self.first_line_warned:
                self.warn(LD_SYNTAX, f"unknown header line ignored: '{self.quoted(tok)}'", span)
            return
        self.column_zero(tok)
        if kind == "VERSION":
            number = value[len("LDmicro"):].strip()
            # LDmicro reads every header but 0.1 as 0.2; some 5.x releases write a bare
            # `LDmicro`, kept as the empty version so the file is written back as it was
            if number not in ("0.1", "0.2", ""):
                self.warn(LD_SYNTAX, f"unknown file version '{value}': read as LDmicro0.2", span)
                number = "0.2"
            self.settings.ld_version = number
        elif kind == "MICRO":
            self.seen_micro = True
            name = value[len("MICRO="):]
            self.settings.mcu = name or None
            self.settings.mcu_span = span
        elif kind == "CYCLE":
            self.cycle(value, span)
        elif kind == "CRYSTAL":
            match = _CRYSTAL_RE.match(value)
            if match:
                self.settings.crystal_hz = int(match.group(1))
            else:
                self.bad_header(tok, "the crystal frequency is not a number")
        elif kind == "BAUD":
            self.baud(tok)
        elif kind == "COMPILED":
            self.settings.compiled = value[len("COMPILED="):] or None
        elif kind == "COMPILER":
            self.settings.compiler = value[len("COMPILER="):].strip() or None

    def column_zero(self, tok: _Tok) -> None:
        if tok.column != 1:
            self.warn(LD_SYNTAX, f"'{tok.value}' must start in column 1: LDmicro ignores an "
                      "indented header line", self.line_span(tok))

    def bad_header(self, tok: _Tok, why: str) -> None:
        self.err(LD_SYNTAX, f"{why}; the default is kept: '{self.quoted(tok)}'", self.line_span(tok))

    def cycle(self, value: str, span: Span) -> None:
        s = self.settings
        for number, form in enumerate(_CYCLE_FORMS):
            match = form.match(value)
            if not match:
                continue
            s.cycle_us = int(match.group(1))
            if number < 3:
                timer = int(match.group(2))
                s.cycle_timer = timer if timer in (0, 1, 3) else 1
                s.cycle_duty = int(match.group(3)) != 0
                if number == 0:
                    s.config_word = int(match.group(4), 16)
            else:
                s.cycle_timer = 1
                s.cycle_duty = False
            if s.cycle_us == 0:
                s.cycle_timer = -1
            return
        self.diags.append(error(LD_SYNTAX, f"the cycle time is not a number; the default "
                                f"is kept: '{value}'", span))

    def baud(self, tok: _Tok) -> None:
        s = self.settings
        for number, form in enumerate(_BAUD_FORMS):
            match = form.match(tok.value)
            if match:
                s.baud = int(match.group(1))
                # LDmicro: a BAUD line without RATE / SPEED sets those rates to 0
                s.spi_rate = int(match.group(2)) if number < 2 else 0
                s.i2c_rate = int(match.group(3)) if number < 1 else 0
                return
        self.bad_header(tok, "the baud rate is not a number")

    # --- IO LIST / VAR LIST / PULL-UP LIST (§3.4) --------------------------------------------

    def section(self, head: _Tok, children: _Children) -> None:
        closed = False
        for child in children:
            if not isinstance(child, Tree):
                continue
            if child.data == "section_end":
                closed = True
            elif child.data == "entry":
                tok = _tok(child.children[0])
                if head.type == "IO_LIST":
                    self.io_entry(tok)
                elif head.type == "VAR_LIST":
                    self.var_entry(tok)
                else:
                    self.pullup_entry(tok)
        if not closed:
            self.err(LD_SYNTAX, f"'{head.value}' is not closed: END missing before the next "
                     "header line", self.line_span(head))

    def io_entry(self, tok: _Tok) -> None:
        line = self.line_text(tok.line - 1)
        span = Span(tok.line - 1, 0, tok.line - 1, len(line))
        match = _IO_RE.match(line)
        if not match:
            self.warn(LD_SYNTAX, f"line skipped in IO LIST (expected 'name at pin'): "
                      f"'{self.quoted(tok)}'", span)
            return
        name, pin_text, slave_text, reg_text = match.groups()
        if listed_type(name) is None:
            self.warn(LD_SYNTAX, f"line skipped in IO LIST: '{name}' is no pin name "
                      f"(X, Y, A, P, I, M, C or H): '{self.quoted(tok)}'", span)
            return
        if name[1:] == "new":  # LDmicro never remembers the editor's default names
            return
        pin: int | str
        digits = _DIGITS_RE.match(pin_text)
        if digits:
            pin = int(digits.group(0))
            slave = self.small_int(slave_text, tok, span)
            register = self.small_int(reg_text, tok, span)
            if not (pin or slave or register):
                return  # not assigned: the writer lists every I/O name the program uses
        else:
            pin, slave, register = pin_text, 0, 0
        self.program.pins.pop(name, None)
        self.program.pins[name] = PinAssignment(name, pin, slave, register, span)

    def small_int(self, text: str | None, tok: _Tok, span: Span) -> int:
        if text is None:
            return 0
        if _INT_RE.match(text):
            return int(text)
        self.warn(LD_SYNTAX, f"Modbus address '{text}' is not a number; 0 is used: "
                  f"'{self.quoted(tok)}'", span)
        return 0

    def var_entry(self, tok: _Tok) -> None:
        line = self.line_text(tok.line - 1)
        span = Span(tok.line - 1, 0, tok.line - 1, len(line))
        match = _VAR_RE.match(line)
        note = ""
        if match:
            size, name = int(match.group(1)), match.group(2)
            note = match.group(3) if match.group(3).strip() else ""
        else:
            match = _VAR_LEGACY_RE.match(line)
            if not match:
                self.err(LD_SYNTAX, f"cannot read this VAR LIST line (expected "
                         f"'<bytes> bytes <name>'): '{self.quoted(tok)}'", span)
                return
            name, size = match.group(1), (int(match.group(2)) + 7) // 8
        self.program.var_sizes.pop(name, None)
        self.program.var_sizes[name] = size
        self.program.var_notes.pop(name, None)
        if note:
            self.program.var_notes[name] = note

    def pullup_entry(self, tok: _Tok) -> None:
        line = self.line_text(tok.line - 1)
        span = Span(tok.line - 1, 0, tok.line - 1, len(line))
        match = _PULLUP_RE.match(line)
        if not match:
            self.warn(LD_SYNTAX, f"line skipped in PULL-UP LIST (expected 'PB: 0xFF'): "
                      f"'{self.quoted(tok)}'", span)
            return
        if not self.seen_micro:
            self.warn(LD_SYNTAX, "PULL-UP LIST entry ignored: LDmicro applies it only after "
                      f"a MICRO= line: '{self.quoted(tok)}'", span)
            return
        port = match.group(1) + match.group(2)
        self.program.pullups.pop(port, None)
        self.program.pullups[port] = int(match.group(3), 16)

    # --- PROGRAM (§3.5) ------------------------------------------------------------------

    def program_head(self, children: _Children) -> None:
        self.seen_program = True
        self.column_zero(_tok(children[0]))

    def stray(self, children: _Children) -> None:
        tok = _tok(children[0])
        span = self.line_span(tok)
        if tok.type == "END":
            message = "END without an open RUNG, PARALLEL or SERIES"
        elif tok.type == "SKIP":
            message = "a ';' line between rungs (LDmicro allows them only inside a rung)"
        else:
            message = "only RUNG lines may stand between rungs"
        self.err(LD_SYNTAX, f"{message}: '{self.quoted(tok)}'", span)

    def rung(self, children: _Children) -> None:
        head = _tok(children[0])
        number = len(self.program.rungs) + 1
        items, end = self.body(children, head, in_parallel=False, what=f"RUNG {number}")
        span = self.line_span(head)
        circuit = Series(items, self.block_span(head, end))
        self.program.rungs.append(Rung(rung_circuit(circuit), span))

    def block_span(self, head: _Tok, end: _Tok | None) -> Span:
        if end is None:
            return self.line_span(head)
        return Span(head.line - 1, head.column - 1, end.line - 1, end.end_column - 1)

    def body(self, children: _Children, head: _Tok, in_parallel: bool, what: str
             ) -> tuple[list[Node], _Tok | None]:
        """The nodes of a block, and its END; `children` are its tree's."""
        return run(self._body(children, head, in_parallel, what))

    def _body(self, children: _Children, head: _Tok, in_parallel: bool, what: str
              ) -> Call[tuple[list[Node], _Tok | None]]:
        items: list[Node] = []
        end: _Tok | None = None
        entries = 0
        for child in children[1:]:
            if not isinstance(child, Tree):
                continue
            first = _tok(child.children[0])
            if child.data == "block_end":
                end = first
                continue
            entries += 1
            if entries == MAX_ENTRIES + 1:
                self.err(LD_SYNTAX, f"{what} has more than {MAX_ENTRIES} entries: LDmicro "
                         "cannot load it (split it with SERIES / PARALLEL)",
                         self.line_span(first))
            if child.data == "element":
                element = self.element(first, child.children[1:])
                if element is not None:
                    items.append(element)
            elif child.data == "parallel":
                if in_parallel:
                    self.err(LD_SYNTAX, "PARALLEL directly inside a PARALLEL: LDmicro cannot "
                             "load it; put the inner PARALLEL in a SERIES",
                             self.line_span(first))
                branches, pend = yield self._body(child.children, first, True, "PARALLEL")
                items.append(Parallel(branches, self.block_span(first, pend)))
            elif child.data == "series":
                inner, send = yield self._body(child.children, first, False, "SERIES")
                items.append(Series(inner, self.block_span(first, send)))
        if end is None:
            self.err(LD_SYNTAX, f"{what} is not closed: END missing "
                     f"('{self.quoted(head)}' has no matching END)", self.line_span(head))
        return items, end

    # --- element lines (§2, §3.7) -----------------------------------------------------------

    def element(self, keyword: _Tok, operands: _Children) -> Element | None:
        """An element line: its keyword and its operand tokens."""
        toks = cast(list[_Tok], operands)
        instruction = LD_KEYWORDS.get(keyword.value)
        span = self.line_span(keyword)
        if instruction is None:
            if keyword.value.startswith("RUNG"):
                message = "RUNG inside a rung"
            else:
                message = f"unknown element keyword '{keyword.value}'"
            self.err(LD_SYNTAX, f"{message}: '{self.quoted(keyword)}'", self.tok_span(keyword))
            return None
        line = _ElementLine(self, instruction, keyword, toks, span)
        try:
            args = getattr(line, "form_" + instruction.ld_form)()
        except _BadLine:
            return None
        if args is None:
            return None
        line.check_names(args)
        return Element(instruction.key, args, span, line.arg_spans)


class _BadLine(Exception):
    """The element line cannot be read (its diagnostic is already recorded)."""


class _ElementLine:
    """One element line being mapped onto its instruction's fields."""

    def __init__(self, reader: _Reader, instruction: Instruction, keyword: _Tok,
                 toks: list[_Tok], span: Span):
        self.r = reader
        self.ins = instruction
        self.kw = keyword
        self.toks = toks
        self.span = span
        # every span of the line holds this one int: a program keeps a dozen spans a rung
        self.row = span.line
        self.arg_spans: dict[str, Span] = {}
        self.raw = reader.line_text(self.row)

    # --- diagnostics ---------------------------------------------------------------------

    def fail(self, message: str, span: Span | None = None, code: str = LD_SYNTAX):
        self.r.err(code, f"{message}: '{self.r.quoted(self.kw)}'", span or self.span)
        raise _BadLine()

    def tok_span(self, first: _Tok, last: _Tok | None = None) -> Span:
        """From the token to the `last` one, on the line (a token never spans lines)."""
        end = first if last is None else last
        return Span(self.row, first.column - 1, self.row, end.end_column - 1)

    def end_span(self) -> Span:
        return Span(self.row, len(self.raw), self.row, len(self.raw) + 1)

    def missing(self, needed: str) -> None:
        self.fail(f"{self.kw.value} needs {needed}, found {len(self.toks)} "
                  f"operand{'s' if len(self.toks) != 1 else ''}", self.end_span())

    def extra(self, used: int) -> None:
        if len(self.toks) > used:
            first = self.toks[used]
            self.r.warn(LD_SYNTAX, f"extra operands after {self.kw.value} ignored: "
                        f"'{self.r.quoted(self.kw)}'",
                        Span(self.row, first.column - 1, self.row, len(self.raw)))

    def rest_of_line(self, tok: _Tok) -> str:
        return self.raw[tok.column - 1:]

    def check_names(self, args: dict) -> None:
        for field in self.ins.fields:
            value = args.get(field.name)
            if field.kind in ("bit", "var", "operand", "label", "token") and isinstance(value, str):
                if len(value) > MAX_NAME_BYTES:
                    self.r.err(BAD_VALUE, f"'{value[:20]}...' is longer than {MAX_NAME_BYTES} "
                               "characters: LDmicro's loader overflows on it",
                               self.arg_spans.get(field.name, self.span))

    # --- values --------------------------------------------------------------------------

    def take(self, field: Field, tok: _Tok) -> object:
        self.arg_spans[field.name] = self.tok_span(tok)
        return self.convert(field, tok)

    def convert(self, field: Field, tok: _Tok) -> object:
        text = tok.value
        kind = field.kind
        if kind == "flag":
            return 1 if self.integer(tok, f"{field.name} (0 or 1)") != 0 else 0
        if kind == "int":
            return self.integer(tok, field.name)
        if kind == "delay":
            return self.delay(tok)
        if kind == "edge":
            if text not in _EDGES:
                self.fail(f"'{text}' is no counting edge (/ rising, \\ falling, - or o level)",
                          self.tok_span(tok))
            return text
        return text

    def integer(self, tok: _Tok, what: str) -> int:
        if not _INT_RE.match(tok.value):
            self.fail(f"{self.kw.value} {what} must be a whole number, not '{tok.value}'",
                      self.tok_span(tok), BAD_VALUE)
        return int(tok.value)

    def delay(self, tok: _Tok) -> int | str:
        """Microseconds as an int, or the name of a variable holding scan cycles."""
        text = tok.value
        if _INT_RE.match(text):
            return int(text)
        if is_literal(text):
            try:
                return literal_value(text)
            except ValueError:
                self.fail(f"bad delay '{text}' (microseconds or a variable name)",
                          self.tok_span(tok), BAD_VALUE)
        return text

    # --- forms ---------------------------------------------------------------------------

    def form_fields(self) -> dict:
        args: dict[str, object] = {}
        fields = self.ins.fields
        for index, field in enumerate(fields):
            if index < len(self.toks):
                args[field.name] = self.take(field, self.toks[index])
            elif field.optional:
                args[field.name] = None
            elif field.default is not None:
                args[field.name] = self.legacy_default(field)
            else:
                required = [f.name for f in fields if f.default is None and not f.optional]
                self.missing(f"{len(required)} operand{'s' if len(required) != 1 else ''} "
                             f"({' '.join(required)})")
        self.extra(len(fields))
        return args

    def legacy_default(self, field: Field) -> object:
        if field.name == "adjust" and self.ins.key in ("TON", "TOF", "RTO"):
            # classic period = delay / cycle - 1 (§2.5)
            return -1 if self.r.settings.ld_version == "0.1" else 0
        return field.default

    def form_quad(self) -> dict:
        args = self.form_fields()
        for name in ("z", "dir"):
            args[name] = unescape_ld(str(args[name]), self.r.encoding) if args[name] else ""
        return args

    def form_coil(self) -> dict:
        if len(self.toks) < 4:
            self.missing("a name and 3 or 4 flags (negated setOnly resetOnly [toggle])")
        name_field = self.ins.fields[0]
        name = self.take(name_field, self.toks[0])
        flag = Field("flag", "flag")
        flags = [self.convert(flag, tok) for tok in self.toks[1:5]]
        coil_type = " "
        for value, symbol in zip(flags, "/SRT"):
            if value:
                coil_type = symbol
                break
        self.arg_spans["type"] = self.tok_span(self.toks[1], self.toks[min(len(self.toks), 5) - 1])
        self.extra(5)
        return {"name": name, "type": coil_type}

    def form_comment(self) -> dict:
        raw = self.raw[self.kw.column - 1 + len("COMMENT") + 1:]
        lines = unescape_ld(raw, self.r.encoding).replace("\r\n", "\n").split("\n")
        # the drawing cannot show the blanks that end a line: they are kept apart (a tab there
        # is dropped)
        stripped = [line.rstrip(" \t") for line in lines]
        ends = tuple(str(len(line) - len(line.rstrip(" "))) for line in lines)
        return {"text": "\n".join(stripped), "line_ends": ends if any(end != "0" for end in ends) else ()}

    def form_sleep(self) -> dict:
        name = self.toks[0].value if self.toks else ""
        delay = self.toks[1].value if len(self.toks) > 1 else ""
        for field, tok in zip(self.ins.fields, self.toks):
            self.arg_spans[field.name] = self.tok_span(tok)
        self.extra(2)
        return {"name": name, "delay": delay}

    def form_setpwm(self) -> dict:
        if len(self.toks) < 2:
            self.missing("a duty cycle and a frequency")
        duty_tok, freq_tok = self.toks[0], self.toks[1]
        self.arg_spans["duty"] = self.tok_span(duty_tok)
        self.arg_spans["freq"] = self.tok_span(freq_tok)
        whole = freq_tok.value.split(".", 1)[0]  # LDmicro drops the fractional part
        if not _INT_RE.match(whole):
            self.fail(f"SET_PWM frequency must be a number of hertz, not '{freq_tok.value}'",
                      self.tok_span(freq_tok), BAD_VALUE)
        name = ""
        if len(self.toks) > 2:
            name = self.toks[2].value
            self.arg_spans["name"] = self.tok_span(self.toks[2])
        if not name.startswith("P"):
            name = "P" + name  # old files; an empty classic name becomes "P"
        resolution = ""
        if len(self.toks) > 3:
            resolution = self.toks[3].value
            self.arg_spans["resolution"] = self.tok_span(self.toks[3])
        # further tokens (the rest of the dialog text) are ignored, as by LDmicro
        return {"duty": duty_tok.value, "freq": int(whole), "name": name,
                "resolution": resolution}

    def numeric_text(self, toks: list[_Tok]) -> str | None:
        """The 0.1 form `n c1 ... cn` (character codes), or None if these tokens
        are not all integers (then they are the 0.2 escaped text)."""
        if not toks or not all(_INT_RE.match(t.value) for t in toks):
            return None
        count = int(toks[0].value)
        codes = toks[1:]
        if count < 0 or (not codes and count > 0):
            return None  # a lone number: the 0.2 text "3" rather than three missing codes
        if len(codes) < count:
            self.fail(f"{self.kw.value} announces {count} character codes but has "
                      f"{len(codes)}", self.end_span())
        if len(codes) > count:
            self.extra(len(self.toks) - len(codes) + count)
        out = []
        for tok in codes[:count]:
            byte = int(tok.value) & 0xFF
            # LDmicro replaces codes below 32 (signed char: also 128..255) by 'X';
            # bytes 128..255 are read here as characters of the code page
            out.append("X" if byte < 32 else decode_bytes(bytes([byte]), self.r.encoding))
        return "".join(out)

    def text_from(self, tok: _Tok) -> str:
        text = unescape_ld(self.rest_of_line(tok), self.r.encoding)
        return text.replace("\n", "")  # LDmicro removes line feeds from these texts

    @staticmethod
    def none(text: str) -> str:
        return "" if text == "(none)" else text

    def form_fstring(self) -> dict:
        if len(self.toks) < 2:
            self.missing("a variable (or (none)) and a text")
        var_tok = self.toks[0]
        self.arg_spans["var"] = self.tok_span(var_tok)
        text = self.numeric_text(self.toks[1:])
        if text is None:
            text = self.text_from(self.toks[1])
        first, last = self.toks[1], self.toks[-1]
        self.arg_spans["text"] = self.tok_span(first, last)
        return {"var": self.none(var_tok.value), "text": text}

    def form_string(self) -> dict:
        if len(self.toks) < 3:
            self.missing("a destination, a variable and a format text (each may be (none))")
        dest_tok, var_tok = self.toks[0], self.toks[1]
        self.arg_spans["dest"] = self.tok_span(dest_tok)
        self.arg_spans["var"] = self.tok_span(var_tok)
        text = self.numeric_text(self.toks[2:])
        if text is None:
            text = self.text_from(self.toks[2])
        first, last = self.toks[2], self.toks[-1]
        self.arg_spans["text"] = self.tok_span(first, last)
        return {"dest": self.none(dest_tok.value), "var": self.none(var_tok.value), "text": text}

    def table_head(self, what: str) -> tuple[str, str, int]:
        dest_tok, index_tok, count_tok = self.toks[0], self.toks[1], self.toks[2]
        self.arg_spans["dest"] = self.tok_span(dest_tok)
        self.arg_spans["index"] = self.tok_span(index_tok)
        count = self.integer(count_tok, f"{what} count")
        if count < 0:
            self.fail(f"{self.kw.value} count must not be negative", self.tok_span(count_tok),
                      BAD_VALUE)
        return dest_tok.value, index_tok.value, count

    def values_span(self, first: int, count: int) -> Span | None:
        if count:
            a, b = self.toks[first], self.toks[first + count - 1]
            return self.tok_span(a, b)
        return None

    def form_lut(self) -> dict:
        if len(self.toks) < 4:
            self.missing("dest index count asString, then the values")
        dest, index, count = self.table_head("value")
        as_string = self.convert(Field("as_string", "flag"), self.toks[3])
        self.arg_spans["as_string"] = self.tok_span(self.toks[3])
        values = self.toks[4:4 + count]
        if len(values) < count:
            self.fail(f"LOOK_UP_TABLE announces {count} values but has {len(values)}",
                      self.end_span())
        span = self.values_span(4, count)
        if span:
            self.arg_spans["values"] = span
        if count > MAX_LUT_VALUES:
            self.r.err(BAD_VALUE, f"LOOK_UP_TABLE has {count} values; LDmicro holds at most "
                       f"{MAX_LUT_VALUES}: '{self.r.quoted(self.kw)}'",
                       span or self.span)
        if len(self.toks) > 4 + count:
            name_tok = self.toks[4 + count]
            table = name_tok.value
            self.arg_spans["table"] = self.tok_span(name_tok)
            self.extra(5 + count)
        else:
            table = f"{dest}{count}"  # classic files: the table is named after dest and count
        return {"dest": dest, "index": index, "values": tuple(t.value for t in values),
                "as_string": as_string, "table": table}

    def form_pwl(self) -> dict:
        if len(self.toks) < 3:
            self.missing("dest index count, then the points")
        dest, index, count = self.table_head("point")
        values = self.toks[3:3 + 2 * count]
        if len(values) < 2 * count:
            self.fail(f"PIECEWISE_LINEAR announces {count} points ({2 * count} numbers) but "
                      f"has {len(values)} numbers", self.end_span())
        span = self.values_span(3, 2 * count)
        if span:
            self.arg_spans["points"] = span
        points = tuple((values[i].value, values[i + 1].value) for i in range(0, 2 * count, 2))
        table = ""
        if len(self.toks) > 3 + 2 * count:
            name_tok = self.toks[3 + 2 * count]
            table = name_tok.value
            self.arg_spans["table"] = self.tok_span(name_tok)
            self.extra(4 + 2 * count)
        return {"dest": dest, "index": index, "points": points, "table": table}


# ==================================================================================
# writing
# ==================================================================================


def write_ld(program: Program, version: str | None = None, *, encoding: str = "cp1252",
             diagnostics: list[Diagnostic] | None = None) -> str:
    """The `.ld` text LDmicro 5.4 writes for this program, with LF line ends.

    `version` "0.2", "0.1" or "" (a bare `LDmicro` header, read as 0.2;
    default: the program's Settings.ld_version).
    `encoding` is the code page the 0.1 character codes are counted in.
    Lines longer than LDmicro reads (511 bytes; 63 in the three lists) are
    written anyway; each is reported as a warning diagnostic appended to
    `diagnostics` (commands pass a list and print them).
    """
    version = program.settings.ld_version if version is None else version
    if version not in ("0.1", "0.2", ""):
        raise ValueError(f"unknown .ld version {version!r}: use '0.1', '0.2' or ''")
    s = program.settings
    out: list[str] = [f"LDmicro{version}"]
    # (line index, limit, span) of every line that must respect §3.1
    if s.mcu:
        out.append(f"MICRO={ldmicro_part_name(s.mcu)}")
    timer = -1 if s.cycle_us == 0 else s.cycle_timer
    out.append(f"CYCLE={s.cycle_us} us at Timer{timer}, YPlcCycleDuty:{int(bool(s.cycle_duty))}, "
               f"ConfigurationWord(s):0x{s.config_word:X}")
    out.append(f"CRYSTAL={s.crystal_hz} Hz")
    out.append(f"BAUD={s.baud} Hz, RATE={s.spi_rate} Hz, SPEED={s.i2c_rate} Hz")
    if s.compiled:
        out.append(f"COMPILED={s.compiled}")
    list_lines: set[int] = set()
    if version != "0.1":
        if s.compiler:
            out.append(f"COMPILER={s.compiler}")
        out += ["", "PULL-UP LIST"]
        for port, value in program.pullups.items():
            list_lines.add(len(out))
            out.append(f"    {port}: 0x{value:X} ")
        out += ["END", "", "VAR LIST"]
        for name, size in program.var_sizes.items():
            list_lines.add(len(out))
            out.append(f"  {size:3d} bytes {name}{program.var_notes.get(name, '')}")
        out.append("END")
    out += ["", "IO LIST"]
    numbers, unwritable = package_pins(program)
    for io in io_list(program, encoding):
        if version == "0.1" and io.name[0] not in "XYA" and io.name not in program.pins:
            continue  # LDmicro's 0.1 writer lists only X, Y and A names (and loses the others' pins)
        pin = program.pins.get(io.name) or PinAssignment(io.name, 0)
        list_lines.add(len(out))
        out.append(f"    {pin.name} at {numbers.get(pin.name, pin.pin)} {pin.modbus_slave} {pin.modbus_register}")
    out += ["END", "", "PROGRAM"]
    spans: dict[int, Span | None] = {}
    for number, rung in enumerate(program.rungs, 1):
        out.append("RUNG" if version == "0.1" else f"RUNG {number}")
        _write_circuit(rung_circuit(rung.circuit), out, spans, version, encoding)
        out.append("END")
    text = "\n".join(out) + "\n"
    if unwritable and diagnostics is None:
        raise ValueError("; ".join(d.message for d in unwritable))
    if diagnostics is not None:
        diagnostics.extend(unwritable)
        diagnostics.extend(line_limit_diagnostics(out, encoding, list_lines, spans))
        if version == "0.1":
            diagnostics.extend(_control_characters(program))
    return text


def ldmicro_part_name(mcu: str) -> str:
    """The name LDmicro knows a part by (`Atmel AVR ATmega328 28-PDIP`) for
    one of textladder's (`atmega328p`, `m328p:32-TQFP`): LDmicro refuses a
    MICRO= line it does not list. A name LDmicro lists, or a part it does not
    (the PIC16F877A), is kept as it is."""
    if is_known_ldmicro_name(mcu):
        return mcu
    device = find_device(mcu)
    return device.ldmicro_name if device is not None and device.ldmicro_name else mcu


def package_pins(program: Program) -> tuple[dict[str, int], list[Diagnostic]]:
    """The package pin number of every pin given by port bit (`PB5`, `RB0`,
    `ADC6`), from the pin table of the program's part and package, and an
    error for each that has none there. LDmicro's IO LIST holds only package
    pin numbers and reads the field as a number: `Yled at PB5` is pin 0 to it,
    "not assigned"."""
    numbers: dict[str, int] = {}
    problems: list[Diagnostic] = []
    mcu = program.settings.mcu
    device = find_device(mcu) if mcu else None
    for name, assignment in program.pins.items():
        text = assignment.pin
        if isinstance(text, int):
            continue
        if not assignment.assigned:  # "" or "0": LDmicro's unassigned pin
            numbers[name] = 0
            continue
        pin = device.pin(text) if device is not None else None
        if pin is not None:
            numbers[name] = pin.number
            continue
        if device is None:
            table = f"textladder has no pin table for '{mcu}'" if mcu else "the program names no part"
            problems.append(error(PORT_BIT_PIN, f"'{name}' is at {text}, a port bit, and {table} to look up its "
                                                "package pin number in (an .ld file's IO LIST holds numbers only): "
                                                "choose a part, or give the pin by number", assignment.span))
            continue
        elsewhere = [other.package for other in packages_of(device.part) if other.pin(text) is not None]
        where = (f"has only in its {' and '.join(elsewhere)} package, not in the {device.package} of the program"
                 if elsewhere else f"({device.package}) does not have")
        problems.append(error(PIN_NOT_ON_PART, f"'{name}' is assigned to {text}, which the {device.title} {where}",
                              assignment.span))
    return numbers, problems


def _control_characters(program: Program) -> list[Diagnostic]:
    """The 0.1 dialect stores a formatted string as character codes, and
    LDmicro reads every code below 32 as 'X': a tab or line end is lost."""
    return [warning(LD_SYNTAX, f"{element.kind} text has a control character ({ord(ch):#04x}); the LDmicro0.1 "
                               "file stores it as a character code that LDmicro reads as 'X' (save as LDmicro0.2 "
                               "to keep it)", element.span)
            for _, element in program.elements() if element.kind == "FORMATTED_STRING"
            for ch in [next((c for c in str(element.args.get("text", "")) if ord(c) < 32), None)] if ch]


def write_ld_bytes(program: Program, encoding: str = "cp1252", newline: str = "\r\n",
                   version: str | None = None,
                   diagnostics: list[Diagnostic] | None = None) -> bytes:
    """The `.ld` file's bytes: LDmicro writes the ANSI code page and CRLF."""
    text = write_ld(program, version, encoding=encoding, diagnostics=diagnostics)
    return encode_text(text.replace("\n", newline), encoding)


def _write_circuit(circuit: Series, out: list[str], spans: dict, version: str, encoding: str) -> None:
    """A rung's lines: its root series is the rung, written without SERIES."""
    # (nodes still to write, their depth, whether they are a parallel's branches,
    # the line that closes them), innermost last: a loop, not recursion, as
    # blocks may nest a thousand deep
    frames = [(iter(circuit.items), 1, False, None)]
    while frames:
        rest, depth, in_parallel, closing = frames[-1]
        for node in rest:
            if isinstance(node, Element):
                spans[len(out)] = node.span
                out.append("  " * depth + element_line(node, version, encoding))
            else:
                frames.append(_open_block(node, depth, in_parallel, out))
                break
        else:
            frames.pop()
            if closing is not None:
                out.append(closing)


def _open_block(node: Series | Parallel, depth: int, in_parallel: bool, out: list[str]):
    """Writes a block's opening line, if it has one; the frame of its contents."""
    pad = "  " * depth
    if isinstance(node, Parallel):
        if in_parallel:  # never in a normalised tree; LDmicro needs a SERIES between
            out.append(pad + "SERIES")
            return iter([node]), depth + 1, False, pad + "END"
        out.append(pad + "PARALLEL")
        return iter(node.branches), depth + 1, True, pad + "END"
    if not in_parallel:  # a series in a series is spliced into it
        return iter(node.items), depth, False, None
    out.append(pad + "SERIES")
    return iter(node.items), depth + 1, False, pad + "END"


def _text_token(text: str) -> str:
    """A FORMATTED_STRING / STRING text as one token (spaces as \\x20). A leading
    digit or sign is escaped so that no reader takes the text for the 0.1
    character-code form; `(none)` itself is escaped so it is not read as empty."""
    token = escape_ld(text, True)
    if text and (re.match(r"[+-]?[0-9]", token) or text == "(none)"):
        token = f"\\x{ord(token[0]):X}" + token[1:]
    return token


def _comment_token(text: str, line_ends: Iterable[object] = ()) -> str:
    ends = [int(str(end)) for end in line_ends]
    lines = text.split("\n")
    if len(ends) == len(lines):
        text = "\n".join(line + " " * end for line, end in zip(lines, ends))
    token = escape_ld(text.replace("\n", "\r\n"), False)
    if text == "(none)":
        token = "\\x28" + token[1:]
    return token


def _str(value: object) -> str:
    if isinstance(value, bool):
        return str(int(value))
    return str(value)


def element_line(element: Element, version: str = "0.2", encoding: str = "cp1252") -> str:
    """One element as LDmicro 5.4 writes it in a `.ld` file (no indentation)."""
    ins = INSTRUCTIONS[element.kind]
    a = element.args
    form = ins.ld_form
    key = ins.key
    if form == "comment":
        return f"COMMENT {_comment_token(str(a.get('text', '')), cast(Iterable[object], a.get('line_ends', ())))}"
    if form == "coil":
        flags = [int(a.get("type", " ") == symbol) for symbol in "/SRT"]
        return f"COIL {a['name']} " + " ".join(map(str, flags))
    # LDmicro 5.4 writes every operand of SET_PWM, SLEEP and the two tables, an
    # empty one too (one from an older file): the line then ends in blanks
    if form == "setpwm":
        return " ".join([key] + [_str(a.get(name, "")) for name in ("duty", "freq", "name", "resolution")])
    if form == "sleep":
        return " ".join([key] + [_str(a.get(name, "")) for name in ("name", "delay")])
    if form == "fstring":
        var = _str(a.get("var") or "(none)")
        text = str(a.get("text", ""))
        if version == "0.1":
            codes = encode_text(text, encoding)
            return " ".join([key, var, str(len(codes))] + [str(c) for c in codes])
        return f"{key} {var} {_text_token(text)}"
    if form == "string":
        # always the text form: the 5.4 reader does not read STRING's numeric form (§3.7)
        dest = _str(a.get("dest") or "(none)")
        var = _str(a.get("var") or "(none)")
        return f"{key} {dest} {var} {_text_token(str(a.get('text', '')))}"
    if form == "lut":
        # the operand is a sequence whichever reader made it (Field kind "values")
        values = [_str(v) for v in cast(Iterable[object], a.get("values", ()))]
        parts = [key, _str(a["dest"]), _str(a["index"]), str(len(values)),
                 _str(a.get("as_string", 0))] + values
        return " ".join(parts + [_str(a.get("table", ""))])
    if form == "pwl":
        points = list(cast(Iterable[tuple[object, object]], a.get("points", ())))
        parts = [key, _str(a["dest"]), _str(a["index"]), str(len(points))]
        for x, y in points:
            parts += [_str(x), _str(y)]
        return " ".join(parts + [_str(a.get("table", ""))])
    if form == "quad":
        parts = [key]
        for field in ins.fields:
            value = a[field.name]
            parts.append(escape_ld(str(value), True) if field.name in ("z", "dir") else _str(value))
        return " ".join(parts)
    # a trailing operand a file may leave out (None) is left out again
    return " ".join([key] + [_str(a[field.name]) for field in ins.fields if a.get(field.name) is not None])


def line_limit_diagnostics(lines: list[str], encoding: str = "cp1252",
                           list_lines: set[int] | None = None,
                           spans: dict[int, Span | None] | None = None) -> list[Diagnostic]:
    """Warnings for lines LDmicro would split while reading (§3.1): over 511
    bytes, or over 63 bytes inside IO LIST / VAR LIST / PULL-UP LIST.
    `list_lines` holds the indexes of list lines; without it they are found
    from the section keywords."""
    if list_lines is None:
        list_lines = set()
        inside = False
        for index, line in enumerate(lines):
            if line in ("IO LIST", "VAR LIST", "PULL-UP LIST"):
                inside = True
            elif line == "END" and inside:
                inside = False
            elif inside:
                list_lines.add(index)
    spans = spans or {}
    problems = []
    for index, line in enumerate(lines):
        limit = MAX_LIST_LINE_BYTES if index in list_lines else MAX_LINE_BYTES
        size = _byte_length(line, encoding)
        if size > limit:
            where = "list line" if index in list_lines else "line"
            problems.append(warning(
                LD_SYNTAX,
                f".ld {where} {index + 1} is {size} bytes; LDmicro reads at most {limit} and "
                f"would split it: '{line.strip()[:40]}...'",
                spans.get(index)))
    return problems


def _byte_length(line: str, encoding: str) -> int:
    try:
        return len(encode_text(line, encoding))
    except (UnicodeError, LookupError):
        return len(line.encode("utf-8", "replace"))
