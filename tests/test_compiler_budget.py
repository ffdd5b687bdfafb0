"""The scan-time budget (compiler/budget.py): the analysis on hand-built
instruction lists; the decoders against the families' own disassemblers
(avr-objdump, gpdasm) with the manuals' cycle counts; what `ladder build`
reports and warns; and, in the simulators, that the worst case is never below
a measured scan (sound) and at most twice the longest one on loop-free
programs driven along their longest path (tight). A scan is measured on the
YPlcCycleDuty pin, high from the start of the scan to its end: simavr and
gpsim give the cycle of each edge."""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import replace

import pytest
from builders import coil, contact, counter, el, move, par, program, timer
from hypothesis import HealthCheck, given, settings
from test_compiler_harness import CORPUS, Event, load, needs_simavr, run_hex
from test_compiler_random import NEW_AVR_BOARDS, cases

import compiler
from compiler.budget import BRANCH, CALL, COMPUTED, JUMP, NEXT, RETURN, SKIP, Analysis, Instruction
from compiler.errors import SCAN_OVERRUN, CompileError
from compiler.image import LoopBound
from compiler.run import gpsim
from lang.loader import load_path
from lang.model import PinAssignment

AVR = "Atmel AVR ATmega328 28-PDIP"
AVR_PINS = {"Xa": "PD2", "Xb": "PD3", "Xc": "PD4", "Ya": "PB0", "Yb": "PB1", "Yc": "PB2", "Yd": "PB3"}
PIC = "Microchip PIC16F877 40-PDIP"
PIC_PINS = {"Xa": "RD0", "Xb": "RD1", "Xc": "RD2", "Ya": "RB0", "Yb": "RB1", "Yc": "RB2", "Yd": "RB3"}
needs_objdump = pytest.mark.skipif(shutil.which("avr-objdump") is None, reason="binutils-avr not installed")
needs_gpdasm = pytest.mark.skipif(shutil.which("gpdasm") is None, reason="gputils not installed")
needs_gpsim = pytest.mark.skipif(not gpsim.available(), reason="gpsim not installed")

# --- the analysis on hand-built code ---------------------------------------------------------


def worst(*instructions: Instruction, bounds=None, entry: int = 0, end: int | None = None):
    table = {i.address: i for i in instructions}
    return Analysis(table.get, bounds or {}).routine(entry, end)


def op(address, cycles=1, flow=NEXT, target=None, taken=0, size=1, targets=()):
    return Instruction(address, size, cycles, flow, target, taken, targets)


def test_straight_code_adds_up_and_a_branch_takes_the_longer_way():
    assert worst(op(0), op(1, 2), op(2), op(3, 4, RETURN)).cycles == 8
    # taken: 2 + 4; not taken: 1 + 5 + 2 + 4
    found = worst(op(0, 1, BRANCH, 3, 2), op(1, 5), op(2, 2, JUMP, 3), op(3, 4, RETURN))
    assert found.cycles == 12 and found.loops == [] and found.unbounded == []


def test_a_skip_over_a_two_word_instruction_costs_its_size():
    code = [op(0, 1, SKIP, 3, 3), op(1, 2, size=2), op(3, 4, RETURN)]
    assert worst(*code).cycles == 7
    assert worst(op(0, 1, SKIP, 3, 9), *code[1:]).cycles == 13


def test_a_counted_loop_costs_its_passes():
    # 0: set-up; 1: the head; 2: back to it (2 taken, 1 not); 3: return
    code = [op(0), op(1), op(2, 1, BRANCH, 1, 2), op(3, 4, RETURN)]
    found = worst(*code, bounds={1: LoopBound(10, "ten passes")})
    # nine passes of 1 + 2, the last 1 + 1
    assert found.cycles == 1 + 9 * 3 + 2 + 4
    assert [(u.head, u.what, u.cycles) for u in found.loops] == [(1, "ten passes", 29)]


