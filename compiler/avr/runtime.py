"""The runtime around the scan: start-up, the scan loop and its timing.

    reset:  stack, zero register, watchdog (2 s), RAM and bit registers
            cleared, pins (outputs low, inputs with their pull-ups), UART,
            start values, Timer1 started in CTC mode
    scan:   [YPlcCycleDuty high] the rungs [YPlcCycleDuty low]
    wait:   clear the watchdog until Timer1 matches, clear its flag, scan

The first scan runs at once after start-up and scan k starts k cycle times
after it, as the simulator's scan k runs at k x cycle. No interrupt is ever
enabled, so the image needs no vector table: the code starts at address 0.
The watchdog resets the MCU when a scan hangs (LOCK, a stuck jump loop).
"""

from __future__ import annotations

from lang.hardware import cycle_setting
from lang.semantics import ir

from ..analysis import uses_uart
from ..backend import Machine
from ..image import LoopBound
from . import bits
from .emit import SCRATCH, A, B
from .memory import MemBit, RegBit
from .part import WGM12, Part
from .peripherals import uart_init
from .select import Context, select

WATCHDOG_2S = 0b111  # WDP2:0
CLOCK, DEADLINE = "~cycle.overflows", "~cycle.deadline"


def _write(cx: Context, register: str, value: int) -> None:
    cx.e.store_byte(cx.part.reg(register), cx.e.constant_reg(value), False)


def _pins(machine: Machine) -> dict[str, tuple[int, int]]:
    """Port letter -> (DDR, pull-up) masks: outputs (Y, P) low, inputs pulled
    up as the PULL-UP LIST says (all of them by default), PWM pins outputs."""
    ports: dict[str, list[int]] = {}
    for name, pin in machine.pins.items():
        if not pin.is_io or name[:1] not in ("X", "Y", "P"):
            continue
        letter, bit = pin.port_bit
        ddr, pulled = ports.setdefault(letter, [0, 0])
        if name[0] == "X":
            ports[letter] = [ddr, pulled | (machine.pullups.get(letter, 0xFF) >> bit & 1) << bit]
        else:
            ports[letter] = [ddr | 1 << bit, pulled]
    return {letter: (ddr, pulled) for letter, (ddr, pulled) in ports.items()}


def _protected(cx: Context, register: str, value: int) -> None:
    """A write the configuration change protection guards (the reduced
    core's CCP): the key, then the write within four cycles."""
    e, protect = cx.e, cx.part.avr["protect"]
    e.constant(value, SCRATCH + 1)
    e.constant(protect["key"], SCRATCH)
    e.store_byte(cx.part.reg(protect["register"]), SCRATCH, False)
    e.store_byte(cx.part.reg(register), SCRATCH + 1, False)


def _clock(cx: Context, crystal_hz: int) -> None:
    """A part whose clock comes from its own oscillator through a prescaler
    (the ATtiny10: 8 MHz divided by 8 at reset): the division that makes the
    program's clock, or else the external clock on CLKI."""
    clock = cx.part.avr["clock"]
    divisions = {clock["oscillator_hz"] >> k: k for k in range(9)}
    if crystal_hz in divisions:
        _protected(cx, clock["prescaler"], divisions[crystal_hz])
    else:
        _protected(cx, clock["source"], clock["external"])
        _protected(cx, clock["prescaler"], 0)


def _watchdog(cx: Context) -> None:
    e, watchdog = cx.e, cx.part.avr["watchdog"]
    e.ins("wdr")
    if "protect" in cx.part.avr:
        _protected(cx, watchdog["control"], 1 << watchdog["WDE"] | WATCHDOG_2S)
        return
    # the change enable bit opens a four-cycle window for the new setting
    _write(cx, watchdog["control"], 1 << watchdog["WDCE"] | 1 << watchdog["WDE"])
    _write(cx, watchdog["control"], 1 << watchdog["WDE"] | WATCHDOG_2S)


def _start(cx: Context, code: ir.Code, machine: Machine) -> None:
    e, part, layout = cx.e, cx.part, cx.layout
    e.ins("cli")
    e.ins("clr", e.zero)
    _write(cx, "SPH", part.ram_end >> 8)
    _write(cx, "SPL", part.ram_end & 0xFF)
    _watchdog(cx)
    if "clock" in part.avr:
        _clock(cx, cx.crystal_hz)
    for reg in layout.homes + tuple(sorted({b.reg for b in layout.bits.values()
                                            if isinstance(b, RegBit) and b.reg not in layout.homes})):
        e.ins("clr", reg)
    if layout.ram_used:
        top = e.new_label()
        e.constant(part.ram_start & 0xFF, 26)
        e.constant(part.ram_start >> 8, 27)
        e.constant(layout.ram_used & 0xFF, 24)
        e.constant(layout.ram_used >> 8, 25)
        e.label(top, loop=True, bound=LoopBound(layout.ram_used, "clearing RAM at start-up"))
        e.ins("st_xp", e.zero)
        if e.core.has("sbiw"):
            e.ins("sbiw", 24, 1)
        else:
            e.ins("subi", 24, 1)
            e.ins("sbci", 25, 0)
        e.branch("brne", top)
    pullups = part.avr.get("pullups")  # a register of its own (PUEB), or the PORT latch of an input
    for letter, (ddr, pulled) in sorted(_pins(machine).items()):
        if pullups:
            _write(cx, f"{pullups}{letter}", pulled)
        _write(cx, f"PORT{letter}", 0 if pullups else pulled)
        _write(cx, f"DDR{letter}", ddr)
    if part.uart and uses_uart(code):
        uart_init(cx)
    select(cx, code.init)
    e.forget_scratch()


