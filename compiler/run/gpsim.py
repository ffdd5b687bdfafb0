"""Run a PIC16 or PIC18 Intel HEX image in gpsim (Debian package gpsim), headless, under a timed
stimulus: for the tests, the benchmarks and anyone checking a compiled image.

gpsim runs a generated command script (``gpsim -i -I script.stc < /dev/null``) always under
a timeout: a script error or a missing final ``quit`` leaves it at its prompt forever, and a
missing HEX still exits 0, so the output is scanned for error messages.

* Inputs: one ``pullup`` module (from ``libgpsim_modules``) per input pin, of 100 ohms,
  attached to the pin through a node; its voltage is switched between 0 and 5 V (or any
  analog voltage, for an ADC input) at exact instruction cycles (``break c N`` then ``run``).
* Outputs: ``log w portX`` / ``log w trisX`` record every write to the watched ports' latch
  and direction registers with the instruction cycle of the write, so every output edge is
  known to the cycle (an output pin's level is its latch bit while its TRIS bit is 0; a pin
  set as input counts as 0, as an undriven pin does). A PIC18 has its latch apart, LATX: a
  write to PORTX writes it, so ``log w latX`` sees every write; an enhanced mid-range PIC16 too,
  but gpsim logs a write to PORTX as that: both are logged there.
* UART: ``log w txreg`` records every transmitted byte with its cycle (gpsim's usart module
  captured nothing).

Times in the API are milliseconds; one instruction cycle is 4 / freq_hz seconds.
gpsim honours the configuration word in the HEX (LDmicro's is at byte address 0x400E; a PIC18's
configuration bytes are at 0x300000).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

END_MARK = "__textladder_gpsim_end__"
# The input modules' source resistance: a switch. At the module's default 10 kOhm
# against PORTB's weak pull-up a pin driven to 0 V sits between the input
# thresholds and keeps reading 1 once it has been high.
DRIVE_OHMS = 100

# Messages gpsim prints for script problems (it carries on at its prompt after them).
_ERROR_PATTERNS = re.compile(
    r"\*\*\*ERROR|syntax error|No such file|No cpu|Unable to find|cannot be set|"
    r"does not contain processor|need to specify processor|not found|unknown|"
    r"Unknown|invalid|Invalid|failed|Failed",
)
_TXREG_MISSING = "break cannot be set on 'txreg'"


class GpsimError(RuntimeError):
    """gpsim is missing, timed out, or reported an error in the script or the run."""


def available() -> bool:
    """True when the gpsim binary is installed."""
    return shutil.which("gpsim") is not None


def processor_name(name: str) -> str:
    """gpsim processor name: ``"PIC16F877"``, ``"p16f877"``, ``"pic18f4520"`` or LDmicro's
    ``"Microchip PIC16F876 28-PDIP or 28-SOIC"`` -> ``"p16f876"``."""
    m = re.search(r"(?:pic|p)?(1[0268][a-z]*\d+[a-z0-9]*)", name.lower())
    if not m:
        raise GpsimError(f"not a PIC name: {name!r}")
    return "p" + m.group(1)


GPIO = "io"  # the 8-pin parts' one port: GP0..GP5, registers GPIO and TRISIO


def parse_pin(pin: str) -> tuple[str, int]:
    """``"RB0"`` / ``"rb0"`` / ``"B0"`` -> ``("b", 0)``; ``"GP2"`` -> ``("io", 2)``."""
    m = re.fullmatch(r"R?([A-G])([0-7])|GP([0-5])", pin.strip().upper())
    if not m:
        raise ValueError(f"bad PIC pin name {pin!r} (want e.g. 'RB0' or 'GP2')")
    if m.group(3):
        return GPIO, int(m.group(3))
    return m.group(1).lower(), int(m.group(2))


def _pin_label(port: str, bit: int) -> str:
    return f"GP{bit}" if port == GPIO else f"R{port.upper()}{bit}"


def _baseline(processor: str) -> bool:
    return processor.startswith("p10")


def _registers(port: str, processor: str = "") -> tuple[str, ...]:
    """gpsim's names of a port's data and direction registers: the latch a
    PIC18's outputs are written in (LATB), else the port; on an enhanced
    mid-range PIC16 (p12f1840, p16f1825: four digits after the F) both, the
    latch our code writes and the port LDmicro's writes (which writes the
    latch too, but gpsim logs it as a write to the port). A baseline PIC10
    sets its directions with the TRIS instruction, which gpsim cannot log:
    its data register only."""
    if _baseline(processor):
        return ("gpio",)
    if port == GPIO:
        return "gpio", "trisio"
    if re.fullmatch(r"p1[26]l?f1\d{3}", processor):
        return f"lat{port}", f"port{port}", f"tris{port}"
    return (f"lat{port}" if processor.startswith("p18") else f"port{port}"), f"tris{port}"


def _port_of(register: str) -> tuple[str, str] | None:
    """(port, "data" or "tris") of a register gpsim logged, or None."""
    if register in ("gpio", "trisio"):
        return GPIO, "data" if register == "gpio" else "tris"
    if register[:-1] in ("port", "tris", "lat") and len(register) in (4, 5):
        return register[-1], "tris" if register.startswith("tris") else "data"
    return None


@dataclass
class PicRun:
    processor: str
    freq_hz: int
    end_cycle: int
    levels: dict[str, int] = field(default_factory=dict)            # level at cycle 0
    edge_cycles: list[tuple[int, str, int]] = field(default_factory=list)  # (cycle, "RC0", v)
    uart_cycles: list[tuple[int, int]] = field(default_factory=list)       # (cycle, byte)
    reads: list[tuple[float, str, int]] = field(default_factory=list)      # (ms, reg, value)
    writes: list[tuple[int, str, int]] = field(default_factory=list)       # every logged write
    output: str = ""
    script: str = ""

    def ms(self, cycle: int) -> float:
        return cycle * 4000.0 / self.freq_hz

    @property
    def edges(self) -> list[tuple[float, str, int]]:
        """[(time_ms, "RC0", level), ...] for every change of a watched pin."""
        return [(self.ms(c), p, v) for c, p, v in self.edge_cycles]

    def pin_edges(self, pin: str) -> list[tuple[float, int]]:
        label = _pin_label(*parse_pin(pin))
        return [(self.ms(c), v) for c, p, v in self.edge_cycles if p == label]

    def level_at(self, pin: str, time_ms: float) -> int:
        label = _pin_label(*parse_pin(pin))
        if label not in self.levels:
            raise KeyError(f"pin {label} was not watched")
        level = self.levels[label]
        for t, v in self.pin_edges(label):
            if t > time_ms:
                break
            level = v
        return level

    @property
    def uart(self) -> list[tuple[float, int]]:
        """[(time_ms, byte), ...] written to TXREG."""
        return [(self.ms(c), b) for c, b in self.uart_cycles]

    def uart_bytes(self) -> bytes:
        return bytes(b for _, b in self.uart_cycles)


_HEADER = re.compile(r"^0x([0-9A-Fa-f]+) ")
_WROTE = re.compile(r"^\s+Wrote: 0x([0-9A-Fa-f]+) to (\w+)\(")
_READ_VALUE = re.compile(r"(\w+) = (0x[0-9A-Fa-f]+|\d+)\s*$")


def parse_log(text: str) -> list[tuple[int, str, int]]:
    """(cycle, register, value) of every write a `log w` recorded."""
    writes: list[tuple[int, str, int]] = []
    cycle = 0
    for line in text.splitlines():
        m = _HEADER.match(line)
        if m:
            cycle = int(m.group(1), 16)
            continue
        m = _WROTE.match(line)
        if m:
            writes.append((cycle, m.group(2).lower(), int(m.group(1), 16)))
    return writes


@dataclass
class _Plan:
    """What a run drives, watches and reads, in instruction cycles."""

    end: int  # the cycle the run stops at
    modules: dict[tuple[str, int], str]  # (port, bit) -> its input module's name
    drives: list[tuple[int, int, str, float]]  # (cycle, order given, module, volts)
    reads: list[tuple[int, str]]  # (cycle, register)
    watched: list[tuple[str, int]]  # (port, bit)

    @property
    def ports(self) -> list[str]:
        return sorted({port for port, _ in self.watched})


def _plan(freq_hz: int, until_ms: float, inputs: Iterable[tuple[float, str, int]],
          analog: Iterable[tuple[float, str, float]], reads: Iterable[tuple[float, str]],
          watch: Iterable[str]) -> _Plan:
    per_ms = freq_hz / 4000.0  # instruction cycles per millisecond

    def at(ms: float) -> int:
        if ms < 0:
            raise ValueError("negative time")
        return round(ms * per_ms)

    end = at(until_ms)
    if end <= 0:
        raise ValueError("until_ms must be positive")
    plan = _Plan(end, {}, [], [(at(t), reg.lower()) for t, reg in reads], [parse_pin(p) for p in watch])
    # digital drives are the modules at 0 or 5 V; analog ones at any voltage
    voltages = [(t, pin, 5.0 if level else 0.0) for t, pin, level in inputs]
    voltages += [(t, pin, float(volts)) for t, pin, volts in analog]
    for seq, (t, pin, volts) in enumerate(voltages):
        port, bit = parse_pin(pin)
        module = plan.modules.setdefault((port, bit), f"in_r{port}{bit}")
        plan.drives.append((at(t), seq, module, volts))
    return plan


def _script(plan: _Plan, processor: str, hex_file: Path, freq_hz: int, log: Path,
            uart: bool | None) -> tuple[str, int, list[tuple[int, str]]]:
    """The command script, the number of cycle breaks it sets and the registers it prints
    (cycle, register) in order."""
    s: list[str] = [f"processor {processor}", f"load {hex_file}", f"frequency {int(freq_hz)}"]
    if plan.modules:
        s.append("module library libgpsim_modules")
        for (port, bit), mod in sorted(plan.modules.items()):
            s += [f"module load pullup {mod}", f"{mod}.resistance = {DRIVE_OHMS}", f"node n_{mod}",
                  f"attach n_{mod} {mod}.pin {_registers(port)[0]}{bit}"]
    s.append(f"log on {log}")
    for port in plan.ports:
        s += [f"log w {register}" for register in _registers(port, processor)]
    if uart is None or uart:
        s.append("log w txreg")
    timeline: dict[int, list[str]] = {}
    for cyc, _, mod, volts in sorted(plan.drives):
        if cyc <= plan.end:
            timeline.setdefault(cyc, []).append(f"{mod}.voltage = {volts:g}")
    for cyc, reg in plan.reads:
        timeline.setdefault(min(cyc, plan.end), []).append(f"__read__ {reg}")
    read_order: list[tuple[int, str]] = []
    breaks = 0
    for cyc in sorted(set(timeline) | {plan.end}):
        if cyc > 0:
            s += [f"break c {cyc}", "run"]
            breaks += 1
        for cmd in timeline.get(cyc, []):
            if cmd.startswith("__read__ "):
                reg = cmd.split()[1]
                read_order.append((cyc, reg))
                s.append(reg)
            else:
                s.append(cmd)
    s += ["log off", f"echo {END_MARK}", "quit"]
    return "\n".join(s) + "\n", breaks, read_order


def _gpsim(folder: Path, script: str, timeout: float) -> str:
    """gpsim's output for the script, run in the folder."""
    (folder / "script.stc").write_text(script)
    # output to a file: gpsim stuck at its prompt on an empty stdin prints prompts
    # endlessly until the timeout
    out_path = folder / "out.txt"
    try:
        with open(out_path, "wb") as out_f:
            subprocess.run(["gpsim", "-i", "-I", str(folder / "script.stc")],
                           stdin=subprocess.DEVNULL, stdout=out_f, stderr=subprocess.STDOUT,
                           timeout=timeout, cwd=folder)
    except subprocess.TimeoutExpired as e:
        with open(out_path, "rb") as f:
            f.seek(max(0, out_path.stat().st_size - 3000))
            tail = f.read().decode(errors="replace")
        raise GpsimError(f"gpsim timed out after {timeout} s (script error or endless "
                         f"run?)\n--- script ---\n{script}--- output tail ---\n{tail}") from e
    return out_path.read_text(errors="replace")


