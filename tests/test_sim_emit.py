"""The simulator's back end (lang/sim/emit.py) writes two shapes of the
intermediate code shorter than op by op; the short code must do what the ops
do, also when the test reads the bit it sets."""

from __future__ import annotations

import pytest

from lang.model import Program
from lang.semantics import ir
from lang.sim.codegen import Gen
from lang.sim.emit import emit_ops

P, X = ir.Bit("Rp"), ir.Bit("Xa")


def run(ops: list[ir.Op], **start: bool) -> dict[str, bool]:
    """The values after the code emit_ops writes for `ops`."""
    gen = Gen(Program())
    gen.new_rung(0, False)
    emit_ops(gen, ops)
    names = {slot.key: f"v{i}" for i, slot in enumerate(gen.slots)}
    source = [f"{local} = {start.get(key, False)}" for key, local in names.items()] + gen.lines
    scope: dict = {}
    exec("\n".join(source), {}, scope)
    return {key: scope[local] for key, local in names.items()}


def set_then_test(cond: ir.Condition) -> list[ir.Op]:
    return [ir.SetBit(P, False), ir.If(cond, [ir.SetBit(P, True)], None, "a", "b")]


@pytest.mark.parametrize("cond", [ir.IsSet(X), ir.IsSet(X, False), ir.IsSet(P), ir.IsSet(P, False)],
                         ids=["x", "not x", "p", "not p"])
@pytest.mark.parametrize("p", [False, True])
@pytest.mark.parametrize("x", [False, True])
def test_a_bit_cleared_then_set_by_a_test(cond, p, x):
    expected = (x == cond.value) if cond.bit == X else not cond.value
    assert run(set_then_test(cond), Rp=p, Xa=x)["Rp"] == expected


@pytest.mark.parametrize("test_bit", [X, P], ids=["x", "p"])
@pytest.mark.parametrize("p", [False, True])
@pytest.mark.parametrize("x", [False, True])
def test_power_cleared_by_a_test(test_bit, p, x):
    ops = [ir.If(ir.IsSet(P), [ir.If(ir.IsSet(test_bit), [ir.SetBit(P, False)], None, "c", "d")], None, "a", "b")]
    held = x if test_bit == X else p
    assert run(ops, Rp=p, Xa=x)["Rp"] == (p and not held)


V = ir.Var("Tacc", 2)


def run_int(ops: list[ir.Op], value: int) -> int:
    gen = Gen(Program())
    gen.new_rung(0, False)
    emit_ops(gen, ops)
    local = gen.var(V)
    scope: dict = {}
    exec("\n".join([f"{local} = {value}", *gen.lines]), {}, scope)
    return scope[local]


@pytest.mark.parametrize("limit, value, result", [(100, 5, 6), (32767, 32766, 32767), (32768, 32767, -32768)])
def test_a_count_below_a_limit_adds_one_without_truncation_only_where_it_cannot_overflow(limit, value, result):
    """`if v < limit: v += 1` is written without wrapping when the limit fits
    the variable; a limit past its largest value keeps the wrap."""
    ops = [ir.If(ir.Holds(V, "<", ir.Const(limit)), [ir.Arith("add", V, V, ir.Const(1))], None, "a", "b")]
    assert run_int(ops, value) == result
