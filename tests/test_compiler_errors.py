"""What the compiler refuses, each a located diagnostic: no part or a part
it does not compile for, instructions and operands it has no code for, a
cycle time, baud rate or PWM output the crystal and timers cannot make,
programs, variables and PERSIST data larger than the part."""

from __future__ import annotations

import dataclasses

import pytest
from builders import coil, contact, el, move, program, span_of

import compiler
from compiler.backend import BACKENDS
from compiler.errors import CompileError
from lang.families import FAMILIES, parts_text
from lang.model import PinAssignment

M328 = "Atmel AVR ATmega328 28-PDIP"
M8 = "Atmel AVR ATmega8 28-PDIP"


def part(prog, mcu=M328, **settings):
    prog.settings.mcu = mcu
    for name, value in settings.items():
        setattr(prog.settings, name, value)
    return prog


def errors(prog, target=None) -> list:
    with pytest.raises(CompileError) as failure:
        compiler.build(prog, target)
    return failure.value.diagnostics


def codes(prog, target=None) -> list[str]:
    return [d.code for d in errors(prog, target)]


def basic():
    prog = program([contact("Xa"), coil("Ya")])
    prog.pins = {"Xa": PinAssignment("Xa", "PD2"), "Ya": PinAssignment("Ya", "PB0")}
    return prog


def test_a_part_no_back_end_compiles_has_no_target(monkeypatch):
    found = errors(basic())
    assert [d.code for d in found] == ["LD701"]
    assert found[0].message == f"cannot compile for no part: ladder build compiles for {parts_text()}"
    assert codes(part(basic(), "St ARM STM32F40X 144-LQFP")) == ["LD701"]  # no pin data
    assert compiler.build(part(basic())).device.part == "atmega328p"
    assert compiler.build(basic(), "atmega16").device.part == "atmega16"
    # the registry decides: a part its family does not list, a family without a back end
    avr = FAMILIES["avr"]
    monkeypatch.setitem(FAMILIES, "avr", dataclasses.replace(avr, parts=tuple(p for p in avr.parts if p != "atmega16")))
    assert codes(basic(), "atmega16") == ["LD701"]
    monkeypatch.delitem(BACKENDS, "pic16", raising=False)
    found = errors(part(basic(), "Microchip PIC16F877 40-PDIP"))
    assert [d.code for d in found] == ["LD701"] and "the PIC16 back end is not installed" in found[0].message


def test_instructions_without_the_avr_layer_are_located_errors():
    prog = part(program([contact("Xa"), el("SPI", name="SPI1", send="s", recv="d")], [move("s", 3)]))
    prog.pins = {"Xa": PinAssignment("Xa", "PD2")}
    found = errors(prog)
    assert [d.code for d in found] == ["LD501"]
    assert found[0].span == prog.rungs[0].circuit.items[1].span


def test_indirect_register_access_is_not_compiled():
    prog = part(program([contact("Xa"), move("#0x1234", 5)]))
    prog.pins = {"Xa": PinAssignment("Xa", "PD2")}
    found = errors(prog)
    assert [d.code for d in found] == ["LD702"]
    assert found[0].span == prog.rungs[0].circuit.items[1].span
    prog = part(program([contact("Xa"), move("#PORTB", 5)]))
    prog.pins = {"Xa": PinAssignment("Xa", "PD2")}
    assert compiler.build(prog).image.symbols["#PORTB"].address == 0x25


def test_a_cycle_time_timer1_cannot_make():
    assert codes(part(basic(), cycle_us=10_000_000)) == ["LD706"]
    assert codes(part(basic(), cycle_us=10, crystal_hz=1_050_000)) == ["LD706"]
    assert compiler.build(part(basic(), cycle_us=1000, crystal_hz=7_372_800)).summary()


def uart_program(**settings):
    prog = part(program([contact("Xa"), el("UART_SEND", var="v")]), **settings)
    prog.pins = {"Xa": PinAssignment("Xa", "PD2")}
    return prog


def test_a_baud_rate_off_by_more_than_two_percent():
    found = errors(uart_program(baud=115200))
    assert [d.code for d in found] == ["LD707"]
    assert "115200" in found[0].message
    assert compiler.build(uart_program(baud=115200, crystal_hz=14_745_600))
    assert compiler.build(uart_program(baud=9600))


