"""The model as JSON (`ladder dump`): a versioned, stable shape for other tools."""

from __future__ import annotations

import json
from dataclasses import asdict

from .model import Element, Node, Parallel, Program, Span

DUMP_VERSION = 1


def _span(span: Span | None) -> list[int] | None:
    return None if span is None else [span.line, span.col, span.end_line, span.end_col]


def _value(value: object) -> object:
    if isinstance(value, tuple):
        return [_value(v) for v in value]
    return value


def node_json(node: Node) -> dict:
    if isinstance(node, Element):
        return {"element": node.kind, "args": {k: _value(v) for k, v in node.args.items()}, "span": _span(node.span)}
    key = "parallel" if isinstance(node, Parallel) else "series"
    children = node.branches if isinstance(node, Parallel) else node.items
    return {key: [node_json(child) for child in children], "span": _span(node.span)}


def program_json(program: Program) -> dict:
    return {
        "version": DUMP_VERSION,
        "settings": asdict(program.settings),
        "pins": [
            {"name": p.name, "pin": p.pin, "modbus_slave": p.modbus_slave, "modbus_register": p.modbus_register}
            for p in program.pins.values()
        ],
        "var_sizes": dict(sorted(program.var_sizes.items())),
        "pullups": dict(sorted(program.pullups.items())),
        "rungs": [{"circuit": node_json(rung.circuit), "span": _span(rung.span)} for rung in program.rungs],
    }


def dumps(program: Program) -> str:
    return json.dumps(program_json(program), indent=2, ensure_ascii=False) + "\n"
