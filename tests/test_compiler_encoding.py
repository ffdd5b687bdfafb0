"""Our AVR encoder against GNU avr-as: every opcode of the table with many
operand values, and jumps relaxed in both directions, assembled by us and by
avr-gcc from our own listing, must give the same bytes."""

from __future__ import annotations

import random
import shutil
import subprocess
from pathlib import Path

import pytest

from compiler.avr import isa
from compiler.avr.asm import Assembler

needs_avr_gcc = pytest.mark.skipif(shutil.which("avr-gcc") is None, reason="gcc-avr not installed")


def reassemble(listing: str, mmcu: str, tmp: Path) -> bytes:
    """The listing assembled by avr-gcc, as the flash image's bytes."""
    source, elf, image = tmp / "prog.s", tmp / "prog.elf", tmp / "prog.bin"
    source.write_text(listing)
    subprocess.run(["avr-gcc", f"-mmcu={mmcu}", "-nostdlib", "-nostartfiles", "-x", "assembler",
                    str(source), "-o", str(elf)], check=True, capture_output=True, text=True)
    subprocess.run(["avr-objcopy", "-O", "binary", "-j", ".text", str(elf), str(image)], check=True)
    return image.read_bytes()


def operands(op: isa.Opcode, rng: random.Random) -> tuple[int, ...]:
    syntax = op.syntax
    pick = {
        "d": lambda: rng.randrange(32),
        "r": lambda: rng.randrange(32),
        "K": lambda: rng.randrange(256),
        "b": lambda: rng.randrange(8),
        "A": lambda: rng.randrange(64),
        "k": lambda: rng.randrange(0x10000),
    }
    values = [pick[field]() for field in syntax.split(",") if field in pick]
    if op.encode.__name__ == "_rd_k8":
        values[0] = 16 + values[0] % 16
    if op.encode.__name__ == "_pair_k6":
        values = [rng.choice((24, 26, 28, 30)), values[1] % 64]
    if op.encode.__name__ == "_movw":
        values = [v & ~1 for v in values]
    if op.encode.__name__ == "_io_bit":
        values[0] %= 32
    if syntax in ("d,X", "X,r", "X+,r"):
        values = [rng.choice([v for v in range(32) if v not in (26, 27)])]
    if syntax == "d,Z+":
        values = [rng.choice([v for v in range(32) if v not in (30, 31)])]
    return tuple(values)


@needs_avr_gcc
def test_every_opcode_reassembles_to_the_same_bytes(tmp_path):
    rng = random.Random(7)
    asm = Assembler(long_jumps=True, flash_words=1 << 17)
    for mnemonic, op in isa.OPCODES.items():
        if op.syntax == "k":
            continue  # jumps and branches are written against labels, below
        for _ in range(12):
            asm.emit(mnemonic, *operands(op, rng))
    assembled = asm.assemble()
    assert reassemble(assembled.listing, "atmega2560", tmp_path) == assembled.image()


@needs_avr_gcc
@pytest.mark.parametrize("long_jumps", [True, False])
def test_jumps_and_branches_relax_and_reassemble(tmp_path, long_jumps):
    asm = Assembler(long_jumps=long_jumps, flash_words=4096 if not long_jumps else 1 << 17)
    asm.label("start")
    for op in isa.INVERSE:
        asm.branch(op, "near")
        asm.branch(op, "far")
    asm.label("near")
    asm.call("far")
    for _ in range(2500 if long_jumps else 1500):
        asm.emit("nop")
    asm.label("far")
    asm.jump("start")
    asm.jump("far")
    asm.address(30, "table", high=False, offset=3)
    asm.address(31, "table", high=True, offset=3)
    asm.label("table")
    asm.data(bytes(range(37)))
    assembled = asm.assemble()
    mmcu = "atmega2560" if long_jumps else "atmega8"
    assert reassemble(assembled.listing, mmcu, tmp_path) == assembled.image()
    text = assembled.listing
    assert ("\tjmp start" in text) == long_jumps
    assert "\tbreq near" in text


def test_encodings_of_a_few_instructions_by_hand():
    assert isa.encode("ldi", 16, 0xFF) == [0xEF0F]
    assert isa.encode("out", 0x3F, 0) == [0xBE0F]
    assert isa.encode("sbis", 0x16, 1) == [0x9BB1]
    assert isa.encode("jmp", 0x1234) == [0x940C, 0x1234]
    assert isa.encode("rjmp", -1) == [0xCFFF]
    assert isa.encode("lds", 24, 0x100) == [0x9180, 0x0100]
