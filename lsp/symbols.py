"""The outline (ide.outline) as LSP's document symbols and folding ranges.

Clients ask for both after every edit (VS Code's breadcrumbs and outline), so
each rung's part is computed once and kept while the rung is unchanged
(`Analysis.per_rung`), with its JSON text, and the answer is those texts
joined (`Encoded`): for a 2,000-rung program, building and converting
thousands of lsprotocol objects, or encoding 1.5 MB of JSON again, would cost
more than the rest of the request."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

from lsprotocol import types

from ide import outline
from ide.outline import Fold, Kind, Symbol
from lang.model import Span

from .documents import Analysis
from .protocol import Encoded, Raw

if TYPE_CHECKING:
    from .server import LadderServer

KINDS = {Kind.SECTION: types.SymbolKind.Namespace, Kind.RUNG: types.SymbolKind.Function,
         Kind.COMMENT: types.SymbolKind.String, Kind.COIL: types.SymbolKind.Variable,
         Kind.OUTPUT: types.SymbolKind.Event}

Json = dict[str, Any]
Encodable = tuple[Json, str]  # a symbol in JSON form, and its JSON text


def _range(analysis: Analysis, span: Span) -> Json:
    r = analysis.positions.range(span)
    return {"start": {"line": r.start.line, "character": r.start.character},
            "end": {"line": r.end.line, "character": r.end.character}}


def _json(analysis: Analysis, symbol: Symbol) -> Json:
    found: Json = {"name": symbol.name}
    if symbol.detail is not None:
        found["detail"] = symbol.detail
    found.update({"kind": int(KINDS[symbol.kind]), "range": _range(analysis, symbol.span),
                  "selectionRange": _range(analysis, symbol.selection)})
    if symbol.children:
        found["children"] = [_json(analysis, child) for child in symbol.children]
    return found


def _encoded(symbol: Json) -> str:
    return json.dumps(symbol, separators=(",", ":"))


def _with_text(symbol: Json) -> Encodable:
    return symbol, _encoded(symbol)


def _rung_symbol(analysis: Analysis, index: int) -> Encodable:
    symbol = outline.rung_symbol(analysis, index)
    assert symbol is not None  # asked for drawn rungs only
    return _with_text(_json(analysis, symbol))


def rung_symbol(analysis: Analysis, index: int) -> Encodable:
    """A drawn rung's symbol and its JSON text, kept while the rung is unchanged."""
    return analysis.per_rung("symbol", index, lambda i: _rung_symbol(analysis, i))


def rung_symbols(analysis: Analysis) -> list[Encodable]:
    """Each drawn rung's symbol, with its JSON text."""
    found = []
    for _, _, index in analysis.locator.rung_extents():
        symbol, text = rung_symbol(analysis, index)
        name = outline.rung_title(analysis.program, index)  # the number changes when rungs are added above
        if symbol["name"] != name:
            symbol, text = _with_text(dict(symbol, name=name))
        found.append((symbol, text))
    return found


def document_symbols(analysis: Analysis) -> list[Encodable]:
    """The top-level DocumentSymbol objects in JSON form, each with its JSON text:
    a text file's sections holding its rungs, a .ld file's rungs."""
    rungs = rung_symbols(analysis)
    sections = outline.section_symbols(analysis)
    if not sections:
        return rungs
    result = []
    for section in sections:
        symbol = _json(analysis, section)
        text = _encoded(symbol)
        children = [(s, t) for s, t in rungs if section.span.line <= s["range"]["start"]["line"] <= section.span.end_line]
        if children:
            symbol["children"] = [s for s, _ in children]
            text = text[:-1] + ',"children":[' + ",".join(t for _, t in children) + "]}"
        result.append((symbol, text))
    return result


def _flat(symbols: list[Json], uri: str, container: str | None = None) -> list[Json]:
    out = []
    for symbol in symbols:
        entry: Json = {"name": symbol["name"], "kind": symbol["kind"], "location": {"uri": uri, "range": symbol["range"]}}
        if container:
            entry["containerName"] = container
        out.append(entry)
        out.extend(_flat(symbol.get("children", []), uri, symbol["name"]))
    return out


def _fold(fold: Fold | None) -> Json | None:
    if fold is None:
        return None
    return {"startLine": fold.first, "endLine": fold.last, "kind": "comment" if fold.comment else "region"}


def rung_fold(analysis: Analysis, index: int) -> Json | None:
    """A rung's folding range, kept while the rung is unchanged."""
    return analysis.per_rung("fold", index, lambda i: _fold(outline.rung_fold(analysis, i)))


def folding_ranges(analysis: Analysis) -> list[Json]:
    ranges = []
    for _, _, index in analysis.locator.rung_extents():
        found = rung_fold(analysis, index)
        if found is not None:
            ranges.append(found)
    ranges.extend(f for f in map(_fold, outline.section_folds(analysis)) if f is not None)
    return ranges


def _shift_range(r: Json, delta: int) -> Json:
    return {"start": {"line": r["start"]["line"] + delta, "character": r["start"]["character"]},
            "end": {"line": r["end"]["line"] + delta, "character": r["end"]["character"]}}


def _shift_symbol_text(symbol: Encodable, delta: int) -> Encodable:
    return _with_text(_shift_symbol(symbol[0], delta))


def _shift_symbol(symbol: Json, delta: int) -> Json:
    moved = dict(symbol, range=_shift_range(symbol["range"], delta),
                 selectionRange=_shift_range(symbol["selectionRange"], delta))
    if "children" in symbol:
        moved["children"] = [_shift_symbol(c, delta) for c in symbol["children"]]
    return moved


def _shift_fold(fold: Json | None, delta: int) -> Json | None:
    if fold is None:
        return None
    return dict(fold, startLine=fold["startLine"] + delta, endLine=fold["endLine"] + delta)


def register(server: LadderServer) -> None:
    server.documents.shifters["symbol"] = _shift_symbol_text
    server.documents.shifters["fold"] = _shift_fold

    @server.on(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    def symbols(ls: LadderServer, params: types.DocumentSymbolParams) -> Encoded | Raw | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        found = analysis.once("symbols", lambda: document_symbols(analysis))
        if ls.client_supports("text_document", "document_symbol", "hierarchical_document_symbol_support"):
            return Encoded("[" + ",".join(text for _, text in found) + "]")
        return Raw(_flat([symbol for symbol, _ in found], analysis.uri))

    @server.on(types.TEXT_DOCUMENT_FOLDING_RANGE)
    def folding(ls: LadderServer, params: types.FoldingRangeParams) -> Raw | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        return Raw(analysis.once("folding", lambda: folding_ranges(analysis)))
