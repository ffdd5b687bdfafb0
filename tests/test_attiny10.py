"""The ATtiny10 and its reduced AVR core (AVRrc). No simulator here models
it (simavr has no ATtiny10 core), so its images are checked statically: its
facts against avr-libc's iotn10.h, the encoder against GNU avr-as for
-mmcu=attiny10 (which refuses what the core lacks), every image of the corpus
programs that fit it and of random programs reassembled from its listing to
the same words, and programs that do not fit refused with located errors."""

from __future__ import annotations

import random
import re
import subprocess
import tarfile
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

import pytest
from builders import coil, contact, el, program
from hypothesis import HealthCheck, assume, given, settings
from test_avr_parts import LDMICRO_SOURCE, moved
from test_avr_parts_ldmicro import ldmicros_hex
from test_compiler_budget import AVR_CYCLES, AVR_SKIPS, _objdump, needs_objdump
from test_compiler_corpus import CASES
from test_compiler_encoding import needs_avr_gcc, operands, reassemble
from test_compiler_harness import IN_CI, differential, load, needs_simavr
from test_compiler_random import BOARDS, Board, cases

import compiler
from compiler.avr import isa
from compiler.avr.asm import Assembler
from compiler.avr.flow import instruction_at
from compiler.avr.part import WGM12, Part
from compiler.budget import BRANCH, CALL, JUMP, NEXT, RETURN, SKIP
from compiler.errors import FLASH_FULL, RAM_FULL, CompileError
from lang.checks import check_program
from lang.devices import find_device
from lang.families import FAMILIES
from lang.hardware import pwm_refusal
from lang.model import Span

NAME = "Atmel AVR ATtiny10 6-Pin packages"
HEADER = Path("/usr/lib/avr/include/avr/iotn10.h")
needs_header = pytest.mark.skipif(not HEADER.is_file() and not IN_CI, reason="avr-libc not installed")

# PB1 is CLKI only with an external clock; PB3 (RESET) is the A/D input, as
# the ATtiny85's board reads its RESET pin
TINY10 = Board("attiny10", "avr", NAME, ("PB1",), ("PB0", "PB2"), "PB3", None, uart=False,
               crystal_hz=8_000_000, cycle_us=10_000,
               left_out=frozenset(("UART_SEND", "UART_SEND_READY", "UART_RECV", "UART_RECV_AVAIL",
                                   "FORMATTED_STRING", "PERSIST", "SET_PWM")))
# the corpus programs with at most four pins and no UART, PWM, PERSIST, SPI or I2C
FITS = ("Tests/test-adc.ld", "reg/tests/integers.ld", "sample/blink.ld")


def _header() -> tuple[dict[str, int], dict[str, int], str]:
    """Registers (data addresses: the reduced core's I/O addresses are its
    data addresses) and bit positions of iotn10.h, with avr/common.h's
    stack pointer and status register (0x3D..0x3F for __AVR_ARCH__ >= 100)."""
    text = HEADER.read_text()
    registers = {"SPL": 0x3D, "SPH": 0x3E, "SREG": 0x3F}
    for m in re.finditer(r"#\s*define\s+(\w+)\s+_SFR_IO(?:8|16)\s*\((0[xX][0-9A-Fa-f]+)\)", text):
        registers.setdefault(m.group(1), int(m.group(2), 16))
    bits = {m.group(1): int(m.group(2)) for m in re.finditer(r"#\s*define\s+(\w+)\s+(\d)\b", text)}
    return registers, bits, text


def _constant(text: str, name: str) -> int:
    m = re.search(rf"#\s*define\s+{name}\s+\(?(0[xX][0-9A-Fa-f]+|\d+)", text)
    assert m is not None, name
    return int(m.group(1), 0)


