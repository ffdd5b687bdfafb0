"""Run an AVR Intel HEX image in simavr (through libsimavr): for the tests, the
benchmarks and anyone checking a compiled image.

The simulator is a small C program, ``avr_harness.c`` in this package, linked against
libsimavr. It is compiled on first use (once per source version) into the user's cache
folder (``$XDG_CACHE_HOME/textladder``, else ``~/.cache/textladder``), or a temporary
folder when that is not writable, and driven through a line script on stdin; see the
comment at the top of ``avr_harness.c`` for the command language. It needs gcc and
simavr's headers and library (Debian: gcc, libsimavr-dev).

Two levels of API:

* :func:`run_avr` runs a raw command list and returns an :class:`AvrRun` (edges in cycles);
* :func:`simulate_avr` takes timed input changes ``[(time_ms, "D2", 0), ...]``, the output
  pins to watch, ADC voltages and UART bytes, and returns the same :class:`AvrRun`, whose
  :meth:`AvrRun.edges_ms` gives the edges in milliseconds.

Pins are named by port letter and bit: ``"B5"`` (``"PB5"`` is accepted too).
"""

from __future__ import annotations

import ctypes.util
import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

SOURCE_NAME = "avr_harness.c"
SIMAVR_INCLUDE = Path("/usr/include/simavr")
DEBIAN_PACKAGES = "gcc and libsimavr-dev"

#: AVRs that LDmicro targets but simavr has no core for (not upstream either).
NO_CORE = {"atmega162", "atmega64", "at90usb647"}


class HarnessError(RuntimeError):
    """The harness could not be built, or a run failed (bad script, crash, timeout)."""


class UnsupportedMcu(HarnessError):
    """simavr has no core for this MCU."""


# --------------------------------------------------------------------------- build


def _compile_flags() -> tuple[list[str], list[str]]:
    """(cflags, libs) from pkg-config when it knows simavr, else the Debian defaults."""
    if shutil.which("pkg-config"):
        try:
            cflags = subprocess.run(["pkg-config", "--cflags", "simavr"], capture_output=True,
                                    text=True, check=True, timeout=20).stdout.split()
            libs = subprocess.run(["pkg-config", "--libs", "simavr"], capture_output=True,
                                  text=True, check=True, timeout=20).stdout.split()
            return cflags, libs
        except (subprocess.SubprocessError, OSError):
            pass
    # libsimavr.so already records its libelf dependency: no -lelf needed (and libelf-dev,
    # which provides the -lelf link name, is usually not installed).
    return [f"-I{SIMAVR_INCLUDE}"], ["-lsimavr"]


_built: Path | None = None
_build_error: str | None = None


def cache_dirs() -> Iterable[Path]:
    """Where the compiled harness is kept: the user's cache, else a temporary folder."""
    cache = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    yield Path(cache) / "textladder"
    yield Path(tempfile.gettempdir()) / f"textladder-{os.getuid()}"


def missing() -> str | None:
    """What is missing to build the harness, naming the Debian packages, or None."""
    if shutil.which("gcc") is None and shutil.which("cc") is None:
        return f"no C compiler: the simavr harness needs {DEBIAN_PACKAGES} (Debian packages)"
    if not (SIMAVR_INCLUDE / "sim_avr.h").exists() or ctypes.util.find_library("simavr") is None:
        return (f"simavr's headers or library are not installed in {SIMAVR_INCLUDE}: install the Debian "
                "package libsimavr-dev (it brings libsimavr)")
    return None


