"""Programs of realistic shape at any size, for the scale and latency
benchmarks: each rung reads the relay the one before wrote, through a contact
and a timer, and every fourth rung has a parallel branch."""

from __future__ import annotations


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


def _header(part: str) -> list[str]:
    return ["LDmicro0.2", f"MICRO={part}", "CYCLE=10000 us at Timer1, YPlcCycleDuty:0", "CRYSTAL=16000000 Hz",
            "", "IO LIST", "    Xstart at 2 0 0", "END", "", "PROGRAM"]


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
