"""The output latch FSR1 points at. The latches (LATx) are in bank 2, the
ports and the variables in bank 0, so every write to an output pin would
select bank 2 and the next variable bank 0 again. INDF1 is in every bank:
with FSR1 pointing at the latch the program uses most, its bits are tested
and written as INDF1's without a bank selection. FSR1 is loaded once at
reset and nothing else writes it (the patterns point FSR0)."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

from lang.semantics import ir

from ...analysis import use_counts
from ..memory import Layout
from ..part import Part

DUTY_WRITES = 2  # YPlcCycleDuty set and cleared each scan


@dataclass(frozen=True)
class Alias:
    latch: int  # the latch's data address
    indf: int  # INDF1
    pointer: tuple[int, int]  # FSR1L, FSR1H

    def prologue(self) -> list[tuple[str, tuple]]:
        """FSR1 = the latch's address."""
        low, high = self.pointer
        return [("movlw", (self.latch & 0xFF,)), ("movwf", (low,)),
                ("movlw", (self.latch >> 8,)), ("movwf", (high,))]


def busiest_latch(code: ir.Code, layout: Layout, part: Part, machine) -> Alias | None:
    """The latch with the most output reads and writes in the scan (the
    cycle-duty pin's two writes too); None without outputs, or when the
    program names FSR1 or INDF1 itself (`#0x06`, `#0x86`...)."""
    # core registers are in every bank: #0x86 is FSR1L too
    own = {part.reg(name) & 0x7F for name in ("INDF1", "FSR1L", "FSR1H")}
    if any(not storage.ram and storage.addr & 0x7F in own for storage in layout.vars.values()):
        return None
    outputs = {name for name, kind in code.bits.items() if kind == ir.OUTPUT}
    uses: Counter[int] = Counter()
    for name, count in use_counts(code.scan, outputs).items():
        uses[layout.bits[name].addr] += count
    pin = machine.duty_pin
    if pin is not None:
        uses[part.latch(pin.port_bit[0])] += DUTY_WRITES
    if not uses:
        return None
    latch = max(sorted(uses), key=lambda address: uses[address])
    return Alias(latch, part.reg("INDF1"), (part.reg("FSR1L"), part.reg("FSR1H")))
