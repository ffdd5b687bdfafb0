"""The runtime around the scan on the PIC10F20x.

    reset:  the factory's calibration (the MOVLW in the last word, which the
            reset runs first) into OSCCAL, FOSC4 cleared (GP2 a port bit, not
            the clock's output); the RAM in use cleared; OPTION:
            Timer0 on the instruction clock (T0CS = 0, which frees GP2 for
            output), its prescaler, the weak pull-ups of GP0, GP1 and GP3 on
            when an input wants one, wake-up on change on only when the
            program has a SLEEP; outputs low, TRIS; with SLEEP and the
            watchdog on, back to sleep when the watchdog woke the part (LDmicro's
            "SLEEP trap"); start values; TMR0 and the cycle's bytes cleared, to the wait
    scan:   [YPlcCycleDuty high] the rungs [YPlcCycleDuty low]
    wait:   until the cycle's ticks have passed (clearing the watchdog when the
            configuration word turns it on), scan

The cycle timer is Timer0, 8 bits with no overflow flag and no interrupt:
it runs free and the wait polls it. The ticks left in this cycle (less one)
are a 16-bit count; each read of TMR0 takes the ticks since the last read
off it, and the scan starts again when it turns negative, the count then
moving on by one cycle's ticks (no drift: a late scan shortens the next
wait). A scan may last up to 256 ticks of Timer0 without losing a turn of
it (the prescaler is the largest that makes the cycle exactly: 4.1 ms at
10 ms, 4 MHz). The start-up enters the wait with no ticks left, so the
first scan runs at Timer0's first tick and scan k starts k cycle times
after it, as in the simulator.
"""

from __future__ import annotations

from lang.hardware import cycle_setting
from lang.semantics import ir

from ..image import LoopBound
from ..pic16 import bits
from ..pic16 import integers as ints
from ..pic16.emit import C, F, W, Z
from ..pic16.memory import FileBit
from ..pic16.runtime import output_masks, pulled_up, scan_loop
from ..pic16.select import Context, select

TRIS_GPIO = 6
CLEAR_ONE_BY_ONE = 9  # up to this many bytes CLRF each: shorter than the loop
CYCLE_BYTES = 3  # TMR0 at the last read, and the ticks left in the cycle (16 bits)
WAIT_CYCLES = 20  # from a read of TMR0 to the scan (about 15) and from its end to the next read (3), at most


def _clear(cx: Context, addresses: list[int]) -> None:
    """Clear the RAM bytes in use: CLRF each, or a loop down the span they lie in."""
    e = cx.e
    if len(addresses) <= CLEAR_ONE_BY_ONE:
        for address in addresses:
            e.ins("clrf", address)
        return
    low, high = min(addresses), max(addresses)
    e.load_constant(high)
    e.store(e.fsr)
    top = e.new_label("clear")
    e.label(top, loop=True, bound=LoopBound(high - low + 1, "clearing RAM at start-up"))
    e.ins("clrf", e.indf)
    e.ins("decf", e.fsr, F)
    e.load(e.fsr)
    e.ins("andlw", 0x1F)  # FSR's unused high bits read as 1
    e.ins("xorlw", low - 1)
    e.ins("btfss", e.status, Z)
    e.goto(top)


def _sleeps(code: ir.Code) -> bool:
    return any(isinstance(op, ir.Sleep) for op in code.scan)


def option_value(cx: Context, prescaler_bits: int, wake_on_change: bool) -> int:
    """OPTION: wake-up on change (GP0, GP1, GP3) when SLEEP wants it, the pull-ups,
    Timer0 on Fosc/4, its prescaler."""
    part = cx.part
    value = prescaler_bits
    if not wake_on_change:
        value |= 1 << part.bit("OPTION_REG", "NOT_GPWU")
    if not pulled_up(cx):
        value |= 1 << part.bit("OPTION_REG", "NOT_GPPU")
    return value


def _back_to_sleep(cx: Context) -> None:
    """After a reset by the watchdog in sleep (TO and PD both cleared), sleep
    again, as LDmicro's image does: only a pin change ends SLEEP."""
    e, status = cx.e, cx.part.reg("STATUS")
    for flag in ("NOT_TO", "NOT_PD"):
        bits.jump_if(e, FileBit(status, cx.part.bit("STATUS", flag)), True, "awake")
    select(cx, [ir.Sleep()])
    e.label("awake")


