"""Random compilable programs: built for a part simavr (AVR) or gpsim (PIC16)
runs, run under a random stimulus, and compared with the simulator on every
name after every scan (test_compiler_harness.py, pic16_harness.py; the PIC16
sample is tests/test_pic16_random.py). benchmarks/compiler_fuzz.py runs the
same generator for as long as it is given.

The generator draws, for a board of a family, from every instruction that
family's back end compiles (the instruction table's support column) but those
the board leaves out, on small pools of names so that elements read what
others write. A program must pass the checks, and the simulator must run it
through the stimulus without a fault (a division by zero, a table index out
of range, a BCD digit above 9, a runaway jump): the MCU's result is undefined
there.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import cache

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from test_compiler_harness import Event, differential, needs_simavr

from compiler.errors import FLASH_FULL, RAM_FULL, CompileError
from lang.checks import check_program
from lang.diagnostics import ERROR
from lang.instructions import INSTRUCTIONS
from lang.model import (
    Element,
    Parallel,
    PinAssignment,
    Program,
    Rung,
    Series,
    Settings,
    rung_circuit,
)
from lang.sim import SimulationError, Simulator

# instructions of the PIC16 peripherals, not compiled yet
PIC16_PERIPHERALS = frozenset(("READ_ADC", "SET_PWM", "UART_SEND", "UART_SEND_READY", "UART_RECV",
                               "UART_RECV_AVAIL", "FORMATTED_STRING", "PERSIST"))


@dataclass(frozen=True)
class Board:
    """A part as the generator uses it: its family, the port bits it offers
    (inputs the harness can drive), the clock and the cycle."""

    part: str
    family: str  # the instruction table's support key: which instructions compile
    ldmicro: str
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    adc: str | None = None
    pwm: str | None = None
    uart: bool = True  # received bytes are fed to the part's UART (the PIC16 harness feeds none)
    crystal_hz: int = 16_000_000
    cycle_us: int = 4000  # room in the cycle for a long scan and a UART byte's arrival
    left_out: frozenset[str] = frozenset()  # instructions not drawn on this board
    # at most this many 4-byte variables allocated first and never used, so
    # that the program's own land in other RAM banks (PIC16)
    ballast: int = 0
    rungs: int = 8  # at most this many rungs drawn (besides the jumps' and relays')
    widest: int = 4  # the widest variable drawn, in bytes: a small part's draws fit it more often

    def draws(self, kind: str) -> bool:
        if kind == "QUAD_ENCOD" and len(self.inputs) < 2:
            return False  # an encoder needs its A and B inputs
        return self.family in INSTRUCTIONS[kind].support and kind not in self.left_out

    @property
    def input_names(self) -> tuple[str, ...]:
        """The input names the board has pins for."""
        return INPUTS[:len(self.inputs)]

    @property
    def output_names(self) -> tuple[str, ...]:
        return OUTPUTS[:len(self.outputs)]


BOARDS = (
    Board("atmega328p", "avr", "Atmel AVR ATmega328 28-PDIP", ("PD2", "PD3", "PD4", "PD7"),
          ("PB0", "PB1", "PB2", "PB3", "PB4", "PB5"), "PC0", "PD6"),
    Board("atmega16", "avr", "Atmel AVR ATmega16 40-PDIP", ("PD2", "PD3", "PD4", "PD5"),
          ("PB0", "PB1", "PB2", "PC0", "PC1", "PC2"), "PA0", "PB3"),
    Board("atmega128", "avr", "Atmel AVR ATmega128 64-TQFP", ("PE2", "PE3", "PA5", "PA6"),
          ("PA0", "PA1", "PA2", "PF5", "PC0", "PC1"), "PF0", "PB7"),
    Board("atmega2560", "avr", "Atmel AVR ATmega2560 100-TQFP", ("PD2", "PD3", "PH0", "PH1"),
          ("PB0", "PB1", "PK0", "PL1", "PC0", "PC1"), "PF0", "PB4"),
    Board("atmega8", "avr", "Atmel AVR ATmega8 28-PDIP", ("PD2", "PD3", "PD4", "PD5"),
          ("PB0", "PB4", "PB5", "PC0", "PC1", "PC2"), "PC3", "PB3"),
    Board("atmega32", "avr", "Atmel AVR ATmega32 40-PDIP", ("PD2", "PD3", "PC6", "PC7"),
          ("PB0", "PB1", "PB2", "PA1", "PA2", "PD6"), "PA0", "PD7"),
    Board("atmega1284p", "avr", "Atmel AVR ATmega1284 40-PDIP", ("PD2", "PD3", "PB5", "PB6"),
          ("PB0", "PB1", "PC2", "PC3", "PA1", "PA2"), "PA0", "PD7"),
)

# the parts LDmicro lists that came later (issue 20), simavr's cores all
_MEGA28 = (("PD2", "PD3", "PD4", "PD7"), ("PB0", "PB1", "PB2", "PB3", "PB4", "PB5"), "PC0", "PD6")
_MEGA40 = (("PD2", "PD3", "PB5", "PB6"), ("PB0", "PB1", "PC2", "PC3", "PA1", "PA2"), "PA0", "PD7")
NEW_AVR_BOARDS = (
    Board("atmega48", "avr", "Atmel AVR ATmega48 28-PDIP", *_MEGA28),
    Board("atmega88", "avr", "Atmel AVR ATmega88 28-PDIP", *_MEGA28),
    Board("atmega168", "avr", "Atmel AVR ATmega168 28-PDIP", *_MEGA28),
    Board("atmega164p", "avr", "Atmel AVR ATmega164 40-PDIP", *_MEGA40),
    Board("atmega324p", "avr", "Atmel AVR ATmega324 40-PDIP", *_MEGA40),
    Board("atmega644p", "avr", "Atmel AVR ATmega644 40-PDIP", *_MEGA40),
    Board("atmega1284p", "avr", "Atmel AVR ATmega1284 44-Pin packages", *_MEGA40),
    Board("atmega32u4", "avr", "Atmel AVR ATmega32U4 44-Pin packages", ("PB0", "PB1", "PB2", "PB3"),
          ("PD1", "PD4", "PD5", "PC6", "PC7", "PE6"), "PF0", "PB7"),
    # six port bits, no UART
    Board("attiny85", "avr", "Atmel AVR ATtiny85 8-Pin packages", ("PB3", "PB4"), ("PB0", "PB2"), "PB5", "PB1",
          uart=False, left_out=frozenset(("UART_SEND", "UART_SEND_READY", "UART_RECV", "UART_RECV_AVAIL",
                                           "FORMATTED_STRING"))),
)

# the C output ignores the part: its board is an AVR one whose instructions are C's
C_BOARDS = (dataclasses.replace(BOARDS[0], family="c"),)


def _pic16(part: str, ldmicro: str, inputs: tuple[str, ...], outputs: tuple[str, ...], crystal_hz: int,
           ballast: int = 68, family: str = "pic16") -> Board:
    """Inputs on pins a gpsim pull-up module drives, analog ones among them (the
    start-up makes them digital), none on the oscillator, MCLR or open-drain
    RA4 pins; a 10 ms cycle, which Timer1 makes exactly at 4 and 20 MHz;
    ballast up to three of the four banks of RAM."""
    return Board(part, family, ldmicro, inputs, outputs, uart=False, crystal_hz=crystal_hz, cycle_us=10_000,
                 left_out=PIC16_PERIPHERALS, ballast=ballast)


PIC16_BOARDS = (
    _pic16("pic16f877", "Microchip PIC16F877 40-PDIP", ("RD0", "RC1", "RA0", "RB4"),
           ("RB0", "RB3", "RC5", "RD7", "RE1", "RA1"), 20_000_000),
    _pic16("pic16f876", "Microchip PIC16F876 28-PDIP or 28-SOIC", ("RC0", "RA2", "RB5", "RB7"),
           ("RB0", "RB1", "RB2", "RC4", "RC5", "RA3"), 4_000_000),
    _pic16("pic16f628", "Microchip PIC16F628 18-PDIP or 18-SOIC", ("RA0", "RA1", "RB4", "RB5"),
           ("RB0", "RB1", "RB2", "RB3", "RA2", "RA3"), 4_000_000, ballast=20),
    _pic16("pic16f88", "Microchip PIC16F88 18-PDIP or 18-SOIC", ("RA0", "RA1", "RB6", "RB7"),
           ("RB0", "RB1", "RB3", "RB4", "RA2", "RA3"), 20_000_000),
    _pic16("pic16f887", "Microchip PIC16F887 40-PDIP", ("RA0", "RD2", "RE0", "RB5"),
           ("RB0", "RC2", "RD0", "RD1", "RE1", "RA5"), 4_000_000),
)

# the PIC18 boards as the PIC16 ones: ballast up to about 300 bytes, beyond BSR's banks 0 and 1
PIC18_BOARDS = (
    _pic16("pic18f4520", "Microchip PIC18F4520 40-PDIP", ("RD0", "RC1", "RA0", "RB4"),
           ("RB0", "RB3", "RC5", "RD7", "RE1", "RA1"), 20_000_000, 80, "pic18"),
    _pic16("pic18f2520", "pic18f2520", ("RC0", "RA2", "RB5", "RB7"),
           ("RB0", "RB1", "RB2", "RC4", "RC5", "RA3"), 4_000_000, 80, "pic18"),
)

INPUTS = ("Xa", "Xb", "Xc", "Xd")
OUTPUTS = ("Ya", "Yb", "Yc", "Yd")
RELAYS = ("Ra", "Rb", "Rc", "Rd")
INTS = ("va", "vb", "vc", "vd", "vr")
COUNTERS = ("Ca", "Cb")
TIMERS = ("TON", "TOF", "RTO", "RTL", "TCY", "THI", "TLO")


def _e(_kind: str, **args) -> Element:
    kind = _kind  # counters have an operand called "kind"
    full = {f.name: f.default for f in INSTRUCTIONS[kind].fields}
    full.update(args)
    return Element(kind, full)


def _literal(size: int = 2):
    half = 1 << (8 * size - 1)
    return st.integers(-half, half - 1).map(str)


def _int_or_literal():
    return st.one_of(st.sampled_from(INTS), st.integers(-300, 300).map(str))


@dataclass
class Drawing:
    """What the element strategies share while one program is drawn."""

    board: Board
    timers: list[str] = field(default_factory=list)


@st.composite
def _element(draw, eol: bool, d: Drawing) -> Element:
    kind = draw(_kinds(d.board, eol))
    element = draw(_strategy(kind, d.board))
    if kind in TIMERS:  # each timer a name of its own
        element = _e(kind, **{**element.args, "name": f"T{len(d.timers)}"})
        d.timers.append(element.args["name"])
    return element


# Strategies are built once per board: building them for every element drawn
# took most of the generator's time.
@cache
def _kinds(board: Board, eol: bool):
    return st.sampled_from([k for k in FACTORIES if INSTRUCTIONS[k].eol == eol and board.draws(k)])


@cache
def _strategy(kind: str, board: Board):
    return FACTORIES[kind](board)


def _simple(kind):
    # a new element each time: elements with memory (edges) are told apart by identity
    return lambda board: st.builds(lambda: _e(kind))


def _contact(board):
    return st.builds(lambda n, neg: _e("CONTACTS", name=n, negated=neg),
                     st.sampled_from(board.input_names + board.output_names + RELAYS + ("ROverflowFlagV",)),
                     st.integers(0, 1))


def _coil(board):
    return st.builds(lambda n, t: _e("COIL", name=n, type=t), st.sampled_from(board.output_names + RELAYS),
                     st.sampled_from(" /SRT"))


def _timer_of(kind):
    return lambda board: st.builds(lambda delay: _e(kind, name="T", delay=delay, adjust=0),
                                   st.one_of(st.integers(1, 25).map(lambda n: board.cycle_us * n),
                                             st.sampled_from(INTS)))


def _counter(kind):
    def make(board):
        return st.builds(lambda n, m, i, k: _e(kind, name=n, max=m, init=i, kind=k), st.sampled_from(COUNTERS),
                         st.one_of(st.integers(-5, 12).map(str), st.sampled_from(INTS)),
                         st.one_of(st.integers(-3, 5).map(str), st.sampled_from(INTS)), st.sampled_from("/\\-o"))
    return make


def _compare(kind):
    return lambda board: st.builds(lambda a, b: _e(kind, op1=a, op2=b), _int_or_literal(), _int_or_literal())


def _math(kind):
    # mostly a constant divisor: a variable one is often 0, which the simulator refuses
    divisor = st.one_of(st.integers(1, 300).map(str), st.integers(-300, -1).map(str), st.sampled_from(INTS))
    return lambda board: st.builds(lambda r, a, b: _e(kind, dest=r, op1=a, op2=b), st.sampled_from(INTS),
                               _int_or_literal(), divisor if kind in ("DIV", "MOD") else _int_or_literal())


def _shift(kind):
    return lambda board: st.builds(lambda r, a, n: _e(kind, dest=r, op1=a, op2=n), st.sampled_from(INTS),
                               st.sampled_from(INTS), st.one_of(st.integers(0, 8).map(str), st.sampled_from(INTS)))


def _unary(kind):
    return lambda board: st.builds(lambda r, a: _e(kind, dest=r, op1=a), st.sampled_from(INTS), _int_or_literal())


def _bit_op(kind):
    return lambda board: st.builds(lambda v, b: _e(kind, var=v, bit=b), st.sampled_from(INTS),
                               st.one_of(st.integers(-1, 33).map(str), st.sampled_from(INTS)))


def _convert(kind):
    # BIN2BCD takes 0..9999 and BCD2BIN digits 0..9 (else the simulator stops): mostly constants
    if kind == "BIN2BCD":
        source = st.one_of(st.sampled_from(INTS), st.integers(0, 9999).map(str), st.integers(0, 9999).map(str))
    elif kind == "BCD2BIN":
        source = st.one_of(st.sampled_from(INTS), st.integers(0, 0x0909).filter(
            lambda v: v & 0xF <= 9 and v >> 8 <= 9 and not v & 0xF0).map(str))
    else:
        source = st.sampled_from(INTS)
    return lambda board: st.builds(lambda r, s: _e(kind, dest=r, src=s), st.sampled_from(INTS), source)


def _segments(kind):
    return lambda board: st.builds(lambda r, s, c: _e(kind, dest=r, src=s, common=c), st.sampled_from(INTS),
                                   st.one_of(st.sampled_from(INTS), st.integers(0, 200).map(str)), st.sampled_from("CA"))


def _quad(board):
    return st.builds(lambda c, ab, z, d, zk, n: _e("QUAD_ENCOD", counter=c, int01=0, a=ab[0], b=ab[1], z=z, dir=d, zkind=zk,
                                                   counts=n),
                     st.sampled_from(INTS), st.permutations(board.input_names).map(lambda names: names[:2]),
                     st.sampled_from(("",) + board.input_names), st.sampled_from(("",) + board.output_names + RELAYS),
                     st.sampled_from("/\\-o"), st.sampled_from((0, 4, 7, 100, -3)))


def _pulser(board):
    return st.builds(lambda times, n, coil: _e("PULSER", p1=times[0], p0=times[1], accel=times[2], counter=n, coil=coil),
                     st.tuples(*[st.integers(1, 4).map(str)] * 3),
                     st.one_of(st.sampled_from(INTS), st.integers(-1, 6).map(str)),
                     st.sampled_from(board.output_names + RELAYS))


def _stepper(board):
    """Two names (two elements may share one's counters, as in LDmicro); a
    curve or none, a table of up to 12 steps, literal or variable counts
    and periods."""
    return st.builds(lambda name, n, p, size, graph, coil: _e("STEPPER", name=name, max=n, p=p, size=size, graph=graph,
                                                               coil=coil),
                     st.sampled_from(("sa", "sb")), st.one_of(st.sampled_from(INTS), st.integers(-1, 30).map(str)),
                     st.one_of(st.sampled_from(INTS), st.integers(0, 4).map(str)), st.integers(0, 12),
                     st.integers(0, 7), st.sampled_from(board.output_names))


def _bus(board):
    return st.builds(lambda r, s, bits: _e("BUS", dest=r, src=s, **{f"b{i}": b for i, b in enumerate(bits)}),
                     st.sampled_from(INTS), st.sampled_from(INTS), st.lists(st.integers(0, 7), min_size=8,
                                                                            max_size=8))


def _lut(board):
    return st.builds(lambda r, i, values: _e("LOOK_UP_TABLE", dest=r, index=i, values=tuple(values)),
                     st.sampled_from(INTS), st.one_of(st.integers(0, 3).map(str), st.sampled_from(INTS),
                                                      st.integers(0, 3).map(str)),
                     st.lists(st.integers(-100, 100).map(str), min_size=4, max_size=8))


@st.composite
def _pwl(draw, board):
    xs = sorted(draw(st.sets(st.integers(-20, 40), min_size=2, max_size=5)))
    points = tuple((str(x), str(draw(st.integers(-30, 30)))) for x in xs)
    return _e("PIECEWISE_LINEAR", dest=draw(st.sampled_from(INTS)), index=draw(st.sampled_from(INTS)), points=points)


def _shift_register(board):
    return st.builds(lambda n: _e("SHIFT_REGISTER", name="sr", stages=n), st.integers(2, 4))


def _random(board):
    return st.builds(lambda r: _e("RANDOM", name=r), st.sampled_from(INTS))


def _seed(board):
    return st.builds(lambda r, s: _e("SEED_RANDOM", name=r, seed=s), st.sampled_from(INTS), _int_or_literal())


def _move(board):
    return st.builds(lambda r, s: _e("MOVE", dest=r, src=s), st.sampled_from(INTS + COUNTERS), _int_or_literal())


def _reset(board):
    return st.builds(lambda n: _e("RES", name=n), st.sampled_from(COUNTERS))


def _persist(board):
    return st.builds(lambda v: _e("PERSIST", var=v), st.sampled_from(INTS))


def _adc(board):
    return st.builds(lambda: _e("READ_ADC", name="Aa", refs=0))


def _pwm(board):
    frequency = board.crystal_hz // (256 * 64)
    return st.builds(lambda duty: _e("SET_PWM", duty=duty, freq=frequency, name="Pa", resolution="0-100%"),
                     _int_or_literal())


def _uart_send(board):
    return st.builds(lambda v, n: _e("UART_SEND", var=v, bytes=n, wait=0), st.sampled_from(INTS), st.integers(1, 3))


def _uart_recv(board):
    # into a 4-byte variable, so that any byte count fits
    return st.builds(lambda n: _e("UART_RECV", var="vr", bytes=n, wait=0), st.integers(1, 3))


def _delay(board):
    return st.builds(lambda us: _e("DELAY", delay=str(us)), st.integers(1, 50))


def _fstring(board):
    return st.builds(lambda v, t: _e("FORMATTED_STRING", var=v, text=t), st.sampled_from(INTS),
                     st.sampled_from(("v=\\3\\r\\n", "\\-5 ok", "x\\1", "n: \\-2.")))


def _t2cnt(board):
    return st.builds(lambda r, n: _e("TIME2COUNT", name=r, delay=board.cycle_us * n), st.sampled_from(INTS),
                     st.integers(1, 50))


FACTORIES = {
    "CONTACTS": _contact, "COIL": _coil, "OSR": _simple("OSR"), "OSF": _simple("OSF"), "ODR": _simple("ODR"),
    "ODF": _simple("ODF"), "OSC": _simple("OSC"), "SHORT": _simple("SHORT"), "OPEN": _simple("OPEN"),
    **{k: _timer_of(k) for k in TIMERS},
    **{k: _counter(k) for k in ("CTU", "CTD", "CTC", "CTR")},
    **{k: _compare(k) for k in ("EQU", "NEQ", "GRT", "GEQ", "LES", "LEQ")},
    **{k: _math(k) for k in ("ADD", "SUB", "MUL", "DIV", "MOD", "AND", "OR", "XOR")},
    **{k: _shift(k) for k in ("SHL", "SHR", "SR0", "ROL", "ROR")},
    **{k: _unary(k) for k in ("NEG", "NOT")},
    **{k: _bit_op(k) for k in ("SET_BIT", "CLEAR_BIT", "IF_BIT_SET", "IF_BIT_CLEAR")},
    **{k: _convert(k) for k in ("BIN2BCD", "BCD2BIN", "SWAP", "OPPOSITE")},
    **{k: _segments(k) for k in ("7SEGMENTS", "9SEGMENTS", "14SEGMENTS", "16SEGMENTS")}, "BUS": _bus,
    "QUAD_ENCOD": _quad, "PULSER": _pulser, "STEPPER": _stepper, "LOOK_UP_TABLE": _lut, "PIECEWISE_LINEAR": _pwl,
    "SHIFT_REGISTER": _shift_register, "RANDOM": _random, "SEED_RANDOM": _seed, "MOVE": _move, "RES": _reset,
    "PERSIST": _persist, "READ_ADC": _adc, "SET_PWM": _pwm, "UART_SEND": _uart_send,
    "UART_SEND_READY": _simple("UART_SEND_READY"), "UART_RECV_AVAIL": _simple("UART_RECV_AVAIL"),
    "FORMATTED_STRING": _fstring, "TIME2COUNT": _t2cnt, "MASTER_RELAY": _simple("MASTER_RELAY"),
    "UART_RECV": _uart_recv, "DELAY": _delay, "CLRWDT": _simple("CLRWDT"), "NPULSE_OFF": _simple("NPULSE_OFF"),
}


@st.composite
def _series(draw, depth: int, ends: bool, d: Drawing):
    items = draw(st.lists(_inline(depth, d), min_size=0 if ends else 1, max_size=3))
    if ends:
        options = [_element(eol=True, d=d)]
        if depth:
            options.append(st.lists(_series(depth - 1, True, d), min_size=2, max_size=3).map(Parallel))
        items.append(draw(st.one_of(*options)))
    return Series(items)


def _inline(depth: int, d: Drawing):
    options = [_element(eol=False, d=d)]
    if depth:
        options.append(st.lists(_series(depth - 1, False, d), min_size=2, max_size=3).map(Parallel))
    return st.one_of(*options)


def _add_jumps(draw, rungs: list[Rung], d: Drawing) -> None:
    """Maybe a forward GOTO to a LABEL, and a subroutine called from the
    middle of a rung whose lower branch still needs its power bit after the
    call (backward jumps could loop until the watchdog resets)."""
    if len(rungs) >= 2 and draw(st.booleans()):
        target = draw(st.integers(1, len(rungs) - 1))
        rungs[target] = Rung(rung_circuit(Series([_e("LABEL", label="ahead")] + rungs[target].circuit.items)))
        source = draw(st.integers(0, target))
        rungs.insert(source, Rung(Series([_e("CONTACTS", name=draw(st.sampled_from(d.board.input_names)), negated=0),
                                          _e("GOTO", label="ahead")])))
    if draw(st.booleans()):
        call = Parallel([Series([_e("GOSUB", label="sub")]),
                         Series([_e("OSC"), _e("COIL", name=draw(st.sampled_from(d.board.output_names)), type=" ")])])
        caller = Rung(rung_circuit(Series([_e("CONTACTS", name=draw(st.sampled_from(d.board.input_names)), negated=0),
                                           call])))
        rungs.insert(draw(st.integers(0, len(rungs))), caller)
        body = [Rung(rung_circuit(draw(_series(1, True, d)))) for _ in range(draw(st.integers(1, 2)))]
        rungs += [Rung(Series([_e("SUBPROG", label="sub")])), *body, Rung(Series([_e("ENDSUB", label="sub")]))]


@dataclass
class Case:
    program: Program
    events: list[Event]
    scans: int


@st.composite
def cases(draw, boards: tuple[Board, ...] = BOARDS) -> Case:
    board = draw(st.sampled_from(boards))
    d = Drawing(board)
    rungs = [Rung(rung_circuit(draw(_series(2, True, d)))) for _ in range(draw(st.integers(1, board.rungs)))]
    _add_jumps(draw, rungs, d)
    pads = draw(st.integers(0, board.ballast))
    if pads:
        rungs.insert(0, Rung(Series([_e("OPEN"), _e("SHIFT_REGISTER", name="pad", stages=pads)])))
    program = Program(Settings(mcu=board.ldmicro, cycle_us=board.cycle_us, crystal_hz=board.crystal_hz, baud=9600),
                      rungs)
    used = {str(v) for _, e in program.elements() for v in e.args.values()}
    # every relay read is written somewhere, and a master relay zone is closed
    for relay in sorted(r for r in RELAYS if r in used):
        program.rungs.append(Rung(Series([_e("CONTACTS", name=draw(st.sampled_from(board.input_names)), negated=0),
                                          _e("COIL", name=relay, type=" ")])))
    if sum(e.kind == "MASTER_RELAY" for _, e in program.elements()) % 2:
        program.rungs.append(Rung(Series([_e("MASTER_RELAY")])))
    used = {str(v) for _, e in program.elements() for v in e.args.values()}
    for name, pin in [*zip(board.input_names, board.inputs), *zip(board.output_names, board.outputs)]:
        if name in used:
            program.pins[name] = PinAssignment(name, pin)
    if "Aa" in used:
        program.pins["Aa"] = PinAssignment("Aa", board.adc)
    if "Pa" in used:
        program.pins["Pa"] = PinAssignment("Pa", board.pwm)
    for name in INTS + tuple(f"sr{i}" for i in range(4)):
        program.var_sizes[name] = draw(st.integers(1, board.widest))
    program.var_sizes["vr"] = board.widest
    program.var_sizes.update((f"pad{i}", 4) for i in range(pads))
    scans = draw(st.integers(40, 120))
    events = [Event(0, x, draw(st.integers(0, 1))) for x in board.input_names if x in program.pins]
    events += [Event(draw(st.integers(1, scans - 1)), draw(st.sampled_from(board.input_names)), draw(st.integers(0, 1)))
               for _ in range(draw(st.integers(0, 12)))]
    events = [e for e in events if e.name in program.pins]
    if "Aa" in program.pins:
        events += [Event(draw(st.integers(0, scans - 1)), "Aa", draw(st.integers(0, 1023))) for _ in range(4)]
    if board.uart and any(e.kind in ("UART_RECV", "UART_RECV_AVAIL") for _, e in program.elements()):
        # at most one byte per scan: the UART holds few more
        arrivals = draw(st.sets(st.integers(1, scans - 1), max_size=6))
        events += [Event(scan, "uart", draw(st.integers(0, 255))) for scan in sorted(arrivals)]
    assume(not any(d.severity == ERROR for d in check_program(program)))
    assume(_simulates(program, events, scans))
    return Case(program, events, scans)


def _simulates(program: Program, events: list[Event], scans: int) -> bool:
    try:
        sim = Simulator(program)
        for scan in range(scans):
            for event in events:
                if event.scan == scan:
                    if event.name == "uart":
                        sim.uart_receive(bytes([event.value]))
                    else:
                        sim.set(event.name, event.value)
            sim.step()
    except SimulationError:
        return False
    return True


@needs_simavr
@pytest.mark.slow
@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases())
def test_random_programs_follow_the_simulator(case, tmp_path_factory):
    try:
        problems = differential(case.program, case.events, case.scans, tmp_path_factory.mktemp("random"))
    except CompileError as problem:
        assume(not too_large(problem))
        raise
    assert problems == [], "\n".join(problems)


@needs_simavr
@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases(NEW_AVR_BOARDS))
def test_random_programs_on_the_later_avrs_follow_the_simulator(case, tmp_path_factory):
    test_random_programs_follow_the_simulator.hypothesis.inner_test(case, tmp_path_factory)


def too_large(problem: CompileError) -> bool:
    """A random program may not fit its part's flash or RAM (the ATmega8's 8 KB, the PIC16F1824's
    256 bytes): not a finding."""
    return all(d.code in (FLASH_FULL, RAM_FULL) for d in problem.diagnostics)
