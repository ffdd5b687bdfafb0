"""The PIC18 assembler: the items the emitter writes (compiler/pic16/asm.py's
`Writer`) become program words and a listing that gpasm reassembles to the
same words.

Jumps. A test of a STATUS flag and the jump it guards, as the shared
patterns write them (`BTFSS STATUS,Z; GOTO L`), become one conditional
branch (BNZ L: one word reaching 128 words either way, 1 cycle or 2 when
taken, where the pair takes 2 words and 2 or 3 cycles). BRA and RCALL take
one word and reach 1,024 words either way; GOTO and CALL take two and reach
all of program memory. Every jump starts in its shortest form; one whose
label is out of reach grows (a branch into its test and a BRA, a BRA into a
GOTO) and the layout is repeated: a jump only ever grows, so labels only
move further and the layout converges. A skip instruction skips a whole
instruction, a two-word one included, so nothing has to stay together and
there are no pages.

Tables: a table's bytes are packed two to a word (`db`) and read with
TBLRD; its routine loads TBLPTR from the label's byte address (`Address`:
its high or low byte).

The listing gives each instruction's byte address (the PIC18's program
counter counts bytes) and words; `labels` are word addresses, as for every
family.
"""

from __future__ import annotations

from ..pic16.asm import (
    Address,
    Assembled,
    Comment,
    Goto,
    Ins,
    Label,
    ProgramTooLarge,
    Table,
    Writer,
    address_text,
    heading,
    label_name,
)
from . import isa

BRANCH, SHORT, LONG = 0, 1, 2  # a jump's forms, shortest first
REACH = {BRANCH: 128, SHORT: 1024}  # words back (and one fewer forward) from the next instruction
# (test, STATUS bit) guarding a jump -> the branch taken when the jump is: the jump runs when the
# test does not skip it, so BTFSS STATUS,Z; GOTO L is BNZ L
BRANCHES = {("btfsc", 0): "bc", ("btfss", 0): "bnc", ("btfsc", 2): "bz", ("btfss", 2): "bnz",
            ("btfsc", 3): "bov", ("btfss", 3): "bnov", ("btfsc", 4): "bn", ("btfss", 4): "bnn"}


class Assembler(Writer):
    def __init__(self, flash_words: int, status: int):
        super().__init__()
        self.flash_words = flash_words
        self.status = status

    def _branch(self, index: int) -> str | None:
        """The conditional branch a jump and the flag test before it make, if any."""
        item, test = self.items[index], self.items[index - 1] if index else None
        if not isinstance(item, Goto) or item.call or not isinstance(test, Ins) or test.args[:1] != (self.status,):
            return None
        return BRANCHES.get((test.op, test.args[1]))

    def _size(self, index: int, forms: dict[int, int]) -> int:
        item = self.items[index]
        if isinstance(item, Goto):
            return 2 if forms[index] == LONG else 1
        if isinstance(item, Ins):
            return 0 if forms.get(index + 1) == BRANCH else isa.words(item.op)
        if isinstance(item, Address):
            return 1
        if isinstance(item, Table):
            return (len(item.values) + 1) // 2
        return 0

    def _layout(self, forms: dict[int, int]) -> tuple[list[int], dict[str, int], int]:
        """Each item's word address, the labels' and the size."""
        addresses, labels, address = [], {}, 0
        for index, item in enumerate(self.items):
            addresses.append(address)
            if isinstance(item, (Label, Table)):
                labels[item.name] = address
            address += self._size(index, forms)
        return addresses, labels, address

    def assemble(self, processor: str, config: dict[int, int]) -> Assembled:
        jumps = {index: item.target for index, item in enumerate(self.items) if isinstance(item, Goto)}
        forms = {index: BRANCH if self._branch(index) else SHORT for index in jumps}
        while True:
            addresses, labels, size = self._layout(forms)
            grown = {index: form + 1 for index, form in forms.items()
                     if form != LONG and not -REACH[form] <= labels[jumps[index]] - addresses[index] - 1 < REACH[form]}
            if not grown:
                break
            forms.update(grown)
        if size > self.flash_words:
            raise ProgramTooLarge(size)
        return self._output(addresses, labels, forms, processor, config)

    def _output(self, addresses: list[int], labels: dict[str, int], forms: dict[int, int], processor: str,
                config: dict[int, int]) -> Assembled:
        words: list[int] = []
        # 302: a banked register's address is written whole; 212: __config by byte address
        lines = [f"\tprocessor {processor}", "\terrorlevel -302, -212",
                 *(f"\t__config 0x{address:06X}, 0x{value:02X}" for address, value in sorted(config.items())),
                 "\torg 0"]
        for index, item in enumerate(self.items):
            address = addresses[index]
            if isinstance(item, (Label, Comment)):
                lines += heading([item])
                continue
            if isinstance(item, Table):
                lines.append(f"{label_name(item.name)}:")
                data = item.values + bytes(len(item.values) % 2)
                for at in range(0, len(data), 8):
                    chunk = data[at:at + 8]
                    packed = [chunk[i] | chunk[i + 1] << 8 for i in range(0, len(chunk), 2)]
                    words += packed
                    lines.append(f"\tdb\t{', '.join(f'0x{b:02X}' for b in chunk)}"
                                 f"\t; {2 * (address + at // 2):06X} {' '.join(f'{w:04X}' for w in packed)}")
                continue
            if forms.get(index + 1) == BRANCH:
                continue  # the flag test is the branch's condition
            op, args, text, comment = self._resolve(index, address, labels, forms)
            encoded = isa.encode(op, *args)
            words += encoded
            note = f"  {comment}" if comment else ""
            lines.append(f"\t{op}\t{text}".rstrip()
                         + f"\t; {2 * address:06X} {' '.join(f'{w:04X}' for w in encoded)}{note}")
        lines.append("\tend")
        return Assembled(words, "\n".join(lines) + "\n", labels)

    def _resolve(self, index: int, address: int, labels: dict[str, int],
                 forms: dict[int, int]) -> tuple[str, tuple, str, str]:
        """(PIC18 mnemonic, operands, operand text for the listing, comment) of an item."""
        item = self.items[index]
        if isinstance(item, Goto):
            target = labels[item.target]
            if forms[index] == LONG:
                return ("call" if item.call else "goto"), (target,), label_name(item.target), item.comment
            branch = self._branch(index) if forms[index] == BRANCH else None
            op = branch or ("rcall" if item.call else "bra")
            return op, (target - address - 1,), label_name(item.target), item.comment
        if isinstance(item, Address):
            byte_address = 2 * labels[item.target]
            value = byte_address >> 8 & 0xFF if item.high else byte_address & 0xFF
            return "movlw", (value,), address_text(item.target, item.high), ""
        assert isinstance(item, Ins)  # labels, comments and tables are written by _output
        op = isa.name(item.op)
        args = item.args
        pattern = isa.INSTRUCTIONS[op].pattern
        text = {
            "fd": lambda: f"0x{args[0]:03X}, {args[1]}, {isa.access(args[0])}",
            "f": lambda: f"0x{args[0]:03X}, {isa.access(args[0])}",
            "fb": lambda: f"0x{args[0]:03X}, {args[1]}, {isa.access(args[0])}",
            "k8": lambda: f"0x{args[0] & 0xFF:02X}",
            "k4": lambda: f"0x{args[0]:X}",
            "ff": lambda: f"0x{args[0]:03X}, 0x{args[1]:03X}",
            "": lambda: "",
        }[pattern]()
        return op, args, text, item.comment
