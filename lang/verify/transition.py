"""One scan of a lowered program as a formula: the intermediate code
(lang.semantics.ir, the code the simulator and the back ends run) executed
symbolically over the SMT solver's bit-vectors.

Bits are Booleans; a variable of n bytes is a bit-vector of 8n bits, read as
its signed value (sign-extended to 64 bits, as wide as any operation needs)
and truncated when written, as docs/semantics.md says. An `If` runs both
branches and merges what they wrote; a GOTO (a forward jump between rungs)
carries what was written so far to its target rung, where it is merged with
the code that ran on. The peripherals the program reads are free inputs:
every X input, each A/D reading (0 to 1023), and the EEPROM's contents at
power-up (docs/verify.md says why).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import z3

from ..numbers import wrap
from ..semantics import ir
from ..sim.peripherals import ADC_MAX

if TYPE_CHECKING:
    from ..model import Element

WIDE = 64  # every operand is read as a signed 64-bit value
# The UART: the time until the transmitter is free, in microseconds x baud (a byte's
# 10 bits are then exactly BYTE_TIME); the bytes received and not taken yet; the
# bytes that arrive before a scan (an input), at most MAX_ARRIVALS a scan.
UART_BUSY, UART_QUEUE, UART_ARRIVALS = "$uart_busy", "$uart_queue", "$uart_arrivals"
BYTE_TIME = 10_000_000
MAX_ARRIVALS = 8
CALL_DEPTH = 8  # GOSUBs inside each other, as the simulator's stack holds


class NotModelled(Exception):
    """An op the prover has no formula for; `element` is where it comes from."""

    def __init__(self, message: str, element):
        super().__init__(message)
        self.element = element


@dataclass
class Machine:
    """What one scan reads and keeps: the state carried from scan to scan
    (every bit but the inputs and the rung's power bits, every variable, the
    EEPROM bytes PERSIST uses) and the inputs each scan reads afresh."""

    code: ir.Code
    state_bits: list[str]
    state_vars: dict[str, int]  # name -> bytes
    inputs: list[str]  # the X inputs
    adcs: list[str]  # the variables READ_ADC writes
    eeprom: dict[int, int]  # address -> bytes of the PERSIST variable kept there
    cycle_us: int
    baud: int
    takes: dict[int, int]  # id of each UartTake op -> its number, in the scan's order
    waits: bool = False  # some UartSend waits for the transmitter

    @staticmethod
    def of(code: ir.Code, cycle_us: int, baud: int) -> Machine:
        inputs = sorted(name for name, kind in code.bits.items() if kind != ir.TEMP and name.startswith("X"))
        state_bits = sorted(name for name, kind in code.bits.items() if kind != ir.TEMP and name not in inputs)
        state_vars = dict(sorted(code.vars.items()))
        adcs: set[str] = set()
        eeprom: dict[int, int] = {}
        takes: dict[int, int] = {}
        waits = False
        for op in walk(code.scan):
            if isinstance(op, ir.ReadAdc):
                adcs.add(op.dst.name)
            elif isinstance(op, ir.EepromLoad | ir.EepromSave):
                eeprom[op.address] = op.var.size
            elif isinstance(op, ir.UartSend | ir.UartReady):
                state_vars[UART_BUSY] = 8
                waits = waits or isinstance(op, ir.UartSend) and op.wait
            elif isinstance(op, ir.UartAvailable | ir.UartTake):
                state_vars[UART_QUEUE] = 4
                if isinstance(op, ir.UartTake):
                    takes[id(op)] = len(takes)
        return Machine(code, state_bits, state_vars, inputs, sorted(adcs), eeprom, cycle_us, baud, takes, waits)

    def fresh_state(self, tag: str) -> dict[str, z3.ExprRef]:
        """A state of free values named after `tag`."""
        state: dict[str, z3.ExprRef] = {name: z3.Bool(f"{name}@{tag}") for name in self.state_bits}
        state.update({name: z3.BitVec(f"{name}@{tag}", 8 * size) for name, size in self.state_vars.items()})
        state.update({eeprom_name(address): z3.BitVec(f"{eeprom_name(address)}@{tag}", 8 * size)
                      for address, size in self.eeprom.items()})
        return state

    def initial_state(self, eeprom: dict[str, z3.ExprRef]) -> dict[str, z3.ExprRef]:
        """Power-up: everything 0 but what the lowering's `init` sets; the
        EEPROM's bytes as given."""
        state: dict[str, z3.ExprRef] = {name: z3.BoolVal(False) for name in self.state_bits}
        state.update({name: z3.BitVecVal(0, 8 * size) for name, size in self.state_vars.items()})
        for op in self.code.init:
            assert isinstance(op, ir.Move) and isinstance(op.dst, ir.Var) and isinstance(op.src, ir.Const)
            state[op.dst.name] = z3.BitVecVal(wrap(op.src.value, op.dst.size), 8 * op.dst.size)
        state.update(eeprom)
        return state

    def fresh_inputs(self, tag: str) -> dict[str, z3.ExprRef]:
        """A scan's inputs: the X inputs, the A/D readings, the bytes arriving
        on the UART and the value of each byte a UartTake op takes."""
        inputs: dict[str, z3.ExprRef] = {name: z3.Bool(f"{name}@{tag}") for name in self.inputs}
        inputs.update({_adc(name): z3.BitVec(f"{_adc(name)}@{tag}", 16) for name in self.adcs})
        if UART_QUEUE in self.state_vars:
            inputs[UART_ARRIVALS] = z3.BitVec(f"{UART_ARRIVALS}@{tag}", 8)
            inputs.update({taken_byte(j): z3.BitVec(f"{taken_byte(j)}@{tag}", 8) for j in self.takes.values()})
        return inputs

    def bounds(self, name: str, value: z3.ExprRef) -> list[z3.BoolRef]:
        """What an input can be: an A/D reading 0..1023, a few bytes arriving."""
        if name.startswith("$adc:"):
            return [z3.ULE(value, ADC_MAX)]
        if name == UART_ARRIVALS:
            return [z3.ULE(value, MAX_ARRIVALS)]
        return []

    def invariants(self, state: dict[str, z3.ExprRef]) -> list[z3.BoolRef]:
        """What holds of every state a run reaches, beyond what the state's
        types say: with no UartSend that waits, the transmitter is busy for one
        byte at most (a byte sent while it is busy is lost)."""
        if UART_BUSY in state and not self.waits:
            return [z3.ULE(state[UART_BUSY], BYTE_TIME)]
        return []

    def erased(self, state: dict[str, z3.ExprRef]) -> list[z3.BoolRef]:
        """The EEPROM bytes of `state` as a new part's: erased."""
        return [state[eeprom_name(address)] == (1 << 8 * size) - 1 for address, size in self.eeprom.items()]

    def scan(self, state: dict[str, z3.ExprRef], inputs: dict[str, z3.ExprRef]) -> dict[str, z3.ExprRef]:
        """Every value after one scan from `state` with `inputs`: the next
        state, and the inputs as the scan read them."""
        env = dict(state)
        env.update(inputs)
        for name in self.code.bits:
            env.setdefault(name, z3.BoolVal(False))  # the rung's power bits, written before they are read
        for name, size in self.code.vars.items():
            env.setdefault(name, z3.BitVecVal(0, 8 * size))
        env.update({took(j): z3.BoolVal(False) for j in self.takes.values()})
        if UART_QUEUE in env:
            env[UART_QUEUE] = env[UART_QUEUE] + z3.ZeroExt(24, env[UART_ARRIVALS])
        run = _Run(self, env)
        run.block(self.code.scan)
        if UART_BUSY in env:
            # the next scan comes one cycle later
            busy, step = run.env[UART_BUSY], self.cycle_us * self.baud
            run.env[UART_BUSY] = z3.If(z3.UGT(busy, step), busy - step, z3.BitVecVal(0, 64))
        return run.env

    def eeprom_names(self) -> list[str]:
        return [eeprom_name(address) for address in self.eeprom]