def _start(cx: Context, code: ir.Code, prescaler_bits: int, watchdog: bool) -> None:
    e, part = cx.e, cx.part
    e.store(part.reg("OSCCAL"))
    # FOSC4 would put the clock on GP2: a calibration word erased to XORLW 0xFF leaves it set
    e.ins("bcf", part.reg("OSCCAL"), part.bit("OSCCAL", "FOSC4"))
    # the scratch bytes are written before they are read, the cycle's bytes set in write_runtime
    clock = cx.layout.clock
    cycle = set(range(clock, clock + CYCLE_BYTES)) if clock is not None else set()
    _clear(cx, sorted(e.ram - set(cx.layout.scratch) - cycle))
    e.load_constant(option_value(cx, prescaler_bits, _sleeps(code)))
    e.ins("option")
    outputs = output_masks(cx).get("P", 0)
    e.ins("clrf", part.port("P"))
    e.load_constant(~outputs & 0x0F)
    e.ins("tris", TRIS_GPIO)
    if watchdog and _sleeps(code):  # only a watchdog time-out clears TO: without it LDmicro's check never acts
        _back_to_sleep(cx)
    select(cx, code.init)


def _wait(cx: Context, ticks: int, watchdog: bool) -> None:
    e, part = cx.e, cx.part
    last = cx.layout.clock
    assert last is not None  # the baseline's cycle is always free-running: the layout gave it its bytes
    left = [last + 1, last + 2]
    e.label("wait", loop=True, bound=LoopBound(None, "waiting for the next cycle"), bank=0)
    if watchdog:  # on only when the program's configuration word turns it on
        e.ins("clrwdt")
    e.load(last)
    e.ins("subwf", part.reg("TMR0"), W)  # the ticks since the last read
    e.ins("addwf", last, F)
    e.ins("subwf", left[0], F)
    e.ins("btfss", e.status, C)
    e.ins("decf", left[1], F)
    bits.jump_if(e, FileBit(left[1], 7), False, "wait")
    e.label("waited")  # the wait loop ends here (benchmarks time the scan without it)
    ints.add_constant(e, left, ticks)
    e.goto("scan")


def scan_limit(part, crystal_hz: int, cycle_us: int) -> tuple[int, str]:
    """How long a scan may last before Timer0 turns between two reads: 256
    ticks at the prescaler the cycle uses, less the wait's own instructions
    between the last read and the scan and back to the next read."""
    timer = part.facts["cycle_timer"]
    setting = cycle_setting(part.device, crystal_hz, cycle_us, free=True)
    assert setting is not None  # the back end refuses a cycle Timer0 cannot make first
    prescaler = next(int(text) for text, select in timer["prescalers"].items() if select == setting[0])
    return timer["counts"] * prescaler - WAIT_CYCLES, "one turn of Timer0"


def write_runtime(cx: Context, code: ir.Code, crystal_hz: int, watchdog: bool) -> None:
    """The runtime and the scan; `watchdog`: the configuration word turns the watchdog on."""
    e = cx.e
    setting = cycle_setting(cx.part.device, crystal_hz, cx.machine.cycle_us, free=True)
    assert setting is not None  # the back end refuses a cycle Timer0 cannot make first
    prescaler_bits, ticks = setting
    _start(cx, code, prescaler_bits, watchdog)
    assert cx.layout.clock is not None  # the layout always has the cycle's bytes here
    # a write to TMR0 clears the prescaler, which counted for the watchdog until OPTION gave it to
    # Timer0 (gpsim holds Timer0 until its old count wraps, up to 2,048 cycles). With TMR0 at the
    # last read (0) and no ticks left, the wait ends at the first tick and sets the count to the
    # cycle's: the first scan runs at once, the next a cycle later
    e.ins("clrf", cx.part.reg("TMR0"))
    for offset in range(CYCLE_BYTES):
        e.ins("clrf", cx.layout.clock + offset)
    e.goto("wait")
    scan_loop(cx, code)
    _wait(cx, ticks, watchdog)
