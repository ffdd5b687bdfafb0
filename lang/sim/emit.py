"""The simulator's back end: each op of the intermediate code as Python
source, one pattern per op. The code is the lowering's (lang.semantics), the
same the compiled back ends translate; what only a simulation has is here:
the peripherals are the user's objects (`PER`, `U`), and what the MCU would
do silently wrong (a division by zero, a table index out of range, a runaway
jump) is a located fault.

Integers are Python ints brought back to their variable's size after every
write (`wrap_expr`); bits are bools.
"""

from __future__ import annotations

from collections.abc import Callable

from .. import numbers
from ..numbers import wrap, wrap_expr
from ..semantics import ir
from ..semantics.lower.io import PWM_FULL
from .codegen import Gen
from .errors import BAD_VALUE, DIVIDE_BY_ZERO, LOCKED, RUNAWAY, STACK, TABLE_INDEX, UART_STALL

MAX_JUMPS_PER_SCAN = 100_000
STACK_DEPTH = 8
RESOLUTIONS = {full: name for name, full in PWM_FULL.items()}

PATTERNS: dict[type, Callable] = {}


def pattern(*kinds: type):
    def register(fn):
        for kind in kinds:
            PATTERNS[kind] = fn
        return fn

    return register


def emit_ops(gen: Gen, ops: list[ir.Op], each: Callable[[], None] | None = None) -> None:
    """The ops' code; `each()` after each op's."""
    skip = False
    for op, after in zip(ops, [*ops[1:], None]):
        if skip:
            skip = False
            continue
        test = _bit_of_test(op, after)
        if test is not None:
            # `p = False; if test: p = True` (a counter's output): one assignment
            gen.emit(f"{gen.bit(test[0])} = {condition(gen, test[1])}")
            skip = True
        else:
            PATTERNS[type(op)](gen, op)
        if each:
            each()


def _bit_of_test(op: ir.Op, after: ir.Op | None) -> tuple[ir.Bit, ir.Condition] | None:
    """The bit and the test of `p = False; if test: p = True`, a test that does not read p."""
    if (isinstance(op, ir.SetBit) and not op.value and isinstance(after, ir.If) and after.otherwise is None
            and after.then == [ir.SetBit(op.dst, True)]
            and not (isinstance(after.cond, ir.IsSet) and after.cond.bit == op.dst)):
        return op.dst, after.cond
    return None


# --- operands ------------------------------------------------------------------------

def value(gen: Gen, operand: ir.Operand) -> str:
    if isinstance(operand, ir.Const):
        return str(operand.value)
    if isinstance(operand, ir.Byte):
        whole = gen.var(operand.var)
        return f"({whole} >> {8 * operand.index} & 255)" if operand.index else f"({whole} & 255)"
    return gen.var(operand)


def assign(gen: Gen, target: ir.Place, expr: str) -> None:
    """`target = expr`, truncated to the target's size."""
    if isinstance(target, ir.Byte):
        whole, var = gen.var(target.var), target.var
        gen.counted.discard(var.name)
        shift = 8 * target.index
        expr = f"{whole} & {~(255 << shift)} | (({expr}) & 255) << {shift}"
        gen.emit(f"{whole} = {wrap_expr(expr, var.size)}")
        return
    local = gen.var(target)
    gen.counted.discard(target.name)
    try:
        gen.emit(f"{local} = {wrap(int(expr), target.size)}")
    except ValueError:
        gen.emit(f"{local} = {wrap_expr(expr, target.size)}")


def function(gen: Gen, fn: Callable) -> str:
    gen.namespace[fn.__name__] = fn
    return fn.__name__


def _args(gen: Gen) -> dict:
    assert gen.element is not None, "a fault outside an element's code"
    return gen.element.args


# --- structure --------------------------------------------------------------------------

def condition(gen: Gen, cond: ir.Condition, holds: bool = True) -> str:
    """Python source testing that `cond` holds (or, with holds=False, fails)."""
    if isinstance(cond, ir.IsSet):
        return gen.bit(cond.bit) if cond.value == holds else f"not {gen.bit(cond.bit)}"
    if isinstance(cond, ir.Holds):
        rel = cond.rel if holds else ir.NEGATED[cond.rel]
        return f"{value(gen, cond.a)} {rel} {value(gen, cond.b)}"
    mask = (f"{numbers.bit_mask(cond.index.value)}" if isinstance(cond.index, ir.Const)
            else f"{function(gen, numbers.bit_mask)}({value(gen, cond.index)})")
    return f"({value(gen, cond.a)} & {mask}) {'!=' if cond.value == holds else '=='} 0"


