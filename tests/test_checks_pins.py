"""Rules about pins, parts and what a target can do (LD4xx, LD5xx).

ATmega328P 28-PDIP: pin 2 PD0 (RXD), 3 PD1 (TXD), 4 PD2, 7 VCC, 8 GND, 12 PD6
(OC0A), 14 PB0, 23 PC0 (ADC0). Its 32-pin package has the analog-only ADC6 on
pin 19. The PIC16F628 has no A/D converter; the ATmega162 (as LDmicro
describes it) no UART.
"""

from __future__ import annotations

import dataclasses

import pytest
from builders import coil, contact, el, found, move, none, one, program, span_of

import lang.devices
from lang.checks import check_program
from lang.devices import find_device

M328 = "Atmel AVR ATmega328 28-PDIP"
M328_32 = "Atmel AVR ATmega328 32-Pin packages"


def _io(mcu=M328, pins=None, *rungs):
    rungs = rungs or ([contact("Xa"), coil("Yb")],)
    return program(*rungs, mcu=mcu, pins=pins)


# --- LD401 pin assigned twice ------------------------------------------------------------------


def test_two_names_on_one_pin():
    prog = _io(M328, {"Xa": 4, "Yb": "PD2"})  # pin 4 is PD2
    d = one(prog, "LD401")
    assert d.severity == "error" and d.span == prog.pins["Yb"].span
    assert "'Yb'" in d.message and "'Xa'" in d.message
    assert d.related[0].span == prog.pins["Xa"].span


def test_distinct_pins_and_stale_entries():
    none(_io(M328, {"Xa": 4, "Yb": 14}), "LD401")
    # a name the program no longer uses is dropped, as LDmicro does
    none(_io(M328, {"Xa": 4, "Yb": 14, "Xold": 4}), "LD401")
    # without a part the raw pin values are compared
    one(_io(None, {"Xa": 4, "Yb": 4}), "LD401")


# --- LD402-LD405 the pin itself -------------------------------------------------------------------


def test_pin_not_on_the_part():
    prog = _io(M328, {"Xa": 40, "Yb": "RB0"})
    hits = found(prog, "LD402")
    assert {d.span for d in hits} == {prog.pins["Xa"].span, prog.pins["Yb"].span}
    assert all(d.severity == "error" and "ATmega328P" in d.message for d in hits)
    none(_io(M328, {"Xa": 4, "Yb": 14}), "LD402")


def test_pin_that_is_not_io():
    prog = _io(M328, {"Xa": 8, "Yb": 14})
    d = one(prog, "LD403")
    assert d.severity == "error" and d.span == prog.pins["Xa"].span and "GND" in d.message


def test_analog_only_pin_is_fine_for_an_a_name_only():
    adc = [contact("Xa"), el("READ_ADC", name="Alevel")]
    none(program(adc, mcu=M328_32, pins={"Xa": 12, "Alevel": 19}), "LD403")
    prog = program([contact("Xa"), coil("Yb")], mcu=M328_32, pins={"Xa": 19, "Yb": 13})
    d = one(prog, "LD403")
    assert "ADC6" in d.message


def test_a_name_on_a_pin_without_adc():
    prog = program([contact("Xa"), el("READ_ADC", name="Alevel")], mcu=M328, pins={"Xa": 4, "Alevel": 14})
    d = one(prog, "LD404")
    assert d.severity == "error" and d.span == prog.pins["Alevel"].span
    assert "Alevel" in d.message and "PB0" in d.message and "PC0" in d.message
    none(program([contact("Xa"), el("READ_ADC", name="Alevel")], mcu=M328, pins={"Xa": 4, "Alevel": 23}), "LD404")


def test_p_name_on_a_pin_without_pwm():
    rung = [contact("Xa"), el("SET_PWM", duty="50", freq=1000, name="Pmotor")]
    prog = program(rung, mcu=M328, pins={"Xa": 4, "Pmotor": 14})
    d = one(prog, "LD405")
    assert d.severity == "error" and d.span == prog.pins["Pmotor"].span and "PD6" in d.message
    none(program(rung, mcu=M328, pins={"Xa": 4, "Pmotor": 12}), "LD405")


# --- LD406 UART pins --------------------------------------------------------------------------------


def test_io_on_the_uart_pins_while_the_uart_is_used():
    send = [contact("Xa"), el("UART_SEND", var="c")]
    prog = program(send, [contact("Xb"), coil("Yc")], [contact("Xd"), move("c", 65)],
                   mcu=M328, pins={"Xa": 4, "Xb": 2, "Yc": 14, "Xd": 5})
    d = one(prog, "LD406")
    assert d.severity == "error" and d.span == prog.pins["Xb"].span
    assert "'Xb'" in d.message and "RX" in d.message


def test_uart_pins_free_when_the_uart_is_unused():
    none(_io(M328, {"Xa": 2, "Yb": 3}), "LD406")


# --- LD407 no pin ---------------------------------------------------------------------------------------


def test_io_without_a_pin_when_a_part_is_selected():
    c = coil("Yb")
    prog = _io(M328, {"Xa": 4}, [contact("Xa"), c])
    d = one(prog, "LD407")
    assert d.severity == "error" and d.span == span_of(c, "name")
    assert "output 'Yb'" in d.message and "ATmega328P" in d.message


