"""Where every bit and variable lives on a PIC16.

The file registers are split into banks of 128 addresses; an instruction
names 7 bits of the address and STATUS.RP1:RP0 supply the bank. Some bytes
are reachable from every bank: the core registers (STATUS, FSR, PCLATH,
INTCON...) and, on most parts, a 16-byte common RAM. What is used most goes
where no bank selection is needed:

* the integer patterns' scratch bytes and the packed bits (relays, element
  memories, the rungs' temporary power bits) in common RAM first, then
  bank 0;
* variables in bank 0 first, then the other banks; a variable never
  straddles two banks.

Input pins are bits of their PORT register (reading it reads the pins),
outputs bits of their PORT latch. Temporaries whose uses do not overlap
share a bit; a temporary still needed after a GOSUB gets a bit of its own
(the called rungs use the same temporaries and there is no data stack).
"""

from __future__ import annotations

from dataclasses import dataclass

from lang.hardware import register_address
from lang.semantics import ir

from ..analysis import live_intervals, use_counts
from ..errors import NOT_COMPILED, RAM_FULL, fail
from .part import Part

SCRATCH_BYTES = 14  # the integer patterns' A, B, C (4 bytes each), a counter D and a spare E


@dataclass(frozen=True)
class FileBit:
    addr: int
    bit: int
    ram: bool = True  # False: a port, which the hardware changes


@dataclass(frozen=True)
class Storage:
    addr: int
    size: int
    ram: bool  # False for special function registers (#PORTB)


@dataclass
class Layout:
    bits: dict[str, FileBit]
    vars: dict[str, Storage]
    scratch: tuple[int, ...]  # SCRATCH_BYTES addresses
    ram_used: int
    ram_size: int
    clock: int | None = None  # a free-running cycle's tick count high byte and 3-byte deadline
    clock_bytes: int = 4  # the bytes at `clock` (the baseline PIC10's cycle needs three)


class _Ram:
    """Free RAM bytes: common RAM first, then bank by bank."""

    def __init__(self, part: Part):
        self.common = list(part.common or ())
        shared = set(self.common)
        self.banked = [a for span in part.ram_ranges() for a in span if a not in shared]
        self.size = len(self.common) + len(self.banked)
        self.used = 0
        self.bank = part.bank_bytes

    def byte(self) -> int:
        """One byte, reachable from every bank if possible."""
        pool = self.common or self.banked
        if not pool:
            raise _Full()
        self.used += 1
        return pool.pop(0)

    def block(self, size: int) -> int:
        """`size` consecutive bytes in one bank (the lowest bank that has them)."""
        for pool in (self.banked, self.common):
            for i in range(len(pool) - size + 1):
                run = pool[i:i + size]
                if run[-1] - run[0] == size - 1 and run[0] // self.bank == run[-1] // self.bank:
                    del pool[i:i + size]
                    self.used += size
                    return run[0]
        raise _Full()


class _Full(Exception):
    pass


def _pin_bit(part: Part, machine, name: str, kind: str) -> FileBit:
    """An input reads its pin; an output is its latch's bit."""
    pin = machine.pins[name]
    return FileBit(part.port(pin.port) if kind == ir.INPUT else part.latch(pin.port), pin.bit, False)


def allocate(code: ir.Code, part: Part, machine, free_running: bool = False, scratch_bytes: int = SCRATCH_BYTES,
             clock_bytes: int = 4) -> Layout:
    """`scratch_bytes` of scratch first (fewer when a back end places them
    itself, as the baseline PIC10 places those its code uses), and
    `clock_bytes` for a free-running cycle."""
    ram = _Ram(part)
    bits: dict[str, FileBit] = {}
    try:
        scratch = tuple(ram.byte() for _ in range(scratch_bytes))
        packed: list[str] = []
        for name, kind in code.bits.items():
            if kind in (ir.INPUT, ir.OUTPUT):
                bits[name] = _pin_bit(part, machine, name, kind)
        memory = [n for n, k in code.bits.items() if k == ir.MEMORY]
        counts = use_counts(code.scan, set(memory))
        packed += sorted(memory, key=lambda n: -counts[n])
        temps = {n for n, k in code.bits.items() if k == ir.TEMP}
        kept = {b.name for op in code.scan if isinstance(op, ir.Call) for b in op.keep}
        packed += sorted(kept & temps)
        # the other temporaries: interval allocation over the scan's ops
        shared: list[int] = []  # slot index -> last op using it
        slot_of: dict[str, int] = {}
        for name, (start, end) in sorted(live_intervals(code.scan, temps - kept).items(), key=lambda kv: kv[1]):
            slot = next((i for i, last in enumerate(shared) if last < start), None)
            if slot is None:
                slot = len(shared)
                shared.append(end)
            else:
                shared[slot] = end
            slot_of[name] = slot
        slots = [f"$slot{i}" for i in range(len(shared))]
        packed += slots
        places: dict[str, FileBit] = {}
        for first in range(0, len(packed), 8):
            address = ram.byte()
            for bit, name in enumerate(packed[first:first + 8]):
                places[name] = FileBit(address, bit)
        bits.update((n, places[n]) for n in packed if n not in slots)
        bits.update((n, places[slots[s]]) for n, s in slot_of.items())
        variables: dict[str, Storage] = {}
        for name, size in code.vars.items():
            if name.startswith("#"):
                register = register_address(part.device, name)
                if register is None:
                    raise fail(NOT_COMPILED, f"'{name}' names no register of the {part.title}; indirect "
                                             "register access is not compiled", machine.locate(name))
                variables[name] = Storage(register, 1, False)
                continue
            variables[name] = Storage(ram.block(size), size, True)
        clock = ram.block(clock_bytes) if free_running else None
    except _Full:
        needed = scratch_bytes + (len(code.bits) + 7) // 8 + sum(code.vars.values())
        raise fail(RAM_FULL, f"the variables, bits and the compiler's {scratch_bytes} scratch bytes need about "
                             f"{needed} bytes of RAM in banks of {part.bank_bytes} addresses; the {part.title} has "
                             f"{ram.size}") from None
    return Layout(bits, variables, scratch, ram.used, ram.size, clock, clock_bytes)
