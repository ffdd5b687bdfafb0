"""The runtime around the scan: start-up, the scan loop and its timing.

    reset:  bank 0, RAM in use cleared, pins digital (A/D inputs and
            comparators off), outputs low, PORTB (GPIO) pull-ups as the
            PULL-UP LIST says, start values, the cycle timer started
    scan:   [YPlcCycleDuty high] the rungs [YPlcCycleDuty low]
    wait:   clear the watchdog until the cycle timer's flag, clear it, scan

The cycle timer is Timer1 with CCP1 in compare mode and its special event
trigger, which restarts Timer1 at the match and sets CCP1IF (CCP2 and
CCP2IF when PWM takes CCP1): the period is exact and no interrupt is used.
Without a CCP left (the PIC12F675, PWM on a part's only CCP), or for a
cycle longer than Timer1 counts, Timer1 runs free instead: its overflows
counted in software, each scan's deadline one cycle after the last. The first scan runs at once after start-up and scan k
starts k cycle times after it, as in the simulator (LDmicro's code waits a
cycle before its first scan).
"""

from __future__ import annotations

from lang.hardware import cycle_runs_free, cycle_setting, internal_clock_refusal
from lang.semantics import ir

from ..errors import INTERNAL_CLOCK, fail
from ..image import LoopBound
from . import bits
from . import integers as ints
from .emit import W, Z
from .memory import FileBit
from .peripherals import analog_setup, pwm_setup, uart_setup
from .select import Context, select

CCP_SPECIAL_EVENT = 0x0B  # CCP1M3:0 = 1011: compare, trigger special event


def _write(cx: Context, register: str, value: int) -> None:
    address = cx.part.reg(register)
    if value == 0:
        cx.e.ins("clrf", address)
    else:
        cx.e.load_constant(value)
        cx.e.store(address)


def output_masks(cx: Context) -> dict[str, int]:
    """Port letter -> output mask (every assigned Y or P name, the duty pin too)."""
    ports: dict[str, int] = {}
    for name, pin in cx.machine.pins.items():
        if pin.is_io:
            letter, bit = pin.port_bit
            ports.setdefault(letter, 0)
            if name[:1] in ("Y", "P"):
                ports[letter] |= 1 << bit
    return ports


def pulled_up(cx: Context) -> dict[str, int]:
    """Port letter -> its inputs that want a weak pull-up, on the ports that
    have them (PORTB, GPIO; on the enhanced core every port with a WPUx)."""
    masks: dict[str, int] = {}
    for name, pin in cx.machine.pins.items():
        if name[:1] == "X" and pin.is_io and (pin.port in ("B", "P") or cx.part.has(f"WPU{pin.port}")):
            letter, bit = pin.port_bit
            masks[letter] = masks.get(letter, 0) | (cx.machine.pullups.get(letter, 0xFF) >> bit & 1) << bit
    return {letter: mask for letter, mask in masks.items() if mask}


def _clear(cx: Context, addresses: list[int]) -> None:
    """Clear the RAM bytes in use: runs of them by e.fsr, a few with CLRF."""
    e = cx.e
    runs: list[list[int]] = []
    for address in sorted(addresses):
        if runs and address == runs[-1][-1] + 1 and address >> 7 == runs[-1][0] >> 7:
            runs[-1].append(address)
        else:
            runs.append([address])
    for run in runs:
        if len(run) <= 4:
            for address in run:
                e.ins("clrf", address)
            continue
        e.point_high(run[0] >> 8)
        e.load_constant(run[0] & 0xFF)
        e.store(e.fsr)
        top = e.new_label("clear")
        e.label(top, loop=True, bound=LoopBound(len(run), "clearing RAM at start-up"))
        e.ins("clrf", e.indf)
        e.ins("incf", e.fsr, 1)
        e.ins("movlw", (run[-1] + 1) & 0xFF)
        e.ins("xorwf", e.fsr, W)
        e.ins("btfss", e.status, Z)
        e.goto(top)


