"""The assembler: a list of instructions, labels, jumps and data becomes
machine words and a listing in GNU avr-as syntax.

Jumps and branches are written against labels; the assembler picks the short
form (RJMP, RCALL, BRxx) where the target is in reach and the long one
otherwise (JMP, CALL, or an inverted branch over a jump), repeating until the
layout is stable. Parts without JMP (8 KB flash) reach everything with RJMP,
whose offset wraps around the flash.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from . import isa


@dataclass
class Ins:
    op: str
    args: tuple = ()
    comment: str = ""


@dataclass
class Label:
    name: str
    comment: str = ""


@dataclass
class Comment:
    """A line of its own in the listing."""

    text: str


@dataclass
class Jump:
    """RJMP/JMP (call=False) or RCALL/CALL (call=True) to a label."""

    target: str
    call: bool = False
    comment: str = ""


@dataclass
class Branch:
    """BRxx to a label; in the long form, the inverse branch over a jump."""

    op: str
    target: str
    comment: str = ""


@dataclass
class Address:
    """LDI of the low or high byte of a label's byte address (tables)."""

    reg: int
    target: str
    high: bool
    offset: int = 0
    comment: str = ""


@dataclass
class Data:
    """Bytes in flash (padded to a whole word)."""

    values: bytes
    comment: str = ""


Item = Ins | Label | Comment | Jump | Branch | Address | Data


@dataclass
class Assembled:
    words: list[int]
    listing: str
    symbols: dict[str, int]  # label -> word address

    def image(self) -> bytes:
        return b"".join(w.to_bytes(2, "little") for w in self.words)