@needs_header
def test_facts_match_avr_libc():
    device = find_device(NAME)
    avr = device.data["avr"]
    registers, bits, text = _header()
    for name, address in avr["registers"].items():
        assert registers[name] == address, name
    assert avr["flash"] == device.memory["flash"] == _constant(text, "FLASHEND") + 1 == 1024
    assert avr["ram"] == {"start": _constant(text, "RAMSTART"), "size": _constant(text, "RAMSIZE")} \
        == {"start": 0x40, "size": 32}
    assert _constant(text, "E2PAGESIZE") == 0 and avr["eeprom"] == device.memory["eeprom"] == 0  # no EEPROM
    assert {pin.name for pin in device.io_pins()} == {f"PB{i}" for i in range(4)}
    assert {f"PINB{i}" for i in range(4)} <= set(bits) and "PINB4" not in bits
    # Timer0 is the 16-bit one: OCR0A has a high byte, CTC is WGM02 in TCCR0B
    assert {"OCR0AH", "TCNT0H"} <= set(registers) and bits["WGM02"] == WGM12
    cycle = avr["cycle_timer"]
    assert cycle["timer"] == 0 and cycle["counts"] == 65536 and bits["OCF0A"] == cycle["OCF0A"]
    assert bits["WDE"] == avr["watchdog"]["WDE"] and "WDCE" not in bits  # the CCP guards WDTCSR instead
    assert avr["sleep"]["power_down"] == 1 << bits["SE"] | 1 << bits["SM1"]
    # an 8-bit converter: ADCL and no ADCH; four channels, MUX1:0
    assert "ADCH" not in registers and avr["adc"]["bits"] == 8 and "MUX2" not in bits
    assert sorted(device.adc.values()) == [0, 1, 2, 3]
    assert "UDR" not in text and device.uart == {}
    # the pull-ups are a register of their own
    assert avr["pullups"] + "B" in registers
    assert Part.of(device).core is isa.REDUCED and not Part.of(device).has_mul


# --- the reduced core against avr-as ----------------------------------------------------------

def _assembles(source: str, tmp: Path) -> bool:
    (tmp / "one.s").write_text(source + "\n")
    done = subprocess.run(["avr-as", "-mmcu=attiny10", str(tmp / "one.s"), "-o", str(tmp / "one.o")],
                          capture_output=True, text=True)
    return done.returncode == 0


@needs_avr_gcc
def test_every_form_of_the_reduced_core_reassembles_to_the_same_bytes(tmp_path):
    rng = random.Random(10)
    asm = Assembler(long_jumps=False, flash_words=512, core=isa.REDUCED)
    for mnemonic, op in isa.OPCODES.items():
        if op.syntax == "k" or not isa.REDUCED.has(mnemonic):
            continue
        for _ in range(12):
            values = list(operands(op, rng))
            for i, field in enumerate(f for f in op.syntax.split(",") if f in ("d", "r", "K", "b", "A", "k")):
                if field in ("d", "r"):
                    values[i] = 16 + values[i] % 16
                    if op.syntax in ("d,X", "X,r", "X+,r"):
                        values[i] = rng.choice([r for r in range(16, 32) if r not in (26, 27)])
                    if op.syntax == "d,Z+":
                        values[i] = rng.choice(range(16, 30))
                elif field == "k":
                    values[i] = rng.choice((0x40, 0x5F, 0x80, 0xBF, rng.randrange(0x40, 0xC0)))
            asm.emit(mnemonic, *values)
    assembled = asm.assemble()
    assert reassemble(assembled.listing, "attiny10", tmp_path) == assembled.image()


