"""The rules about program flow and the values names can hold: LD133 (read
before the rung that writes it), LD217 (rungs that never do anything),
LD316 (a comparison that cannot change) and LD317 (a divisor that can be
zero). Each finding is also shown in the simulator: what the rule says
happens does happen, and a program it does not report behaves."""

from __future__ import annotations

import operator
import random
import re
from dataclasses import replace

import pytest
from builders import coil, contact, el, found, move, none, one, par, program, span_of
from corpus import all_ld_files
from hypothesis import given, settings
from hypothesis import strategies as st

from lang import ldfile
from lang.checks import Checker, check_program
from lang.config import Severities
from lang.sim import ElementKey, SimulationError, Simulator

# --- LD133 read before write ----------------------------------------------------------


def test_a_relay_read_above_its_coil_lags_one_scan():
    read, write = contact("Rready"), coil("Rready")
    prog = program([read, coil("Ylamp")], [contact("Xstart"), write])
    d = one(prog, "LD133")
    assert d.severity == "info"
    assert d.span == span_of(read, "name")
    assert "read in rung 1 before rung 2 writes it" in d.message
    assert [r.span for r in d.related] == [span_of(write, "name")]
    # what the message says: the lamp follows the relay one scan late
    sim = Simulator(prog)
    sim.set_input("Xstart", 1)
    sim.step()
    assert (sim.value("Rready"), sim.value("Ylamp")) == (1, 0)
    sim.step()
    assert sim.value("Ylamp") == 1


def test_a_variable_read_above_its_computation():
    prog = program([el("GRT", op1="level", op2="100"), coil("Yfull")],
                   [el("READ_ADC", name="Alevel")],
                   [el("DIV", dest="level", op1="Alevel", op2="4")])
    assert "'level' is read in rung 1 before rung 3 writes it" in one(prog, "LD133").message


@pytest.mark.parametrize("rungs", [
    # a self-holding contact: read and written in one rung
    [[par([contact("Xstart")], [contact("Rrun")]), contact("Xstop", 1), coil("Rrun")]],
    # an edge memory: the rung compares the input with last scan's copy
    [[contact("Xin"), contact("Rprev", 1), coil("Rpulse")], [contact("Xin"), coil("Rprev")]],
    # a flag only ever set: rungs above work until it is done
    [[contact("Rdone", 1), el("ADD", dest="i", op1="i", op2="1")], [el("GRT", op1="i", op2="6"), coil("Rdone", "S")]],
    # written below, but also above: the first write comes first
    [[contact("Xa"), coil("Rx")], [contact("Rx"), coil("Ya")], [contact("Xb"), coil("Rx")]],
    # outputs, timers and counters have their own rules
    [[contact("Ya"), coil("Yb")], [contact("Xa"), coil("Ya")]],
    # nothing writes it: LD130
    [[contact("Rnever"), coil("Ya")]],
], ids=["self-holding", "edge-memory", "set-only", "written-above", "output", "never-written"])
def test_what_is_not_a_lag(rungs):
    none(program(*rungs), "LD133")


def test_a_subroutine_or_a_backward_goto_may_run_the_write_first():
    sub = program([contact("Rx"), coil("Ya")], [el("GOSUB", label="s")],
                  [el("SUBPROG", label="s")], [contact("Xa"), coil("Rx")], [el("ENDSUB", label="s")])
    none(sub, "LD133")
    loop = program([el("LABEL", label="top"), contact("Rx"), coil("Ya")], [contact("Xa"), coil("Rx")],
                   [contact("Xb"), el("GOTO", label="top")])
    none(loop, "LD133")
    forward = program([contact("Xb"), el("GOTO", label="on")], [el("LABEL", label="on"), contact("Rx"), coil("Ya")],
                      [contact("Xa"), coil("Rx")])
    assert len(found(forward, "LD133")) == 1


def test_its_severity_is_configurable():
    prog = program([contact("Rready"), coil("Ylamp")], [contact("Xstart"), coil("Rready")])
    raised = Checker().check(prog, severities=Severities({"LD133": "warning"}))
    assert [d.severity for d in raised if d.code == "LD133"] == ["warning"]
    assert not [d for d in Checker().check(prog, severities=Severities({"LD133": "off"})) if d.code == "LD133"]


