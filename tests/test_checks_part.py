"""`ladder check` says what `ladder build` would say about the program's own
part: the same code, message and place, without compiling. Real programs
(avr-hw.ld's unassigned PWM name, test-pwm.ld's approximated frequency,
pic-adc.ld's digital pin made analog), each part rule on both families, the
input-only MCLR pins, PERSIST beyond the EEPROM, indirect access to a
register the part lacks, operand forms with no code, and a property over the
corpus and random programs: what a build reports is among what the check
reports, but for what only the compiled code can tell (its size, its scan
time)."""

from __future__ import annotations

from pathlib import Path

import pytest
from builders import coil, contact, el, move, program
from corpus import CORPUS, all_ld_files
from generators import programs
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import compiler
from compiler.errors import CompileError
from ladder.cli import main
from lang import ldfile
from lang.checks import check_program
from lang.devices import all_devices, find_device
from lang.families import compiled
from lang.instructions import INSTRUCTIONS

M328 = "Atmel AVR ATmega328 28-PDIP"
P877 = "Microchip PIC16F877 40-PDIP"
P887 = "Microchip PIC16F887 40-PDIP"
P72 = "Microchip PIC16F72 28-Pin PDIP, SOIC, SSOP"

# What only the compiled image can tell: flash and RAM use, the scan's worst case.
NEEDS_THE_IMAGE = {"LD703", "LD704", "LD712"}

# The MCLR pins that double as an input and cannot drive (the datasheets' pin tables
# and MCLRE configuration bit: "input only"); nothing else of these parts is.
INPUT_ONLY = {
    "pic12f675": {"GP3"}, "pic12f683": {"GP3"}, "pic10f200": {"GP3"}, "pic10f202": {"GP3"},
    "pic16f628": {"RA5"}, "pic16f628a": {"RA5"}, "pic16f819": {"RA5"}, "pic16f88": {"RA5"},
    "pic16f886": {"RE3"}, "pic16f887": {"RE3"},
    "pic12f1840": {"RA3"}, "pic16f1824": {"RA3"}, "pic16f1827": {"RA5"}, "pic16f1512": {"RE3"}, "pic16f1516": {"RE3"},
}


def _key(d):
    return d.code, d.message, d.span


def _built(prog) -> list:
    """What `ladder build` reports: its errors, or its warnings."""
    try:
        return compiler.build(prog).warnings
    except CompileError as failure:
        return failure.diagnostics


def _same_in_check_and_build(prog, code: str):
    """The one diagnostic `code` of the check, which the build reports as it is."""
    checked = [d for d in check_program(prog) if d.code == code]
    assert len(checked) == 1, checked
    assert _key(checked[0]) in {_key(d) for d in _built(prog)}
    return checked[0]


def _corpus(relative: str):
    path = CORPUS / "ldmicro" / relative
    if not path.exists():
        pytest.skip("no corpus beside the repository")
    return ldfile.read_ld_bytes(path.read_bytes())[0]


# --- the programs of the issue ------------------------------------------------------------


def test_avr_hw_unassigned_pwm_name_is_reported_by_check_as_by_build_and_ldmicro():
    # LDmicro 5.4.1.1: "Must assign pins for all I/O. 'P' is not assigned."
    d = _same_in_check_and_build(_corpus("reg/tests/avr-hw.ld"), "LD407")
    assert d.severity == "error" and d.message.startswith("PWM output 'P' has no pin")


def test_approximated_pwm_frequency_is_reported_by_check():
    d = _same_in_check_and_build(_corpus("Tests/test-pwm.ld"), "LD709")
    assert d.severity == "warning" and d.message == "PWM on OC2A runs at 1800.0 Hz (asked 1200 Hz)"


def test_digital_pin_made_analog_is_reported_by_check():
    d = _same_in_check_and_build(_corpus("sample/pic-adc.ld"), "LD714")
    assert d.message.startswith("'Xlimit' is on RA0 (AN0), which the PIC16F877 makes analog")


def test_ladder_check_on_the_file_reports_it(tmp_path, capsys):
    source = CORPUS / "ldmicro" / "reg" / "tests" / "avr-hw.ld"
    if not source.exists():
        pytest.skip("no corpus beside the repository")
    copy = tmp_path / "avr-hw.ld"
    copy.write_bytes(source.read_bytes())
    assert main(["check", str(copy)]) == 1
    assert "error LD407 PWM output 'P' has no pin: assign it a pin of the ATmega128" in capsys.readouterr().out


