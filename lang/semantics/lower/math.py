"""Moves, arithmetic, bit operations, conversions, random numbers, tables,
the shift register and display decoders. Every result is truncated to its
destination's size; operands are read as the signed values they hold."""

from __future__ import annotations

from itertools import pairwise

from lang import numbers
from lang.codes import code
from lang.values import is_literal

from .. import ir
from ..errors import OPERAND, fail
from .builder import Builder, Holds, IsSet, lowers

SEED_MULTIPLIER = 69069


def _when(b: Builder, p: ir.Bit, *ops: ir.Op) -> None:
    with b.if_(IsSet(p)):
        for op in ops:
            b.emit(op)


def operand_width(b: Builder, token, default: int) -> int:
    token = str(token)
    return default if is_literal(token) else b.size(token)


@lowers("MOVE")
def move(b: Builder, el, p: ir.Bit) -> None:
    _when(b, p, ir.Move(b.dest(), b.operand(el.args["src"])))


@lowers("ADD", "SUB")
def add_sub(b: Builder, el, p: ir.Bit) -> None:
    # the flag costs code, so it is only computed when a contact reads it
    flag = b.bit("ROverflowFlagV") if b.overflow_read else None
    _when(b, p, ir.Arith(el.kind.lower(), b.dest(), b.operand(el.args["op1"]), b.operand(el.args["op2"]), flag))


@lowers("MUL", "AND", "OR", "XOR")
def binary(b: Builder, el, p: ir.Bit) -> None:
    _when(b, p, ir.Arith(el.kind.lower(), b.dest(), b.operand(el.args["op1"]), b.operand(el.args["op2"])))


@lowers("DIV", "MOD")
def divide(b: Builder, el, p: ir.Bit) -> None:
    _when(b, p, ir.Divide(el.kind.lower(), b.dest(), b.operand(el.args["op1"]), b.operand(el.args["op2"])))


@lowers("NEG", "NOT")
def unary(b: Builder, el, p: ir.Bit) -> None:
    _when(b, p, ir.Unary(el.kind.lower(), b.dest(), b.operand(el.args["op1"])))