def test_a_wait_bounded_in_time_costs_that_time_and_one_pass():
    code = [op(0), op(1), op(2, 1, BRANCH, 1, 2), op(3, 4, RETURN)]
    found = worst(*code, bounds={1: LoopBound(None, "a conversion", cycles=100)})
    assert found.cycles == 1 + (100 + 3 + 2) + 4
    both = worst(*code, bounds={1: LoopBound(5, "both", cycles=100)})
    assert both.cycles == 1 + (4 * 3 + 2) + 4  # the tighter of the two


def test_a_loop_left_from_its_middle():
    # 0 head; 1 skip to 3 or fall to 2: return; 3 jump back (like PIC16's multiplication)
    code = [op(0), op(1, 1, SKIP, 3, 2), op(2, 2, RETURN), op(3, 2, JUMP, 0)]
    assert worst(*code, bounds={0: LoopBound(5, "m")}).cycles == 4 * (1 + 2 + 2) + (1 + 1 + 2)


def test_nested_loops_multiply():
    # outer head 0, inner head 1 (back from 2), outer back from 3
    code = [op(0), op(1), op(2, 1, BRANCH, 1, 2), op(3, 1, BRANCH, 0, 2), op(4, 4, RETURN)]
    bounds = {0: LoopBound(3, "outer"), 1: LoopBound(4, "inner")}
    inner = 3 * (1 + 2) + (1 + 1)
    outer_pass = 1 + inner + 2
    assert worst(*code, bounds=bounds).cycles == 2 * outer_pass + (1 + inner + 1) + 4


def test_a_call_costs_its_callee_each_time():
    code = [op(0, 3, CALL, 10), op(1, 3, CALL, 10), op(2, 4, RETURN), op(10, 1), op(11, 4, RETURN)]
    assert worst(*code).cycles == 2 * (3 + 5) + 4


def test_without_a_bound_the_reasons_are_given():
    code = [op(0, 1, BRANCH, 4, 2), op(1), op(2, 2, JUMP, 1), op(4), op(5, 2, JUMP, 4)]
    found = worst(*code, bounds={1: LoopBound(None, "LOCK")})
    assert sorted((u.head, u.what) for u in found.unbounded) == [(1, "LOCK"), (4, None)]


def test_recursion_unknown_jumps_and_jumps_into_loops_are_unbounded():
    recursive = worst(op(0, 3, CALL, 0), op(1, 4, RETURN))
    assert [u.what for u in recursive.unbounded] == ["a subroutine that calls itself"]
    computed = worst(op(0, 2, COMPUTED, targets=(1, 2)), op(1, 5, RETURN), op(2, 2, RETURN))
    assert computed.cycles == 7 and not computed.unbounded
    unknown = worst(op(0, 2, COMPUTED))
    assert "computed jump" in unknown.unbounded[0].what
    # 0 branches to 2, the middle of the loop 1..3
    into = worst(op(0, 1, BRANCH, 2, 2), op(1), op(2), op(3, 1, BRANCH, 1, 2), op(4, 4, RETURN),
                 bounds={1: LoopBound(3, "loop")})
    assert [u.what for u in into.unbounded] == ["a jump into the middle of a loop"]
    assert worst(op(0, 2, JUMP, 7)).unbounded[0].what.startswith("code the analysis cannot read")


def test_the_scan_ends_at_its_end_label():
    code = [op(0), op(1, 1, BRANCH, 3, 2), op(2, 2), op(3), op(4, 2, JUMP, 3)]
    assert worst(*code, end=3).cycles == 1 + 1 + 2


# --- the decoders against the families' disassemblers -----------------------------------------

# the AVR Instruction Set Manual's cycles for the classic cores (2-byte program counter)
AVR_CYCLES = {**dict.fromkeys(("lds", "sts", "ld", "st", "push", "pop", "mul", "sbiw", "adiw", "sbi", "cbi",
                               "rjmp"), 2), "lpm": 3, "jmp": 3, "rcall": 3, "call": 4, "ret": 4}