# --- LD217 rungs that never do anything -------------------------------------------------


def _random_inputs(sim: Simulator, names: list[str], scans: int, seed: int = 1):
    """Run `scans` scans with random input bits; yield after each."""
    rng = random.Random(seed)
    for _ in range(scans):
        for name in names:
            if name in sim.variables():
                sim.set_input(name, rng.randint(0, 1))
        sim.step()
        yield


def test_rungs_after_a_goto_that_always_jumps():
    goto = el("GOTO", label="skip")
    first = contact("Xa")
    prog = program([goto], [first, coil("Ya")], [contact("Xb"), coil("Yb")],
                   [el("LABEL", label="skip"), contact("Xc"), coil("Yc")])
    d = one(prog, "LD217")
    assert d.span == first.span and "rungs 2 to 3 never run" in d.message and "before rung 4" in d.message
    assert [r.span for r in d.related] == [goto.span]
    sim = Simulator(prog)
    for _ in _random_inputs(sim, ["Xa", "Xb", "Xc"], 50):
        assert sim.value("Ya") == sim.value("Yb") == 0
        assert not sim.energized()[ElementKey(1, 0)]


@pytest.mark.parametrize("rungs", [
    [[contact("Xa"), el("GOTO", label="skip")], [contact("Xb"), coil("Yb")], [el("LABEL", label="skip")]],
    [[el("GOTO", label="2")], [contact("Xb"), coil("Yb")], [contact("Xc"), coil("Yc")]],
    [[contact("Xon"), el("MASTER_RELAY")], [el("GOTO", label="l")], [contact("Xb"), coil("Yb")],
     [el("LABEL", label="l")]],
    [[el("GOTO", label="l")], [el("LABEL", label="l"), contact("Xb"), coil("Yb")]],
], ids=["conditional", "to-the-next-rung-by-number", "in-a-master-relay-zone", "nothing-between"])
def test_gotos_that_skip_nothing_for_ever(rungs):
    none(program(*rungs), "LD217")


def test_a_goto_after_a_short_always_jumps_to_the_end():
    prog = program([el("SHORT"), el("GOTO", label="9")], [contact("Xb"), coil("Yb")], [contact("Xc"), coil("Yc")])
    assert "rungs 2 to 3 never run" in one(prog, "LD217").message and "the end of the program" in \
        one(prog, "LD217").message


def test_a_goto_to_a_rung_number_lands_there():
    prog = program([el("GOTO", label="3")], [contact("Xb"), coil("Yb")], [contact("Xc"), coil("Yc")])
    assert "rung 2 never runs" in one(prog, "LD217").message


def test_a_master_relay_zone_that_is_always_off():
    relay = el("MASTER_RELAY")
    prog = program([contact("Rnever"), relay], [contact("Xa"), coil("Ya")],
                   [contact("Xb"), el("TON", name="Tdelay", delay=20000), coil("Yb")],
                   [el("MASTER_RELAY")], [contact("Xc"), coil("Yc")])
    d = one(prog, "LD217")
    assert d.span == relay.span and "rungs 2 to 3 run unpowered on every scan" in d.message
    sim = Simulator(prog)
    seen_c = set()
    for _ in _random_inputs(sim, ["Xa", "Xb", "Xc"], 50):
        assert sim.value("Ya") == sim.value("Yb") == 0
        seen_c.add(sim.value("Yc"))
    assert seen_c == {0, 1}  # the zone was closed again


@pytest.mark.parametrize("rungs", [
    [[contact("Xon"), el("MASTER_RELAY")], [contact("Xa"), coil("Ya")], [el("MASTER_RELAY")]],
    # the second relay closes the always-off zone; the third opens one on an input
    [[el("OPEN"), el("MASTER_RELAY")], [el("MASTER_RELAY")], [contact("Xon"), el("MASTER_RELAY")],
     [contact("Xa"), coil("Ya")]],
    # a jump decides which relays run
    [[contact("Rnever"), el("MASTER_RELAY")], [contact("Xa"), coil("Ya")], [el("MASTER_RELAY")],
     [contact("Xb"), el("GOTO", label="1")]],
], ids=["on-an-input", "empty-zone-then-input", "with-a-jump"])
def test_master_relay_zones_that_can_be_on(rungs):
    none(program(*rungs), "LD217")


