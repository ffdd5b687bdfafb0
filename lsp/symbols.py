"""The outline (ide.outline) as LSP's document symbols and folding ranges.

Clients ask for both after every edit (VS Code's breadcrumbs and outline), so
each rung's part is computed once and kept while the rung is unchanged
(`Analysis.per_rung`), with its JSON text, those texts are kept joined in
runs of rungs (`Analysis.per_run`), and the answer is the runs' texts joined
(`Encoded`): for a 2,000-rung program, building and converting thousands of
lsprotocol objects, or encoding 1.5 MB of JSON again, would cost more than
the rest of the request, and for 18,000 rungs joining 18,000 parts would."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import replace
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


def _rung_text(analysis: Analysis, index: int) -> str:
    """A drawn rung's symbol's JSON text, with its number now (rungs added above renumber it)."""
    symbol, text = rung_symbol(analysis, index)
    name = outline.rung_title(analysis.program, index)
    return text if symbol["name"] == name else _encoded(dict(symbol, name=name))


def _sections(analysis: Analysis) -> list[tuple[Symbol | None, list[int]]]:
    """Each section of a text file with the indexes of the drawn rungs its
    lines hold; for a .ld file, None with every drawn rung."""
    extents = analysis.locator.rung_extents()
    sections = outline.section_symbols(analysis)
    if not sections:
        return [(None, [index for _, _, index in extents])]
    above = analysis.locator.rungs_above
    return [(section, [index for _, _, index in extents[above(section.span.line):above(section.span.end_line + 1)]])
            for section in sections]


# the line numbers of a symbol's or a folding range's JSON text ("line", "startLine", "endLine"; a
# string's quotes are escaped, so none is in a name or a detail)
_LINE_NUMBER = re.compile(r'(?<=ine":)(\d+)')


# a run's JSON text, and that text split around its line numbers (at the odd places): moved by a
# line added above, it is shifted, not encoded again
Template = tuple[str, list[str]]


def _template(text: str) -> Template:
    return text, _LINE_NUMBER.split(text)


def _shift_template(template: Template, delta: int) -> Template:
    parts = template[1][:]
    parts[1::2] = [str(int(number) + delta) for number in parts[1::2]]
    return "".join(parts), parts


def _joined(runs: list[Template]) -> list[str]:
    """The runs' texts with a comma between each two that are not empty, to be joined once with the rest."""
    return [piece for text, _ in runs if text for piece in (",", text)][1:]


def _symbol_runs(analysis: Analysis, section: Symbol | None, indexes: list[int]) -> Iterator[Template]:
    return analysis.per_run(f"symbols {section.name if section else ''}", indexes,
                             lambda run: _template(",".join(_rung_text(analysis, index) for index in run)),
                             _shift_template)


def document_symbols(analysis: Analysis) -> str:
    """The JSON text of the hierarchical DocumentSymbol objects: a text file's
    sections holding its rungs, a .ld file's rungs. The rungs' texts are
    joined in runs kept while their rungs are unchanged, shifted when a line
    added or removed above moved them (`Analysis.per_run`), so an edit of one
    rung joins that rung's run again, not every rung; the answer (13 MB for
    18,000 rungs) is joined once, from its pieces."""
    pieces: list[str] = []
    for section, indexes in _sections(analysis):
        runs = _joined(list(_symbol_runs(analysis, section, indexes)))
        if pieces:
            pieces.append(",")
        if section is None:
            pieces.extend(runs)
            continue
        text = _encoded(_json(analysis, section))
        pieces.extend([text[:-1], ',"children":[', *runs, "]}"] if runs else [text])
    return "".join(["[", *pieces, "]"])


def flat_symbols(analysis: Analysis) -> list[Json]:
    """The SymbolInformation objects in JSON form, for a client without hierarchical symbols."""
    found = []
    for section, indexes in _sections(analysis):
        rungs = [dict(rung_symbol(analysis, index)[0], name=outline.rung_title(analysis.program, index))
                 for index in indexes]
        if section is None:
            found.extend(rungs)
        else:
            found.append(dict(_json(analysis, section), children=rungs) if rungs else _json(analysis, section))
    return _flat(found, analysis.uri)


def _flat(symbols: list[Json], uri: str, container: str | None = None) -> list[Json]:
    out = []
    for symbol in symbols:
        entry: Json = {"name": symbol["name"], "kind": symbol["kind"], "location": {"uri": uri, "range": symbol["range"]}}
        if container:
            entry["containerName"] = container
        out.append(entry)
        out.extend(_flat(symbol.get("children", []), uri, symbol["name"]))
    return out


def _fold(fold: Fold) -> str:
    kind = "comment" if fold.comment else "region"
    return f'{{"startLine":{fold.first},"endLine":{fold.last},"kind":"{kind}"}}'


def rung_fold(analysis: Analysis, index: int) -> Fold | None:
    """A rung's folding range, kept while the rung is unchanged."""
    return analysis.per_rung("fold", index, lambda i: outline.rung_fold(analysis, i))


def _fold_runs(analysis: Analysis) -> Iterator[Template]:
    indexes = [index for _, _, index in analysis.locator.rung_extents()]
    return analysis.per_run("folding", indexes, lambda run: _template(",".join(
        _fold(fold) for fold in (rung_fold(analysis, index) for index in run) if fold is not None)), _shift_template)


def runs(analysis: Analysis) -> Iterator[object]:
    """The runs of the outline and the folding worked out one at a time (lsp/warmup.py)."""
    for section, indexes in _sections(analysis):
        yield from _symbol_runs(analysis, section, indexes)
    yield from _fold_runs(analysis)


def folding_ranges(analysis: Analysis) -> str:
    """The JSON text of the FoldingRange objects: each rung's, joined in runs
    kept while their rungs are unchanged (shifted when moved), and each section's."""
    runs = list(_fold_runs(analysis))
    runs.extend(_template(_fold(fold)) for fold in outline.section_folds(analysis))
    return "".join(["[", *_joined(runs), "]"])


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


def _shift_fold(fold: Fold | None, delta: int) -> Fold | None:
    return None if fold is None else replace(fold, first=fold.first + delta, last=fold.last + delta)


def register(server: LadderServer) -> None:
    server.documents.shifters["symbol"] = _shift_symbol_text
    server.documents.shifters["fold"] = _shift_fold

    @server.on(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    def symbols(ls: LadderServer, params: types.DocumentSymbolParams) -> Encoded | Raw | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        if ls.client_supports("text_document", "document_symbol", "hierarchical_document_symbol_support"):
            return Encoded(analysis.once("symbols", lambda: document_symbols(analysis)))
        return Raw(flat_symbols(analysis))

    @server.on(types.TEXT_DOCUMENT_FOLDING_RANGE)
    def folding(ls: LadderServer, params: types.FoldingRangeParams) -> Encoded | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        return Encoded(analysis.once("folding", lambda: folding_ranges(analysis)))