AVR_SKIPS = {"sbrc", "sbrs", "sbic", "sbis", "cpse"}
_OBJDUMP = re.compile(r"^\s*([0-9a-f]+):\t((?:[0-9a-f]{2} )+)\s*\t(\w+)\s*([^;]*)(?:;\s*(0x[0-9a-f]+))?")


def _objdump(hex_path, arch: str, start: int) -> list[tuple[int, int, str, str, int | None]]:
    out = subprocess.run(["avr-objdump", "-D", "-b", "ihex", "-m", arch, f"--start-address={2 * start:#x}",
                          str(hex_path)], capture_output=True, text=True, check=True).stdout
    found = []
    for line in out.splitlines():
        m = _OBJDUMP.match(line)
        if m:
            address, size = int(m.group(1), 16) // 2, len(m.group(2).split()) // 2
            operands = m.group(4).strip()
            target = m.group(5) or (operands if m.group(3) in ("jmp", "call") else None)
            found.append((address, size, m.group(3), operands, int(target, 16) // 2 if target else None))
    return found


@needs_objdump
@pytest.mark.parametrize("path, target, arch", [
    ("sample/swatch2.ld", None, "avr5"), ("sample/hello.ld", None, "avr4"),
    ("reg/tests/integers.ld", "atmega2560", "avr6"), ("Tests/test-adc.ld", None, "avr5"),
    ("sample/hello.ld", "atmega48", "avr4"), ("reg/tests/integers.ld", "at90usb647", "avr5"),
])
def test_avr_decoder_agrees_with_avr_objdump(path, target, arch, tmp_path):
    from compiler.avr.flow import instruction_at

    build = compiler.build(load(path), target)
    build.write(tmp_path / "p.hex")
    image, pc_bytes = build.image, build.device.data["avr"]["pc_bytes"]
    listed = _objdump(tmp_path / "p.hex", arch, image.labels["start"])
    assert len(listed) > 50
    sizes = {address: size for address, size, *_ in listed}
    for address, size, mnemonic, _operands, target_address in listed:
        ins = instruction_at(image.words, address, build.device)
        assert ins is not None and ins.size == size, (address, mnemonic)
        extra = pc_bytes - 2 if mnemonic in ("rcall", "call", "ret") else 0
        if mnemonic in AVR_SKIPS:
            assert (ins.flow, ins.cycles, ins.taken) == (SKIP, 1, 1 + sizes[address + 1])
            assert ins.target == address + 1 + sizes[address + 1]
        elif mnemonic.startswith("br"):
            assert (ins.flow, ins.cycles, ins.taken, ins.target) == (BRANCH, 1, 2, target_address)
        else:
            flow = {"rjmp": JUMP, "jmp": JUMP, "rcall": CALL, "call": CALL, "ret": RETURN}.get(mnemonic, NEXT)
            assert (ins.flow, ins.cycles) == (flow, AVR_CYCLES.get(mnemonic, 1) + extra), (address, mnemonic)
            if flow in (JUMP, CALL):
                assert ins.target == target_address


PIC_TWO_CYCLES = {"goto", "call", "return", "retlw", "retfie"}
PIC_SKIPS = {"btfsc", "btfss", "decfsz", "incfsz"}
_GPDASM = re.compile(r"^([0-9a-f]{4}):\s+([0-9a-f]{4})\s+(\w+)\s*(.*)$")


def _tables_and_routines():
    """A PIC16 program with RETLW tables (a write to PCL), calls and loops."""
    lut = el("LOOK_UP_TABLE", dest="v", index="i", values=("3", "-200", "7", "1000"))
    return program([contact("Xa"), par([lut], [el("DIV", dest="q", op1="v", op2="i")],
                                       [el("SHL", dest="s", op1="v", op2="i")])],
                   mcu=PIC, pins={"Xa": "RD0"}, sizes={"v": 2, "i": 1, "q": 4, "s": 2})


@needs_gpdasm
@pytest.mark.parametrize("source", ["sample/blink.ld", "reg/tests/contacts.ld", _tables_and_routines])
def test_pic16_decoder_agrees_with_gpdasm(source, tmp_path):
    from compiler.pic16.flow import instruction_at
    from compiler.pic16.part import Part

    build = compiler.build(load(source) if isinstance(source, str) else source())
    build.write(tmp_path / "p.hex")
    words = build.image.words
    out = subprocess.run(["gpdasm", "-p", Part.of(build.device).processor, str(tmp_path / "p.hex")],
                         capture_output=True, text=True, check=True).stdout
    listed = [(int(m.group(1), 16), m.group(3), m.group(4)) for m in map(_GPDASM.match, out.splitlines())
              if m and int(m.group(1), 16) < len(words)]
    assert len(listed) == len(words)
    seen = set()
    for address, mnemonic, operands in listed:
        ins = instruction_at(words, address, build.device)
        assert ins is not None, (address, mnemonic)
        seen.add(ins.flow)
        if mnemonic in PIC_SKIPS:
            assert (ins.flow, ins.cycles, ins.taken, ins.target) == (SKIP, 1, 2, address + 2)
        elif mnemonic in ("goto", "call"):
            assert (ins.flow, ins.cycles) == (JUMP if mnemonic == "goto" else CALL, 2)
            assert ins.target & 0x7FF == int(operands, 16)
        elif re.match(r"0x02, 0x1$", operands) or (mnemonic in ("movwf", "clrf") and operands == "0x02"):
            assert (ins.flow, ins.cycles) == (COMPUTED, 2)  # a write to PCL: a table
            assert ins.targets and all(words[t] >> 10 == 0b1101 for t in ins.targets)
        else:
            assert ins.cycles == (2 if mnemonic in PIC_TWO_CYCLES else 1), (address, mnemonic)
            assert ins.flow == (RETURN if mnemonic in ("return", "retlw", "retfie") else NEXT)
    assert seen >= {NEXT, SKIP, JUMP}
    if not isinstance(source, str):
        assert seen >= {CALL, RETURN, COMPUTED}


def test_pic16_decoder_finds_the_page_of_far_jumps():
    """A program past 2K words: every GOTO and CALL goes to a label, some of
    them on another page (the page selection before them read)."""
    from compiler.pic16.flow import instruction_at

    rungs = [[contact("Xa" if i % 2 else "Xb"),
              par([el("ADD", dest=f"v{i}", op1=f"v{i}", op2="3")], [el("GRT", op1=f"v{i}", op2="100"), coil("Ya")],
                  [el("EQU", op1=f"v{(i + 7) % 30}", op2=f"v{i}"), el("MUL", dest=f"m{i}", op1=f"v{i}", op2="3")])]
             for i in range(40)]
    build = compiler.build(program(*rungs, mcu=PIC, pins=PIC_PINS, crystal_hz=20_000_000))
    words, labels = build.image.words, set(build.image.labels.values())
    assert len(words) > 2048
    jumps = [(a, ins.target) for a in range(len(words))
             if (ins := instruction_at(words, a, build.device)) is not None and ins.flow in (JUMP, CALL)]
    assert all(target in labels for _, target in jumps)
    assert any(target // 2048 != a // 2048 for a, target in jumps)


# --- what the compiler reports ---------------------------------------------------------------


def _compiled_corpus():
    for path in sorted(CORPUS.rglob("*.ld")):
        try:
            yield path, compiler.build(load_path(path)[0])
        except CompileError:
            continue


# The bound is not path-sensitive: swatch1's four FORMATTED_STRINGs, one of which runs per 1 ms
# scan, each divide in 32 bits on the PIC16 (about 1,400 cycles each at 16 MHz); the bound adds
# all four (6,500 cycles) where the longest scan measured in gpsim is 1,360.
LOOSE = {"swatch1.ld"}


def test_the_corpus_programs_are_bounded_and_fit_their_cycle():
    seen = 0
    for path, build in _compiled_corpus():
        if path.name in LOOSE:
            continue
        seen += 1
        budget = build.budget
        assert budget.cycles is not None and not budget.overruns, (path, budget.summary())
        assert SCAN_OVERRUN not in {w.code for w in build.warnings}, path
    assert seen >= 10


def _divisions(mcu: str, crystal_hz: int, count: int, size: int):
    pins = {"Xgo": "PD2" if "AVR" in mcu else "RD2"}
    quiet = [contact("Xgo"), coil("Rquiet")]
    busy = [contact("Xgo"), par(*[[el("DIV", dest=f"q{i}", op1=f"n{i}", op2=f"d{i}")] for i in range(count)])]
    return program(quiet, busy, mcu=mcu, pins=pins, cycle_us=1000, crystal_hz=crystal_hz,
                   sizes={f"{v}{i}": size for i in range(count) for v in "qnd"})


@pytest.mark.parametrize("mcu, count, size", [
    ("Microchip PIC16F877 40-PDIP", 2, 4), ("Atmel AVR ATmega328 28-PDIP", 8, 4)])
def test_a_scan_that_cannot_fit_is_warned_on_its_costliest_rung(mcu, count, size):
    build = compiler.build(_divisions(mcu, 4_000_000, count, size))
    budget = build.budget
    assert budget.overruns and budget.rung == 2
    assert budget.dominant[0].what == "a 32-bit division, one bit a pass" and budget.dominant[0].count == count
    warning = next(w for w in build.warnings if w.code == SCAN_OVERRUN)
    assert warning.severity == "warning" and warning.span.line == 1  # the second rung (0-based lines)
    assert "more than the 1 ms cycle" in warning.message and "32-bit division" in warning.message
    fewer = compiler.build(_divisions(mcu, 4_000_000, 1, 2))
    assert not fewer.budget.overruns and SCAN_OVERRUN not in {w.code for w in fewer.warnings}


def test_units_are_the_cpu_cycles_of_each_family():
    avr = compiler.build(_divisions("Atmel AVR ATmega328 28-PDIP", 4_000_000, 1, 2)).budget
    pic = compiler.build(_divisions("Microchip PIC16F877 40-PDIP", 4_000_000, 1, 2)).budget
    assert avr.us == pytest.approx(avr.cycles / 4)  # clock cycles at 4 MHz
    assert pic.us == pytest.approx(pic.cycles)  # instruction cycles at 1 MHz
    assert re.fullmatch(r"scan: at most [\d,]+ cycles = [\d.,]+ µs of the 1 ms cycle \(\d+\.\d%\).*",
                        avr.summary())


UNBOUNDED = [
    ([contact("Xgo"), el("LOCK")], "LOCK in rung 2"),
    ([contact("Xgo"), el("DELAY", delay="wait")], "a DELAY by a variable in rung 2"),
    ([contact("Xgo"), el("GOTO", label="top")], "a GOTO back to rung 1"),
    ([contact("Xgo"), el("UART_RECV", var="got", bytes=2, wait=1)], "a UART receive waiting for a byte in rung 2"),
]


@pytest.mark.parametrize("rung, reason", UNBOUNDED)
def test_an_unbounded_scan_says_why_and_where(rung, reason):
    first = [el("LABEL", label="top"), contact("Xgo"), coil("Ya")]
    prog = program(first, rung, mcu="Atmel AVR ATmega328 28-PDIP", pins={"Xgo": "PD2", "Ya": "PB0"},
                   sizes={"wait": 2, "got": 2})
    build = compiler.build(prog)
    assert build.budget.cycles is None and not build.budget.overruns
    assert build.budget.summary() == f"scan: no bound ({reason})"
    assert SCAN_OVERRUN not in {w.code for w in build.warnings}


def test_every_reason_is_given_in_rung_order():
    rungs = [[contact("Xgo"), coil("Ya")], [contact("Xgo"), el("DELAY", delay="wait")], [contact("Xgo"), el("LOCK")]]
    prog = program(*rungs, mcu=AVR, pins={"Xgo": "PD2", "Ya": "PB0"}, sizes={"wait": 2})
    assert compiler.build(prog).budget.summary() == "scan: no bound (a DELAY by a variable in rung 2; LOCK in rung 3)"


def test_a_uart_byte_already_received_is_bounded():
    rung = [contact("Xgo"), el("UART_RECV", var="got", bytes=1, wait=0)]
    build = compiler.build(program(rung, mcu="Atmel AVR ATmega328 28-PDIP", pins={"Xgo": "PD2"}))
    assert build.budget.cycles is not None


@settings(max_examples=20, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases())
def test_every_loop_of_a_random_program_has_a_bound(case):
    """The generator draws no LOCK, variable DELAY, waiting receive or
    backward GOTO: every loop the AVR back end writes must carry a bound."""
    try:
        build = compiler.build(case.program)
    except CompileError:
        return
    assert build.budget.cycles is not None, build.budget.summary()


@settings(max_examples=20, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases(NEW_AVR_BOARDS))
def test_every_loop_of_a_random_program_on_the_later_avrs_has_a_bound(case):
    test_every_loop_of_a_random_program_has_a_bound.hypothesis.inner_test(case)


# --- in the simulators ----------------------------------------------------------------------------

def with_duty(prog, build):
    """The program with YPlcCycleDuty on a free pin (not a UART, PWM or A/D pin)."""
    device = build.device
    used = {device.pin(a.pin).name for a in prog.pins.values() if device.pin(a.pin) is not None}
    special = set(device.uart.values()) | set(device.pwm) | set(device.adc)
    # the ATtiny85's pins are all special: then any pin the program leaves
    free = ([p for p in device.io_pins() if p.name not in used | special] or
            [p for p in device.io_pins() if p.name not in used])[-1]
    pins = {**prog.pins, "YPlcCycleDuty": PinAssignment("YPlcCycleDuty", free.name)}
    return replace(prog, settings=replace(prog.settings, cycle_duty=True), pins=pins), free


def _high_times(edges: list[tuple[int, int]]) -> list[int]:
    found, rise = [], None
    for cycle, level in edges:
        if level:
            rise = cycle
        elif rise is not None:
            found.append(cycle - rise)
            rise = None
    return found


def measure_avr(prog, events: list[Event], scans: int, tmp_path):
    """(the build, the cycles each scan took in simavr)."""
    prog, pin = with_duty(prog, compiler.build(prog))
    build = compiler.build(prog)
    build.write(tmp_path / "p.hex")
    run = run_hex(build, tmp_path / "p.hex", events, scans, [], watch=["YPlcCycleDuty"]).run
    return build, _high_times([(c, v) for c, p, v in run.edges if p == f"{pin.port}{pin.bit}"])


def measure_pic(prog, inputs_ms: list[tuple[float, str, int]], until_ms: float, tmp_path):
    """(the build, the instruction cycles each scan took in gpsim)."""
    prog, pin = with_duty(prog, compiler.build(prog))
    build = compiler.build(prog)
    build.write(tmp_path / "p.hex")
    run = gpsim.run_pic(tmp_path / "p.hex", build.device.part, prog.settings.crystal_hz, inputs=inputs_ms,
                        watch=[pin.name], until_ms=until_ms, uart=False, timeout=120)
    return build, _high_times([(c, v) for c, _, v in run.edge_cycles])


def _sound(build, measured: list[int]) -> float:
    """The worst case over the longest measured scan (at least 1)."""
    assert len(measured) > 10
    ratio = build.budget.cycles / max(measured)
    assert ratio >= 1, f"{build.budget.summary()}; measured {max(measured)}"
    return ratio



CORPUS_AVR = {  # the compiler corpus tests' stimuli
    "sample/traffic.ld": "TRAFFIC", "reg/tests/timers-counters.ld": "TIMERS", "sample/ctu_ctd_ctc.ld": None,
    "sample/ctu_ctd_ctc_ctr.ld": None, "sample/hello.ld": None, "sample/swatch2.ld": "SWATCH",
    "Tests/test-adc.ld": "ADC",
}


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("path", sorted(CORPUS_AVR))
def test_avr_worst_case_covers_every_measured_scan_of_the_corpus(path, tmp_path):
    import test_compiler_corpus as corpus

    events = getattr(corpus, CORPUS_AVR[path]) if CORPUS_AVR[path] else []
    scans = max([e.scan for e in events], default=0) + 300
    _sound(*measure_avr(load(path), events, scans, tmp_path))


@needs_simavr
@pytest.mark.slow
@settings(max_examples=12, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases())
def test_avr_worst_case_covers_every_measured_scan_of_random_programs(case, tmp_path_factory):
    try:
        build, measured = measure_avr(case.program, case.events, case.scans, tmp_path_factory.mktemp("budget"))
    except CompileError:
        return
    _sound(build, measured)


@needs_simavr
@pytest.mark.slow
@settings(max_examples=24, deadline=None, suppress_health_check=list(HealthCheck))
@given(case=cases(tuple(replace(board, inputs=board.inputs[:1]) if board.part == "attiny85" else board
                        for board in NEW_AVR_BOARDS)))  # a pin left for YPlcCycleDuty
def test_avr_worst_case_covers_every_measured_scan_on_the_later_avrs(case, tmp_path_factory):
    test_avr_worst_case_covers_every_measured_scan_of_random_programs.hypothesis.inner_test(case, tmp_path_factory)


@needs_simavr
@pytest.mark.slow
def test_avr_waits_on_hardware_cover_simavr(tmp_path):
    """UART SEND that waits for the transmitter (2 bytes: the second waits a
    whole frame), an A/D conversion (the first takes 25 ADC clocks) and a
    DELAY, every scan."""
    rungs = [[contact("Xa"), el("UART_SEND", var="word", bytes=2, wait=1)],
             [contact("Xa"), el("READ_ADC", name="Ain", refs=0)], [contact("Xa"), el("DELAY", delay="1000")]]
    prog = program(*rungs, mcu=AVR, pins={"Xa": "PD2", "Ain": "PC0"}, sizes={"word": 2},
                   crystal_hz=16_000_000, cycle_us=20_000)
    build, measured = measure_avr(prog, [Event(0, "Xa", 1)], 40, tmp_path)
    assert {w.what for w in build.budget.dominant} == {"waiting for the UART transmitter", "DELAY"}
    assert _sound(build, measured) <= 2


def _logic(mcu: str, pins: dict, arithmetic: bool):
    """Contacts, coils, edges, timers, counters, comparisons and (AVR) 16-bit
    arithmetic: no loop anywhere. Every rung does its most with Xa and Xb on
    and Xc toggling each scan."""
    rungs = [
        [par([contact("Xa"), contact("Xb")], [contact("Ya")]), contact("Xc", 1), coil("Ya")],
        [contact("Xa"), timer("TON", "Ton", 50_000), timer("TOF", "Toff", 30_000), coil("Yb")],
        [contact("Xc"), counter("CTU", "Cup", 1000)],
        [contact("Xb"), el("OSR"), counter("CTC", "Cring", 7)],
        [el("GEQ", op1="Cup", op2="3"), contact("Xb"), par([coil("Yc")], [move("v", "Cup")])],
        [contact("Xa"), el("RTO", name="Trto", delay=1_000_000, adjust=0), coil("Yd", "S")],
    ]
    if arithmetic:
        rungs += [[contact("Xa"), par([el("ADD", dest="s", op1="v", op2="Cup")],
                                      [el("MUL", dest="p", op1="s", op2="Cring")],
                                      [el("SUB", dest="d", op1="p", op2="v")])]]
    else:
        rungs += [[contact("Xa"), par([el("ADD", dest="s", op1="v", op2="Cup")],
                                      [el("SUB", dest="d", op1="s", op2="Cring")])]]
    return program(*rungs, mcu=mcu, pins=pins, crystal_hz=16_000_000 if "AVR" in mcu else 4_000_000,
                   sizes={"v": 2, "s": 2, "p": 2, "d": 2})


def _bits(mcu: str, pins: dict):
    """Series and parallel contacts into set, reset and plain coils; relays."""
    rungs = []
    for i in range(6):
        a, b = ("Xa", "Xb") if i % 2 else ("Xb", "Xa")
        rungs.append([par([contact(a), contact(f"R{i}")], [contact(b), contact("Xc", 1)]), el("OSF"),
                      par([coil(f"R{i + 1}")], [coil("Yc", "S" if i % 2 else "R")])])
    rungs.append([contact("R6"), contact("Xa"), par([coil("Ya")], [coil("Yb", "R")])])
    return program(*rungs, mcu=mcu, pins=pins, crystal_hz=16_000_000 if "AVR" in mcu else 4_000_000)


def _toggling(scans: int) -> list[Event]:
    return [Event(0, "Xa", 1), Event(0, "Xb", 1)] + [Event(s, "Xc", s % 2) for s in range(scans)]


TIGHT = {"logic": lambda mcu, pins: _logic(mcu, pins, "AVR" in mcu), "bits": _bits}


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(TIGHT))
def test_avr_worst_case_is_tight_on_loop_free_programs(name, tmp_path):
    build, measured = measure_avr(TIGHT[name](AVR, AVR_PINS), _toggling(80), 80, tmp_path)
    assert build.budget.loops == (), "not loop-free"
    assert _sound(build, measured) <= 2


def _pic_inputs(scans: int, cycle_ms: float) -> list[tuple[float, str, int]]:
    return [(max(0.0, (e.scan - 0.5) * cycle_ms), PIC_PINS[e.name], e.value) for e in _toggling(scans)]


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(TIGHT))
def test_pic16_worst_case_is_tight_on_loop_free_programs(name, tmp_path):
    build, measured = measure_pic(TIGHT[name](PIC, PIC_PINS), _pic_inputs(80, 10), 800, tmp_path)
    assert build.budget.loops == (), "not loop-free"
    assert _sound(build, measured) <= 2


@needs_gpsim
@pytest.mark.slow
def test_pic16_worst_case_covers_blink_and_a_program_of_loops(tmp_path):
    blink = load("sample/blink.ld")
    _sound(*measure_pic(blink, [(0, "RD2", 1), (300, "RD2", 0), (320, "RD2", 1), (900, "RD2", 0)], 2000,
                        tmp_path))
    loops = program(
        [contact("Xa"), par([el("ADD", dest="n", op1="n", op2="12345")], [el("DIV", dest="q", op1="n", op2="7")],
                            [el("SHL", dest="s", op1="n", op2="k")], [el("BIN2BCD", dest="b", src="q")])],
        [contact("Xb"), par([el("ADD", dest="k", op1="k", op2="1")], [el("MOD", dest="k", op1="k", op2="31")])],
        mcu=PIC, pins=PIC_PINS, crystal_hz=4_000_000, sizes={"n": 4, "q": 4, "s": 4, "k": 2, "b": 4})
    build, measured = measure_pic(loops, _pic_inputs(100, 10), 1000, tmp_path)
    assert "a 32-bit division, one bit a pass" in {w.what for w in build.budget.loops}
    _sound(build, measured)
