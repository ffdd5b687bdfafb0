"""Peripheral patterns and their set-up: busy-wait delays, the A/D converter,
PWM on the CCP modules, the USART and the data EEPROM.

The UART's "ready" means what the simulator means: the last byte has left
the transmitter completely (TXREG empty, TXIF, and the shift register empty,
TRMT), which is also true before anything was sent; a byte written while
the transmitter is busy is lost.
"""

from __future__ import annotations

from fractions import Fraction

from lang.devices import Pin
from lang.hardware import analog_group, baud_setting, pwm_setting
from lang.semantics import ir

from ..errors import NOT_COMPILED, fail
from ..image import LoopBound
from . import bits
from . import integers as ints
from .emit import F, W, Z
from .memory import FileBit
from .part import Part

# one count of a variable DELAY: 19 instruction cycles of 4 clock cycles
DELAY_LOOP_CYCLES = 76

TAD_MIN_NS = 1600  # the converter's shortest clock period (PIC16F87x: 1.6 us)
ACQUISITION_US = 20  # the sample-and-hold capacitor's charging time before a conversion
PWM_MODE = 0x0C  # CCPxM3:0 = 11xx


def _locate(cx, kind: str):
    found = cx.machine.elements(kind)
    return found[0] if found else None


def _bit(cx, register: str, name: str) -> FileBit:
    return FileBit(cx.part.reg(register), cx.part.bit(register, name), False)


def _write(cx, register: str, value: int) -> None:
    address = cx.part.reg(register)
    if value & 0xFF == 0:
        cx.e.ins("clrf", address)
    else:
        cx.e.load_constant(value)
        cx.e.store(address)


def _wait_while(cx, loc: FileBit, value: bool, bound: LoopBound) -> None:
    """Clear the watchdog until the bit differs from `value`."""
    e = cx.e
    top = e.new_label("wait")
    e.label(top, loop=True, bound=bound)
    e.ins("clrwdt")
    bits.jump_if(e, loc, value, top)


def _cycles(cx, microseconds: float) -> int:
    """Instruction cycles (Fosc/4) in a time."""
    return round(microseconds * cx.machine.crystal_hz / 4_000_000)


