"""Peripherals of compiled programs in simavr: A/D readings at their
thresholds, PWM duty and frequency on the pin, UART text byte for byte and
received bytes, PERSIST values surviving a reset with the EEPROM kept."""

from __future__ import annotations

import pytest
from test_compiler_harness import Event, differential, load, needs_simavr

import compiler
from compiler.avr.part import Part
from compiler.run import simavr as sa
from lang.ldfile import read_ld
from lang.sim import Simulator


def ld(text: str):
    program, problems = read_ld(text)
    assert not [p for p in problems if p.severity == "error"], problems
    return program


ADC = """LDmicro0.2
MICRO={micro}
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Ain at {pin} 0 0
    Ylow at {low} 0 0
    Yhigh at {high} 0 0
END

PROGRAM
RUNG 1
  PARALLEL
    READ_ADC Ain 0
    SERIES
      LEQ Ain 500
      COIL Ylow 0 0 0 0
    END
    SERIES
      GEQ Ain 501
      COIL Yhigh 0 0 0 0
    END
  END
END
"""


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("micro, pin, low, high", [
    ("Atmel AVR ATmega16 40-PDIP", 40, 1, 2),  # PA0, ADC0
    ("Atmel AVR ATmega2560 100-TQFP", "PF2", "PB0", "PB1"),  # ADC2
    ("Atmel AVR ATmega328 28-PDIP", 23, 14, 15),  # PC0, ADC0
])
def test_adc_readings_at_the_thresholds(micro, pin, low, high, tmp_path):
    program = ld(ADC.format(micro=micro, pin=pin, low=low, high=high))
    readings = [0, 499, 500, 501, 502, 1023, 1, 500, 1000, 501]
    events = [Event(10 * i, "Ain", value) for i, value in enumerate(readings)]
    assert differential(program, events, 10 * len(readings), tmp_path) == []


@needs_simavr
@pytest.mark.slow
def test_adc_channels_above_7_select_mux5(tmp_path):
    """simavr's ATmega2560 does not convert ADC8..15 (it reads 0), so the
    channel selection is checked in the registers: ADC10 is MUX5 in ADCSRB
    and 2 in ADMUX."""
    program = ld(ADC.format(micro="Atmel AVR ATmega2560 100-TQFP", pin="PK2", low="PB0", high="PB1"))
    build = compiler.build(program)
    build.write(tmp_path / "adc.hex")
    part = Part.of(build.device)
    run = sa.run_avr(tmp_path / "adc.hex", part.mmcu, 16_000_000,
                     ["run_to 400000", f"peek {part.reg('ADCSRB')} 1", f"peek {part.reg('ADMUX')} 1"])
    registers = [int(line.split()[2], 16) for line in run.raw.splitlines() if line.startswith("@peek")]
    assert registers == [1 << 3, 2]


PWM = """LDmicro0.2
MICRO={micro}
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Pout at {pins[0]} 0 0
    Xoff at {pins[1]} 0 0
    Xa at {pins[2]} 0 0
    Xb at {pins[3]} 0 0
    Xc at {pins[4]} 0 0
END

PROGRAM
RUNG 1
  CONTACTS Xa 1 0
  MOVE duty {duties[0]}
END
RUNG 2
  CONTACTS Xa 0 0
  MOVE duty {duties[1]}
END
RUNG 3
  CONTACTS Xb 0 0
  MOVE duty 0
END
RUNG 4
  CONTACTS Xc 0 0
  MOVE duty {full}
END
RUNG 5
  CONTACTS Xoff 1 0
  SET_PWM duty {freq} Pout 0-{full}{percent}
END
RUNG 6
  CONTACTS Xoff 0 0
  RES Pout
END
"""


