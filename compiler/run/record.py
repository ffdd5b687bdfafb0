"""A compiled program run under a stimulus, its values read after every scan:
the AVR image in simavr, the PIC16 image in gpsim, the C built on the host.
The tests compare such a recording with the simulator scan for scan, and
`ladder test --on avr|pic16|c` replays a scenario's checks on it
(`FirmwareSim`).

A stimulus is a list of `Event(scan, name, value)`: the simulator applies an
event before that scan. simavr drives the pin (or sets the A/D voltage) 0.05
cycle before the scan starts and sends a UART byte 0.75 cycle before (simavr
delivers a byte up to about 1.1 ms later at 9600 baud, its receiver ticking
once a byte time, so it must come after the scan before it has ended and in
time for its own); gpsim switches the input pin's pull-up module 0.05 cycle
before, and a usart module starts sending a UART byte 0.75 cycle before (a
frame of 10 bits at the program's baud rate must fit in that time). After
each scan, at 0.9 cycle when it is over, the MCU's data memory
is read through the build's symbol map; the C harness prints its variables.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from bisect import bisect_right
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from lang.model import Program
from lang.sim import Simulator
from lang.sim.scenario import RunStopped

from . import c as c_run
from . import simavr as sa
from .gpsim import DRIVE_OHMS, parse_log

ADC_REFERENCE_MV = 5000  # the AVR harness's AREF and AVCC
SAMPLE_AT, DRIVE_BEFORE, SEND_BEFORE = 0.9, 0.05, 0.75  # fractions of a cycle


@dataclass(frozen=True)
class Event:
    scan: int
    name: str  # an input, an A name (A/D reading), or "uart" (a received byte)
    value: int


@dataclass
class Recording:
    """The values of `names` after each scan, and the UART's output: all the
    bytes sent and how many had been sent after each scan."""

    names: list[str]
    rows: list[dict[str, int]]
    sent: bytes = b""
    sent_after: list[int] = field(default_factory=list)


class FirmwareError(RuntimeError):
    """The compiled program could not be run or read."""


# --- the C built on the host -----------------------------------------------------------------

def record_c(program: Program, events: list[Event], scans: int, names: list[str] | None = None,
             folder: Path | None = None, sanitize: bool = False) -> Recording:
    """Every name the C keeps (or `names`) after each scan."""
    import compiler

    sources = compiler.build_c(program, "program", "program.ladder")
    names = sorted(n for n in sources.symbols if n[0] != "#") if names is None else names
    built = c_run.build(sources, "program", names, program.settings.cycle_us, program.settings.baud, folder,
                        sanitize=sanitize)
    script = []
    for scan in range(scans):
        for event in events:
            if event.scan == scan:
                script.append(f"uart {event.value}" if event.name == "uart" else f"set {event.name} {event.value}")
        script += ["run 1", "show"]
    script.append("sent")
    lines = built.run(script)
    rows = [list(map(int, line.split()[1:])) for line in lines if line.startswith("@values")]
    sent = next((bytes(map(int, line.split()[1:])) for line in lines if line.startswith("@sent")), b"")
    return Recording(names, [dict(zip(names, row)) for row in rows], sent, [row[len(names)] for row in rows])


# --- the AVR image in simavr -----------------------------------------------------------------

def adc_millivolts(reading: int) -> int:
    """The voltage simavr converts to `reading` (it scales by 1023/AREF... 1024)."""
    return -(-reading * ADC_REFERENCE_MV // 1023)


def _pin_of(build, name: str) -> tuple[str, int]:
    pin = build.device.pin(build.program.pins[name].pin)
    return pin.port, pin.bit


def _adc_channel(build, name: str) -> int:
    device = build.device
    return device.adc[device.pin(build.program.pins[name].pin).name]


def spans(symbols: dict) -> list[tuple[int, int]]:
    """Few peek ranges covering every address."""
    addresses = sorted({s.address + i for s in symbols.values() for i in range(s.size)})
    found: list[list[int]] = []
    for address in addresses:
        if found and address - found[-1][1] <= 16:
            found[-1][1] = address
        else:
            found.append([address, address])
    return [(a, b - a + 1) for a, b in found] or [(0, 1)]


def symbol_value(symbol, data: dict[int, int]) -> int:
    if symbol.bit is not None:
        return data[symbol.address] >> symbol.bit & 1
    raw = bytes(data[symbol.address + i] for i in range(symbol.size))
    return int.from_bytes(raw, "little", signed=True)


def _drive(events: list[Event], cycle_ms: float, cycle_at, pin_of, adc_channel) -> list[tuple[int, int, str]]:
    """simavr commands that give the stimulus: (cycle, order, command)."""
    commands = []
    for event in events:
        lead = SEND_BEFORE if event.name == "uart" else DRIVE_BEFORE
        at = cycle_at(max(0.0, (event.scan - lead) * cycle_ms))
        if event.name == "uart":
            commands.append((at, 1, f"uart_in {event.value}"))
        elif event.name[0] == "X":
            port, bit = pin_of(event.name)
            commands.append((at, 1, f"drive {port} {bit} {event.value}"))
        else:
            commands.append((at, 1, f"adc {adc_channel(event.name)} {adc_millivolts(event.value)}"))
    return commands


def _script(commands: list[tuple[int, int, str]]) -> list[str]:
    script = []
    for at, _, command in sorted(commands, key=lambda c: (c[0], c[1])):
        if at:
            script.append(f"run_to {at}")
        script.append(command)
    return script


def record_avr(build, hex_path: Path, events: list[Event], scans: int, names: list[str],
               watch: Iterable[str] = ()) -> tuple[Recording, sa.AvrRun]:
    """Run the image under the stimulus; the values of `names` read from the
    data space after each scan (and the edges of the `watch` pins)."""
    settings = build.program.settings
    freq, cycle_ms = settings.crystal_hz, settings.cycle_us / 1000

    def cycle_at(ms: float) -> int:
        return round(ms * freq / 1000)

    commands = [(0, 0, "watch {} {}".format(*_pin_of(build, name))) for name in watch]
    uart = sa.uart_number(build.device)
    commands += [(0, 0, f"uart {uart}")] if uart else []
    commands += _drive(events, cycle_ms, cycle_at, lambda name: _pin_of(build, name),
                       lambda name: _adc_channel(build, name))
    symbols = {n: build.image.symbols[n] for n in names}
    ranges = spans(symbols)
    samples = [cycle_at((scan + SAMPLE_AT) * cycle_ms) for scan in range(scans)]
    for at in samples:
        commands += [(at, 2, f"peek {start} {length}") for start, length in ranges]
    run = sa.run_avr(hex_path, build.device.part, freq, _script(commands), timeout=300)
    memory: list[dict[int, int]] = []
    for line in run.raw.splitlines():
        if line.startswith("@peek"):
            fields = line.split()
            start = int(fields[1])
            if start == ranges[0][0]:
                memory.append({})
            memory[-1].update({start + i: int(b, 16) for i, b in enumerate(fields[2:])})
    rows = [{n: symbol_value(s, data) for n, s in symbols.items()} for data in memory]
    sent_after = [sum(1 for cycle, _ in run.uart if cycle <= at) for at in samples]
    return Recording(list(names), rows, run.uart_bytes(), sent_after), run


def record_pins(hex_path: Path, part: str, freq_hz: int, cycle_us: int, events: list[Event], scans: int,
                pins: dict[str, str], adc: dict[str, int] | None = None) -> Recording:
    """An AVR image whose memory has no symbol map (an Arduino sketch):
    its output pins' levels after each scan. `pins` maps the program's
    input and output names to port bits (`PD2`), `adc` its A/D names to
    channels."""
    cycle_ms = cycle_us / 1000

    def cycle_at(ms: float) -> int:
        return round(ms * freq_hz / 1000)

    def pin_of(name: str) -> tuple[str, int]:
        return pins[name][1], int(pins[name][2:])

    outputs = sorted(n for n in pins if n[0] == "Y")
    commands = [(0, 0, "watch {} {}".format(*pin_of(name))) for name in outputs]
    commands += _drive(events, cycle_ms, cycle_at, pin_of, (adc or {}).get)
    end = cycle_at((scans + SAMPLE_AT) * cycle_ms)
    run = sa.run_avr(hex_path, part, freq_hz, _script(commands + [(end, 3, "cycles")]), timeout=300)
    rows = [{name: run.level_at(pins[name], (scan + SAMPLE_AT) * cycle_ms) for name in outputs}
            for scan in range(scans)]
    return Recording(outputs, rows, run.uart_bytes(), [0] * scans)


# --- the PIC16 image in gpsim ----------------------------------------------------------------

END_MARK = "__textladder_end__"
UART_IN = "uart_in"  # the gpsim usart module that sends the scenario's bytes
_VALUE = re.compile(r"^\*?\*?(?:gpsim> )*\s*(\w+)\[[^\]]*\] = \$([0-9a-fA-F]+)")
_PC = re.compile(r"^\*?\*?(?:gpsim> )*\s*pc = 0x([0-9a-fA-F]+)")


class CycleOverrun(FirmwareError):
    """A scan had not ended by the time its values are read."""

    def __init__(self, scan: int, pc: int):
        super().__init__(f"scan {scan} still running at {SAMPLE_AT} cycle (PC {pc:#06x}): the scan is longer "
                         "than the cycle allows at this crystal")
        self.scan = scan


def pic_part(device):
    """The PIC16 or PIC18 back end's view of a PIC part."""
    from ..pic16.part import Part
    from ..pic18.part import Part as Pic18Part

    return (Pic18Part if device.family == "pic18" else Part).of(device)