@dataclass
class Step:
    """One scan over placeholders, built once: `next` is each state's value
    after the scan, in terms of the `state` before it and the `inputs` it
    reads; `reads[name]` are the placeholders `next[name]` depends on."""

    machine: Machine
    state: dict[str, z3.ExprRef]
    inputs: dict[str, z3.ExprRef]
    next: dict[str, z3.ExprRef]  # and, for a counterexample, whether each UartTake took a byte
    reads: dict[str, frozenset[str]]

    @staticmethod
    def of(machine: Machine) -> Step:
        state, inputs = machine.fresh_state("pre"), machine.fresh_inputs("in")
        after = machine.scan(state, inputs)
        following = {name: after[name] for name in [*state, *map(took, machine.takes.values())]}
        return Step(machine, state, inputs, following, _reads(following, {**state, **inputs}))

    def cone(self, names: list[str]) -> set[str]:
        """The names whose values decide those of `names`, scan after scan
        (the cone of influence): only these need to be unrolled."""
        seen: set[str] = set()
        todo = list(names)
        while todo:
            name = todo.pop()
            if name not in seen:
                seen.add(name)
                todo.extend(self.reads.get(name, ()))
        return seen


def _reads(exprs: dict[str, z3.ExprRef], leaves: dict[str, z3.ExprRef]) -> dict[str, frozenset[str]]:
    """The leaves each expression contains (shared subterms visited once)."""
    names = {leaf.get_id(): name for name, leaf in leaves.items()}
    memo: dict[int, frozenset[str]] = {}
    for expr in exprs.values():
        stack = [expr]
        while stack:
            node = stack[-1]
            key = node.get_id()
            if key in memo:
                stack.pop()
                continue
            if key in names:
                memo[key] = frozenset((names[key],))
                stack.pop()
                continue
            children = [node.arg(i) for i in range(node.num_args())]
            waiting = [child for child in children if child.get_id() not in memo]
            if waiting:
                stack.extend(waiting)
                continue
            memo[key] = frozenset().union(*(memo[child.get_id()] for child in children))
            stack.pop()
    return {name: memo[expr.get_id()] for name, expr in exprs.items()}