@dataclass
class Assembler:
    long_jumps: bool  # the part has JMP/CALL
    flash_words: int
    core: isa.Core = isa.CLASSIC
    items: list[Item] = field(default_factory=list)

    # --- writing ---------------------------------------------------------------

    def emit(self, op: str, *args: int, comment: str = "") -> None:
        self.items.append(Ins(op, tuple(args), comment))

    def label(self, name: str, comment: str = "") -> None:
        self.items.append(Label(name, comment))

    def comment(self, text: str) -> None:
        self.items.append(Comment(text))

    def jump(self, target: str, comment: str = "") -> None:
        self.items.append(Jump(target, False, comment))

    def call(self, target: str, comment: str = "") -> None:
        self.items.append(Jump(target, True, comment))

    def branch(self, op: str, target: str, comment: str = "") -> None:
        self.items.append(Branch(op, target, comment))

    def address(self, reg: int, target: str, high: bool, offset: int = 0) -> None:
        """`offset` is added to the byte address (the reduced core reads flash at 0x4000 up)."""
        self.items.append(Address(reg, target, high, offset))

    def data(self, values: bytes, comment: str = "") -> None:
        self.items.append(Data(bytes(values), comment))

    # --- layout ------------------------------------------------------------------

    def _size(self, item: Item, long: bool) -> int:
        if isinstance(item, Ins):
            return isa.size(item.op, self.core)
        if isinstance(item, Jump):
            return 2 if long else 1
        if isinstance(item, Branch):
            return 1 + (2 if self.long_jumps else 1) if long else 1
        if isinstance(item, Address):
            return 1
        if isinstance(item, Data):
            return (len(item.values) + 1) // 2
        return 0

    def _layout(self, longs: set[int]) -> tuple[list[int], dict[str, int]]:
        addresses, symbols, pc = [], {}, 0
        for index, item in enumerate(self.items):
            addresses.append(pc)
            if isinstance(item, Label):
                if item.name in symbols:
                    raise ValueError(f"label {item.name} defined twice")
                symbols[item.name] = pc
            pc += self._size(item, index in longs)
        return addresses, symbols

    def _in_reach(self, item: Item, pc: int, target: int) -> bool:
        offset = target - (pc + 1)
        if isinstance(item, Branch):
            return -64 <= offset <= 63
        return -2048 <= offset <= 2047 or not self.long_jumps

    def assemble(self) -> Assembled:
        longs: set[int] = set()
        while True:
            addresses, symbols = self._layout(longs)
            grown = {i for i, item in enumerate(self.items)
                     if isinstance(item, (Jump, Branch)) and i not in longs
                     and not self._in_reach(item, addresses[i], self._target(symbols, item.target))}
            if not grown:
                break
            longs |= grown
        words: list[int] = []
        lines: list[str] = []
        for index, item in enumerate(self.items):
            pc = addresses[index]
            for text, encoded, comment in self._render(item, pc, symbols, index in longs):
                lines.append(_line(text, pc, encoded, comment))
                words.extend(encoded)
                pc += len(encoded)
        return Assembled(words, "\n".join(lines) + "\n", symbols)

    @staticmethod
    def _target(symbols: dict[str, int], name: str) -> int:
        if name not in symbols:
            raise ValueError(f"jump to undefined label {name}")
        return symbols[name]

    def _relative(self, pc: int, target: int) -> int:
        offset = target - (pc + 1)
        if not self.long_jumps and not -2048 <= offset <= 2047:
            # 8 KB parts: the program counter wraps, so RJMP reaches everything
            offset = (offset + self.flash_words // 2) % self.flash_words - self.flash_words // 2
        return offset

    def _render(self, item: Item, pc: int, symbols: dict[str, int], long: bool):
        """(text, words, comment) for each machine instruction of an item."""
        if isinstance(item, Label):
            yield f"{item.name}:", [], item.comment
        elif isinstance(item, Comment):
            yield "", [], item.text
        elif isinstance(item, Ins):
            yield "\t" + isa.text(item.op, *item.args), isa.encode(item.op, *item.args, core=self.core), item.comment
        elif isinstance(item, Address):
            byte_address = 2 * self._target(symbols, item.target) + item.offset
            value = byte_address >> 8 if item.high else byte_address & 0xFF
            expr = f"{'hi8' if item.high else 'lo8'}({item.target}{f'+{item.offset}' if item.offset else ''})"
            yield f"\tldi r{item.reg}, {expr}", isa.encode("ldi", item.reg, value), item.comment
        elif isinstance(item, Data):
            padded = item.values + (b"\0" if len(item.values) % 2 else b"")
            for start in range(0, len(padded), 16):
                chunk = padded[start:start + 16]
                words = [chunk[i] | chunk[i + 1] << 8 for i in range(0, len(chunk), 2)]
                yield "\t.byte " + ", ".join(f"0x{b:02x}" for b in chunk), words, item.comment if not start else ""
        elif isinstance(item, Jump):
            target = self._target(symbols, item.target)
            if long:
                op = "call" if item.call else "jmp"
                yield f"\t{op} {item.target}", isa.encode(op, target), item.comment
            else:
                op = "rcall" if item.call else "rjmp"
                yield f"\t{op} {item.target}", isa.encode(op, self._relative(pc, target)), item.comment
        else:
            target = self._target(symbols, item.target)
            if not long:
                yield f"\t{item.op} {item.target}", isa.encode(item.op, target - (pc + 1)), item.comment
                return
            jump = "jmp" if self.long_jumps else "rjmp"
            over = isa.size(jump)
            yield f"\t{isa.INVERSE[item.op]} .+{2 * over}", isa.encode(isa.INVERSE[item.op], over), \
                item.comment
            words = isa.encode(jump, target) if self.long_jumps else isa.encode(jump, self._relative(pc + 1, target))
            yield f"\t{jump} {item.target}", words, ""


def _line(text: str, pc: int, words: list[int], comment: str) -> str:
    if not words:
        return f"{text}\t; {comment}" if text and comment else text or f"; {comment}"
    code = " ".join(f"{w:04x}" for w in words)
    note = f"{2 * pc:05x}: {code}"
    if comment:
        note += f"  {comment}"
    return f"{text.ljust(28)}; {note}"


def _falls_into(items: list[Item], start: int, label: str) -> bool:
    """Whether the labels and comments from `start` on include `label`."""
    for index in range(start, len(items)):  # by index: a slice would copy the rest, quadratic overall
        item = items[index]
        if isinstance(item, Label):
            if item.name == label:
                return True
        elif not isinstance(item, Comment):
            return False
    return False


def compress_skips(items: list[Item]) -> None:
    """Peephole, in place, until nothing changes:
    `SBRS ..; RJMP L; one instruction; L:` -> `SBRC ..; the instruction`,
    `BRxx L1; RJMP L2; L1:` -> `BR(not xx) L2; L1:`, and a jump (or a skip
    over a jump) to the label that follows goes."""
    changed = True
    while changed:
        changed = False
        out: list[Item] = []
        i = 0
        while i < len(items):
            item = items[i]
            following = items[i + 1] if i + 1 < len(items) else None
            jump = following if isinstance(following, Jump) and not following.call else None
            if isinstance(item, Ins) and item.op in isa.SKIP_INVERSE and jump is not None:
                if _falls_into(items, i + 2, jump.target):
                    i += 2
                    changed = True
                    continue
                third = items[i + 2] if i + 2 < len(items) else None
                if isinstance(third, (Ins, Jump)) and _falls_into(items, i + 3, jump.target):
                    out += [Ins(isa.SKIP_INVERSE[item.op], item.args, item.comment), third]
                    i += 3
                    changed = True
                    continue
            if isinstance(item, Branch) and jump is not None and _falls_into(items, i + 2, item.target):
                out.append(Branch(isa.INVERSE[item.op], jump.target, item.comment))
                i += 2
                changed = True
                continue
            if isinstance(item, (Jump, Branch)) and not getattr(item, "call", False) \
                    and _falls_into(items, i + 1, item.target):
                i += 1
                changed = True
                continue
            out.append(item)
            i += 1
        items[:] = out
