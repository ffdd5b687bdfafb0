"""The scan-time budget on the enhanced mid-range core (compiler/pic16/flow.py
reads its words): the decoder against gpdasm on our images (MOVLB, MOVLP,
BRA, the carry instructions, tables, calls, far jumps), and the budget
against the scans measured in gpsim on the PIC16F1824 (run as p16f1825):
never below the longest measured scan (sound), and on loop-free programs
driven along their longest path at most 1.25 times it (tight)."""

from __future__ import annotations

import re
import subprocess
from dataclasses import replace

import pytest
from test_compiler_budget import TIGHT, _high_times, _sound, _toggling, needs_gpdasm, needs_gpsim
from test_pic16e_encoding import _busy_program

import compiler
from compiler.budget import CALL, COMPUTED, JUMP, NEXT, RETURN, SKIP
from compiler.pic16.flow import instruction_at
from compiler.pic16.part import Part
from compiler.run import gpsim
from lang.model import PinAssignment

PART = "Microchip PIC16F1824 14-Pin PDIP, SOIC, TSSOP"
# not the MCLR pin RA3 (gpsim 0.31 restarts the part on its edges); the cycle-duty output on RA5
PINS = {"Xa": "RC4", "Xb": "RA4", "Xc": "RC0", "Ya": "RA0", "Yb": "RA1", "Yc": "RA2", "Yd": "RC2"}
TWO_CYCLES = {"goto", "call", "return", "retlw", "retfie", "bra", "brw", "callw"}
SKIPS = {"btfsc", "btfss", "decfsz", "incfsz"}
_GPDASM = re.compile(r"^([0-9a-f]{4}):\s+([0-9a-f]{4})\s+(\w+)\s*(.*)$")


@needs_gpdasm
@pytest.mark.parametrize("part,rungs", [("pic16f1824", 40), ("pic16f1527", 90)])
def test_the_decoder_agrees_with_gpdasm(part, rungs, tmp_path):
    build = compiler.build(_busy_program(part, rungs, {"Xa": "RA0"}))
    build.write(tmp_path / "p.hex")
    words = build.image.words
    out = subprocess.run(["gpdasm", "-p", Part.of(build.device).processor, str(tmp_path / "p.hex")],
                         capture_output=True, text=True, check=True).stdout
    listed = [(int(m.group(1), 16), m.group(3).lower(), m.group(4)) for m in map(_GPDASM.match, out.splitlines())
              if m and int(m.group(1), 16) < len(words)]
    assert len(listed) == len(words)
    labels = set(build.image.labels.values())
    seen = set()
    for address, mnemonic, operands in listed:
        ins = instruction_at(words, address, build.device)
        assert ins is not None, (address, mnemonic)
        seen.add(ins.flow)
        if mnemonic in SKIPS:
            assert (ins.flow, ins.cycles, ins.taken, ins.target) == (SKIP, 1, 2, address + 2)
        elif mnemonic in ("goto", "call", "bra"):
            assert (ins.flow, ins.cycles) == (CALL if mnemonic == "call" else JUMP, 2)
            assert ins.target in labels, (address, mnemonic)
        elif (mnemonic in ("movwf", "clrf") and operands.lower() in ("0x02", "pcl") or re.match(r"(0x02|pcl), 1", operands, re.I)
              or mnemonic == "brw"):
            assert (ins.flow, ins.cycles) == (COMPUTED, 2)  # a write to PCL or a BRW: a table
            assert ins.targets and all(words[t] >> 8 == 0x34 for t in ins.targets)
        else:
            assert ins.cycles == (2 if mnemonic in TWO_CYCLES else 1), (address, mnemonic)
            assert ins.flow == (RETURN if mnemonic in ("return", "retlw", "retfie") else NEXT), (address, mnemonic)
    assert seen >= {NEXT, SKIP, JUMP, CALL, RETURN, COMPUTED}


def measure(prog, until_ms: float, tmp_path):
    """(the build, the instruction cycles each scan took in gpsim)."""
    prog = replace(prog, settings=replace(prog.settings, cycle_duty=True),
                   pins={**prog.pins, "YPlcCycleDuty": PinAssignment("YPlcCycleDuty", "RA5")})
    build = compiler.build(prog)
    pin = build.device.pin("RA5")
    build.write(tmp_path / "p.hex")
    inputs = [(max(0.0, (e.scan - 0.5) * prog.settings.cycle_us / 1000), PINS[e.name], e.value)
              for e in _toggling(int(until_ms * 1000 // prog.settings.cycle_us))]
    run = gpsim.run_pic(tmp_path / "p.hex", Part.of(build.device).gpsim, prog.settings.crystal_hz, inputs=inputs,
                        watch=[pin.name], until_ms=until_ms, uart=False, timeout=120)
    return build, _high_times([(c, v) for c, _, v in run.edge_cycles])


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(TIGHT))
def test_the_worst_case_is_sound_and_tight_on_loop_free_programs(name, tmp_path):
    build, measured = measure(TIGHT[name](PART, PINS), 800, tmp_path)
    assert build.budget.loops == (), "not loop-free"
    assert _sound(build, measured) <= 1.25, f"{build.budget.cycles} against {max(measured)} measured"