@pattern(ir.If)
def if_(gen: Gen, op: ir.If) -> None:
    test = _power_test(op)
    if test is not None:
        # a comparison or a bit test: the power goes on while the test holds
        power = gen.bit(test[0])
        gen.emit(f"{power} = {power} and {condition(gen, test[1], holds=False)}")
        return
    counted = _counted(gen, op.cond)
    _block(gen, f"if {condition(gen, op.cond)}:", op.then)
    gen.counted.discard(counted)
    if op.otherwise:
        _block(gen, "else:", op.otherwise)


def _block(gen: Gen, header: str, ops: list[ir.Op]) -> None:
    with gen.block(header):
        written = len(gen.lines)
        emit_ops(gen, ops)
        if len(gen.lines) == written:  # ops with no effect in a simulation
            gen.emit("pass")


def _power_test(op: ir.If) -> tuple[ir.Bit, ir.Condition] | None:
    """The power bit and the test of `if p: if test: p = False`."""
    cond, then = op.cond, op.then
    if not (isinstance(cond, ir.IsSet) and cond.value and op.otherwise is None and len(then) == 1):
        return None
    inner = then[0]
    if isinstance(inner, ir.If) and inner.otherwise is None and inner.then == [ir.SetBit(cond.bit, False)]:
        return cond.bit, inner.cond
    return None


def _counted(gen: Gen, cond: ir.Condition) -> str | None:
    """A variable `cond` holds below a constant it can count up to: within
    the block, adding 1 to it cannot overflow (a timer's accumulator)."""
    if (isinstance(cond, ir.Holds) and cond.rel == "<" and isinstance(cond.a, ir.Var)
            and isinstance(cond.b, ir.Const) and cond.b.value < 1 << (8 * cond.a.size - 1)):
        gen.counted.add(cond.a.name)
        return cond.a.name
    return None


@pattern(ir.Note)
def note(gen: Gen, op: ir.Note) -> None:
    if op.element is not None:
        gen.enter(op.element)


@pattern(ir.Trace)
def trace(gen: Gen, op: ir.Trace) -> None:
    if gen.traced:
        gen.emit(f"E[{gen.number}] = bool({gen.bit(op.bit)})")


@pattern(ir.Delay, ir.ClearWatchdog)
def nothing(gen: Gen, op: ir.Op) -> None:
    """DELAY's busy-wait does not move simulated time (the scan still starts
    every cycle, as on the MCU while the delay fits), and there is no
    watchdog to clear."""


@pattern(ir.Halt)
def halt(gen: Gen, op: ir.Halt) -> None:
    gen.emit(gen.fault(LOCKED, "'LOCK reached: the MCU stops here in an endless loop'"))


# --- jumps between rungs: segments of the dispatch loop (lang/sim/compile.py) ------------

def _jump(gen: Gen, segment: int | str) -> None:
    gen.emit("J += 1")
    gen.emit(f"if J > {MAX_JUMPS_PER_SCAN}: "
             + gen.fault(RUNAWAY, f"'more than {MAX_JUMPS_PER_SCAN} jumps in one scan'"))
    gen.emit(f"seg = {segment}")
    gen.emit("continue")


@pattern(ir.Jump)
def jump(gen: Gen, op: ir.Jump) -> None:
    assert gen.jumps is not None, "a jump in a program the compiler found none in"
    _jump(gen, gen.jumps.segment(op.target))


@pattern(ir.Call)
def call(gen: Gen, op: ir.Call) -> None:
    jumps = gen.jumps
    assert jumps is not None, "a GOSUB in a program the compiler found none in"
    back = gen.return_point = jumps.new_return_point()
    gen.emit(f"if len(K) >= {STACK_DEPTH}: "
             + gen.fault(STACK, f"'GOSUB nested more than {STACK_DEPTH} deep: stack overflow'"))
    gen.emit(f"K.append({back})")
    _jump(gen, jumps.segment(op.target))


@pattern(ir.Return)
def return_(gen: Gen, op: ir.Return) -> None:
    gen.emit("if not K: " + gen.fault(STACK, "'return with no GOSUB to return to: stack underflow'"))
    _jump(gen, "K.pop()")