def _check_output(out: str, script: str, uart: bool | None, breaks: int, end: int) -> None:
    """GpsimError unless gpsim ran the whole script without complaint."""
    problems = [ln for ln in out.splitlines() if _ERROR_PATTERNS.search(ln)]
    if uart is None:
        problems = [ln for ln in problems if _TXREG_MISSING not in ln]
    if problems:
        raise GpsimError("gpsim reported: " + " | ".join(problems)
                         + f"\n--- script ---\n{script}")
    if END_MARK not in out:
        raise GpsimError(f"gpsim did not reach the end of the script\n{out[-2000:]}")
    hits = re.findall(r"cycle break: 0x[0-9A-Fa-f]+ = (\d+)", out)
    if len(hits) != breaks or (hits and int(hits[-1]) != end):
        raise GpsimError(f"gpsim stopped early: {len(hits)} of {breaks} cycle breaks reached"
                         f"\n{out[-2000:]}")


def _record_writes(run: PicRun, watched: list[tuple[str, int]], ports: list[str]) -> None:
    """The watched pins' edges and the UART's bytes, from the logged writes."""
    # pin levels from port latch and TRIS writes (reset: TRIS = 1s, latch 0); on a baseline PIC10,
    # whose TRIS gpsim cannot log, the watched pins are outputs from the start
    latch = {p: 0 for p in ports}
    tris = {p: 0 if _baseline(run.processor) else 0xFF for p in ports}
    pin_level = {(p, b): 0 for p, b in watched}
    for p, b in watched:
        run.levels[_pin_label(p, b)] = 0
    for cyc, reg, val in run.writes:
        if reg == "txreg":
            run.uart_cycles.append((cyc, val & 0xFF))
            continue
        found = _port_of(reg)
        if found is None or found[0] not in latch:
            continue
        p, kind = found
        (latch if kind == "data" else tris)[p] = val
        for (wp, wb), old in pin_level.items():
            if wp != p:
                continue
            new = 0 if (tris[p] >> wb) & 1 else (latch[p] >> wb) & 1
            if new != old:
                pin_level[(wp, wb)] = new
                run.edge_cycles.append((cyc, _pin_label(wp, wb), new))