def _duty(edges, start_ms, end_ms):
    """(period ms, high fraction) of a square wave between two times."""
    rises = [t for t, v in edges if v and start_ms <= t < end_ms]
    falls = [t for t, v in edges if not v and rises and rises[0] < t < end_ms]
    period = (rises[-1] - rises[0]) / (len(rises) - 1)
    high = sum(f - r for r, f in zip(rises, falls)) / min(len(rises), len(falls))
    return period, high / period


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("micro, pins, freq, full, duties", [
    # OC0A, fast PWM: 16 MHz / 256 / 64 = 976.6 Hz
    ("Atmel AVR ATmega328 28-PDIP", (12, 4, 5, 6, 11), 977, 100, (25, 90)),
    # OC2 of a one-register timer (TCCR2 holds mode, output and clock bits)
    ("Atmel AVR ATmega16 40-PDIP", (21, 16, 17, 18, 19), 977, 256, (64, 192)),
])
def test_pwm_duty_and_frequency_on_the_pin(micro, pins, freq, full, duties, tmp_path):
    program = ld(PWM.format(micro=micro, pins=pins, freq=freq, full=full, duties=duties,
                            percent="%" if full == 100 else ""))
    build = compiler.build(program)
    assert build.warnings == []
    hex_path = tmp_path / "pwm.hex"
    build.write(hex_path)
    device = build.device
    names = ("Pout", "Xoff", "Xa", "Xb", "Xc")
    pin = {n: f"{device.pin(program.pins[n].pin).port}{device.pin(program.pins[n].pin).bit}" for n in names}
    # 100 ms per phase: the first duty, the second, 0, full, off
    phases = [(0, 0, 0, 0), (0, 1, 0, 0), (0, 1, 1, 0), (0, 1, 0, 1), (1, 1, 0, 1)]
    inputs = [(100 * i + (5 if i else 0), pin[name], level) for i, levels in enumerate(phases)
              for name, level in zip(("Xoff", "Xa", "Xb", "Xc"), levels)]
    run = sa.simulate_avr(hex_path, build.device.part, 16_000_000, until_ms=500, inputs=inputs, watch=[pin["Pout"]])
    edges = run.pin_edges_ms(pin["Pout"])
    for i, duty in enumerate(duties):
        period, high = _duty(edges, 100 * i + 30, 100 * i + 95)
        assert period == pytest.approx(1000 / freq, rel=0.01)
        assert high == pytest.approx(duty / full, abs=1 / 256 + 0.002)
    for i, level in ((2, 0), (3, 1), (4, 0)):  # 0: low, full: high, RES: off (low)
        assert not [t for t, _ in edges if 100 * i + 20 < t < 100 * i + 100]
        assert run.level_at(pin["Pout"], 100 * i + 50) == level


@needs_simavr
@pytest.mark.slow
def test_formatted_strings_byte_for_byte(tmp_path):
    program = load("sample/hello.ld")
    build = compiler.build(program)
    hex_path = tmp_path / "hello.hex"
    build.write(hex_path)
    scans = 600
    sim = Simulator(program)
    sim.step(scans)
    run = sa.simulate_avr(hex_path, build.device.part, program.settings.crystal_hz, until_ms=scans * 10 - 5)
    assert run.uart_bytes() == sim.uart_output()
    assert b"Hello, world:      3\r\n" in run.uart_bytes()
    # each byte goes out in the scan the simulator sends it
    for (t_sim, byte), (t_avr, sent) in zip(sim.uart_sent(), run.uart_ms()):
        assert byte == sent and t_sim <= t_avr < t_sim + 1


ECHO = """LDmicro0.2
MICRO=Atmel AVR ATmega328 28-PDIP
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Ygot at 14 0 0
END

PROGRAM
RUNG 1
  UART_RECV c 1 0
  PARALLEL
    COIL Ygot 0 0 0 0
    UART_SEND c 1 0
  END
END
RUNG 2
  UART_RECV_AVAIL
  COIL Rwaiting 0 0 0 0
END
"""


@needs_simavr
@pytest.mark.slow
def test_received_bytes_are_taken_and_echoed(tmp_path):
    program = ld(ECHO)
    events = [Event(2, "uart", 65), Event(3, "uart", 0x9C), Event(6, "uart", 10), Event(6, "uart", 255)]
    assert differential(program, events, 15, tmp_path) == []