def eeprom_name(address: int) -> str:
    """The state that holds the EEPROM's copy of the PERSIST variable at `address`."""
    return f"$eeprom@{address}"


def _adc(name: str) -> str:
    return f"$adc:{name}"


def took(j: int) -> str:
    """Whether UartTake op number j took a byte in the scan (what a
    counterexample needs to know to send the bytes in order)."""
    return f"$uart_took:{j}"


def taken_byte(j: int) -> str:
    """The input holding the byte UartTake op number j takes."""
    return f"$uart_byte:{j}"


def adc_input(name: str) -> str:
    """The input holding the A/D reading READ_ADC copies into `name`."""
    return _adc(name)


def walk(ops: list[ir.Op]):
    for op in ops:
        yield op
        if isinstance(op, ir.If):
            yield from walk(op.then)
            yield from walk(op.otherwise or [])


def choose(cond: z3.BoolRef, then: z3.ExprRef, otherwise: z3.ExprRef) -> z3.ExprRef:
    """z3.If of two values of one sort, without the conversions z3.If tries
    first: a scan makes thousands."""
    ctx = then.ctx
    return then.__class__(z3.Z3_mk_ite(ctx.ref(), cond.as_ast(), then.as_ast(), otherwise.as_ast()), ctx)


class _Run:
    """The symbolic execution of one scan: `env` holds every value so far.
    Both branches of an If run, one after the other; a write takes effect
    under `guard`: the conditions of the Ifs around it (`path`), and that no
    GOTO above has left the code for a rung below (`pending`: the conditions
    under which the jumps to each label were taken). At its label a jump's
    condition no longer holds the writes back: what the skipped code wrote
    under the guard kept the values from before the jump."""

    def __init__(self, machine: Machine, env: dict[str, z3.ExprRef]):
        self.machine = machine
        self.env = env
        self.path: list[z3.BoolRef] = []
        self.pending: dict[str, list[z3.BoolRef]] = {}
        self.guard: z3.BoolRef | None = None  # None: always
        self.element: Element | None = None
        self.seen_labels: set[str] = set()
        self.returns: list[str] = []  # the labels the subroutines being run return to, innermost last
        self.calls = 0

    # --- structure ---------------------------------------------------------------

    def block(self, ops: list[ir.Op]) -> None:
        for op in ops:
            handler = OPS.get(type(op))
            if handler is None:
                raise NotModelled(f"{_what(op)} is not modelled by the prover", self.element)
            handler(self, op)

    def _reguard(self) -> None:
        parts = list(self.path)
        jumped = [cond for conds in self.pending.values() for cond in conds]
        if jumped:
            parts.append(z3.Not(z3.Or(*jumped)) if len(jumped) > 1 else z3.Not(jumped[0]))
        self.guard = None if not parts else parts[0] if len(parts) == 1 else z3.And(*parts)

    def branch(self, op: ir.If) -> None:
        # the condition is read before either branch writes anything
        cond = self.condition(op.cond)
        self.path.append(cond)
        self._reguard()
        self.block(op.then)
        if op.otherwise:
            self.path[-1] = z3.Not(cond)
            self._reguard()
            self.block(op.otherwise)
        self.path.pop()
        self._reguard()

    def label(self, op: ir.Label) -> None:
        self.seen_labels.add(op.name)
        if self.pending.pop(op.name, None):
            self._reguard()

    def call(self, op: ir.Call) -> None:
        """GOSUB: the subroutine's rungs run here, from its first to the
        RETURN of its ENDSUB; a RETURN on the way holds back what follows it
        until then. It comes back right after the GOSUB element."""
        if len(self.returns) >= CALL_DEPTH:
            raise NotModelled(f"GOSUB nested more than {CALL_DEPTH} deep (the simulator's stack overflows)",
                              self.element)
        scan = self.machine.code.scan
        self.calls += 1
        back = f"$return{self.calls}"
        self.returns.append(back)
        caller = self.element
        position = next(i for i, o in enumerate(scan) if isinstance(o, ir.Label) and o.name == op.target)
        for body in scan[position:]:
            if isinstance(body, ir.Return):
                break
            self.block([body])
        else:
            raise NotModelled("a subroutine that does not end in ENDSUB", caller)
        self.returns.pop()
        self.element = caller
        if self.pending.pop(back, None):
            self._reguard()

    def return_(self, op: ir.Return) -> None:
        # outside a subroutine (only reached in a scan the simulator stops, LD613), nothing after it runs
        where = self.returns[-1] if self.returns else "$stopped"
        reached = self.guard if self.guard is not None else z3.BoolVal(True)
        if not z3.is_false(z3.simplify(reached)):
            self.pending.setdefault(where, []).append(reached)
            self._reguard()

    def jump(self, op: ir.Jump) -> None:
        if op.target in self.seen_labels:
            raise NotModelled("a GOTO back to an earlier rung (a loop inside the scan) is not modelled by the prover",
                              self.element)
        self.pending.setdefault(op.target, []).append(self.guard if self.guard is not None else z3.BoolVal(True))
        self._reguard()

    # --- operands ------------------------------------------------------------------

    def read(self, operand: ir.Operand) -> z3.BitVecRef:
        if isinstance(operand, ir.Const):
            return z3.BitVecVal(operand.value, WIDE)
        if isinstance(operand, ir.Byte):
            whole = self.env[operand.var.name]
            return z3.ZeroExt(WIDE - 8, z3.Extract(8 * operand.index + 7, 8 * operand.index, whole))
        return z3.SignExt(WIDE - 8 * operand.size, self.env[operand.name])

    def write(self, target: ir.Place, value: z3.BitVecRef) -> None:
        if isinstance(target, ir.Byte):
            var, low = target.var, 8 * target.index
            whole = self.env[var.name]
            parts = [z3.Extract(8 * var.size - 1, low + 8, whole)] if low + 8 < 8 * var.size else []
            parts.append(z3.Extract(7, 0, value))
            if low:
                parts.append(z3.Extract(low - 1, 0, whole))
            self.set(var.name, z3.Concat(*parts) if len(parts) > 1 else parts[0])
            return
        self.set(target.name, z3.Extract(8 * target.size - 1, 0, value))

    def set(self, name: str, value: z3.ExprRef) -> None:
        """A write, which happens only where the code is reached."""
        self.env[name] = value if self.guard is None else choose(self.guard, value, self.env[name])

    def bit(self, bit: ir.Bit) -> z3.BoolRef:
        return self.env[bit.name]

    def condition(self, cond: ir.Condition) -> z3.BoolRef:
        if isinstance(cond, ir.IsSet):
            bit = self.bit(cond.bit)
            return bit if cond.value else z3.Not(bit)
        if isinstance(cond, ir.Holds):
            return RELATIONS[cond.rel](self.read(cond.a), self.read(cond.b))
        tested = (self.read(cond.a) & bit_mask(self.read(cond.index))) != 0
        return tested if cond.value else z3.Not(tested)


