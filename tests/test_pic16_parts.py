"""The PIC16 parts' facts (the `pic16` key of lang/devices/pic*.json) against
gputils: every SFR and the named bits of its header (p16f877a.inc...), RAM from
__MAXRAM/__BADRAM and the linker script's banks (16f877a_g.lkr), the
configuration fields from the header's __CONFIG symbols; LDmicro's own
configuration words; gpasm and gpsim accept every processor name, and gpsim's
register file has the same general-purpose bytes and mirrors."""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import pytest
from corpus import CORPUS

from compiler.pic16.part import Part
from lang.devices import find_device

GPUTILS = Path("/usr/share/gputils")
CONFIG_MASK = 0x3FFF  # a configuration word has 14 bits

# part -> LDmicro's name (None: LDmicro does not list it)
PARTS = {
    "pic12f675": "Microchip PIC12F675 8-pin packages",
    "pic12f683": "Microchip PIC12F683 8-pin packages",
    "pic16f628": "Microchip PIC16F628 18-PDIP or 18-SOIC",
    "pic16f628a": None,
    "pic16f72": "Microchip PIC16F72 28-Pin PDIP, SOIC, SSOP",
    "pic16f819": "Microchip PIC16F819 18-PDIP or 18-SOIC",
    "pic16f876": "Microchip PIC16F876 28-PDIP or 28-SOIC",
    "pic16f876a": None,
    "pic16f877": "Microchip PIC16F877 40-PDIP",
    "pic16f877a": None,
    "pic16f88": "Microchip PIC16F88 18-PDIP or 18-SOIC",
    "pic16f886": "Microchip PIC16F886 28-PDIP or 28-SOIC",
    "pic16f887": "Microchip PIC16F887 40-PDIP",
}

# LDmicro 5.4.1.1's configuration words (mcutable.h; `ldmicro compile` writes
# exactly these at 0x2007/0x2008 of the HEX, checked for every part).
LDMICRO_WORDS = {
    "pic12f675": [0x3FC4], "pic12f683": [0x3FC4], "pic16f628": [0x3F62], "pic16f72": [0x00D2],
    "pic16f819": [0x3F42], "pic16f876": [0x3F72], "pic16f877": [0x3F72], "pic16f88": [0x2F42, 0x0000],
    "pic16f886": [0x23E2, 0x3EFF], "pic16f887": [0x23E2, 0x0600],
}

# registers whose bits every part file must carry where the header has them
BIT_REGISTERS = ("STATUS", "OPTION_REG", "INTCON", "PIR1", "PIR2", "PIE1", "PIE2", "T1CON", "T2CON",
                 "CCP1CON", "CCP2CON", "TXSTA", "RCSTA", "ADCON0", "ADCON1", "ANSEL", "ANSELH", "CMCON",
                 "CMCON0", "CM1CON0", "CM2CON0", "EECON1", "OSCCON", "WDTCON", "PCON", "TRISE")

needs_gputils = pytest.mark.skipif(not (GPUTILS / "header").is_dir(), reason="gputils not installed")


# ------------------------------------------------------------------ gputils' files


@dataclass
class Header:
    """What a gputils processor header (p16f877a.inc) defines."""

    registers: dict[str, int] = field(default_factory=dict)
    bits: dict[str, dict[str, int]] = field(default_factory=dict)
    maxram: int = 0
    badram: set[int] = field(default_factory=set)
    config_addresses: list[int] = field(default_factory=list)
    config_symbols: list[dict[str, int]] = field(default_factory=list)  # per word: _SYMBOL -> value


_SECTION = re.compile(r"^;-----\s+(\w+)\s+(\w+)")
_EQU = re.compile(r"^(\w+)\s+EQU\s+H'([0-9A-Fa-f]+)'")
_BADRAM = re.compile(r"__BADRAM\s+H'([0-9A-Fa-f]+)'(?:-H'([0-9A-Fa-f]+)')?")


