"""The PIC18 parts' facts (the `pic18` key of lang/devices/pic18f*.json)
against their sources: every SFR and the named bits of gputils' header
(p18f4520.inc), RAM, the access bank, program memory and EEPROM from the
linker script (18f4520_g.lkr), the configuration fields from the header's
symbols; the PIC18F4520's pins and A/D channels from LDmicro's mcutable.h;
the configuration bytes as the HEX carries them and what they mean; gpsim
runs each processor."""

from __future__ import annotations

import re
import subprocess
import tarfile
from functools import cache
from pathlib import Path

import pytest
from test_pic16_parts import GPUTILS, header, needs_gputils

import compiler
from compiler.pic18.part import CONFIG_END, CONFIG_START, Part
from lang.devices import find_device, is_known_ldmicro_name
from lang.families import FAMILIES

SHARED = Path(__file__).resolve().parents[2] / "shared"
LDMICRO_SOURCE = SHARED / "tools" / "ldmicro" / "ldmicro-5.4.1.1-src.tar.gz"
PARTS = ["pic18f4520", "pic18f2520"]
# registers whose bits the device files carry (the ones the back end and the checks name)
BIT_REGISTERS = ("STATUS", "INTCON", "INTCON2", "PIR1", "PIR2", "PIE1", "PIE2", "T1CON", "T2CON", "T3CON",
                 "CCP1CON", "CCP2CON", "TXSTA", "RCSTA", "BAUDCON", "ADCON0", "ADCON1", "ADCON2", "CMCON",
                 "EECON1", "TRISE", "RCON", "WDTCON")


def facts(part: str) -> dict:
    return find_device(part).data["pic18"]


@cache
def linker_script(processor: str) -> dict[str, range]:
    """NAME -> addresses of each CODEPAGE, DATABANK and ACCESSBANK (the non-extended map)."""
    text = (GPUTILS / "lkr" / f"{processor[1:]}_g.lkr").read_text()
    text = re.sub(r"#IFDEF _EXTENDEDMODE.*?#ELSE(.*?)#FI", r"\1", text, flags=re.S)
    return {name: range(int(start, 16), int(end, 16) + 1)
            for name, start, end in re.findall(r"^\s*(?:CODEPAGE|DATABANK|ACCESSBANK)\s+NAME=(\S+)\s+START=0x(\w+)"
                                               r"\s+END=0x(\w+)", text, re.M)}


@cache
def mcutable() -> str:
    with tarfile.open(LDMICRO_SOURCE) as archive:
        member = next(m for m in archive.getmembers() if m.name.endswith("ldmicro/mcutable.h"))
        data = archive.extractfile(member)
        assert data is not None
        return data.read().decode("latin-1")


def _table(name: str) -> str:
    text = mcutable()
    start = text.index(name)
    return text[start:text.index("};", start)]


@needs_gputils
@pytest.mark.parametrize("part", PARTS)
def test_registers_and_bits_are_the_headers(part):
    found = header(facts(part)["processor"])
    registers = {name: address for name, address in found.registers.items() if not name.startswith("DDR")}
    assert facts(part)["registers"] == registers
    assert facts(part)["bits"] == {r: found.bits[r] for r in BIT_REGISTERS if r in found.bits}


@needs_gputils
@pytest.mark.parametrize("part", PARTS)
def test_adc_channels_are_the_headers(part):
    """Each ANn the header names among a port's bits (PORTB: AN12 on RB0,
    AN10, AN8, AN9, AN11 on RB1-RB4) is that pin's channel, and nothing else
    is; ADCON1's PCFG groups are the datasheet's: PCFG3:0 = p makes AN0 to
    AN(14 - p) analog (0010 all thirteen), as far as the part has them."""
    bits = header(facts(part)["processor"]).bits
    expected = {f"R{port}{bits[f'PORT{port}'][name]}": int(name[2:])
                for port in "ABCDE" for name in bits.get(f"PORT{port}", {}) if re.fullmatch(r"AN\d+", name)}
    device = find_device(part)
    assert device.adc == expected
    assert all(f"AN{channel}" in device.pin(pin).functions for pin, channel in expected.items())
    groups = {value: set(channels) for value, channels in facts(part)["features"]["adc"]["pcfg"]}
    present = set(expected.values())
    assert set(map(frozenset, groups.values())) == {frozenset(c for c in range(15 - p) if c in present)
                                                    for p in range(2, 15)}
    assert all(channels == {c for c in range(15 - value) if c in present} for value, channels in groups.items())


