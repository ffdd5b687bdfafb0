"""Programs of realistic shape at any size, for the scale and latency
benchmarks: each rung reads the relay the one before wrote, through a contact
and a timer, and every fourth rung has a parallel branch; variants of it; and
the real LDmicro programs of the corpus, converted and repeated."""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path

from lang.iolist import BUS_PINS
from lang.loader import load_path
from lang.textform.details import NAME_KINDS
from lang.textform.writer import render_program

ROOT = Path(__file__).resolve().parents[1]
IDENTIFIER = re.compile(r"[A-Za-z_]\w*")


def chain_timers_parallels(rungs: int, part: str = "Atmel AVR ATmega2560 100-TQFP") -> str:
    """The program as a `.ld` file."""
    lines = _header(part)
    for i in range(rungs):
        source = "Xstart" if i == 0 else f"R{i - 1}"
        lines.append(f"RUNG {i + 1}")
        if i % 4 == 3:
            lines += ["  PARALLEL", f"    CONTACTS {source} 0 0", f"    CONTACTS R{max(i - 2, 0)} 1 0", "  END"]
        else:
            lines.append(f"  CONTACTS {source} 0 0")
        lines += [f"  TON T{i} 100000 0", f"  COIL R{i} 0 0 0 0", "END"]
    return "\n".join(lines) + "\n"


def _header(part: str, io_list: tuple[str, ...] = ("Xstart at 2 0 0",)) -> list[str]:
    return ["LDmicro0.2", f"MICRO={part}", "CYCLE=10000 us at Timer1, YPlcCycleDuty:0", "CRYSTAL=16000000 Hz",
            "", "IO LIST", *(f"    {line}" for line in io_list), "END", "", "PROGRAM"]


COMMENT_LINES = [
    "Conveyor section {n}: the relay of this stage follows the previous stage after its on delay, so",
    "that each motor starts only once the one before it runs. Keep the delays long enough for the belts",
    "to reach speed; a stage that trips drops every stage after it, and the line restarts from the first",
    "stage when the operator presses start again. See the wiring diagram, sheet {n}, for the terminals.",
]


