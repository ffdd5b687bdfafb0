"""Our PIC16 images against LDmicro's, run on demand:
`python benchmarks/pic16_size.py` (needs gpsim and LDmicro 5.4 built by
../shared/tools/ldmicro/build.sh at /opt/ldmicro, or LDMICRO=path).

For each PIC program of the corpus with an LDmicro HEX: the program-memory
words of our image and of LDmicro's (its HEX in the corpus), and the
instruction cycles of a scan, measured the same way for both: the
cycle-duty output (YPlcCycleDuty, high while the scan runs) put on a free pin
of the program with the cycle-duty setting on, both images run in gpsim for
one simulated second with the inputs at rest, and the pin's high time taken
from its writes (mean and worst over the scans). LDmicro's image of that
variant is made by LDmicro itself from the .ld our writer makes. Targets: the
geometric means at most 0.5 (words) and 0.4 (scan cycles) of LDmicro's, no
program larger or slower (a scan dominated by a hardware wait is reported
apart).
"""

from __future__ import annotations

import math
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from intelhex import IntelHex
from ldmicro_oracle import ldmicro_compile
from test_compiler_harness import LDMICRO_HEX, load

import compiler
from compiler.pic16.part import Part
from compiler.run import gpsim
from lang.ldfile import write_ld_bytes
from lang.model import PinAssignment

WORDS_TARGET, CYCLES_TARGET = 0.5, 0.4
PROGRAMS = {  # program: LDmicro's image in the corpus
    "reg/tests/contacts.ld": "reg_tests_contacts",
    "sample/blink.ld": "sample_blink",
    "sample/serial.ld": "sample_serial",
    "sample/pic-adc.ld": "sample_pic-adc",
    "sample/swatch1.ld": "sample_swatch1",
}
FREE_PINS = ("RD7", "RD6", "RD5", "RB7", "RB6", "RB5", "RB4")
HARDWARE_WAITS = {"sample/pic-adc.ld": "A/D conversion"}


def words(hex_path: Path) -> int:
    image = IntelHex(str(hex_path))
    return len([a for a in image.addresses() if a < 0x4000]) // 2


def with_duty_pin(program):
    """The program with YPlcCycleDuty on a free pin and the cycle-duty setting on."""
    if program.settings.cycle_duty and "YPlcCycleDuty" in program.pins:
        return program
    device = compiler.target_device(program, None)
    used = {device.pin(a.pin).name for a in program.pins.values() if device.pin(a.pin) is not None}
    pin = next(p for p in FREE_PINS if p not in used and device.pin(p) is not None)
    pins = dict(program.pins)
    pins["YPlcCycleDuty"] = PinAssignment("YPlcCycleDuty", device.pin(pin).number)  # LDmicro wants numbers
    return replace(program, pins=pins, settings=replace(program.settings, cycle_duty=True))


def scan_cycles(hex_path: Path, program, device) -> tuple[float, int]:
    """(mean, worst) instruction cycles the duty pin is high per scan, over one second."""
    pin = device.pin(program.pins["YPlcCycleDuty"].pin).name
    inputs = [(0.0, device.pin(a.pin).name, 0) for n, a in program.pins.items() if n[0] == "X"]
    run = gpsim.run_pic(hex_path, Part.of(device).gpsim, program.settings.crystal_hz, inputs=inputs,
                        watch=[pin], until_ms=1000, uart=Part.of(device).feature("uart"), timeout=300)
    per_ms = program.settings.crystal_hz / 4000
    edges = run.pin_edges(pin)
    highs = [round((fall - rise) * per_ms) for (rise, up), (fall, down) in zip(edges, edges[1:]) if up and not down]
    return sum(highs) / len(highs), max(highs)


def ldmicro_image(program, folder: Path) -> Path:
    source = folder / "variant.ld"
    source.write_bytes(write_ld_bytes(program))
    out = folder / "variant.hex"
    ldmicro_compile(source, out, check=True)
    return out


def main() -> int:
    rows, word_ratios, cycle_ratios = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for path, reference in PROGRAMS.items():
            program = load(path)
            build = compiler.build(program)
            ours_words, theirs_words = len(build.image.words), words(LDMICRO_HEX / f"{reference}.hex")
            variant = with_duty_pin(program)
            ours = folder / "ours.hex"
            compiler.build(variant).write(ours)
            theirs = ldmicro_image(variant, folder)
            device = build.device
            (mean, worst), (their_mean, their_worst) = (scan_cycles(h, variant, device) for h in (ours, theirs))
            compared(rows, word_ratios, cycle_ratios, path, device.title, (ours_words, theirs_words),
                     (mean, worst), (their_mean, their_worst))
    return summary(rows, word_ratios, cycle_ratios, WORDS_TARGET, CYCLES_TARGET)


def compared(rows: list[str], word_ratios: list[float], cycle_ratios: list[float], path: str, title: str,
             sizes: tuple[int, int], ours: tuple[float, int], theirs: tuple[float, int]) -> None:
    """One program's row, our image against LDmicro's, and its ratios (no
    cycle ratio for a scan dominated by a hardware wait)."""
    (ours_words, theirs_words), (mean, worst), (their_mean, their_worst) = sizes, ours, theirs
    word_ratios.append(ours_words / theirs_words)
    if path not in HARDWARE_WAITS:
        cycle_ratios.append(mean / their_mean)
    rows.append(f"| {path} | {title} | {ours_words} | {theirs_words} | {ours_words / theirs_words:.2f} "
                f"| {mean:.0f} | {their_mean:.0f} | {mean / their_mean:.2f} | {worst} | {their_worst} |"
                + (f" {HARDWARE_WAITS[path]}" if path in HARDWARE_WAITS else ""))


def summary(rows: list[str], word_ratios: list[float], cycle_ratios: list[float], words_target: float,
            cycles_target: float, reference: str = "LDmicro") -> int:
    """The table (against `reference`'s images) and the geometric means; 0
    when both meet their targets."""
    print(f"| program | part | words | {reference} | ratio | cycles/scan | {reference} | ratio | worst | {reference} |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    print("\n".join(rows))

    def geomean(values):
        return math.exp(sum(map(math.log, values)) / len(values))

    words_mean, cycles_mean = geomean(word_ratios), geomean(cycle_ratios)
    print(f"\ngeometric means: words {words_mean:.2f} (target {words_target}), scan cycles {cycles_mean:.2f} "
          f"(target {cycles_target}; scans dominated by a hardware wait left out)")
    return 0 if words_mean <= words_target and cycles_mean <= cycles_target else 1


if __name__ == "__main__":
    sys.exit(main())