# --- LD316 a comparison that cannot change ------------------------------------------------


def test_a_comparison_with_a_value_never_written():
    compare = el("EQU", op1="mode", op2="3")
    prog = program([contact("Xm"), move("mode", 1)], [contact("Xa"), move("mode", 2)], [compare, coil("Yservice")])
    d = one(prog, "LD316")
    assert d.span == compare.span
    assert "always false" in d.message and "'mode' only ever holds 0, 1, 2" in d.message
    sim = Simulator(prog)
    for _ in _random_inputs(sim, ["Xm", "Xa"], 40):
        assert not sim.energized()[ElementKey(2, 0)]


def test_a_comparison_decided_by_the_width():
    prog = program([contact("Xa"), el("ADD", dest="small", op1="small", op2="1")],
                   [el("LEQ", op1="small", op2="127"), coil("Ya")],
                   [el("GRT", op1="small", op2="100"), coil("Yb")],
                   sizes={"small": 1})
    d = one(prog, "LD316")
    assert "LEQ [small <= 127] in rung 2 is always true" in d.message and "-128 to 127" in d.message
    sim = Simulator(prog)
    sim.set_input("Xa", 1)
    for _ in range(300):  # past the wrap-around
        sim.step()
        assert sim.value("Ya") == 1


def test_two_constants_and_a_move_that_wraps():
    assert "both operands are constants" in one(program([el("NEQ", op1="5", op2="5"), coil("Ya")]), "LD316").message
    # MOV 256 into one byte stores 0: 'b' holds only 0
    prog = program([contact("Xa"), move("b", 256)], [el("EQU", op1="b", op2="0"), coil("Ya")], sizes={"b": 1})
    assert "always true" in one(prog, "LD316").message


@pytest.mark.parametrize("rungs", [
    [[contact("Xa"), move("mode", 1)], [el("EQU", op1="mode", op2="1"), coil("Ya")]],
    [[el("READ_ADC", name="Alevel")], [el("GRT", op1="Alevel", op2="500"), coil("Ya")]],
    # nothing writes it: LD131
    [[el("EQU", op1="never", op2="0"), coil("Ya")]],
    # outside the range: LD301's
    [[contact("Xa"), el("ADD", dest="v", op1="v", op2="1")], [el("LES", op1="v", op2="40000"), coil("Ya")]],
], ids=["assigned-value", "adc", "never-written", "out-of-range-constant"])
def test_comparisons_that_can_change(rungs):
    none(program(*rungs), "LD316")


# --- LD317 a divisor that can be zero -------------------------------------------------------


def test_dividing_by_an_adc_reading():
    divide = el("DIV", dest="ticks", op1="6000", op2="Aspeed")
    prog = program([el("READ_ADC", name="Aspeed")], [divide])
    d = one(prog, "LD317")
    assert d.span == span_of(divide, "op2") and "the READ ADC in rung 1" in d.message
    sim = Simulator(prog)
    sim.set_adc("Aspeed", 0)
    with pytest.raises(SimulationError) as failure:
        sim.step()
    assert [x.code for x in failure.value.diagnostics] == ["LD610"]


def test_a_guard_in_the_rung_rules_zero_out():
    for guard in (el("NEQ", op1="Aspeed", op2="0"), el("GRT", op1="Aspeed", op2="0"),
                  el("GEQ", op1="Aspeed", op2="1"), el("LES", op1="0", op2="Aspeed")):
        prog = program([el("READ_ADC", name="Aspeed")], [guard, el("DIV", dest="t", op1="6000", op2="Aspeed")])
        none(prog, "LD317")
        sim = Simulator(prog)
        sim.set_adc("Aspeed", 0)
        sim.step(3)
    weak = program([el("READ_ADC", name="Aspeed")],
                   [el("GEQ", op1="Aspeed", op2="0"), el("DIV", dest="t", op1="6000", op2="Aspeed")])
    assert found(weak, "LD317")


