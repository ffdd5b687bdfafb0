"""Simulated peripherals: ADC, UART (timing and exact text), formatted
strings, PWM and EEPROM (PERSIST across a reset)."""

from __future__ import annotations

import pytest
from builders import coil, contact, el, program

from lang.sim import SimulationError, Simulator
from lang.strings import parse_format


def test_read_adc_copies_the_reading_when_powered():
    sim = Simulator(program([contact("Xread"), el("READ_ADC", name="Apot", refs=0)]))
    sim.set_adc("Apot", 512)
    sim.step()
    assert sim.value("Apot") == 0
    sim.set_input("Xread", 1)
    sim.step()
    assert sim.value("Apot") == 512
    with pytest.raises(ValueError):
        sim.set_adc("Apot", 1024)


def fstring(text: str, var: str = "", **kwargs) -> Simulator:
    return Simulator(program([contact("Xgo"), el("FORMATTED_STRING", var=var, text=text), coil("Ysending")],
                             **kwargs))


@pytest.mark.parametrize("text, value, sent", [
    ("value: \\3\\r\\n", 12, b"value:  12\r\n"),
    ("\\3", 0, b"  0"),
    ("\\5", 1234, b" 1234"),
    ("[\\-3]", -7, b"[-  7]"),
    ("[\\-3]", 45, b"[  45]"),
    ("\\x41\\t\\\\\\e", 0, b"A\t\\\x1b"),
    ("\\3", 1234, b"<34"),  # too many digits: LDmicro's code sends '0' + 12 first
])
def test_formatted_string_text(text, value, sent):
    var = "v" if "\\3" in text or "\\5" in text or "\\-" in text else ""
    sim = fstring(text, var)
    if var:
        sim.set_variable("v", value)
    sim.set_input("Xgo", 1)
    sim.step(30)
    assert sim.uart_output() == sent


def test_formatted_string_one_character_per_scan_while_busy():
    sim = fstring("abc")
    sim.set_input("Xgo", 1)
    outputs = []
    for _ in range(5):
        sim.step()
        outputs.append(sim.value("Ysending"))
        sim.set_input("Xgo", 0)  # sending goes on once started
    assert [t for t, _ in sim.uart_sent()] == [0, 10, 20]
    assert outputs == [1, 1, 0, 0, 0]
    assert sim.uart_output() == b"abc"


def test_formatted_string_waits_for_a_slow_uart():
    # 300 baud: a byte takes 33.3 ms, 3.33 scans of 10 ms: one byte every 4 scans
    sim = fstring("ab", baud=300)
    sim.set_input("Xgo", 1)
    sim.step(10)
    assert [t for t, _ in sim.uart_sent()] == [0, 40]


def test_formatted_string_bad_escape_is_a_located_error():
    with pytest.raises(SimulationError) as raised:
        fstring("\\q")
    assert raised.value.diagnostics[0].code == "LD604"


def test_parse_format_escapes():
    fmt = parse_format("\\-2\\0n")
    assert fmt.steps == (("s", None), ("d", 0), ("d", 1), ("c", 10)) and fmt.signed and fmt.digits == 2
    with pytest.raises(ValueError):
        parse_format("\\1\\2")


def test_uart_send_busy_for_the_byte_time():
    # 9600 baud: 1.04 ms per byte; at a 0.5 ms cycle busy for 3 scans
    sim = Simulator(program([contact("Xsend"), el("UART_SEND", var="c", bytes=1, wait=0), coil("Ybusy")],
                            [el("UART_SEND_READY"), coil("Yready")], cycle_us=500))
    sim.set_variable("c", ord("A"))
    sim.set_input("Xsend", 1)
    sim.step()
    sim.set_input("Xsend", 0)
    busy, ready = [sim.value("Ybusy")], [sim.value("Yready")]
    for _ in range(4):
        sim.step()
        busy.append(sim.value("Ybusy"))
        ready.append(sim.value("Yready"))
    assert busy == [1, 1, 1, 0, 0] and ready == [0, 0, 0, 1, 1]
    assert sim.uart_output() == b"A"


def test_uart_receive_one_byte_per_scan():
    sim = Simulator(program([el("UART_RECV_AVAIL"), coil("Yavail")],
                            [el("UART_RECV", var="c", bytes=1, wait=0), coil("Ygot")]))
    sim.uart_receive(b"hi")
    got = []
    for _ in range(3):
        sim.step()
        got.append((sim.value("Yavail"), sim.value("Ygot"), sim.value("c")))
    assert got == [(1, 1, ord("h")), (1, 1, ord("i")), (0, 0, ord("i"))]


def test_uart_multi_byte_send_low_byte_first():
    sim = Simulator(program([contact("Xsend"), el("UART_SEND", var="w", bytes=2, wait=0)]))
    sim.set_variable("w", 0x4142)
    sim.set_input("Xsend", 1)
    sim.step()
    sim.set_input("Xsend", 0)
    sim.step(3)
    assert sim.uart_output() == b"BA"


def test_pwm_duty_and_reset():
    sim = Simulator(program([contact("Xon"), el("SET_PWM", duty="d", freq=1000, name="Pout", resolution="0-100%")],
                            [contact("Xoff"), el("RES", name="Pout")],
                            [contact("Pout"), coil("Yrunning")]))
    sim.set_variable("d", 40)
    sim.set_input("Xon", 1)
    sim.step()
    out = sim.pwm()["Pout"]
    assert (out.duty, out.freq_hz, out.on, sim.value("Yrunning")) == (40, 1000, True, 1)
    sim.set_input("Xon", 0)
    sim.set_input("Xoff", 1)
    sim.step()
    assert sim.pwm()["Pout"].on is False and sim.value("Yrunning") == 0


def persistent() -> Simulator:
    return Simulator(program([el("PERSIST", var="saved")],
                             [contact("Xinc"), el("OSR"), el("ADD", dest="saved", op1="saved", op2="1")]))


def test_fresh_eeprom_reads_minus_one():
    sim = persistent()
    sim.step()
    assert sim.value("saved") == -1


def test_persist_survives_a_reset():
    sim = persistent()
    sim.step()
    for _ in range(3):
        sim.set_input("Xinc", 1)
        sim.step()
        sim.set_input("Xinc", 0)
        sim.step()
    assert sim.value("saved") == 2
    sim.reset()
    assert sim.value("saved") == 0
    sim.step()
    assert sim.value("saved") == 2
    sim.reset(keep_eeprom=False)
    sim.step()
    assert sim.value("saved") == -1


def test_set_routes_to_adc_bit_or_variable():
    sim = Simulator(program([el("READ_ADC", name="Apot", refs=0)], [contact("Xa"), el("MOVE", dest="v", src="Apot")]))
    sim.set("Apot", 300)
    sim.set("Xa", 1)
    sim.set("v", 7)
    assert sim.value("v") == 7
    sim.step()
    assert sim.value("Apot") == 300 and sim.value("v") == 300
