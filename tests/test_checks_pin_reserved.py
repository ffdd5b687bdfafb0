"""LD413: an I/O name on a pin the chip, as the build configures it, gives to
its oscillator, reset input or programming interface.

Pins by port name (the datasheets): PIC16F628 RA7 OSC1, RA6 OSC2, RA5 MCLR,
RB4 PGM; PIC16F876 RB3 PGM, RB6 PGC, RB7 PGD; PIC12F675 GP5 OSC1, GP4 OSC2;
ATmega328P PB6 XTAL1, PB7 XTAL2; ATtiny85 PB3 XTAL1, PB5 RESET.
Configuration words from gputils' p16f628.inc: the default 0x3F62 is
_FOSC_HS & _MCLRE_ON & _LVP_OFF; 0x3F50 is _FOSC_INTOSCIO & _MCLRE_OFF.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from builders import coil, contact, el, found, none, one, program, words
from test_compiler_harness import IN_CI

import compiler
from compiler.run.gpsim import run_pic
from ladder.cli import main
from lang import ldfile
from lang.checks import check_program
from lang.devices import all_devices

PIC628 = "Microchip PIC16F628 18-PDIP or 18-SOIC"
PIC876 = "Microchip PIC16F876 28-PDIP or 28-SOIC"
PIC675 = "Microchip PIC12F675 8-pin packages"
M328 = "Atmel AVR ATmega328 28-PDIP"
TINY85 = "Atmel AVR ATtiny85 8-Pin packages"


def _io(mcu, pins, **settings):
    return program([contact("Xa"), coil("Yb")], mcu=mcu, pins=pins, **settings)


def test_crystal_pins_of_a_pic_in_the_default_configuration():
    prog = _io(PIC628, {"Xa": "RA7", "Yb": "RA6"})
    hits = found(prog, "LD413")
    assert {d.span for d in hits} == {prog.pins["Xa"].span, prog.pins["Yb"].span}
    assert all(d.severity == "warning" for d in hits)
    words(hits[0], "'Xa'", "OSC1", "_FOSC_HS", "0x3F62")


def test_the_internal_oscillator_frees_them():
    none(_io(PIC628, {"Xa": "RA7", "Yb": "RA6"}, config_word=0x3F50), "LD413")
    # INTOSC with CLKOUT: RA6 gives the clock out, RA7 is free
    prog = _io(PIC628, {"Xa": "RA7", "Yb": "RA6"}, config_word=0x3F51)
    d = one(prog, "LD413")
    assert d.span == prog.pins["Yb"].span
    words(d, "the program's configuration word 0x3F51")


def test_an_input_on_mclr_when_mclre_is_on():
    d = one(_io(PIC628, {"Xa": "RA5", "Yb": "RB0"}), "LD413")
    words(d, "input 'Xa'", "MCLR", "_MCLRE_ON")
    none(_io(PIC628, {"Xa": "RA5", "Yb": "RB0"}, config_word=0x3F50), "LD413")


def test_an_output_on_mclr_is_ld412_alone():
    prog = _io(PIC628, {"Xa": "RB0", "Yb": "RA5"})
    one(prog, "LD412")
    none(prog, "LD413")


def test_programming_pins_only_when_the_configuration_takes_them():
    # the default: LVP and DEBUG off, RB3, RB6 and RB7 are I/O
    none(_io(PIC876, {"Xa": "RB3", "Yb": "RB6"}), "LD413")
    lvp_and_debug = 0x3FFF & ~0x0800 & ~0x0002 & ~0x0001  # DEBUG on, HS, LVP on (bit 7 set)
    prog = _io(PIC876, {"Xa": "RB3", "Yb": "RB6"}, config_word=lvp_and_debug)
    assert {d.span for d in found(prog, "LD413")} == {prog.pins["Xa"].span, prog.pins["Yb"].span}


def test_a_12f_runs_on_its_internal_oscillator_by_default():
    none(_io(PIC675, {"Xa": "GP5", "Yb": "GP4"}), "LD413")


def test_avr_crystal_pins_when_the_internal_oscillator_cannot_make_the_clock():
    prog = _io(M328, {"Xa": "PB6", "Yb": "PB7"}, crystal_hz=16000000)
    hits = found(prog, "LD413")
    assert len(hits) == 2
    words(hits[0], "16 MHz", "internal oscillator", "XTAL1")
    none(_io(M328, {"Xa": "PB6", "Yb": "PB7"}, crystal_hz=8000000), "LD413")
    none(_io(M328, {"Xa": "PB0", "Yb": "PB1"}, crystal_hz=16000000), "LD413")


def test_the_attiny85_reset_pin():
    d = one(_io(TINY85, {"Xa": "PB5", "Yb": "PB0"}, crystal_hz=8000000), "LD413")
    words(d, "RESET", "RSTDISBL", "ISP")
    # an A/D input on it reads while the voltage stays above the reset level
    prog = program([el("READ_ADC", name="Avolts")], mcu=TINY85, pins={"Avolts": "PB5"}, crystal_hz=8000000)
    none(prog, "LD413")


def test_no_part_no_finding():
    assert not [d for d in check_program(_io(None, {"Xa": 16, "Yb": 15})) if d.code == "LD413"]


# --- the device data, against gputils' headers and gpsim ----------------------------------------

GPUTILS = Path("/usr/share/gputils/header")
needs_gputils = pytest.mark.skipif(not GPUTILS.is_dir() and not IN_CI, reason="gputils not installed")
needs_gpsim = pytest.mark.skipif(shutil.which("gpsim") is None and not IN_CI, reason="gpsim not installed")
PICS = list({d.part: d for d in all_devices() if d.family == "pic16" and d.data.get("reserved_pins")}.values())


def _symbols(processor: str, field: str) -> dict[str, int]:
    """gputils' configuration symbols of a field: {"HS": 0x3FEE, "INTOSCIO": 0x3FFC, "ON": ...}."""
    text = (GPUTILS / f"{processor}.inc").read_text(encoding="latin-1")
    return {m.group(1): int(m.group(2), 16)
            for m in re.finditer(rf"^_{field}_(\w+)\s+EQU\s+H'([0-9A-F]+)'", text, re.MULTILINE)}