RELATIONS: dict[str, Callable] = {
    "==": lambda a, b: a == b, "!=": lambda a, b: a != b, "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b,
}


def bit_mask(index: z3.BitVecRef) -> z3.BitVecRef:
    """lang.numbers.bit_mask: 1 << index, none for a negative index, bit 63 past it."""
    capped = z3.If(index > 63, z3.BitVecVal(63, WIDE), index)
    return z3.If(index < 0, z3.BitVecVal(0, WIDE), z3.BitVecVal(1, WIDE) << capped)


def _what(op: ir.Op) -> str:
    names = {ir.Halt: "LOCK", ir.Sleep: "SLEEP", ir.ReadSfr: "raw register access (RSFR, SSFR, CSFR, TSFR, TCSFR)",
             ir.WriteSfr: "raw register access (WSFR, SSFR, CSFR)"}
    return names.get(type(op), type(op).__name__)


# --- each op -------------------------------------------------------------------------

def _note(run: _Run, op: ir.Note) -> None:
    if op.element is not None:
        run.element = op.element


def _set_bit(run: _Run, op: ir.SetBit) -> None:
    run.set(op.dst.name, z3.BoolVal(op.value))


def _copy_bit(run: _Run, op: ir.CopyBit) -> None:
    src = run.bit(op.src)
    run.set(op.dst.name, z3.Not(src) if op.invert else src)


