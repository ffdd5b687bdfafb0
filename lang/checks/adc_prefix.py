"""LD109: READ ADC into a name that does not start with A."""

from __future__ import annotations

from ..codes import register
from ..values import is_literal
from ..diagnostics import warning
from .common import arg_span, rung_no, token

CODE = register(
    "LD109", "READ ADC name does not start with A",
    "READ ADC reads the analog pin assigned to its name. LDmicro makes that name an A/D input "
    "whatever its first letter, but by convention (and for the I/O list and the pin checks) it "
    "starts with A.",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("READ_ADC"):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and not name.startswith("A"):
            found.append(warning(
                CODE,
                f"READ ADC '{name}' in {rung_no(rung)}: A/D input names start with A (e.g. 'A{name}')",
                arg_span(element, "name"),
            ))
    return found