def build_harness() -> Path:
    """Compile avr_harness.c (once per source version) and return the executable's path."""
    global _built, _build_error
    if _built is not None and _built.exists():
        return _built
    if _build_error is not None:
        raise HarnessError(_build_error)
    problem = missing()
    if problem is not None:
        _build_error = problem
        raise HarnessError(_build_error)
    source = resources.files(__package__).joinpath(SOURCE_NAME).read_bytes()
    digest = hashlib.sha256(source).hexdigest()[:12]
    gcc = shutil.which("gcc") or shutil.which("cc")
    assert gcc is not None  # missing() said there is one
    cflags, libs = _compile_flags()
    last_err = ""
    for d in cache_dirs():
        exe = d / f"avr_harness-{digest}"
        if exe.exists() and os.access(exe, os.X_OK):
            _built = exe
            return exe
        try:
            d.mkdir(parents=True, exist_ok=True)
            if not os.access(d, os.W_OK):
                raise OSError(f"{d} is not writable")
            # parallel test workers may build at the same time: private names, then an atomic rename
            tmp_source = d / f".avr_harness-{digest}-{os.getpid()}.c"
            tmp = d / f".avr_harness-{digest}-{os.getpid()}"
            tmp_source.write_bytes(source)
            try:
                proc = subprocess.run(
                    [gcc, "-O2", "-Wall", *cflags, str(tmp_source), "-o", str(tmp), *libs],
                    capture_output=True, text=True, timeout=120)
            finally:
                tmp_source.unlink()
        except (OSError, subprocess.SubprocessError) as e:
            last_err = str(e)
            continue
        if proc.returncode != 0:
            _build_error = f"building avr_harness failed:\n{proc.stderr}"
            raise HarnessError(_build_error)
        os.replace(tmp, exe)
        _built = exe
        return exe
    _build_error = f"no writable folder to build avr_harness in: {last_err}"
    raise HarnessError(_build_error)


def available() -> bool:
    """True when the harness's ingredients are installed: a C compiler, simavr's headers and
    libsimavr (Debian: gcc, libsimavr-dev). Building is not attempted here, so that a harness
    that fails to build makes the tests fail instead of skipping them."""
    return missing() is None


# --------------------------------------------------------------------------- names


def core_name(mcu: str) -> str:
    """simavr core name for an MCU name: ``"ATmega128"``, ``"atmega328p"`` or LDmicro's
    ``"Atmel AVR ATmega128 64-TQFP"`` all work. Raises UnsupportedMcu for parts without a
    simavr core (ATmega162, ATmega64, AT90USB647)."""
    m = re.search(r"(atmega|attiny|at90usb)\s*(\d+[a-z0-9]*)", mcu.lower())
    if not m:
        raise UnsupportedMcu(f"not an AVR name: {mcu!r}")
    name = m.group(1) + m.group(2)
    if name in NO_CORE:
        raise UnsupportedMcu(f"simavr has no core for {name} (none upstream either); "
                             "check it statically or run a sibling build")
    return name


def uart_number(device) -> str | None:
    """The USART a compiled image uses, for the harness's `uart` command: "1"
    on the ATmega64/128, 32U4 and AT90USB647, else "0"; None without one."""
    uart = device.data["avr"].get("uart")
    if uart is None:
        return None
    return "1" if uart["UDR"].endswith("1") else "0"


def parse_pin(pin: str) -> tuple[str, int]:
    """``"B5"`` / ``"PB5"`` / ``"pb5"`` -> ``("B", 5)``."""
    m = re.fullmatch(r"P?([A-L])([0-7])", pin.strip().upper())
    if not m:
        raise ValueError(f"bad AVR pin name {pin!r} (want e.g. 'B5' or 'PB5')")
    return m.group(1), int(m.group(2))


# --------------------------------------------------------------------------- results