# --- each part rule, on both families ------------------------------------------------------------


def _pwm(name="Pa", freq=1000, duty="50", resolution=""):
    return el("SET_PWM", duty=duty, freq=freq, name=name, resolution=resolution)


def test_pwm_on_the_cycle_timer_is_refused_by_check():
    prog = program([contact("Xa"), _pwm()], mcu=M328, pins={"Xa": 4, "Pa": 15})  # PB1: OC1A
    d = _same_in_check_and_build(prog, "LD708")
    assert d.message == "PWM on OC1A: Timer1 makes the scan cycle; use an 8-bit timer's output"


@pytest.mark.parametrize("mcu, pins, timer", [(M328, {"Pa": 12, "Pb": 11}, 0),  # OC0A, OC0B
                                              (P877, {"Pa": 17, "Pb": 16}, 2)])  # CCP1, CCP2
def test_two_outputs_of_one_timer_at_different_frequencies(mcu, pins, timer):
    prog = program([contact("Xa"), _pwm("Pa", 1000)], [contact("Xa"), _pwm("Pb", 250)],
                   mcu=mcu, pins={"Xa": 4 if mcu == M328 else 33, **pins})
    d = _same_in_check_and_build(prog, "LD708")
    assert d.message.startswith(f"the outputs of Timer{timer} ask for different PWM frequencies")
    assert d.span == prog.rungs[1].circuit.items[1].span


def test_pic16_pwm_frequency_approximated_at_check():
    prog = program([contact("Xa"), _pwm("Pa", 100)], mcu=P877, pins={"Xa": 33, "Pa": 17}, crystal_hz=20_000_000)
    d = _same_in_check_and_build(prog, "LD709")
    assert d.message == "PWM on CCP1 runs at 1220.7 Hz (asked 100 Hz)"


def test_cycle_time_the_timer_cannot_make_is_refused_by_check():
    prog = program([contact("Xa"), coil("Yb")], mcu=M328, pins={"Xa": 4, "Yb": 5}, cycle_us=10_000_000)
    d = _same_in_check_and_build(prog, "LD706")
    assert d.message.startswith("a 10000 ms cycle cannot be made from a 16 MHz crystal")


def test_pic16_long_cycle_runs_timer1_free_and_passes_both():
    # longer than Timer1 counts (0.52 s at 4 MHz): counted in software, as the build does
    prog = program([contact("Xa"), coil("Yb")], mcu=P877, pins={"Xa": 33, "Yb": 34}, cycle_us=2_000_000,
                   crystal_hz=4_000_000)
    assert not [d for d in check_program(prog) if d.code == "LD706"]
    compiler.build(prog)


@pytest.mark.parametrize("mcu, crystal, baud, code", [(M328, 16_000_000, 115200, "LD707"),
                                                      (P877, 4_000_000, 115200, "LD707"),
                                                      (P877, 8_000_000, 57600, "LD713")])
def test_baud_rates_at_check(mcu, crystal, baud, code):
    prog = program([contact("Xa"), el("UART_SEND", var="c")], mcu=mcu, pins={"Xa": 4 if mcu == M328 else 33},
                   crystal_hz=crystal, baud=baud)
    d = _same_in_check_and_build(prog, code)
    assert d.span == prog.rungs[0].circuit.items[1].span


def test_part_rules_stay_quiet_without_a_part_or_for_c():
    prog = program([contact("Xa"), _pwm()], mcu=None, cycle_us=10_000_000, baud=115200)
    assert not [d for d in check_program(prog) if d.code[2] == "7"]
    assert not [d for d in check_program(program([_pwm()], mcu=M328, cycle_us=10_000_000), family="c")
                if d.code[2] == "7"]


# --- PERSIST, indirect registers and operand forms, known before any code is written ---------------


def test_persist_on_a_part_without_eeprom_is_reported_by_check():
    prog = program([contact("Xa"), el("PERSIST", var="count")], mcu=P72, pins={"Xa": 2}, crystal_hz=4_000_000)
    d = _same_in_check_and_build(prog, "LD705")
    assert d.message == "the PERSIST variables need 2 bytes of EEPROM; the part has 0"
    assert d.span == prog.rungs[0].circuit.items[1].span


