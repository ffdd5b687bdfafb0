"""The baseline assembler: the items the shared emitter writes
(compiler/pic16/asm.py's `Writer`, in the mid-range instruction set) become
12-bit program words and a listing that gpasm reassembles to the same words.

What the mid-range patterns write and the baseline lacks is written with
what it has, on a byte of RAM of its own (`temp`), with the same result
and the same C and Z:

    ADDLW k   MOVWF t; MOVLW k; ADDWF t,W   (after MOVF f,W: MOVLW k; ADDWF f,W)
    SUBLW k   XORLW 0xFF; MOVWF t; MOVLW k+1; ADDWF t,W    (k - W = ~W + k + 1)
    SUBLW 255 XORLW 0xFF; BSF STATUS,C
    RETURN    RETLW 0    (W after a call is never relied on: the emitter forgets it)

None of them may follow a skip (a skip skips one word): the patterns write
them after a load of W, never under a skip; the assembler checks it.

Reach. A GOTO reaches all 512 words; a CALL, and a computed jump (a write
to PCL), only the first 256 (bit 8 of the PC is cleared). The back end puts
its tables and routines first; what still lies beyond is refused with the
addresses (`OutOfReach`). The PIC10F20x's last word holds the factory's
oscillator calibration (MOVLW), which the reset runs first: it is never
written.
"""

from __future__ import annotations

from ..pic16.asm import Assembled, Goto, Ins, ProgramTooLarge, Table
from ..pic16.asm import Assembler as Pic16Assembler
from ..pic16.emit import STATUS, C, W
from . import isa


class OutOfReach(Exception):
    def __init__(self, label: str, address: int):
        super().__init__(f"{label} at {address}")
        self.label = label
        self.address = address


def lowered(op: str, args: tuple, temp: int) -> list[tuple[str, tuple]] | None:
    """The baseline instructions for a mid-range one it lacks, None for its own."""
    if op == "addlw":
        return [("movwf", (temp,)), ("movlw", (args[0] & 0xFF,)), ("addwf", (temp, W))]
    if op == "sublw" and args[0] & 0xFF == 0xFF:
        return [("xorlw", (0xFF,)), ("bsf", (STATUS, C))]
    if op == "sublw":
        return [("xorlw", (0xFF,)), ("movwf", (temp,)), ("movlw", ((args[0] + 1) & 0xFF,)), ("addwf", (temp, W))]
    if op == "return":
        return [("retlw", (0,))]
    return None


class Assembler(Pic16Assembler):
    isa = isa  # the baseline's 12-bit words

    def __init__(self, flash_words: int, call_words: int, temp: int, never_negative: frozenset[int] = frozenset()):
        super().__init__(flash_words, page_words=flash_words)
        self.call_words = call_words  # the words a CALL or a write to PCL reaches
        self.temp = temp
        self.never_negative = never_negative  # the file registers whose bit 7 no write sets (ranges.py)

    def emit(self, op: str, *args: int, comment: str = "") -> None:
        if self._signed_at_least(op, args) or self._added_to_loaded(op, args):
            return
        written = lowered(op, args, self.temp)
        if written is None:
            super().emit(op, *args, comment=comment)
            return
        last = self.items[-1] if self.items else None
        assert len(written) == 1 or not (isinstance(last, Ins) and last.op in isa.SKIPS), f"{op} after a skip"
        for index, (name, operands) in enumerate(written):
            super().emit(name, *operands, comment=comment if index == 0 else "")

    def _loaded(self, back: int) -> Ins | None:
        """The MOVF f,W `back` items from the end, when no skip guards it."""
        if len(self.items) < back:
            return None
        load = self.items[-back]
        before = self.items[-back - 1] if len(self.items) > back else None
        if not (isinstance(load, Ins) and load.op == "movf" and load.args[1] == W) or (
                isinstance(before, Ins) and before.op in isa.SKIPS):
            return None
        return load

    def _signed_at_least(self, op: str, args: tuple) -> bool:
        """`MOVF f,W; XORLW 0x80; ADDLW k` (C: f >= c signed, c = -k with its sign
        flipped; Z: f == c) becomes `MOVLW c; SUBWF f,W` and the sign's fix-up, a
        skip on f's sign bit over BCF C (c >= 0: a negative f is less) or BSF C (c
        < 0: a positive f is more): the same C, Z and W, one word less and no byte
        of RAM. No fix-up for c >= 0 when no write makes f negative (ranges.py)."""
        last = self.items[-1] if self.items else None
        if op != "addlw" or not args[0] & 0xFF or not (isinstance(last, Ins) and last.op == "xorlw"
                                                      and last.args[0] == 0x80):
            return False
        load = self._loaded(2)
        if load is None:
            return False
        f, c = load.args[0], (0x100 - args[0]) & 0xFF ^ 0x80
        del self.items[-2:]
        super().emit("movlw", c, comment=load.comment)
        super().emit("subwf", f, W)
        if f in self.never_negative and not c & 0x80:
            return True  # both at 0 or more: the unsigned order is the signed one
        super().emit("btfss" if c & 0x80 else "btfsc", f, 7)
        super().emit("bsf" if c & 0x80 else "bcf", STATUS, C)
        return True

    def _added_to_loaded(self, op: str, args: tuple) -> bool:
        """`MOVF f,W; ADDLW k` becomes `MOVLW k; ADDWF f,W` (the same sum and flags, no byte of
        RAM), when no skip guards the MOVF."""
        load = self._loaded(1) if op == "addlw" else None
        if load is None:
            return False
        self.items[-1] = Ins("movlw", (args[0] & 0xFF,), load.comment)
        super().emit("addwf", load.args[0], W)
        return True

    def assemble(self, processor: str, config: dict[int, int]) -> Assembled:
        placed, labels, size = self._layout(set())
        if size > self.flash_words:
            raise ProgramTooLarge(size)
        for item in self.items:
            if isinstance(item, Goto) and item.call and labels[item.target] >= self.call_words:
                raise OutOfReach(item.target, labels[item.target])
            if isinstance(item, Table) and labels[item.name] + len(item.values) > self.call_words:
                raise OutOfReach(item.name, labels[item.name] + len(item.values) - 1)
        return self._output(placed, labels, processor, config)

    def _resolve(self, word, address: int, labels: dict[str, int], jump: str | None):
        if word.op == "tris":
            return "tris", word.args, f"0x{word.args[0]:02X}"
        return super()._resolve(word, address, labels, jump)