PERSIST = """LDmicro0.2
MICRO=Atmel AVR ATmega328 28-PDIP
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Xinc at 4 0 0
END

VAR LIST
    4 bytes total
END

PROGRAM
RUNG 1
  PARALLEL
    PERSIST count
    PERSIST total
  END
END
RUNG 2
  CONTACTS Xinc 0 0
  OSR
  PARALLEL
    ADD count count 1
    ADD total total 100000
  END
END
"""


@needs_simavr
@pytest.mark.slow
def test_persist_survives_a_reset(tmp_path):
    program = ld(PERSIST)
    build = compiler.build(program)
    hex_path = tmp_path / "persist.hex"
    build.write(hex_path)
    freq = program.settings.crystal_hz

    def at(ms):
        return f"run_to {round(ms * freq / 1000)}"

    count, total = build.image.symbols["count"], build.image.symbols["total"]
    peek = [f"peek {count.address} 2", f"peek {total.address} 4"]
    pulses = [f"{at(t)}\ndrive D 2 {v}" for t, v in ((55, 1), (75, 0), (95, 1), (115, 0), (135, 1), (155, 0))]
    commands = ["drive D 2 0"] + "\n".join(pulses).split("\n") + [at(300)] + peek + ["reset", at(350)] + peek
    commands += [at(365), "drive D 2 1", at(400)] + peek + [at(600), "eeprom_read 0 6"]
    run = sa.run_avr(hex_path, build.device.part, freq, commands)
    values = [line.split()[2:] for line in run.raw.splitlines() if line.startswith("@peek")]
    got = [int.from_bytes(bytes(int(b, 16) for b in v), "little", signed=True) for v in values]
    # the simulator: EEPROM erased (count -1, total -1), three pulses, a reset
    # that keeps the EEPROM, one more pulse
    sim = Simulator(program)
    for scans, level in ((6, 0), (2, 1), (2, 0), (2, 1), (2, 0), (2, 1), (14, 0)):
        sim.set("Xinc", level)
        sim.step(scans)
    expected = [sim.value("count"), sim.value("total")]
    sim.reset(keep_eeprom=True)
    sim.set("Xinc", 0)
    sim.step(5)
    expected += [sim.value("count"), sim.value("total")]
    sim.set("Xinc", 1)
    sim.step(4)
    expected += [sim.value("count"), sim.value("total")]
    assert expected[:2] == [2, 299999] and expected[2:4] == expected[:2]
    assert got == expected
    eeprom = bytes(int(b, 16) for b in run.raw.split("@eeprom")[1].split("\n")[0].split())
    assert eeprom == (3).to_bytes(2, "little") + (399999).to_bytes(4, "little")


WAITING = """LDmicro0.2
MICRO=Atmel AVR ATmega328 28-PDIP
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Xa at 4 0 0
    Ygot at 14 0 0
END

VAR LIST
    4 bytes pair
END

PROGRAM
RUNG 1
  MOVE word 0x4142
END
RUNG 2
  CONTACTS Xa 0 0
  OSR
  UART_SEND word 2 1
END
RUNG 3
  UART_RECV pair 3 1
  COIL Ygot 0 0 0 0
END
"""


@needs_simavr
@pytest.mark.slow
def test_sending_and_receiving_several_bytes_waiting_for_the_uart(tmp_path):
    """With `wait` the scan waits for the transmitter between bytes and for
    every byte received (the UART holds three)."""
    program = ld(WAITING)
    events = [Event(0, "Xa", 0), Event(3, "Xa", 1), Event(7, "Xa", 0), Event(9, "Xa", 1)]
    events += [Event(5, "uart", b) for b in (1, 2, 3)] + [Event(12, "uart", b) for b in (0xF0, 0x0F, 0x80)]
    assert differential(program, events, 20, tmp_path) == []
    build = compiler.build(program)
    build.write(tmp_path / "w.hex")
    run = sa.simulate_avr(tmp_path / "w.hex", build.device.part, 16_000_000, until_ms=200,
                          inputs=[(0, "D2", 0), (25, "D2", 1), (65, "D2", 0), (85, "D2", 1)])
    assert run.uart_bytes() == b"BABA"
