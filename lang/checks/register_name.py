"""LD702: a `#` name (indirect register access) that names none of the part's
registers, which the back ends have no code for; and a raw register access
(RSFR...TCSFR) at a constant address that is none of them either: on an AVR
the working registers r0-r31 (data addresses 0x00-0x1F), which the compiled
program keeps its own values in, or an address past the end of RAM."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..families import compiled, family_of
from ..hardware import data_addresses, register_address
from ..index import ProgramIndex
from ..model import Program
from .common import NAMES, RUNGS, arg_span, literal_or_none, rung_no

CODE = rule_code(__name__)
SFR_KINDS = ("RSFR", "WSFR", "SSFR", "CSFR", "TSFR", "TCSFR")

# the operand kinds that hold an integer variable, which a `#` name makes a register
_INTEGER_KINDS = frozenset({"var", "operand", "delay"})


def _holds_integer(use) -> bool:
    return any(field.name == use.field and field.kind in _INTEGER_KINDS for field in use.element.spec.fields)


def check_names(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if not index.pins_matter or not compiled(device):
        return []
    found = []
    for name, uses in index.uses.items():
        if name[:1] != "#" or register_address(device, name) is not None:
            continue
        if any(_holds_integer(use) for use in uses):
            # the build names the first element that uses it
            found.append(report(CODE, f"'{name}' names no register of the {device.title}; indirect register "
                                      "access is not compiled", uses[0].element.span))
    return found


def check_addresses(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    family = family_of(device) if device is not None and compiled(device) else None
    if family is None:
        return []
    found = []
    for rung, element in index.of_kind(*SFR_KINDS):
        text = str(element.args.get("sfr", ""))
        address = literal_or_none(text)
        if not element.spec.supports(family.key) or address is None:
            continue
        if register_address(device, f"#{address}") is None:
            place = "first" if element.spec.fields[0].name == "sfr" else "second"
            found.append(report(CODE, f"{element.kind} in {rung_no(rung)}: address {text} is none of the "
                                      f"{device.title}'s registers or RAM ({_reach(device)}); the address is "
                                      f"{element.kind}'s {place} operand, as LDmicro compiles it",
                                arg_span(element, "sfr")))
    return found


def _reach(device) -> str:
    addresses = data_addresses(device)
    return f"data addresses 0x{addresses.start:02X} to 0x{addresses.stop - 1:X}" + (
        "; 0x00 to 0x1F are the working registers, which the compiled program uses" if addresses.start else "")


CHECKS = {NAMES: check_names, RUNGS: check_addresses}