@cache
def header(processor: str) -> Header:
    result = Header()
    section: dict[str, int] | None = None
    for line in (GPUTILS / "header" / f"{processor}.inc").read_text().splitlines():
        if line.startswith(";====="):
            section = None
        m = _SECTION.match(line)
        if m:
            name, kind = m.groups()
            if kind == "Files":
                section = result.registers
            elif kind == "Bits":
                section = result.bits.setdefault(name, {})
            elif kind == "Options":  # CONFIG, CONFIG1, CONFIG2
                result.config_symbols.append({})
                section = result.config_symbols[-1]
            else:  # DEVID, IDLOC Equates
                section = None
            continue
        m = _EQU.match(line)
        if m and re.fullmatch(r"_CONFIG\d?", m.group(1)):
            result.config_addresses.append(int(m.group(2), 16))
        elif m and section is not None:
            section[m.group(1)] = int(m.group(2), 16)
        m = re.search(r"__MAXRAM\s+H'([0-9A-Fa-f]+)'", line)
        if m:
            result.maxram = int(m.group(1), 16)
        m = _BADRAM.search(line)
        if m:
            first = int(m.group(1), 16)
            result.badram |= set(range(first, int(m.group(2) or m.group(1), 16) + 1))
    return result


@dataclass
class LinkerScript:
    """The memory map of gputils' generic linker script (16f877a_g.lkr)."""

    code: dict[str, range] = field(default_factory=dict)  # CODEPAGE name -> word addresses
    sfr: set[int] = field(default_factory=set)
    gpr: set[int] = field(default_factory=set)  # the physical general-purpose bytes
    shared: list[tuple[str, range, bool]] = field(default_factory=list)  # SHAREBANK name, range, protected


_MEMORY = re.compile(r"^(CODEPAGE|DATABANK|SHAREBANK)\s+NAME=(\S+)\s+START=0x([0-9A-F]+)\s+END=0x([0-9A-F]+)"
                     r"(\s+PROTECTED)?", re.I)


@cache
def linker_script(processor: str) -> LinkerScript:
    result = LinkerScript()
    # gputils renamed a few shared banks (16F72, 16F819) and kept Microchip's
    # lines as "////" comments: the original names pair a mirror with its bytes
    original: dict[int, str] = {}
    for line in (GPUTILS / "lkr" / f"{processor[1:]}_g.lkr").read_text().splitlines():
        commented = line.startswith("////")
        m = _MEMORY.match(line[4:] if commented else line)
        if not m:
            continue
        kind, name, protected = m.group(1).upper(), m.group(2), bool(m.group(5))
        span = range(int(m.group(3), 16), int(m.group(4), 16) + 1)
        if commented:
            original[span[0]] = name
        elif kind == "CODEPAGE":
            result.code[name] = span
        elif kind == "DATABANK" and name.startswith("sfr"):
            result.sfr |= set(span)
        elif kind == "DATABANK":
            result.gpr |= set(span)
        else:
            result.shared.append((original.get(span[0], name), span, protected))
            if not protected:
                result.gpr |= set(span)
    return result


def lkr_mirrors(script: LinkerScript) -> dict[int, int]:
    """Protected shared-bank address -> the byte of the same-named bank it reaches."""
    owners = {name: span for name, span, protected in script.shared if not protected}
    return {address: owners[name][i]
            for name, span, protected in script.shared if protected
            for i, address in enumerate(span)}


def lkr_common(script: LinkerScript) -> range | None:
    """The shared bytes every bank reaches (in bank-0 addresses)."""
    banks: dict[str, set[int]] = {}
    for name, span, _ in script.shared:
        banks.setdefault(name, set()).add(span[0] >> 7)
    every = {address >> 7 for address in script.sfr}
    for name, span, protected in script.shared:
        if not protected and banks[name] == every:
            return span
    return None


def implemented(symbols: dict[str, int]) -> int:
    """The bits some of these configuration symbols clear (a symbol is the
    word with only its own field's bits set to its value)."""
    mask = 0
    for value in symbols.values():
        mask |= ~value & CONFIG_MASK
    return mask


def config_fields(symbols: dict[str, int], name: str) -> tuple[int, dict[str, int]]:
    """(mask, {symbol: value on the mask}) of a field: its _NAME_* symbols."""
    options = {s: v for s, v in symbols.items() if s.startswith(f"_{name}_")}
    mask = implemented(options)
    return mask, {s: v & mask for s, v in options.items()}


# ------------------------------------------------------------------ helpers


def pic16(part: str) -> dict:
    return find_device(part).data["pic16"]


