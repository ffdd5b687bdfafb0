"""Programs of realistic shape at any size, for the scale and latency
benchmarks: each rung reads the relay the one before wrote, through a contact
and a timer, and every fourth rung has a parallel branch."""

from __future__ import annotations


def chain_timers_parallels(rungs: int, part: str = "Atmel AVR ATmega2560 100-TQFP") -> str:
    """The program as a `.ld` file."""
    lines = ["LDmicro0.2", f"MICRO={part}", "CYCLE=10000 us at Timer1, YPlcCycleDuty:0", "CRYSTAL=16000000 Hz",
             "", "IO LIST", "    Xstart at 2 0 0", "END", "", "PROGRAM"]
    for i in range(rungs):
        source = "Xstart" if i == 0 else f"R{i - 1}"
        lines.append(f"RUNG {i + 1}")
        if i % 4 == 3:
            lines += ["  PARALLEL", f"    CONTACTS {source} 0 0", f"    CONTACTS R{max(i - 2, 0)} 1 0", "  END"]
        else:
            lines.append(f"  CONTACTS {source} 0 0")
        lines += [f"  TON T{i} 100000 0", f"  COIL R{i} 0 0 0 0", "END"]
    return "\n".join(lines) + "\n"
