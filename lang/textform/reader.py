"""Reading the text form (`.ladder`, and LDmicro's "Export as Text" `.txt`)
into a Program. Rungs are read one by one and cached by their lines, so an
edit re-reads only the rungs it touches."""

from __future__ import annotations

import re
from collections import Counter, OrderedDict
from decimal import Decimal, InvalidOperation

from .. import codes
from ..diagnostics import Diagnostic, error
from ..model import PinAssignment, Program, Rung, Series, Settings, Span
from . import details as details_section
from .rungs import Line, read_rung
from .sections import DETAILS, DIAGRAM, IO, SETTINGS, VARS, Section, split_sections

HEADER_RE = re.compile(
    r"\s*(?:for\s+'(?P<mcu>.*)',|no MCU assigned,)\s*"
    r"(?:(?P<mhz>[\d.]+)\s*MHz crystal,\s*)?(?P<ms>[\d.]+)\s*ms cycle time\s*\Z"
)
RAIL_RE = re.compile(r"\|[|+]")
VAR_RE = re.compile(r"\s*(\d+)\s+bytes?\s+(\S+)")

_CACHE: OrderedDict[tuple, tuple[Rung | None, list[Diagnostic]]] = OrderedDict()
_CACHE_SIZE = 50000


def read_text(text: str) -> tuple[Program, list[Diagnostic]]:
    lines = text.splitlines()
    program = Program()
    problems: list[Diagnostic] = []
    sections = split_sections(lines)
    titles = {s.title for s in sections}
    for section in sections:
        if section.title == "header":
            _read_header(section, program.settings, problems, has_diagram=DIAGRAM in titles)
        elif section.title == DIAGRAM:
            program.rungs = _read_diagram(section, problems)
        elif section.title == IO:
            _read_io(section, program, problems)
        elif section.title == VARS:
            _read_vars(section, program, problems)
        elif section.title == SETTINGS:
            details_section.read_settings(section, program, problems)
        elif section.title == DETAILS:
            details_section.read_details(section, program, problems)
        else:
            problems.append(error(codes.SECTION, f"unknown section {section.title!r}",
                                  Span.at(section.title_line, 0, len(section.title) + 1)))
    if DIAGRAM not in titles:
        problems.append(error(codes.UNREADABLE, "no LADDER DIAGRAM section: this is not a ladder text file",
                              Span.at(0, 0)))
    return program, problems


def _read_header(section: Section, settings: Settings, problems: list[Diagnostic], has_diagram: bool) -> None:
    for number, text in section.lines:
        if not text.strip() or text.startswith("LDmicro export text") or text.startswith("Source file:"):
            continue
        match = HEADER_RE.match(text)
        if not match:
            if has_diagram:
                problems.append(error(codes.SECTION, "expected the line `for '<part>', <f> MHz crystal, "
                                      "<t> ms cycle time`", Span.at(number, 0, len(text))))
            continue
        settings.mcu = match.group("mcu")
        if settings.mcu is not None:
            start = text.index("'") + 1
            settings.mcu_span = Span.at(number, start, start + len(settings.mcu))
        try:
            if match.group("mhz"):
                settings.crystal_hz = int(Decimal(match.group("mhz")) * 1000000)
            settings.cycle_us = int(Decimal(match.group("ms")) * 1000)
        except InvalidOperation:
            problems.append(error(codes.SECTION, "bad number in the header line", Span.at(number, 0, len(text))))


# --- the diagram ---------------------------------------------------------------------

def _rail(text: str) -> int:
    """Column of the left rail: the first `|` followed by `|` or `+` (-1: none)."""
    left = text.find("|")
    while left >= 0 and text[left + 1:left + 2] not in ("|", "+"):
        left = text.find("|", left + 1)
    return left


def _end(text: str, left: int) -> int:
    stripped = text.rstrip()
    return len(stripped) - 2 if stripped.endswith("||") and len(stripped) - 2 > left else len(stripped)


def _blank(raw: tuple[int, str, int]) -> bool:
    _, text, left = raw
    return not text[left + 2:_end(text, left)].strip()


def _line(raw: tuple[int, str, int], label: str | None = None) -> Line:
    number, text, left = raw
    return Line(number, text, left, _end(text, left), text[:left].strip() if label is None else label)


def _read_diagram(section: Section, problems: list[Diagnostic]) -> list[Rung]:
    rungs: list[Rung] = []
    for raws, symbol_index, labels in _raw_blocks(section, problems):
        if not raws:
            rungs.append(Rung(Series([])))
            continue
        # unchanged rungs (same lines at the same place) are not read again
        key = (raws[0][0], "\n".join(raw[1] for raw in raws), symbol_index)
        cached = _CACHE.get(key)
        if cached is None:
            block = [_line(raw, labels.get(raw[0])) for raw in raws]
            _fix_right_rail(block)
            cached = read_rung(block, symbol_index)
            _CACHE[key] = cached
            if len(_CACHE) > _CACHE_SIZE:
                _CACHE.popitem(last=False)
        rung, found = cached
        problems.extend(found)
        if rung is not None:
            rungs.append(rung)
    return rungs