def test_persist_beyond_the_eeprom_is_reported_on_the_first_that_does_not_fit():
    rungs = [[contact("Xa"), el("PERSIST", var=f"v{i}")] for i in range(130)]
    prog = program(*rungs, mcu="Atmel AVR ATmega8 28-PDIP", pins={"Xa": 4}, sizes={f"v{i}": 4 for i in range(130)})
    d = _same_in_check_and_build(prog, "LD705")
    assert d.message == "the PERSIST variables need 516 bytes of EEPROM; the part has 512"
    assert d.span == prog.rungs[128].circuit.items[1].span
    # a timer kept in the EEPROM takes the bytes its delay needs, as the lowering gives it
    fits = program([contact("Xa"), el("PERSIST", var="v")], mcu=M328, pins={"Xa": 4})
    assert not [d for d in check_program(fits) if d.code == "LD705"]
    compiler.build(fits)


@pytest.mark.parametrize("mcu, name, pin", [(M328, "#0x1234", 4), (M328, "#TRISZ", 4), (P877, "#0x200", 33),
                                            (P877, "#PORTF", 33)])
def test_a_register_the_part_does_not_have_is_reported_by_check(mcu, name, pin):
    prog = program([contact("Xa"), move(name, 5)], [contact("Xa"), move("v", name)], mcu=mcu, pins={"Xa": pin})
    d = _same_in_check_and_build(prog, "LD702")
    assert d.message.startswith(f"'{name}' names no register of the ")
    assert d.span == prog.rungs[0].circuit.items[1].span  # the first use, as the build says


@pytest.mark.parametrize("mcu, pin, name", [(M328, 4, "#PORTB"), (M328, 4, "#TRISB"), (M328, 4, "#0x25"),
                                            (P877, 33, "#PINB"), (P877, 33, "#DDRA"), (P877, 33, "#0x1FF")])
def test_each_familys_register_names_pass_both(mcu, pin, name):
    prog = program([contact("Xa"), move(name, 5)], mcu=mcu, pins={"Xa": pin})
    assert not [d for d in check_program(prog) if d.code == "LD702"]
    compiler.build(prog)


@pytest.mark.parametrize("element, message", [
    (el("DELAY", delay="-5"), "a delay cannot be negative"),
    (el("TIME2COUNT", name="v", delay="Tvar", adjust=0), "the T2CNT delay must be a time, not a variable"),
    (el("TIME2DELAY", name="v", delay="Tvar"), "the T2DLY delay must be a time"),
    (el("UART_RECV", var="v", bytes=3), "UART RECV of 3 bytes into 'v' of 2 bytes"),
])
@pytest.mark.parametrize("mcu, pin", [(M328, 4), (P877, 33)])
def test_operand_forms_without_code_are_reported_by_check(element, message, mcu, pin):
    prog = program([contact("Xa"), element], mcu=mcu, pins={"Xa": pin})
    d = _same_in_check_and_build(prog, "LD710")
    assert d.message == message and d.span == prog.rungs[0].circuit.items[1].span


def test_a_pwm_resolution_the_instruction_does_not_have_is_reported_by_check():
    prog = program([contact("Xa"), _pwm("Pa", 976, resolution="0-2048")], mcu=M328, pins={"Xa": 4, "Pa": 12})
    d = _same_in_check_and_build(prog, "LD710")
    assert d.message == "unknown PWM resolution '0-2048'"


def _with_operand(spec, field: str, name: str):
    """An element of the instruction with `name` in `field` and ordinary operands elsewhere."""
    args = {}
    for other in spec.fields:
        if other.name == field:
            args[other.name] = name
        elif other.kind in ("var", "operand"):
            args[other.name] = f"v_{other.name}"
        elif other.kind == "delay":
            args[other.name] = 100_000
        elif other.kind == "bit":
            args[other.name] = f"Rother_{other.name}"
        elif other.kind == "values":
            args[other.name] = [1, 2, 3, 4]
        elif other.kind == "points":
            args[other.name] = [(0, 0), (10, 10)]
        elif other.kind == "text":
            args[other.name] = "value \\3"
        elif other.kind == "label":
            args[other.name] = "L1"
        else:
            args[other.name] = other.default if other.default is not None else 1
    return el(spec.key, **args)


