"""The assembler: instructions, labels, jumps and RETLW tables become program
words and a listing that gpasm reassembles to the same words.

Code pages. GOTO and CALL carry 11 address bits; PCLATH<4:3> supply the
page. The invariant kept here: at every instruction boundary PCLATH<4:3> is
the page the PC is in. So

* a GOTO or CALL to another page is preceded by the BSF/BCF PCLATH that
  select the target's page (before the skip instruction guarding it, if
  any: a skip skips one word);
* after every CALL the caller's page is selected again, on parts with more
  than one page (the callee may end in another page, a table lookup leaves
  PCLATH pointing at the table);
* code that falls through into a new page begins it with the selection of
  that page;
* a sequence that must stay together (a skip and what it skips, a page
  selection and its jump) is never split by a page boundary: NOPs move it
  into the next page.

Page selections are only ever added while the layout is repeated, so the
layout converges. Parts with one page need none of this, nor does a program
that fits in the first page.

A table is a run of RETLW reached by a computed jump that sets all of
PCLATH (`address` loads a label's high or low byte with MOVLW), so it may
lie anywhere.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from . import isa

PCLATH = 0x0A
PAGE_BITS = (3, 4)  # PCLATH bits that select the page of GOTO and CALL


@dataclass
class Ins:
    op: str
    args: tuple = ()
    comment: str = ""


@dataclass
class Label:
    name: str


@dataclass
class Comment:
    """A line of its own in the listing."""

    text: str


@dataclass
class Goto:
    """GOTO (call=False) or CALL (call=True) to a label."""

    target: str
    call: bool = False
    comment: str = ""


@dataclass
class Address:
    """MOVLW of the high (PCLATH) or low byte of a label's word address."""

    target: str
    high: bool


@dataclass
class Table:
    """RETLW of each byte, under a label."""

    name: str
    values: bytes


Item = Ins | Label | Comment | Goto | Address | Table


class ProgramTooLarge(Exception):
    def __init__(self, words: int):
        super().__init__(f"{words} words")
        self.words = words


@dataclass
class Assembled:
    words: list[int]
    listing: str
    symbols: dict[str, int]  # label -> word address


@dataclass
class _Word:
    """One laid-out word. `target`: the label a GOTO/CALL goes to or a MOVLW
    loads a byte of; `select`: for a page selection ("pagesel", args = the
    PCLATH bit), whose page it selects: "target" (the group's jump's) or
    "here" (the page the word is in)."""

    op: str
    args: tuple = ()
    target: str | None = None
    high: bool = False
    select: str | None = None
    comment: str = ""


class Writer:
    """The items in program order, as the emitter writes them; each
    family's assembler lays them out."""

    relative_tables = False  # a table of up to 256 entries is reached by BRW (PC + 1 + W) from its index's low byte

    def __init__(self) -> None:
        self.items: list[Item] = []

    def emit(self, op: str, *args: int, comment: str = "") -> None:
        self.items.append(Ins(op, tuple(args), comment))

    def label(self, name: str) -> None:
        self.items.append(Label(name))

    def comment(self, text: str) -> None:
        self.items.append(Comment(text))

    def goto(self, target: str, comment: str = "") -> None:
        self.items.append(Goto(target, False, comment))

    def call(self, target: str, comment: str = "") -> None:
        self.items.append(Goto(target, True, comment))

    def address(self, target: str, high: bool) -> None:
        self.items.append(Address(target, high))

    def table(self, name: str, values: bytes) -> None:
        self.items.append(Table(name, bytes(values)))


