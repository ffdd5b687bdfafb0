"""The corpus's PIC16 programs moved to the enhanced mid-range parts gpsim
models (the PIC12F1840, and the PIC16F1824 as p16f1825), compiled by us and
by LDmicro 5.4.1.1 from the same .ld: both images in gpsim under the same
stimulus drive the same output edges, in the same scans give or take one,
and send the same UART text. benchmarks/pic16e_size.py compares their size
and scan time on the same programs.

A program is moved by giving each name a pin of the part that can serve it
(A/D inputs first, then the PWM output, the inputs, an input-only pin for
one of them, the outputs; the UART's pins left out when the program uses
the UART), the cycle-duty output one more, and the clock of the internal
oscillator nearest the program's; with a PWM output the cycle is Timer0's,
as LDmicro requires on these parts ("PWM and PLC cycle timer can not use the
same timer"). LDmicro is found at /opt/ldmicro/ldmicro (or LDMICRO=); these
tests run in the LDmicro step of .ci/run (marker `ldmicro`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from ldmicro_oracle import installed, ldmicro_compile
from test_compiler_harness import load
from test_pic16_compiler import LDMICRO as EVENTS
from test_pic16_compiler import _analog, _stimuli

import compiler
from compiler.pic16.part import Part
from compiler.run import gpsim
from lang.devices import find_device
from lang.ldfile import write_ld_bytes
from lang.model import PinAssignment

pytestmark = pytest.mark.ldmicro

PROGRAMS = ("reg/tests/contacts.ld", "sample/blink.ld", "sample/serial.ld", "sample/pic-adc.ld", "sample/swatch1.ld",
            "reg/tests/misc-ops.ld", "reg/tests/pic16-hw.ld")
BANNER = 45  # swatch1's first FORMATTED_STRING: past it the text depends on gpsim's UART pace


def _uses_uart(program) -> bool:
    return any(e.kind.startswith("UART") or e.kind == "FORMATTED_STRING" for _, e in program.elements())


def moved(program, part: str, input_only: bool = True):
    """The program on the part, each name on a pin that can serve it, the
    duty output on one more; None when the part has too few pins.
    `input_only` False leaves the MCLR pin alone (gpsim 0.31 restarts the
    p12f1840 and p16f1825 on its edges although the configuration makes it
    an input)."""
    device = find_device(part)
    facts = Part.of(device)
    reserved = set(device.uart.values()) if _uses_uart(program) else set()
    free = [p for p in device.io_pins() if p.name not in reserved and (input_only or not p.input_only)]
    intosc = facts.feature("intosc")  # the baseline's one internal clock is a fact of its own
    clocks = sorted(int(hz) for hz in intosc["settings"]) if intosc else [facts.facts["clock_hz"]]
    crystal = min(clocks, key=lambda hz: (abs(hz - program.settings.crystal_hz), -hz))
    pwm = {str(e.args["name"]) for _, e in program.elements() if e.kind == "SET_PWM"}  # a corpus test leaves it unpinned
    names = [n for n in dict.fromkeys([*program.pins, *sorted(pwm)]) if n != "YPlcCycleDuty"] + ["YPlcCycleDuty"]
    # the most constrained first: A/D inputs, the PWM output, inputs (an input-only pin is one), outputs
    order = sorted(names, key=lambda n: ("APXY".index(n[0]) if n[0] in "APXY" else 4))
    pins = {}
    for name in order:
        fits = [p for p in free if (name[0] != "A" or device.adc_channel(p) is not None)
                and (name[0] != "P" or device.pwm_unit(p) is not None) and (name[0] == "X" or not p.input_only)]
        if not fits:
            return None
        pin = next((p for p in fits if p.input_only), fits[0]) if name[0] == "X" else fits[0]
        free.remove(pin)
        pins[name] = PinAssignment(name, pin.number)  # LDmicro wants package pin numbers
    # LDmicro's PWM on these parts needs Timer0 for the cycle ("PWM and PLC cycle timer can not use the same timer")
    timer = 0 if pwm else program.settings.cycle_timer
    settings = replace(program.settings, mcu=device.ldmicro_name, crystal_hz=crystal, cycle_duty=True, config_word=0,
                       cycle_timer=timer)
    return replace(program, pins=pins, settings=settings)


def ldmicro_image(program, folder: Path) -> tuple[Path | None, str]:
    """LDmicro's HEX of the program, or None and why LDmicro refused it."""
    source, out = folder / "variant.ld", folder / "variant.hex"
    source.write_bytes(write_ld_bytes(program))
    out.unlink(missing_ok=True)
    run = ldmicro_compile(source, out)
    said = " ".join((run.stdout + run.stderr).split())[-160:]
    return (out if run.returncode == 0 and out.exists() else None), said


