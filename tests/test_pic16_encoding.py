"""Our PIC16 encoder and assembler against gputils and gpsim.

* Every mnemonic of compiler/pic16/isa.py with boundary operands: `isa.encode`
  gives gpasm's word for the same source line.
* Programs that cross code-page boundaries (gotos and calls both ways, code
  falling through a boundary, a skip that would be the last word of a page, a
  skip guarding a far goto, a RETLW table reached by a computed jump across a
  256-word boundary): the listing reassembled by gpasm gives exactly our words
  and configuration word(s), and gpsim runs the program in the order it was
  written (each step writes its number to PORTB).
* Random forward control flow over two to four pages (slow): gpasm and gpsim
  again, against the order the blocks mean.
"""

from __future__ import annotations

import random
import subprocess
from collections.abc import Callable
from functools import cache
from pathlib import Path

import pytest
from intelhex import IntelHex
from test_compiler_harness import IN_CI

from compiler.pic16 import isa
from compiler.pic16.asm import Assembled, Assembler
from compiler.pic16.part import Part
from compiler.run import gpsim
from lang.devices import find_device

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")

STATUS, PCL, PCLATH, PORTB, TRISB = 0x03, 0x02, 0x0A, 0x06, 0x86
C, RP0 = 0, 5
FLAG, INDEX = 0x20, 0x21  # bank-0 RAM the test programs use

# boundary operands of each pattern: file registers of bank 0 and of the last
# bank (the word keeps 7 bits), both destinations, both end bits, literals
# written signed and unsigned, both ends of an 11-bit address
BOUNDARIES: dict[str, list[tuple[int, ...]]] = {
    "fd": [(f, d) for f in (0x00, 0x7F, 0x80, 0x1FF) for d in (0, 1)],
    "f": [(0x00,), (0x7F,), (0x80,), (0x1FF,)],
    "fb": [(f, b) for f in (0x00, 0x7F, 0x1FF) for b in (0, 7)],
    "k8": [(0x00,), (0x7F,), (0x80,), (0xFF,), (-0x80,), (-0x01,)],
    "k11": [(0x000,), (0x400,), (0x7FF,)],
    "": [()],
}
OUT_OF_RANGE: dict[str, list[tuple[int, ...]]] = {
    "fd": [(-1, 0), (0x200, 0), (0x20, 2)],
    "f": [(-1,), (0x200,)],
    "fb": [(0x20, 8), (0x20, -1), (0x200, 0)],
    "k8": [(0x100,), (-0x81,)],
    "k11": [(0x800,), (-1,)],
    "": [],
}


def _number(value: int) -> str:
    """gpasm's default radix is hexadecimal: write every number with 0x."""
    return f"-0x{-value:X}" if value < 0 else f"0x{value:X}"


