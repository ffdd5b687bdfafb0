"""LD330: a PERSIST variable that can change on every scan wears the EEPROM
out. The simulator, which runs PERSIST as the compiled code does (a write
whenever the variable differs from its EEPROM copy), counts the writes the
rule speaks of: every scan where it reports, once per event where it does not."""

from __future__ import annotations

from pathlib import Path

import pytest
from builders import coil, contact, counter, el, move, none, one, par, program, timer, words

from ladder.cli import main
from lang import ldfile
from lang.checks import check_program
from lang.sim import Simulator
from lang.sim.peripherals import Eeprom

M328 = "Atmel AVR ATmega328 28-PDIP"
PERSIST = [el("PERSIST", var="saved")]


class CountingEeprom(Eeprom):
    writes: int = 0

    def write(self, address: int, size: int, value: int) -> None:
        self.writes += 1
        super().write(address, size, value)


def _writes(prog, scans: int, **inputs) -> int:
    """EEPROM writes in `scans` scans with the inputs held as given."""
    sim = Simulator(prog)
    sim.peripherals.eeprom = eeprom = CountingEeprom()
    for name, value in inputs.items():
        sim.set_input(name, value)
    sim.step(scans)
    return eeprom.writes


def _pressed(prog, times: int) -> int:
    """EEPROM writes while Xrun is pressed `times` times, 10 scans on and 10 off."""
    sim = Simulator(prog)
    sim.peripherals.eeprom = eeprom = CountingEeprom()
    sim.step(10)
    for _ in range(times):
        for value in (1, 0):
            sim.set_input("Xrun", value)
            sim.step(10)
    return eeprom.writes


def _adding(*condition, op2="1"):
    return program([*condition, el("ADD", dest="saved", op1="saved", op2=op2)], PERSIST, mcu=M328)


def test_a_variable_that_adds_to_itself_on_every_scan():
    prog = _adding(contact("Xrun"))
    d = one(prog, "LD330")
    assert d.severity == "warning" and d.span == prog.rungs[1].circuit.items[0].arg_spans["var"]
    words(d, "'saved'", "ADD in rung 1", "100 writes a second", "10 ms", "100,000", "17 minutes", "OSR")
    assert d.related[0].span == prog.rungs[0].circuit.items[1].span
    # the first powered scan loads it; every later one writes it back
    assert _writes(prog, 50, Xrun=1) == 49


def test_the_rate_is_the_cycle_or_the_eeprom_write_time_whichever_is_slower():
    fast = program([contact("Xrun"), el("ADD", dest="saved", op1="saved", op2="1")], PERSIST,
                   mcu=M328, cycle_us=1000)
    # the ATmega328P's EEPROM takes 3.4 ms a byte (its datasheet): at most one write per 3.4 ms
    words(one(fast, "LD330"), "294.118 writes a second", "3.4 ms")


def test_behind_a_one_shot_it_changes_once_per_event():
    prog = _adding(contact("Xrun"), el("OSR"))
    none(prog, "LD330")
    assert _pressed(prog, 3) == 3
    assert _pressed(_adding(contact("Xrun")), 3) == 30


def test_behind_a_relay_that_a_one_shot_pulses():
    prog = program([contact("Xrun"), el("OSR"), coil("Rpulse")],
                   [contact("Rpulse"), el("ADD", dest="saved", op1="saved", op2="1")], PERSIST, mcu=M328)
    none(prog, "LD330")
    assert _pressed(prog, 3) == 3


def test_behind_a_timer_that_resets_itself_once_a_second():
    tick = [contact("Rtick", negated=1), timer("TON", "Tsec", 1000000), coil("Rtick")]
    prog = program(tick, [contact("Rtick"), el("ADD", dest="saved", op1="saved", op2="1")], PERSIST, mcu=M328)
    none(prog, "LD330")
    assert _writes(prog, 350) == 3  # 3.5 s: one tick a second
    free_running = [contact("Xrun"), timer("TON", "Tsec", 1000000), coil("Rtick")]
    one(program(free_running, [contact("Rtick"), el("ADD", dest="saved", op1="saved", op2="1")], PERSIST,
                mcu=M328), "LD330")


def test_a_one_shot_in_one_branch_only_does_not_gate():
    branches = par([contact("Xa"), el("OSR")], [contact("Xb")])
    one(program([branches, el("ADD", dest="saved", op1="saved", op2="1")], PERSIST, mcu=M328), "LD330")
    both = par([contact("Xa"), el("OSR")], [contact("Xb"), el("OSF")])
    none(program([both, el("ADD", dest="saved", op1="saved", op2="1")], PERSIST, mcu=M328), "LD330")