@lowers("SHL", "SHR", "SR0", "ROL", "ROR")
def shift(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest()
    a, n = b.operand(el.args["op1"]), b.operand(el.args["op2"])
    width = operand_width(b, el.args["op1"], d.size)
    if isinstance(n, ir.Const) and not 0 <= n.value <= 8 * width:
        raise fail(OPERAND, f"shift count {n.value} out of range of '{el.args['op1']}': "
                                f"0 to {8 * width} inclusive", el, check=code("LD302"))
    _when(b, p, ir.Shift(el.kind.lower(), d, a, n, width))


@lowers("SET_BIT", "CLEAR_BIT")
def set_clear_bit(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest("var")
    _when(b, p, ir.ChangeBitOf(d, b.operand(el.args["bit"]), el.kind == "SET_BIT"))


@lowers("BIN2BCD", "BCD2BIN")
def bcd(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest()
    _when(b, p, ir.Convert(el.kind.lower(), d, b.operand(el.args["src"]), 4))


@lowers("SWAP", "OPPOSITE")
def reorder(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest()
    width = operand_width(b, el.args["src"], d.size)
    _when(b, p, ir.Convert(el.kind.lower(), d, b.operand(el.args["src"]), width))


def _seed(b: Builder, name: str) -> ir.Var:
    b.vars[f"$seed_{name}"] = 4
    return ir.Var(f"$seed_{name}", 4)


@lowers("RANDOM")
def random(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest("name")
    seed = _seed(b, d.name)
    # the seed's most significant bytes that fit the destination
    _when(b, p,
          ir.Arith("mul", seed, seed, ir.Const(SEED_MULTIPLIER)),
          ir.Arith("add", seed, seed, ir.Const(1)),
          ir.Shift("sr0", d, seed, ir.Const(32 - 8 * d.size), 4))


@lowers("SEED_RANDOM")
def seed_random(b: Builder, el, p: ir.Bit) -> None:
    _when(b, p, ir.Move(_seed(b, str(el.args["name"])), b.operand(el.args["seed"])))


@lowers("SHIFT_REGISTER")
def shift_register(b: Builder, el, p: ir.Bit) -> None:
    name, stages = el.args["name"], int(el.args["stages"])
    st = b.memory_bit("edge")
    with b.if_(IsSet(p)), b.if_(IsSet(st, False)):
        for i in range(stages - 2, -1, -1):
            b.emit(ir.Move(b.var(f"{name}{i + 1}"), b.var(f"{name}{i}")))
    b.emit(ir.CopyBit(st, p))


@lowers("LOOK_UP_TABLE")
def look_up_table(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest()
    values = tuple(b.literal(v) for v in el.args.get("values", ()))
    if not values:
        raise fail(OPERAND, "look-up table with no values", el, check=code("LD308"))
    _when(b, p, ir.Table(d, values, b.operand(el.args["index"])))


@lowers("PIECEWISE_LINEAR")
def piecewise_linear(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest()
    points = [(b.literal(x), b.literal(y)) for x, y in el.args.get("points", ())]
    if not points:
        raise fail(OPERAND, "piecewise linear table with zero elements", el, check=code("LD305"))
    if any(q[0] <= r[0] for r, q in pairwise(points)):
        raise fail(OPERAND, "x values in a piecewise linear table must be strictly increasing", el,
                   check=code("LD306"))
    token = el.args["index"]
    with b.if_(IsSet(p)):
        # segments from the last down, each one that holds the index
        # recomputing the result step by step in the destination's size: the
        # lowest matching segment wins (docs/semantics.md)
        for i in range(len(points) - 1, 0, -1):
            (x0, y0), (x1, y1) = points[i - 1], points[i]
            dx, dy = x1 - x0, y1 - y0
            if not -32768 < dx * dy < 32767:
                raise fail(OPERAND, "numerical problem with the piecewise linear table: make the "
                                        "entries smaller or the points closer", el, check=code("LD307"))
            with b.if_(Holds(b.operand(token), "<=", ir.Const(x1))):
                b.emit(ir.Arith("sub", d, b.operand(token), ir.Const(x0)))
                b.emit(ir.Arith("mul", d, d, ir.Const(dy)))
                b.emit(ir.Divide("div", d, d, ir.Const(dx)))
                b.emit(ir.Arith("add", d, d, ir.Const(y0)))


@lowers("7SEGMENTS", "9SEGMENTS", "14SEGMENTS", "16SEGMENTS")
def segments(b: Builder, el, p: ir.Bit) -> None:
    """The four decoders differ only in their font (LDmicro's intcode.cpp
    compiles them alike)."""
    d = b.dest()
    anode = str(el.args.get("common", "C")) != "C"
    font = tuple(~c if anode else c for c in numbers.SEGMENT_FONTS[el.kind.removesuffix("SEGMENTS")])
    src = str(el.args["src"])
    if is_literal(src):
        _when(b, p, ir.Move(d, ir.Const(font[numbers.seg7_index(b.literal(src))])))
        return
    s = b.var(src)
    index = b.temp_var(2)
    with b.if_(IsSet(p)):
        # LDmicro's code rewrites the source with the font index it used
        with b.if_(Holds(s, "==", ir.Const(numbers.DEGREE_CHAR))) as degree:
            b.emit(ir.Move(index, ir.Const(numbers.DEGREE_INDEX)))
            with degree.otherwise():
                b.emit(ir.Move(index, ir.Const(0x20)))
                with b.if_(Holds(s, ">=", ir.Const(0))):
                    with b.if_(Holds(s, "<", ir.Const(len(font)))):
                        b.emit(ir.Move(index, s))
        b.emit(ir.Move(s, index))
        b.emit(ir.Table(d, font, index))


@lowers("BUS")
def bus(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest()
    # as the simulator (and LDmicro's compiled code): source bit j goes to bit b<j>; a b<j> outside
    # the byte (0-7) sends its bit nowhere (docs/semantics.md)
    pairs = tuple((j, int(el.args[f"b{j}"])) for j in range(8) if 0 <= int(el.args[f"b{j}"]) <= 7)
    src = b.operand(el.args["src"])
    if isinstance(src, ir.Const):
        value = 0
        for source, dest in pairs:
            value |= ((src.value >> source) & 1) << dest
        _when(b, p, ir.Move(d, ir.Const(value)))
        return
    _when(b, p, ir.Permute(d, src, pairs))