def _taken_by(field: str, use: str, mode: str) -> bool:
    """Whether an oscillator mode (gputils' name) or a switch takes the pin, from the datasheets:
    OSC1 serves every mode but the internal oscillator's; OSC2 the crystals' and those with CLKOUT."""
    if field != "FOSC":
        return mode == "ON"
    if use.startswith("OSC1"):
        return not mode.startswith("INT")
    return mode in ("LP", "XT", "HS") or (mode.endswith("CLK") or mode.endswith("CLKOUT")) and "NOCLKOUT" not in mode


@needs_gputils
@pytest.mark.parametrize("device", PICS, ids=lambda d: d.part)
def test_the_configuration_values_are_gputils(device):
    for pin, entries in device.data["reserved_pins"].items():
        for entry in entries:
            symbols = _symbols(device.data["pic16"]["processor"], entry["field"])
            assert symbols, (device.part, entry["field"])
            cleared = 0
            for value in symbols.values():
                cleared |= ~value & 0x3FFF  # the field's bits: those its symbols clear
            assert entry["mask"] == cleared, (device.part, pin)
            expected = {value & entry["mask"] for mode, value in symbols.items()
                        if _taken_by(entry["field"], entry["use"], mode)}
            assert set(entry["values"]) == expected, (device.part, pin, entry["use"])


@needs_gpsim
def test_gpsim_drives_no_output_on_the_crystal_pin_the_check_reports(tmp_path, capsys):
    # the default configuration (HS crystal): RA6 is OSC2 and stays low; with the internal
    # oscillator (0x3F50) it follows its coil like RA0
    rungs = ([coil("Ylamp")], [coil("Yother")])
    for config, reported, level in ((0, True, 0), (0x3F50, False, 1)):
        prog = program(*rungs, mcu=PIC628, pins={"Ylamp": "RA6", "Yother": "RA0"}, crystal_hz=4_000_000,
                       config_word=config)
        assert bool(found(prog, "LD413")) == reported
        image = tmp_path / f"osc{config}.hex"
        compiler.build(prog).write(image)
        run = run_pic(image, "p16f628", 4_000_000, watch=["RA6", "RA0"], until_ms=30)
        assert run.level_at("RA0", 20) == 1
        assert run.level_at("RA6", 20) == level


def test_a_project_makes_it_an_error(tmp_path, capsys):
    (tmp_path / "ladder.toml").write_text('[diagnostics]\nLD413 = "error"\n', encoding="utf-8")
    fixture = Path(__file__).parent / "diagnostics" / "LD413.ladder"
    (tmp_path / "osc.ladder").write_text(fixture.read_text(encoding="utf-8"), encoding="utf-8")
    assert main(["check", str(tmp_path / "osc.ladder")]) == 1
    assert "error LD413" in capsys.readouterr().out


CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus"


@pytest.mark.skipif(not CORPUS.is_dir(), reason="no corpus beside the repository")
def test_no_corpus_program_uses_a_reserved_pin():
    for path in sorted(CORPUS.rglob("*.ld")):
        prog, _ = ldfile.read_ld_bytes(path.read_bytes())
        assert not [d for d in check_program(prog) if d.code == "LD413"], path
