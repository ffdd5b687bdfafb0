"""The PIC18 encoder and assembler against gpasm: every instruction form of
compiler/pic18/isa.py (access and banked file registers, both destinations,
every bit, the literal range, BSR, MOVFF, conditional branches,
short and long jumps both ways, tables and their addresses) assembled by us and by gpasm from our
listing, word for word; the budget's decoder (compiler/pic18/flow.py) reads
every word back as the instruction it is."""

from __future__ import annotations

import subprocess

import pytest
from intelhex import IntelHex
from test_pic16_parts import needs_gputils

from compiler.budget import BRANCH, CALL, JUMP, NEXT, RETURN, SKIP
from compiler.pic16.isa import EncodingError
from compiler.pic18 import flow, isa
from compiler.pic18.asm import Assembler
from compiler.pic18.part import Part
from lang.devices import find_device

PART = Part.of(find_device("pic18f4520"))
STATUS = PART.reg("STATUS")
JUMPS = ("n8", "n11", "k20")  # jumps come from labels
FILES = (0x000, 0x05A, 0x07F, 0x080, 0x123, 0x5FF, 0xF80, 0xFD8, 0xFFF)  # access RAM, banked RAM, access SFRs

OPERANDS = {
    "fd": [(f, d) for f in FILES for d in (0, 1)],
    "f": [(f,) for f in FILES],
    "fb": [(f, b) for f in (0x010, 0x1A0, 0xF81) for b in range(8)],
    "k8": [(k,) for k in (0, 1, 0x7F, 0x80, 0xFF, -1, -128)],
    "k4": [(k,) for k in range(16)],
    "ff": [(0x000, 0x5FF), (0xFD8, 0x123), (0x07F, 0xF8B)],
    "": [()],
}


def _every_form() -> Assembler:
    asm = Assembler(PART.flash_words, STATUS)
    asm.label("start")
    for op, spec in isa.INSTRUCTIONS.items():
        if spec.pattern in JUMPS:
            continue
        for args in OPERANDS[spec.pattern]:
            asm.emit(op, *args)
    for op in isa.ALIASES:  # the patterns' mid-range names
        asm.emit(op, 0x020, 1)
        asm.emit(op, 0x120, 0)
    # short jumps both ways, long ones past BRA's reach, a table and its address
    asm.goto("start")
    asm.call("start")
    asm.goto("far")
    asm.call("far")
    asm.address("values", high=True)
    asm.address("values", high=False)
    asm.emit("btfss", 0xFD8, 2)
    asm.goto("near")
    asm.label("near")
    # every flag test guarding a jump: a branch in reach, a test and a BRA or GOTO beyond
    for test, bit in isa_branches():
        asm.emit(test, STATUS, bit)
        asm.goto("near")
        asm.emit(test, STATUS, bit)
        asm.goto("middle")
        asm.emit(test, STATUS, bit)
        asm.goto("far")
    for _ in range(600):
        asm.emit("nop")
    asm.label("middle")
    for _ in range(600):
        asm.emit("nop")
    asm.label("far")
    asm.goto("start")
    asm.emit("return")
    asm.table("values", bytes(range(1, 12)))
    return asm


def isa_branches() -> list[tuple[str, int]]:
    from compiler.pic18.asm import BRANCHES

    return sorted(BRANCHES)


def _gpasm(listing: str, tmp_path) -> list[int]:
    (tmp_path / "g.asm").write_text(listing)
    subprocess.run(["gpasm", "-o", str(tmp_path / "g.hex"), str(tmp_path / "g.asm")], check=True,
                   capture_output=True)
    image = IntelHex(str(tmp_path / "g.hex"))
    end = max(a for a in image.addresses() if a < 0x200000) + 1
    return [image[a] | image[a + 1] << 8 for a in range(0, end, 2)]


@needs_gputils
def test_every_instruction_form_is_what_gpasm_makes_of_the_listing(tmp_path):
    asm = _every_form()
    assembled = asm.assemble(PART.processor, PART.config_bytes())
    assert _gpasm(assembled.listing, tmp_path) == assembled.words
    text = assembled.listing
    # near jumps are BRA/RCALL, far ones GOTO/CALL
    assert "\tbra\tstart" in text and "\trcall\tstart" in text and "\tgoto\tfar" in text and "\tcall\tfar" in text
    assert "\tgoto\tstart" in text  # from past 1,024 words back
    for branch in ("bz", "bnz", "bc", "bnc", "bov", "bnov", "bn", "bnn"):
        assert f"\t{branch}\tnear" in text
    assert "\tbra\tmiddle" in text and "\tgoto\tfar" in text


def test_operands_out_of_range_are_refused():
    for op, args in (("movf", (0x1000, 0)), ("bsf", (0x10, 8)), ("movlb", (16,)), ("movlw", (256,)),
                     ("bra", (1024,))):
        with pytest.raises(EncodingError):
            isa.encode(op, *args)


def test_the_budget_decoder_reads_every_word_as_its_instruction():
    asm = _every_form()
    assembled = asm.assemble(PART.processor, PART.config_bytes())
    words, labels = assembled.words, assembled.symbols
    table_start = labels["values"]
    address, seen = 0, set()
    while address < table_start:
        ins = flow.instruction_at(words, address, None)
        assert ins is not None, hex(address)
        seen.add(ins.flow)
        if ins.flow in (JUMP, CALL, BRANCH):
            assert ins.target in labels.values()
        if ins.flow == SKIP:
            assert ins.target == address + 1 + ins.taken - 1 and ins.taken in (2, 3)
        address = ins.next
    assert address == table_start
    assert seen >= {NEXT, JUMP, CALL, SKIP, RETURN, BRANCH}


def test_each_instruction_decodes_to_its_size_and_cycles():
    for op, spec in isa.INSTRUCTIONS.items():
        if spec.pattern in JUMPS:
            continue
        words = list(isa.encode(op, *OPERANDS[spec.pattern][0]))
        ins = flow.instruction_at(words + [0], 0, None)
        assert ins is not None and ins.size == spec.words, op
        if not spec.skips:
            assert ins.cycles == spec.cycles, op
    # a skip over a two-word instruction skips both words, in 3 cycles
    words = [*isa.encode("btfsc", 0xFD8, 0), *isa.encode("movff", 1, 2), 0]
    skip = flow.instruction_at(words, 0, None)
    assert (skip.flow, skip.target, skip.taken) == (SKIP, 3, 3)