def _oscillator(cx: Context) -> None:
    """OSCCON for the program's clock where the configuration word selects
    the internal oscillator (it starts at 500 kHz), with LDmicro's values;
    a clock it cannot make is LD716, which the checks report too."""
    part, machine = cx.part, cx.machine
    intosc = part.feature("intosc")
    fosc = part.config_field("FOSC")
    if intosc is None or fosc is None:
        return
    word = part.config_words[0][1] if machine.config_word is None else machine.config_word & 0x3FFF
    if word & fosc.mask != fosc.value:
        return  # the program's configuration word chooses a crystal or an external clock
    refusal = internal_clock_refusal(part.device, machine.crystal_hz, machine.config_word)
    if refusal is not None:
        raise fail(INTERNAL_CLOCK, refusal)  # the checks say it first, on the header (LD716)
    _write(cx, intosc["register"], intosc["settings"][str(machine.crystal_hz)])


def _start(cx: Context, code: ir.Code) -> None:
    part = cx.part
    _oscillator(cx)
    # the scratch bytes are written before they are read
    _clear(cx, sorted(cx.e.ram - set(cx.layout.scratch)))
    for features in ("digital_io", "comparators_off"):
        for register, value in sorted(part.feature(features, {}).items()):
            _write(cx, register, value)
    analog_setup(cx, {op.channel for op in code.scan if isinstance(op, ir.ReadAdc)})
    outputs = output_masks(cx)
    for letter in sorted(outputs):
        cx.e.ins("clrf", part.latch(letter))
    # the WPUx before the TRISx: the pull-up switch after them is in the TRIS's bank on the enhanced
    # core (OPTION_REG in bank 1, WPUx in bank 4), one bank selection fewer; nothing is pulled up before
    pulled = pulled_up(cx)
    for letter, mask in sorted(pulled.items()):
        register = "WPU" if letter == "P" else f"WPU{letter}"
        if part.has(register):
            _write(cx, register, mask)
    for letter, mask in sorted(outputs.items()):
        direction = ~mask & 0xFF
        if "PSPMODE" in part.bits(f"TRIS{letter}"):
            direction &= 0x0F  # TRISE's high bits: PORTD as a port, not the parallel slave port
        cx.e.load_constant(direction)
        cx.e.store(part.tris(letter))
    if pulled:
        switch = part.pullup_switch()
        assert switch is not None  # a port with weak pull-ups has their switch
        cx.e.ins("bcf", *switch)  # RBPU/GPPU/WPUEN low: the weak pull-ups on
    uart_setup(cx, code)
    pwm_setup(cx, code)
    select(cx, code.init)


def _cycle_module(cx: Context, code: ir.Code) -> str | None:
    """The CCP module whose compare match restarts Timer1: CCP1, or CCP2 when
    PWM takes CCP1; None when none is left (Timer1 then runs free)."""
    pwm = {op.unit for op in code.scan if isinstance(op, ir.SetPwm)}
    return next((unit for unit in ("CCP1", "CCP2") if unit not in pwm and cx.part.has(f"{unit}CON")), None)


def scan_loop(cx: Context, code: ir.Code) -> None:
    """The scan: its label (the loop's head), the rungs, with the cycle-duty
    pin high while they run."""
    e = cx.e
    duty = duty_pin(cx)
    e.label("scan", loop=True, bank=0)
    if duty:
        bits.write(e, duty, True)
    select(cx, code.scan)
    if duty:
        bits.write(e, duty, False)


def _ccp_cycle(cx: Context, code: ir.Code, unit: str) -> None:
    e, part = cx.e, cx.part
    setting = cycle_setting(part.device, cx.machine.crystal_hz, cx.machine.cycle_us, free=False)
    assert setting is not None  # the checks refuse a cycle Timer1 cannot make (LD706)
    prescaler, counts = setting
    _write(cx, f"CCPR{unit[-1]}L", (counts - 1) & 0xFF)
    _write(cx, f"CCPR{unit[-1]}H", (counts - 1) >> 8)
    _write(cx, f"{unit}CON", CCP_SPECIAL_EVENT)
    _write(cx, "T1CON", prescaler << 4 | 1)  # TMR1ON
    scan_loop(cx, code)
    e.label("wait", loop=True, bound=LoopBound(None, "waiting for the next cycle"), bank=0)
    e.ins("clrwdt")
    flags = "PIR1" if unit == "CCP1" else "PIR2"
    flag = FileBit(part.reg(flags), part.bit(flags, f"{unit}IF"), False)
    bits.jump_if(e, flag, False, "wait")
    e.label("waited")  # the wait loop ends here (benchmarks time the scan without it)
    bits.write(e, flag, False)
    e.goto("scan")