@pytest.mark.parametrize("part", ["pic12f1840", "pic16f1824"])
@pytest.mark.parametrize("path", sorted(EVENTS))
def test_same_output_edges_and_text_as_ldmicros_hex(path, part, tmp_path):
    installed()
    program = moved(load(path), part)
    if program is None:
        assert (path, part) == ("reg/tests/contacts.ld", "pic12f1840")  # eight pins; the PIC12F1840 has six
        return
    _, events, scans = EVENTS[path]
    build = compiler.build(program)
    ours = tmp_path / "ours.hex"
    build.write(ours)
    theirs, said = ldmicro_image(program, tmp_path)
    assert theirs is not None, said
    device = build.device
    cycle_ms = program.settings.cycle_us / 1000
    pins = sorted({device.pin(program.pins[n].pin).name for n in program.pins if n[0] == "Y" and n != "YPlcCycleDuty"})
    until = scans * cycle_ms
    mine, reference = (gpsim.run_pic(hex_path, Part.of(device).gpsim, program.settings.crystal_hz,
                                     inputs=_stimuli(program, device, events, cycle_ms),
                                     analog=_analog(program, device, events, cycle_ms), watch=pins, until_ms=until,
                                     uart=True, timeout=120)
                       for hex_path in (ours, theirs))
    last = until - 3 * cycle_ms  # LDmicro runs one scan behind: its last edges may be cut off
    for pin in pins:
        a = [(t, v) for t, v in mine.pin_edges(pin) if t < last]
        b = reference.pin_edges(pin)[:len(a)]
        assert [v for _, v in a] == [v for _, v in b], f"{pin}: ours {a[:8]}, LDmicro {b[:8]}"
        for (t_ours, _), (t_theirs, _) in zip(a, b):
            assert abs(t_theirs // cycle_ms - t_ours // cycle_ms) <= 1, f"{pin}: {t_ours:.3f} ms, LDmicro {t_theirs:.3f} ms"
    text, expected = mine.uart_bytes(), reference.uart_bytes()
    common = min(len(text), len(expected), BANNER if path == "sample/swatch1.ld" else len(text))
    assert text[:common] == expected[:common]


@pytest.mark.parametrize("number,pin,bit,lands", [(6, "RC4", 4, 5), (8, "RC2", 2, 3)])
def test_ldmicros_pwm_on_its_other_pins_of_the_pic16f1824_lands_on_the_ccps_first_pin(number, pin, bit, lands,
                                                                                       tmp_path):
    """LDmicro offers PWM on pins 6 (RC4) and 8 (RC2) but leaves the CCP's
    steering at reset: its image drives RC5 (pin 5) and RC3 (pin 7) instead,
    and the chosen pin stays low. Ours drives the chosen pin (PSTRxCON)."""
    installed()
    from builders import el, move
    from builders import program as build_program

    device = find_device("pic16f1824")
    prog = build_program([move("duty", "30")], [el("SET_PWM", duty="duty", freq=1000, name="Ppwm")],
                         mcu="pic16f1824", pins={"Ppwm": pin}, crystal_hz=16_000_000)
    # LDmicro wants the package pin number, and the cycle at Timer0 with PWM on these parts
    prog = replace(prog, pins={"Ppwm": PinAssignment("Ppwm", number)},
                   settings=replace(prog.settings, mcu=device.ldmicro_name, config_word=0, cycle_timer=0))
    ours = tmp_path / "ours.hex"
    compiler.build(prog).write(ours)
    theirs, said = ldmicro_image(prog, tmp_path)
    assert theirs is not None, said
    times = [20 + 4 * i / 400 for i in range(400)]
    duties = []
    for image in (ours, theirs):
        run = gpsim.run_pic(image, "p16f1825", 16_000_000, reads=[(t, "portc") for t in times], until_ms=times[-1] + 1)
        duties.append([sum(value >> b & 1 for _, _, value in run.reads) / len(run.reads) for b in (bit, lands)])
    (ours_chosen, ours_other), (theirs_chosen, theirs_other) = duties
    assert abs(ours_chosen - 0.30) < 0.02 and ours_other == 0
    assert theirs_chosen == 0 and abs(theirs_other - 0.30) < 0.02
