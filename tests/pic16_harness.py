"""Running a compiled PIC16 program in gpsim beside the simulator, scan for scan.

The stimulus is the AVR harness's (test_compiler_harness.Event): the
simulator applies an event before its scan; gpsim switches the input pin's
pull-up module 0.05 cycle before the scan starts. After each scan, at 0.9
cycle, the script prints every file register the compared names live in
(`reg(0x20)`) and the PC, and the comparison takes every name both sides
have. A PC outside the wait loop there means the scan is longer than the
cycle allows (CycleOverrun): the values are a scan's half-done work, not a
result to compare.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from pathlib import Path

from test_compiler_harness import DRIVE_BEFORE, SAMPLE_AT, Event, compared_names, mismatches, simulate

import compiler
from compiler.pic16.part import Part
from compiler.run.gpsim import DRIVE_OHMS

END_MARK = "__textladder_end__"
_VALUE = re.compile(r"^\*?\*?(?:gpsim> )*\s*(\w+)\[[^\]]*\] = \$([0-9a-fA-F]+)")
_PC = re.compile(r"^\*?\*?(?:gpsim> )*\s*pc = 0x([0-9a-fA-F]+)")


class CycleOverrun(Exception):
    """A scan had not ended by the time its values are read."""

    def __init__(self, scan: int, pc: int):
        super().__init__(f"scan {scan} still running at {SAMPLE_AT} cycle (PC {pc:#06x}): the scan is longer "
                         "than the cycle allows at this crystal")
        self.scan = scan


def run_scans(build, hex_path: Path, events: list[Event], scans: int, names: list[str],
              timeout: float = 300) -> list[dict[str, int]]:
    settings = build.program.settings
    per_ms = settings.crystal_hz / 4000
    cycle_ms = settings.cycle_us / 1000
    device = build.device

    def at(ms: float) -> int:
        return max(1, round(ms * per_ms))

    timeline: list[tuple[int, int, int, str]] = []  # cycle, kind, order, command
    modules: dict[str, str] = {}
    for event in events:
        pin = device.pin(build.program.pins[event.name].pin)
        module = modules.setdefault(pin.name, f"in_{pin.name.lower()}")
        # an input's level, or an A/D reading as the voltage that converts to it (VDD = 5 V reference)
        volts = (5 if event.value else 0) if event.name[0] == "X" else round((event.value + 0.5) * 5 / 1024, 4)
        timeline.append((at(max(0.0, (event.scan - DRIVE_BEFORE) * cycle_ms)), 0, len(timeline),
                         f"{module}.voltage = {volts}"))
    symbols = {n: build.image.symbols[n] for n in names}
    addresses = sorted({s.address + i for s in symbols.values() for i in range(s.size)})
    for scan in range(scans):
        cycle = at((scan + SAMPLE_AT) * cycle_ms)
        timeline += [(cycle, 1, i, f"reg({address:#x})") for i, address in enumerate(addresses)]
        timeline.append((cycle, 1, len(addresses), "pc"))
    timeline.sort()
    lines = [f"processor {Part.of(device).gpsim}", "load fw.hex", f"frequency {settings.crystal_hz}"]
    if modules:
        lines.append("module library libgpsim_modules")
        for pin_name, module in sorted(modules.items()):
            port = "gpio" if pin_name.startswith("GP") else f"port{pin_name[1].lower()}"
            lines += [f"module load pullup {module}", f"{module}.resistance = {DRIVE_OHMS}", f"node n_{module}",
                      f"attach n_{module} {module}.pin {port}{pin_name[-1]}"]
    last = 0
    for cycle, _, _, command in timeline:
        if cycle > last:
            lines += [f"break c {cycle}", "run"]
            last = cycle
        lines.append(command)
    lines += [f"echo {END_MARK}", "quit"]
    with tempfile.TemporaryDirectory(prefix="textladder-pic-") as tmp:
        shutil.copyfile(hex_path, Path(tmp) / "fw.hex")
        (Path(tmp) / "script.stc").write_text("\n".join(lines) + "\n")
        with open(Path(tmp) / "out.txt", "wb") as out:
            subprocess.run(["gpsim", "-i", "-I", "script.stc"], stdin=subprocess.DEVNULL, stdout=out,
                           stderr=subprocess.STDOUT, timeout=timeout, cwd=tmp, check=False)
        text = (Path(tmp) / "out.txt").read_text(errors="replace")
    if END_MARK not in text or "ERROR" in text:
        raise RuntimeError("gpsim did not run the script through:\n" + text[-3000:])
    values = [int(m.group(2), 16) for m in map(_VALUE.match, text.splitlines()) if m]
    if len(values) != scans * len(addresses):
        raise RuntimeError(f"gpsim printed {len(values)} register values, expected {scans * len(addresses)}")
    pcs = [int(m.group(1), 16) for m in map(_PC.match, text.splitlines()) if m]
    waiting = range(build.image.labels["wait"], build.image.labels["waited"])
    late = next((scan for scan, pc in enumerate(pcs) if pc not in waiting), None)
    if len(pcs) != scans:
        raise RuntimeError(f"gpsim printed {len(pcs)} PCs, expected {scans}")
    if late is not None:
        raise CycleOverrun(late, pcs[late])
    samples = []
    for scan in range(scans):
        data = dict(zip(addresses, values[scan * len(addresses):(scan + 1) * len(addresses)]))
        samples.append({n: _value(s, data) for n, s in symbols.items()})
    return samples


def erase_eeprom(hex_path: Path, size: int) -> None:
    """Add the data EEPROM as a new chip has it (every byte 0xFF) to the HEX:
    gpsim starts it at 0. EEPROM data lies at word 0x2100, a byte a word."""
    from intelhex import IntelHex

    image = IntelHex(str(hex_path))
    for i in range(size):
        image[0x4200 + 2 * i] = 0xFF
        image[0x4200 + 2 * i + 1] = 0x00
    image.write_hex_file(str(hex_path))


def _value(symbol, data: dict[int, int]) -> int:
    if symbol.bit is not None:
        return data[symbol.address] >> symbol.bit & 1
    raw = bytes(data[symbol.address + i] for i in range(symbol.size))
    return int.from_bytes(raw, "little", signed=True)


def differential(program, events: list[Event], scans: int, tmp_path: Path, target: str | None = None) -> list[str]:
    """Mismatches between the simulator and the compiled PIC image, as text.
    Inputs the stimulus does not set at scan 0 are driven low from the start,
    as the simulator has them (a PIC pin with a pull-up would read high)."""
    given = {e.name for e in events if e.scan == 0}
    events = [Event(0, n, 0) for n in sorted(program.pins) if n[0] == "X" and n not in given] + list(events)
    build = compiler.build(program, target)
    hex_path = tmp_path / "program.hex"
    build.write(hex_path)
    erase_eeprom(hex_path, Part.of(build.device).eeprom)
    program = build.program
    names = compared_names(program, build)
    expected = simulate(program, events, scans, names)
    actual = run_scans(build, hex_path, events, scans, names)
    return mismatches(expected, actual, names)
