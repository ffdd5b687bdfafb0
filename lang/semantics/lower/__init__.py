"""The lowering: a checked ladder Program becomes intermediate code.

Rungs run top to bottom, each on a fresh power bit; series are evaluated
left to right on it, parallels branch by branch from a copy of their input.
Every rung has a label, so GOTO and GOSUB jump to rungs; what LDmicro sets
before the first scan (counter start values, TOF accumulators, random seeds)
is `Code.init`. The simulator and every back end run this code: it is the
one definition of what each instruction does (docs/semantics.md).
"""

from __future__ import annotations

from lang import trampoline
from lang.codes import code
from lang.devices import Device
from lang.families import Family, family_of
from lang.instructions import COUNTERS, JUMPS
from lang.labels import describe
from lang.model import Element, Program, Series
from lang.storage import DEFAULT_SEED, counter_defs, variable_names
from lang.values import as_int, is_literal, literal_value

from .. import ir
from ..errors import JUMP, OPERAND, UNSUPPORTED, fail
from ..operands import operand_refusal
from . import io, logic, math, pulses, sfr, stepper, timers  # noqa: F401  (they register the lowerings)
from .builder import LOWERINGS, Builder

# the 16-bit addresses of LDmicro's EEPROM_read()/EEPROM_write() hooks
C_EEPROM_BYTES = 65536


def rung_label(index: int) -> str:
    return f"rung{index + 1}"


class Jumps:
    """Where GOTO, GOSUB and the end of a SUBPROG's body go, as rung labels
    (the first LABEL, SUBPROG or ENDSUB of a label counts; `repeated` holds
    the others)."""

    def __init__(self, program: Program, elements: list[tuple[int, Element]]):
        self.count = len(program.rungs)
        self.labels: dict[str, int] = {}
        self.subprogs: dict[str, int] = {}
        self.endsubs: dict[str, int] = {}
        self.repeated: list[Element] = []
        self._subprog_elements: dict[str, Element] = {}
        tables = {"LABEL": self.labels, "SUBPROG": self.subprogs, "ENDSUB": self.endsubs}
        for rung, element in elements:
            table = tables.get(element.kind)
            if table is None:
                continue
            label = str(element.args.get("label", ""))
            if label in table:
                self.repeated.append(element)
                continue
            table[label] = rung
            if element.kind == "SUBPROG":
                self._subprog_elements[label] = element

    def unended(self) -> list[Element]:
        """The SUBPROGs with no ENDSUB of their label."""
        return [e for label, e in self._subprog_elements.items() if label not in self.endsubs]

    def goto_target(self, element: Element) -> str:
        label = str(element.args["label"])
        if is_literal(label):
            # a rung number, clamped to 1..rungs+1 as LDmicro does (rungs+1 = end of scan)
            number = literal_value(label)
            return rung_label(min(max(number, 1), self.count + 1) - 1)
        if label not in self.labels:
            raise fail(JUMP, f"GOTO: LABEL '{label}' not found", element, check=code("LD207"))
        return rung_label(self.labels[label])

    def gosub_target(self, element: Element) -> str:
        label = str(element.args["label"])
        if is_literal(label):
            raise fail(JUMP, f"GOSUB: SUBPROG as a number '{label}' is not allowed", element, check=code("LD209"))
        if label not in self.subprogs:
            raise fail(JUMP, f"GOSUB: SUBPROG '{label}' not found", element, check=code("LD208"))
        return rung_label(self.subprogs[label] + 1)

    def after_endsub(self, element: Element) -> str:
        label = str(element.args["label"])
        if label not in self.endsubs:
            raise fail(JUMP, f"SUBPROG: ENDSUB '{label}' not found", element, check=code("LD205"))
        return rung_label(self.endsubs[label] + 1)


class PartBuilder(Builder):
    """The builder with what lowering needs to know of the target: which
    instructions its family compiles, which A/D channel and which PWM unit a
    name's pin is, how long the back end's delay loop takes. With no device
    (C) the user's runtime owns the peripherals: an A/D reading or a PWM
    output is known by its name, and the EEPROM has no size of ours to check."""

    def __init__(self, program: Program, elements: list[tuple[int, Element]], device: Device | None,
                 family: Family, delay_loop_cycles: int, bits, sizes, classes, trace: bool = False):
        super().__init__(program, [e for _, e in elements], bits, sizes, classes)
        self.trace = trace
        # the simulator, which traces, shows the flag with every other variable
        self.overflow_read = self.overflow_read or trace
        self.device = device
        self.family = family
        self.delay_loop_cycles = delay_loop_cycles
        self.eeprom_size = device.memory.get("eeprom", 0) if device is not None else C_EEPROM_BYTES
        self.jumps = Jumps(program, elements)
        self.counter_defs = counter_defs(program)

    def lower(self, element: Element, power: ir.Bit) -> None:
        self.element = element
        self.position += 1
        self.emit(ir.Note(describe(element), element=element))
        if not element.spec.supports(self.family.key) or element.kind not in LOWERINGS:
            raise fail(UNSUPPORTED, f"{element.kind} cannot be compiled for {self.family.title}", element)
        refused = operand_refusal(element, self.size)
        if refused:
            raise fail(OPERAND, refused, element)
        # a jump leaves the element's code at once: its power is traced before
        jumps = element.kind in JUMPS
        if self.trace and jumps:
            self.emit(ir.Trace(power))
        LOWERINGS[element.kind](self, element, power)
        if self.trace and not jumps:
            self.emit(ir.Trace(power))

    def _pin(self, device: Device, name: str):
        assignment = self.program.pins.get(name)
        pin = device.pin(assignment.pin) if assignment is not None else None
        if pin is None:
            raise fail(UNSUPPORTED, f"'{name}' has no pin of the {device.title}", self.element)
        return pin

    def adc_channel(self, name: str) -> int:
        if self.device is None:
            return 0
        pin = self._pin(self.device, name)
        if pin.name not in self.device.adc:
            raise fail(UNSUPPORTED, f"'{name}' is on {pin.name}, which has no A/D channel", self.element)
        return self.device.adc[pin.name]

    def pwm_unit(self, name: str) -> str:
        if self.device is None:
            return name
        pin = self._pin(self.device, name)
        if pin.name not in self.device.pwm:
            raise fail(UNSUPPORTED, f"'{name}' is on {pin.name}, which has no PWM output", self.element)
        return self.device.pwm[pin.name]


