"""Moves, arithmetic, bit operations, conversions, random numbers, tables,
the shift register and display decoders. Every result is truncated to its
destination's size; operands are read as the signed values they hold."""

from __future__ import annotations

from .. import numbers
from ..values import is_literal
from .codegen import CannotSimulate, Gen, handles
from .errors import BAD_OPERAND, BAD_VALUE, DIVIDE_BY_ZERO, TABLE_INDEX
from .gen_logic import bit_mask_expr

SEED_MASK = 0xFFFFFFFF


@handles("MOVE")
def move(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    gen.emit(f"if {p}: {d} = {gen.wrap(gen.operand(el.args['src']), name)}")


@handles("ADD", "SUB")
def add_sub(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    a, b = gen.operand(el.args["op1"]), gen.operand(el.args["op2"])
    flag = gen.bit("ROverflowFlagV")
    r = gen.temp("r")
    with gen.block(f"if {p}:"):
        gen.emit(f"{r} = {a} {'+' if el.kind == 'ADD' else '-'} {b}")
        gen.emit(f"{d} = {gen.wrap(r, name)}")
        # signed overflow of the destination's size; LDmicro never clears the flag
        gen.emit(f"if {d} != {r}: {flag} = True")


@handles("MUL", "AND", "OR", "XOR")
def binary(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    a, b = gen.operand(el.args["op1"]), gen.operand(el.args["op2"])
    op = {"MUL": "*", "AND": "&", "OR": "|", "XOR": "^"}[el.kind]
    gen.emit(f"if {p}: {d} = {gen.wrap(f'{a} {op} {b}', name)}")


@handles("DIV", "MOD")
def divide(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    a, b = gen.operand(el.args["op1"]), gen.operand(el.args["op2"])
    fn = "cdiv" if el.kind == "DIV" else "cmod"
    gen.namespace[fn] = getattr(numbers, fn)
    with gen.block(f"if {p}:"):
        sign = "/" if el.kind == "DIV" else "%"
        what = f"{el.kind} {el.args['dest']} := {el.args['op1']} {sign} {el.args['op2']}"
        gen.emit(f"if {b} == 0: " + gen.fault(DIVIDE_BY_ZERO, repr(f"division by zero: {what} with "
                                                                  f"{el.args['op2']} = 0")))
        gen.emit(f"{d} = {gen.wrap(f'{fn}({a}, {b})', name)}")


@handles("NEG", "NOT")
def unary(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    a = gen.operand(el.args["op1"])
    gen.emit(f"if {p}: {d} = {gen.wrap(('-' if el.kind == 'NEG' else '~') + f'({a})', name)}")


@handles("SHL", "SHR", "SR0", "ROL", "ROR")
def shift(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    a, n = gen.operand(el.args["op1"]), gen.operand(el.args["op2"])
    width = gen.operand_size(el.args["op1"], gen.size(name))
    if is_literal(str(el.args["op2"])) and not 0 <= int(n) <= 8 * width:
        raise CannotSimulate(BAD_OPERAND, f"shift count {n} out of range of '{el.args['op1']}': "
                                        f"0 to {8 * width} inclusive")
    gen.namespace["shift"] = numbers.shift
    gen.emit(f"if {p}: {d} = {gen.wrap(f'shift({el.kind!r}, {a}, {n}, {width})', name)}")


@handles("SET_BIT", "CLEAR_BIT")
def set_clear_bit(gen: Gen, el, p: str) -> None:
    d, name = gen.dest("var")
    mask = bit_mask_expr(gen, el.args["bit"])
    expr = f"{d} | {mask}" if el.kind == "SET_BIT" else f"{d} & ~{mask}"
    gen.emit(f"if {p}: {d} = {gen.wrap(expr, name)}")


@handles("BIN2BCD", "BCD2BIN")
def bcd(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    src = gen.operand(el.args["src"])
    fn = el.kind.lower()
    gen.namespace[fn] = getattr(numbers, fn)
    r = gen.temp("r")
    why = ("f'{" + src + "} is negative or above 9999'" if el.kind == "BIN2BCD"
           else "f'0x{" + src + " & 0xFFFFFFFF:X} is not unpacked BCD'")
    with gen.block(f"if {p}:"):
        gen.emit(f"{r} = {fn}({src})")
        gen.emit(f"if {r} is None: " + gen.fault(BAD_VALUE, why))
        gen.emit(f"{d} = {gen.wrap(r, name)}")


@handles("SWAP", "OPPOSITE")
def reorder(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    src = gen.operand(el.args["src"])
    width = gen.operand_size(el.args["src"], gen.size(name))
    fn = el.kind.lower()
    gen.namespace[fn] = getattr(numbers, fn)
    gen.emit(f"if {p}: {d} = {gen.wrap(f'{fn}({src}, {width})', name)}")


def _seed(gen: Gen, name: str) -> str:
    return gen.slot(f"$seed_{name}", "int", 4)


@handles("RANDOM")
def random(gen: Gen, el, p: str) -> None:
    d, name = gen.dest("name")
    seed = _seed(gen, name)
    u = gen.temp("u")
    with gen.block(f"if {p}:"):
        gen.emit(f"{u} = (({seed} & {SEED_MASK}) * 69069 + 1) & {SEED_MASK}")
        gen.emit(f"{seed} = {numbers.wrap_expr(u, 4)}")
        # the seed's most significant bytes that fit the destination
        gen.emit(f"{d} = {gen.wrap(f'{u} >> {32 - 8 * gen.size(name)}', name)}")


@handles("SEED_RANDOM")
def seed_random(gen: Gen, el, p: str) -> None:
    seed = _seed(gen, el.args["name"])
    gen.emit(f"if {p}: {seed} = {numbers.wrap_expr(gen.operand(el.args['seed']), 4)}")


@handles("SHIFT_REGISTER")
def shift_register(gen: Gen, el, p: str) -> None:
    name, stages = el.args["name"], int(el.args["stages"])
    st = gen.memory("edge")
    with gen.block(f"if {p} and not {st}:"):
        gen.emit("pass")
        for i in range(stages - 2, -1, -1):
            src, dst = f"{name}{i}", f"{name}{i + 1}"
            gen.emit(f"{gen.var(dst)} = {gen.wrap(gen.var(src), dst)}")
    gen.emit(f"{st} = {p}")


@handles("LOOK_UP_TABLE")
def look_up_table(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    values = tuple(gen.literal(str(v)) for v in el.args.get("values", ()))
    if not values:
        raise CannotSimulate(BAD_OPERAND, "look-up table with no values")
    table = gen.constant(values, "LUT")
    index = gen.operand(el.args["index"])
    i = gen.temp("i")
    with gen.block(f"if {p}:"):
        gen.emit(f"{i} = {index}")
        gen.emit(f"if not 0 <= {i} < {len(values)}: "
                 + gen.fault(TABLE_INDEX, f"f'index {{{i}}} out of range for table "
                                          f"{el.args.get('table') or name}[0..{len(values) - 1}]'"))
        gen.emit(f"{d} = {gen.wrap(f'{table}[{i}]', name)}")


@handles("PIECEWISE_LINEAR")
def piecewise_linear(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    points = [(gen.literal(str(x)), gen.literal(str(y))) for x, y in el.args.get("points", ())]
    if not points:
        raise CannotSimulate(BAD_OPERAND, "piecewise linear table with zero elements")
    if any(b[0] <= a[0] for a, b in zip(points, points[1:])):
        raise CannotSimulate(BAD_OPERAND, "x values in a piecewise linear table must be strictly increasing")
    index = el.args["index"]
    gen.namespace["cdiv"] = numbers.cdiv
    with gen.block(f"if {p}:"):
        gen.emit("pass")
        # LDmicro tests the segments from the last down, each one that holds
        # the index recomputing the result step by step in the destination's
        # size: the lowest matching segment wins, an index past the last x
        # leaves the destination alone, one below the first extrapolates
        for i in range(len(points) - 1, 0, -1):
            (x0, y0), (x1, y1) = points[i - 1], points[i]
            dx, dy = x1 - x0, y1 - y0
            if not -32768 < dx * dy < 32767:
                raise CannotSimulate(BAD_OPERAND, "numerical problem with the piecewise linear table: "
                                                "make the entries smaller or the points closer")
            with gen.block(f"if {gen.operand(index)} <= {x1}:"):
                gen.emit(f"{d} = {gen.wrap(f'{gen.operand(index)} - {x0}', name)}")
                gen.emit(f"{d} = {gen.wrap(f'{d} * {dy}', name)}")
                gen.emit(f"{d} = {gen.wrap(f'cdiv({d}, {dx})', name)}")
                gen.emit(f"{d} = {gen.wrap(f'{d} + {y0}', name)}")


@handles("7SEGMENTS")
def seven_segments(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    anode = str(el.args.get("common", "C")) != "C"
    src = str(el.args["src"])
    if is_literal(src):
        pattern = numbers.CHAR7SEG[numbers.seg7_index(gen.literal(src))]
        gen.emit(f"if {p}: {d} = {gen.wrap(str(~pattern if anode else pattern), name)}")
        return
    gen.namespace["CHAR7SEG"] = numbers.CHAR7SEG
    gen.namespace["seg7_index"] = numbers.seg7_index
    s = gen.var(src)
    i = gen.temp("i")
    with gen.block(f"if {p}:"):
        gen.emit(f"{i} = seg7_index({s})")
        # LDmicro's code stores the font index back into the source variable
        gen.emit(f"{s} = {gen.wrap(i, src)}")
        gen.emit(f"{d} = {gen.wrap(('~' if anode else '') + f'CHAR7SEG[{i}]', name)}")


@handles("BUS")
def bus(gen: Gen, el, p: str) -> None:
    d, name = gen.dest()
    src = gen.operand(el.args["src"])
    # LDmicro's compiled code: field b<j> (the .ld line lists b7 first) is the
    # destination bit of source bit j; a destination bit no source names is 0
    terms = [f"(({src} >> {j}) & 1) << {int(el.args[f'b{j}'])}" for j in range(8)]
    gen.emit(f"if {p}: {d} = {gen.wrap(' | '.join(terms), name)}")
