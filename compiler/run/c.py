"""Run the C of a ladder program on the host: the generated files, a
`ladder.h`, and a generated harness (`harness.c`) that provides the runtime's
functions over plain variables, built with the host's C compiler and driven
by a line script on stdin.

The harness models what the simulator models, so that the two can be compared
scan for scan: scan k runs at k x the cycle time; the UART transmitter is busy
for 10 bit times per byte at the program's baud rate (a byte written while it
is busy is lost; polling it while busy lets time pass, as an MCU's busy-wait
does); received bytes queue; the EEPROM starts erased (0xFF) and is never busy.

Commands, one per line (a name is a program name the harness knows):

    set NAME VALUE   an input X (0/1), an A/D reading A (0..1023), or a variable or relay
    uart BYTE        a byte arrives at the UART
    run N            N scans
    show             one line: `@values`, each watched name's value in order, and the
                     number of bytes the UART has sent
    sent             one line: `@sent` and the bytes transmitted so far

It needs a C compiler (Debian: gcc); `sanitize` builds it with
`-fsanitize=undefined,address` and makes any finding fail the run.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from ..c import CSources, default_ladder_h

DEBIAN_PACKAGES = "gcc"
CFLAGS = ("-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O1")
SANITIZE = ("-fsanitize=undefined,address", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer")


class CRunError(RuntimeError):
    """The harness did not build, or a run failed (a sanitizer finding, a crash, a timeout)."""


def compiler() -> str | None:
    return shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")


def available() -> bool:
    return compiler() is not None


def harness_source(sources: CSources, stem: str, watch: list[str], cycle_us: int, baud: int) -> str:
    inputs = [(n, c) for n, (kind, c) in sources.symbols.items() if kind == "input"]
    outputs = [(n, c) for n, (kind, c) in sources.symbols.items() if kind == "output"]
    hooks = set(sources.hooks)
    out = ["#include <stdio.h>", "#include <stdlib.h>", "#include <string.h>", "#include <stdint.h>",
           '#include "ladder.h"', f'#include "{stem}.h"', "",
           "static double now_us, busy_until_us;",
           f"static const double byte_us = 10e6 / {baud};",
           "static unsigned char rx[4096], tx[65536];",
           "static unsigned rx_head, rx_tail, tx_count;",
           "static unsigned char eeprom[65536];", ""]
    for _, c in inputs:
        out.append(f"static BOOLEAN_t in_{c}; BOOLEAN_t Read_{c}(void) {{ return in_{c}; }}")
    for _, c in outputs:
        # LDmicro's C also calls Write0_/Write1_ of an output (a set or reset coil)
        out.append(f"static BOOLEAN_t out_{c}; BOOLEAN_t Read_{c}(void) {{ return out_{c}; }} "
                   f"void Write_{c}(BOOLEAN_t v) {{ out_{c} = v ? 1 : 0; }} "
                   f"void Write0_{c}(void) {{ out_{c} = 0; }} void Write1_{c}(void) {{ out_{c} = 1; }}")
    adcs = sorted(h.split()[1].removesuffix("(void)") for h in hooks if h.startswith("SWORD Read_Ub_A"))
    for hook in adcs:
        out.append(f"static SWORD adc_{hook[5:]}; SWORD {hook}(void) {{ return adc_{hook[5:]}; }}")
    for hook in sorted(h.split()[1].split("(")[0] for h in hooks if h.startswith("void Write_Ub_P")):
        out.append(f"static SWORD duty_{hook[6:]}; void {hook}(SWORD duty) {{ duty_{hook[6:]} = duty; }}")
    out += [
        "BOOLEAN_t UART_Transmit_Ready(void)",
        "{",
        "    if (now_us >= busy_until_us) return 1;",
        "    now_us += 0.25; /* a busy-wait lets time pass */",
        "    return 0;",
        "}",
        "void UART_Transmit(unsigned char b)",
        "{",
        "    if (now_us < busy_until_us) return;",
        "    if (tx_count < sizeof tx) tx[tx_count++] = b;",
        "    busy_until_us = now_us + byte_us;",
        "}",
        "BOOLEAN_t UART_Receive_Avail(void) { return rx_head != rx_tail; }",
        "unsigned char UART_Receive(void)",
        "{",
        "    unsigned char b = rx[rx_tail % sizeof rx];",
        "    if (rx_head != rx_tail) rx_tail++;",
        "    return b;",
        "}",
        "unsigned char EEPROM_read(int address) { return eeprom[(unsigned)address & 0xFFFFu]; }",
        "void EEPROM_write(int address, unsigned char b) { eeprom[(unsigned)address & 0xFFFFu] = b; }",
        "BOOLEAN_t EEPROM_busy(void) { return 0; }",
        "void delay_us(SDWORD us) { (void)us; }",
        "",
        "static void show(void)",
        "{",
        '    printf("@values");',
    ]
    for name in watch:
        kind, c = sources.symbols[name]
        value = {"input": f"in_{c}", "output": f"out_{c}"}.get(kind, c)
        out.append(f'    printf(" %ld", (long){value});')
    out += ['    printf(" %u\\n", tx_count);', "}", "",
            "int main(void)",
            "{",
            "    char line[256], name[128];",
            "    long value, scan = 0, n;",
            "    memset(eeprom, 0xFF, sizeof eeprom);",
            "    setupPlc();",
            "    while (fgets(line, sizeof line, stdin)) {",
            '        if (sscanf(line, "set %127s %ld", name, &value) == 2) {']
    branches = [f'strcmp(name, "{n}") == 0) in_{c} = value ? 1 : 0;' for n, c in inputs]
    branches += [f'strcmp(name, "{h[8:]}") == 0) adc_{h[5:]} = (SWORD)value;' for h in adcs]
    adc_names = {h[8:] for h in adcs}
    branches += [f'strcmp(name, "{n}") == 0) {c} = ({"BOOLEAN_t" if kind == "bit" else "SDWORD"})value;'
                 for n, (kind, c) in sources.symbols.items() if kind in ("bit", "int") and n not in adc_names]
    for i, branch in enumerate(branches):
        out.append(f"            {'else ' if i else ''}if ({branch}")
    out += ["        } else if (sscanf(line, \"uart %ld\", &value) == 1) {",
            "            rx[rx_head++ % sizeof rx] = (unsigned char)value;",
            "        } else if (sscanf(line, \"run %ld\", &n) == 1) {",
            "            while (n-- > 0) {",
            f"                now_us = (double)scan * {cycle_us};",
            "                PlcCycle();",
            "                scan++;",
            "            }",
            "        } else if (strncmp(line, \"show\", 4) == 0) {",
            "            show();",
            "        } else if (strncmp(line, \"sent\", 4) == 0) {",
            "            unsigned i;",
            '            printf("@sent");',
            '            for (i = 0; i < tx_count; i++) printf(" %u", tx[i]);',
            '            printf("\\n");',
            "        }",
            "        fflush(stdout);",
            "    }",
            "    return 0;",
            "}", ""]
    return "\n".join(out)


@dataclass
class CProgram:
    """A built harness: its executable and what `show` prints."""

    executable: Path
    watch: list[str]

    def run(self, script: list[str], timeout: float = 60) -> list[str]:
        """The lines the harness prints for `script`."""
        try:
            done = subprocess.run([str(self.executable)], input="\n".join(script) + "\n", capture_output=True,
                                  text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise CRunError(f"the program did not finish within {timeout:g} s (a LOCK or a runaway loop?)") from None
        if done.returncode != 0:
            raise CRunError(f"the program stopped with status {done.returncode}: {done.stderr.strip()[-2000:]}")
        return done.stdout.splitlines()

    def start(self) -> subprocess.Popen:
        """The harness as a process to talk to line by line."""
        return subprocess.Popen([str(self.executable)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True, bufsize=1)


def build(sources: CSources, stem: str, watch: list[str], cycle_us: int, baud: int, folder: Path | None = None,
          sanitize: bool = False, flags: tuple[str, ...] = CFLAGS, write_program: bool = True) -> CProgram:
    """Write the program's C, a default ladder.h and the harness into `folder`
    (a new temporary one by default) and compile them; without
    `write_program` the folder already holds the program's FILE.c and FILE.h
    (LDmicro's, say) and its ladder.h, compiled with `flags`."""
    cc = compiler()
    if cc is None:
        raise CRunError(f"no C compiler found (install the Debian package {DEBIAN_PACKAGES}, or set CC)")
    folder = Path(folder or tempfile.mkdtemp(prefix="ladder-c-"))
    folder.mkdir(parents=True, exist_ok=True)
    if write_program:
        (folder / f"{stem}.c").write_text(sources.c)
        (folder / f"{stem}.h").write_text(sources.h)
        (folder / "ladder.h").write_text(default_ladder_h())
    (folder / "harness.c").write_text(harness_source(sources, stem, watch, cycle_us, baud))
    executable = folder / "program"
    common = [*(SANITIZE if sanitize else ()), "-DEXTERN_EVERYTHING", "-I", str(folder)]
    for command in ([cc, *flags, *common, "-c", "-o", str(folder / "program.o"), str(folder / f"{stem}.c")],
                    [cc, *CFLAGS, *common, "-c", "-o", str(folder / "harness.o"), str(folder / "harness.c")],
                    [cc, *common, "-o", str(executable), str(folder / "program.o"), str(folder / "harness.o")]):
        done = subprocess.run(command, capture_output=True, text=True, timeout=300)
        if done.returncode != 0:
            raise CRunError(f"{' '.join(command)} failed:\n{done.stderr.strip()[-4000:]}")
    return CProgram(executable, watch)