def _circuit(b: PartBuilder, node, p: ir.Bit, tail: bool) -> trampoline.Call[None]:
    """A generator run by lang.trampoline: blocks may nest deeper than
    Python's recursion limit."""
    if isinstance(node, Element):
        b.lower(node, p)
    elif isinstance(node, Series):
        for i, item in enumerate(node.items):
            yield _circuit(b, item, p, tail and i == len(node.items) - 1)
    else:
        # every branch sees the parallel's input; a branch's side effects
        # are visible to the branches below it; nothing follows a parallel
        # that ends its rung, so its output is not needed there
        out = None if tail else b.temp()
        if out:
            b.emit(ir.SetBit(out, False))
        for branch in node.branches:
            bp = b.temp()
            b.emit(ir.CopyBit(bp, p))
            yield _circuit(b, branch, bp, out is None)
            if out:
                b.emit(ir.OrBit(out, bp))
        if out:
            b.emit(ir.CopyBit(p, out))


def _initial_values(b: PartBuilder, elements: list[tuple[int, Element]]) -> list[ir.Op]:
    """What LDmicro's INIT VARS block sets before the first scan, in program
    order so that the last one wins (docs/semantics.md, "Start values")."""
    ops: list[ir.Op] = []
    for _, element in elements:
        b.element = element
        kind = element.kind
        if kind in COUNTERS and is_literal(str(element.args.get("init", "0"))):
            name = str(element.args["name"])
            ops.append(ir.Move(b.var(name), ir.Const(b.literal(element.args.get("init", "0")))))
        elif kind == "TOF":
            name, delay = str(element.args["name"]), element.args["delay"]
            t = b.var(name)
            if isinstance(delay, int):
                ops.append(ir.Move(t, ir.Const(b.period(delay, as_int(element.args.get("adjust", 0) or 0), name))))
            else:
                # LDmicro cannot start a variable-delay TOF; start it expired
                ops.append(ir.Move(t, ir.Const((1 << (8 * t.size - 1)) - 1)))
        elif kind == "SEED_RANDOM":
            ops.append(ir.Move(ir.Var(f"$seed_{element.args['name']}", 4), ir.Const(DEFAULT_SEED)))
    return ops


def _classes(names) -> dict[str, str]:
    return {name: ir.INPUT if name[0] == "X" else ir.OUTPUT for name in names if name[:1] in ("X", "Y")}


def lower_program(program: Program, device: Device | None, delay_loop_cycles: int,
                  family: Family | None = None, trace: bool = False) -> ir.Code:
    """The program's intermediate code for a part of a compiled family (or,
    with no device, for `family`: C, or the simulator), whose back end's
    variable delay loop takes `delay_loop_cycles` per count; with `trace`,
    each element's output power is recorded (`ir.Trace`) and the overflow
    flag kept even when no contact reads it, as the simulator needs."""
    bits, sizes = variable_names(program)
    family = family or (family_of(device) if device is not None else None)
    assert family is not None, "a part of a compiled family, or the family to lower for"
    # on a part the X and Y names with pins are I/O; in C every one is (the user's runtime reads and writes it)
    pinned = [name for name, pin in program.pins.items() if pin.assigned] if device is not None else bits
    elements = list(program.elements())
    b = PartBuilder(program, elements, device, family, delay_loop_cycles, bits, sizes, _classes(pinned), trace)
    mcr = any(e.kind == "MASTER_RELAY" for _, e in elements)
    if mcr:
        b.emit(ir.SetBit(b.bit("$mcr"), True))
    for index, rung in enumerate(program.rungs):
        b.rung, b.position = index, -1
        b.place(rung_label(index))
        if rung.is_comment or not rung.circuit.items:
            continue
        b.emit(ir.Note(f"rung {index + 1}", rung=index))
        p = b.temp()
        b.emit(ir.CopyBit(p, b.bit("$mcr")) if mcr else ir.SetBit(p, True))
        trampoline.run(_circuit(b, rung.circuit, p, True))
    b.place(rung_label(len(program.rungs)))
    init = _initial_values(b, elements)
    return ir.Code(b.ops, init, b.bits, b.vars, b.eeprom)