class Assembler(Writer):
    isa = isa  # the instruction table the words are encoded with
    code_space = 0  # what gpasm adds to a code label's address in high(): 0x8000 on the enhanced core

    def __init__(self, flash_words: int, page_words: int = 2048):
        super().__init__()
        self.flash_words = flash_words
        self.page_words = page_words
        self._one_page = False  # the program is laid out as if the part had one page

    # --- layout ------------------------------------------------------------------

    @property
    def _paged(self) -> bool:
        return self.flash_words > self.page_words and not self._one_page

    def _select(self, which: str) -> list[_Word]:
        pages = -(-self.flash_words // self.page_words)
        bits = PAGE_BITS[:max(1, (pages - 1).bit_length())]
        return [_Word("pagesel", (bit,), select=which) for bit in bits]

    def _groups(self, far: set[int]) -> list[tuple[list, list[_Word], bool]]:
        """(labels and comments before it, words that stay together, falls
        through) for each run of items; `far` holds the indexes of the jumps
        to another page."""
        groups: list[tuple[list, list[_Word], bool]] = []
        before: list = []
        skip: Ins | None = None
        for index, item in enumerate(self.items):
            if isinstance(item, (Label, Comment)):
                assert skip is None or isinstance(item, Comment), f"label {item} right after a skip"
                before.append(item)
                continue
            if isinstance(item, Ins) and item.op in self.isa.SKIPS and skip is None:
                skip = item
                continue
            words: list[_Word] = []
            guard = [_Word(skip.op, skip.args, comment=skip.comment)] if skip is not None else []
            if isinstance(item, Goto):
                if index in far:
                    words += self._select("target")
                words += guard + [_Word("call" if item.call else "goto", target=item.target, comment=item.comment)]
                if self._paged and (item.call or (index in far and guard)):
                    words += self._select("here")
                falls = item.call or bool(guard)
            elif isinstance(item, Ins):
                words = guard + [_Word(item.op, item.args, comment=item.comment)]
                falls = item.op not in self.isa.ENDS or bool(guard)
            elif isinstance(item, Address):
                words = guard + [_Word("movlw", target=item.target, high=item.high)]
                falls = True
            else:
                assert not guard, "a table right after a skip"
                before.append(Label(item.name))
                words = [_Word("retlw", (value,)) for value in item.values]
                falls = False
            skip = None
            groups.append((before, words, falls))
            before = []
        assert skip is None, "the code ends with a skip"
        if before:
            groups.append((before, [], False))
        return groups

    def _layout(self, far: set[int]):
        """[(first address, labels and comments, words leading into a new
        page, words)], label addresses, size."""
        placed: list[tuple[int, list, int, list[_Word]]] = []
        labels: dict[str, int] = {}
        address, falls = 0, False
        page = self.page_words
        for before, words, next_falls in self._groups(far):
            start = address
            lead: list[_Word] = []
            if self._paged and words:
                if (address + len(words) - 1) // page != address // page:
                    lead = [_Word("nop") for _ in range(page - address % page)]
                    address += len(lead)
                if address % page == 0 and address and (falls or lead):
                    fix = self._select("here")
                    lead += fix
                    address += len(fix)
            for item in before:
                if isinstance(item, Label):
                    labels[item.name] = address
            placed.append((start, before, len(lead), lead + words))
            address += len(words)
            if words:
                falls = next_falls
        return placed, labels, address

    def assemble(self, processor: str, config: dict[int, int]) -> Assembled:
        # a program that fits in page 0 needs no page selection: PCLATH's page bits stay 0 (a
        # table's computed jump leaves them so too)
        self._one_page = True
        placed, labels, size = self._layout(set())
        if size <= min(self.page_words, self.flash_words):
            return self._output(placed, labels, processor, config)
        self._one_page = False
        far: set[int] = set()
        jumps = [(i, item.target) for i, item in enumerate(self.items) if isinstance(item, Goto)]
        while True:
            placed, labels, size = self._layout(far)
            if not self._paged:
                break
            at = [start + i for start, _, _, words in placed for i, w in enumerate(words) if w.op in ("goto", "call")]
            found = far | {index for (index, target), address in zip(jumps, at)
                           if labels[target] // self.page_words != address // self.page_words}
            if found == far:
                break
            far = found
        if size > self.flash_words:
            raise ProgramTooLarge(size)
        return self._output(placed, labels, processor, config)

    def _output(self, placed, labels: dict[str, int], processor: str, config: dict[int, int]) -> Assembled:
        words: list[int] = []
        lines = [f"\tprocessor {processor}", "\terrorlevel -302, -306",
                 *(f"\t__config 0x{address:04X}, 0x{value:04X}" for address, value in sorted(config.items())),
                 "\torg 0"]
        for start, before, lead, group in placed:
            jump = next((w.target for w in group if w.op in ("goto", "call")), None)
            for offset, word in enumerate(group):
                address = start + offset
                if offset == lead:
                    lines += heading(before)
                op, args, text = self._resolve(word, address, labels, jump)
                value = self.isa.encode(op, *args)
                words.append(value)
                note = f"  {word.comment}" if word.comment else ""
                lines.append(f"\t{op}\t{text}".rstrip() + f"\t; {address:04X} {value:04X}{note}")
            if not group:
                lines += heading(before)
        lines.append("\tend")
        return Assembled(words, "\n".join(lines) + "\n", labels)

    def _resolve(self, word: _Word, address: int, labels: dict[str, int], jump: str | None):
        """(mnemonic, operands, operand text for the listing) of a laid-out word."""
        if word.select is not None:
            if word.select == "target":
                assert jump is not None  # the select comes in its jump's group
                page = labels[jump] // self.page_words
            else:
                page = address // self.page_words
            return self._page_selection(word, page)
        if word.target is not None:
            target = labels[word.target]
            if word.op == "movlw":
                value = (target + self.code_space) >> 8 & 0xFF if word.high else target & 0xFF
                return "movlw", (value,), address_text(word.target, word.high)
            return word.op, (target & 0x7FF,), label_name(word.target)
        pattern = self.isa.INSTRUCTIONS[word.op].pattern
        args = word.args
        text = {"fd": lambda: f"0x{args[0]:02X}, {args[1]}", "f": lambda: f"0x{args[0]:02X}",
                "fb": lambda: f"0x{args[0]:02X}, {args[1]}", "k8": lambda: f"0x{args[0] & 0xFF:02X}",
                "": lambda: ""}.get(pattern, lambda: ", ".join(f"0x{arg:02X}" for arg in args))()
        return word.op, args, text

    def _page_selection(self, word: _Word, page: int) -> tuple[str, tuple, str]:
        """The instruction of a page selection word: BCF/BSF of its PCLATH bit."""
        bit = word.args[0]
        op = "bsf" if page >> PAGE_BITS.index(bit) & 1 else "bcf"
        return op, (PCLATH, bit), f"0x{PCLATH:02X}, {bit}"



def heading(items: list) -> list[str]:
    """Labels and comments as listing lines."""
    return [f"{label_name(item.name)}:" if isinstance(item, Label) else f"; {item.text}" for item in items]


def address_text(label: str, high: bool) -> str:
    """gpasm's operand for a byte of a label's address."""
    return f"{'high' if high else 'low'}({label_name(label)})"


def label_name(label: str) -> str:
    """A label as gpasm spells one: letters, digits and underscores."""
    return re.sub(r"\W", "_", label)