def pwm_program(pin: str, freq: int = 976, other: str | None = None, other_freq: int = 976):
    rungs = [[contact("Xa"), el("SET_PWM", duty="50", freq=freq, name="Pa", resolution="0-100%")]]
    if other:
        rungs.append([contact("Xa"), el("SET_PWM", duty="20", freq=other_freq, name="Pb", resolution="0-100%")])
    prog = part(program(*rungs))
    prog.pins = {"Xa": PinAssignment("Xa", "PD2"), "Pa": PinAssignment("Pa", pin)}
    if other:
        prog.pins["Pb"] = PinAssignment("Pb", other)
    return prog


def test_pwm_outputs_the_back_end_cannot_drive():
    prog = pwm_program("PB1")  # OC1A: Timer1 makes the scan cycle
    found = errors(prog)
    assert [d.code for d in found] == ["LD708"]
    assert found[0].span == span_of(prog.rungs[0].circuit.items[1])
    assert codes(pwm_program("PD6", other="PD5", other_freq=61)) == ["LD708"]  # one timer, two frequencies
    assert compiler.build(pwm_program("PD6", other="PD5")).warnings == []
    warned = compiler.build(pwm_program("PB3", freq=1200))
    assert [d.code for d in warned.warnings] == ["LD709"]
    assert "asked 1200 Hz" in warned.warnings[0].message


def test_a_program_larger_than_flash():
    rungs = [[contact("Xa"), el("MUL", dest=f"v{i}", op1=f"w{i % 100}", op2="1000")] for i in range(700)]
    rungs.append([contact("Xa"), coil("Ya")])
    prog = part(program(*rungs), M8)
    prog.pins = {"Xa": PinAssignment("Xa", "PD2"), "Ya": PinAssignment("Ya", "PB0")}
    prog.var_sizes.update({f"v{i}": 1 for i in range(700)} | {f"w{i}": 1 for i in range(100)})
    found = errors(prog)
    assert [d.code for d in found] == ["LD703"]
    assert "8192" in found[0].message


def test_variables_larger_than_ram():
    rungs = [[contact("Xa"), move(f"v{i}", 1)] for i in range(300)]
    prog = part(program(*rungs), M8)
    prog.pins = {"Xa": PinAssignment("Xa", "PD2")}
    prog.var_sizes.update({f"v{i}": 4 for i in range(300)})
    assert codes(prog) == ["LD704"]


def test_persist_variables_larger_than_eeprom():
    rungs = [[contact("Xa"), move(f"v{i}", 1)] for i in range(140)]
    rungs += [[el("PERSIST", var=f"v{i}")] for i in range(140)]
    prog = part(program(*rungs), M8)
    prog.pins = {"Xa": PinAssignment("Xa", "PD2")}
    prog.var_sizes.update({f"v{i}": 4 for i in range(140)})
    found = errors(prog)
    assert [d.code for d in found] == ["LD705"]
    assert found[0].span == prog.rungs[268].circuit.items[0].span  # the 129th: 516 bytes > 512


def test_retargeting_by_port_name_and_by_package_pin_number():
    prog = basic()
    prog.settings.mcu = M328
    assert compiler.build(prog, "atmega2560").warnings == []  # port names carry over
    numbered = program([contact("Xa"), coil("Ya")], mcu=M328, pins={"Xa": 4, "Ya": 14})  # PD2, PB0
    moved = compiler.build(numbered, "atmega16")  # pin 4 is PB3, pin 14 PD0 on the ATmega16
    assert [d.code for d in moved.warnings] == ["LD711", "LD711"]
    assert moved.warnings[0].span == numbered.pins["Xa"].span
    numbered.pins["Ya"] = PinAssignment("Ya", 60)
    assert "LD402" in codes(numbered, "atmega16")  # the 40-pin ATmega16 has no pin 60


def test_check_errors_stop_the_build():
    prog = part(program([contact("Xa"), coil("Ya")]))  # no pins
    assert set(codes(prog)) == {"LD407"}