def gpasm_words(source: str, processor: str, tmp: Path) -> dict[int, int]:
    """Word address -> word of the HEX gpasm makes from the source."""
    path = tmp / "prog.asm"
    path.write_text(source)
    subprocess.run(["gpasm", "-p", processor, "-o", str(tmp / "prog.hex"), str(path)], check=True,
                   capture_output=True, text=True, timeout=60)
    image = IntelHex(str(tmp / "prog.hex"))
    addresses = sorted({a // 2 for a in image.addresses()})
    return {a: image[2 * a] | image[2 * a + 1] << 8 for a in addresses}


def test_every_mnemonic_encodes_as_gpasm_does(tmp_path):
    lines = ["\tprocessor p16f877a", "\terrorlevel -302, -306", "\torg 0"]
    expected = []
    for op, spec in isa.INSTRUCTIONS.items():
        for args in BOUNDARIES[spec.pattern]:
            lines.append(f"\t{op}\t{', '.join(map(_number, args))}")
            expected.append((lines[-1].strip(), isa.encode(op, *args)))
    lines.append("\tend")
    words = gpasm_words("\n".join(lines) + "\n", "p16f877a", tmp_path)
    got = [words[address] for address in range(len(expected))]
    assert {source: word for (source, word), word2 in zip(expected, got) if word != word2} == {}
    assert len(words) == len(expected)


@pytest.mark.parametrize("op", sorted(isa.INSTRUCTIONS))
def test_operands_out_of_range_are_refused(op):
    for args in OUT_OF_RANGE[isa.INSTRUCTIONS[op].pattern]:
        with pytest.raises(isa.EncodingError):
            isa.encode(op, *args)


# --- the assembler ------------------------------------------------------------------------------

def part(name: str) -> Part:
    return Part.of(find_device(name))


def check_reassembles(assembled: Assembled, processor: str, config: dict[int, int], tmp: Path) -> None:
    """gpasm makes exactly our words and configuration words from the listing."""
    words = gpasm_words(assembled.listing, processor, tmp)
    program = {a: w for a, w in words.items() if a < 0x2000}
    assert program == dict(enumerate(assembled.words))
    assert {a: w for a, w in words.items() if a >= 0x2000} == config


def is_skip(word: int) -> bool:
    """BTFSC, BTFSS, DECFSZ, INCFSZ: decoded from the word, not from our table."""
    return word >> 10 in (0b0110, 0b0111) or word >> 8 in (0x0B, 0x0F)


def table_value(index: int) -> int:
    return (index * 37 + 11) & 0xFF


class Writer:
    """Writes test programs: steps that write their number to PORTB, and
    fillers that move what follows towards a page boundary."""

    def __init__(self, flash_words: int, page_words: int, fills: list[int]):
        self.asm = Assembler(flash_words, page_words)
        self.fills = fills
        self.stations = 0
        self.hops = 0

    def step(self, value: int) -> None:
        self.asm.emit("movlw", value)
        self.asm.emit("movwf", PORTB)

    def hop(self) -> None:
        """A near goto over a wrong step: it lands right only when PCLATH
        selects the page the code is in."""
        self.hops += 1
        self.asm.goto(f"hop{self.hops}")
        self.step(0xEE)
        self.asm.label(f"hop{self.hops}")

    def station(self) -> None:
        """NOPs, then what follows: `mark<n>` labels the last NOP."""
        for _ in range(self.fills[self.stations] - 1):
            self.asm.emit("nop")
        self.asm.label(f"mark{self.stations}")
        self.asm.emit("nop")
        self.stations += 1


def place(build: Callable[[list[int]], Writer], starts: list[int], processor: str, config) -> Writer:
    """The program with each station's code starting where `starts` says (as
    laid out without the assembler moving it across a page boundary)."""
    fills = [1] * len(starts)
    for i, start in enumerate(starts):
        for _ in range(4):
            symbols = build(fills).asm.assemble(processor, config).symbols
            off = start - 1 - symbols[f"mark{i}"]
            if off == 0:
                break
            fills[i] += off
        assert symbols[f"mark{i}"] == start - 1, f"station {i} not placed"
    return build(fills)


def four_pages(fills: list[int]) -> Writer:
    """The program for a 4-page part (p16f877a): stations at the three page
    boundaries."""
    w = Writer(8192, 2048, fills)
    a = w.asm
    # page 0
    a.emit("bsf", STATUS, RP0)
    a.emit("clrf", TRISB)
    a.emit("bcf", STATUS, RP0)
    a.emit("clrf", FLAG)
    w.step(1)
    a.goto("p1_entry")  # 0 -> 1
    a.label("p0_return")
    w.step(3)
    a.call("p2_sub")  # 0 -> 2, which calls back into page 0
    w.hop()
    w.step(6)
    for index in (0, 127, 128, 255):
        a.emit("movlw", index)
        a.emit("movwf", INDEX)
        a.call("read_table")  # 0 -> 1, a computed jump, RETLW
        a.emit("movwf", PORTB)
        w.hop()
    a.emit("btfsc", FLAG, 0)  # clear: skips the far goto
    a.goto("p3_wrong")
    w.hop()
    w.step(7)
    a.emit("bsf", FLAG, 0)
    a.emit("btfsc", FLAG, 0)  # set: the far goto is taken
    a.goto("p3_entry")
    w.step(0xEE)
    a.label("p0_sub")
    w.step(5)
    a.emit("return")
    a.label("p0_end")
    w.step(50)
    a.label("done")
    a.goto("done")
    # station 0: straight-line code falling from page 0 into page 1
    w.station()
    a.label("s0")
    for value in (20, 21, 22):
        w.step(value)
    w.hop()
    w.step(23)
    a.goto("s1")
    a.label("p1_entry")
    w.step(2)
    a.goto("p0_return")  # 1 -> 0
    a.label("read_table")
    a.address("table", high=True)
    a.emit("movwf", PCLATH)
    a.address("table", high=False)
    a.emit("addwf", INDEX, 0)
    a.emit("btfsc", STATUS, C)
    a.emit("incf", PCLATH, 1)
    a.emit("movwf", PCL)
    a.table("table", bytes(table_value(i) for i in range(256)))
    # station 1: a skip that would be the last word of page 1
    w.station()
    a.label("s1")
    a.emit("movlw", 30)
    a.emit("btfsc", FLAG, 1)  # clear: skips
    a.emit("movlw", 0xEE)
    a.emit("movwf", PORTB)
    w.hop()
    w.step(31)
    a.goto("s2")
    a.label("p2_sub")
    w.step(4)
    a.call("p0_sub")  # 2 -> 0
    w.hop()
    a.emit("return")
    # station 2: a skip guarding a far goto across the boundary of page 3
    w.station()
    a.label("s2")
    a.emit("btfss", FLAG, 0)  # set: skips the far goto
    a.goto("p0_end")
    w.hop()
    w.step(40)
    a.emit("btfss", FLAG, 1)  # clear: the far goto is taken
    a.goto("p0_end")
    w.step(0xEE)
    a.label("p3_entry")
    w.step(8)
    a.goto("s0")  # 3 -> 0
    a.label("p3_wrong")
    w.step(0xEE)
    a.goto("done")
    return w


FOUR_PAGES_ORDER = [1, 2, 3, 4, 5, 6, *map(table_value, (0, 127, 128, 255)), 7, 8, 20, 21, 22, 23, 30, 31, 40, 50]


@cache
def four_page_program(lead: int) -> tuple[Assembled, dict[int, int]]:
    """The stations' code starting `lead` words before each boundary."""
    p = part("pic16f877a")
    config = dict(p.config_words)
    writer = place(four_pages, [boundary - lead for boundary in (0x800, 0x1000, 0x1800)], p.processor, config)
    return writer.asm.assemble(p.processor, config), config


def assert_laid_over_the_pages(assembled: Assembled) -> None:
    symbols = assembled.symbols
    page = {name: address // 2048 for name, address in symbols.items()}
    assert (page["p0_return"], page["p0_sub"], page["p1_entry"], page["p2_sub"], page["p3_entry"]) == (0, 0, 1, 2, 3)
    table = symbols["table"]
    assert table // 256 != (table + 255) // 256, "the table does not cross a 256-word boundary"
    for boundary in (0x800, 0x1000, 0x1800):
        assert not is_skip(assembled.words[boundary - 1]), f"a skip is the last word before {boundary:#x}"


@pytest.mark.parametrize("lead", range(1, 5))
def test_a_four_page_program_reassembles(lead, tmp_path):
    assembled, config = four_page_program(lead)
    assert_laid_over_the_pages(assembled)
    check_reassembles(assembled, "p16f877a", config, tmp_path)


@needs_gpsim
@pytest.mark.parametrize("lead", range(1, 5))
def test_a_four_page_program_runs_in_order_in_gpsim(lead, tmp_path):
    assembled, config = four_page_program(lead)
    image = IntelHex()
    for address, word in enumerate(assembled.words):
        image[2 * address], image[2 * address + 1] = word & 0xFF, word >> 8
    for address, word in config.items():
        image[2 * address], image[2 * address + 1] = word & 0xFF, word >> 8
    hex_path = tmp_path / "pages.hex"
    image.write_hex_file(str(hex_path))
    run = gpsim.run_pic(hex_path, "p16f877a", 4_000_000, watch=["RB0"], until_ms=20, timeout=60)
    written = [value for _, register, value in run.writes if register == "portb"]
    assert written == FOUR_PAGES_ORDER


def test_a_two_page_part_with_two_configuration_words_reassembles(tmp_path):
    """The PIC16F88: gotos and calls both ways over its one boundary, code
    falling through it, and both configuration words."""
    p = part("pic16f88")
    config = {0x2007: 0x3F50, 0x2008: 0x3FFC}

    def build(fills: list[int]) -> Writer:
        w = Writer(p.flash_words, p.page_words, fills)
        a = w.asm
        w.step(1)
        a.call("far_sub")  # 0 -> 1
        a.goto("far")  # 0 -> 1
        a.label("near_sub")
        a.emit("retlw", 9)
        w.station()
        for value in range(4):
            w.step(value)
        w.hop()
        a.emit("decfsz", FLAG, 1)
        a.goto("far")
        a.label("far")
        a.call("near_sub")  # 1 -> 0
        a.goto("near_sub")  # 1 -> 0
        a.label("far_sub")
        a.emit("return")
        return w

    writer = place(build, [0x800 - 3], p.processor, config)
    assembled = writer.asm.assemble(p.processor, config)
    assert assembled.symbols["far"] >= 0x800 > assembled.symbols["near_sub"]
    assert not is_skip(assembled.words[0x7FF])
    check_reassembles(assembled, p.processor, config, tmp_path)


def test_a_one_page_part_selects_no_page(tmp_path):
    """The PIC16F628's 2K words are one page: PCLATH is written only by the
    table lookup."""
    p = part("pic16f628")
    config = dict(p.config_words)
    a = Assembler(p.flash_words, p.page_words)
    a.call("lookup")
    a.label("loop")
    a.goto("loop")
    a.label("lookup")
    a.address("table", high=True)
    a.emit("movwf", PCLATH)
    a.address("table", high=False)
    a.emit("movwf", PCL)
    a.table("table", bytes(range(10)))
    assembled = a.assemble(p.processor, config)
    # MOVWF PCLATH, BCF/BSF PCLATH,b
    writes_pclath = [w for w in assembled.words if w == 0x0080 | PCLATH or w & 0x3C7F in (0x1000 | PCLATH, 0x1400 | PCLATH)]
    assert len(writes_pclath) == 1
    check_reassembles(assembled, p.processor, config, tmp_path)


# --- random control flow ------------------------------------------------------------------------

ACTIONS = ("fall", "goto", "skipped goto", "taken goto", "call", "skipped call", "taken call", "inline subroutine",
           "skip over one", "nops", "nops", "table")


def random_flow(seed: int, blocks: int = 120) -> tuple[Assembler, list[int]]:
    """Blocks that each write their number to PORTB, then jump forward, call a
    subroutine (behind the last block or jumped around where it is), read a
    RETLW table, skip, or run into NOPs that move what follows; FLAG bit 0 is
    set, bit 1 clear. With the PORTB values in the order the blocks mean."""
    rng = random.Random(seed)
    w = Writer(8192, 2048, [])
    a = w.asm
    a.emit("bsf", STATUS, RP0)
    a.emit("clrf", TRISB)
    a.emit("bcf", STATUS, RP0)
    a.emit("movlw", 1)
    a.emit("movwf", FLAG)
    plan = [(rng.choice(ACTIONS), rng.randrange(i + 1, blocks + 1), rng.randrange(256)) for i in range(blocks)]
    behind: list[tuple[str, int]] = []  # subroutines after the last block, with the value they write
    sub_value: dict[int, int] = {}
    for i, (action, target, index) in enumerate(plan):
        a.label(f"b{i}")
        w.step(i % 250 + 1)
        if action == "goto":
            a.goto(f"b{target}")
        elif action in ("skipped goto", "taken goto"):
            a.emit("btfss" if action == "skipped goto" else "btfsc", FLAG, 0)
            a.goto(f"b{target}")
        elif action in ("call", "skipped call", "taken call", "inline subroutine"):
            sub_value[i] = 0xC0 | i & 0x1F
            if action != "call" and action != "inline subroutine":
                a.emit("btfss" if action == "skipped call" else "btfsc", FLAG, 0)
            a.call(f"s{i}")
            if action == "inline subroutine":
                a.goto(f"over{i}")
                a.label(f"s{i}")
                w.step(sub_value[i])
                a.emit("return")
                a.label(f"over{i}")
            else:
                behind.append((f"s{i}", sub_value[i]))
        elif action == "table":
            a.emit("movlw", index)
            a.emit("movwf", INDEX)
            a.call(f"read{i}")
            a.emit("movwf", PORTB)
            a.goto(f"over{i}")
            a.label(f"read{i}")
            a.address(f"data{i}", high=True)
            a.emit("movwf", PCLATH)
            a.address(f"data{i}", high=False)
            a.emit("addwf", INDEX, 0)
            a.emit("btfsc", STATUS, C)
            a.emit("incf", PCLATH, 1)
            a.emit("movwf", PCL)
            a.table(f"data{i}", bytes((k * 7 + i) & 0xFF for k in range(256)))
            a.label(f"over{i}")
        elif action == "skip over one":
            a.emit("movlw", 0xE1)
            a.emit("btfsc", FLAG, 1)  # clear: skips
            a.emit("movlw", 0xE2)
            a.emit("movwf", PORTB)
        elif action == "nops":
            for _ in range(rng.randrange(200)):
                a.emit("nop")
    a.label(f"b{blocks}")
    w.step(0xFF)
    a.label("done")
    a.goto("done")
    for name, value in behind:
        a.label(name)
        w.step(value)
        a.emit("return")
    expected, i = [], 0
    while i < blocks:
        action, target, index = plan[i]
        expected.append(i % 250 + 1)
        if action in ("goto", "taken goto"):
            i = target
            continue
        if action in ("call", "taken call", "inline subroutine"):
            expected.append(sub_value[i])
        elif action == "table":
            expected.append((index * 7 + i) & 0xFF)
        elif action == "skip over one":
            expected.append(0xE1)
        i += 1
    return a, expected + [0xFF]


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("seed", range(20))
def test_random_control_flow_over_four_pages_runs_in_order(seed, tmp_path):
    p = part("pic16f877a")
    config = dict(p.config_words)
    asm, expected = random_flow(seed)
    assembled = asm.assemble(p.processor, config)
    assert len(assembled.words) > 2048, "the program should cross a page boundary"
    check_reassembles(assembled, p.processor, config, tmp_path)
    image = IntelHex()
    for address, word in [*enumerate(assembled.words), *config.items()]:
        image[2 * address], image[2 * address + 1] = word & 0xFF, word >> 8
    image.write_hex_file(str(tmp_path / "flow.hex"))
    run = gpsim.run_pic(tmp_path / "flow.hex", p.processor, 20_000_000, watch=["RB0"], until_ms=10, timeout=60)
    assert [value for _, register, value in run.writes if register == "portb"] == expected
