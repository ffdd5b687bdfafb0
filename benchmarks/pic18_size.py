"""Our PIC18 images against our PIC16 images of the same programs, run on
demand: `python benchmarks/pic18_size.py` (needs gpsim). LDmicro makes no
PIC18 HEX (its PIC18F4520 entry is for its C output only), so the issue's
§9 compares the PIC18 with the PIC16 the program was drawn for.

The corpus's PIC programs that tests/test_pic16_compiler.py and
tests/test_pic18_compiler.py run (`CASES`: a pin given to misc-ops' and
pic16-hw's PWM output), each with the cycle-duty output on a free pin
(pic16_size.py's `with_duty_pin`), compiled for their PIC16F876/877 and
moved to the PIC18
of the same package (the PIC18F2520 for the 28-pin PIC16F876, the
PIC18F4520 for the 40-pin PIC16F877: the same pin numbers are the same port
bits), at the program's own clock. Words are program-memory words: 14 bits
on the PIC16, 16 bits (2 bytes) on the PIC18. Scan cycles are the duty pin's
high time in instruction cycles (Fosc/4 on both), over one simulated second
in gpsim with the inputs at rest (pic16_size.py's `scan_cycles`). Targets:
the geometric means at most 1.0 of the PIC16's (the PIC18 no larger in
words and no slower).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from pic16_size import compared, scan_cycles, summary, with_duty_pin
from test_compiler_harness import load
from test_pic16_compiler import CASES
from test_pic18_compiler import moved

import compiler

WORDS_TARGET, CYCLES_TARGET = 1.0, 1.0


def main() -> int:
    rows, word_ratios, cycle_ratios = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for path, (_, _, adapt) in CASES.items():
            variant = with_duty_pin(adapt(load(path)) if adapt else load(path))
            pic16, pic18 = compiler.build(variant), compiler.build(variant, moved(variant.settings.mcu))
            measured = []
            for name, build in (("pic18", pic18), ("pic16", pic16)):
                image = folder / f"{name}.hex"
                build.write(image)
                measured.append(scan_cycles(image, variant, build.device))
            compared(rows, word_ratios, cycle_ratios, path, pic18.device.title,
                     (len(pic18.image.words), len(pic16.image.words)), *measured)
    return summary(rows, word_ratios, cycle_ratios, WORDS_TARGET, CYCLES_TARGET, reference="PIC16")


if __name__ == "__main__":
    sys.exit(main())