# --- bits -------------------------------------------------------------------------------

@pattern(ir.SetBit)
def set_bit(gen: Gen, op: ir.SetBit) -> None:
    gen.emit(f"{gen.bit(op.dst)} = {op.value}")


@pattern(ir.CopyBit)
def copy_bit(gen: Gen, op: ir.CopyBit) -> None:
    gen.emit(f"{gen.bit(op.dst)} = {'not ' if op.invert else ''}{gen.bit(op.src)}")


@pattern(ir.AndBit)
def and_bit(gen: Gen, op: ir.AndBit) -> None:
    dst = gen.bit(op.dst)
    gen.emit(f"{dst} = {dst} and {'not ' if op.invert else ''}{gen.bit(op.src)}")


@pattern(ir.OrBit)
def or_bit(gen: Gen, op: ir.OrBit) -> None:
    dst = gen.bit(op.dst)
    gen.emit(f"{dst} = {dst} or {gen.bit(op.src)}")


# --- integers ---------------------------------------------------------------------------

ARITH = {"add": "+", "sub": "-", "mul": "*", "and": "&", "or": "|", "xor": "^"}


@pattern(ir.Move)
def move(gen: Gen, op: ir.Move) -> None:
    assign(gen, op.dst, value(gen, op.src))


@pattern(ir.Arith)
def arith(gen: Gen, op: ir.Arith) -> None:
    if (op.op == "add" and op.overflow is None and op.b == ir.Const(1) and op.a == op.dst
            and isinstance(op.dst, ir.Var) and op.dst.name in gen.counted):
        gen.emit(f"{gen.var(op.dst)} += 1")
        gen.counted.discard(op.dst.name)
        return
    expr = f"{value(gen, op.a)} {ARITH[op.op]} {value(gen, op.b)}"
    if op.overflow is None:
        assign(gen, op.dst, expr)
        return
    gen.emit(f"r = {expr}")
    assign(gen, op.dst, "r")
    # signed overflow of the destination's size; LDmicro never clears the flag
    gen.emit(f"if {value(gen, op.dst)} != r: {gen.bit(op.overflow)} = True")


@pattern(ir.Divide)
def divide(gen: Gen, op: ir.Divide) -> None:
    a, b = value(gen, op.a), value(gen, op.b)
    if not isinstance(op.b, ir.Const) or op.b.value == 0:
        args = _args(gen)
        what = (f"{gen.element.kind if gen.element else ''} {args.get('dest')} := {args.get('op1')} "
                f"{'/' if op.op == 'div' else '%'} {args.get('op2')}")
        gen.emit(f"if {b} == 0: " + gen.fault(DIVIDE_BY_ZERO, repr(f"division by zero: {what} with "
                                                                 f"{args.get('op2')} = 0")))
    fn = function(gen, numbers.cdiv if op.op == "div" else numbers.cmod)
    if op.remainder is None:
        assign(gen, op.dst, f"{fn}({a}, {b})")
        return
    # both from the same operands, which the quotient may overwrite
    gen.emit(f"q, r = {fn}({a}, {b}), {function(gen, numbers.cmod)}({a}, {b})")
    assign(gen, op.dst, "q")
    assign(gen, op.remainder, "r")


@pattern(ir.Unary)
def unary(gen: Gen, op: ir.Unary) -> None:
    assign(gen, op.dst, f"{'-' if op.op == 'neg' else '~'}({value(gen, op.a)})")


@pattern(ir.Shift)
def shift(gen: Gen, op: ir.Shift) -> None:
    assign(gen, op.dst, f"{function(gen, numbers.shift)}({op.op.upper()!r}, {value(gen, op.a)}, "
                        f"{value(gen, op.count)}, {op.width})")


@pattern(ir.ChangeBitOf)
def change_bit_of(gen: Gen, op: ir.ChangeBitOf) -> None:
    # a bit past the destination's width is cut off by the truncation
    mask = (f"{numbers.bit_mask(op.index.value)}" if isinstance(op.index, ir.Const)
            else f"{function(gen, numbers.bit_mask)}({value(gen, op.index)})")
    dst = value(gen, op.dst)
    assign(gen, op.dst, f"{dst} | {mask}" if op.value else f"{dst} & ~{mask}")