INTEGER_FIELDS = [(spec.key, field.name) for spec in INSTRUCTIONS.values() if spec.supports("avr")
                  for field in spec.fields if field.kind in ("var", "operand", "delay")]


@pytest.mark.parametrize("kind, field", INTEGER_FIELDS)
def test_a_bit_where_the_lowering_needs_an_integer_is_reported_by_check(kind, field):
    """Every variable, operand and delay field of the table: where the build
    refuses a coil's name, the check does, at the same element."""
    element = _with_operand(INSTRUCTIONS[kind], field, "Rbit")
    prog = program([contact("Xa"), coil("Rbit")], [contact("Xa"), element], [el("LABEL", label="L1")],
                   mcu=M328, pins={"Xa": 4})
    refused = [d for d in _built(prog) if d.message == "'Rbit' is a bit; it cannot hold an integer"]
    checked = [d for d in check_program(prog) if d.code == "LD710" and "'Rbit'" in d.message]
    assert [_key(d) for d in checked] == [_key(d) for d in refused]


def test_operand_forms_are_not_part_rules_without_a_part():
    prog = program([contact("Xa"), el("DELAY", delay="-5")])
    assert not [d for d in check_program(prog) if d.code == "LD710"]
    assert [d.code for d in check_program(prog, family="c") if d.code == "LD710"] == ["LD710"]


# --- input-only pins ------------------------------------------------------------------------------


def test_input_only_pins_are_the_datasheets_and_ldmicros():
    for device in all_devices():
        marked = {pin.name for pin in device.pins.values() if pin.input_only}
        assert marked == INPUT_ONLY.get(device.part, set()), device
        # LDmicro's own pin list says "(Input Only)" (the PIC16F1824's "(Input only)") of exactly these
        labelled = {pin.name for pin in device.io_pins() if "(input only)" in pin.label.lower()}
        assert marked == labelled, device
        assert all(device.pin(name).is_io for name in marked)


@pytest.mark.parametrize("part", sorted(INPUT_ONLY))
def test_an_output_on_an_input_only_pin_is_an_error_at_check_and_build(part):
    device = find_device(part)
    pin = next(p for p in device.pins.values() if p.input_only)
    other = next(p for p in device.io_pins() if not p.input_only and p.name not in device.uart.values())
    mcu = device.ldmicro_name or part
    prog = program([contact("Xa"), coil("Yout")], mcu=mcu, pins={"Xa": other.number, "Yout": pin.number},
                   crystal_hz=4_000_000)
    d = _same_in_check_and_build(prog, "LD412")
    assert d.severity == "error" and d.span == prog.pins["Yout"].span
    assert f"({pin.name}), which can only be an input on the {device.title}" in d.message
    # as an input it is fine
    reading = program([contact("Xin"), coil("Yout")], mcu=mcu, pins={"Xin": pin.number, "Yout": other.number},
                      crystal_hz=4_000_000)
    assert not [d for d in check_program(reading) if d.code == "LD412"]
    if compiled(device):
        compiler.build(reading)


# --- what a build reports, the check reports ------------------------------------------------------


def _build_within_check(prog) -> None:
    checked = {_key(d) for d in check_program(prog)}
    missing = [d for d in _built(prog) if _key(d) not in checked and d.code not in NEEDS_THE_IMAGE]
    assert not missing, missing


def _compiled_corpus() -> list[Path]:
    return [path for path in all_ld_files() if _names_a_compiled_part(ldfile.read_ld_bytes(path.read_bytes())[0])]


@pytest.mark.skipif(not all_ld_files(), reason="no corpus beside the repository")
def test_every_corpus_program_for_a_compiled_part_builds_within_its_check():
    paths = _compiled_corpus()
    assert len(paths) >= 20
    for path in paths:
        _build_within_check(ldfile.read_ld_bytes(path.read_bytes())[0])


def _names_a_compiled_part(prog) -> bool:
    device = find_device(prog.settings.mcu) if prog.settings.mcu else None
    return device is not None and compiled(device)


COMPILED = [device for device in all_devices() if compiled(device)]

