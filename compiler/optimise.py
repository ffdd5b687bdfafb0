"""Optimising the intermediate code before it is lowered to a target, in its
flat form (`ir.flatten`: labels, jumps and conditional jumps).

* Known bits: a forward pass tracks which temporary and memory bits have a
  known value (the rung starts powered; after a conditional jump on a bit,
  both paths know it) and folds the bit operations and tests they decide.
* Constant folding: integer operations and comparisons of constants.
* Copies: a temporary that is a copy of another bit is read as that bit,
  within straight-line code while neither changes.
* Dead temporaries: a backward liveness pass deletes writes of temporary
  bits nothing reads, and records on each Call the temporaries that must
  survive it.
* Jumps: jumps to the next op, jumps to jumps, unreachable code and unused
  labels go.

Packing bits into bytes and keeping values in registers are the back end's
part (compiler/avr/memory.py, compiler/avr/select.py).
"""

from __future__ import annotations

from dataclasses import replace

from lang.numbers import cdiv, cmod, wrap
from lang.semantics import ir

_ENDS = (ir.Jump, ir.Return, ir.Halt)


def optimise(code: ir.Code, rungs_by_jumps: bool = False) -> ir.Code:
    ops = _settled(ir.flatten(code.scan), code.bits, False)
    if rungs_by_jumps:
        ops = _settled(_bits_as_jumps(ops, code.bits), code.bits, True)
    return replace(code, scan=ops, init=_fold_constants(code.init))


def _settled(ops: list[ir.Op], classes: dict[str, str], by_jumps: bool) -> list[ir.Op]:
    while True:
        before = ops
        ops = _fold_constants(ops)
        ops = _known_bits(ops, classes)
        ops = _copies(ops, classes)
        if by_jumps:
            ops = _decided_tests_copied(_jumps_over_jumps(ops), classes)
        ops = _jumps(ops)
        ops = _dead_temporaries(ops, classes)
        if ops == before:
            return ops


# --- control flow helpers ------------------------------------------------------------

def _target(op: ir.Op) -> str | None:
    return op.target if isinstance(op, ir.JUMPS) else None


def _label_positions(ops: list[ir.Op]) -> dict[str, int]:
    return {op.name: i for i, op in enumerate(ops) if isinstance(op, ir.Label)}


# --- constants ---------------------------------------------------------------------------

_ARITH = {"add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b,
          "and": lambda a, b: a & b, "or": lambda a, b: a | b, "xor": lambda a, b: a ^ b}
