"""The PIC16 integer patterns operation by operation, in gpsim beside the
simulator: every combination of destination and operand widths (1 to 4
bytes) with the edge values of each width (0, ±1, the extremes and their
neighbours, carries and borrows between bytes) and random ones.

Each program loads its operands every scan from look-up tables indexed by a
scan counter (a1..a4 and b1..b4, one per width) and computes one result per
width combination into a variable (or relay) of its own; pic16_harness
compares them all after every scan, so scan k checks the k-th operand pair.
The results fill several RAM banks. A 100 ms cycle at 20 MHz leaves room
for 64 32-bit divisions in one scan.
"""

from __future__ import annotations

import random
from itertools import product

import pytest
from builders import coil, contact, el, program
from pic16_harness import differential
from test_compiler_harness import IN_CI

from compiler.run import gpsim

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")

WIDTHS = (1, 2, 3, 4)
SCANS = 24
MCU = "Microchip PIC16F877 40-PDIP"
# literal operands: one and two bytes of every kind, all of whose bytes carry
CONSTANTS = ("1", "-1", "255", "-300", "32767", "16909060")


def edges(width: int) -> list[int]:
    top = 1 << (8 * width - 1)
    return [0, 1, -1, top - 1, -top, top - 2, -top + 1, 0xFF, -0x100, (0x55555555 >> (32 - 8 * width))]


def values(width: int, seed: int, nonzero: bool = False) -> list[int]:
    """SCANS values of a width: its edges, then random ones, shuffled."""
    rng = random.Random(seed)
    top = 1 << (8 * width - 1)
    found = edges(width) + [rng.randrange(-top, top) for _ in range(SCANS - len(edges(width)))]
    found = [v for v in found if -top <= v < top and not (nonzero and v == 0)]
    while len(found) < SCANS:
        found.append(rng.randrange(1, top))
    rng.shuffle(found)
    return found


def operand_rungs(nonzero_b: bool = False, small_b: range | None = None) -> tuple[list, dict[str, int]]:
    """Rungs loading a1..a4 and b1..b4 from tables at index vi, and vi += 1 at
    the end (the caller appends it); half the scans b equals a where it fits."""
    rungs, sizes = [], {"vi": 2}
    for width in WIDTHS:
        a = values(width, 10 + width)
        if small_b is not None:
            b = [random.Random(20 + width).choice(small_b) for _ in range(SCANS)]
        else:
            b = values(width, 20 + width, nonzero_b)
            b = [a[scan] if scan % 2 == 0 and (a[scan] or not nonzero_b) else v for scan, v in enumerate(b)]
        for name, table in ((f"a{width}", a), (f"b{width}", b)):
            rungs.append([el("LOOK_UP_TABLE", dest=name, index="vi", values=tuple(map(str, table)))])
            sizes[name] = width
    return rungs, sizes


def run(rungs: list, sizes: dict[str, int], tmp_path) -> list[str]:
    counted = rungs + [[el("ADD", dest="vi", op1="vi", op2="1")]]
    built = program(*counted, mcu=MCU, crystal_hz=20_000_000, cycle_us=100_000, sizes=sizes)
    return differential(built, [], SCANS, tmp_path)


BINARY = ("ADD", "SUB", "MUL", "DIV", "MOD", "AND", "OR", "XOR")


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("kind", BINARY)
def test_binary_operations_of_variables(kind, tmp_path):
    rungs, sizes = operand_rungs(nonzero_b=kind in ("DIV", "MOD"))
    for n, x, y in product(WIDTHS, WIDTHS, WIDTHS):
        rungs.append([el(kind, dest=f"d{n}{x}{y}", op1=f"a{x}", op2=f"b{y}")])
        sizes[f"d{n}{x}{y}"] = n
    assert run(rungs, sizes, tmp_path) == []


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("kind", BINARY)
def test_binary_operations_with_a_literal(kind, tmp_path):
    """The variable first; the literal first too for the operations that do not
    commute (a destination of the variable's width: RAM is short)."""
    rungs, sizes = operand_rungs(nonzero_b=True)
    for n, x, (k, literal) in product(WIDTHS, WIDTHS, enumerate(CONSTANTS)):
        rungs.append([el(kind, dest=f"d{n}{x}{k}", op1=f"a{x}", op2=literal)])
        sizes[f"d{n}{x}{k}"] = n
    if kind in ("SUB", "DIV", "MOD"):
        for x, (k, literal) in product(WIDTHS, enumerate(CONSTANTS)):
            rungs.append([el(kind, dest=f"e{x}{k}", op1=literal, op2=f"b{x}")])
            sizes[f"e{x}{k}"] = x
    assert run(rungs, sizes, tmp_path) == []


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("kind", ("ADD", "SUB"))
def test_the_overflow_flag(kind, tmp_path):
    """Cleared before each operation, copied to a relay of its own after it."""
    rungs, sizes = operand_rungs()
    for n, x, y in product(WIDTHS, WIDTHS, WIDTHS):
        rungs += [[coil("ROverflowFlagV", "R")], [el(kind, dest=f"d{n}{x}{y}", op1=f"a{x}", op2=f"b{y}")],
                  [contact("ROverflowFlagV"), coil(f"Rv{n}{x}{y}")]]
        sizes[f"d{n}{x}{y}"] = n
    assert run(rungs, sizes, tmp_path) == []


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("literal", (False, True))
def test_comparisons(literal, tmp_path):
    rungs, sizes = operand_rungs()
    seconds = [(f"{k}", c) for k, c in enumerate(CONSTANTS)] if literal else [(f"{y}", f"b{y}") for y in WIDTHS]
    for kind, x, (tag, b) in product(("EQU", "NEQ", "GRT", "GEQ", "LES", "LEQ"), WIDTHS, seconds):
        rungs.append([el(kind, op1=f"a{x}", op2=b), coil(f"R{kind}{x}{tag}")])
    assert run(rungs, sizes, tmp_path) == []


