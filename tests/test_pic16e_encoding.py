"""The enhanced mid-range encoder and assembler against gputils and gpsim.

* Every mnemonic of compiler/pic16/enhanced/isa.py with boundary operands:
  `isa.encode` gives gpasm's word for the same source line.
* A compiled program for each part (every bank of its RAM in use, a RETLW
  table, multiplication and division routines, more than one code page on the
  parts with more): the listing reassembled by gpasm gives exactly our words
  and configuration words. gpasm knows every part; gpsim does not, so this is
  what checks the PIC16F1512, 1516, 1527 and 1827 images.
* A program of more than 2048 words on the PIC12F1840 (two pages, MOVLP
  before every far GOTO and CALL) runs in gpsim beside the simulator.
"""

from __future__ import annotations

import pytest
from builders import coil, contact, el, move, program
from pic16_harness import differential
from test_compiler_harness import Event
from test_pic16_encoding import _number, gpasm_words, needs_gpsim

import compiler
from compiler.pic16.enhanced import isa
from compiler.pic16.isa import EncodingError
from compiler.pic16.part import Part
from lang.devices import find_device
from lang.families import FAMILIES

ENHANCED = [part for part in FAMILIES["pic16"].parts if Part.of(find_device(part)).enhanced]

BOUNDARIES: dict[str, list[tuple[int, ...]]] = {
    "fd": [(f, d) for f in (0x00, 0x7F, 0x80, 0xFFF) for d in (0, 1)],
    "f": [(0x00,), (0x7F,), (0x80,), (0xFFF,)],
    "fb": [(f, b) for f in (0x00, 0x7F, 0xFFF) for b in (0, 7)],
    "k8": [(0x00,), (0x7F,), (0x80,), (0xFF,), (-0x80,), (-0x01,)],
    "k11": [(0x000,), (0x400,), (0x7FF,)],
    "k5": [(0,), (31,)],
    "k7": [(0,), (0x7F,)],
    "": [()],
}
OUT_OF_RANGE: dict[str, list[tuple[int, ...]]] = {
    "fd": [(-1, 0), (0x1000, 0), (0x20, 2)], "f": [(-1,), (0x1000,)], "fb": [(0x20, 8), (0x1000, 0)],
    "k8": [(0x100,), (-0x81,)], "k11": [(0x800,), (-1,)], "k5": [(32,), (-1,)], "k7": [(0x80,), (-1,)],
    "n9": [(256,), (-257,)], "": [],
}


def test_every_mnemonic_encodes_as_gpasm_does(tmp_path):
    lines = ["\tprocessor p16f1827", "\terrorlevel -302, -306", "\torg 0"]
    expected = []
    for op, spec in isa.INSTRUCTIONS.items():
        if spec.pattern == "n9":  # BRA's operand is a target address: gpasm takes `$ + 1 + n`
            for n in (-256, -1, 0, 255):
                lines.append(f"\tbra\t$ + 1 + {_number(n)}")
                expected.append((lines[-1].strip(), isa.encode(op, n)))
            continue
        for args in BOUNDARIES[spec.pattern]:
            lines.append(f"\t{op}\t{', '.join(map(_number, args))}")
            expected.append((lines[-1].strip(), isa.encode(op, *args)))
    lines.append("\tend")
    words = gpasm_words("\n".join(lines) + "\n", "p16f1827", tmp_path)
    got = [words.get(address) for address in range(len(expected))]
    assert {source: word for (source, word), word2 in zip(expected, got) if word != word2} == {}


@pytest.mark.parametrize("op", sorted(isa.INSTRUCTIONS))
def test_operands_out_of_range_are_refused(op):
    for args in OUT_OF_RANGE[isa.INSTRUCTIONS[op].pattern]:
        with pytest.raises(EncodingError):
            isa.encode(op, *args)


def _busy_program(part: str, rungs: int, pins: dict[str, str], *extra):
    """Arithmetic on 32-bit variables spread over RAM, a look-up table,
    multiplication and division: `rungs` rungs of it, and the `extra` rungs."""
    body = [[contact("Xa"), el("LOOK_UP_TABLE", dest="vt", index="vi", values=("3", "1", "4", "1", "5"))]]
    for i in range(rungs):
        body.append([contact("Xa"), el("MUL", dest=f"v{i % 7}", op1=f"v{(i + 1) % 7}", op2=str(i + 3))])
        body.append([el("DIV", dest=f"w{i % 5}", op1=f"v{i % 7}", op2=str(i % 9 - 4 or 7))])
        body.append([el("ADD", dest=f"v{(i + 3) % 7}", op1=f"w{i % 5}", op2=f"v{i % 7}")])
    sizes = {f"v{i}": 4 for i in range(7)} | {f"w{i}": 4 for i in range(5)}
    return program(*body, [move("vi", "2")], *extra, mcu=part, pins=pins, sizes=sizes, crystal_hz=16_000_000,
                   cycle_us=100_000)


@pytest.mark.parametrize("part", ENHANCED)
def test_compiled_programs_reassemble_to_the_same_words(part, tmp_path):
    device = find_device(part)
    facts = Part.of(device)
    # past the first page where there is a second, past the second where there are more
    rungs = 4 if facts.flash_words <= 2048 else 40 if facts.flash_words <= 4096 else 90
    built = compiler.build(_busy_program(part, rungs, {"Xa": device.io_pins()[0].name}))
    words = gpasm_words(built.image.listing, facts.processor, tmp_path)
    assert {a: w for a, w in words.items() if a < 0x8000} == dict(enumerate(built.image.words))
    assert {a: w for a, w in words.items() if a >= 0x8000} == dict(facts.config_words)
    if facts.flash_words > 2048:
        assert len(built.image.words) > min(4096, facts.flash_words // 2)
        assert any(w & 0x3F80 == 0x3180 for w in built.image.words)  # MOVLP


@needs_gpsim
def test_a_program_over_two_pages_runs_as_the_simulator_says(tmp_path):
    prog = _busy_program("pic12f1840", 40, {"Xa": "RA4", "Xb": "RA2", "Yb": "RA5"}, [contact("Xb"), coil("Yb")])
    assert len(compiler.build(prog).image.words) > 2048
    events = [Event(0, "Xa", 1), Event(2, "Xb", 1), Event(4, "Xa", 0), Event(5, "Xb", 0)]
    assert differential(prog, events, 8, tmp_path) == []