def _and_bit(run: _Run, op: ir.AndBit) -> None:
    src = run.bit(op.src)
    run.set(op.dst.name, z3.And(run.bit(op.dst), z3.Not(src) if op.invert else src))


def _or_bit(run: _Run, op: ir.OrBit) -> None:
    run.set(op.dst.name, z3.Or(run.bit(op.dst), run.bit(op.src)))


def _move(run: _Run, op: ir.Move) -> None:
    run.write(op.dst, run.read(op.src))


ARITH: dict[str, Callable] = {"add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b,
                              "and": lambda a, b: a & b, "or": lambda a, b: a | b, "xor": lambda a, b: a ^ b}


def _width(operand: ir.Operand) -> int:
    """The bits that hold the operand's signed value."""
    if isinstance(operand, ir.Const):
        return max(operand.value.bit_length(), (-operand.value - 1).bit_length()) + 1
    return 9 if isinstance(operand, ir.Byte) else 8 * operand.size


def _narrow(value: z3.BitVecRef, bits: int) -> z3.BitVecRef:
    return z3.Extract(bits - 1, 0, value) if bits < WIDE else value


def _arith(run: _Run, op: ir.Arith) -> None:
    if op.overflow is not None:
        # exact, one bit wider than the operands and the destination: signed
        # overflow of the destination's size sets the flag, which is never cleared
        bits = min(WIDE, max(_width(op.a), _width(op.b), 8 * op.dst.size) + 1)
        result = ARITH[op.op](_narrow(run.read(op.a), bits), _narrow(run.read(op.b), bits))
        run.write(op.dst, result)
        kept = z3.Extract(8 * op.dst.size - 1, 0, result)
        fits = z3.SignExt(bits - 8 * op.dst.size, kept) == result if bits > 8 * op.dst.size else z3.BoolVal(True)
        run.set(op.overflow.name, z3.Or(run.bit(op.overflow), z3.Not(fits)))
        return
    # the result is truncated to the destination: its bits of the operands are enough
    # (a multiplication as wide as the destination is far cheaper for the solver)
    bits = 8 * op.dst.size
    run.write(op.dst, ARITH[op.op](_narrow(run.read(op.a), bits), _narrow(run.read(op.b), bits)))


