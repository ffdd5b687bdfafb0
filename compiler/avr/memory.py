"""Where every bit and variable lives.

Bits are packed eight to a byte. Input pins are bits of their PIN register,
outputs bits of their PORT latch. The program's relays and the elements'
hidden memories go to registers r3..r15 (the most used first), where one
instruction tests or copies them, and the rest to RAM bytes. The rung's
temporary power bits share registers r16 and r17 (on the reduced core, which
has r16..r31 only, memory bits are in RAM and temporaries in r17): two temporaries whose uses
do not overlap get the same bit; when more are live at once they spill to
RAM. Integer variables are consecutive RAM bytes, least significant first;
`#PORTB`-style names are the part's registers.
"""

from __future__ import annotations

from dataclasses import dataclass

from lang.hardware import register_address
from lang.semantics import ir

from ..analysis import live_intervals, use_counts
from ..backend import Machine
from ..errors import NOT_COMPILED, RAM_FULL, fail
from .part import Part


@dataclass(frozen=True)
class Registers:
    """The registers given to bits and to the two fixed uses, by core."""

    zero: int  # always 0
    loaded: int  # where a byte is loaded to test one of its bits
    homes: tuple[int, ...]  # memory bits, eight each
    temps: tuple[int, ...]  # the rung's power bits, eight each


# the reduced core has r16..r31 only: the integer patterns keep r18..r31, so
# memory bits live in RAM, eight power bits in r17, and r31 (free between
# the routines that use it) takes the loaded byte
REGISTERS = {"classic": Registers(2, 0, tuple(range(3, 16)), (16, 17)),
             "reduced": Registers(16, 31, (), (17,))}


@dataclass(frozen=True)
class RegBit:
    reg: int
    bit: int


@dataclass(frozen=True)
class MemBit:
    """A bit of a data-space byte: an I/O register or RAM."""

    addr: int
    bit: int
    ram: bool = True


@dataclass(frozen=True)
class Storage:
    addr: int
    size: int
    ram: bool  # False for I/O registers, whose value hardware may change


@dataclass
class Layout:
    bits: dict[str, RegBit | MemBit]
    vars: dict[str, Storage]
    ram_used: int  # bytes from the start of RAM
    homes: tuple[int, ...]  # registers holding memory bits


def allocate(code: ir.Code, part: Part, machine: Machine) -> Layout:
    bits: dict[str, RegBit | MemBit] = {}
    ram_bits: list[str] = []
    # pins
    for name, kind in code.bits.items():
        if kind in (ir.INPUT, ir.OUTPUT):
            pin = machine.pins[name]
            port, bit = pin.port_bit
            bits[name] = MemBit(part.port("PIN" if kind == ir.INPUT else "PORT", port), bit, False)
    # memory bits: the most used in registers
    memory = [n for n, k in code.bits.items() if k == ir.MEMORY]
    counts = use_counts(code.scan, set(memory))
    ranked = sorted(memory, key=lambda n: -counts[n])
    plan = REGISTERS[part.core.name]
    slots = [RegBit(r, b) for r in plan.homes for b in range(8)]
    for name, slot in zip(ranked, slots):
        bits[name] = slot
    ram_bits += ranked[len(slots):]
    homes = tuple(sorted({slot.reg for _, slot in zip(ranked, slots)}))
    # temporaries: interval allocation over the scan's ops
    temps = {n for n, k in code.bits.items() if k == ir.TEMP}
    free = [RegBit(r, b) for r in plan.temps for b in range(8)]
    active: list[tuple[int, RegBit]] = []  # (last use, the bit) of the temporaries in registers
    for name, (start, end) in sorted(live_intervals(code.scan, temps).items(), key=lambda kv: kv[1]):
        for last, held in list(active):
            if last < start:
                active.remove((last, held))
                free.append(held)
        if free:
            bits[name] = held = free.pop(0)
            active.append((end, held))
        else:
            ram_bits.append(name)
    # RAM: bit bytes, then variables
    address = part.ram_start
    for i, name in enumerate(ram_bits):
        bits[name] = MemBit(address + i // 8, i % 8)
    address += (len(ram_bits) + 7) // 8
    variables: dict[str, Storage] = {}
    for name, size in code.vars.items():
        if name.startswith("#"):
            register = register_address(part.device, name)
            if register is None:
                raise fail(NOT_COMPILED, f"'{name}' names no register of the {part.title}; indirect "
                                         "register access is not compiled", machine.locate(name))
            variables[name] = Storage(register, 1, False)
            continue
        variables[name] = Storage(address, size, True)
        address += size
    used = address - part.ram_start
    fits_ram(part, used, part.stack_reserve)
    return Layout(bits, variables, used, homes)


def fits_ram(part: Part, used: int, stack: int) -> None:
    """LD704 unless the variables and the stack fit the part's RAM."""
    size = part.ram_end - part.ram_start + 1
    if used + stack > size:
        raise fail(RAM_FULL, f"the variables need {used} bytes of RAM and the stack {stack}; "
                             f"the {part.title} has {size}")
