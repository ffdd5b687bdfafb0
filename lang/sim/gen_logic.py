"""Contacts, coils, edge elements, comparisons, bit tests and program flow.
Each follows the intermediate code LDmicro compiles for it (intcode.cpp),
so that the simulation matches the MCU scan for scan."""

from __future__ import annotations

from ..instructions import RELATIONS
from ..numbers import bit_mask
from ..values import is_literal
from .codegen import Gen, handles
from .errors import LOCKED, RUNAWAY, STACK

MAX_JUMPS_PER_SCAN = 100_000
STACK_DEPTH = 8


@handles("CONTACTS")
def contacts(gen: Gen, el, p: str) -> None:
    bit = gen.bit(el.args["name"])
    gen.emit(f"{p} = {p} and {'not ' if el.args.get('negated') else ''}{bit}")


@handles("COIL")
def coil(gen: Gen, el, p: str) -> None:
    bit = gen.bit(el.args["name"])
    kind = el.args.get("type", " ")
    if kind == "/":
        gen.emit(f"{bit} = not {p}")
    elif kind == "S":
        gen.emit(f"if {p}: {bit} = True")
    elif kind == "R":
        gen.emit(f"if {p}: {bit} = False")
    elif kind == "T":
        seen = gen.memory("toggle")
        with gen.block(f"if {p}:"):
            with gen.block(f"if not {seen}:"):
                gen.emit(f"{seen} = True")
                gen.emit(f"{bit} = not {bit}")
        gen.emit(f"else: {seen} = False")
    else:
        gen.emit(f"{bit} = {p}")


@handles("OSR")
def one_shot_rising(gen: Gen, el, p: str) -> None:
    st = gen.memory("st")
    with gen.block(f"if {p}:"):
        gen.emit(f"if {st}: {p} = False")
        gen.emit(f"else: {st} = True")
    gen.emit(f"else: {st} = False")


@handles("OSF")
def one_shot_falling(gen: Gen, el, p: str) -> None:
    st = gen.memory("st")
    with gen.block(f"if {p}:"):
        gen.emit(f"{st} = True")
        gen.emit(f"{p} = False")
    with gen.block("elif " + st + ":"):
        gen.emit(f"{st} = False")
        gen.emit(f"{p} = True")


@handles("ODR")
def one_drop_rising(gen: Gen, el, p: str) -> None:
    st = gen.memory("st")
    with gen.block(f"if {p}:"):
        with gen.block(f"if not {st}:"):
            gen.emit(f"{p} = False")
            gen.emit(f"{st} = True")
    with gen.block("else:"):
        gen.emit(f"{p} = True")
        gen.emit(f"{st} = False")


@handles("ODF")
def one_drop_falling(gen: Gen, el, p: str) -> None:
    st, hi = gen.memory("st"), gen.memory("hi")
    with gen.block(f"if not {p}:"):
        gen.emit(f"{p} = {st}")
        gen.emit(f"if {hi}: {st} = True")
    with gen.block("else:"):
        gen.emit(f"{st} = False")
        gen.emit(f"{hi} = True")


@handles("OSC")
def oscillator(gen: Gen, el, p: str) -> None:
    st = gen.memory("st")
    with gen.block(f"if {p}:"):
        with gen.block(f"if {st}:"):
            gen.emit(f"{st} = False")
            gen.emit(f"{p} = False")
        gen.emit(f"else: {st} = True")
    gen.emit(f"else: {st} = False")


def bit_mask_expr(gen: Gen, token) -> str:
    """Source for the mask of a bit number (a literal or a variable)."""
    token = str(token)
    if is_literal(token):
        return str(bit_mask(gen.literal(token)))
    gen.namespace["bit_mask"] = bit_mask
    return f"bit_mask({gen.var(token)})"




@handles(*RELATIONS)
def compare(gen: Gen, el, p: str) -> None:
    a, b = gen.operand(el.args["op1"]), gen.operand(el.args["op2"])
    gen.emit(f"{p} = {p} and {a} {RELATIONS[el.kind]} {b}")


@handles("IF_BIT_SET", "IF_BIT_CLEAR")
def if_bit(gen: Gen, el, p: str) -> None:
    value = gen.operand(el.args["var"])
    test = "!= 0" if el.kind == "IF_BIT_SET" else "== 0"
    gen.emit(f"{p} = {p} and ({value} & {bit_mask_expr(gen, el.args['bit'])}) {test}")


@handles("SHORT", "LABEL", "COMMENT", "CLRWDT", "DELAY")
def pass_through(gen: Gen, el, p: str) -> None:
    """No effect in simulation: a LABEL only marks its rung, CLRWDT has no
    watchdog to clear, and DELAY's busy-wait does not move simulated time
    (the scan still starts every cycle, as on the MCU while DELAY fits)."""


@handles("OPEN")
def open_circuit(gen: Gen, el, p: str) -> None:
    gen.emit(f"{p} = False")


@handles("MASTER_RELAY")
def master_relay(gen: Gen, el, p: str) -> None:
    mcr = gen.bit("$mcr")
    # a cleared relay is always set again here, or nothing could set it
    gen.emit(f"{mcr} = True if not {mcr} else {p}")


@handles("LOCK")
def lock(gen: Gen, el, p: str) -> None:
    gen.emit(f"if {p}: " + gen.fault(LOCKED, "'LOCK reached: the MCU stops here in an endless loop'"))


def _jump(gen: Gen, target: int | str) -> list[str]:
    return ["J += 1",
            f"if J > {MAX_JUMPS_PER_SCAN}: "
            + gen.fault(RUNAWAY, f"'more than {MAX_JUMPS_PER_SCAN} jumps in one scan'"),
            f"seg = {target}", "continue"]


@handles("GOTO")
def goto(gen: Gen, el, p: str) -> None:
    with gen.block(f"if {p}:"):
        for line in _jump(gen, gen.jump_table().goto_target(el)):
            gen.emit(line)


@handles("GOSUB")
def gosub(gen: Gen, el, p: str) -> None:
    jumps = gen.jump_table()
    back = jumps.new_return_point()
    with gen.block(f"if {p}:"):
        gen.emit(f"if len(K) >= {STACK_DEPTH}: "
                 + gen.fault(STACK, f"'GOSUB nested more than {STACK_DEPTH} deep: stack overflow'"))
        gen.emit(f"K.append({back})")
        for line in _jump(gen, jumps.gosub_target(el)):
            gen.emit(line)
    jumps.split(back)


def _return(gen: Gen) -> None:
    gen.emit("if not K: " + gen.fault(STACK, "'return with no GOSUB to return to: stack underflow'"))
    for line in _jump(gen, "K.pop()"):
        gen.emit(line)


@handles("RETURN")
def return_(gen: Gen, el, p: str) -> None:
    with gen.block(f"if {p}:"):
        _return(gen)


@handles("ENDSUB")
def endsub(gen: Gen, el, p: str) -> None:
    _return(gen)


@handles("SUBPROG")
def subprog(gen: Gen, el, p: str) -> None:
    # the normal flow of the scan skips the subroutine's body
    for line in _jump(gen, gen.jump_table().after_endsub(el)):
        gen.emit(line)