def rung_blocks(section: Section, problems: list[Diagnostic]) -> list[tuple[list[Line], int]]:
    """The lines of each rung and the index of its first symbol line."""
    return [([_line(raw, labels.get(raw[0])) for raw in raws], symbol)
            for raws, symbol, labels in _raw_blocks(section, problems)]


def _raw_blocks(section: Section, problems: list[Diagnostic]):
    """Each rung's lines as (number, text, rail column), the index of its first
    symbol line, and labels overridden (an empty rung's number).

    A rung starts on the name line above a line numbered in the number field,
    or on the first drawn line after a line with no rail; a rung without a
    number whose first line starts with a wire has no name line."""
    blocks: list = []
    current: list[tuple[int, str, int]] = []
    symbol: int | None = None
    labels: dict[int, str] = {}

    def close() -> None:
        nonlocal current, symbol
        if any(not _blank(raw) for raw in current):
            blocks.append((current, symbol))
        current, symbol = [], None

    raws = [(number, text, _rail(text)) for number, text in section.lines]
    for position, raw in enumerate(raws):
        number, text, left = raw
        if left < 0:
            if text.strip():
                problems.append(error(codes.BROKEN_WIRE, "this diagram line has no left rail `||`",
                                      Span.at(number, 0, len(text.rstrip()))))
            close()
            continue
        if "[END]" in text:
            close()
            break
        label = text[:left].strip()
        if label.isdigit() and position + 1 < len(raws):
            following = raws[position + 1]
            if following[2] >= 0 and following[1][:following[2]].strip().isdigit():
                # LDmicro draws an empty rung with no rows: its number lands
                # on the next rung's name line
                close()
                blocks.append(([], None))
                labels[number] = label = ""
        if label.isdigit():
            name_line = current.pop() if current and current[-1][0] == number - 1 else None
            close()
            current = [name_line] if name_line is not None else []
            symbol = len(current)
        elif label:
            problems.append(error(codes.UNKNOWN_ELEMENT, f"{label!r} in the rung-number field",
                                  Span.at(number, 0, left)))
        current.append(raw)
    close()
    return [(*_trim(block, symbol), labels) for block, symbol in blocks]


def _trim(block: list, symbol: int | None) -> tuple[list, int]:
    if not block:
        return block, 0
    if symbol is None:
        while block and _blank(block[0]):
            block = block[1:]
        _, text, left = block[0]
        content = text[left + 2:]
        starts_drawn = content[:1] in ("-", "+") or text[left + 1:left + 2] == "+"
        symbol = 0 if starts_drawn or content.lstrip().startswith(";") else min(1, len(block) - 1)
    else:
        drop = max(0, symbol - 1)
        block, symbol = block[drop:], symbol - drop
    while len(block) > symbol + 1 and _blank(block[-1]):
        block = block[:-1]
    return block, symbol


def _fix_right_rail(block: list[Line]) -> None:
    """The right rail is where most lines of the rung end in `||`; a long name
    may have eaten its first `|`."""
    ends = Counter(len(line.text.rstrip()) - 2 for line in block if line.text.rstrip().endswith("||"))
    if not ends:
        return
    rail = ends.most_common(1)[0][0]
    for line in block:
        stripped = line.text.rstrip()
        if len(stripped) - 2 == rail and stripped.endswith("||"):
            line.end = rail
        elif len(stripped) - 1 == rail + 1 and stripped.endswith("|"):
            line.end = rail + 1


# --- the tables after the diagram ---------------------------------------------------------

def _read_io(section: Section, program: Program, problems: list[Diagnostic]) -> None:
    for number, text in section.lines:
        cells = [cell.strip() for cell in text.split("|")]
        if len(cells) < 3 or not cells[0] or cells[0] == "Name" or set(cells[0]) <= set("-"):
            continue
        if "UART" in cells[1]:
            continue  # LDmicro lists the UART's fixed pins here, not an assignment
        name, pin_text = cells[0], cells[2]
        port_text = cells[3] if len(cells) > 3 else ""
        pin: int | str | None = None
        if pin_text.isdigit():
            pin = int(pin_text)
        elif re.fullmatch(r"[A-Za-z]{1,2}\d{1,2}", pin_text):
            pin = pin_text.upper()
        elif not pin_text or pin_text.startswith("(not assigned"):
            if re.fullmatch(r"[A-Za-z]{1,2}\d{1,2}", port_text):
                pin = port_text.upper()
        else:
            column = text.find(pin_text)
            problems.append(error(codes.SECTION, f"{pin_text!r} is not a pin number or port bit (e.g. 4 or PD2)",
                                  Span.at(number, column, column + len(pin_text))))
            continue
        if pin in (None, 0) or name in program.pins:
            continue
        column = text.find(name)
        program.pins[name] = PinAssignment(name, pin, span=Span.at(number, column, column + len(name)))


def _read_vars(section: Section, program: Program, problems: list[Diagnostic]) -> None:
    for number, text in section.lines:
        if not text.strip():
            continue
        match = VAR_RE.match(text)
        if not match:
            problems.append(error(codes.SECTION, "expected `<n> bytes <name>`", Span.at(number, 0, len(text))))
            continue
        program.var_sizes[match.group(2)] = int(match.group(1))
