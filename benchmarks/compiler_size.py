"""Our compiled images against LDmicro's, run on demand:
`python benchmarks/compiler_size.py`.

For each corpus program with an LDmicro HEX (/work/shared/corpus/ldmicro-hex):
the flash bytes of both images, and the CPU cycles a scan takes, measured in
simavr by a small probe (C, built once against libsimavr) that steps
instruction by instruction under the program's stimulus and counts the
cycles spent outside the loop that waits for the next cycle. Targets: the
geometric means at most 0.6 (flash) and 0.5 (scan cycles) of LDmicro's, no
program larger or slower. integers.ld targets the ATmega162, which simavr
cannot run: its size is compared, its scan is not.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from intelhex import IntelHex
from test_compiler_corpus import ADC, SWATCH, TIMERS, TRAFFIC
from test_compiler_harness import LDMICRO_HEX, adc_millivolts, load

import compiler

SCANS = 400
FLASH_TARGET, CYCLES_TARGET = 0.6, 0.5

PROGRAMS = {  # program: (LDmicro's image, stimulus)
    "sample/traffic.ld": ("sample_traffic", TRAFFIC),
    "reg/tests/timers-counters.ld": ("reg_tests_timers-counters", TIMERS),
    "sample/ctu_ctd_ctc.ld": ("sample_ctu_ctd_ctc", []),
    "sample/ctu_ctd_ctc_ctr.ld": ("sample_ctu_ctd_ctc_ctr", []),
    "sample/hello.ld": ("sample_hello", []),
    "sample/swatch2.ld": ("sample_swatch2", SWATCH),
    "Tests/test-adc.ld": ("Tests_test-adc", ADC),
    "reg/tests/integers.ld": ("reg_tests_integers", []),
}
NO_CORE = {"atmega162", "atmega64"}

PROBE = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sim_avr.h"
#include "sim_hex.h"
#include "avr_ioport.h"
#include "avr_adc.h"
#include "avr_uart.h"

static void no_sleep(avr_t *avr, avr_cycle_count_t how_long) { (void)avr; (void)how_long; }

/* probe <mcu> <freq> <hex> <idle first word> <idle last word> <cycles>;
   stdin: "<cycle> drive <port> <bit> <level>" or "<cycle> adc <channel> <mV>",
   sorted by cycle. Prints "scans N busy C max M". */
int main(int argc, char **argv)
{
    if (argc != 7) return 2;
    avr_t *avr = avr_make_mcu_by_name(argv[1]);
    if (!avr) return 3;
    avr_init(avr);
    avr->frequency = strtoul(argv[2], NULL, 10);
    avr->sleep = no_sleep;
    avr->log = LOG_NONE;
    avr->vcc = avr->avcc = avr->aref = 5000;
    ihex_chunk_p chunks = NULL;
    int n = read_ihex_chunks(argv[3], &chunks);
    for (int i = 0; i < n; i++)
        memcpy(avr->flash + chunks[i].baseaddr, chunks[i].data, chunks[i].size);
    avr->codeend = avr->flashend;
    uint32_t flags = 0;
    if (avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags) == 0) {
        flags &= ~(uint32_t)(AVR_UART_FLAG_POLL_SLEEP | AVR_UART_FLAG_STDIO);
        avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    }
    uint32_t idle_lo = 2 * strtoul(argv[4], NULL, 10), idle_hi = 2 * strtoul(argv[5], NULL, 10);
    unsigned long long until = strtoull(argv[6], NULL, 10);
    unsigned long long at; char kind[16]; char port[4]; int a, b;
    int have = scanf("%llu %15s %3s %d %d", &at, kind, port, &a, &b) == 5;
    uint8_t mask[12] = {0}, value[12] = {0};
    unsigned long long scans = 0, busy = 0, scan_busy = 0, worst = 0;
    int started = 0, was_idle = 0;
    while (avr->cycle < until) {
        while (have && at <= avr->cycle) {
            if (!strcmp(kind, "drive")) {
                int p = port[0] - 'A';
                mask[p] |= 1 << a;
                value[p] = (value[p] & ~(1 << a)) | ((b ? 1 : 0) << a);
                avr_ioport_external_t ext = { .name = port[0], .mask = mask[p], .value = value[p] };
                avr_ioctl(avr, AVR_IOCTL_IOPORT_SET_EXTERNAL(port[0]), &ext);
                avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(port[0]), a), b);
            } else {
                avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0 + atoi(port)), a);
            }
            have = scanf("%llu %15s %3s %d %d", &at, kind, port, &a, &b) == 5;
        }
        uint32_t pc = avr->pc;
        avr_cycle_count_t before = avr->cycle;
        int state = avr_run(avr);
        if (state == cpu_Done || state == cpu_Crashed) break;
        int idle = pc >= idle_lo && pc <= idle_hi;
        if (!idle)
            scan_busy += avr->cycle - before;
        if (idle && !was_idle) {
            if (started) {
                scans++;
                busy += scan_busy;
                if (scan_busy > worst) worst = scan_busy;
            }
            started = 1;
            scan_busy = 0;
        }
        was_idle = idle;
    }
    printf("scans %llu busy %llu max %llu\n", scans, busy, worst);
    return 0;
}
"""