def test_a_divisor_set_to_a_constant_after_the_division_starts_at_zero():
    late = program([contact("Xgo"), el("DIV", dest="q", op1="100", op2="k")], [contact("Xset"), move("k", 4)])
    assert "it starts at 0 and no MOV sets it before this DIV" in one(late, "LD317").message
    sim = Simulator(late)
    sim.set_input("Xgo", 1)
    with pytest.raises(SimulationError) as failure:
        sim.step()
    assert [x.code for x in failure.value.diagnostics] == ["LD610"]
    # a first-scan relay sets it above the division: not reported, and no division by zero
    first_scan = program([contact("Rinit", 1), move("k", 4)], [coil("Rinit", "S")],
                         [contact("Xgo"), el("DIV", dest="q", op1="100", op2="k")])
    none(first_scan, "LD317")
    sim = Simulator(first_scan)
    sim.set_input("Xgo", 1)
    sim.step(3)
    assert sim.value("q") == 25


def test_constant_divisors():
    none(program([move("k", 4)], [contact("Xa"), el("DIV", dest="q", op1="100", op2="k")]), "LD317")
    zero_moved = program([contact("Xb"), move("k", 0)], [contact("Xa"), el("MOD", dest="q", op1="100", op2="k")])
    assert "a MOV sets 'k' to 0" in one(zero_moved, "LD317").message
    literal = program([contact("Xa"), el("DIV", dest="q", op1="100", op2="0")])
    assert "divides by the constant 0" in one(literal, "LD317").message
    none(program([contact("Xa"), el("DIV", dest="q", op1="100", op2="7")]), "LD317")


# --- checked again after an edit -----------------------------------------------------------


def test_an_edit_that_adds_a_jump_is_checked_whole():
    """A backward GOTO added far from the relay changes its LD133: the
    language server's incremental check gives what a whole check gives."""
    rungs = [[el("LABEL", label="top"), contact("Rx"), coil("Ya")], [contact("Xa"), coil("Rx")],
             [contact("Xc"), coil("Yc")], [contact("Xd"), coil("Yd")]]
    before = program(*rungs)
    checker = Checker()
    assert [d.code for d in checker.check(before) if d.code == "LD133"] == ["LD133"]
    jump = program([contact("Xb"), el("GOTO", label="top")]).rungs[0]
    after = replace(before, rungs=before.rungs[:3] + [jump])
    assert checker.check(after) == check_program(after)
    assert checker.last == "whole" and not found(after, "LD133")
    plain = program([contact("Xe"), coil("Ye")]).rungs[0]
    again = replace(after, rungs=after.rungs[:2] + [plain] + after.rungs[3:])
    assert checker.check(again) == check_program(again) and checker.last == "edit"


# --- what the rules claim holds in the simulator, on random programs ---------------------------

_OPERANDS = ("v", "w", "0", "1", "3", "-128", "127")
_TESTS = {"EQU": operator.eq, "NEQ": operator.ne, "GRT": operator.gt, "GEQ": operator.ge, "LES": operator.lt,
          "LEQ": operator.le}