def long_comments(rungs: int, every: int = 5, part: str = "Atmel AVR ATmega2560 100-TQFP") -> str:
    """The chain of `chain_timers_parallels` where every `every`-th rung is a
    four-line COMMENT of about 400 characters (`rungs` counts both kinds)."""
    lines = _header(part)
    relays = 0  # the chain's rungs so far
    for i in range(rungs):
        lines.append(f"RUNG {i + 1}")
        if i % every == 0:
            text = "\\r\\n".join(line.format(n=i // every + 1) for line in COMMENT_LINES)
            lines += [f"  COMMENT {text}", "END"]
            continue
        source = "Xstart" if relays == 0 else f"R{relays - 1}"
        if relays % 4 == 3:
            lines += ["  PARALLEL", f"    CONTACTS {source} 0 0", f"    CONTACTS R{relays - 2} 1 0", "  END"]
        else:
            lines.append(f"  CONTACTS {source} 0 0")
        lines += [f"  TON T{relays} 100000 0", f"  COIL R{relays} 0 0 0 0", "END"]
        relays += 1
    return "\n".join(lines) + "\n"


def wide_rungs(rungs: int, part: str = "Atmel AVR ATmega2560 100-TQFP") -> str:
    """Rungs about a dozen elements wide: contacts on the relays of the rungs
    before, two parallel branches (one of them with a series of two inside),
    two timers and a coil."""
    lines = _header(part)
    for i in range(rungs):
        r = ["Xstart" if back > i else f"R{i - back}" for back in range(13)]  # r[k]: the relay k rungs up
        lines += [f"RUNG {i + 1}", f"  CONTACTS {r[1]} 0 0", f"  CONTACTS {r[2]} 0 0",
                  "  PARALLEL", "    SERIES", f"      CONTACTS {r[3]} 0 0", f"      CONTACTS {r[4]} 1 0", "    END",
                  f"    CONTACTS {r[5]} 0 0", "  END",
                  f"  CONTACTS {r[6]} 1 0", f"  TON T{i} 100000 0", f"  CONTACTS {r[7]} 0 0",
                  "  PARALLEL", f"    CONTACTS {r[8]} 0 0", f"    CONTACTS {r[9]} 1 0", f"    CONTACTS {r[10]} 0 0",
                  "  END",
                  f"  CONTACTS {r[11]} 1 0", f"  TOF TF{i} 50000 0", f"  CONTACTS {r[12]} 0 0",
                  f"  COIL R{i} 0 0 0 0", "END"]
    return "\n".join(lines) + "\n"


def io_table(rungs: int) -> str:
    """A Modbus slave on an ATmega2560 whose I/O table has a row per rung:
    even rungs read an input (a contact on an X pin, 40 of them, or on a
    Modbus discrete input I) through a timer into a relay, odd rungs drive an
    output (a Y pin, 40, or a Modbus coil M) from it. The X and Y names take
    the part's I/O pins but for the UART's; the I and M names get Modbus
    addresses of slave 1 (SETTINGS)."""
    pins = _io_pins("atmega2560", "100-TQFP")
    pairs = rungs // 2
    inputs = [f"X{i}" if i < 40 else f"I{i}" for i in range(pairs)]
    outputs = [f"Y{i}" if i < 40 else f"M{i}" for i in range(pairs)]
    io_list = [f"{name} at {pins[i]} 0 0" if i < 40 else f"{name} at 0 1 {i}" for i, name in enumerate(inputs)]
    io_list += [f"{name} at {pins[40 + i]} 0 0" if i < 40 else f"{name} at 0 1 {i}" for i, name in enumerate(outputs)]
    lines = _header("Atmel AVR ATmega2560 100-TQFP", tuple(io_list))
    for i in range(pairs):
        lines += [f"RUNG {2 * i + 1}", f"  CONTACTS {inputs[i]} 0 0", f"  TON T{i} 100000 0", f"  COIL R{i} 0 0 0 0",
                  "END", f"RUNG {2 * i + 2}", f"  CONTACTS R{i} 0 0", f"  COIL {outputs[i]} 0 0 0 0", "END"]
    return "\n".join(lines) + "\n"


def _io_pins(part: str, package: str) -> list[int]:
    """The package pin numbers of the part's I/O pins, the UART's left out."""
    device = json.loads((ROOT / "lang" / "devices" / f"{part}.json").read_text())
    numbered = next(p["pins"] for p in device["packages"] if p["package"] == package)
    uart = set(device["uart"].values())
    return [int(number) for number, port in numbered.items() if port in device["io"] and port not in uart]


def corpus_root() -> Path:
    """The corpus of real LDmicro programs in the shared folder beside the
    checkout (or beside the folder of worktrees the checkout is in)."""
    return next((folder / "shared" / "corpus" for folder in ROOT.parents if (folder / "shared" / "corpus").is_dir()),
                ROOT.parent / "shared" / "corpus")


def dialect(path: Path) -> str:
    """The file version its first line names (LDmicro0.1 -> 0.1; a bare
    `LDmicro`, which some 5.x releases write, -> `bare`)."""
    first = path.read_bytes().split(b"\n", 1)[0].strip().decode("latin-1")
    return first.removeprefix("LDmicro") or "bare"


def converted(path: Path, rungs: int) -> str:
    """The `.ld` file converted to the text form, its rungs repeated up to
    `rungs` with every drawn name of the n-th copy ending in n (so DETAILS has
    a line per renamed timer, after the renamed rungs; a parameter the drawing
    does not show, as an SPI element's mode `Master`, is no name and stays as
    it is), but for the names the
    program gives a pin or a Modbus address: every copy reads and drives the
    same pins, as the original, instead of thousands of names without one
    (each an error). ValueError if the file does not read without problems."""
    program, problems = load_path(path)
    if problems:
        raise ValueError(f"{len(problems)} problem(s) reading it, the first: {problems[0].code} {problems[0].message}")
    if not program.rungs:
        raise ValueError("it has no rungs to repeat")
    kept = set(program.pins)
    original = program.rungs
    program.rungs = []
    for copy_number in range(-(-rungs // len(original))):
        for rung in copy.deepcopy(original):
            for element in rung.elements():
                for f in element.spec.fields:
                    value = element.args.get(f.name)
                    if (f.drawn and f.kind in NAME_KINDS and isinstance(value, str) and IDENTIFIER.fullmatch(value)
                            and not _pinned(value, kept)):
                        element.args[f.name] = f"{value}{copy_number}"
            program.rungs.append(rung)
    del program.rungs[rungs:]
    return render_program(program)


def _pinned(name: str, assigned: set[str]) -> bool:
    """Whether the name, or a pin of the bus it names, has an assignment."""
    return name in assigned or any(name + suffix in assigned for pins in BUS_PINS.values() for suffix, _ in pins)