_RELATE = {"==": lambda a, b: a == b, "!=": lambda a, b: a != b, "<": lambda a, b: a < b,
           "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b}


def _fold_constants(ops: list[ir.Op]) -> list[ir.Op]:
    out: list[ir.Op] = []
    for op in ops:
        if isinstance(op, ir.Arith) and isinstance(op.a, ir.Const) and isinstance(op.b, ir.Const):
            exact = _ARITH[op.op](op.a.value, op.b.value)
            out.append(ir.Move(op.dst, ir.Const(wrap(exact, op.dst.size))))
            if op.overflow is not None and wrap(exact, op.dst.size) != exact and op.op in ("add", "sub"):
                out.append(ir.SetBit(op.overflow, True))
        elif isinstance(op, ir.Divide) and isinstance(op.a, ir.Const) and isinstance(op.b, ir.Const) \
                and op.b.value and op.remainder is None:
            value = (cdiv if op.op == "div" else cmod)(op.a.value, op.b.value)
            out.append(ir.Move(op.dst, ir.Const(wrap(value, op.dst.size))))
        elif isinstance(op, ir.Unary) and isinstance(op.a, ir.Const):
            value = -op.a.value if op.op == "neg" else ~op.a.value
            out.append(ir.Move(op.dst, ir.Const(wrap(value, op.dst.size))))
        elif isinstance(op, ir.JumpIf) and isinstance(op.a, ir.Const) and isinstance(op.b, ir.Const):
            if _RELATE[op.rel](op.a.value, op.b.value):
                out.append(ir.Jump(op.target))
        else:
            out.append(op)
    return out


# --- known bits ------------------------------------------------------------------------------

def _known_bits(ops: list[ir.Op], classes: dict[str, str]) -> list[ir.Op]:
    """Forward pass; `known` maps a bit to its value on the path being
    followed. A label merges what every jump to it and the fall-through
    know; a label reached by a backward jump knows nothing. A jump to a test
    of a bit its path knows goes straight where the test leads (and so does
    a path falling into one)."""
    tracked = {name for name, kind in classes.items() if kind in (ir.TEMP, ir.MEMORY)}
    ops = _labels_after_bit_tests(ops)
    positions = _label_positions(ops)
    # labels entered by a backward jump or a call: nothing is known there
    backward = {op.target for i, op in enumerate(ops) if isinstance(op, ir.JUMPS) and positions[op.target] <= i}
    backward |= {op.target for op in ops if isinstance(op, ir.Call)}
    incoming: dict[str, list[dict]] = {}
    out: list[ir.Op] = []
    known: dict | None = {}  # None: this point cannot be reached by falling through

    def merge(states: list[dict]) -> dict:
        first, *rest = states
        return {bit: value for bit, value in first.items() if all(s.get(bit) == value for s in rest)}

    def thread(label: str, state: dict, here: int) -> str:
        """Where a path knowing `state` that jumps to `label` really goes
        (forward only: the backward jumps stay as they are)."""
        for _ in range(len(ops)):
            i = positions[label]
            while i < len(ops) and isinstance(ops[i], (ir.Label, ir.Note)):
                i += 1
            test = ops[i] if i < len(ops) else None
            if not isinstance(test, ir.JumpIfBit) or test.bit.name not in state:
                return label
            past = ops[i + 1]
            assert isinstance(past, ir.Label)  # _labels_after_bit_tests put it there
            after = test.target if state[test.bit.name] == test.value else past.name
            if positions[after] <= here:
                return label
            label = after
        return label

    for i, op in enumerate(ops):
        if isinstance(op, ir.Label):
            if known is not None and op.name not in backward:
                ahead = thread(op.name, known, i)
                if ahead != op.name:
                    incoming.setdefault(ahead, []).append(known)
                    out.append(ir.Jump(ahead))
                    known = None
            states = incoming.pop(op.name, []) + ([known] if known is not None else [])
            known = {} if op.name in backward or not states else merge(states)
            out.append(op)
            continue
        if known is None:
            out.append(op)  # unreachable; _jumps removes it
            continue
        folded = _fold_bit_op(op, known)
        if folded is None:
            continue
        op = folded
        if isinstance(op, ir.JumpIfBit):
            taken = dict(known)
            if op.bit.name in tracked:
                taken[op.bit.name] = op.value
                known[op.bit.name] = not op.value
            op = replace(op, target=thread(op.target, taken, i))
            incoming.setdefault(op.target, []).append(taken)
        elif isinstance(op, ir.JUMPS):
            op = replace(op, target=thread(op.target, known, i))
            incoming.setdefault(op.target, []).append(dict(known))
            if isinstance(op, ir.Jump):
                known = None
        elif isinstance(op, (ir.Return, ir.Halt)):
            known = None
        elif isinstance(op, ir.Call):
            # the subroutine may change any memory bit; the temporaries it
            # must keep are saved around it
            known = {bit: value for bit, value in known.items() if ir.Bit(bit) in op.keep}
        else:
            _learn(op, known, tracked)
        out.append(op)
    return out


def _labels_after_bit_tests(ops: list[ir.Op]) -> list[ir.Op]:
    """A label after every bit test, for jumps threaded past it (_jumps
    removes the unused ones)."""
    out: list[ir.Op] = []
    count = max((int(op.name[4:]) for op in ops if isinstance(op, ir.Label) and op.name.startswith("past")),
                default=0)
    for i, op in enumerate(ops):
        out.append(op)
        if isinstance(op, ir.JumpIfBit) and not (i + 1 < len(ops) and isinstance(ops[i + 1], ir.Label)):
            count += 1
            out.append(ir.Label(f"past{count}"))
    return out


def _fold_bit_op(op: ir.Op, known: dict) -> ir.Op | None:
    """The op simplified by what is known, or None when it does nothing."""
    def value(bit: ir.Bit):
        return known.get(bit.name)

    if isinstance(op, ir.SetBit):
        return None if value(op.dst) == op.value else op
    if isinstance(op, ir.CopyBit):
        src = value(op.src)
        if src is not None:
            return _fold_bit_op(ir.SetBit(op.dst, src != op.invert), known)
        return None if op.src == op.dst and not op.invert else op
    if isinstance(op, ir.AndBit):
        src, dst = value(op.src), value(op.dst)
        if src is not None:
            return None if src != op.invert else _fold_bit_op(ir.SetBit(op.dst, False), known)
        if dst is False:
            return None
        if dst is True:
            return ir.CopyBit(op.dst, op.src, op.invert)
        return op
    if isinstance(op, ir.OrBit):
        src, dst = value(op.src), value(op.dst)
        if src is not None:
            return None if not src else _fold_bit_op(ir.SetBit(op.dst, True), known)
        if dst is True:
            return None
        if dst is False:
            return ir.CopyBit(op.dst, op.src)
        return op
    if isinstance(op, ir.JumpIfBit):
        bit = value(op.bit)
        if bit is not None:
            return ir.Jump(op.target) if bit == op.value else None
    return op


def _learn(op: ir.Op, known: dict, tracked: set[str]) -> None:
    """Update `known` after an op that does not jump."""
    if isinstance(op, ir.SetBit):
        if op.dst.name in tracked:
            known[op.dst.name] = op.value
        return
    if isinstance(op, ir.Arith) and op.overflow is not None:
        if not known.get(op.overflow.name):
            known.pop(op.overflow.name, None)
        return
    for bit in op.writes():
        known.pop(bit.name, None)


# --- jumps ---------------------------------------------------------------------------------

def _jumps(ops: list[ir.Op]) -> list[ir.Op]:
    # where each label really leads: past other labels and notes, and
    # through unconditional jumps
    positions = _label_positions(ops)

    def resolve(label: str) -> str:
        seen = set()
        while label not in seen:
            seen.add(label)
            i = positions[label]
            while i < len(ops) and isinstance(ops[i], (ir.Label, ir.Note)):
                i += 1
            jump = ops[i] if i < len(ops) else None
            if isinstance(jump, ir.Jump):
                label = jump.target
            else:
                break
        return label

    threaded = [replace(op, target=resolve(op.target)) if isinstance(op, ir.JUMPS) else op for op in ops]
    # drop what no path reaches, and jumps to the op after them
    kept: list[ir.Op] = []
    reachable = True
    for i, op in enumerate(threaded):
        if isinstance(op, ir.Label):
            reachable = True
        if not reachable and not isinstance(op, ir.Note):
            continue
        target = _target(op)
        if target and _falls_to(threaded, i + 1, target):
            continue
        kept.append(op)
        if isinstance(op, _ENDS):
            reachable = False
    used = {_target(op) for op in kept if _target(op)} | {op.target for op in kept if isinstance(op, ir.Call)}
    return [op for op in kept if not isinstance(op, ir.Label) or op.name in used or op.name.startswith("rung")]


def _falls_to(ops: list[ir.Op], start: int, label: str) -> bool:
    """Whether falling through from `start` reaches `label` before any code."""
    for index in range(start, len(ops)):  # by index: a slice would copy the rest, quadratic overall
        op = ops[index]
        if isinstance(op, ir.Label):
            if op.name == label:
                return True
        elif not isinstance(op, ir.Note):
            return False
    return False


# --- dead temporaries --------------------------------------------------------------------------

_PURE_BIT_OPS = (ir.SetBit, ir.CopyBit, ir.AndBit, ir.OrBit, ir.UartReady, ir.UartAvailable)


def _copies(ops: list[ir.Op], classes: dict[str, str]) -> list[ir.Op]:
    """Reads of a temporary that is a copy of another bit read that bit, and
    the copy often dies: within straight-line code, until either is written
    (a copy of an input pin only when it is read once)."""
    temps = {name for name, kind in classes.items() if kind == ir.TEMP}
    reads = _use_counts(ops, temps)
    alias: dict[str, tuple[ir.Bit, bool]] = {}  # temporary -> (bit, inverted)
    out: list[ir.Op] = []
    for op in ops:
        if isinstance(op, (ir.Label, ir.Call)):
            alias.clear()
        op = _read_through(op, alias)
        written = {bit.name for bit in op.writes()}
        alias = {t: (b, inv) for t, (b, inv) in alias.items() if t not in written and b.name not in written}
        # a pin may change during the scan: an input is read as often as the
        # program reads it, so only a copy read once may be replaced by it
        if (isinstance(op, ir.CopyBit) and op.dst.name in temps and op.src != op.dst
                and (classes.get(op.src.name) != ir.INPUT or reads[op.dst.name] == 1)):
            alias[op.dst.name] = (op.src, op.invert)
        out.append(op)
    return out


def _use_counts(ops: list[ir.Op], names: set[str]) -> dict[str, int]:
    counts = dict.fromkeys(names, 0)
    for op in ops:
        for bit in op.reads():
            if bit.name in counts:
                counts[bit.name] += 1
    return counts


def _read_through(op: ir.Op, alias: dict) -> ir.Op:
    if isinstance(op, (ir.CopyBit, ir.AndBit)) and op.src.name in alias:
        bit, inv = alias[op.src.name]
        return replace(op, src=bit, invert=op.invert ^ inv)
    if isinstance(op, ir.OrBit) and op.src.name in alias and not alias[op.src.name][1]:
        return replace(op, src=alias[op.src.name][0])
    if isinstance(op, ir.JumpIfBit) and op.bit.name in alias:
        bit, inv = alias[op.bit.name]
        return replace(op, bit=bit, value=op.value ^ inv)
    return op


def _dead_temporaries(ops: list[ir.Op], classes: dict[str, str]) -> list[ir.Op]:
    temps = {name for name, kind in classes.items() if kind == ir.TEMP}
    positions = _label_positions(ops)
    live_in = _liveness(ops, temps, positions)
    out: list[ir.Op] = []
    for i, op in enumerate(ops):
        live_out = frozenset().union(*(live_in[j] for j in _successors(ops, i, positions)))
        if isinstance(op, _PURE_BIT_OPS):
            dst = op.writes()[0].name
            if dst in temps and dst not in live_out:
                continue
        if isinstance(op, ir.Call):
            op = replace(op, keep=frozenset(ir.Bit(name) for name in live_out))
        out.append(op)
    return out


def _successors(ops: list[ir.Op], i: int, positions: dict[str, int]) -> list[int]:
    op = ops[i]
    following = [i + 1] if i + 1 < len(ops) and not isinstance(op, _ENDS) else []
    target = _target(op)
    return following + ([positions[target]] if target else [])


def _liveness(ops: list[ir.Op], temps: set[str], positions: dict[str, int]) -> list[frozenset[str]]:
    """live_in[i]: the temporaries op i or a later one reads before writing."""
    # each op's successors, reads and writes once: the sweeps below repeat until nothing changes
    successors = [_successors(ops, i, positions) for i in range(len(ops))]
    reads = [frozenset(b.name for b in op.reads()) & temps for op in ops]
    # AndBit and OrBit read their destination too
    writes = [frozenset() if isinstance(op, ir.AndBit | ir.OrBit) else frozenset(b.name for b in op.writes()) & temps
              for op in ops]
    live_in: list[frozenset[str]] = [frozenset()] * len(ops)
    changed = True
    while changed:
        changed = False
        for i in range(len(ops) - 1, -1, -1):
            out = frozenset().union(*(live_in[j] for j in successors[i]))
            new = (out - writes[i]) | reads[i]
            if new != live_in[i]:
                live_in[i] = new
                changed = True
    return live_in


# --- rungs evaluated by jumps -------------------------------------------------------------------

def _bits_as_jumps(ops: list[ir.Op], classes: dict[str, str]) -> list[ir.Op]:
    """Each bit operation on a temporary as a test of its source and jumps
    around the writes, so that the known-bits pass threads every path to
    where the rung's state decides it and the state bits die."""
    temps = {name for name, kind in classes.items() if kind == ir.TEMP}
    out: list[ir.Op] = []
    count = 0

    def label() -> str:
        nonlocal count
        count += 1
        return f"bj{count}"

    for op in ops:
        if isinstance(op, ir.AndBit) and op.dst.name in temps:
            keep = label()
            out += [ir.JumpIfBit(op.src, not op.invert, keep), ir.SetBit(op.dst, False), ir.Label(keep)]
        elif isinstance(op, ir.OrBit) and op.dst.name in temps:
            keep = label()
            out += [ir.JumpIfBit(op.src, False, keep), ir.SetBit(op.dst, True), ir.Label(keep)]
        elif isinstance(op, ir.CopyBit) and op.src != op.dst and temps & {op.src.name, op.dst.name}:
            clear, end = label(), label()
            out += [ir.JumpIfBit(op.src, op.invert, clear), ir.SetBit(op.dst, True), ir.Jump(end),
                    ir.Label(clear), ir.SetBit(op.dst, False), ir.Label(end)]
        else:
            out.append(op)
    return out


def _jumps_over_jumps(ops: list[ir.Op]) -> list[ir.Op]:
    """A conditional jump over a jump is the opposite condition's jump; one
    to where the code after it goes anyway is none."""
    positions = _label_positions(ops)
    targets = {_target(op) for op in ops} | {op.target for op in ops if isinstance(op, ir.Call)}

    def code_at(i: int) -> int:
        """The first op at or after i that is not a label or a note."""
        while i < len(ops) and isinstance(ops[i], (ir.Label, ir.Note)):
            i += 1
        return i

    def goes(i: int) -> int:
        """Where the code from i goes first: past a jump too."""
        i = code_at(i)
        jump = ops[i] if i < len(ops) else None
        return code_at(positions[jump.target]) if isinstance(jump, ir.Jump) else i

    out: list[ir.Op] = []
    i = 0
    while i < len(ops):
        op = ops[i]
        if isinstance(op, ir.JumpIfBit | ir.JumpIf | ir.JumpIfBitOf):
            if goes(i + 1) == goes(positions[op.target]):
                i += 1
                continue
            after = code_at(i + 1)
            jump = ops[after] if after < len(ops) else None
            entered = any(isinstance(between, ir.Label) and (between.name in targets or between.name.startswith("rung"))
                          for between in ops[i + 1:after])  # other code jumps to the jump
            if isinstance(jump, ir.Jump) and not entered and _falls_to(ops, after + 1, op.target):
                out += [_opposite(op, jump.target), *ops[i + 1:after]]
                i = after + 1
                continue
        out.append(op)
        i += 1
    return out


def _opposite(op: ir.JumpIfBit | ir.JumpIf | ir.JumpIfBitOf, target: str) -> ir.Op:
    if isinstance(op, ir.JumpIf):
        return replace(op, rel=ir.NEGATED[op.rel], target=target)
    return replace(op, value=not op.value, target=target)


# the longest stretch of code copied to a jump that knows the test at its end
_COPIED_OPS = 24
_QUIET = (ir.Label, ir.Note, ir.Jump, ir.JumpIfBit, ir.JumpIf, ir.JumpIfBitOf, ir.SetBit, ir.CopyBit, ir.AndBit,
          ir.OrBit)


def _decided_tests_copied(ops: list[ir.Op], classes: dict[str, str]) -> list[ir.Op]:
    """A jump after which a temporary's value is known (or a fall-through
    into a label), to code that only tests and writes temporaries before it
    tests that one, is replaced by a copy of that code (tail duplication):
    the known-bits pass then decides the test in the copy, the rest of it
    dies, and a rung's parallel branch that already holds goes straight to
    its coil."""
    temps = {name for name, kind in classes.items() if kind == ir.TEMP}
    ops = _labels_after_bit_tests(ops)
    positions = _label_positions(ops)
    copies = max((int(name[4:]) for name in positions if name.startswith("copy")), default=0)
    out: list[ir.Op] = []
    known: dict[str, bool] = {}
    for i, op in enumerate(ops):
        start = positions[op.target] if isinstance(op, ir.Jump) else i if isinstance(op, ir.Label) else None
        region = _region(ops, start, known, temps) if known and start is not None and start >= i else None
        if start is not None and region is not None:
            renamed = {}
            for label in region:
                if isinstance(label, ir.Label):
                    copies += 1
                    renamed[label.name] = f"copy{copies}"
            out += [ir.Label(renamed[copied.name]) if isinstance(copied, ir.Label)
                    else replace(copied, target=renamed[copied.target])
                    if isinstance(copied, ir.JUMPS) and copied.target in renamed else copied
                    for copied in region if not isinstance(copied, ir.Note)]  # a note marks its rung's one place
            after = ops[start + len(region)]
            assert isinstance(after, ir.Label)  # _region ends before a label
            out.append(ir.Jump(after.name))
            known = {}
            if isinstance(op, ir.Jump):
                continue
        if isinstance(op, (ir.Label, ir.Call, *ir.JUMPS)):
            known = {}
        elif isinstance(op, ir.SetBit) and op.dst.name in temps:
            known[op.dst.name] = op.value
        else:
            for bit in op.writes():
                known.pop(bit.name, None)
        out.append(op)
    return out


def _region(ops: list[ir.Op], start: int, known: dict[str, bool], temps: set[str]) -> list[ir.Op] | None:
    """The code from `start` up to and including the first test of a bit in
    `known`, when it has no side effect but on temporaries, jumps only
    forward within or past itself, and writes no bit of `known` first."""
    labels: set[str] = set()
    for end in range(start, min(len(ops), start + _COPIED_OPS)):
        op = ops[end]
        if not isinstance(op, _QUIET):
            return None
        if isinstance(op, ir.Label):
            if op.name.startswith("rung"):
                return None
            labels.add(op.name)
        if isinstance(op, ir.JUMPS) and op.target in labels:
            return None
        if isinstance(op, ir.JumpIfBit) and op.bit.name in known:
            return ops[start:end + 1] if end + 1 < len(ops) and isinstance(ops[end + 1], ir.Label) else None
        written = {bit.name for bit in op.writes()}
        if written - temps or written & known.keys():
            return None
    return None