@needs_gputils
@pytest.mark.parametrize("part", PARTS)
def test_memory_is_the_linker_scripts(part):
    pic18 = facts(part)
    script = linker_script(pic18["processor"])
    ram = sorted(a for name, span in script.items() if name.startswith("gpr") or name == "accessram" for a in span)
    assert pic18["ram"] == [[ram[0], ram[-1]]] and ram == list(range(ram[0], ram[-1] + 1))
    assert range(pic18["access"][0], pic18["access"][1] + 1) == script["accessram"]
    assert pic18["access_sfr"] == script["accesssfr"].start
    assert 2 * pic18["flash_words"] == len(script["page"]) == find_device(part).memory["flash"]
    assert pic18["eeprom"] == len(script["eedata"]) == find_device(part).memory["eeprom"]
    # every register the device file names is an SFR of the access bank's top
    assert all(address in script["accesssfr"] for address in pic18["registers"].values())


@needs_gputils
@pytest.mark.parametrize("part", PARTS)
def test_config_fields_are_the_headers_symbols(part):
    pic18 = facts(part)
    text = (GPUTILS / "header" / f"{pic18['processor']}.inc").read_text()
    addresses = {name: int(value, 16) for name, value in re.findall(r"^_(CONFIG\d[LH])\s+EQU\s+H'(\w+)'", text, re.M)}
    words = pic18["config"]["words"]
    assert [w["address"] for w in words] == sorted(addresses.values())
    symbols = header(pic18["processor"]).config_symbols
    for name, field in pic18["config"]["fields"].items():
        options = symbols[field["word"]]
        assert field["symbol"] in options and field["symbol"].startswith(f"_{name}_")
        mask = 0
        for symbol, value in options.items():
            if symbol.startswith(f"_{name}_"):
                mask |= ~value & 0xFF
        assert field["mask"] == mask and field["value"] == options[field["symbol"]] & mask
    for index, word in enumerate(words):
        chosen = [f["symbol"] for f in pic18["config"]["fields"].values() if f["word"] == index]
        value = 0xFF
        for symbol in chosen:
            value &= symbols[index][symbol]
        assert word["value"] == value


def test_the_configuration_means_what_the_back_end_says():
    """HS crystal; then what LDmicro's HI-TECH C output for the PIC18F4520
    sets (ansic.cpp: WDTDIS & PWRTEN & BORDIS, MCLREN & PBDIGITAL, DEBUGDIS &
    XINSTDIS & LVPDIS & STVREN); no protection."""
    for part in PARTS:
        fields = {name: f["symbol"] for name, f in facts(part)["config"]["fields"].items()}
        assert {fields[n] for n in ("OSC", "WDT", "PWRT", "BOREN", "MCLRE", "PBADEN", "DEBUG", "XINST", "LVP",
                                    "STVREN")} == {
            "_OSC_HS_1H", "_WDT_OFF_2H", "_PWRT_ON_2L", "_BOREN_OFF_2L", "_MCLRE_ON_3H", "_PBADEN_OFF_3H",
            "_DEBUG_OFF_4L", "_XINST_OFF_4L", "_LVP_OFF_4L", "_STVREN_ON_4L"}
        assert all(symbol.endswith(("_OFF_5L", "_OFF_5H", "_OFF_6L", "_OFF_6H", "_OFF_7L", "_OFF_7H"))
                   for name, symbol in fields.items() if re.match(r"(CP|WRT|EBTR)", name))


@needs_gputils
@pytest.mark.parametrize("part", PARTS)
def test_the_hex_carries_the_configuration_bytes_and_gpasm_agrees(part, tmp_path):
    from builders import coil, contact, program
    from intelhex import IntelHex

    build = compiler.build(program([contact("Xa"), coil("Ya")], mcu=part, pins={"Xa": "RB0", "Ya": "RC0"}))
    build.write(tmp_path / "p.hex")
    ours = IntelHex(str(tmp_path / "p.hex"))
    expected = Part.of(build.device).config_bytes()
    assert {a: ours[a] for a in range(CONFIG_START, CONFIG_END + 1)} == expected
    assert expected[0x300001] & 0x0F == 0b0010 and not expected[0x300003] & 1  # HS, WDTEN off
    subprocess.run(["gpasm", "-o", str(tmp_path / "g.hex"), str(tmp_path / "p.asm")], check=True,
                   capture_output=True)
    assert IntelHex(str(tmp_path / "g.hex")).todict() == ours.todict()


