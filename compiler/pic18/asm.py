"""The PIC18 assembler: the items the emitter writes (compiler/pic16/asm.py's
`Writer`) become program words and a listing that gpasm reassembles to the
same words.

Jumps. BRA and RCALL take one word and reach 1,024 words either way; GOTO
and CALL take two and reach all of program memory. Every jump starts short;
one whose label is out of reach becomes long and the layout is repeated
(a jump only ever grows, so labels only move further and the layout
converges). A skip instruction skips a whole instruction, a two-word one
included, so nothing has to stay together and there are no pages.

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

SHORT_REACH = 1024  # BRA/RCALL: -1024 .. 1023 words from the next instruction


class Assembler(Writer):
    def __init__(self, flash_words: int):
        super().__init__()
        self.flash_words = flash_words

    def _size(self, index: int, far: set[int]) -> int:
        item = self.items[index]
        if isinstance(item, Goto):
            return 2 if index in far else 1
        if isinstance(item, Ins):
            return isa.words(item.op)
        if isinstance(item, Address):
            return 1
        if isinstance(item, Table):
            return (len(item.values) + 1) // 2
        return 0

    def _layout(self, far: set[int]) -> tuple[list[int], dict[str, int], int]:
        """Each item's word address, the labels' and the size."""
        addresses, labels, address = [], {}, 0
        for index, item in enumerate(self.items):
            addresses.append(address)
            if isinstance(item, (Label, Table)):
                labels[item.name] = address
            address += self._size(index, far)
        return addresses, labels, address

    def assemble(self, processor: str, config: dict[int, int]) -> Assembled:
        far: set[int] = set()
        while True:
            addresses, labels, size = self._layout(far)
            found = far | {index for index, item in enumerate(self.items)
                           if isinstance(item, Goto) and index not in far
                           and not -SHORT_REACH <= labels[item.target] - addresses[index] - 1 < SHORT_REACH}
            if found == far:
                break
            far = found
        if size > self.flash_words:
            raise ProgramTooLarge(size)
        return self._output(addresses, labels, far, processor, config)

    def _output(self, addresses: list[int], labels: dict[str, int], far: set[int], processor: str,
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
            op, args, text, comment = self._resolve(item, address, labels, index in far)
            encoded = isa.encode(op, *args)
            words += encoded
            note = f"  {comment}" if comment else ""
            lines.append(f"\t{op}\t{text}".rstrip()
                         + f"\t; {2 * address:06X} {' '.join(f'{w:04X}' for w in encoded)}{note}")
        lines.append("\tend")
        return Assembled(words, "\n".join(lines) + "\n", labels)

    @staticmethod
    def _resolve(item, address: int, labels: dict[str, int], far: bool) -> tuple[str, tuple, str, str]:
        """(PIC18 mnemonic, operands, operand text for the listing, comment) of an item."""
        if isinstance(item, Goto):
            target = labels[item.target]
            if far:
                return ("call" if item.call else "goto"), (target,), label_name(item.target), item.comment
            return ("rcall" if item.call else "bra"), (target - address - 1,), label_name(item.target), item.comment
        if isinstance(item, Address):
            byte_address = 2 * labels[item.target]
            value = byte_address >> 8 & 0xFF if item.high else byte_address & 0xFF
            return "movlw", (value,), address_text(item.target, item.high), ""
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
            "fk": lambda: f"{args[0]}, 0x{args[1]:03X}",
            "": lambda: "",
        }[pattern]()
        return op, args, text, item.comment