@dataclass
class AvrRun:
    """What one harness run printed, parsed. Times are CPU cycles unless named *_ms."""

    freq_hz: int
    edges: list[tuple[int, str, int]] = field(default_factory=list)    # (cycle, "B5", level)
    levels: dict[str, int] = field(default_factory=dict)                 # level when watched
    uart: list[tuple[int, int]] = field(default_factory=list)            # (cycle, byte)
    ports: list[tuple[str, int, int, int]] = field(default_factory=list)  # (P, PORT, DDR, PIN)
    eeprom: list[bytes] = field(default_factory=list)
    cycles: list[int] = field(default_factory=list)                      # 'cycles' answers
    resets: list[int] = field(default_factory=list)
    final_cycle: int = 0
    state: str | None = None          # "crashed" / "done" if the core stopped
    raw: str = ""
    stderr: str = ""

    def ms(self, cycle: int) -> float:
        return cycle * 1000.0 / self.freq_hz

    def edges_ms(self) -> list[tuple[float, str, int]]:
        return [(self.ms(c), p, v) for c, p, v in self.edges]

    def pin_edges_ms(self, pin: str) -> list[tuple[float, int]]:
        """Edges of one pin: [(time_ms, level), ...]."""
        port, bit = parse_pin(pin)
        name = f"{port}{bit}"
        return [(self.ms(c), v) for c, p, v in self.edges if p == name]

    def level_at(self, pin: str, time_ms: float) -> int:
        """Level of a watched pin at a time (from its initial level and edges)."""
        port, bit = parse_pin(pin)
        name = f"{port}{bit}"
        if name not in self.levels:
            raise KeyError(f"pin {name} was not watched")
        level = self.levels[name]
        for t, v in self.pin_edges_ms(name):
            if t > time_ms:
                break
            level = v
        return level

    def uart_bytes(self) -> bytes:
        return bytes(b for _, b in self.uart)

    def uart_ms(self) -> list[tuple[float, int]]:
        return [(self.ms(c), b) for c, b in self.uart]

    def port(self, letter: str) -> tuple[int, int, int]:
        """(PORT, DDR, PIN) of the last 'read' of that port."""
        for p, port, ddr, pin in reversed(self.ports):
            if p == letter.upper():
                return port, ddr, pin
        raise KeyError(f"port {letter} was not read")


def _parse(out: str, freq_hz: int) -> tuple[AvrRun, list[str]]:
    run = AvrRun(freq_hz=freq_hz, raw=out)
    errors: list[str] = []
    for line in out.splitlines():
        if not line.startswith("@"):
            continue
        f = line[1:].split()
        if not f:
            continue
        kind = f[0]
        if kind == "edge":
            run.edges.append((int(f[1]), f[2], int(f[3])))
        elif kind == "level":
            run.levels[f[2]] = int(f[3])
        elif kind == "uart":
            run.uart.append((int(f[1]), int(f[2])))
        elif kind == "port":
            run.ports.append((f[1], int(f[2], 16), int(f[3], 16), int(f[4], 16)))
        elif kind == "eeprom":
            run.eeprom.append(bytes(int(x, 16) for x in f[1:]))
        elif kind == "cycles":
            run.cycles.append(int(f[1]))
        elif kind == "reset":
            run.resets.append(int(f[1]))
        elif kind == "state":
            run.final_cycle = int(f[1])
            run.state = f[2]
        elif kind == "bye":
            run.final_cycle = int(f[1])
        elif kind == "error":
            errors.append(" ".join(f[1:]))
    return run, errors


# --------------------------------------------------------------------------- running