def erase_eeprom(hex_path: Path, size: int, place: tuple[int, int] = (0x4200, 2)) -> None:
    """Add the data EEPROM as a new chip has it (every byte 0xFF) to the HEX:
    gpsim starts it at 0. `place`: its first byte address and the bytes each
    EEPROM byte takes (the back end's Part.eeprom_hex): a PIC16's EEPROM data
    lies at word 0x2100, a byte a word; a PIC18's at byte 0xF00000."""
    from intelhex import IntelHex

    start, stride = place
    image = IntelHex(str(hex_path))
    for i in range(size):
        image[start + stride * i] = 0xFF
        for pad in range(1, stride):
            image[start + stride * i + pad] = 0x00
    image.write_hex_file(str(hex_path))


def record_pic16(build, hex_path: Path, events: list[Event], scans: int, names: list[str],
                 timeout: float = 300) -> Recording:
    """Run the image in gpsim under the stimulus; the values of `names` after
    each scan, read from the file registers (with the PC: one outside the
    wait for the next cycle is a CycleOverrun). On a part with a UART every
    write to TXREG is a byte sent, at the cycle of the write (gpsim logs
    them; its usart module gives nothing out), and the bytes received come
    from a usart module on the RX pin, sent 0.75 cycle before their scan."""
    settings = build.program.settings
    device = build.device
    part = pic_part(device)
    # a PIC10F20x runs on its internal oscillator whatever the crystal setting says
    clock_hz = part.facts.get("clock_hz", settings.crystal_hz)
    per_ms = clock_hz / 4000
    cycle_ms = settings.cycle_us / 1000

    def at(ms: float) -> int:
        return max(1, round(ms * per_ms))

    timeline: list[tuple[int, int, int, str]] = []  # cycle, kind, order, command
    modules: dict[str, str] = {}
    receiving = device.uart.get("rx") if any(e.name == "uart" for e in events) else None
    for event in events:
        if event.name == "uart":
            if receiving:
                timeline.append((at(max(0.0, (event.scan - SEND_BEFORE) * cycle_ms)), 0, len(timeline),
                                 f"{UART_IN}.tx = {event.value}"))
            continue
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
    if part.gpsim is None:
        raise FirmwareError(f"gpsim has no model of the {part.title} (nor of a sibling with its pins): its image "
                            "cannot be run here")
    uart = part.feature("uart")
    lines = [f"processor {part.gpsim}", "load fw.hex", f"frequency {clock_hz}"]
    if modules:
        lines.append("module library libgpsim_modules")
        for pin_name, module in sorted(modules.items()):
            port = "gpio" if pin_name.startswith("GP") else f"port{pin_name[1].lower()}"
            lines += [f"module load pullup {module}", f"{module}.resistance = {DRIVE_OHMS}", f"node n_{module}",
                      f"attach n_{module} {module}.pin {port}{pin_name[-1]}"]
    if receiving:
        # the bytes come from a usart module's TX pin, at the program's baud rate, into the RX pin
        lines += (["module library libgpsim_modules"] if not modules else []) + [
            f"module load usart {UART_IN}", f"{UART_IN}.txbaud = {settings.baud}",
            f"{UART_IN}.rxbaud = {settings.baud}", f"node n_{UART_IN}",
            f"attach n_{UART_IN} {UART_IN}.TXPIN port{receiving[1].lower()}{receiving[-1]}"]
    if uart:
        lines += ["log on uart.log", "log w txreg"]
    last = 0
    for cycle, _, _, command in timeline:
        if cycle > last:
            lines += [f"break c {cycle}", "run"]
            last = cycle
        lines.append(command)
    lines += (["log off"] if uart else []) + [f"echo {END_MARK}", "quit"]
    with tempfile.TemporaryDirectory(prefix="textladder-pic-") as tmp:
        shutil.copyfile(hex_path, Path(tmp) / "fw.hex")
        (Path(tmp) / "script.stc").write_text("\n".join(lines) + "\n")
        with open(Path(tmp) / "out.txt", "wb") as out:
            subprocess.run(["gpsim", "-i", "-I", "script.stc"], stdin=subprocess.DEVNULL, stdout=out,
                           stderr=subprocess.STDOUT, timeout=timeout, cwd=tmp, check=False)
        text = (Path(tmp) / "out.txt").read_text(errors="replace")
        log = Path(tmp) / "uart.log"
        sent = [(cycle, value & 0xFF) for cycle, register, value in
                parse_log(log.read_text(errors="replace") if log.exists() else "") if register == "txreg"]
    if END_MARK not in text or "ERROR" in text:
        raise FirmwareError("gpsim did not run the script through:\n" + text[-3000:])
    values = [int(m.group(2), 16) for m in map(_VALUE.match, text.splitlines()) if m]
    if len(values) != scans * len(addresses):
        raise FirmwareError(f"gpsim printed {len(values)} register values, expected {scans * len(addresses)}")
    # gpsim gives a PIC18's PC in bytes, a PIC16's in words
    pcs = [int(m.group(1), 16) // part.pc_step for m in map(_PC.match, text.splitlines()) if m]
    if len(pcs) != scans:
        raise FirmwareError(f"gpsim printed {len(pcs)} PCs, expected {scans}")
    waiting = range(build.image.labels["wait"], build.image.labels["waited"])
    late = next((scan for scan, pc in enumerate(pcs) if pc not in waiting), None)
    if late is not None:
        raise CycleOverrun(late, pcs[late])
    rows = []
    for scan in range(scans):
        data = dict(zip(addresses, values[scan * len(addresses):(scan + 1) * len(addresses)]))
        rows.append({n: symbol_value(s, data) for n, s in symbols.items()})
    samples = [at((scan + SAMPLE_AT) * cycle_ms) for scan in range(scans)]
    cycles = [cycle for cycle, _ in sent]
    return Recording(list(names), rows, bytes(b for _, b in sent), [bisect_right(cycles, s) for s in samples])


# --- a scenario's checks on a recording ------------------------------------------------------------

class FirmwareSim(Simulator):
    """The simulator, run as usual, whose values are the firmware's: the
    scenario runner (lang.sim.scenario) reads a recording made under the
    same stimulus through it. Only the names the firmware holds are
    signals; the UART output is the firmware's. A scan past the recording
    raises `stop` (the reason the recording ends there), or says that the
    recording ended."""

    def __init__(self, program: Program, recording: Recording, stop: RunStopped | None = None):
        super().__init__(program)
        self.recording = recording
        self.stop = stop
        self._row = -1

    def step(self, n: int = 1) -> None:
        if self._row + n >= len(self.recording.rows):
            raise self.stop or RunStopped(f"the firmware's recording ends after {len(self.recording.rows)} scans")
        super().step(n)
        self._row += n

    def variables(self) -> dict[str, int]:
        return {n: v for n, v in super().variables().items() if n in self.recording.names}

    def value(self, name: str) -> int:
        if self._row < 0:
            return super().value(name)
        return self.recording.rows[self._row][name]

    def model_value(self, name: str) -> int:
        return super().value(name)

    def uart_output(self) -> bytes:
        if self._row < 0:
            return b""
        return self.recording.sent[:self.recording.sent_after[self._row]]