def _spin(cx, cycles: int, what: str) -> None:
    """Wait about `cycles` instruction cycles (3 a pass of DECFSZ/GOTO)."""
    passes = min(max(-(-cycles // 3), 1), 255)
    e = cx.e
    counter = cx.layout.scratch[12]
    e.load_constant(passes)
    e.store(counter)
    top = e.new_label("spin")
    e.label(top, loop=True, bound=LoopBound(passes, what))
    e.ins("decfsz", counter, F)
    e.goto(top)


# --- delays ---------------------------------------------------------------------------

def delay(cx, op: ir.Delay) -> None:
    """A loop of the family's delay_loop_cycles clock cycles per count
    (DELAY_LOOP_CYCLES on a PIC16), clearing the watchdog."""
    e = cx.e
    s = ints.Scratch(cx.layout.scratch)
    done = e.new_label("delay")
    count = None
    if op.loops:
        ints.copy_in(cx, op.amount, s.A)
        e.ins("btfsc", s.A[3], 7)
        e.goto(done)  # a negative count waits nothing
    else:
        assert isinstance(op.amount, ir.Const)  # a delay that does not loop is a constant time
        count = round(op.amount.value * cx.machine.crystal_hz / (1_000_000 * cx.delay_loop_cycles))
        if count <= 0:
            return
        ints.copy_in(cx, ir.Const(count), s.A)
    e.load(s.A[0])
    for reg in s.A[1:]:
        e.ins("iorwf", reg, W)
    e.ins("btfsc", e.status, Z)
    e.goto(done)
    top = e.new_label("delay")
    e.label(top, loop=True, bound=LoopBound(count, "DELAY") if count else LoopBound(None, "a DELAY by a variable"))
    e.ins("clrwdt")
    ints.add_constant(e, s.A, -1)
    e.load(s.A[0])
    for reg in s.A[1:]:
        e.ins("iorwf", reg, W)
    e.ins("btfss", e.status, Z)
    e.goto(top)
    e.label(done)


# --- A/D converter ---------------------------------------------------------------------------

def adc_clock(part: Part, crystal_hz: int) -> int:
    """ADCS: the smallest of Fosc/2, /8, /32 (the part's `clocks`: the
    enhanced core's /2 to /64) whose period is at least TAD_MIN_NS; the
    converter's own RC clock (3) beyond that."""
    for divisor, select in part.feature("adc").get("clocks", [[2, 0], [8, 1], [32, 2]]):
        if divisor * 1e9 / crystal_hz >= TAD_MIN_NS:
            return select
    return 3


def analog_setup(cx, channels: set[int]) -> None:
    """At start-up: the pins of the channels READ ADC uses analog, the
    others digital (as far as the part can: the checks warn of each digital
    pin made analog with them, LD714); results right-justified."""
    part = cx.part
    adc = part.feature("adc")
    if adc is None or not channels:
        return
    adfm = next((r for r in ("ADCON1", "ADCON0") if "ADFM" in part.bits(r)), None)
    if part.enhanced:
        # an ANSELx per port; ADCON1: right-justified, the conversion clock, VDD as the reference
        analog: dict[str, int] = {}
        for pin, channel in part.device.adc.items():
            if channel in channels:
                analog[pin[1]] = analog.get(pin[1], 0) | 1 << int(pin[2])
        for letter, mask in sorted(analog.items()):
            _write(cx, f"ANSEL{letter}", mask)
        _write(cx, "ADCON1", 1 << part.bit("ADCON1", "ADFM") | _adcs(part, "ADCON1", adc_clock(part, cx.machine.crystal_hz)))
        return
    if part.has("ANSEL"):
        mask = sum(1 << c for c in channels)
        clock = 0
        if "ADCS0" in part.bits("ANSEL"):
            clock = _adcs(part, "ANSEL", adc_clock(part, cx.machine.crystal_hz))
        _write(cx, "ANSEL", mask & 0xFF | clock)
        if part.has("ANSELH"):
            _write(cx, "ANSELH", mask >> 8)
        if adfm == "ADCON1":
            _write(cx, "ADCON1", 1 << part.bit("ADCON1", "ADFM"))
        return
    group = analog_group(part.device, channels)
    assert group is not None  # a part without ANSEL chooses its analog pins by PCFG
    _write(cx, "ADCON1", group[0] | (1 << part.bit("ADCON1", "ADFM") if adfm == "ADCON1" else 0))
    if "ADFM" in part.bits("ADCON2"):
        # the PIC18's converter clock and justification (acquisition time 0: the program waits it)
        _write(cx, "ADCON2", 1 << part.bit("ADCON2", "ADFM") | _adcs(part, "ADCON2", adc_clock(part, cx.machine.crystal_hz)))


def _adcs(part: Part, register: str, select: int) -> int:
    return sum((select >> i & 1) << part.bit(register, f"ADCS{i}") for i in range(3) if f"ADCS{i}" in part.bits(register))


def read_adc(cx, op: ir.ReadAdc) -> None:
    e, part = cx.e, cx.part
    adc = part.feature("adc")
    control = 1 << part.bit("ADCON0", "ADON") | op.channel << part.bit("ADCON0", "CHS0")
    if "ADCS0" in part.bits("ADCON0"):
        control |= _adcs(part, "ADCON0", adc_clock(part, cx.machine.crystal_hz))
    if "ADFM" in part.bits("ADCON0"):
        control |= 1 << part.bit("ADCON0", "ADFM")
    _write(cx, "ADCON0", control)
    _spin(cx, _cycles(cx, ACQUISITION_US), "the A/D input's acquisition time")
    go = _bit(cx, "ADCON0", "GO" if "GO" in part.bits("ADCON0") else "GO_NOT_DONE")
    bits.write(e, go, True)
    # 12 converter clocks of at most 32 instruction cycles... each pass is 4 cycles
    _wait_while(cx, go, True, LoopBound(12 * 32 // 4 + 1, "an A/D conversion"))
    _copy_unsigned(cx, [part.reg(name) for name in reversed(adc["result"])], op.dst)


def _copy_unsigned(cx, registers: list[int], target) -> None:
    """The registers (low byte first) straight into the destination, zero
    above them: each register read once (RCREG's read takes the byte)."""
    for i, address in enumerate(ints.target_bytes(cx, target)):
        ints.put(cx.e, ints.Byte("mem", registers[i]) if i < len(registers) else ints.Byte("const", 0), address)


# --- PWM ----------------------------------------------------------------------------------

# Timer2 makes every CCP's period (PR2 + 1) with the prescaler T2CKPS: the
# checks (LD708, LD709) have said what the program asks is possible.

def set_pwm(cx, op: ir.SetPwm) -> None:
    """0 or less: the CCP off and its pin low; full or more: off and high;
    else duty * 4 * period / full tenths of a Timer2 count (10 bits)."""
    e, part = cx.e, cx.part
    s = ints.Scratch(cx.layout.scratch)
    setting = pwm_setting(part.device, op.unit, cx.machine.crystal_hz, op.freq)
    if isinstance(op.duty, ir.Const):
        _constant_duty(cx, op, setting.period)
        return
    off, on, done = e.new_label("pwm"), e.new_label("pwm"), e.new_label("pwm")
    width = max(2, ints.size(cx, op.duty))
    duty = s.C[:width]
    ints.copy_in(cx, op.duty, duty)
    e.ins("btfsc", duty[-1], 7)
    e.goto(off)
    e.load(duty[0])
    for reg in duty[1:]:
        e.ins("iorwf", reg, W)
    e.ins("btfsc", e.status, Z)
    e.goto(off)
    ints.chain(e, "cmp", duty, [ints.Byte("const", op.full >> 8 * i & 0xFF) for i in range(width)])
    e.ins("btfsc", e.status, 0)
    e.goto(on)
    unit = op.unit
    ccp = part.reg(f"{unit}CON")
    if Fraction(4 * setting.period, op.full) == 4:
        # the 10 bits are duty * 4: CCPxCON<5:4> = 0, CCPRxL = the duty
        e.load_constant(PWM_MODE)
        e.store(ccp)
        e.load(duty[0])
    else:
        value = _ten_bits(cx, duty, 4 * setting.period, op.full)
        # CCPRxL = the 10 bits >> 2, CCPxCON<5:4> = their low two, PWM mode
        e.load(value[0])
        e.ins("andlw", 3)
        e.store(s.E)
        e.ins("swapf", s.E, W)
        e.ins("iorlw", PWM_MODE)
        e.store(ccp)
        for _ in range(2):
            e.ins("bcf", e.status, 0)
            e.ins("rrf", value[1], F)
            e.ins("rrf", value[0], F)
        e.load(value[0])
    e.store(part.reg(f"CCPR{unit[-1]}L"))
    e.goto(done)
    e.label(on)
    _disconnect(cx, unit, True)
    e.goto(done)
    e.label(off)
    _disconnect(cx, unit, False)
    e.label(done)


def _ten_bits(cx, duty: list[int], numerator: int, full: int) -> list[int]:
    """The 10-bit duty cycle duty * numerator // full (0 < duty < full) in
    two scratch bytes, low first: the duty shifted where the scale is a
    power of two (4 x a period of 64 with a full scale of 256...), shifted
    and added once where it is an integer of two bits (4 x 125 / 100 = 5),
    else duty * factor >> shift (no division)."""
    e = cx.e
    s = ints.Scratch(cx.layout.scratch)
    scale = Fraction(numerator, full)
    if _power_of_two(scale.numerator) and _power_of_two(scale.denominator):
        up = scale.numerator.bit_length() - scale.denominator.bit_length()
        for _ in range(abs(up)):
            ints.shift_once(e, "shl" if up > 0 else "sr0", duty[:2])
        return duty[:2]
    if scale.denominator == 1 and scale.numerator.bit_count() == 2:
        # two bits set (3, 5, 6...): (duty << (top - bottom) + duty) << bottom, no multiplication
        scaled = s.A[:2]
        for reg, src in zip(scaled, duty[:2]):
            e.load(src)
            e.store(reg)
        bottom, top = (scale.numerator & -scale.numerator).bit_length() - 1, scale.numerator.bit_length() - 1
        for _ in range(top - bottom):
            ints.shift_once(e, "shl", scaled)
        ints.add_files(e, scaled, duty[:2])
        for _ in range(bottom):
            ints.shift_once(e, "shl", scaled)
        return scaled
    factor, shift = pwm_scale(numerator, full)
    for reg, value in zip(s.A[:3], factor.to_bytes(3, "little")):
        ints.put(e, ints.Byte("const", value), reg)
    ints.copy_in(cx, ir.Const(0), s.B[2:3])
    for reg, src in zip(s.B, duty[:2]):
        e.load(src)
        e.store(reg)
    e.call(cx.routine("mul3"))  # its passes: the duty's 10 bits at most
    product = s.C[:3]
    if shift % 8 > 4:
        # >> 8q + 5, 6 or 7 as << 3, 2 or 1 into a fourth byte, and the bytes from q + 1: fewer passes
        if shift >= 8:
            product = s.C[:4]
            e.ins("clrf", product[3])
        for _ in range(8 - shift % 8):
            e.ins("bcf", e.status, 0)
            for reg in product:
                e.ins("rlf", reg, F)
        high = product[shift // 8 + 1:][:2]
    else:
        for _ in range(shift % 8):
            e.ins("bcf", e.status, 0)
            for reg in reversed(product):
                e.ins("rrf", reg, F)
        high = product[shift // 8:][:2]
    for byte, dst in zip(high + [None], s.A[:2]):
        ints.put(e, ints.Byte("mem", byte) if byte is not None else ints.Byte("const", 0), dst)
    return s.A[:2]


def _power_of_two(n: int) -> bool:
    return n & (n - 1) == 0


def pwm_scale(numerator: int, full: int) -> tuple[int, int]:
    """(factor, shift) with duty * factor >> shift == duty * numerator // full
    for every duty from 1 to full - 1 (checked here, one by one) and the
    product within 24 bits: the largest shift that is exact. Every PWM
    setting has one (numerator = 4 x a period of 1 to 256; full 100 to 1024)."""
    for shift in range(23, -1, -1):
        factor = -(-(numerator << shift) // full)
        if factor * (full - 1) < 1 << 24 and all(
                duty * factor >> shift == duty * numerator // full for duty in range(1, full)):
            return factor, shift
    raise AssertionError(f"no exact scale for {numerator}/{full}")


def _constant_duty(cx, op: ir.SetPwm, period: int) -> None:
    """A literal duty: its register values computed here, as the code
    above would compute them every scan (the same truncating division)."""
    assert isinstance(op.duty, ir.Const)  # the caller's choice: a literal duty
    duty = op.duty.value
    if duty <= 0 or duty >= op.full:
        _disconnect(cx, op.unit, duty > 0)
        return
    tenths = duty * 4 * period // op.full
    _write(cx, f"{op.unit}CON", (tenths & 3) << 4 | PWM_MODE)
    _write(cx, f"CCPR{op.unit[-1]}L", tenths >> 2)


def pwm_setup(cx, code: ir.Code) -> None:
    """Timer2 running at the PWM frequency when a program uses PWM."""
    ops = [op for op in code.scan if isinstance(op, ir.SetPwm)]
    if not ops:
        return
    setting = pwm_setting(cx.part.device, ops[0].unit, cx.machine.crystal_hz, ops[0].freq)
    _write(cx, "PR2", setting.period - 1)
    _write(cx, "T2CON", 1 << 2 | setting.select)  # TMR2ON, T2CKPS
    for unit in sorted({op.unit for op in ops}):
        # an enhanced CCP in single-output mode drives the pins its steering register selects
        steering = cx.part.facts["pwm"][unit].get("steering")
        if steering is not None:
            value = 1 << steering["pins"][_pwm_pin(cx, unit).name]
            if value != steering["reset"]:
                _write(cx, steering["register"], value)


def _pwm_pin(cx, unit: str) -> Pin:
    """The pin of the program's PWM output (a P name) on `unit`: one pin a
    unit where the part offers it on more than one (LD708)."""
    pwm = cx.part.device.pwm
    return next(pin for name, pin in sorted(cx.machine.pins.items()) if name[0] == "P" and pwm.get(pin.name) == unit)


def _disconnect(cx, unit: str, level: bool) -> None:
    """The CCP off: the pin shows its latch."""
    e, part = cx.e, cx.part
    e.ins("clrf", part.reg(f"{unit}CON"))
    port, bit = _pwm_pin(cx, unit).port_bit
    bits.write(e, FileBit(part.latch(port), bit, False), level)


def pwm_off(cx, op: ir.PwmOff) -> None:
    _disconnect(cx, op.unit, False)


# --- UART -------------------------------------------------------------------------------------

def _uart_element(cx):
    return _locate(cx, "UART_SEND") or _locate(cx, "UART_RECV") or _locate(cx, "FORMATTED_STRING")


def uart_setup(cx, code: ir.Code) -> None:
    """The USART on at the baud rate (the checks have said it can make it,
    LD707, and warned when it is more than 2 % off, LD713)."""
    if not any(isinstance(op, (ir.UartSend, ir.UartReady, ir.UartAvailable, ir.UartTake)) for op in code.scan):
        return
    if not cx.part.feature("uart"):
        raise fail(NOT_COMPILED, f"the {cx.part.title} has no UART", _uart_element(cx))
    setting = baud_setting(cx.part.device, cx.machine.crystal_hz, cx.machine.baud)
    _write(cx, "SPBRG", setting.value)
    _write(cx, "TXSTA", 1 << cx.part.bit("TXSTA", "TXEN") | setting.select << cx.part.bit("TXSTA", "BRGH"))
    _write(cx, "RCSTA", 1 << cx.part.bit("RCSTA", "SPEN") | 1 << cx.part.bit("RCSTA", "CREN"))


def _ready(cx, busy: str) -> None:
    """To `busy` unless the transmitter is empty (TXIF and TRMT)."""
    bits.jump_if(cx.e, _bit(cx, "PIR1", "TXIF"), False, busy)
    bits.jump_if(cx.e, _bit(cx, "TXSTA", "TRMT"), False, busy)


def uart_ready(cx, op: ir.UartReady) -> None:
    e = cx.e
    busy, done = e.new_label("uart"), e.new_label("uart")
    dst = cx.bit(op.dst)
    _ready(cx, busy)
    bits.write(e, dst, True)
    e.goto(done)
    e.label(busy)
    bits.write(e, dst, False)
    e.label(done)


def uart_send(cx, op: ir.UartSend) -> None:
    e = cx.e
    done = e.new_label("uart")
    if op.wait:
        # one byte time: 10 bits at the baud rate, 7 cycles a pass
        passes = _cycles(cx, 10e6 / cx.machine.baud) // 7 + 1
        top = e.new_label("uart")
        e.label(top, loop=True, bound=LoopBound(passes, "waiting for the UART transmitter"))
        e.ins("clrwdt")
        _ready(cx, top)
    else:
        _ready(cx, done)  # busy: the byte is lost, as on the simulator
    ints.load_w(e, ints.byte(cx, op.value, 0))
    e.store(cx.part.reg("TXREG"))
    e.label(done)


def _clear_overrun(cx) -> None:
    """An overrun stops the receiver until CREN is cleared and set again."""
    e = cx.e
    overrun = _bit(cx, "RCSTA", "OERR")
    cren = _bit(cx, "RCSTA", "CREN")
    ok = e.new_label("uart")
    bits.jump_if(e, overrun, False, ok)
    bits.write(e, cren, False)
    bits.write(e, cren, True)
    e.label(ok)


def uart_available(cx, op: ir.UartAvailable) -> None:
    _clear_overrun(cx)
    bits.copy(cx.e, cx.bit(op.dst), _bit(cx, "PIR1", "RCIF"), False)


def uart_take(cx, op: ir.UartTake) -> None:
    """A byte already seen in the receiver is taken at once; one still to
    come, whenever it comes."""
    _clear_overrun(cx)
    if op.wait:
        _wait_while(cx, _bit(cx, "PIR1", "RCIF"), False, LoopBound(None, "a UART receive waiting for a byte"))
    _copy_unsigned(cx, [cx.part.reg("RCREG")], op.dst)


# --- EEPROM ----------------------------------------------------------------------------------

def _eeprom(cx) -> dict:
    eeprom = cx.part.feature("eeprom")
    if eeprom is None:
        raise fail(NOT_COMPILED, f"the {cx.part.title} has no data EEPROM for PERSIST", _locate(cx, "PERSIST"))
    return eeprom


def _eeprom_read(cx, address: int) -> None:
    """W = the EEPROM byte."""
    e, part, eeprom = cx.e, cx.part, _eeprom(cx)
    _write(cx, eeprom["address"], address)
    for memory in ("EEPGD", "CFGS"):  # the data EEPROM, not program memory or the configuration
        if memory in part.bits(eeprom["control"]):
            bits.write(e, _bit(cx, eeprom["control"], memory), False)
    bits.write(e, _bit(cx, eeprom["control"], "RD"), True)
    e.load(part.reg(eeprom["data"]))


def eeprom_load(cx, op: ir.EepromLoad) -> None:
    eeprom = _eeprom(cx)
    _wait_while(cx, _bit(cx, eeprom["control"], "WR"), True,
                LoopBound(_cycles(cx, 5000) // 4 + 1, "an EEPROM write"))
    st = ints.storage(cx, op.var)
    for i in range(st.size):
        _eeprom_read(cx, op.address + i)
        cx.e.store(st.addr + i)


def eeprom_save(cx, op: ir.EepromSave) -> None:
    """The first byte that differs is written if the EEPROM is idle; the rest
    wait for later scans (a write takes milliseconds)."""
    e, part, eeprom = cx.e, cx.part, _eeprom(cx)
    done = e.new_label("eeprom")
    control = eeprom["control"]
    bits.jump_if(e, _bit(cx, control, "WR"), True, done)
    st = ints.storage(cx, op.var)
    spare = cx.layout.scratch[13]
    for i in range(st.size):
        same = e.new_label("eeprom")
        _eeprom_read(cx, op.address + i)
        e.store(spare)
        e.load(st.addr + i)
        e.ins("xorwf", spare, W)
        e.ins("btfsc", e.status, Z)
        e.goto(same)
        e.load(st.addr + i)
        e.store(part.reg(eeprom["data"]))
        bits.write(e, _bit(cx, control, "WREN"), True)
        # the unlock sequence, then WR, with no instruction between
        e.load_constant(0x55)
        e.store(part.reg(eeprom["unlock"]))
        e.load_constant(0xAA)
        e.store(part.reg(eeprom["unlock"]))
        bits.write(e, _bit(cx, control, "WR"), True)
        bits.write(e, _bit(cx, control, "WREN"), False)
        e.goto(done)
        e.label(same)
    e.label(done)