@needs_avr_gcc
def test_avr_as_refuses_what_the_reduced_core_lacks_and_so_does_the_encoder(tmp_path):
    examples = {"mul": "mul r16, r17", "movw": "movw r16, r18", "sbiw": "sbiw r24, 1", "lpm_p": "lpm r16, Z+",
                "jmp": "jmp 0", "call": "call 0"}
    assert set(examples) == set(isa.REDUCED.lacks)
    for mnemonic, source in examples.items():
        assert not _assembles(source, tmp_path), source
        with pytest.raises(isa.EncodingError):
            isa.encode(mnemonic, *([24, 1] if mnemonic in ("mul", "movw", "sbiw") else [0]), core=isa.REDUCED)
    # registers r0..r15 do not exist; LDS/STS reach 0x40..0xBF only (avr-as
    # takes other addresses modulo that window: the encoder refuses them)
    assert not _assembles("mov r0, r16", tmp_path)
    for bad in (("mov", 15, 16), ("lds", 16, 0x3F), ("sts", 0xC0, 16)):
        with pytest.raises(isa.EncodingError):
            isa.encode(*bad, core=isa.REDUCED)


# --- images ------------------------------------------------------------------------------------

def _moved(path: str):
    prog = moved(load(path), TINY10)
    return replace(prog, settings=replace(prog.settings, crystal_hz=TINY10.crystal_hz))


@needs_avr_gcc
@pytest.mark.parametrize("path", FITS)
def test_corpus_programs_that_fit_reassemble_to_the_same_words(path, tmp_path):
    build = compiler.build(_moved(path))
    assert build.device.part == "attiny10"
    assert reassemble(build.image.listing, "attiny10", tmp_path) == build.image.program_bytes()


def _protected_write(listing: str, io: int) -> int:
    """The value the code writes to an I/O register the configuration change
    protection guards, checking that the CCP key (0xD8) is written to CCP
    (0x3C) by the instruction just before."""
    code = [line.split(";")[0].strip() for line in listing.splitlines() if line.startswith("\t")]

    def value(reg: str, before: int) -> int:
        for line in reversed(code[:before]):
            if line.startswith(f"ldi {reg}, "):
                return int(line.split(", ")[1], 16)
            if line.startswith(f"mov {reg}, "):
                return value(line.split(", ")[1], before) if line.split(", ")[1] != "r16" else 0  # r16: zero
        raise AssertionError(f"{reg} never loaded")

    [at] = [i for i, line in enumerate(code) if line.startswith(f"out 0x{io:02x}, ")]
    assert code[at - 1].startswith("out 0x3c, ") and value(code[at - 1].split(", ")[1], at - 1) == 0xD8
    return value(code[at].split(", ")[1], at)


@pytest.mark.parametrize("crystal_hz, prescaler", [(8_000_000, 0), (1_000_000, 3), (62_500, 7)])
def test_the_clock_is_the_oscillator_divided_as_the_program_asks(crystal_hz, prescaler):
    """CLKPSR (0x36): the 8 MHz oscillator divided by 2^n (the datasheet; 1 MHz
    at reset), the watchdog (WDTCSR, 0x31) at 2 s with WDE, both after the key."""
    prog = program([contact("Xa"), coil("Ya")], mcu=NAME, pins={"Xa": "PB1", "Ya": "PB0"})
    listing = compiler.build(replace(prog, settings=replace(prog.settings, crystal_hz=crystal_hz))).image.listing
    assert _protected_write(listing, 0x36) == prescaler
    assert _protected_write(listing, 0x31) == 0b1111


def test_an_external_clock_comes_in_on_clki():
    """A clock that is no division of the oscillator: CLKMSR (0x37) selects
    the external clock on CLKI (PB1), which the program then cannot use."""
    prog = program([contact("Xa"), coil("Ya")], mcu=NAME, pins={"Xa": "PB2", "Ya": "PB0"})
    listing = compiler.build(replace(prog, settings=replace(prog.settings, crystal_hz=16_000_000))).image.listing
    assert _protected_write(listing, 0x37) == 0b10 and _protected_write(listing, 0x36) == 0
    prog.pins["Xa"] = replace(prog.pins["Xa"], pin="PB1")
    [found] = [d for d in check_program(replace(prog, settings=replace(prog.settings, crystal_hz=16_000_000)))
               if d.code == "LD413"]
    assert "which the ATtiny10 uses as CLKI, the external clock's input, when it runs at 16 MHz" in found.message
    assert "so the clock comes in on CLKI (the ATtiny10 takes no crystal)" in found.message