@needs_gputils
def test_the_programs_configuration_word_is_config1_as_ldmicro_takes_it(tmp_path):
    """LDmicro's HI-TECH C output writes the ConfigurationWord as
    `__PROG_CONFIG(1, word)`: CONFIG1L and CONFIG1H (the oscillator: 0x06,
    HS with the PLL); the other bytes stay the part's."""
    from builders import coil, contact, program
    from intelhex import IntelHex

    build = compiler.build(program([contact("Xa"), coil("Ya")], mcu="pic18f4520", pins={"Xa": "RB0", "Ya": "RC0"},
                                   config_word=0x0600))
    build.write(tmp_path / "p.hex")
    ours = IntelHex(str(tmp_path / "p.hex"))
    part = Part.of(build.device)
    assert (ours[0x300000], ours[0x300001]) == (0x00, 0x06)
    assert all(ours[a] == v for a, v in part.config_bytes().items() if a > 0x300001)
    subprocess.run(["gpasm", "-o", str(tmp_path / "g.hex"), str(tmp_path / "p.asm")], check=True,
                   capture_output=True)
    assert IntelHex(str(tmp_path / "g.hex")).todict() == ours.todict()


@needs_gputils
@pytest.mark.parametrize("part", PARTS)
def test_a_clock_past_25_mhz_selects_the_pll_and_past_40_is_refused(part, tmp_path):
    """HS runs a crystal up to 25 MHz; beyond it, up to 40 MHz, the PLL (the
    header's _OSC_HSPLL_1H: 4 x the crystal) makes the clock the program
    gives, the listing names the crystal, and the rest of the bytes stay the
    part's; gpasm agrees. 48 MHz is LD716."""
    from builders import coil, contact, program
    from intelhex import IntelHex

    from compiler.errors import CompileError

    pll = facts(part)["features"]["pll"]
    osc = facts(part)["config"]["fields"]["OSC"]
    assert pll["osc"]["value"] == header(facts(part)["processor"]).config_symbols[0][pll["osc"]["symbol"]] & osc["mask"]
    for clock, expected in ((25_000_000, 0b0010), (26_000_000, 0b0110), (40_000_000, 0b0110)):
        build = compiler.build(program([contact("Xa"), coil("Ya")], mcu=part, pins={"Xa": "RB0", "Ya": "RC0"},
                                       crystal_hz=clock))
        build.write(tmp_path / "p.hex")
        ours = IntelHex(str(tmp_path / "p.hex"))
        assert ours[0x300001] & osc["mask"] == expected
        assert ("a 10 MHz crystal" in build.image.listing) == (clock == 40_000_000)  # what to fit on the board
        assert all(ours[a] == v for a, v in Part.of(build.device).config_bytes().items() if a != 0x300001)
        subprocess.run(["gpasm", "-o", str(tmp_path / "g.hex"), str(tmp_path / "p.asm")], check=True,
                       capture_output=True)
        assert IntelHex(str(tmp_path / "g.hex")).todict() == ours.todict()
    fast = program([contact("Xa"), coil("Ya")], mcu=part, pins={"Xa": "RB0", "Ya": "RC0"}, crystal_hz=48_000_000)
    with pytest.raises(CompileError) as raised:
        compiler.build(fast)
    (found,) = raised.value.diagnostics
    assert found.code == "LD716" and "40 MHz at most" in found.message and "48 MHz" in found.message


def test_a_pic16_configuration_word_does_not_carry_to_a_pic18():
    from builders import coil, contact, program

    pic16 = program([contact("Xa"), coil("Ya")], mcu="Microchip PIC16F877 40-PDIP", pins={"Xa": "RB0", "Ya": "RC0"},
                    config_word=0x3F76)
    build = compiler.build(pic16, "pic18f4520")
    assert build.program.settings.config_word == 0
    segment = build.image.segments[CONFIG_START]
    assert list(segment) == list(Part.of(build.device).config_bytes().values())