def _divide(run: _Run, op: ir.Divide) -> None:
    # the SMT division truncates toward zero and its remainder has the
    # dividend's sign, as C's (lang.numbers.cdiv, cmod), at one bit more than
    # the operands need (-2^31 / -1 fits); a division by zero, where the
    # simulator stops, gets the solver's value (docs/verify.md)
    bits = min(WIDE, max(_width(op.a), _width(op.b)) + 1)
    a, b = _narrow(run.read(op.a), bits), _narrow(run.read(op.b), bits)

    def wide(value: z3.BitVecRef) -> z3.BitVecRef:
        return z3.SignExt(WIDE - bits, value) if bits < WIDE else value

    run.write(op.dst, wide(a / b if op.op == "div" else z3.SRem(a, b)))
    if op.remainder is not None:
        run.write(op.remainder, wide(z3.SRem(a, b)))


def _unary(run: _Run, op: ir.Unary) -> None:
    a = run.read(op.a)
    run.write(op.dst, -a if op.op == "neg" else ~a)


def _shift(run: _Run, op: ir.Shift) -> None:
    """lang.numbers.shift, bit for bit."""
    bits = 8 * op.width
    mask = z3.BitVecVal((1 << bits) - 1, WIDE)
    value, count = run.read(op.a), run.read(op.count)
    count = z3.If(count < 0, z3.BitVecVal(0, WIDE), count)
    capped = z3.If(count > bits, z3.BitVecVal(bits, WIDE), count)
    unsigned = value & mask
    if op.op == "shr":
        result = value >> capped
    elif op.op == "shl":
        result = (unsigned << capped) & mask
    elif op.op == "sr0":
        result = z3.LShR(unsigned, capped)
    else:
        turn = z3.URem(count, bits)
        left, right = (turn, bits - turn) if op.op == "rol" else (bits - turn, turn)
        result = ((unsigned << left) | z3.LShR(unsigned, right)) & mask
    run.write(op.dst, result)


def _change_bit_of(run: _Run, op: ir.ChangeBitOf) -> None:
    mask = bit_mask(run.read(op.index))
    dst = run.read(op.dst)
    run.write(op.dst, dst | mask if op.value else dst & ~mask)


def _convert(run: _Run, op: ir.Convert) -> None:
    value = run.read(op.src)
    if op.op == "bin2bcd":
        # a value outside 0..9999 stops the simulator; here it converts as the digits fall
        result = z3.BitVecVal(0, WIDE)
        for position in range(4):
            digit = z3.URem(z3.UDiv(value, 10 ** position), 10)
            result = result | digit << 8 * position
    elif op.op == "bcd2bin":
        result = z3.BitVecVal(0, WIDE)
        for position in range(4):
            result = result + (z3.LShR(value, 8 * position) & 0x0F) * 10 ** position
    elif op.op == "swap" and op.width == 1:
        result = z3.ZeroExt(WIDE - 8, z3.Concat(z3.Extract(3, 0, value), z3.Extract(7, 4, value)))
    elif op.op == "swap":
        parts = [z3.Extract(8 * i + 7, 8 * i, value) for i in range(op.width)]
        result = z3.ZeroExt(WIDE - 8 * op.width, z3.Concat(*parts))
    else:  # opposite: the bits in reverse order
        parts = [z3.Extract(i, i, value) for i in range(8 * op.width)]
        result = z3.ZeroExt(WIDE - 8 * op.width, z3.Concat(*parts))
    run.write(op.dst, result)


