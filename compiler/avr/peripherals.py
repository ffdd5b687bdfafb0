"""Peripheral patterns and their set-up: the A/D converter, PWM on the 8-bit
timers, the UART and the EEPROM.

The UART's "ready" means what the simulator means: the last byte has left
the transmitter completely (TXC), or nothing was sent yet (a flag set at
start-up), so a byte written while one is still shifting out is lost.
"""

from __future__ import annotations

from lang.hardware import baud_setting, pwm_setting
from lang.semantics import ir

from ..image import LoopBound
from . import bits, integers
from .emit import SCRATCH, A, B
from .memory import MemBit
from .part import (
    ADEN,
    ADSC,
    EEMWE,
    EERE,
    EEWE,
    RXC,
    RXEN,
    TXC,
    TXEN,
    U2X,
    URSEL,
    Part,
)

ADC_MAX_CLOCK = 200_000  # the converter's clock for full resolution
# ADC clocks from ADSC to the result: the first conversion after ADEN is set
# takes 25, and it starts at the next rising edge of the ADC clock
ADC_CONVERSION_CLOCKS = 25 + 1
# bit times from a byte written to UDR to TXC: start, 8 data and stop bits,
# and up to one more until the transmitter's clock starts the frame
UART_FRAME_BITS = 10 + 1
UART_IDLE = "~uart.idle"  # no byte sent yet: the transmitter is ready


def _io_bit(e, part: Part, register: str, bit: int, value: bool) -> None:
    bits.write(e, MemBit(part.reg(register), bit, False), value)


def _wait_while(e, part: Part, register: str, bit: int, value: bool, bound: LoopBound) -> None:
    top = e.new_label()
    e.label(top, loop=True, bound=bound)
    bits.jump_if(e, MemBit(part.reg(register), bit, False), value, top)


def _write(e, part: Part, register: str, value: int) -> None:
    e.store_byte(part.reg(register), e.constant_reg(value, SCRATCH), False)


# --- A/D converter -------------------------------------------------------------------------

def adc_prescaler(crystal_hz: int) -> int:
    """ADPS bits: the smallest division that brings the clock to 200 kHz."""
    for bits_ in range(1, 8):
        if crystal_hz >> bits_ <= ADC_MAX_CLOCK:
            return bits_
    return 7


def read_adc(cx, op: ir.ReadAdc) -> None:
    e, part, adc = cx.e, cx.part, cx.part.adc
    refs = (op.refs & 3) << 6 if adc.get("refs", True) else 0  # the ATtiny10 has VCC only
    _write(e, part, adc["ADMUX"], refs | (op.channel & 7))
    if "MUX5" in adc:  # channels 8 and up: the register and bit of MUX5 differ by part
        register, bit = adc["MUX5"]
        _io_bit(e, part, register, bit, op.channel >= 8)
    _write(e, part, adc["ADCSRA"], 1 << ADEN | 1 << ADSC | adc_prescaler(cx.crystal_hz))
    prescaler = 1 << adc_prescaler(cx.crystal_hz)
    _wait_while(e, part, adc["ADCSRA"], ADSC, True,
                LoopBound(None, "the A/D conversion", cycles=ADC_CONVERSION_CLOCKS * prescaler))
    e.load_byte(part.reg(adc["ADCL"]), A[0], False)  # ADCL first: it latches ADCH
    if adc.get("bits", 10) == 8:
        # an 8-bit converter (the ATtiny10): its reading times 4, on the
        # 0..1023 scale READ ADC has on every other part
        e.ins("mov", A[1], e.zero)
        for _ in range(2):
            e.ins("lsl", A[0])
            e.ins("rol", A[1])
    else:
        e.load_byte(part.reg(adc["ADCH"]), A[1], False)
    n = integers.target_size(cx, op.dst)
    integers.extend(cx, A[:max(n, 2)], 2, signed=False)
    integers.store(cx, op.dst, A[:max(n, 2)])


# --- PWM --------------------------------------------------------------------------------

# Fast PWM counting 0..255 on an 8-bit timer, its prescaler the one whose
# frequency is nearest: the checks (LD708, LD709) have said what the program
# asks is possible.

