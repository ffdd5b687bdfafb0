"""Hover: an instruction (what it does, its operands), a name (its role, pin,
where it is written and read, its value while a simulation runs), a rung
(its logic in one line), the part in the header line, a row of the I/O
table. The words come from lang/ (instruction table, ide.names, ide.outline)."""

from __future__ import annotations

from lsprotocol import types

from ide import names
from ide.locate import word_at
from ide.outline import rung_logic
from lang.instructions import LAYERS
from lang.model import Element, Span
from lang.textform.sections import DETAILS, IO, VARS
from lang.values import format_delay

from .documents import LADDER

ACCESS = {"read": "read", "write": "written", "rw": "read and written", "": ""}


def register(server) -> None:
    @server.on(types.TEXT_DOCUMENT_HOVER)
    def hover(ls, params: types.HoverParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        line, col = analysis.positions.from_client(params.position)
        found = hover_at(ls, analysis, line, col)
        if found is None:
            return None
        text, span = found
        markdown = _markdown(ls)
        value = text if markdown else _plain(text)
        return types.Hover(
            contents=types.MarkupContent(kind=types.MarkupKind.Markdown if markdown else types.MarkupKind.PlainText,
                                         value=value),
            range=analysis.positions.range(span) if span is not None else None)


def _markdown(ls) -> bool:
    formats = None
    try:
        formats = ls.client_capabilities.text_document.hover.content_format
    except AttributeError:
        pass
    return not formats or types.MarkupKind.Markdown in formats


def _plain(text: str) -> str:
    return text.replace("**", "").replace("`", "")


def hover_at(ls, analysis, line: int, col: int) -> tuple[str, Span | None] | None:
    locator = analysis.locator
    text = analysis.line(line)
    if analysis.kind == LADDER:
        section = locator.section_at(line)
        if section == "header":
            return _header_hover(analysis, line, text)
        if section in (IO, VARS, DETAILS):
            word = word_at(text, col)
            if word and _known_name(analysis, word[2]):
                return name_hover(ls, analysis, word[2]), Span.at(line, word[0], word[1])
            return None
    hit = locator.hit(line, col)
    if hit is None:
        if analysis.kind != LADDER:
            word = word_at(text, col)
            if word and _known_name(analysis, word[2]):
                return name_hover(ls, analysis, word[2]), Span.at(line, word[0], word[1])
        return None
    if hit.element is not None and hit.field is not None:
        value = hit.element.args.get(hit.field)
        span = hit.element.arg_spans.get(hit.field)
        if isinstance(value, str) and names.takes_name(hit.element.kind, hit.field) and names.is_name(value) \
                and hit.element.spec.get_field(hit.field).kind != "label":
            return name_hover(ls, analysis, value), span
        return instruction_hover(hit.element, hit.field), span
    if hit.element is not None:
        span = locator.glyph_span(hit.element)
        return instruction_hover(hit.element), span
    rung = analysis.program.rungs[hit.rung]
    extent = locator.rung_lines(hit.rung)
    span = None
    if hit.part == "number":
        rail = text.find("|")
        span = Span.at(line, 0, rail if rail > 0 else len(text))
    elif extent is not None:
        span = Span(extent[0], 0, extent[1], len(analysis.line(extent[1])))
    return f"**Rung {hit.rung + 1}**\n\n```\n{rung_logic(rung)}\n```", span


def _known_name(analysis, word: str) -> bool:
    program = analysis.program
    return word in analysis.index.uses or word in program.pins or word in program.var_sizes


def name_hover(ls, analysis, name: str) -> str:
    lines = names.summary(analysis.program, analysis.index, name)
    sim = ls.simulations
    if sim is not None:
        value = sim.value_of(analysis.uri, name)
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
    from lang.labels import label

    return label(element).upper() if element.kind != "COIL" else label(element)


def _header_hover(analysis, line: int, text: str):
    settings = analysis.program.settings
    if not text.lstrip().startswith(("for '", "no MCU")):
        return None
    if not settings.mcu:
        return "No part selected: write `for '<part>', ...` (see `ladder parts`).", Span.at(line, 0, len(text))
    from lang.devices import find_device

    device = find_device(settings.mcu)
    start = text.find("'") + 1
    span = Span.at(line, start, start + len(settings.mcu))
    if device is None:
        return f"`{settings.mcu}`: no pin data for this part.", span
    memory = ", ".join(f"{k} {v}" for k, v in device.memory.items()) if device.memory else ""
    io = len(device.io_pins())
    body = (f"**{device.title}** ({device.package}), {device.family}: {len(device.pins)} pins, {io} I/O pins."
            + (f"\n\n{memory}" if memory else "")
            + f"\n\nCrystal {settings.crystal_hz / 1e6:g} MHz, cycle time {settings.cycle_us / 1000:g} ms.")
    return body, span