# the classic cores' cycles (test_compiler_budget.py), with the reduced core's
# one-cycle LDS/STS and the larger counts given for its calls, returns and POP
REDUCED_CYCLES = {**AVR_CYCLES, "lds": 1, "sts": 1, "rcall": 4, "ret": 6, "pop": 3}


@needs_objdump
@pytest.mark.parametrize("path", FITS)
def test_the_budgets_decoder_reads_the_reduced_core_as_avr_objdump_does(path, tmp_path):
    """The one-word LDS/STS are the classic cores' LDD/STD encodings: the
    decoder must size them, and every other instruction, as avr-objdump's
    avrtiny (avr:100) does."""
    build = compiler.build(_moved(path))
    build.write(tmp_path / "p.hex")
    listed = _objdump(tmp_path / "p.hex", "avr:100", build.image.labels["start"])
    assert len(listed) > 50 and {"lds", "sts"} & {mnemonic for _, _, mnemonic, _, _ in listed}
    sizes = {address: size for address, size, *_ in listed}
    for address, size, mnemonic, _operands, target in listed:
        ins = instruction_at(build.image.words, address, build.device)
        assert ins is not None and ins.size == size, (address, mnemonic)
        if mnemonic in AVR_SKIPS:
            skipped = sizes[address + 1]
            assert (ins.flow, ins.cycles, ins.taken, ins.target) == (SKIP, 1, 1 + skipped, address + 1 + skipped)
        elif mnemonic.startswith("br"):
            assert (ins.flow, ins.cycles, ins.taken, ins.target) == (BRANCH, 1, 2, target)
        else:
            flow = {"rjmp": JUMP, "rcall": CALL, "ret": RETURN}.get(mnemonic, NEXT)
            assert (ins.flow, ins.cycles) == (flow, REDUCED_CYCLES.get(mnemonic, 1)), (address, mnemonic)


# --- what does not fit -------------------------------------------------------------------------

def _refusal(prog) -> list[tuple[str, str, Span | None]]:
    with pytest.raises(CompileError) as refused:
        compiler.build(prog)
    return [(d.code, d.message, d.span) for d in refused.value.diagnostics]


def test_a_program_beyond_the_flash_is_ld703_with_the_numbers():
    rungs = [[contact("Xa"), el("ADD", dest=f"v{i % 4}", op1=f"v{(i + 1) % 4}", op2=str(i + 300))] for i in range(120)]
    [(code, message, _)] = _refusal(program(*rungs, mcu=NAME, pins={"Xa": "PB1"}))
    assert code == FLASH_FULL
    assert re.fullmatch(r"the program needs \d{4} bytes of flash; the ATtiny10 has 1024", message)


def test_variables_and_the_stack_beyond_the_ram_are_ld704_with_the_numbers():
    """The stack is what the image's calls and pushes take (compiler/avr/stack.py):
    a 16-bit division is two calls deep, 4 bytes."""
    rungs = [[contact("Xa"), el("MOVE", dest=f"v{i}", src=str(i + 1000))] for i in range(15)]
    assert compiler.build(program(*rungs, mcu=NAME, pins={"Xa": "PB1"})).image.ram_bytes == 30
    divide = [contact("Xa"), el("DIV", dest="v0", op1="v1", op2="v2")]
    [(code, message, _)] = _refusal(program(*rungs, divide, mcu=NAME, pins={"Xa": "PB1"}))
    assert (code, message) == (RAM_FULL, "the variables need 30 bytes of RAM and the stack 4; the ATtiny10 has 32")
    recursive = [[contact("Xa"), el("GOSUB", label="sub")], [el("SUBPROG", label="sub")],
                 [contact("Xa"), el("GOSUB", label="sub")], [el("ENDSUB", label="sub")]]
    [(code, message, _)] = _refusal(program(*recursive, mcu=NAME, pins={"Xa": "PB1"}))
    assert (code, message) == (RAM_FULL, "the stack has no bound (a subroutine that calls itself); "
                                         "the ATtiny10 has 32 bytes of RAM")


