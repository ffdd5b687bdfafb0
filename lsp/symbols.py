"""The outline: document symbols (the sections of a text file, each rung
with its comment or logic, the names it writes) and folding (one range per
rung and per section).

Clients ask for both after every edit (VS Code's breadcrumbs and outline), so
each rung's part is computed once and kept while the rung is unchanged
(`Analysis.per_rung`), with its JSON text, and the answer is those texts
joined (`Encoded`): for a 2,000-rung program, building and converting
thousands of lsprotocol objects, or encoding 1.5 MB of JSON again, would cost
more than the rest of the request."""

from __future__ import annotations

import json

from lsprotocol import types

from ide.outline import outputs, rung_logic, rung_title
from lang.model import Span

from .documents import LADDER
from .protocol import Encoded, Raw

SECTION_NAMES = {"header": "Header"}


def _range(analysis, span: Span) -> dict:
    r = analysis.positions.range(span)
    return {"start": {"line": r.start.line, "character": r.start.character},
            "end": {"line": r.end.line, "character": r.end.character}}


def _output_name(element) -> str:
    for f in element.spec.fields:
        if f.access in ("write", "rw") and element.args.get(f.name):
            return str(element.args[f.name])
    return element.kind


def _rung_symbol(analysis, index: int) -> dict:
    extent = analysis.locator.rung_lines(index)
    first, last = extent
    rung = analysis.program.rungs[index]
    children = []
    for element in outputs(rung):
        span = element.span
        if span is None:
            continue
        name_span = next((element.arg_spans[f.name] for f in element.spec.fields
                          if f.access in ("write", "rw") and f.name in element.arg_spans), span)
        children.append({
            "name": _output_name(element), "detail": element.spec.title,
            "kind": int(types.SymbolKind.Variable if element.kind == "COIL" else types.SymbolKind.Event),
            "range": _range(analysis, span), "selectionRange": _range(analysis, name_span)})
    symbol = {
        "name": rung_title(analysis.program, index),
        "detail": rung_logic(rung) if not rung.is_comment else "comment",
        "kind": int(types.SymbolKind.String if rung.is_comment else types.SymbolKind.Function),
        "range": _range(analysis, Span(first, 0, last, len(analysis.line(last)))),
        "selectionRange": _range(analysis, Span.at(first, 0, len(analysis.line(first)))),
    }
    if children:
        symbol["children"] = children
    return symbol


def _encoded(symbol: dict) -> str:
    return json.dumps(symbol, separators=(",", ":"))


def _with_text(symbol: dict) -> tuple[dict, str]:
    return symbol, _encoded(symbol)


def rung_symbol(analysis, index: int) -> tuple[dict, str]:
    """A rung's symbol and its JSON text, kept while the rung is unchanged."""
    return analysis.per_rung("symbol", index, lambda i: _with_text(_rung_symbol(analysis, i)))


def rung_symbols(analysis) -> list[tuple[dict, str]]:
    """Each drawn rung's symbol, with its JSON text."""
    found = []
    for _, _, index in analysis.locator.rung_extents():
        symbol, text = rung_symbol(analysis, index)
        name = rung_title(analysis.program, index)  # the number changes when rungs are added above
        if symbol["name"] != name:
            symbol, text = _with_text(dict(symbol, name=name))
        found.append((symbol, text))
    return found


def document_symbols(analysis) -> list[tuple[dict, str]]:
    """The top-level DocumentSymbol objects in JSON form, each with its JSON text."""
    rungs = rung_symbols(analysis)
    if analysis.kind != LADDER:
        return rungs
    result = []
    for title, first, last in analysis.locator.sections:
        if title == "header" and not any(analysis.line(n).strip() for n in range(first, last + 1)):
            continue
        symbol = {"name": SECTION_NAMES.get(title, title), "kind": int(types.SymbolKind.Namespace),
                  "range": _range(analysis, Span(first, 0, last, len(analysis.line(last)))),
                  "selectionRange": _range(analysis, Span.at(first, 0, len(analysis.line(first))))}
        text = _encoded(symbol)
        if title == "LADDER DIAGRAM":
            children = [(s, t) for s, t in rungs if first <= s["range"]["start"]["line"] <= last]
            if children:
                symbol["children"] = [s for s, _ in children]
                text = text[:-1] + ',"children":[' + ",".join(t for _, t in children) + "]}"
        result.append((symbol, text))
    return result


def _flat(symbols: list[dict], uri: str, container: str | None = None) -> list[dict]:
    out = []
    for symbol in symbols:
        entry = {"name": symbol["name"], "kind": symbol["kind"], "location": {"uri": uri, "range": symbol["range"]}}
        if container:
            entry["containerName"] = container
        out.append(entry)
        out.extend(_flat(symbol.get("children", []), uri, symbol["name"]))
    return out


def rung_fold(analysis, index: int) -> dict | None:
    """A rung's folding range, kept while the rung is unchanged."""
    return analysis.per_rung("fold", index, lambda i: _rung_fold(analysis, i))


def _rung_fold(analysis, index: int) -> dict | None:
    extent = analysis.locator.rung_lines(index)
    first, last = extent
    if last <= first:
        return None
    rung = analysis.program.rungs[index]
    return {"startLine": first, "endLine": last, "kind": "comment" if rung.is_comment else "region"}


def folding_ranges(analysis) -> list[dict]:
    ranges = []
    for _, _, index in analysis.locator.rung_extents():
        found = rung_fold(analysis, index)
        if found is not None:
            ranges.append(found)
    if analysis.kind == LADDER:
        for title, first, last in analysis.locator.sections:
            while last > first and not analysis.line(last).strip():
                last -= 1
            if title != "header" and last > first:
                ranges.append({"startLine": first, "endLine": last, "kind": "region"})
    return ranges


def _shift_range(r: dict, delta: int) -> dict:
    return {"start": {"line": r["start"]["line"] + delta, "character": r["start"]["character"]},
            "end": {"line": r["end"]["line"] + delta, "character": r["end"]["character"]}}


def _shift_symbol_text(symbol: tuple[dict, str], delta: int) -> tuple[dict, str]:
    return _with_text(_shift_symbol(symbol[0], delta))


def _shift_symbol(symbol: dict, delta: int) -> dict:
    moved = dict(symbol, range=_shift_range(symbol["range"], delta),
                 selectionRange=_shift_range(symbol["selectionRange"], delta))
    if "children" in symbol:
        moved["children"] = [_shift_symbol(c, delta) for c in symbol["children"]]
    return moved


def _shift_fold(fold: dict | None, delta: int) -> dict | None:
    if fold is None:
        return None
    return dict(fold, startLine=fold["startLine"] + delta, endLine=fold["endLine"] + delta)


def register(server) -> None:
    server.documents.shifters["symbol"] = _shift_symbol_text
    server.documents.shifters["fold"] = _shift_fold
    @server.on(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    def symbols(ls, params: types.DocumentSymbolParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        found = analysis.once("symbols", lambda: document_symbols(analysis))
        if ls.client_supports("text_document", "document_symbol", "hierarchical_document_symbol_support"):
            return Encoded("[" + ",".join(text for _, text in found) + "]")
        return Raw(_flat([symbol for symbol, _ in found], analysis.uri))

    @server.on(types.TEXT_DOCUMENT_FOLDING_RANGE)
    def folding(ls, params: types.FoldingRangeParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        return Raw(analysis.once("folding", lambda: folding_ranges(analysis)))
