"""Each intermediate op, by its class, to C statements: the C back end's table
of patterns.

Values are read as `int32_t` expressions (a `Byte` unsigned), computed as
`uint32_t` and stored through `ld_sext` into the destination's width
(helpers.py). Where the simulator stops with a run-time error (a division by
zero, a table index out of range, BIN2BCD outside 0..9999, a BCD digit above
9) the C code leaves the destination as it was: the result is defined, and
docs/c.md says so. GOSUB is a `goto` with the return site pushed on a stack
of 8, the simulator's depth; the temporaries a call must keep are pushed with
it, so a subroutine that calls itself cannot clobber its caller's.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from lang.semantics import ir

from .names import C_TYPES, Names

STACK_DEPTH = 8  # the simulator's GOSUB depth (docs/semantics.md)


def c_constant(value: int) -> str:
    value = ((value + (1 << 31)) & 0xFFFFFFFF) - (1 << 31)
    if value == -(1 << 31):
        return "INT32_MIN"
    return str(value) if -32767 <= value <= 32767 else f"INT32_C({value})"


def comment_safe(text: str) -> str:
    # nothing a comment holds may end it early or form a trigraph
    return text.replace("*/", "* /").replace("??", "? ?")


@dataclass
class Writer:
    names: Names
    drawing: Callable[[int], list[str]]  # rung index -> the rung's drawing lines
    lines: list[str] = field(default_factory=list)
    helpers: set[str] = field(default_factory=set)
    tables: list[tuple[int, ...]] = field(default_factory=list)
    used: set[str] = field(default_factory=set)  # C names of the storage the code touches
    hooks: set[str] = field(default_factory=set)  # the user's runtime functions it calls
    targets: set[str] = field(default_factory=set)  # labels something jumps to
    calls: int = 0  # return sites so far
    returns: bool = False  # a RETURN or ENDSUB was written (it may come with no GOSUB left to reach it)
    keeps: int = 0  # the most temporaries one call keeps

    def line(self, text: str, depth: int = 1) -> None:
        self.lines.append("    " * depth + text)

    def helper(self, name: str) -> str:
        self.helpers.add(name)
        return name

    # --- values ------------------------------------------------------------------

    def value(self, operand: ir.Operand) -> str:
        """An int32_t expression."""
        if isinstance(operand, ir.Const):
            return c_constant(operand.value)
        if isinstance(operand, ir.Byte):
            return f"(int32_t)(((uint32_t){self.var(operand.var)} >> {8 * operand.index}) & 0xFFu)"
        return f"(int32_t){self.var(operand)}"

    def unsigned(self, operand: ir.Operand) -> str:
        if isinstance(operand, ir.Const):
            return f"(uint32_t){c_constant(operand.value)}"
        return f"(uint32_t){self.value(operand)}"

    def var(self, var: ir.Var) -> str:
        name = self.names.vars[var.name]
        self.used.add(name)
        return name

    def store(self, target: ir.Place, expression: str, depth: int = 1) -> None:
        """target := the uint32_t `expression`, wrapped to its width."""
        sext = self.helper("ld_sext")
        if isinstance(target, ir.Byte):
            var, shift = target.var, 8 * target.index
            name = self.var(var)
            merged = (f"((uint32_t){name} & ~(UINT32_C(0xFF) << {shift})) | "
                      f"((({expression}) & 0xFFu) << {shift})")
            self.line(f"{name} = ({C_TYPES[var.size]}){sext}({merged}, {8 * var.size});", depth)
        else:
            self.line(f"{self.var(target)} = ({C_TYPES[target.size]}){sext}({expression}, {8 * target.size});", depth)

    # --- bits --------------------------------------------------------------------

    def read(self, bit: ir.Bit) -> str:
        text = self.names.read_bit(bit)
        (self.hooks if text.endswith("()") else self.used).add(text.removesuffix("()"))
        return text

    def write(self, bit: ir.Bit, value: str, depth: int = 1) -> None:
        text = self.names.write_bit(bit, value)
        if text.startswith("Write_"):
            self.hooks.add(text.split("(")[0])
        else:
            self.used.add(self.names.bits[bit.name])
        self.line(text, depth)

    def goto(self, label: str) -> str:
        self.targets.add(label)
        return f"goto {label_name(label)};"


def label_name(label: str) -> str:
    return re.sub(r"[^A-Za-z0-9_]", "_", label)


# --- the patterns ---------------------------------------------------------------------

def _note(w: Writer, op: ir.Note) -> None:
    if op.rung is None:
        w.line(f"/* {comment_safe(op.text)} */")
        return
    w.lines.append("")
    w.line(f"/* {comment_safe(op.text)}")
    for text in w.drawing(op.rung):
        w.line(f" * {comment_safe(text)}".rstrip())
    w.line(" */")


_C_RANGES = {1: (-128, 127), 2: (-32768, 32767)}  # of SBYTE and SWORD; a wider C type holds every constant
_RELATIONS = {"==": int.__eq__, "!=": int.__ne__, "<": int.__lt__, ">=": int.__ge__, ">": int.__gt__,
              "<=": int.__le__}


def _constant_outcome(op: ir.JumpIf) -> bool | None:
    """A variable compared with a constant its C type cannot hold always
    compares the same way (and C warns of such a comparison)."""
    for var, const, flip in ((op.a, op.b, False), (op.b, op.a, True)):
        if isinstance(var, ir.Var) and isinstance(const, ir.Const) and var.size in _C_RANGES:
            low, high = _C_RANGES[var.size]
            if not low <= const.value <= high:
                sample = low if const.value > high else high
                a, b = (const.value, sample) if flip else (sample, const.value)
                return _RELATIONS[op.rel](a, b)
    return None


def _jump_if(w: Writer, op: ir.JumpIf) -> None:
    outcome = _constant_outcome(op)
    if outcome is None:
        w.line(f"if ({w.value(op.a)} {op.rel} {w.value(op.b)}) {w.goto(op.target)}")
    elif outcome:
        w.line(w.goto(op.target))


def _jump_if_bit_of(w: Writer, op: ir.JumpIfBitOf) -> None:
    test = f"{w.helper('ld_bit')}({w.value(op.a)}, {w.value(op.index)})"
    w.line(f"if ({'' if op.value else '!'}{test}) {w.goto(op.target)}")


def _call(w: Writer, op: ir.Call) -> None:
    w.calls += 1
    keep = sorted(op.keep, key=lambda b: b.name)
    w.keeps = max(w.keeps, len(keep))
    w.line(f"if (ld_sp >= {STACK_DEPTH}) return; /* GOSUB nested too deep: this scan ends here */")
    w.line(f"ld_stack[ld_sp] = {w.calls};")
    for i, bit in enumerate(keep):
        w.line(f"ld_kept[ld_sp][{i}] = {w.read(bit)};")
    w.line("ld_sp++;")
    w.line(w.goto(op.target))
    w.lines.append(f"ld_return{w.calls}:;")
    for i, bit in enumerate(keep):
        w.write(bit, f"ld_kept[ld_sp][{i}]")


def _return(w: Writer, op: ir.Return) -> None:
    w.returns = True
    w.line(w.goto("ld_dispatch"))


def _bit_op(w: Writer, op) -> None:
    src = ("!" if getattr(op, "invert", False) else "") + w.read(op.src)
    if isinstance(op, ir.CopyBit):
        w.write(op.dst, src)
    else:
        w.write(op.dst, f"{w.read(op.dst)} {'&&' if isinstance(op, ir.AndBit) else '||'} {src}")


def _move(w: Writer, op: ir.Move) -> None:
    if isinstance(op.src, ir.Const) and isinstance(op.dst, ir.Var):
        half = 1 << (8 * op.dst.size - 1)
        w.line(f"{w.var(op.dst)} = {c_constant(((op.src.value + half) & (2 * half - 1)) - half)};")
    else:
        w.store(op.dst, w.unsigned(op.src))


_ARITH = {"add": "+", "sub": "-", "mul": "*", "and": "&", "or": "|", "xor": "^"}


def _arith(w: Writer, op: ir.Arith) -> None:
    symbol = _ARITH[op.op]
    if op.overflow is None:
        w.store(op.dst, f"{w.unsigned(op.a)} {symbol} {w.unsigned(op.b)}")
        return
    # the exact result, taken before the store (the destination may be an operand)
    w.line("{")
    w.line(f"int64_t r = (int64_t){w.value(op.a)} {symbol} (int64_t){w.value(op.b)};", 2)
    w.store(op.dst, "(uint32_t)r", 2)
    w.line(f"if (!{w.helper('ld_fits')}(r, {8 * op.dst.size})) {{", 2)
    w.write(op.overflow, "1", 3)
    w.line("}", 2)
    w.line("}")


def _change_bit(w: Writer, op: ir.ChangeBitOf) -> None:
    change = "| (UINT32_C(1) << i)" if op.value else "& ~(UINT32_C(1) << i)"
    _guarded(w, f"int32_t i = {w.value(op.index)};", f"i >= 0 && i < {8 * op.dst.size}", op.dst,
             f"{w.unsigned(op.dst)} {change}")


def _divide(w: Writer, op: ir.Divide) -> None:
    w.line("{")
    w.line(f"int32_t d = {w.value(op.b)};", 2)
    w.line("if (d != 0) { /* the simulator stops at a division by zero; here it changes nothing */", 2)
    w.line(f"int64_t n = {w.value(op.a)};", 3)
    w.store(op.dst, f"(uint32_t)(n {'/' if op.op == 'div' else '%'} d)", 3)
    if op.remainder is not None:
        w.store(op.remainder, "(uint32_t)(n % d)", 3)
    w.line("}", 2)
    w.line("}")


def _unary(w: Writer, op: ir.Unary) -> None:
    w.store(op.dst, f"0u - {w.unsigned(op.a)}" if op.op == "neg" else f"~{w.unsigned(op.a)}")


def _shift(w: Writer, op: ir.Shift) -> None:
    bits, count = 8 * op.width, w.value(op.count)
    if op.op == "shr":
        w.store(op.dst, f"{w.helper('ld_shr')}({w.value(op.a)}, {count})")
    else:
        w.store(op.dst, f"{w.helper('ld_' + op.op)}({w.unsigned(op.a)}, {count}, {bits})")


def _guarded(w: Writer, declaration: str, condition: str, dst: ir.Place, expression: str) -> None:
    """{ declaration; if (condition) dst := expression; }: the C of an op the simulator stops at
    for some values, which leaves its destination as it was there."""
    w.line("{")
    w.line(declaration, 2)
    w.line(f"if ({condition}) {{", 2)
    w.store(dst, expression, 3)
    w.line("}", 2)
    w.line("}")


def _convert(w: Writer, op: ir.Convert) -> None:
    if op.op == "bin2bcd":
        _guarded(w, f"int32_t v = {w.value(op.src)};", "v >= 0 && v <= 9999", op.dst, f"{w.helper('ld_bin2bcd')}(v)")
    elif op.op == "bcd2bin":
        _guarded(w, f"uint32_t v = {w.unsigned(op.src)};", f"{w.helper('ld_bcd_ok')}(v)", op.dst,
                 f"{w.helper('ld_bcd2bin')}(v)")
    elif op.op == "swap":
        w.store(op.dst, f"{w.helper('ld_swap')}({w.unsigned(op.src)}, {op.width})")
    else:
        w.store(op.dst, f"{w.helper('ld_opposite')}({w.unsigned(op.src)}, {8 * op.width})")


def _table(w: Writer, op: ir.Table) -> None:
    w.tables.append(op.values)
    _guarded(w, f"int32_t i = {w.value(op.index)};", f"i >= 0 && i < {len(op.values)}", op.dst,
             f"(uint32_t)ld_table{len(w.tables)}[i]")


def _permute(w: Writer, op: ir.Permute) -> None:
    source = w.unsigned(op.src)
    terms = [f"((({source} >> {min(s, 31)}) & 1u) << {d})" for s, d in op.pairs]
    w.store(op.dst, " | ".join(terms) or "0u")


def _hook(w: Writer, name: str) -> str:
    w.hooks.add(name)
    return name


def _read_adc(w: Writer, op: ir.ReadAdc) -> None:
    hook = _hook(w, f"Read_Ub_{w.names.vars[op.dst.name].split('_', 1)[1]}")
    w.store(op.dst, f"(uint32_t)(int32_t){hook}()")


def _pwm_hook(w: Writer, unit: str) -> str:
    return _hook(w, f"Write_{w.names.bits[unit]}")


def _set_pwm(w: Writer, op: ir.SetPwm) -> None:
    duty = f"(SWORD){w.helper('ld_sext')}({w.unsigned(op.duty)}, 16)"
    w.line(f"{_pwm_hook(w, op.unit)}({duty}); /* duty out of {op.full}, {op.freq} Hz */")


def _uart_send(w: Writer, op: ir.UartSend) -> None:
    if op.wait:
        w.line(f"while (!{_hook(w, 'UART_Transmit_Ready')}()) {{ }}")
    w.line(f"{_hook(w, 'UART_Transmit')}((unsigned char)({w.unsigned(op.value)} & 0xFFu));")


def _uart_take(w: Writer, op: ir.UartTake) -> None:
    if op.wait:
        w.line(f"while (!{_hook(w, 'UART_Receive_Avail')}()) {{ }}")
    w.store(op.dst, f"(uint32_t){_hook(w, 'UART_Receive')}()")


def _eeprom_load(w: Writer, op: ir.EepromLoad) -> None:
    read = _hook(w, "EEPROM_read")
    parts = [f"((uint32_t){read}({op.address + i}) << {8 * i})" for i in range(op.var.size)]
    w.store(op.var, " | ".join(parts))


def _eeprom_save(w: Writer, op: ir.EepromSave) -> None:
    # one differing byte written per scan, when the EEPROM is idle
    read, write = _hook(w, "EEPROM_read"), _hook(w, "EEPROM_write")
    w.line(f"if (!{_hook(w, 'EEPROM_busy')}()) {{")
    for i in range(op.var.size):
        byte = f"(unsigned char)(({w.unsigned(op.var)} >> {8 * i}) & 0xFFu)"
        w.line(f"{'} else ' if i else ''}if ({read}({op.address + i}) != {byte}) {{", 2)
        w.line(f"{write}({op.address + i}, {byte});", 3)
    w.line("}", 2)
    w.line("}")


def _delay(w: Writer, op: ir.Delay) -> None:
    if isinstance(op.amount, ir.Const) and op.amount.value <= 0:
        return
    w.line(f"{_hook(w, 'delay_us')}({w.value(op.amount)});")


PATTERNS = {
    ir.Label: lambda w, op: w.lines.append(f"{label_name(op.name)}:;"),
    ir.Note: _note,
    ir.Jump: lambda w, op: w.line(w.goto(op.target)),
    ir.JumpIfBit: lambda w, op: w.line(f"if ({'' if op.value else '!'}{w.read(op.bit)}) {w.goto(op.target)}"),
    ir.JumpIf: _jump_if,
    ir.JumpIfBitOf: _jump_if_bit_of,
    ir.Call: _call,
    ir.Return: _return,
    ir.SetBit: lambda w, op: w.write(op.dst, "1" if op.value else "0"),
    ir.CopyBit: _bit_op,
    ir.AndBit: _bit_op,
    ir.OrBit: _bit_op,
    ir.Move: _move,
    ir.Arith: _arith,
    ir.ChangeBitOf: _change_bit,
    ir.Divide: _divide,
    ir.Unary: _unary,
    ir.Shift: _shift,
    ir.Convert: _convert,
    ir.Table: _table,
    ir.Permute: _permute,
    ir.ReadAdc: _read_adc,
    ir.SetPwm: _set_pwm,
    ir.PwmOff: lambda w, op: w.line(f"{_pwm_hook(w, op.unit)}(0);"),
    ir.UartSend: _uart_send,
    ir.UartReady: lambda w, op: w.write(op.dst, f"{_hook(w, 'UART_Transmit_Ready')}()"),
    ir.UartAvailable: lambda w, op: w.write(op.dst, f"{_hook(w, 'UART_Receive_Avail')}()"),
    ir.UartTake: _uart_take,
    ir.EepromLoad: _eeprom_load,
    ir.EepromSave: _eeprom_save,
    ir.Delay: _delay,
    ir.ClearWatchdog: lambda w, op: w.lines.extend(["#ifdef USE_WDT", "    WDT_restart();", "#endif"]),
    ir.Halt: lambda w, op: w.line("for (;;) { } /* LOCK: the watchdog resets the MCU */"),
}


def write_ops(w: Writer, ops: list[ir.Op]) -> None:
    for op in ops:
        PATTERNS[type(op)](w, op)