def _free_cycle(cx: Context, code: ir.Code, clock: int) -> None:
    """Timer1 runs free; a 24-bit tick count (its overflows counted in
    software above TMR1H:TMR1L) is compared with the next scan's deadline,
    which moves on by one cycle each scan: no drift, a few cycles of jitter.
    A scan may last up to 65536 ticks without losing an overflow."""
    e, part = cx.e, cx.part
    setting = cycle_setting(part.device, cx.machine.crystal_hz, cx.machine.cycle_us, free=True)
    assert setting is not None  # the checks refuse a cycle Timer1 cannot make (LD706)
    select_bits, ticks = setting
    high, deadline = clock, [clock + 1 + i for i in range(3)]
    s = cx.layout.scratch
    count = [s[11], s[12], s[13]]  # the tick count read now, less the deadline
    overflow = FileBit(part.reg("PIR1"), part.bit("PIR1", "TMR1IF"), False)
    # TMR1 is undefined after power-on (and gpsim's enhanced models start it near an overflow):
    # the count starts at 0 with no overflow pending
    e.ins("clrf", part.reg("TMR1L"))
    e.ins("clrf", part.reg("TMR1H"))
    bits.write(e, overflow, False)
    _write(cx, "T1CON", select_bits << 4 | 1)  # TMR1ON
    scan_loop(cx, code)
    ints.add_constant(e, deadline, ticks)
    e.label("wait", loop=True, bound=LoopBound(None, "waiting for the next cycle"), bank=0)
    e.ins("clrwdt")

    def count_overflow() -> None:
        bits.write(e, overflow, False)
        e.ins("incf", high, 1)

    bits.when(e, overflow, True, count_overflow)
    # TMR1H, TMR1L, TMR1H again: read the low byte again when the high one moved meanwhile
    timer_low, timer_high = part.reg("TMR1L"), part.reg("TMR1H")
    read = e.new_label("tick")
    e.label(read, loop=True, bound=LoopBound(2, "reading Timer1 across its carry"))
    e.load(timer_high)
    e.store(count[1])
    e.load(timer_low)
    e.store(count[0])
    e.load(timer_high)
    e.ins("xorwf", count[1], 0)
    e.ins("btfss", e.status, Z)
    e.goto(read)
    e.load(high)
    e.store(count[2])
    ints.chain(e, "sub", count, [ints.Byte("mem", d) for d in deadline])
    # the deadline may sit in another bank (RAM filled by the variables); the wait loop starts
    # in bank 0, whose selection cannot come between the skip and its GOTO (the scratch
    # bytes are in bank 0 or common RAM)
    e.bank0()
    bits.jump_if(e, FileBit(count[2], 7), True, "wait")
    e.label("waited")  # the wait loop ends here (benchmarks time the scan without it)
    e.goto("scan")


def _scan_loop(cx: Context, code: ir.Code) -> None:
    unit = _cycle_module(cx, code)
    if cx.layout.clock is not None:
        _free_cycle(cx, code, cx.layout.clock)
    else:
        assert unit is not None  # without one the layout has a clock (free_running)
        _ccp_cycle(cx, code, unit)


def duty_pin(cx: Context) -> FileBit | None:
    """LDmicro's YPlcCycleDuty output: high while the scan runs."""
    pin = cx.machine.duty_pin
    return FileBit(cx.part.latch(pin.port_bit[0]), pin.port_bit[1], False) if pin is not None and pin.is_io else None


def free_running(code: ir.Code, part, machine) -> bool:
    """True when a free-running Timer1 makes the scan cycle: no CCP module is
    left for it, or the cycle is longer than Timer1 counts (0.52 s at 4 MHz)."""
    pwm = {op.unit for op in code.scan if isinstance(op, ir.SetPwm)}
    return cycle_runs_free(part.device, machine.crystal_hz, machine.cycle_us, pwm)


def write_runtime(cx: Context, code: ir.Code) -> None:
    """The runtime and the scan."""
    _start(cx, code)
    _scan_loop(cx, code)