def test_uart_persist_and_pwm_the_part_lacks_are_located_errors():
    send = el("UART_SEND", var="v", wait=0)
    [(code, message, span)] = _refusal(program([contact("Xa"), send], mcu=NAME, pins={"Xa": "PB1"}))
    assert (code, span) == ("LD503", Span(0, 100, 0, 150)) and "the ATtiny10 has no UART" in message
    persist = el("PERSIST", var="v")
    [(code, message, _)] = _refusal(program([persist], [contact("Xa"), el("MOVE", dest="v", src="1")],
                                            mcu=NAME, pins={"Xa": "PB1"}))
    assert (code, message) == ("LD705", "the PERSIST variables need 2 bytes of EEPROM; the part has 0")
    pwm = el("SET_PWM", duty="50", freq=1000, name="P")
    assert [(c, m) for c, m, _ in _refusal(program([contact("Xa"), pwm], mcu=NAME, pins={"Xa": "PB1", "P": "PB0"}))] \
        == [("LD708", "PWM on OC0A: Timer0 makes the scan cycle; use an 8-bit timer's output")]
    assert [c for c, _, _ in _refusal(program([contact("Xa"), pwm], mcu=NAME, pins={"Xa": "PB1", "P": "PB2"}))] \
        == ["LD405"]


# --- random programs ---------------------------------------------------------------------------

@needs_avr_gcc
@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases((TINY10,)))
def test_random_programs_that_fit_reassemble_to_the_same_words(case, tmp_path_factory):
    try:
        build = compiler.build(case.program)
    except CompileError as problem:
        # 1 KB of flash and 32 bytes of RAM: a program that does not fit is refused with its numbers
        assume(not all(d.code in (FLASH_FULL, RAM_FULL) for d in problem.diagnostics))
        raise
    assert reassemble(build.image.listing, "attiny10", tmp_path_factory.mktemp("tiny10")) \
        == build.image.program_bytes()


# --- LDmicro -----------------------------------------------------------------------------------

@pytest.mark.ldmicro
@pytest.mark.parametrize("timer, register, value", [(0, "OCR0A", 249), (1, "TCCR1A", 0)])
def test_ldmicro_refuses_every_attiny10_program(timer, register, value, tmp_path):
    """LDmicro 5.4.1.1 lists the ATtiny10 but its register table for it
    (avr.cpp) leaves OCR0A out and has no Timer1: the cycle's first write
    goes to address 0, and it refuses the program whichever timer makes the
    cycle ("WriteMemory(0, 249)": OCR0A's count at Timer0; "WriteMemory(0,
    0)": TCCR1A at Timer1). We build them."""
    prog = _moved("sample/blink.ld")
    prog = replace(prog, settings=replace(prog.settings, cycle_timer=timer))
    with pytest.raises(AssertionError, match=rf"Zero memory address not allowed!\s+WriteMemory\(0, {value}\)"):
        ldmicros_hex(prog, tmp_path)
    assert f"WriteMemory(REG_{register}, " in _ldmicro_avr_source()
    assert compiler.build(prog).device.part == "attiny10"