def run_avr(hex_path: str | os.PathLike, mcu: str, freq_hz: int, commands: Sequence[str],
            timeout: float = 60, allow_crash: bool = False) -> AvrRun:
    """Run the harness on a HEX file with a list of commands (see avr_harness.c).

    Raises HarnessError on any ``@error`` line, a non-zero exit, a timeout, or a crashed core
    (unless allow_crash)."""
    hex_path = Path(hex_path)
    if not hex_path.is_file():
        raise HarnessError(f"no HEX file {hex_path}")
    core = core_name(mcu)
    exe = build_harness()
    script = "\n".join(list(commands) + ["quit"]) + "\n"
    try:
        proc = subprocess.run([str(exe), core, str(int(freq_hz)), str(hex_path)], input=script,
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        raise HarnessError(f"avr_harness timed out after {timeout} s") from e
    run, errors = _parse(proc.stdout, int(freq_hz))
    run.stderr = proc.stderr
    if any(e.startswith("unknown mcu") for e in errors):
        raise UnsupportedMcu(f"simavr has no core {core!r}")
    if errors:
        raise HarnessError("avr_harness: " + "; ".join(errors))
    if proc.returncode != 0:
        raise HarnessError(f"avr_harness exited with {proc.returncode}: {proc.stderr.strip()}")
    if "@bye" not in proc.stdout:
        raise HarnessError("avr_harness stopped before the end of the script")
    if run.state and not allow_crash:
        raise HarnessError(f"the AVR core stopped ({run.state}) at cycle {run.final_cycle}")
    return run


def stimulus_commands(freq_hz: int, until_ms: float,
                      inputs: Iterable[tuple[float, str, int]] = (),
                      watch: Iterable[str] = (),
                      adc: Iterable[tuple[float, int, int]] = (),
                      uart_in: Iterable[tuple[float, int]] = (),
                      reads_ms: Iterable[float] = ()) -> list[str]:
    """Commands for a timed stimulus.

    inputs: ``(time_ms, "D2", level)`` pin drives; adc: ``(time_ms, channel, millivolts)``;
    uart_in: ``(time_ms, byte)``; reads_ms: times at which the registers of every port with
    a watched or driven pin are read (result: AvrRun.ports). Events at the same time apply
    in the order given, before the simulation advances past that time. Watches start at
    time 0."""
    events: list[tuple[int, int, str]] = []  # (cycle, seq, command)
    seq = 0

    def at(ms: float) -> int:
        if ms < 0:
            raise ValueError("negative time")
        return round(ms * freq_hz / 1000.0)

    ports: set[str] = set()
    for pin in watch:
        port, bit = parse_pin(pin)
        ports.add(port)
        events.append((0, seq, f"watch {port} {bit}"))
        seq += 1
    for t, pin, level in inputs:
        port, bit = parse_pin(pin)
        ports.add(port)
        events.append((at(t), seq, f"drive {port} {bit} {1 if level else 0}"))
        seq += 1
    for t, ch, mv in adc:
        events.append((at(t), seq, f"adc {int(ch)} {int(mv)}"))
        seq += 1
    for t, byte in uart_in:
        events.append((at(t), seq, f"uart_in {int(byte) & 0xFF}"))
        seq += 1
    for t in reads_ms:
        for port in sorted(ports):
            events.append((at(t), seq, f"read {port}"))
            seq += 1
    end = at(until_ms)
    events.sort()
    cmds: list[str] = []
    for cycle, _, cmd in events:
        if cycle > end:
            break
        if cycle > 0:
            cmds.append(f"run_to {cycle}")
        cmds.append(cmd)
    cmds.append(f"run_to {end}")
    cmds.append("cycles")
    return cmds


def simulate_avr(hex_path: str | os.PathLike, mcu: str, freq_hz: int, until_ms: float,
                 inputs: Iterable[tuple[float, str, int]] = (), watch: Iterable[str] = (),
                 adc: Iterable[tuple[float, int, int]] = (),
                 uart_in: Iterable[tuple[float, int]] = (), reads_ms: Iterable[float] = (),
                 timeout: float = 60) -> AvrRun:
    """Run a HEX file under a timed stimulus; the result's edges_ms() / pin_edges_ms() give
    the watched pins' edges in milliseconds, uart_ms() the transmitted bytes.

    Undriven AVR inputs read 1 when the firmware turns its pull-ups on: drive every input
    explicitly from time 0."""
    cmds = stimulus_commands(freq_hz, until_ms, inputs, watch, adc, uart_in, reads_ms)
    return run_avr(hex_path, mcu, freq_hz, cmds, timeout=timeout)