@st.composite
def _flow_programs(draw):
    """Small programs over a few names, where constants, moves, jumps and
    master relays meet often."""
    count = draw(st.integers(2, 7))
    rungs = []
    for _ in range(count):
        items = []
        if draw(st.integers(0, 5)) == 0:
            items.append(el("LABEL", label="L"))
        for _ in range(draw(st.integers(0, 3))):
            choice = draw(st.integers(0, 5))
            if choice <= 1:
                items.append(contact(draw(st.sampled_from(("Xa", "Xb", "Ra", "Rb", "Rnever"))), draw(st.integers(0, 1))))
            elif choice <= 3:
                items.append(el(draw(st.sampled_from(("EQU", "NEQ", "GRT", "GEQ", "LES", "LEQ"))),
                                op1=draw(st.sampled_from(_OPERANDS)), op2=draw(st.sampled_from(_OPERANDS))))
            else:
                items.append(el(draw(st.sampled_from(("SHORT", "OPEN")))))
        end = draw(st.integers(0, 6))
        if end <= 1:
            items.append(coil(draw(st.sampled_from(("Ra", "Rb", "Ya", "Yb"))), draw(st.sampled_from(" /"))))
        elif end == 2:
            items.append(move(draw(st.sampled_from(("v", "w"))), draw(st.sampled_from(("1", "2", "-5", "300")))))
        elif end == 3:
            items.append(el("ADD", dest="w", op1="w", op2="1"))
        elif end == 4:
            items.append(el("MASTER_RELAY"))
        elif end == 5:
            items.append(el("GOTO", label=str(draw(st.integers(1, count + 1)))))
        else:
            items.append(coil("Yc"))
        rungs.append(items)
    return program(*rungs, sizes={"v": 1})


_RANGE = re.compile(r"rungs? (\d+)(?: to (\d+))? (?:never runs?|runs? unpowered)")


@settings(max_examples=300, deadline=None)
@given(prog=_flow_programs(), seed=st.integers(0, 1000))
def test_what_ld217_and_ld316_claim_holds_in_the_simulator(prog, seed):
    found = check_program(prog)
    if any(d.severity == "error" for d in found):
        return
    claims = [d for d in found if d.code in ("LD217", "LD316")]
    sim = Simulator(prog)
    keys = {element.span: ElementKey(n, k) for n, rung in enumerate(prog.rungs)
            for k, element in enumerate(rung.elements())}
    dead = set()
    for d in claims:
        if d.code == "LD217":
            first, last = _RANGE.search(d.message).groups()
            dead |= set(range(int(first) - 1, int(last or first)))
    values = [{"v": 0, "w": 0}]
    try:
        for _ in _random_inputs(sim, ["Xa", "Xb"], 20, seed):
            energized = sim.energized()
            for key, on in energized.items():
                assert not (on and key.rung in dead), f"{key} ran in a rung LD217 reported"
            values.append({"v": sim.value("v") if "v" in sim.variables() else 0,
                           "w": sim.value("w") if "w" in sim.variables() else 0})
            for d in claims:
                if d.code == "LD316" and "always false" in d.message:
                    assert not energized[keys[d.span]], d.message
    except SimulationError:
        return  # a jump loop the MCU's watchdog would end: nothing to compare
    for d in claims:
        if d.code == "LD316":
            element = next(e for rung in prog.rungs for e in rung.elements() if e.span == d.span)
            result = "always true" in d.message
            for held in values:
                a, b = (held.get(op, None) if op in held else int(op) for op in
                        (element.args["op1"], element.args["op2"]))
                assert _TESTS[element.kind](a, b) == result, (d.message, held)


# --- the corpus --------------------------------------------------------------------------------

# Every hit on LDmicro's real programs, each a one-scan lag that does no harm, named in LD133's docs.
CORPUS_LAGS = {
    "manual1.ld": {"Rchatter"},
    "misc-ops.ld": {"reg0"}, "reg_tests_misc-ops.ld": {"reg0"},
    "test-i2c-2.ld": {"digit0", "digit1"}, "Tests_test-i2c-2.ld": {"digit0", "digit1"},
    "var-timer.ld": {"Rdel_input", "t_max"}, "sample_var-timer.ld": {"Rdel_input", "t_max"},
    "catalog.ld": {"var", "counter"},  # LDmicro's element catalogue: every element on default names
}


def test_the_corpus_hits():
    lags = {}
    for path in all_ld_files():
        prog, _ = ldfile.read_ld_bytes(path.read_bytes())
        found = [d for d in check_program(prog) if d.code in ("LD133", "LD217", "LD316", "LD317")]
        assert {d.code for d in found} <= {"LD133"}, (path, [d.message for d in found])
        if found:
            lags[path.name] = {d.message.split("'")[1] for d in found}
    assert lags == CORPUS_LAGS
