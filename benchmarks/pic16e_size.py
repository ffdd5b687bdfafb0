"""Our enhanced mid-range PIC16 images against LDmicro's, run on demand:
`python benchmarks/pic16e_size.py` (needs gpsim and LDmicro 5.4 built by
../shared/tools/ldmicro/build.sh at /opt/ldmicro, or LDMICRO=path).

The PIC programs of benchmarks/pic16_size.py (and two more of the corpus's
PIC16 tests), moved to the parts gpsim models, the PIC12F1840 and the
PIC16F1824 (run as its sibling p16f1825), as tests/test_pic16e_ldmicro.py
moves them (a pin for each name that can serve it, the cycle-duty output on
one more, the clock of the internal oscillator nearest the program's; a
program needing more pins than the part has is left out). LDmicro compiles
the same program (the .ld our writer makes);
both images run in gpsim for one simulated second with the inputs at rest,
and a scan's instruction cycles are the duty pin's high time (pic16_size.py's
measure). Program words are counted below the configuration words (0x8000).
Targets: the geometric means at most 0.45 (words) and 0.35 (scan cycles) of
LDmicro's (scans dominated by a hardware wait left out of the cycles).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from intelhex import IntelHex
from pic16_size import compared, scan_cycles, summary
from test_compiler_harness import load
from test_pic16e_ldmicro import PROGRAMS, ldmicro_image, moved

import compiler

WORDS_TARGET, CYCLES_TARGET = 0.45, 0.35
PARTS = ("pic12f1840", "pic16f1824")
CONFIG_SPACE = 0x8000  # word address of the configuration words


def words(hex_path: Path) -> int:
    image = IntelHex(str(hex_path))
    return len([a for a in image.addresses() if a < 2 * CONFIG_SPACE]) // 2


def main() -> int:
    rows, word_ratios, cycle_ratios = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for part in PARTS:
            for path in PROGRAMS:
                program = moved(load(path), part)
                if program is None:
                    rows.append(f"| {path} | {part} | too few pins |")
                    continue
                build = compiler.build(program)
                ours = folder / "ours.hex"
                build.write(ours)
                theirs, said = ldmicro_image(program, folder)
                if theirs is None:
                    rows.append(f"| {path} | {build.device.title} | {len(build.image.words)} | LDmicro refuses: {said} |")
                    continue
                ours_words, theirs_words = len(build.image.words), words(theirs)
                (mean, worst), (their_mean, their_worst) = (scan_cycles(h, program, build.device)
                                                            for h in (ours, theirs))
                compared(rows, word_ratios, cycle_ratios, path, build.device.title, (ours_words, theirs_words),
                         (mean, worst), (their_mean, their_worst))
    return summary(rows, word_ratios, cycle_ratios, WORDS_TARGET, CYCLES_TARGET)


if __name__ == "__main__":
    sys.exit(main())