@needs_gpsim
@pytest.mark.slow
def test_negation_and_complement(tmp_path):
    rungs, sizes = operand_rungs()
    for kind, n, x in product(("NEG", "NOT"), WIDTHS, WIDTHS):
        rungs.append([el(kind, dest=f"{kind}{n}{x}", op1=f"a{x}")])
        sizes[f"{kind}{n}{x}"] = n
    assert run(rungs, sizes, tmp_path) == []


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("kind", ("SHL", "SHR", "SR0", "ROL", "ROR"))
def test_shifts_by_a_variable_and_by_literals(kind, tmp_path):
    rungs, sizes = operand_rungs(small_b=range(-2, 35))
    for n, x in product(WIDTHS, WIDTHS):
        rungs.append([el(kind, dest=f"d{n}{x}", op1=f"a{x}", op2=f"b{x}")])
        sizes[f"d{n}{x}"] = n
    for x in WIDTHS:
        for count in sorted({0, 1, 3, 7, 8, 9, 8 * x - 1, 8 * x} - {9} if x == 1 else {0, 1, 3, 7, 8, 9, 8 * x - 1, 8 * x}):
            rungs.append([el(kind, dest=f"k{x}{count}", op1=f"a{x}", op2=str(count))])
            sizes[f"k{x}{count}"] = x
    assert run(rungs, sizes, tmp_path) == []


@needs_gpsim
@pytest.mark.slow
def test_bit_numbers(tmp_path):
    """SET_BIT and CLEAR_BIT of a variable bit number on a copy of a (so the
    results do not pile up), IF_BIT_SET and IF_BIT_CLEAR to relays."""
    rungs, sizes = operand_rungs(small_b=range(-2, 35))
    for x in WIDTHS:
        for kind in ("SET_BIT", "CLEAR_BIT"):
            rungs += [[el("MOVE", dest=f"{kind}{x}", src=f"a{x}")], [el(kind, var=f"{kind}{x}", bit=f"b{x}")]]
            sizes[f"{kind}{x}"] = x
        for kind in ("IF_BIT_SET", "IF_BIT_CLEAR"):
            rungs.append([el(kind, var=f"a{x}", bit=f"b{x}"), coil(f"R{kind}{x}")])
            for bit in (0, 7, 8, 8 * x - 1, 8 * x + 3):
                rungs.append([el(kind, var=f"a{x}", bit=str(bit)), coil(f"R{kind}{x}k{bit}")])
    assert run(rungs, sizes, tmp_path) == []


@needs_gpsim
@pytest.mark.slow
def test_conversions(tmp_path):
    """SWAP and OPPOSITE of every width; BIN2BCD of 0..9999 and BCD2BIN of
    unpacked digits (the simulator refuses anything else)."""
    rungs, sizes = operand_rungs()
    rng = random.Random(5)
    decimal = [0, 1, 9, 10, 99, 100, 999, 1000, 9999] + [rng.randrange(10000) for _ in range(SCANS - 9)]
    digits = [sum(rng.randrange(10) << 8 * i for i in range(2)) for _ in range(SCANS)]
    rungs += [[el("LOOK_UP_TABLE", dest="dec", index="vi", values=tuple(map(str, decimal)))],
              [el("LOOK_UP_TABLE", dest="bcd", index="vi", values=tuple(map(str, digits)))]]
    sizes.update(dec=2, bcd=2)
    for n, x in product(WIDTHS, WIDTHS):
        for kind in ("SWAP", "OPPOSITE"):
            rungs.append([el(kind, dest=f"{kind}{n}{x}", src=f"a{x}")])
            sizes[f"{kind}{n}{x}"] = n
    for n in WIDTHS:
        rungs += [[el("BIN2BCD", dest=f"BIN2BCD{n}", src="dec")], [el("BCD2BIN", dest=f"BCD2BIN{n}", src="bcd")]]
        sizes.update({f"BIN2BCD{n}": n, f"BCD2BIN{n}": n})
    assert run(rungs, sizes, tmp_path) == []