@pattern(ir.Convert)
def convert(gen: Gen, op: ir.Convert) -> None:
    src = value(gen, op.src)
    fn = function(gen, getattr(numbers, op.op))
    if op.op not in ("bin2bcd", "bcd2bin"):
        assign(gen, op.dst, f"{fn}({src}, {op.width})")
        return
    why = (f"f'{{{src}}} is negative or above 9999'" if op.op == "bin2bcd"
           else f"f'0x{{{src} & 0xFFFFFFFF:X}} is not unpacked BCD'")
    gen.emit(f"r = {fn}({src})")
    gen.emit("if r is None: " + gen.fault(BAD_VALUE, why))
    assign(gen, op.dst, "r")


@pattern(ir.Table)
def table(gen: Gen, op: ir.Table) -> None:
    values = gen.constant(op.values, "LUT")
    gen.emit(f"i = {value(gen, op.index)}")
    name = _args(gen).get("table") or getattr(op.dst, "name", "")
    gen.emit(f"if not 0 <= i < {len(op.values)}: "
             + gen.fault(TABLE_INDEX, f"f'index {{i}} out of range for table {name}[0..{len(op.values) - 1}]'"))
    assign(gen, op.dst, f"{values}[i]")


@pattern(ir.Permute)
def permute(gen: Gen, op: ir.Permute) -> None:
    src = value(gen, op.src)
    assign(gen, op.dst, " | ".join(f"(({src} >> {s}) & 1) << {d}" for s, d in op.pairs))


# --- peripherals: the simulator's objects the user drives (lang/sim/peripherals.py) --------

@pattern(ir.ReadAdc)
def read_adc(gen: Gen, op: ir.ReadAdc) -> None:
    assign(gen, op.dst, f"PER.read_adc({op.dst.name!r})")


@pattern(ir.ReadSfr)
def read_sfr(gen: Gen, op: ir.ReadSfr) -> None:
    assign(gen, op.dst, f"PER.read_register({value(gen, op.address)})")


@pattern(ir.WriteSfr)
def write_sfr(gen: Gen, op: ir.WriteSfr) -> None:
    gen.emit(f"PER.write_register({value(gen, op.address)}, {value(gen, op.value)})")


@pattern(ir.SetPwm)
def set_pwm(gen: Gen, op: ir.SetPwm) -> None:
    gen.emit(f"PER.set_pwm({op.unit!r}, {value(gen, op.duty)}, {op.freq}, {RESOLUTIONS[op.full]!r})")


@pattern(ir.PwmOff)
def pwm_off(gen: Gen, op: ir.PwmOff) -> None:
    gen.emit(f"PER.pwm_off({op.unit!r})")


@pattern(ir.UartSend)
def uart_send(gen: Gen, op: ir.UartSend) -> None:
    gen.uses_time = True
    gen.emit(f"U.send(now, {value(gen, op.value)} & 255{', True' if op.wait else ''})")


@pattern(ir.UartReady)
def uart_ready(gen: Gen, op: ir.UartReady) -> None:
    gen.uses_time = True
    gen.emit(f"{gen.bit(op.dst)} = U.ready(now)")


@pattern(ir.UartAvailable)
def uart_available(gen: Gen, op: ir.UartAvailable) -> None:
    gen.emit(f"{gen.bit(op.dst)} = U.available()")


@pattern(ir.UartTake)
def uart_take(gen: Gen, op: ir.UartTake) -> None:
    if op.wait:
        # the MCU would wait for ever for a byte the user never sends
        count = int(_args(gen).get("bytes", 1) or 1)
        taken = op.dst.index if isinstance(op.dst, ir.Byte) else 0
        gen.emit("if not U.received: " + gen.fault(UART_STALL, f"f'UART RECV waits for {count} bytes, "
                                                               f"{{len(U.received) + {taken}}} received'"))
    assign(gen, op.dst, "U.take()")


@pattern(ir.EepromLoad)
def eeprom_load(gen: Gen, op: ir.EepromLoad) -> None:
    assign(gen, op.var, f"PER.eeprom.read({op.address}, {op.var.size})")


@pattern(ir.EepromSave)
def eeprom_save(gen: Gen, op: ir.EepromSave) -> None:
    v = gen.var(op.var)
    gen.emit(f"if PER.eeprom.read({op.address}, {op.var.size}) != {v}: "
             f"PER.eeprom.write({op.address}, {op.var.size}, {v})")