@pytest.mark.skipif(not LDMICRO_SOURCE.is_file(), reason="LDmicro's source not beside the checkout")
def test_the_pic18f4520_pins_are_ldmicros():
    device = find_device("pic18f4520")
    pins = re.findall(r"\{\s*'(\w)',\s*(\d+),\s*(\d+),\s*\"([^\"]*)\"", _table("McuIoPinInfo Pic18F4520IoPinInfo[]"))
    assert pins
    for port, bit, number, label in pins:
        pin = device.pin(int(number))
        assert (pin.port, pin.bit, pin.label) == (port, int(bit), label.strip())
    assert len(device.io_pins()) == len(pins)
    channels = re.findall(r"\{\s*(\d+),\s*0x(\w+)\s*\}", _table("McuAdcPinInfo Pic18F4520AdcPinInfo[]"))
    ldmicros = {device.pin(int(number)).name: int(channel, 16) for number, channel in channels}
    # LDmicro's table stops at AN7; AN8-AN12 on RB0-RB4 are the header's (test_adc_channels_are_the_headers)
    assert ldmicros == {pin: channel for pin, channel in device.adc.items() if channel < 8}
    assert '"Microchip PIC18F4520 40-PDIP"' in mcutable()


def test_the_pic18f2520_has_the_28_pin_footprint_of_the_pic16f876():
    """The same die as the PIC18F4520 without PORTD and RE0-RE2, on the
    PIC16F876's pins (LDmicro has no entry for it)."""
    ours, pic16 = find_device("pic18f2520"), find_device("pic16f876")
    assert {n: p.name for n, p in ours.pins.items()} == {n: p.name for n, p in pic16.pins.items()}
    assert ours.pwm == pic16.pwm and ours.uart == pic16.uart
    assert {pin: channel for pin, channel in ours.adc.items() if channel < 8} == pic16.adc
    assert facts("pic18f2520")["registers"].keys() <= facts("pic18f4520")["registers"].keys()
    assert "PORTD" not in facts("pic18f2520")["registers"]


def test_ldmicros_name_finds_the_pic18f4520_and_both_are_compiled():
    assert is_known_ldmicro_name("Microchip PIC18F4520 40-PDIP")
    assert find_device("Microchip PIC18F4520 40-PDIP").part == "pic18f4520"
    assert find_device("pic18f4520").ldmicro_name == "Microchip PIC18F4520 40-PDIP"
    assert find_device("18f2520").part == "pic18f2520" and find_device("pic18f2520").ldmicro_name == ""
    assert FAMILIES["pic18"].parts == tuple(PARTS)


@pytest.mark.skipif(not (GPUTILS / "header").is_dir(), reason="gputils not installed")
@pytest.mark.parametrize("part", PARTS)
def test_gpsim_runs_the_processor(part, tmp_path):
    from builders import coil, contact, program

    from compiler.run import gpsim

    build = compiler.build(program([contact("Xa"), coil("Ya")], mcu=part, pins={"Xa": "RB0", "Ya": "RC0"},
                                   crystal_hz=4_000_000))
    build.write(tmp_path / "p.hex")
    run = gpsim.run_pic(tmp_path / "p.hex", Part.of(build.device).gpsim, 4_000_000,
                        inputs=[(0, "RB0", 0), (20, "RB0", 1), (45, "RB0", 0)], watch=["RC0"], until_ms=80)
    assert [v for _, v in run.pin_edges("RC0")] == [1, 0]
    assert [round(t / 10) for t, _ in run.pin_edges("RC0")] == [2, 5]  # the first scans that read each change


def test_the_pic18_compiles_what_the_pic16_compiles_and_refuses_the_rest_with_ld501():
    """One support entry per instruction: the PIC18 back end is the PIC16's
    patterns, so its column is the PIC16's; an instruction neither compiles
    (SPI here) is LD501 at its element, an error in the build."""
    from builders import contact, el, program

    from compiler.errors import CompileError
    from lang.instructions import INSTRUCTIONS

    assert {k for k, i in INSTRUCTIONS.items() if "pic18" in i.support} == \
        {k for k, i in INSTRUCTIONS.items() if "pic16" in i.support}
    spi = el("SPI", name="SPI1", send="s", recv="r", mode="Master", bitrate="1000000")
    with pytest.raises(CompileError) as found:
        compiler.build(program([contact("Xa"), spi], mcu="pic18f4520", pins={"Xa": "RB0"}))
    (problem,) = found.value.diagnostics
    assert problem.code == "LD501" and "PIC18" in problem.message
    assert problem.span == spi.span