def test_ldmicros_attiny10_registers_are_not_the_parts():
    """The addresses LDmicro's table does give the ATtiny10 are the
    ATmega's data addresses, none the ATtiny10's (iotn10.h): it could not
    drive the part had it compiled."""
    text = _ldmicro_avr_source()
    table = text[text.index('McuAs(" ATtiny10 ")'):text.index('McuAs(" ATtiny85 ")')]
    given = {m.group(1): int(m.group(2), 16) for m in re.finditer(r"^\s*REG_(\w+)\s*=\s*(0x[0-9A-F]+);", table, re.M)}
    assert "OCR0A" not in given and "TCCR1A" not in given
    ours = find_device(NAME).data["avr"]["registers"]
    wrong = {name: (address, ours[name]) for name, address in given.items() if name in ours}
    assert wrong == {"TCCR0A": (0x4A, 0x2E), "TCCR0B": (0x53, 0x2D), "TIFR0": (0x35, 0x2A), "ADMUX": (0x7C, 0x1B),
                     "ADCSRA": (0x7A, 0x1D), "ADCL": (0x78, 0x19)}


def _ldmicro_avr_source() -> str:
    with tarfile.open(LDMICRO_SOURCE) as archive:
        member = archive.extractfile("ldmicro-5.4.1.1/ldmicro/avr.cpp")
        assert member is not None
        return member.read().decode("latin-1")


def test_the_docs_table_of_avr_parts_is_the_device_files():
    docs = (Path(__file__).resolve().parents[1] / "docs" / "compiler.md").read_text()
    section = docs[docs.index("## AVR parts"):docs.index("## The ATtiny10")]
    rows = {cells[0]: cells[1:] for line in section.splitlines() if line.startswith("| ") and "---" not in line
            for cells in [[c.strip() for c in line.strip("|").split("|")]] if cells[0] != "part"}
    parts = [find_device(part) for part in FAMILIES["avr"].parts]
    assert list(rows) == [device.title for device in parts]
    for device in parts:
        avr = device.data["avr"]
        core, flash, ram, eeprom, uart, adc, pwm, _lacks, _flashing = rows[device.title]
        assert core == ("AVRrc" if avr.get("core") == "reduced" else avr["arch"])
        assert [int(n.replace(",", "")) for n in (flash, ram, eeprom)] == [avr["flash"], avr["ram"]["size"],
                                                                           avr["eeprom"]]
        assert (uart == "yes") == bool(device.uart) and int(adc) == len(device.adc)
        driven = sorted({unit for unit in device.pwm.values() if pwm_refusal(device, unit, 1000) is None})
        assert pwm == (", ".join(driven) or "—")


# --- the reduced core's choices, run -----------------------------------------------------------

# No simulator runs the ATtiny10. What can be run is the code the reduced core
# makes the back end choose (sixteen registers, bits in RAM, no MUL, MOVW or
# SBIW) on a part simavr has, with that part's encodings and memory map: the
# ATmega328P. The ATtiny10's own encodings, addresses and peripherals are
# checked above, statically, and are not run by this.
SIBLING = replace(isa.REDUCED, io_offset=isa.CLASSIC.io_offset, forms={}, flash_data=None,
                  lacks=isa.REDUCED.lacks - {"lpm_p"})


@contextmanager
def _reduced_choices(part: str):
    """The part compiled with SIBLING's choices while in the block."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setitem(isa.CORES, "reduced", SIBLING)
        patch.setitem(find_device(part).data["avr"], "core", "reduced")
        yield


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("path", sorted(CASES))
def test_corpus_programs_with_the_reduced_cores_choices_follow_the_simulator(path, tmp_path):
    events, scans = CASES[path]
    program = load(path)
    with _reduced_choices(program.settings.mcu):
        assert differential(program, events, scans, tmp_path) == []


@needs_simavr
@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases(BOARDS[:1]))
def test_random_programs_with_the_reduced_cores_choices_follow_the_simulator(case, tmp_path_factory):
    with _reduced_choices(case.program.settings.mcu):
        try:
            problems = differential(case.program, case.events, case.scans, tmp_path_factory.mktemp("sibling"))
        except CompileError as problem:
            assume(not all(d.code in (FLASH_FULL, RAM_FULL) for d in problem.diagnostics))
            raise
    assert problems == [], "\n".join(problems)