def test_a_persist_that_runs_only_on_an_edge():
    prog = program([contact("Xrun"), el("ADD", dest="saved", op1="saved", op2="1")],
                   [contact("Xsave"), el("OSR"), el("PERSIST", var="saved")], mcu=M328)
    none(prog, "LD330")


def test_changes_that_stop_or_step_on_edges():
    none(_adding(contact("Xrun"), op2="0"), "LD330")  # adds nothing
    none(program([contact("Xrun"), move("saved", "5")], PERSIST, mcu=M328), "LD330")  # once
    # a counter counts on rising edges
    none(program([contact("Xrun"), counter("CTU", "saved", "100")], PERSIST, mcu=M328), "LD330")
    # a received byte comes once
    none(program([el("UART_RECV", var="byte"), el("ADD", dest="saved", op1="saved", op2="byte")], PERSIST,
                 mcu=M328), "LD330")
    prog = program([contact("Xrun"), move("saved", "Xrun")], PERSIST, mcu=M328)
    none(prog, "LD330")


def test_a_copy_of_a_timer_changes_with_it():
    prog = program([contact("Xrun"), timer("TON", "Tpump", 100000)],
                   [contact("Xrun"), move("saved", "Tpump")], PERSIST, mcu=M328)
    d = one(prog, "LD330")
    words(d, "MOV in rung 2 copies 'Tpump' into 'saved'", "TON in rung 1 counts the time")
    assert _writes(prog, 9, Xrun=1) == 8


def test_an_ad_reading_and_a_persisted_timer():
    prog = program([el("READ_ADC", name="saved")], PERSIST, mcu=M328)
    words(one(prog, "LD330"), "READ ADC", "A/D converter")
    words(one(program([contact("Xrun"), timer("RTO", "Trun", 3600000000)], [el("PERSIST", var="Trun")],
                      mcu=M328), "LD330"), "RTO", "counts the time in 'Trun'")


def test_without_persist_or_a_part():
    none(program([contact("Xrun"), el("ADD", dest="saved", op1="saved", op2="1")], mcu=M328), "LD330")
    # without a part the rate is the cycle's
    no_part = program([contact("Xrun"), el("ADD", dest="saved", op1="saved", op2="1")], PERSIST)
    words(one(no_part, "LD330"), "100 writes a second")


def test_a_long_chain_of_copies():
    chain = [[contact("Xrun"), move(f"v{i}", f"v{i + 1}")] for i in range(3000)]
    prog = program([contact("Xrun"), timer("TON", "v3000", 100000)], *chain,
                   [el("PERSIST", var="v0")], mcu=M328)
    words(one(prog, "LD330"), "'v0'", "copies 'v1' into 'v0'", "TON in rung 1")


def test_a_counter_that_counts_on_every_scan():
    prog = program([contact("Xrun"), counter("CTC", "saved", "1000", edge="-")], PERSIST, mcu=M328)
    words(one(prog, "LD330"), "CTC in rung 1 counts in 'saved' on every scan its input is 1")
    assert _writes(prog, 20, Xrun=1) == 19


def test_a_project_turns_it_off(tmp_path, capsys):
    (tmp_path / "ladder.toml").write_text('[diagnostics]\nLD330 = "off"\n', encoding="utf-8")
    fixture = Path(__file__).parent / "diagnostics" / "LD330.ladder"
    (tmp_path / "hours.ladder").write_text(fixture.read_text(encoding="utf-8"), encoding="utf-8")
    assert main(["check", str(tmp_path / "hours.ladder")]) == 0
    assert "LD330" not in capsys.readouterr().out


CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus"


@pytest.mark.skipif(not CORPUS.is_dir(), reason="no corpus beside the repository")
def test_the_corpus_programs_change_their_persistent_variables_on_events():
    # LDmicro's asm_demo and c_demo and its AVR and PIC16 hardware tests: ADD behind OSR, MOV
    # behind OSR or after a UART RECV
    persisting = 0
    for path in sorted(CORPUS.rglob("*.ld")):
        prog, _ = ldfile.read_ld_bytes(path.read_bytes())
        persisting += any(e.kind == "PERSIST" for rung in prog.rungs for e in rung.elements())
        assert not [d for d in check_program(prog) if d.code == "LD330"], path
    assert persisting >= 4