def _table(run: _Run, op: ir.Table) -> None:
    # an index out of range stops the simulator; here it reads 0
    index = run.read(op.index)
    result = z3.BitVecVal(0, WIDE)
    for position in range(len(op.values) - 1, -1, -1):
        result = z3.If(index == position, z3.BitVecVal(op.values[position], WIDE), result)
    run.write(op.dst, result)


def _permute(run: _Run, op: ir.Permute) -> None:
    src = run.read(op.src)
    result = z3.BitVecVal(0, WIDE)
    for source, dest in op.pairs:
        result = result | ((z3.LShR(src, source) & 1) << dest)
    run.write(op.dst, result)


def _read_adc(run: _Run, op: ir.ReadAdc) -> None:
    run.write(op.dst, z3.ZeroExt(WIDE - 16, run.env[_adc(op.dst.name)]))


def _eeprom_load(run: _Run, op: ir.EepromLoad) -> None:
    run.write(op.var, z3.SignExt(WIDE - 8 * op.var.size, run.env[eeprom_name(op.address)]))


def _eeprom_save(run: _Run, op: ir.EepromSave) -> None:
    # the simulator's EEPROM is never busy: the copy follows the variable at once
    run.set(eeprom_name(op.address), run.env[op.var.name])


def _uart_ready(run: _Run, op: ir.UartReady) -> None:
    run.set(op.dst.name, run.env[UART_BUSY] == 0)


def _uart_send(run: _Run, op: ir.UartSend) -> None:
    """lang.sim.peripherals.Uart.send: a byte written while the transmitter
    is busy is lost, or (wait) queued behind the one in progress."""
    busy = run.env[UART_BUSY]
    later = busy + BYTE_TIME if op.wait else busy
    run.set(UART_BUSY, z3.If(busy == 0, z3.BitVecVal(BYTE_TIME, 64), later))


def _uart_available(run: _Run, op: ir.UartAvailable) -> None:
    run.set(op.dst.name, run.env[UART_QUEUE] != 0)


def _uart_take(run: _Run, op: ir.UartTake) -> None:
    # with `wait` and nothing received the simulator stops (LD616); here the byte comes
    j = run.machine.takes[id(op)]
    queue = run.env[UART_QUEUE]
    run.set(took(j), queue != 0)
    run.write(op.dst, z3.ZeroExt(WIDE - 8, run.env[taken_byte(j)]))
    run.set(UART_QUEUE, z3.If(queue != 0, queue - 1, queue))


def _nothing(run: _Run, op: ir.Op) -> None:
    """No effect on what the program computes: a busy-wait, the watchdog,
    the editor's trace, the PWM unit's own registers (its P bit is set by
    the lowering)."""


OPS: dict[type, Callable] = {
    ir.Label: _Run.label, ir.Note: _note, ir.Trace: _nothing, ir.Jump: _Run.jump, ir.If: _Run.branch,
    ir.Call: _Run.call, ir.Return: _Run.return_,
    ir.SetBit: _set_bit, ir.CopyBit: _copy_bit, ir.AndBit: _and_bit, ir.OrBit: _or_bit,
    ir.Move: _move, ir.Arith: _arith, ir.Divide: _divide, ir.Unary: _unary, ir.Shift: _shift,
    ir.ChangeBitOf: _change_bit_of, ir.Convert: _convert, ir.Table: _table, ir.Permute: _permute,
    ir.ReadAdc: _read_adc, ir.EepromLoad: _eeprom_load, ir.EepromSave: _eeprom_save,
    ir.SetPwm: _nothing, ir.PwmOff: _nothing, ir.Delay: _nothing, ir.ClearWatchdog: _nothing,
    ir.UartReady: _uart_ready, ir.UartSend: _uart_send, ir.UartAvailable: _uart_available, ir.UartTake: _uart_take,
}
