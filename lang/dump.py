"""The model as JSON (`ladder dump`): a versioned, stable shape for other tools."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import asdict, dataclass

from .model import Element, Node, Parallel, Program, Span
from .trampoline import run

DUMP_VERSION = 1
INDENT = "  "


def _span(span: Span | None) -> list[int] | None:
    return None if span is None else [span.line, span.col, span.end_line, span.end_col]


def _value(value: object) -> object:
    if isinstance(value, tuple):
        return [_value(v) for v in value]
    return value


def node_json(node: Node) -> dict:
    return run(_node_json(node))


def _node_json(node: Node):
    if isinstance(node, Element):
        return {"element": node.kind, "args": {k: _value(v) for k, v in node.args.items()}, "span": _span(node.span)}
    key = "parallel" if isinstance(node, Parallel) else "series"
    children = []
    for child in node.branches if isinstance(node, Parallel) else node.items:
        children.append((yield _node_json(child)))
    return {key: children, "span": _span(node.span)}


def _settings(program: Program) -> dict:
    settings = asdict(program.settings)
    span = program.settings.mcu_span
    settings["mcu_span"] = None if span is None else span._asdict()
    return settings


def program_json(program: Program) -> dict:
    return {
        "version": DUMP_VERSION,
        "settings": _settings(program),
        "pins": [
            {"name": p.name, "pin": p.pin, "modbus_slave": p.modbus_slave, "modbus_register": p.modbus_register}
            for p in program.pins.values()
        ],
        "var_sizes": dict(sorted(program.var_sizes.items())),
        "pullups": dict(sorted(program.pullups.items())),
        "rungs": [{"circuit": node_json(rung.circuit), "span": _span(rung.span)} for rung in program.rungs],
    }


def dumps(program: Program) -> str:
    return json_text(program_json(program)) + "\n"


@dataclass
class _Open:
    """A list or object being written: its entries left (key None in a list)."""

    entries: Iterator[tuple[str | None, object]]
    close: str
    started: bool = False


def json_text(value: object) -> str:
    """What json.dumps(value, indent=2, ensure_ascii=False) gives, written
    with a stack of open containers: json.dumps recurses once per level, and
    a rung may nest parallels thousands of levels deep."""
    out: list[str] = []
    stack: list[_Open] = []
    _begin(value, out, stack)
    while stack:
        top = stack[-1]
        entry = next(top.entries, None)
        if entry is None:
            stack.pop()
            out.append("\n" + INDENT * len(stack) + top.close)
            continue
        out.append(("," if top.started else "") + "\n" + INDENT * len(stack))
        top.started = True
        key, item = entry
        if key is not None:
            out.append(json.dumps(key, ensure_ascii=False) + ": ")
        _begin(item, out, stack)
    return "".join(out)


def _begin(value: object, out: list[str], stack: list[_Open]) -> None:
    """A scalar or empty container whole; a container's opening bracket,
    its entries left on the stack."""
    if isinstance(value, dict) and value:
        out.append("{")
        stack.append(_Open(iter(value.items()), "}"))
    elif isinstance(value, (list, tuple)) and value:
        out.append("[")
        stack.append(_Open(((None, item) for item in value), "]"))
    else:
        out.append(json.dumps(value, ensure_ascii=False))
