"""LD714: a digital input or output on a pin that READ ADC makes analog,
on the parts whose ADCON1 chooses the analog pins in fixed groups."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import analog_group
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import used_pins

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if not index.pins_matter:
        return []
    read = set()
    for _, element in index.of_kind("READ_ADC"):
        assignment = program.pins.get(token(element.args.get("name")))
        pin = device.pin(assignment.pin) if assignment is not None and assignment.assigned else None
        if pin is not None and pin.name in device.adc:
            read.add(device.adc[pin.name])
    group = analog_group(device, read)
    if group is None:
        return []
    inputs = ", ".join(f"AN{c}" for c in sorted(read))
    found = []
    for name, _, pin in sorted(used_pins(program, index), key=lambda used: used[0]):
        channel = device.adc.get(pin.name) if pin is not None else None
        if name[0] in "XYP" and channel in group[1] and channel not in read:
            effect = "it reads 0" if name[0] == "X" else "reading the port back reads it as 0"
            found.append(report(CODE, f"'{name}' is on {pin.name} (AN{channel}), which the {device.title} makes "
                                      f"analog with the A/D inputs on {inputs}: {effect}",
                                index.uses[name][0].span))
    return found