# elements some of whose forms no back end compiles, with forms that compile beside them
ODD = (lambda: el("SLEEP"), lambda: el("9SEGMENTS", dest="Vseg", src="Vsrc"),
       lambda: move("#0x1234", 1), lambda: move("#PORTB", 1), lambda: move("Vreg", "#TRISC"), lambda: move("#0x60", 2),
       lambda: el("DELAY", delay="-1"), lambda: el("DELAY", delay="10"),
       lambda: el("TIME2COUNT", name="Vt", delay="Vdelay", adjust=0),
       lambda: el("TIME2COUNT", name="Vt", delay=100_000, adjust=0),
       lambda: el("TIME2DELAY", name="Vd", delay="Vdelay"), lambda: el("TIME2DELAY", name="Vd", delay=-3),
       lambda: el("UART_RECV", var="Vrecv", bytes=3), lambda: el("UART_RECV", var="Vrecv", bytes=2))


@st.composite
def part_programs(draw):
    """A program for a compiled part that leans on its hardware: inputs and
    outputs on any of its pins (the MCLR input among them), PWM outputs at
    any frequency and resolution, an A/D input, the UART, PERSIST variables
    up to beyond the EEPROM, instructions, registers and operand forms its
    family may have no code for, any crystal, cycle and baud rate."""
    device = draw(st.sampled_from(COMPILED))
    pins: dict[str, int] = {}

    def give(name, choices):
        """A pin for the name, mostly one no other name has."""
        free = [pin for pin in choices if pin.number not in pins.values()] or choices
        pins[name] = draw(st.sampled_from(free)).number

    give("Xa", device.io_pins())
    give("Yb", device.io_pins())
    rungs = [[contact("Xa"), coil("Yb")]]
    pwm = [device.pin(name) for name in sorted(device.pwm) if device.pin(name) is not None]
    for name in ("Pa", "Pb")[:draw(st.integers(0, 2 if pwm else 0))]:
        give(name, pwm)
        rungs.append([contact("Xa"), _pwm(name, draw(st.integers(-1, 200_000)),
                                          resolution=draw(st.sampled_from(["", "0-256", "0-1024", "0-2048"])))])
    adc = [device.pin(name) for name in sorted(device.adc) if device.pin(name) is not None]
    if adc and draw(st.booleans()):
        give("Ain", adc)
        rungs.append([contact("Xa"), el("READ_ADC", name="Ain")])
    if draw(st.booleans()):
        rungs.append([contact("Xa"), el("UART_SEND", var="c")])
    # PERSIST up to beyond the EEPROM (none at all on the PIC16F72)
    sizes = {}
    for i in range(draw(st.one_of(st.just(0), st.integers(1, 3), st.integers(30, 130)))):
        sizes[f"Vkeep{i}"] = draw(st.integers(1, 4))
        rungs.append([contact("Xa"), el("PERSIST", var=f"Vkeep{i}")])
    # what the family has no code for: an instruction, a register, an operand form
    rungs += [[contact("Xa"), odd] for odd in draw(st.lists(st.sampled_from(range(len(ODD))).map(lambda i: ODD[i]()),
                                                             max_size=2))]
    return program(*rungs, mcu=device.ldmicro_name or device.part, pins=pins, sizes=sizes,
                   crystal_hz=draw(st.one_of(st.sampled_from([4_000_000, 8_000_000, 16_000_000, 20_000_000]),
                                             st.integers(1_000_000, 20_000_000))),
                   cycle_us=draw(st.integers(100, 2_000_000)),
                   baud=draw(st.sampled_from([2400, 9600, 19200, 38400, 57600, 115200])))


@settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))
@given(part_programs())
def test_programs_on_a_parts_hardware_build_within_their_check(prog):
    _build_within_check(prog)


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(programs())
def test_random_programs_build_within_their_check(prog):
    assume(_names_a_compiled_part(prog))
    _build_within_check(prog)


@pytest.mark.slow
@settings(max_examples=1000, deadline=None, suppress_health_check=list(HealthCheck))
@given(programs())
def test_many_random_programs_build_within_their_check(prog):
    assume(_names_a_compiled_part(prog))
    _build_within_check(prog)


@pytest.mark.slow
@settings(max_examples=2000, deadline=None, suppress_health_check=list(HealthCheck))
@given(part_programs())
def test_many_programs_on_a_parts_hardware_build_within_their_check(prog):
    _build_within_check(prog)