def _record_reads(run: PicRun, read_order: list[tuple[int, str]]) -> None:
    """The registers the script printed: gpsim answers "portc = 0x3" in script order."""
    values = [m for m in (_READ_VALUE.search(ln) for ln in run.output.splitlines()) if m]
    vi = 0
    for cyc, reg in read_order:
        while vi < len(values) and values[vi].group(1).lower() != reg:
            vi += 1
        if vi == len(values):
            raise GpsimError(f"no value printed for register {reg}")
        run.reads.append((run.ms(cyc), reg, int(values[vi].group(2), 0)))
        vi += 1


def run_pic(hex_path: str | os.PathLike, processor: str, freq_hz: int,
            inputs: Iterable[tuple[float, str, int]] = (), watch: Iterable[str] = (),
            until_ms: float = 1000.0, analog: Iterable[tuple[float, str, float]] = (),
            uart: bool | None = None, reads: Iterable[tuple[float, str]] = (),
            timeout: float = 60) -> PicRun:
    """Run a PIC HEX file in gpsim.

    inputs: ``(time_ms, "RB0", 0|1)`` digital drives (0 V / 5 V through a pull-up module);
    analog: ``(time_ms, "RA1", volts)`` the same modules at any voltage, for ADC inputs;
    watch: output pins whose edges are recorded; reads: ``(time_ms, "portc")`` registers
    printed at that time (result in PicRun.reads); uart: record TXREG writes (None = if the
    part has a TXREG). A driven pin floats high (the module's 5 V) until its first change:
    give every input a level at time 0.
    """
    if not available():
        raise GpsimError("gpsim is not installed: install the Debian package gpsim")
    hex_path = Path(hex_path)
    if not hex_path.is_file():
        raise GpsimError(f"no HEX file {hex_path}")
    proc_name = processor_name(processor)
    plan = _plan(freq_hz, until_ms, inputs, analog, reads, watch)
    with tempfile.TemporaryDirectory(prefix="textladder-gpsim-") as tmp:
        folder = Path(tmp)
        fw = folder / "fw.hex"   # a plain path: gpsim's parser does not take quoted names
        shutil.copyfile(hex_path, fw)
        log = folder / "run.log"
        script, breaks, read_order = _script(plan, proc_name, fw, freq_hz, log, uart)
        out = _gpsim(folder, script, timeout)
        log_text = log.read_text(errors="replace") if log.exists() else ""
    _check_output(out, script, uart, breaks, plan.end)
    run = PicRun(processor=proc_name, freq_hz=int(freq_hz), end_cycle=plan.end, output=out,
                 script=script, writes=parse_log(log_text))
    _record_writes(run, plan.watched, plan.ports)
    _record_reads(run, read_order)
    return run