def runs_free(part: Part) -> bool:
    """The cycle timer is an 8-bit one counted in software (the ATtiny85's
    Timer0), not Timer1 restarting itself at a compare match."""
    return "free_ticks" in part.avr["cycle_timer"]


def cycle_variables(part: Part) -> dict[str, int]:
    """RAM the runtime keeps for a free-running cycle timer: its overflows
    (the bits above its count) and the next scan's deadline, in ticks."""
    return {CLOCK: 2, DEADLINE: 3} if runs_free(part) else {}


def scan_limit(part: Part, machine: Machine) -> tuple[int, str] | None:
    """How long a scan may last before a free-running cycle timer loses an
    overflow: one turn of the timer at the prescaler the cycle uses."""
    if not runs_free(part):
        return None
    timer = part.avr["cycle_timer"]
    setting = cycle_setting(part.device, machine.crystal_hz, machine.cycle_us, free=True)
    assert setting is not None  # the checks refuse a cycle the timer cannot make (LD706)
    prescaler = next(int(text) for text, select in timer["prescalers"].items() if select == setting[0])
    return timer["counts"] * prescaler * timer["clock_divider"], f"one turn of Timer{timer['timer']}"


def _scan(cx: Context, code: ir.Code, machine: Machine) -> None:
    e, part = cx.e, cx.part
    pin = machine.duty_pin  # LDmicro's YPlcCycleDuty: high while the scan runs
    duty = MemBit(part.port("PORT", pin.port_bit[0]), pin.port_bit[1], False) if pin is not None else None
    e.label("scan", loop=True)
    if duty:
        bits.write(e, duty, True)
    select(cx, code.scan)
    if duty:
        bits.write(e, duty, False)


def _compare_cycle(cx: Context, code: ir.Code, machine: Machine) -> None:
    """A 16-bit timer in CTC mode (Timer1; the ATtiny10's Timer0): its
    compare flag marks each cycle."""
    e, part = cx.e, cx.part
    setting = cycle_setting(part.device, cx.crystal_hz, machine.cycle_us, free=False)
    assert setting is not None  # the checks refuse a cycle the timer cannot make (LD706)
    select_bits, counts = setting
    flags = part.avr["cycle_timer"]
    n = flags.get("timer", 1)
    _write(cx, f"TCCR{n}A", 0)
    _write(cx, f"OCR{n}AH", (counts - 1) >> 8)  # the high byte first: it goes through TEMP
    _write(cx, f"OCR{n}AL", (counts - 1) & 0xFF)
    _write(cx, f"TCCR{n}B", 1 << WGM12 | select_bits)  # WGMn2: bit 3 of TCCRnB on every part
    _scan(cx, code, machine)
    e.label("wait", loop=True, bound=LoopBound(None, "waiting for the next cycle"))
    e.ins("wdr")
    flag = MemBit(part.reg(flags["flags"]), flags[f"OCF{n}A"], False)
    bits.jump_if(e, flag, False, "wait")
    e.label("waited")  # the wait loop ends here (benchmarks time the scan without it)
    _write(cx, flags["flags"], 1 << flags[f"OCF{n}A"])  # writing 1 clears it
    e.jump("scan")


def _free_cycle(cx: Context, code: ir.Code, machine: Machine) -> None:
    """An 8-bit timer runs free; a 24-bit tick count (its overflows counted
    in software above its count register) is compared with the next scan's
    deadline, which moves on by one cycle each scan: no drift. The overflow
    flag remembers one overflow while the scan runs, so a scan may last up to
    256 ticks (of the largest prescaler that makes the cycle) without the
    cycle stretching."""
    e, part = cx.e, cx.part
    timer = part.avr["cycle_timer"]
    setting = cycle_setting(part.device, cx.crystal_hz, machine.cycle_us, free=True)
    assert setting is not None  # the checks refuse a cycle the timer cannot make (LD706)
    select_bits, ticks = setting
    clock, deadline = cx.layout.vars[CLOCK].addr, cx.layout.vars[DEADLINE].addr  # cleared at start-up
    overflow = MemBit(part.reg(timer["flags"]), timer["TOV0"], False)
    _write(cx, timer["control"], select_bits)
    _scan(cx, code, machine)
    for i, reg in enumerate(A[:3]):
        e.load_byte(deadline + i, reg, True)
    for i, reg in enumerate(A[:3]):
        e.ins("subi" if i == 0 else "sbci", reg, (-ticks >> 8 * i) & 0xFF)
        e.store_byte(deadline + i, reg, True)
    e.label("wait", loop=True, bound=LoopBound(None, "waiting for the next cycle"))
    e.ins("wdr")
    counted = e.new_label()
    bits.jump_if(e, overflow, False, counted)
    _write(cx, timer["flags"], 1 << timer["TOV0"])  # writing 1 clears it
    e.load_byte(clock, B[0], True)
    e.load_byte(clock + 1, B[1], True)
    e.ins("subi", B[0], 0xFF)  # + 1
    e.ins("sbci", B[1], 0xFF)
    e.store_byte(clock, B[0], True)
    e.store_byte(clock + 1, B[1], True)
    e.label(counted)
    # the count after the flag: an overflow in between is counted on the next pass
    e.load_byte(part.reg(timer["count"]), A[0], False)
    e.load_byte(clock, A[1], True)
    e.load_byte(clock + 1, A[2], True)
    for i in range(3):
        e.load_byte(deadline + i, B[i], True)
        e.ins("sub" if i == 0 else "sbc", A[i], B[i])
    e.branch("brmi", "wait")
    e.label("waited")  # the wait loop ends here (benchmarks time the scan without it)
    e.jump("scan")


def write_runtime(cx: Context, code: ir.Code, machine: Machine) -> None:
    _start(cx, code, machine)
    (_free_cycle if runs_free(cx.part) else _compare_cycle)(cx, code, machine)

