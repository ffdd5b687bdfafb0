"""The image every back end returns (compiler/image.py): its Intel HEX,
checked by an independent reader (gpdasm for the PIC layout), its summary
line, and files that appear whole or not at all."""

from __future__ import annotations

import io
import os
import subprocess

import pytest
from intelhex import IntelHex

from compiler.image import Build, Image, Symbol
from lang.devices import find_device
from lang.model import Program

NOP, GOTO_0 = 0x0000, 0x2800  # PIC16 14-bit words


def pic_image(**changes) -> Image:
    fields = dict(words=[NOP, GOTO_0], listing="\tnop\n\tgoto 0\n", ram_bytes=40, ram_size=368, flash_size=8192,
                  flash_unit="words", warnings=[], symbols={"Ya": Symbol(0x20, 1, 3)}, labels={"start": 0},
                  segments={0x400E: (0x3F72).to_bytes(2, "little"), 0x4200: bytes([7, 0, 9, 0])},
                  listing_suffix=".asm")
    fields.update(changes)
    return Image(**fields)


def test_a_pic_image_is_words_at_twice_their_address_with_config_and_eeprom(tmp_path):
    path = tmp_path / "pic.hex"
    path.write_text(pic_image().hex())
    disassembly = subprocess.run(["gpdasm", "-p", "p16f877a", str(path)], capture_output=True, text=True,
                                 timeout=30, check=True).stdout
    lines = [" ".join(line.split()) for line in disassembly.splitlines()]
    assert lines[:3] == ["0000: 0000 nop", "0001: 2800 goto 0x0000", "2007: 3f72 dw 0x3f72"]
    data = IntelHex(str(path))
    assert [data[a] for a in (0x4200, 0x4201, 0x4202, 0x4203)] == [7, 0, 9, 0]


def test_an_avr_image_is_its_words_little_endian():
    image = pic_image(words=[0x940C, 0x0034, 0xCFFF], segments={}, flash_unit="bytes", flash_size=32768)
    data = IntelHex()
    data.loadhex(io.StringIO(image.hex()))
    assert data.tobinstr() == bytes([0x0C, 0x94, 0x34, 0x00, 0xFF, 0xCF]) == image.program_bytes()
    assert image.flash_used == 6


def test_the_summary_counts_flash_in_the_families_unit():
    device = find_device("pic16f877a")
    image = pic_image(words=[NOP] * 812)
    assert Build(Program(), device, image, []).summary() == \
        "PIC16F877A: flash 812/8192 words (9.9%), RAM 40/368 bytes (10.9%)"
    avr = pic_image(words=[NOP] * 500, flash_unit="bytes", flash_size=32768, ram_bytes=100, ram_size=2048,
                    segments={})
    assert Build(Program(), find_device("atmega328p"), avr, []).summary() == \
        "ATmega328P: flash 1000/32768 bytes (3.1%), RAM 100/2048 bytes (4.9%)"


def test_a_segment_inside_program_memory_is_refused():
    with pytest.raises(ValueError, match="overlaps program memory"):
        pic_image(segments={0x0002: b"\x00"})
    with pytest.raises(ValueError, match="unit"):
        pic_image(flash_unit="kilobytes")


def test_write_puts_the_listing_beside_with_the_back_ends_suffix(tmp_path):
    build = Build(Program(), find_device("pic16f877a"), pic_image(), [])
    build.write(tmp_path / "out.hex")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.asm", "out.hex"]
    assert (tmp_path / "out.asm").read_text() == "\tnop\n\tgoto 0\n"


def test_a_failed_write_leaves_the_old_file_whole(tmp_path, monkeypatch):
    target = tmp_path / "out.hex"
    target.write_text("old image\n")

    def refuse(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", refuse)
    with pytest.raises(OSError):
        Build(Program(), find_device("pic16f877a"), pic_image(), []).write(target)
    assert target.read_text() == "old image\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.hex"]
