"""Hover: an instruction (what it does, its operands), a name (its role, pin,
where it is written and read, its value while a simulation runs), a rung
(its logic in one line), the part in the header line, a row of the I/O
table. The words come from lang/ (the instruction table), ide.names and
ide.outline; the text is Markdown."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from lang.instructions import LAYERS
from lang.labels import label
from lang.loader import TEXT_KIND
from lang.model import Element, Span
from lang.textform.sections import DETAILS, IO, VARS
from lang.values import format_delay

from . import names
from .document import Document
from .locate import word_at
from .outline import rung_logic

ACCESS = {"read": "read", "write": "written", "rw": "read and written", "": ""}

# a name's value in the simulation of the document, None when none runs or it has no such name
Values = Callable[[str], "int | None"]


@dataclass(frozen=True)
class Hover:
    markdown: str
    span: Span | None  # what the text is about


def hover_at(document: Document, line: int, col: int, value_of: Values) -> Hover | None:
    locator = document.locator
    text = document.line(line)
    if document.kind == TEXT_KIND:
        section = locator.section_at(line)
        if section == "header":
            return _header_hover(document, line, text)
        if section in (IO, VARS, DETAILS):
            return _word_hover(document, line, col, value_of)
    hit = locator.hit(line, col)
    if hit is None:
        return _word_hover(document, line, col, value_of) if document.kind != TEXT_KIND else None
    if hit.element is not None and hit.field is not None:
        value = hit.element.args.get(hit.field)
        span = hit.element.arg_spans.get(hit.field)
        if isinstance(value, str) and names.takes_name(hit.element.kind, hit.field) and names.is_name(value) \
                and hit.element.spec.get_field(hit.field).kind != "label":
            return Hover(name_hover(document, value, value_of), span)
        return Hover(instruction_hover(hit.element, hit.field), span)
    if hit.element is not None:
        return Hover(instruction_hover(hit.element), locator.glyph_span(hit.element))
    rung = document.program.rungs[hit.rung]
    extent = locator.rung_lines(hit.rung)
    rung_span = None
    if hit.part == "number":
        rail = text.find("|")
        rung_span = Span.at(line, 0, rail if rail > 0 else len(text))
    elif extent is not None:
        rung_span = Span(extent[0], 0, extent[1], len(document.line(extent[1])))
    return Hover(f"**Rung {hit.rung + 1}**\n\n```\n{rung_logic(rung)}\n```", rung_span)


def _word_hover(document: Document, line: int, col: int, value_of: Values) -> Hover | None:
    word = word_at(document.line(line), col)
    if word and names.known(document.program, document.index, word[2]):
        return Hover(name_hover(document, word[2], value_of), Span.at(line, word[0], word[1]))
    return None


def name_hover(document: Document, name: str, value_of: Values) -> str:
    lines = names.summary(document.program, document.index, name)
    value = value_of(name)
    if value is not None:
        lines.append(f"Simulation: **{name} = {value}**.")
    return "\n\n".join(lines)


def instruction_hover(element: Element, focus: str | None = None) -> str:
    spec = element.spec
    parts = [f"**{_label(element)}** — {spec.title}", spec.doc]
    operands = []
    for f in spec.fields:
        if f.kind in ("flag",) and not f.drawn:
            continue
        value = element.args.get(f.name)
        if value in (None, "", ()) and not f.drawn:
            continue
        shown = format_delay(value) if f.kind == "delay" and isinstance(value, int) else value
        what = []
        if f.prefixes:
            what.append("a name starting " + "/".join(f.prefixes))
        if ACCESS.get(f.access):
            what.append(ACCESS[f.access])
        if not f.drawn:
            what.append("in DETAILS")
        entry = f"`{f.name}` = `{shown}`" + (f" ({', '.join(what)})" if what else "")
        operands.append(("→ " if f.name == focus else "") + entry)
    if operands:
        parts.append("Operands:\n" + "\n".join(f"- {o}" for o in operands))
    notes = []
    if spec.eol:
        notes.append("Must end its rung (or branch).")
    missing = [layer for layer in LAYERS if layer not in spec.support and layer != "parse"]
    if missing:
        notes.append("Not supported by: " + ", ".join(missing) + ".")
    if notes:
        parts.append(" ".join(notes))
    return "\n\n".join(parts)


def _label(element: Element) -> str:
    return label(element).upper() if element.kind != "COIL" else label(element)


def _header_hover(document: Document, line: int, text: str) -> Hover | None:
    settings = document.program.settings
    if not text.lstrip().startswith(("for '", "no MCU")):
        return None
    if not settings.mcu:
        return Hover("No part selected: write `for '<part>', ...` (see `ladder parts`).", Span.at(line, 0, len(text)))
    from lang.devices import find_device

    device = find_device(settings.mcu)
    start = text.find("'") + 1
    span = Span.at(line, start, start + len(settings.mcu))
    if device is None:
        return Hover(f"`{settings.mcu}`: no pin data for this part.", span)
    memory = ", ".join(f"{k} {v}" for k, v in device.memory.items()) if device.memory else ""
    io = len(device.io_pins())
    body = (f"**{device.title}** ({device.package}), {device.family}: {len(device.pins)} pins, {io} I/O pins."
            + (f"\n\n{memory}" if memory else "")
            + f"\n\nCrystal {settings.crystal_hz / 1e6:g} MHz, cycle time {settings.cycle_us / 1000:g} ms.")
    return Hover(body, span)
