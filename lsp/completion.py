"""Completion, by where the cursor is:

* on an operand of an element: the names the program already uses that this
  operand allows (its prefixes: a coil takes Y, R or M names...);
* on a blank line of the diagram between rungs: whole rungs, one per
  instruction, drawn as the formatter draws them (a snippet whose names are
  placeholders when the client takes snippets);
* on a wire inside a rung: an element inserted there, the rung drawn again;
* in the header line: the part names; in the I/O table: the program's X, Y,
  A and P names without a row, then the pins and ports of the selected part;
* in a .ld file: instruction lines with LDmicro's defaults, and names.

Inserting into a 2-D drawing means changing several lines: the item's main
edit replaces the cursor's line (LSP wants a one-line range there) and
`additionalTextEdits` the rung's other lines.
"""

from __future__ import annotations

from functools import lru_cache

from lsprotocol import types

from ide import edits, names
from ide.locate import Locator, rail_column, word_at
from lang.instructions import INSTRUCTIONS
from lang.model import Span
from lang.roles import role
from lang.textform.sections import DIAGRAM, IO

from .documents import LD
from .navigation import newline

MAX_NAMES = 200  # names offered at once (clangd offers 100, VS Code shows a dozen)


def register(server) -> None:
    @server.on(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["'"]))
    def completion(ls, params: types.CompletionParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        line, col = analysis.positions.from_client(params.position)
        col = min(col, len(analysis.line(line)))
        items = complete(ls, analysis, line, col)
        if items is None or isinstance(items, types.CompletionList):
            return items
        return types.CompletionList(is_incomplete=False, items=items)


def _snippets(ls) -> bool:
    return ls.client_supports("text_document", "completion", "completion_item", "snippet_support")


def complete(ls, analysis, line: int, col: int) -> list[types.CompletionItem] | types.CompletionList | None:
    text = analysis.line(line)
    if analysis.kind == LD:
        return _ld(ls, analysis, line, col, text)
    section = analysis.locator.section_at(line)
    if section == "header":
        return _parts(analysis, line, col, text)
    if section == IO:
        return _io_row(analysis, line, col, text)
    if section != DIAGRAM:
        return None
    hit = analysis.locator.hit(line, col, end_inclusive=True)
    if hit is not None and hit.element is not None and hit.field is not None:
        return _names(analysis, line, col, text, hit.element.kind, hit.field)
    if hit is not None:
        if analysis.has_errors:
            return []
        return _insert_here(ls, analysis, line, col, hit.rung)
    if analysis.locator.rung_at(line) is None and _blankish(text):
        return _rungs(ls, analysis, line, col, text)
    word = word_at(text, col)
    if word is not None:  # a rung that does not read yet: any name
        return _names(analysis, line, col, text, None, None)
    return []


def _word_range(analysis, line: int, col: int, text: str) -> tuple[int, int, str]:
    word = word_at(text, col)
    if word is None or word[0] > col:
        return col, col, ""
    return word[0], word[1], text[word[0]:col]


def _names(analysis, line, col, text, kind, field) -> types.CompletionList:
    """The names that fit, the first MAX_NAMES of them: a big program has
    thousands, and the client asks again as more is typed (`isIncomplete`)."""
    start, end, typed = _word_range(analysis, line, col, text)
    found = names.candidates(analysis.program, analysis.index, kind, field, typed)
    edit_range = analysis.positions.range(Span.at(line, start, end))
    items = []
    for name in found[:MAX_NAMES]:
        short = role(name)[0]
        items.append(types.CompletionItem(
            label=name, kind=types.CompletionItemKind.Variable, detail=short,
            text_edit=types.TextEdit(range=edit_range, new_text=name)))
    return types.CompletionList(is_incomplete=len(found) > MAX_NAMES, items=items)


# --- the header and the I/O table ------------------------------------------------------------

def _parts(analysis, line, col, text) -> list[types.CompletionItem] | None:
    start = text.find("'")
    if not text.lstrip().startswith("for") or start < 0 or col <= start:
        return None
    end = text.find("'", start + 1)
    end = end if end >= 0 else len(text)
    if col > end:
        return None
    edit_range = analysis.positions.range(Span.at(line, start + 1, end))
    return [types.CompletionItem(label=name, kind=types.CompletionItemKind.Module, detail=detail,
                                 text_edit=types.TextEdit(range=edit_range, new_text=name))
            for name, detail in names.part_candidates()]


def _io_row(analysis, line, col, text) -> list[types.CompletionItem] | None:
    column = text[:col].count("|")
    cells = text.split("|")
    if column == 0:
        start, end, _ = _word_range(analysis, line, col, text)
        edit_range = analysis.positions.range(Span.at(line, start, end))
        return [types.CompletionItem(label=n, kind=types.CompletionItemKind.Variable, detail=role(n)[0],
                                     text_edit=types.TextEdit(range=edit_range, new_text=n))
                for n in names.unassigned_io_names(analysis.program, analysis.index)]
    if column not in (2, 3):
        return None
    name = cells[0].strip()
    bounds = [i for i, ch in enumerate(text) if ch == "|"]
    left = bounds[column - 1] + 1
    right = bounds[column] if len(bounds) > column else len(text)
    edit_range = analysis.positions.range(Span.at(line, left, right))
    items = []
    typed = text[left:col]
    for position, (number, port, label) in enumerate(names.pin_candidates(analysis.program, name)):
        value = str(number) if column == 2 else port
        new_text = f" {value:>3} " if column == 2 else f" {value:<5} "
        items.append(types.CompletionItem(
            label=value, kind=types.CompletionItemKind.Value,
            detail=label if column == 2 else f"pin {number}: {label}",
            sort_text=f"{position:04d}", filter_text=typed + value,
            text_edit=types.TextEdit(range=edit_range, new_text=new_text)))
    return items


# --- whole rungs and elements -------------------------------------------------------------------

def _blankish(text: str) -> bool:
    """A diagram line with nothing drawn on it, or one word typed."""
    rail = rail_column(text)
    body = text[rail + 2:] if rail >= 0 else text
    return len(body.replace("|", " ").split()) <= 1 and "[END]" not in text


@lru_cache(maxsize=512)
def _rung_snippet(kind: str, columns: int) -> tuple[tuple[str, ...], tuple]:
    lines, places = edits.drawn_operands(edits.example_rung(kind), 1, columns)
    return tuple(lines), tuple(places)


def _escape(text: str) -> str:
    return text.replace("\\", "\\\\").replace("$", "\\$").replace("}", "\\}")


def _snippet_text(lines: tuple[str, ...], places: tuple, nl: str) -> str:
    out = []
    number = 1
    by_line: dict[int, list] = {}
    for line, col, end in places:
        by_line.setdefault(line, []).append((col, end))
    for index, line in enumerate(lines):
        pieces, pos = [], 0
        for col, end in sorted(by_line.get(index, [])):
            pieces.append(_escape(line[pos:col]))
            pieces.append(f"${{{number}:{_escape(line[col:end])}}}")
            number += 1
            pos = end
        pieces.append(_escape(line[pos:]))
        out.append("".join(pieces))
    return nl.join(out)


def _rungs(ls, analysis, line, col, text) -> list[types.CompletionItem]:
    columns = edits.columns_of(analysis.text, analysis.program)
    nl = newline(analysis)
    number = sum(1 for first, _, _ in analysis.locator.rung_extents() if first < line) + 1
    edit_range = analysis.positions.range(Span.at(line, 0, len(text)))
    blank = ("    ||" + " " * (17 * columns) + "||").rstrip() if rail_column(text) >= 0 else ""
    typed = text[:col]
    snippets = _snippets(ls)
    items = []
    for order, kind in enumerate(_menu()):
        try:
            snippet, places = _rung_snippet(kind, columns)
        except edits.EditError:
            continue
        lines = list(snippet)
        for index, drawn in enumerate(lines):
            if drawn[:4].strip().isdigit():
                lines[index] = f"{number:04d}" + drawn[4:]
        spacer = blank
        if snippets:
            body = _snippet_text(tuple(lines), places, nl) + nl + _escape(spacer) + nl + _escape(blank) + "$0"
        else:
            body = nl.join(lines + [spacer, blank])
        spec = INSTRUCTIONS[kind]
        items.append(types.CompletionItem(
            label=f"rung: {_keyword(kind)}", kind=types.CompletionItemKind.Snippet,
            detail=spec.title, documentation=types.MarkupContent(kind=types.MarkupKind.PlainText,
                                                                  value=spec.doc + "\n\n" + "\n".join(lines)),
            filter_text=typed + _keyword(kind) + " " + spec.title, sort_text=f"{order:03d}",
            insert_text_format=types.InsertTextFormat.Snippet if snippets else types.InsertTextFormat.PlainText,
            text_edit=types.TextEdit(range=edit_range, new_text=body)))
    return items


def _menu() -> list[str]:
    rest = sorted(k for k in INSTRUCTIONS if edits.insertable(k) and k not in edits.COMMON
                  and k not in ("SHORT", "OPEN"))
    return [k for k in edits.COMMON if k not in ("SHORT", "OPEN")] + rest


def _keyword(kind: str) -> str:
    from lang.labels import label

    return label(edits.new_element(kind)) if kind in ("COIL", "CONTACTS") else kind


def _insert_here(ls, analysis, line, col, rung_index) -> list[types.CompletionItem]:
    """Elements inserted at a place on a wire of a drawn rung."""
    locator: Locator = analysis.locator
    rung = analysis.program.rungs[rung_index]
    if rung.is_comment:
        return []
    on_line = [(locator.glyph_span(e), e) for e in rung.elements()]
    on_line = [(g, e) for g, e in on_line if g.line == line]
    if not on_line:
        return []
    left = [(g, e) for g, e in on_line if g.end_col <= col]
    if left:
        anchor, after = max(left, key=lambda item: item[0].end_col)[1], True
    else:
        anchor, after = min(on_line, key=lambda item: item[0].col)[1], False
    extent = locator.rung_lines(rung_index)
    assert extent is not None  # the rung was found where it is drawn
    first, last = extent
    columns = edits.columns_of(analysis.text, analysis.program)
    nl = newline(analysis)
    typed = analysis.line(line)[:col]
    items = []
    for order, kind in enumerate(edits.COMMON):
        try:
            changed = edits.insert_element(rung, anchor, edits.new_element(kind), after=after)
        except edits.EditError:
            continue
        lines = edits.drawn_lines(changed, rung_index + 1, columns)
        k = line - first
        if k >= len(lines):
            continue
        main = types.TextEdit(range=analysis.positions.range(Span.at(line, 0, len(analysis.line(line)))),
                              new_text=lines[k])
        extra = []
        if k > 0:  # the lines above, up to the end of the line before the cursor's (no shared edge)
            extra.append(types.TextEdit(
                range=types.Range(start=types.Position(line=first, character=0),
                                  end=analysis.positions.to_client(line - 1, len(analysis.line(line - 1)))),
                new_text=nl.join(lines[:k])))
        rest = lines[k + 1:]
        if line < last and rest:  # the lines below, from the start of the next line
            extra.append(types.TextEdit(
                range=types.Range(start=types.Position(line=line + 1, character=0),
                                  end=analysis.positions.to_client(last, len(analysis.line(last)))),
                new_text=nl.join(rest)))
        elif line < last or rest:
            extra.append(types.TextEdit(
                range=types.Range(start=analysis.positions.to_client(line, len(analysis.line(line))),
                                  end=analysis.positions.to_client(last, len(analysis.line(last)))),
                new_text="".join(nl + x for x in rest)))
        spec = INSTRUCTIONS[kind]
        where = "after" if after else "before"
        items.append(types.CompletionItem(
            label=f"insert {_keyword(kind)}", kind=types.CompletionItemKind.Snippet,
            detail=f"{spec.title}, {where} {edits_describe(anchor)}",
            filter_text=typed + _keyword(kind), sort_text=f"{order:03d}",
            text_edit=main, additional_text_edits=extra or None))
    return items


def edits_describe(element) -> str:
    from lang.labels import describe

    return describe(element)


# --- .ld files ---------------------------------------------------------------------------------

def _ld(ls, analysis, line, col, text) -> list[types.CompletionItem] | types.CompletionList | None:
    indent = len(text) - len(text.lstrip())
    first_word_end = indent + len(text.lstrip().split(" ")[0]) if text.strip() else indent
    if col > first_word_end:  # an operand
        hit = analysis.locator.hit(line, col, end_inclusive=True)
        if hit is not None and hit.element is not None and hit.field is not None:
            return _names(analysis, line, col, text, hit.element.kind, hit.field)
        return _names(analysis, line, col, text, None, None)
    if analysis.locator.rung_at(line) is None and text.strip() not in ("",) and \
            not any(text.strip().startswith(k) for k in INSTRUCTIONS):
        return None  # a header or I/O LIST line
    edit_range = analysis.positions.range(Span.at(line, indent, len(text)))
    items = []
    for kind in sorted(k for k in INSTRUCTIONS if edits.insertable(k)):
        default = INSTRUCTIONS[kind].example
        items.append(types.CompletionItem(
            label=kind, kind=types.CompletionItemKind.Keyword, detail=INSTRUCTIONS[kind].title,
            documentation=INSTRUCTIONS[kind].doc,
            text_edit=types.TextEdit(range=edit_range, new_text=default)))
    return items
