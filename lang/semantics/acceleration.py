"""STEPPER's acceleration table, as LDmicro 5.4's accel.cpp (CalcSteps and
makeAccelTable) computes it in floating point: the scans between step pulses
while the motor speeds up along one of six curves, which the compiled code
reads forwards to accelerate and backwards to decelerate.

Only what the compiled code uses is kept: the table (`dtMul` of steps 1 to
n), its length n, the shift that undoes the table's scaling when the period
is a variable, and the bytes an entry needs. The float arithmetic is
LDmicro's, operation for operation, so that every rounding lands where its
does (tests/test_stepper_ldmicro.py compares the tables with LDmicro's C).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from lang.numbers import byte_needed

# graph -> (the k of the curve for a table of n_size steps, the time of a
# distance s on it), for the curves that compute t from s (LDmicro's sFt = 0)
Curve = tuple[Callable[[int], float], Callable[[float, float], float]]
_CURVES: dict[int, Curve] = {
    1: (lambda n: 1.0 / (2.0 * n), lambda k, s: math.sqrt(2.0 * s / k)),  # v = k*t
    2: (lambda n: math.pow(1.0 / math.pow(3.0 * n / 2.0, 2.0 / 3.0), 3.0 / 4.0),
        lambda k, s: math.pow(3.0 * s / (2.0 * k), 2.0 / 3.0)),  # v = k*sqrt(t)
    3: (lambda n: math.pow(1.0 / math.pow(4.0 * n / 3.0, 3.0 / 4.0), 4.0 / 9.0),
        lambda k, s: math.pow(4.0 * s / (3.0 * k), 3.0 / 4.0)),  # v = k*t^(1/3)
    4: (lambda n: math.pow(1.0 / math.pow(3.0 * n, 1.0 / 3.0), 6.0),
        lambda k, s: math.pow(3.0 * s / k, 1.0 / 3.0)),  # v = k*t^2
    5: (lambda n: 0.5 / math.pow(1.0 * (n * 6) / 2.0, 2.0),
        lambda k, s: math.pow(3.0 * s / k, 1.0 / 3.0)),  # S-curve, s = i
}
# graph 6, the S-curve with t = i, steps one scan apart: its dt are all 1
GRAPHS = range(1, 7)
# S-curves mirror their first half (LDmicro's nN = 2)
_SYMMETRIC = (5, 6)


@dataclass(frozen=True)
class Steps:
    table: tuple[int, ...]  # scans before each step while accelerating (LDmicro's Tdata)
    shift: int  # with a variable period: the table is scaled by 2**shift (LDmicro's shrt)
    element_size: int  # bytes an entry needs (LDmicro's sovElement)


def c_round(x: float) -> int:
    """C's round(): halves away from zero."""
    return int(math.floor(abs(x) + 0.5)) * (1 if x >= 0 else -1)


def steps(n_size: int, graph: int, period: int) -> Steps:
    """The table of a STEPPER with `n_size` acceleration steps on curve
    `graph` (1..6) and a literal `period` (scans a step at full speed), or
    `period` 0 when the period is a variable: then the table is the curve's
    scaled so its longest step fits 7 bits, and `shift` undoes the scaling
    after the compiled code multiplies by the variable."""
    dt = [0.0] * (n_size + 2)
    t_prev = 0.0
    for i in range(1, n_size + 1):
        if graph == 6:
            t = float(i)
        else:
            k, time_of = _CURVES[graph]
            t = time_of(k(n_size), float(i))
        dt[i] = t - t_prev
        t_prev = t
    if graph in _SYMMETRIC:
        j = n_size // 2
        for i in range(1 + n_size // 2, n_size + 1):
            dt[i] = dt[j]
            j -= 1
    dt[n_size + 1] = 1.0  # the first step at full speed
    mult, shift = 1, 0
    if period < 1:
        period = 1
        dt_max = max(dt[1:n_size + 2])
        # the largest power of two (up to 32) that keeps the longest step below 128
        if dt_max <= 127:
            for bound, s in ((64, 0), (32, 1), (16, 2), (8, 3), (4, 4), (2, 5)):
                if dt_max > bound - 1:
                    mult, shift = 1 << s, s
                    break
    dt_mul = [0] + [c_round(dt[i] * mult * period) for i in range(1, n_size + 1)]
    dt_mul.append(c_round(dt[n_size + 1]) * mult * period)
    n = 0
    for i in range(n_size, 0, -1):
        if dt_mul[i] != dt_mul[n_size]:
            break
        n = i + 1
    return Steps(tuple(dt_mul[1:n + 1]), shift, byte_needed(max([0, *dt_mul[1:n_size + 1]])))