def addresses(spans) -> set[int]:
    return {address for first, last in spans for address in range(first, last + 1)}


def mirror_map(data: dict) -> dict[int, int]:
    return {first + i: target + i for first, last, target in data["mirrors"] for i in range(last - first + 1)}


def hex_words(path: Path) -> dict[int, int]:
    """The 14-bit words of a PIC Intel HEX file: word address -> value."""
    data: dict[int, int] = {}
    upper = 0
    for line in path.read_text().split():
        raw = bytes.fromhex(line[1:])
        count, address, kind = raw[0], raw[1] << 8 | raw[2], raw[3]
        if kind == 4:
            upper = raw[4] << 8 | raw[5]
        elif kind == 0:
            for i in range(0, count, 2):
                data[((upper << 16) + address + i) // 2] = raw[4 + i] | raw[5 + i] << 8
    return data


def assemble(source: str, processor: str, tmp: Path) -> dict[int, int]:
    """gpasm's words of a source, written to tmp/t.hex."""
    (tmp / "t.asm").write_text(source)
    run = subprocess.run(["gpasm", "-p", processor, "-o", str(tmp / "t.hex"), str(tmp / "t.asm")],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    return hex_words(tmp / "t.hex")


def source(part: str, words, body=("\tnop",)) -> str:
    """A program for the part with configuration words (address, number or
    expression of the header's symbols)."""
    processor = pic16(part)["processor"]
    lines = [f"\tlist p={processor}", f"\t#include <{processor}.inc>"]
    lines += [f"\t__CONFIG {address:#x}, {value if isinstance(value, str) else f'{value:#06x}'}"
              for address, value in words]
    return "\n".join([*lines, *body, "\tend", ""])


def gpsim(script: list[str], tmp: Path) -> str:
    (tmp / "run.stc").write_text("\n".join([*script, "quit", ""]))
    run = subprocess.run(["timeout", "30", "gpsim", "-i", "-I", str(tmp / "run.stc")],
                         stdin=subprocess.DEVNULL, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert not re.search(r"Unable to find|No cpu|syntax error|\*\*\*ERROR", run.stdout), run.stdout
    return run.stdout


def dumps(text: str) -> list[dict[int, int]]:
    """The register file of each gpsim `dump` (unimplemented bytes left out)."""
    result: list[dict[int, int]] = []
    for line in text.splitlines():
        m = re.match(r"^([0-9a-f]{4}):\s+((?:(?:[0-9a-f]{2}|--)\s+){16})", line)
        if m:
            base = int(m.group(1), 16)
            if base == 0:
                result.append({})
            for i, cell in enumerate(m.group(2).split()):
                if cell != "--":
                    result[-1][base + i] = int(cell, 16)
    return result


needs_gpasm = pytest.mark.skipif(shutil.which("gpasm") is None, reason="gputils not installed")
needs_gpsim = pytest.mark.skipif(shutil.which("gpsim") is None, reason="gpsim not installed")
EXACT = sorted(p for p in PARTS if pic16(p)["gpsim_exact"])
# gpsim 0.31's PIC16F886 model lacks bank 2's first 16 general-purpose bytes
# (its 16F887 has them; the datasheet, header and linker script give both 368)
GPSIM_GAPS = {"pic16f886": set(range(0x110, 0x120))}
# pins gpsim 0.31 never makes analog: its 16F88x put AN4 on RA4 rather than
# RA5 (an A/D test of AN4 there reads RA4), and its 16F887 leaves RE2 digital
GPSIM_DIGITAL = {"pic16f886": {"RA5"}, "pic16f887": {"RA5", "RE2"}}


# ------------------------------------------------------------------ registers and RAM


@needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
def test_registers_and_bits_are_the_headers(part):
    data = pic16(part)
    h = header(data["processor"])
    assert data["registers"] == h.registers
    assert set(data["bits"]) == {r for r in BIT_REGISTERS if r in h.bits}
    for register, bits in data["bits"].items():
        assert bits == h.bits[register], register


@needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
def test_ram_is_inside_the_headers_memory(part):
    data = pic16(part)
    h = header(data["processor"])
    gpr, mirrors = addresses(data["ram"]), mirror_map(data)
    assert data["banks"] == -(-(h.maxram + 1) // 0x80)
    sfrs = set(h.registers.values())
    for address in gpr | set(mirrors):
        assert address <= h.maxram and address not in h.badram and address not in sfrs, hex(address)
    assert sum(last - first + 1 for first, last in data["ram"]) == len(gpr) == find_device(part).memory["ram"]
    assert not gpr & set(mirrors)
    for address, target in mirrors.items():  # another bank's byte at the same offset
        assert target in gpr and address % 0x80 == target % 0x80 and address // 0x80 != target // 0x80
    if data["common"]:
        first, last = data["common"]
        for address in range(first, last + 1):
            reached = {0} | {m // 0x80 for m, t in mirrors.items() if t == address}
            assert address in gpr and address < 0x80 and reached == set(range(data["banks"]))


@needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
def test_ram_is_the_linker_scripts(part):
    data = pic16(part)
    script, h = linker_script(data["processor"]), header(data["processor"])
    gpr, mirrors = addresses(data["ram"]), mirror_map(data)
    assert gpr == script.gpr
    assert mirrors == lkr_mirrors(script)
    common = lkr_common(script)
    assert data["common"] == ([common[0], common[-1]] if common else None)
    # every other implemented address is a special function register or its mirror
    rest = set(range(h.maxram + 1)) - h.badram - gpr - set(mirrors)
    assert rest <= script.sfr


@needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
def test_memory_sizes_are_the_linker_scripts(part):
    data, device = pic16(part), find_device(part)
    script = linker_script(data["processor"])
    assert data["flash_words"] == max(s[-1] for s in script.code.values() if s[0] < 0x2000) + 1
    assert data["page_words"] == 2048
    for name, span in script.code.items():
        if name.startswith("page"):
            assert span[0] // 2048 == span[-1] // 2048, name
    assert data["eeprom"] == len(script.code.get("eedata", ()))
    assert device.memory["flash_words"] == data["flash_words"] and device.memory["eeprom"] == data["eeprom"]
    osccal = data["features"].get("osccal")
    assert (osccal["address"] if osccal else None) == (script.code[".oscval"][0] if ".oscval" in script.code else None)


@needs_gpsim
@pytest.mark.parametrize("part", EXACT)
def test_gpsim_has_the_same_ram_and_mirrors(part, tmp_path):
    """Two patterns written to every general-purpose byte read back intact
    (no two are one byte) and every mirror reads its target's value."""
    data = pic16(part)
    gpr, mirrors = sorted(addresses(data["ram"])), mirror_map(data)
    patterns = [[i % 253 + 1 for i in range(len(gpr))], [i * 7 % 251 + 1 for i in range(len(gpr))]]
    assert len(set(zip(*patterns))) == len(gpr)
    assemble(source(part, Part.of(find_device(part)).config_words), data["processor"], tmp_path)
    script = [f"processor {data['gpsim']}", f"load {tmp_path / 't.hex'}"]
    for pattern in patterns:
        script += [f"ramData[{a:#x}]={v}" for a, v in zip(gpr, pattern)] + ["dump"]
    files = dumps(gpsim(script, tmp_path))
    assert len(files) == 2
    gaps = GPSIM_GAPS.get(part, set())
    for pattern, values in zip(patterns, files):
        assert [values.get(a) for a in gpr] == [None if a in gaps else v for a, v in zip(gpr, pattern)]
        assert {a: values.get(a) for a in mirrors} == {a: values[t] for a, t in mirrors.items()}


# ------------------------------------------------------------------ configuration words


@needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
def test_config_fields_are_the_headers_symbols(part):
    """Each field's bits and value are its header symbols'; the fields cover
    every bit a symbol sets, once; a word is the AND of its fields' symbols
    on those bits."""
    data = pic16(part)
    h = header(data["processor"])
    config = Part.of(find_device(part))
    assert [address for address, _ in config.config_words] == h.config_addresses
    assert len(h.config_symbols) == len(h.config_addresses)
    covered = [0] * len(h.config_symbols)
    for name in data["config"]["fields"]:
        f = config.config_field(name)
        mask, options = config_fields(h.config_symbols[f.word], name)
        assert f.mask == mask and f.value & ~mask == 0, name
        assert options[f.symbol] == f.value, name
        assert config.config_words[f.word][1] & mask == f.value, name
        assert not covered[f.word] & mask, name
        covered[f.word] |= mask
    for word, symbols in enumerate(h.config_symbols):
        bits = implemented(symbols)
        assert covered[word] == bits
        anded = CONFIG_MASK
        for symbol in config.config_symbols(word):
            anded &= symbols[symbol]
        assert anded & bits == config.config_words[word][1] & bits


@pytest.mark.parametrize("part", sorted(PARTS))
def test_config_words_are_ldmicros(part):
    """LDmicro's own words for the parts it lists; an A part has its non-A
    sibling's words, which mean the same there (the fields test checks)."""
    config = Part.of(find_device(part))
    words = [value for _, value in config.config_words]
    assert config.ldmicro_config == (PARTS[part] is not None)
    assert words == LDMICRO_WORDS[part if config.ldmicro_config else part[:-1]]


def test_ldmicros_own_hex_files_carry_the_words():
    """Every PIC HEX file of the corpus LDmicro compiled has its part's words."""
    checked = 0
    for listing in sorted((CORPUS / "ldmicro-hex").glob("*.asm")):
        m = re.search(r"^\s*LIST\s+p=(PIC\w+)", listing.read_text(errors="replace"), re.M)
        if not m:
            continue
        image = hex_words(listing.with_suffix(".hex"))
        for address, value in Part.of(find_device(m.group(1))).config_words:
            assert image[address] == value, listing.name
        checked += 1
    assert checked >= 5


@pytest.mark.parametrize("part", sorted(PARTS))
def test_config_means_what_ldmicro_says(part):
    """"crystal oscillator, BOD enabled, LVP disabled, PWRT enabled, all code
    protection off" and the watchdog off (pic16.cpp); the PIC12F run on the
    internal oscillator with GP3 as an input (mcutable.h's comments)."""
    config = Part.of(find_device(part))
    symbol = {name: config.config_field(name).symbol for name in config.facts["config"]["fields"]}
    oscillator = {"pic12f675": "_FOSC_INTRCIO", "pic12f683": "_FOSC_INTOSCIO"}.get(part, "_FOSC_HS")
    assert symbol["FOSC"] == oscillator
    assert symbol["WDTE"] == "_WDTE_OFF" and symbol["PWRTE"] == "_PWRTE_ON" and symbol["BOREN"] == "_BOREN_ON"
    assert symbol["CP"] == "_CP_OFF" and symbol.get("CPD", "_CPD_OFF") == "_CPD_OFF"
    assert symbol.get("LVP", "_LVP_OFF") == "_LVP_OFF" and symbol.get("WRT", "_WRT_OFF") in ("_WRT_OFF", "_WRT_ON")
    if part.startswith("pic12f"):
        assert symbol["MCLRE"] == "_MCLRE_OFF"


@needs_gpasm
@pytest.mark.parametrize("part", sorted(PARTS))
def test_gpasm_writes_the_words_from_the_symbols(part, tmp_path):
    """gpasm takes the processor name and assembles __CONFIG from the field
    symbols to the words (on the implemented bits)."""
    config = Part.of(find_device(part))
    h = header(config.processor)
    symbolic = [(address, " & ".join(config.config_symbols(word)))
                for word, (address, _) in enumerate(config.config_words)]
    image = assemble(source(part, symbolic), config.processor, tmp_path)
    for word, (address, value) in enumerate(config.config_words):
        bits = implemented(h.config_symbols[word])
        assert image[address] & bits == value & bits


# ------------------------------------------------------------------ gpsim, lookup, features


@needs_gpsim
@pytest.mark.parametrize("part", sorted(PARTS))
def test_gpsim_runs_the_processor(part, tmp_path):
    config = Part.of(find_device(part))
    assert config.gpsim_exact == (config.gpsim == config.processor)
    assemble(source(part, config.config_words), config.processor, tmp_path)
    assert "Leaving pic_processor::LoadProgramFile" in gpsim([f"processor {config.gpsim}",
                                                                f"load {tmp_path / 't.hex'}"], tmp_path)


@pytest.mark.parametrize("part", sorted(PARTS))
def test_parts_are_found_by_ldmicro_and_short_names(part):
    names = [part, part[3:], "p" + part[3:], part.upper()]
    if PARTS[part]:
        names.append(PARTS[part])
        assert find_device(part).ldmicro_name == PARTS[part]
    for name in names:
        assert Part.of(find_device(name)).processor == "p" + part[3:], name


@needs_gputils
@pytest.mark.parametrize("part", sorted(PARTS))
def test_features_name_the_parts_registers(part):
    data = pic16(part)
    h, features, device = header(data["processor"]), data["features"], find_device(part)
    for letter, (port, tris) in data["ports"].items():
        assert port in h.registers and tris in h.registers, letter
    assert {pin.port for pin in device.io_pins()} <= set(data["ports"])
    adc = features.get("adc")
    assert bool(adc) == bool(device.adc)
    if adc:
        assert all(r in h.registers for r in adc["result"]) and len(adc["result"]) == -(-adc["bits"] // 8)
    for register, value in [*features["digital_io"].items(), *features["comparators_off"].items()]:
        assert register in h.registers and 0 <= value <= 0xFF
    for register, value in features["comparators_off"].items():  # CM2:CM0 = 111: off
        assert value == sum(1 << h.bits[register][f"CM{i}"] for i in range(3))
    assert features["uart"] == bool(device.uart) == ("TXSTA" in h.registers)
    assert set(features["cycle_timers"]) <= {"timer0", "timer1"} and "timer0" in features["cycle_timers"]
    assert ("timer1" in features["cycle_timers"]) == ("CCP1CON" in h.registers)
    eeprom = features.get("eeprom")
    assert bool(eeprom) == bool(data["eeprom"])
    if eeprom:
        assert {eeprom[k] for k in ("data", "address", "control", "unlock")} <= set(h.registers)
        assert "EEIF" in h.bits[eeprom["flag"]]
    if "osccal" in features:
        assert features["osccal"]["address"] == data["flash_words"] - 1
        assert features["osccal"]["register"] in h.registers
    for pin, unit in device.pwm.items():
        assert f"{unit}CON" in h.registers, pin


def _analog_pins(part: str):
    device = find_device(part)
    return [pin for pin in device.io_pins() if any(f.startswith("AN") for f in pin.functions)]


@needs_gpsim
@pytest.mark.parametrize("part", [p for p in EXACT if _analog_pins(p)])
def test_start_up_writes_make_the_analog_pins_digital(part, tmp_path):
    """In gpsim, analog-capable pins pulled high read 0 in the reset state of
    the registers the part's digital_io and comparators_off write, and 1
    after those writes. (gpsim gives a pin its analog mode when the register
    is written, so both programs first write back gpsim's reset values.)"""
    config = Part.of(find_device(part))
    pins = _analog_pins(part)
    ports = sorted({pin.port for pin in pins})
    first = config.ram_ranges()[0][0]
    features = config.facts["features"]
    writes = {**features["digital_io"], **features["comparators_off"]}
    assemble(source(part, config.config_words), config.processor, tmp_path)
    reset = dumps(gpsim([f"processor {config.gpsim}", f"load {tmp_path / 't.hex'}", "dump"], tmp_path))[0]

    def read_ports(*stores: dict[str, int]) -> dict[str, int]:
        lines = []
        for store in stores:
            for register, value in store.items():
                lines += [f"\tbanksel {register}", f"\tmovlw {value:#04x}", f"\tmovwf {register} & 0x7f"]
        for i, letter in enumerate(ports):
            register = config.facts["ports"][letter][0]
            lines += [f"\tbanksel {register}", f"\tmovf {register} & 0x7f, w", "\tbanksel 0",
                      f"\tmovwf {first + i:#x}"]
        assemble(source(part, config.config_words, [*lines, "loop\tgoto loop"]), config.processor, tmp_path)
        script = [f"processor {config.gpsim}", f"load {tmp_path / 't.hex'}", "module library libgpsim_modules"]
        for pin in pins:
            name = f"gpio{pin.bit}" if pin.port == "P" else f"port{pin.port.lower()}{pin.bit}"
            script += [f"module load pullup up_{name}", f"node n_{name}", f"attach n_{name} up_{name}.pin {name}"]
        script += ["break c 1000", "run"] + [f"ramData[{first + i:#x}]" for i in range(len(ports))]
        values = re.findall(r"ramData\[\$[0-9a-f]+\] = \$([0-9a-f]+)", gpsim(script, tmp_path))
        return dict(zip(ports, (int(v, 16) for v in values)))

    reset_state = {register: reset[config.reg(register)] for register in writes}
    before, after = read_ports(reset_state), read_ports(reset_state, writes)
    levels = {pin.name: (before[pin.port] >> pin.bit & 1, after[pin.port] >> pin.bit & 1) for pin in pins}
    digital = GPSIM_DIGITAL.get(part, set())
    assert levels == {pin.name: (int(pin.name in digital), 1) for pin in pins}


# ------------------------------------------------------------------ the Part API


def test_part_api_on_the_pic16f877a():
    part = Part.of(find_device("pic16f877a"))
    assert (part.title, part.processor, part.gpsim, part.gpsim_exact) == ("PIC16F877A", "p16f877a", "p16f877a", True)
    assert (part.flash_words, part.page_words, part.pages, part.eeprom, part.banks) == (8192, 2048, 4, 256, 4)
    assert part.reg("ADCON1") == 0x9F and part.bank(part.reg("ADCON1")) == 1 and part.bank(part.reg("EECON1")) == 3
    assert part.has("CMCON") and not part.has("ANSEL")  # the A part's comparators
    assert not Part.of(find_device("pic16f877")).has("CMCON")
    assert part.bit("STATUS", "RP0") == 5 and part.bit("EECON1", "RD") == 0 and part.bit("PIR1", "CCP1IF") == 2
    assert part.ram_ranges() == [range(0x20, 0x80), range(0xA0, 0xF0), range(0x110, 0x170), range(0x190, 0x1F0)]
    assert part.common == range(0x70, 0x80)
    assert (part.physical(0xF5), part.physical(0x1F0), part.physical(0x1A0)) == (0x75, 0x70, 0x1A0)
    assert (part.port("B"), part.tris("B"), part.port("E"), part.tris("E")) == (0x06, 0x86, 0x09, 0x89)
    assert part.config_words == ((0x2007, 0x3F72),) and not part.ldmicro_config
    assert part.config_field("WDTE").value == 0 and part.config_field("MCLRE") is None
    assert "_FOSC_HS" in part.config_symbols(0) and "_LVP_OFF" in part.config_symbols(0)
    assert part.feature("digital_io") == {"ADCON1": 7} and part.feature("comparators_off") == {}
    assert part.feature("osccal") is None and part.feature("nothing", 1) == 1


def test_part_api_on_the_small_and_odd_parts():
    pic12 = Part.of(find_device("Microchip PIC12F675 8-pin packages"))
    assert (pic12.banks, pic12.pages, pic12.common, pic12.physical(0xA0)) == (2, 1, range(0x20, 0x60), 0x20)
    assert (pic12.port("P"), pic12.tris("P")) == (0x05, 0x85)
    assert pic12.feature("cycle_timers") == ["timer0"] and pic12.feature("osccal")["address"] == 0x3FF
    assert pic12.config_field("FOSC").symbol == "_FOSC_INTRCIO" and pic12.config_field("MCLRE").value == 0
    f72 = Part.of(find_device("pic16f72"))
    assert (f72.gpsim, f72.gpsim_exact, f72.eeprom) == ("p16f73", False, 0)
    assert (f72.physical(0xC0), f72.physical(0x120), f72.physical(0x1A0)) == (0x40, 0x20, 0xA0)
    assert f72.common == range(0x40, 0x80)
    assert f72.feature("adc")["bits"] == 8 and f72.feature("adc")["result"] == ["ADRES"] and f72.feature("eeprom") is None
    f88 = Part.of(find_device("pic16f88"))
    assert f88.config_words == ((0x2007, 0x2F42), (0x2008, 0x0000)) and f88.ldmicro_config
    assert f88.config_field("FCMEN").word == 1 and f88.config_symbols(1) == ["_IESO_OFF", "_FCMEN_OFF"]
    assert f88.config_field("CCPMX").symbol == "_CCPMX_RB3"
    # LDmicro's 16F819 word puts CCP1 on RB2, though LDmicro offers its PWM on RB3
    assert Part.of(find_device("pic16f819")).config_field("CCPMX").symbol == "_CCPMX_RB2"
    assert find_device("pic16f819").pwm == {"RB3": "CCP1"}
