"""LD413: an I/O name on a pin that the chip, as the build configures it,
gives to its oscillator, its reset input or its programming interface:
works in the simulator, not on the chip.

Which pin does what under which setting is device data (`reserved_pins` in
lang/devices/*.json): a PIC's pin is taken when its configuration word (the
program's ConfigurationWord, else the part's default that the build writes)
selects the function; an AVR's crystal pins when the crystal frequency is
none its internal oscillator makes; an AVR's reset pin always, as shipped
(the fuse that frees it also ends programming over ISP)."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from ..values import format_frequency
from .common import is_analog, is_pwm, pin_text, used_pins

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if not index.pins_matter:
        return []
    reserved = device.data.get("reserved_pins", {})
    found = []
    for name, assignment, pin in used_pins(program, index):
        if pin is None or pin.name not in reserved:
            continue
        output = name.startswith("Y") or is_pwm(index, name)
        if output and pin.input_only:
            continue  # LD412: no output driver at all
        for entry in reserved[pin.name]:
            why = _taken(program, device, entry, is_analog(index, name))
            if why is None:
                continue
            what = "output" if output else "input"
            where = pin_text(assignment)
            where = where if where == pin.name else f"{where} ({pin.name})"
            found.append(report(
                CODE,
                f"{what} '{name}' is on {where}, which the {device.title} uses as "
                f"{entry['use']}, {why}: on the chip it is no {what}, although the simulator shows one",
                assignment.span,
            ))
            break
    return found


def _taken(program: Program, device, entry: dict, analog: bool) -> str | None:
    """Why the pin is taken in the build's configuration, or None when it is free."""
    if "field" in entry:
        word, default = configuration_word(program, device)
        value = word & entry["mask"]
        if value not in entry["values"]:
            return None
        if default:
            symbol = device.data[device.family]["config"]["fields"][entry["field"]]["symbol"]
            return f"with the configuration word the build writes (the part's default, 0x{word:04X}: {symbol})"
        return f"with the program's configuration word 0x{word:04X} (its {entry['field']} bits 0x{value:X} select it)"
    if "clock_hz_internal" in entry:
        crystal = program.settings.crystal_hz
        internal = entry["clock_hz_internal"]
        if crystal in internal:
            return None
        made = ", ".join(format_frequency(hz) for hz in internal[:-1]) + f" and {format_frequency(internal[-1])}"
        taken = entry.get("clock_source", "a crystal takes XTAL1 and XTAL2 (an external clock XTAL1 alone)")
        return (f"when it runs at {format_frequency(crystal)}, a clock its internal oscillator cannot make (it makes "
                f"{made}), so {taken}")
    if analog:
        return None  # an A/D input on the reset pin reads while its voltage stays above the reset level
    return f"unless the {entry['fuse']} fuse is programmed, which also ends programming the chip over ISP"


def configuration_word(program: Program, device) -> tuple[int, bool]:
    """The first configuration word the build writes, and whether it is the
    part's default: the program's ConfigurationWord setting (its low 16
    bits, as LDmicro stores two words) when it sets one."""
    if program.settings.config_word:
        return program.settings.config_word & 0xFFFF, False
    words = device.data[device.family]["config"]["words"]
    return min(words, key=lambda w: w["address"])["value"], True
