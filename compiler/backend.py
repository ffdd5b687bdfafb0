"""The seam between the compiler's front end and its back ends.

A back end sees two things: the optimised intermediate code (`ir.Code`) and
a `Machine`, a neutral description of what to build for (the part, the
clock, the scan cycle, the pins and the settings that shape the runtime).
It never sees the ladder `Program`. Each family in `lang.families.FAMILIES`
with parts has one back end, the package `compiler.<family>`, which registers
itself here when it is imported; `compiler/__init__.py` imports one for each
such family, so `lang.families` is the one list of back ends.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from lang.devices import Device, Pin
from lang.model import Program
from lang.roles import CYCLE_DUTY_PIN
from lang.semantics import ir

from .budget import Decoder
from .image import Image


@dataclass(frozen=True)
class Machine:
    device: Device  # the part and package: pins, A/D, PWM and UART maps; .data has the family's key
    crystal_hz: int
    cycle_us: int
    baud: int
    pins: dict[str, Pin]  # every assigned name that has a pin on the device -> that pin
    pullups: dict[str, int]  # port letter -> pull-up mask; a port absent: all on (LDmicro)
    duty_pin: Pin | None  # YPlcCycleDuty's pin when the cycle-duty setting is on
    config_word: int | None  # the ConfigurationWord setting when the program sets one (PIC)
    cycle_timer: int | None  # the "at Timer0/Timer1" choice, None without a cycle
    locate: Callable[[str], object | None]  # name -> the first element using it (to place diagnostics)
    elements: Callable[[str], list]  # instruction kind -> its elements in program order


class Backend(Protocol):
    family: str  # its key in lang.families.FAMILIES
    delay_loop_cycles: int  # CPU cycles one count of a variable DELAY takes (T2DLY converts with it)
    rungs_by_jumps: bool  # the optimiser evaluates rungs by tests and jumps (compiler.optimise) for it

    @property
    def flow(self) -> Decoder:
        """Reads the family's program memory for the scan budget: its module compiler.<family>.flow."""
        ...

    def compile(self, code: ir.Code, machine: Machine) -> Image: ...


BACKENDS: dict[str, Backend] = {}


def register(backend: Backend) -> None:
    BACKENDS[backend.family] = backend


def machine_for(program: Program, device: Device) -> Machine:
    """What a back end needs to know of a checked program, for a device."""
    settings = program.settings
    pins = {name: pin for name, assignment in program.pins.items()
            if (pin := device.pin(assignment.pin)) is not None}
    duty = pins.get(CYCLE_DUTY_PIN) if settings.cycle_duty else None
    return Machine(
        device=device,
        crystal_hz=settings.crystal_hz,
        cycle_us=settings.cycle_us,
        baud=settings.baud,
        pins=pins,
        pullups={port[1:].upper(): mask for port, mask in program.pullups.items() if len(port) == 2},
        duty_pin=duty if duty is not None and duty.is_io else None,
        config_word=settings.config_word or None,
        cycle_timer=settings.cycle_timer if settings.cycle_timer >= 0 else None,
        locate=lambda name: first_use(program, name),
        elements=lambda kind: [element for _, element in program.elements() if element.kind == kind],
    )


def first_use(program: Program, name: str):
    for _, element in program.elements():
        if name in {str(v) for v in element.args.values()}:
            return element
    return None