def _probe() -> Path:
    build = Path(tempfile.gettempdir()) / "textladder-scan-probe"
    build.mkdir(exist_ok=True)
    exe, source = build / "probe", build / "probe.c"
    if not exe.exists() or source.read_text() != PROBE if source.exists() else True:
        source.write_text(PROBE)
        subprocess.run(["gcc", "-O2", "-I/usr/include/simavr", str(source), "-o", str(exe), "-lsimavr"],
                       check=True, capture_output=True)
    return exe


def scan_cycles(hex_path: Path, mcu: str, freq: int, idle: tuple[int, int], stimulus: list[str],
                cycles: int) -> tuple[float, int]:
    """(mean, worst) CPU cycles per scan, the waiting loop left out."""
    out = subprocess.run([str(_probe()), mcu, str(freq), str(hex_path), str(idle[0]), str(idle[1]), str(cycles)],
                         input="\n".join(stimulus) + "\n", capture_output=True, text=True, check=True).stdout
    m = re.search(r"scans (\d+) busy (\d+) max (\d+)", out)
    scans, busy, worst = map(int, m.groups())
    return busy / scans, worst


def ldmicro_idle_loop(listing: Path) -> tuple[int, int]:
    """The words of LDmicro's loop that waits for the cycle timer: the three
    instructions after the two LDIs at "Begin Of PLC Cycle"."""
    lines = listing.read_text(errors="replace").splitlines()
    start = next(i for i, line in enumerate(lines) if "Begin Of PLC Cycle" in line)
    loop = next(line for line in lines[start + 1:] if re.match(r"l_[0-9a-f]+:\s+ld\s", line))
    first = int(re.match(r"l_([0-9a-f]+):", loop).group(1), 16)
    return first, first + 2


def stimulus(program, build, events) -> list[str]:
    device = build.device
    settings = program.settings
    commands = []
    for event in sorted(events, key=lambda e: e.scan):
        at = round(max(0.0, event.scan - 0.5) * settings.cycle_us * settings.crystal_hz / 1_000_000)
        pin = device.pin(program.pins[event.name].pin)
        if event.name[0] == "X":
            commands.append(f"{at} drive {pin.port} {pin.bit} {event.value}")
        else:
            commands.append(f"{at} adc {device.adc[pin.name]} {adc_millivolts(event.value)} 0")
    return commands


def measure() -> list[dict]:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for path, (reference, events) in PROGRAMS.items():
            program = load(path)
            build = compiler.build(program)
            ours = Path(tmp) / "ours.hex"
            build.write(ours)
            theirs = LDMICRO_HEX / f"{reference}.hex"
            row = {"program": path, "part": build.device.title, "flash": build.image.flash_used,
                   "ldmicro_flash": len(IntelHex(str(theirs)))}
            if build.device.part not in NO_CORE:
                settings = program.settings
                cycles = SCANS * settings.cycle_us * settings.crystal_hz // 1_000_000
                commands = stimulus(program, build, events)
                row["cycles"] = scan_cycles(ours, build.device.part, settings.crystal_hz,
                                            (build.image.labels["wait"], build.image.labels["waited"] - 1), commands, cycles)
                row["ldmicro_cycles"] = scan_cycles(theirs, build.device.part, settings.crystal_hz,
                                                    ldmicro_idle_loop(theirs.with_suffix(".asm")), commands, cycles)
            rows.append(row)
    return rows


def _geomean(values: list[float]) -> float:
    return math.exp(sum(math.log(v) for v in values) / len(values))


def main() -> int:
    rows = measure()
    print(f"{'program':30} {'part':11} {'flash':>6} {'LDmicro':>8} {'ratio':>6}   {'cycles/scan':>11} "
          f"{'LDmicro':>8} {'ratio':>6}   {'worst':>6} {'LDmicro':>8}")
    flash_ratios, cycle_ratios, ok = [], [], True
    for row in rows:
        ratio = row["flash"] / row["ldmicro_flash"]
        flash_ratios.append(ratio)
        ok &= ratio <= 1
        line = f"{row['program']:30} {row['part']:11} {row['flash']:6} {row['ldmicro_flash']:8} {ratio:6.2f}"
        if "cycles" in row:
            (mean, worst), (their_mean, their_worst) = row["cycles"], row["ldmicro_cycles"]
            cycle_ratios.append(mean / their_mean)
            ok &= mean <= their_mean and worst <= their_worst
            line += f"   {mean:11.1f} {their_mean:8.1f} {mean / their_mean:6.2f}   {worst:6} {their_worst:8}"
        else:
            line += "   (no simavr core: scan not measured)"
        print(line)
    flash, cycles = _geomean(flash_ratios), _geomean(cycle_ratios)
    print(f"geometric mean: flash {flash:.2f} (target <= {FLASH_TARGET}), "
          f"cycles per scan {cycles:.2f} (target <= {CYCLES_TARGET}); "
          f"{'no program larger or slower' if ok else 'SOME PROGRAM IS LARGER OR SLOWER'}")
    return 0 if ok and flash <= FLASH_TARGET and cycles <= CYCLES_TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