def set_pwm(cx, op: ir.SetPwm) -> None:
    """0 or less: the output disconnected and low; full or more: disconnected
    and high (the timer would still make a spike at either end)."""
    e, part = cx.e, cx.part
    cfg = part.pwm(op.unit)
    setting = pwm_setting(part.device, op.unit, cx.crystal_hz, op.freq)
    off, on, done = e.new_label(), e.new_label(), e.new_label()
    duty = A[:max(2, integers.size(cx, op.duty))]
    integers.load(cx, op.duty, duty)
    e.ins("tst", duty[-1])
    e.branch("brmi", off)
    e.ins("mov", SCRATCH, duty[0])
    for reg in duty[1:]:
        e.ins("or_", SCRATCH, reg)
    e.branch("breq", off)
    e.ins("cpi", duty[0], op.full & 0xFF)
    for i, reg in enumerate(duty[1:], 1):
        e.ins("cpc", reg, e.constant_reg((op.full >> 8 * i) & 0xFF, SCRATCH + 1))
    e.branch("brge", on)
    _scale(cx, op.full, duty)
    e.store_byte(part.reg(cfg["ocr"]), SCRATCH, False)
    if "top" in cfg:  # the ATtiny85's Timer1 counts to OCR1C: a full period of 256
        _write(e, part, cfg["top"], 0xFF)
    control = cfg["com"] | cfg["fast"]
    if cfg["clock"] == cfg["control"]:
        control |= setting.select
    else:
        _write(e, part, cfg["clock"], setting.select)
    e.load_byte(part.reg(cfg["control"]), SCRATCH, False)
    e.ins("ori", SCRATCH, control)
    e.store_byte(part.reg(cfg["control"]), SCRATCH, False)
    e.jump(done)
    e.label(on)
    _disconnect(cx, op.unit, True)
    e.jump(done)
    e.label(off)
    _disconnect(cx, op.unit, False)
    e.label(done)


def _scale(cx, full: int, duty) -> None:
    """SCRATCH = duty * 256 / full, for 0 < duty < full."""
    e = cx.e
    if full == 100 and not cx.part.has_mul:
        # duty * 655 / 256, the same as below, by the multiplication routine
        for reg in A[len(duty):]:
            e.ins("clr", reg)
        for i, reg in enumerate(B):
            e.constant((655 >> 8 * i) & 0xFF, reg)
        e.call(cx.routine("mul32"))
        e.ins("mov", SCRATCH, A[1])
        return
    if full == 100:
        # duty * 2.56 as duty * 2 + duty * 143 / 256
        e.constant(143, SCRATCH)
        e.ins("mul", duty[0], SCRATCH)
        e.ins("mov", SCRATCH, 1)
        e.ins("add", SCRATCH, duty[0])
        e.ins("add", SCRATCH, duty[0])
        return
    shifts = {256: 0, 512: 1, 1024: 2}[full]
    for _ in range(shifts):
        e.ins("lsr", duty[1])
        e.ins("ror", duty[0])
    e.ins("mov", SCRATCH, duty[0])


def _disconnect(cx, unit: str, level: bool) -> None:
    """The output taken from the timer: the pin shows its latch, written
    here (which also makes a simulator that keeps the timer's last level
    see the pin change)."""
    e, part, cfg = cx.e, cx.part, cx.part.pwm(unit)
    e.load_byte(part.reg(cfg["control"]), SCRATCH, False)
    e.ins("andi", SCRATCH, ~cfg["com"] & 0xFF)
    e.store_byte(part.reg(cfg["control"]), SCRATCH, False)
    pin = part.device.pin(next(p for p, u in part.device.pwm.items() if u == unit))
    bits.write(e, MemBit(part.port("PORT", pin.port), pin.bit, False), level)


def pwm_off(cx, op: ir.PwmOff) -> None:
    _disconnect(cx, op.unit, False)


# --- UART ---------------------------------------------------------------------------------

def uart_init(cx) -> None:
    e, part, uart = cx.e, cx.part, cx.part.uart
    setting = baud_setting(part.device, cx.crystal_hz, cx.baud)
    ubrr, double = setting.value, bool(setting.select)
    # on parts sharing UBRRH with UCSRC, URSEL = 0 selects UBRRH
    _write(e, part, uart["UBRRH"], (ubrr >> 8) & ~(1 << URSEL))
    _write(e, part, uart["UBRRL"], ubrr & 0xFF)
    _write(e, part, uart["UCSRA"], int(double) << U2X)
    _write(e, part, uart["UCSRB"], 1 << RXEN | 1 << TXEN)
    bits.write(e, cx.bit(ir.Bit(UART_IDLE)), True)


def _status(cx) -> MemBit:
    return MemBit(cx.part.reg(cx.part.uart["UCSRA"]), 0, False)


def uart_ready(cx, dst) -> None:
    """dst = TXC, or nothing sent yet"""
    e = cx.e
    e.load_byte(_status(cx).addr, e.loaded, False)
    e.ins("bst", e.loaded, TXC)
    bits.when(e, cx.bit(ir.Bit(UART_IDLE)), True, lambda: e.ins("set"))
    bits.from_t(e, cx.bit(dst))


