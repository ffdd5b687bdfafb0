"""Our PIC10F200/202 images against LDmicro's, run on demand:
`python benchmarks/pic10_size.py` (needs gpsim and LDmicro 5.4 built by
../shared/tools/ldmicro/build.sh at /opt/ldmicro, or LDMICRO=path).

The corpus programs that fit the baseline parts (4 pins, one of them an
input only; 255 or 511 words; 16 or 24 bytes of RAM), moved as
tests/test_pic16e_ldmicro.py moves a program to a part (a pin for each
name, the cycle-duty output on one more, the part's one clock, 4 MHz, the
cycle on Timer0), on
each part they fit (tests/test_pic10_corpus.py runs the same list in gpsim
against the simulator). LDmicro compiles the same program (the .ld our
writer makes); both images run in gpsim for one simulated second with the
inputs at rest, and a scan's instruction cycles are the duty pin's high
time (pic16_size.py's measure). Program words are counted below the
calibration word (LDmicro's configuration word, which it puts at 0x1FF or
0x3FF, is left out). Targets: the geometric means at most 0.45 (words) and
0.35 (scan cycles) of LDmicro's, no program larger or slower.
"""

from __future__ import annotations

import re
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from pic16_size import compared, scan_cycles, summary
from test_pic10_corpus import CORPUS_PROGRAMS, on_pic10
from test_pic16_parts import hex_words
from test_pic16e_ldmicro import ldmicro_image

import compiler

WORDS_TARGET, CYCLES_TARGET = 0.45, 0.35


def main() -> int:
    rows, word_ratios, cycle_ratios = [], [], []
    slower = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for path, part in CORPUS_PROGRAMS:
            program = on_pic10(path, part)
            build = compiler.build(program)
            ours = folder / "ours.hex"
            build.write(ours)
            theirs, said = ldmicro_image(program, folder)
            if theirs is None:
                reason = re.search(r"Compile error \(.*?\): (.*?)\[", said)
                rows.append(f"| {path} | {build.device.title} | {len(build.image.words)} | LDmicro refuses: "
                            f"{reason.group(1) if reason else said} |")
                continue
            flash = build.device.memory["flash_words"]
            # LDmicro's configuration word goes at twice the part's words less one (0x1FF, 0x3FF)
            code = [a for a in hex_words(theirs) if a != 2 * flash - 1]
            if max(code) >= flash - 1:
                rows.append(f"| {path} | {build.device.title} | {len(build.image.words)} | LDmicro's image runs "
                            f"to word {max(code)}, past the {flash - 1} words of the part |")
                continue
            theirs_words = len(code)
            (mean, worst), (their_mean, their_worst) = (scan_cycles(h, program, build.device)
                                                        for h in (ours, theirs))
            compared(rows, word_ratios, cycle_ratios, path, build.device.title, (len(build.image.words), theirs_words),
                     (mean, worst), (their_mean, their_worst))
            if len(build.image.words) >= theirs_words or worst >= their_worst:
                slower.append(f"{path} on the {build.device.title}")
    status = summary(rows, word_ratios, cycle_ratios, WORDS_TARGET, CYCLES_TARGET)
    for program in slower:
        print(f"not smaller and faster than LDmicro's: {program}")
    return status or int(bool(slower))


if __name__ == "__main__":
    sys.exit(main())