def test_no_pins_needed_without_a_part():
    none(_io(None, {}), "LD407")
    pin0 = _io(M328, {"Xa": 4, "Yb": 0})  # LDmicro writes pin 0 for "no pin"
    assert one(pin0, "LD407").message.startswith("output 'Yb'")


def test_the_classic_pwm_name_needs_its_pin_as_ldmicro_and_the_build_say():
    # LDmicro 5.4: "Must assign pins for all I/O. 'P' is not assigned."
    classic = el("SET_PWM", duty="50", freq=1000, name="P")
    d = one(program([contact("Xa"), classic], mcu=M328, pins={"Xa": 4}), "LD407")
    assert d.message.startswith("PWM output 'P' has no pin") and d.span == span_of(classic, "name")


# --- LD408 / LD409 parts -----------------------------------------------------------------------------------


def test_part_known_to_ldmicro_without_data():
    prog = _io("St ARM STM32F40X 144-LQFP", {"Xa": 999})
    d = one(prog, "LD408")
    assert d.severity == "warning" and d.span is None and "STM32" in d.message
    none(prog, "LD402")  # no pin checks then
    none(prog, "LD409")


def test_unknown_part():
    d = one(_io("Zilog Z8 Encore", {}), "LD409")
    assert d.severity == "error" and "Zilog Z8 Encore" in d.message
    none(_io(M328, {"Xa": 4, "Yb": 14}), "LD409")
    none(_io("atmega328p", {"Xa": 4, "Yb": 14}), "LD408")


# --- LD410 / LD411 assignments that do nothing ----------------------------------------------------------------


def test_pin_on_a_relay():
    prog = program([contact("Xa"), coil("Rb")], [contact("Rb"), coil("Yc")], mcu=M328,
                   pins={"Xa": 4, "Rb": 5, "Yc": 14})
    d = one(prog, "LD410")
    assert d.severity == "warning" and d.span == prog.pins["Rb"].span and "'Rb'" in d.message
    none(_io(M328, {"Xa": 4, "Yb": 14}), "LD410")


def test_pin_on_an_unused_name():
    prog = _io(M328, {"Xa": 4, "Yb": 14, "Xgone": 5})
    d = one(prog, "LD411")
    assert d.severity == "warning" and d.span == prog.pins["Xgone"].span and "Xgone" in d.message
    none(_io(M328, {"Xa": 4, "Yb": 14, "Xgone": 0}), "LD411")


# --- LD501-LD504 what the part cannot do ---------------------------------------------------------------------


def test_instruction_the_family_cannot_compile():
    stop = el("NPULSE_OFF")
    pic = "Microchip PIC16F877 40-PDIP"
    prog = program([contact("Xa"), stop], mcu=pic, pins={"Xa": 2})
    d = one(prog, "LD501")
    assert d.severity == "warning" and d.span == span_of(stop)
    assert "NPULSE OFF" in d.message and "PIC16" in d.message
    # the same rule, an error when the program is about to be compiled
    built = [d for d in check_program(prog, for_build=True) if d.code == "LD501"]
    assert [(b.severity, b.span, b.message) for b in built] == [("error", d.span, d.message)]
    none(program([contact("Xa"), el("SLEEP")], mcu=M328, pins={"Xa": 4}), "LD501")
    none(program([contact("Xa"), el("SLEEP")], mcu=pic, pins={"Xa": 2}), "LD501")
    none(program([contact("Xa"), el("SLEEP")]), "LD501")  # no part: nothing to say


def test_read_adc_on_a_part_without_adc():
    r = el("READ_ADC", name="Ax")
    d = one(program([contact("Xa"), r], mcu="Microchip PIC16F628 18-PDIP or 18-SOIC"), "LD502")
    assert d.severity == "error" and d.span == span_of(r) and "PIC16F628" in d.message
    none(program([contact("Xa"), el("READ_ADC", name="Ax")], mcu=M328), "LD502")


def test_uart_on_a_part_without_uart():
    f = el("FORMATTED_STRING", var="", text="hi")
    d = one(program([contact("Xa"), f], mcu="Atmel AVR ATmega162 40-PDIP"), "LD503")
    assert d.severity == "error" and d.span == span_of(f) and "no UART" in d.message
    none(program([contact("Xa"), el("FORMATTED_STRING", var="", text="hi")], mcu=M328), "LD503")


@pytest.fixture
def part_without_pwm(monkeypatch):
    device = dataclasses.replace(find_device(M328), pwm={})
    monkeypatch.setattr(lang.devices, "find_device", lambda name: device)
    return device


def test_set_pwm_on_a_part_without_pwm(part_without_pwm):
    s = el("SET_PWM", duty="50", freq=1000, name="Pm")
    d = one(program([contact("Xa"), s], mcu=M328), "LD504")
    assert d.severity == "error" and d.span == span_of(s) and "no PWM" in d.message


def test_set_pwm_on_a_part_with_pwm():
    none(program([contact("Xa"), el("SET_PWM", duty="50", freq=1000, name="Pm")], mcu=M328), "LD504")