def uart_send(cx, op: ir.UartSend) -> None:
    e, part, uart = cx.e, cx.part, cx.part.uart
    done = e.new_label()
    ready = e.new_label()
    top = e.new_label()
    e.label(top, loop=op.wait, bound=_transmitter_wait(cx) if op.wait else None)
    status = part.reg(uart["UCSRA"])
    e.load_byte(status, e.loaded, False)
    e.ins("sbrc", e.loaded, TXC)
    e.jump(ready)
    bits.jump_if(e, cx.bit(ir.Bit(UART_IDLE)), True, ready)
    if op.wait:
        e.ins("wdr")
        e.jump(top)
    else:
        e.jump(done)  # busy: the byte is lost, as on the simulator
    e.label(ready)
    integers.load(cx, op.value, A[:1])
    # clear TXC (writing 1 clears it), keeping the speed bit, then send
    _write(e, part, uart["UCSRA"], 1 << TXC | int(cx.uart_double) << U2X)
    e.store_byte(part.reg(uart["UDR"]), A[0], False)
    bits.write(e, cx.bit(ir.Bit(UART_IDLE)), False)
    e.label(done)


def _transmitter_wait(cx) -> LoopBound:
    """The last byte leaves the transmitter within one frame."""
    setting = baud_setting(cx.part.device, cx.crystal_hz, cx.baud)
    ubrr, double = setting.value, bool(setting.select)
    bit_cycles = (8 if double else 16) * (ubrr + 1)
    return LoopBound(None, "waiting for the UART transmitter", cycles=UART_FRAME_BITS * bit_cycles)


def uart_available(cx, dst) -> None:
    status = _status(cx)
    bits.copy(cx.e, cx.bit(dst), MemBit(status.addr, RXC, False), False)


def uart_take(cx, op: ir.UartTake) -> None:
    e, part, uart = cx.e, cx.part, cx.part.uart
    top = e.new_label()
    # a byte already seen in the receiver is taken at once; one still to come, whenever it comes
    bound = LoopBound(None, "a UART receive waiting for a byte") if op.wait else LoopBound(1, "a UART receive")
    e.label(top, loop=True, bound=bound)
    e.ins("wdr")
    bits.jump_if(e, MemBit(part.reg(uart["UCSRA"]), RXC, False), False, top)
    e.load_byte(part.reg(uart["UDR"]), A[0], False)
    n = integers.target_size(cx, op.dst)
    integers.extend(cx, A[:max(n, 2)], 1, signed=False)
    integers.store(cx, op.dst, A[:max(n, 2)])


# --- EEPROM --------------------------------------------------------------------------------

def _eeprom_address(cx, address: int) -> None:
    e, part = cx.e, cx.part
    e.store_byte(part.reg("EEARH"), e.constant_reg(address >> 8, SCRATCH), False)
    e.store_byte(part.reg("EEARL"), e.constant_reg(address & 0xFF, SCRATCH), False)


def _eeprom_read(cx, address: int, reg: int) -> None:
    e, part = cx.e, cx.part
    _eeprom_address(cx, address)
    _io_bit(e, part, "EECR", EERE, True)
    e.load_byte(part.reg("EEDR"), reg, False)


def eeprom_load(cx, op: ir.EepromLoad) -> None:
    e, part = cx.e, cx.part
    write_cycles = part.avr["eeprom_write_us"] * cx.crystal_hz // 1_000_000
    _wait_while(e, part, "EECR", EEWE, True, LoopBound(None, "waiting for an EEPROM write", cycles=write_cycles))
    st = integers.storage(cx, op.var)
    for i in range(st.size):
        _eeprom_read(cx, op.address + i, A[0])
        e.store_byte(st.addr + i, A[0], st.ram)


def eeprom_save(cx, op: ir.EepromSave) -> None:
    """The first byte that differs is written if the EEPROM is idle; the
    rest wait for later scans (a write takes milliseconds)."""
    e, part = cx.e, cx.part
    done = e.new_label()
    eecr = MemBit(part.reg("EECR"), EEWE, False)
    bits.jump_if(e, eecr, True, done)
    st = integers.storage(cx, op.var)
    for i in range(st.size):
        same = e.new_label()
        _eeprom_read(cx, op.address + i, e.loaded)
        e.load_byte(st.addr + i, A[0], st.ram)
        e.ins("cp", e.loaded, A[0])
        e.branch("breq", same)
        e.store_byte(part.reg("EEDR"), A[0], False)
        # the write must follow the master enable within four cycles
        assert e.bit_io(part.reg("EECR")) is not None
        _io_bit(e, part, "EECR", EEMWE, True)
        _io_bit(e, part, "EECR", EEWE, True)
        e.jump(done)
        e.label(same)
    e.label(done)

