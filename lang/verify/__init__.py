"""`ladder verify`: properties (lang/properties.py) proved for every input
sequence, by bounded model checking and k-induction with an SMT solver over
the lowered program, the intermediate code the simulator and the back ends
run (docs/verify.md).

The solver, z3, is an optional dependency (`textladder[verify]`): it is
imported only when a proof is asked for, and its absence is one message.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..codes import code

if TYPE_CHECKING:
    from ..model import Program
    from ..properties import Property
    from .prover import Result

INSTALL = "pip install 'textladder[verify]'"
DEFAULT_BOUND = 50  # scans
DEFAULT_TIMEOUT_S = 60.0
NOT_MODELLED = code("LD620")


class SolverMissing(Exception):
    def __init__(self):
        super().__init__(f"the SMT solver z3 is not installed; install it with: {INSTALL}")


def verify(program: Program, properties: list[Property], bound: int = DEFAULT_BOUND,
           timeout_s: float = DEFAULT_TIMEOUT_S) -> list:
    """Each property's `prover.Result` (the properties read only names the
    simulator knows). SimulationError (with located diagnostics) for a
    program the simulator cannot run or the prover cannot model;
    SolverMissing without z3."""
    try:
        import z3  # noqa: F401  (only to know it is there)
    except ImportError:
        raise SolverMissing() from None
    from ..semantics import errors as lowering
    from ..semantics.lower import lower_program
    from ..sim import SimulationError, Simulator
    from ..sim.compile import LOWERING_CODES, SIMULATOR
    from ..sim.errors import located
    from .prover import prove
    from .transition import Machine, NotModelled

    Simulator(program)  # what cannot be simulated cannot be verified either: the same located errors
    try:
        code = lower_program(program, None, 1, SIMULATOR, trace=True)
    except lowering.LoweringError as problem:
        raise SimulationError([located(LOWERING_CODES[problem.kind], problem.message, problem.element)]) from None
    try:
        settings = program.settings
        return prove(Machine.of(code, settings.cycle_us, settings.baud), properties, settings.cycle_us, bound, timeout_s)
    except NotModelled as problem:
        raise SimulationError([located(NOT_MODELLED, str(problem), problem.element)]) from None


def verdict(result: Result, cycle_us: int) -> str:
    """What a result says, as `ladder verify` prints it before the property:
    `proved (k = 1)`, `fails at 60 ms (scan 7)`, `holds up to 50 scans (not proved)`..."""
    from ..sim.trace import format_time
    from .prover import FAILS, PROVED

    reach = result.prop.kind == "reachable"
    witness = result.witness
    if witness is not None:
        when = f"{format_time(witness.scan * cycle_us, cycle_us)} ms (scan {witness.scan + 1})"
        return f"proved: reached at {when}" if reach else f"fails at {when}"
    if result.verdict == PROVED:
        return f"proved (k = {result.k})"
    if result.verdict == FAILS:
        return f"fails: never reached, whatever the inputs (k = {result.k})"
    why = f"; {result.why}" if result.why else ""
    if reach:
        return f"not reached in {result.depth} scans (not proved){why}"
    return f"holds up to {result.depth} scans (not proved){why}"
