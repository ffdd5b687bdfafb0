"""Our PIC10F200/202 images against LDmicro 5.4's own, for the programs of
tests/pic10_programs: LDmicro's HEX made by LDmicro itself (/opt/ldmicro, or
LDMICRO=), both run in gpsim under the program's stimulus file, every output
pin making the same edges within two cycles (LDmicro's first scan comes a
cycle late, its Timer0 reloads drift), as tests/test_pic16_oracle.py does on
the PIC16; and ours takes fewer words of program memory and fewer cycles a
scan (the longest, measured on the cycle-duty pin).

LDmicro's defects on these parts (docs/pic10.md): its configuration word at
word 0x1FF (0x3FF on the PIC10F202), where neither part has one (0xFFF), and
the oscillator calibration the reset vector leaves in W never stored.

These tests need LDmicro under wine: marker `ldmicro`.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from ldmicro_oracle import ldmicro_compile
from test_compiler_budget import measure_pic
from test_pic16_oracle import _run
from test_pic16_parts import hex_words

import compiler
from compiler.run import gpsim
from lang.loader import load_path

pytestmark = pytest.mark.ldmicro

PROGRAMS = Path(__file__).parent / "pic10_programs"
NAMES = ["p10f200_basic", "p10f202_arith"]


def _ldmicro_hex(source: Path, folder: Path) -> Path:
    theirs = folder / "ldmicro.hex"
    ldmicro_compile(source, theirs, check=True)
    return theirs


@pytest.mark.parametrize("name", NAMES)
def test_same_outputs_as_ldmicros_image(name, tmp_path):
    source = PROGRAMS / f"{name}.ld"
    stimulus = json.loads((PROGRAMS / f"{name}.json").read_text())
    program, _ = load_path(source)
    build = compiler.build(program)
    ours = tmp_path / "ours.hex"
    build.write(ours)
    theirs = _ldmicro_hex(source, tmp_path)
    outputs, mine = _run(ours, program, build.device, stimulus)
    _, reference = _run(theirs, program, build.device, stimulus)
    cycle_ms = program.settings.cycle_us / 1000
    last = stimulus["until_ms"] - 3 * cycle_ms
    for pin in outputs:
        a = [(t, v) for t, v in mine.pin_edges(pin) if t < last]
        b = reference.pin_edges(pin)[:len(a)]
        assert a, f"{pin} never changes"
        assert [v for _, v in a] == [v for _, v in b], f"{pin}: ours {a[:10]}, LDmicro's {b[:10]}"
        for (t_ours, _), (t_theirs, _) in zip(a, b):
            assert abs(t_theirs - t_ours) <= 2 * cycle_ms + 0.02 * t_ours, \
                f"{pin}: our edge at {t_ours:.3f} ms, LDmicro's at {t_theirs:.3f} ms"


def _pin3_free(source: Path) -> str:
    """The program with the output on GP1 (pin 3) made an internal relay: room for the cycle-duty pin."""
    text = source.read_text()
    name = re.search(r"\n    (\w+) at 3 0 0", text).group(1)
    text = text.replace(f"\n    {name} at 3 0 0", "")
    return re.sub(rf"\b{name}\b", f"R{name[1:]}", text)


@pytest.mark.parametrize("name", NAMES)
def test_fewer_words_and_shorter_scans_than_ldmicros_image(name, tmp_path):
    text = _pin3_free(PROGRAMS / f"{name}.ld")
    (tmp_path / "free.ld").write_text(text)
    program, _ = load_path(tmp_path / "free.ld")
    # measure_pic puts our YPlcCycleDuty on the free pin, GP1; LDmicro's goes there too
    build, ours = measure_pic(program, [(0.0, "GP3", 1), (0.0, "GP0", 1)], 300, tmp_path)
    (tmp_path / "duty.ld").write_text(text.replace("YPlcCycleDuty:0", "YPlcCycleDuty:1").replace(
        "IO LIST\n", "IO LIST\n    YPlcCycleDuty at 3 0 0\n"))
    theirs_hex = _ldmicro_hex(tmp_path / "duty.ld", tmp_path)
    run = gpsim.run_pic(theirs_hex, build.device.part, 4_000_000, inputs=[(0.0, "GP3", 1), (0.0, "GP0", 1)],
                        watch=["GP1"], until_ms=300, uart=False, timeout=120)
    edges = [(c, v) for c, _, v in run.edge_cycles]
    theirs = [fall - rise for (rise, high), (fall, low) in zip(edges, edges[1:]) if high == 1 and low == 0]
    words = [address for address in hex_words(theirs_hex) if address < build.device.memory["flash_words"] - 1]
    assert len(build.image.words) < len(words)
    assert max(ours) < max(theirs)
    print(f"{name}: {len(build.image.words)} words against LDmicro's {len(words)}; "
          f"{max(ours)} cycles a scan against {max(theirs)}")
