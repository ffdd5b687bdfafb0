"""Power flow (series, parallel, order effects), no I/O image, master relay,
GOTO/LABEL, subroutines and their error cases."""

from __future__ import annotations

import pytest
from builders import coil, contact, el, program
from builders import par as parallel
from builders import ser as series

from lang.sim import ElementKey, SimulationError, Simulator


def test_no_input_output_image_later_rungs_see_new_values():
    sim = Simulator(program([contact("Xa"), coil("R1")], [contact("R1"), coil("Y1")]))
    sim.set_input("Xa", 1)
    sim.step()
    assert sim.value("Y1") == 1  # the same scan


def test_earlier_rung_sees_the_value_on_the_next_scan():
    sim = Simulator(program([contact("R1"), coil("Y1")], [contact("Xa"), coil("R1")]))
    sim.set_input("Xa", 1)
    sim.step()
    assert sim.value("Y1") == 0
    sim.step()
    assert sim.value("Y1") == 1


def test_parallel_branches_see_the_same_input_and_earlier_side_effects():
    # branch 1 sets R1; branch 2 reads it in the same scan; both get the parallel's input
    sim = Simulator(program([contact("Xa"), parallel(coil("R1", "S"), series(contact("R1"), coil("Y2")),
                                                     series(contact("R1", negated=1), coil("Y3")))]))
    sim.set_input("Xa", 1)
    sim.step()
    assert (sim.value("R1"), sim.value("Y2"), sim.value("Y3")) == (1, 1, 0)


def test_parallel_is_or_of_branches():
    sim = Simulator(program([parallel(contact("Xa"), contact("Xb")), contact("Xc"), coil("Y")]))
    for a, b, c in [(0, 0, 1), (1, 0, 1), (0, 1, 1), (1, 1, 0)]:
        sim.set_input("Xa", a)
        sim.set_input("Xb", b)
        sim.set_input("Xc", c)
        sim.step()
        assert sim.value("Y") == ((a or b) and c)


def test_lower_coil_in_parallel_wins():
    # sample/coil_s_r_n.ld rung 2: a normal and an inverted coil on one relay
    sim = Simulator(program([contact("Xa"), parallel(coil("Rnew"), coil("Rnew", "/"))]))
    sim.set_input("Xa", 1)
    sim.step()
    assert sim.value("Rnew") == 0
    sim.set_input("Xa", 0)
    sim.step()
    assert sim.value("Rnew") == 1


def test_set_reset_latch_last_write_wins():
    sim = Simulator(program([contact("Xs"), coil("Y", "S")], [contact("Xr"), coil("Y", "R")]))
    sim.set_input("Xs", 1)
    sim.set_input("Xr", 1)
    sim.step()
    assert sim.value("Y") == 0
    sim.set_input("Xr", 0)
    sim.step()
    sim.set_input("Xs", 0)
    sim.step()
    assert sim.value("Y") == 1


def test_set1_input_starts_high():
    sim = Simulator(program([contact("Xup", set1=1), coil("Y")]))
    assert sim.value("Xup") == 1
    sim.step()
    assert sim.value("Y") == 1


def test_master_relay_switches_off_the_zone():
    sim = Simulator(program(
        [contact("Xenable"), el("MASTER_RELAY")],
        [contact("Xa"), coil("Y1")],
        [contact("Xa"), el("TON", name="Tt", delay=30000, adjust=0), coil("Y2")],
        [el("MASTER_RELAY")],
        [contact("Xa"), coil("Y3")],
    ))
    sim.set_input("Xa", 1)
    sim.step(5)
    assert (sim.value("Y1"), sim.value("Y2"), sim.value("Y3")) == (0, 0, 1)
    sim.set_input("Xenable", 1)
    sim.step(3)
    assert (sim.value("Y1"), sim.value("Y2")) == (1, 0)
    sim.step()
    assert sim.value("Y2") == 1
    sim.set_input("Xenable", 0)
    sim.step()
    assert (sim.value("Y1"), sim.value("Y2"), sim.value("Tt"), sim.value("Y3")) == (0, 0, 0, 1)


def test_goto_skips_rungs_which_keep_their_state():
    sim = Simulator(program(
        [contact("Xjump"), el("GOTO", label="skip")],
        [contact("Xa"), coil("Y1")],
        [el("LABEL", label="skip"), contact("Xa"), coil("Y2")],
    ))
    sim.set_input("Xa", 1)
    sim.step()
    sim.set_input("Xjump", 1)
    sim.set_input("Xa", 0)
    sim.step()
    assert (sim.value("Y1"), sim.value("Y2")) == (1, 0)  # jumps at once, not a scan late
    assert sim.energized()[ElementKey(1, 0)] is False  # skipped in the last scan


def test_goto_rung_number_and_end_of_scan():
    sim = Simulator(program(
        [el("GOTO", label="3")],
        [coil("Y1")],
        [coil("Y2")],
    ))
    sim.step()
    assert (sim.value("Y1"), sim.value("Y2")) == (0, 1)
    end = Simulator(program([el("GOTO", label="99")], [coil("Y1")]))
    end.step()
    assert end.value("Y1") == 0


def test_backward_goto_loops_within_a_scan():
    sim = Simulator(program(
        [el("LABEL", label="top"), el("ADD", dest="n", op1="n", op2="1")],
        [el("LES", op1="n", op2="10"), el("GOTO", label="top")],
    ))
    sim.step()
    assert sim.value("n") == 10


def test_runaway_loop_is_an_error():
    sim = Simulator(program([el("LABEL", label="top")], [el("GOTO", label="top")]))
    with pytest.raises(SimulationError) as raised:
        sim.step()
    assert raised.value.diagnostics[0].code == "LD612"


def test_missing_label_is_a_located_error():
    goto = el("GOTO", label="nowhere")
    with pytest.raises(SimulationError) as raised:
        Simulator(program([goto]))
    assert raised.value.diagnostics[0].code == "LD603"


def test_a_label_twice_and_a_subroutine_without_end_are_located_errors():
    second, unended = el("LABEL", label="top"), el("SUBPROG", label="sub")
    with pytest.raises(SimulationError) as raised:
        Simulator(program([el("LABEL", label="top")], [second], [unended], [el("GOTO", label="top")]))
    found = [(d.code, d.message, d.span) for d in raised.value.diagnostics]
    assert found == [("LD603", "LABEL: only one LABEL 'top' is allowed", second.span),
                     ("LD603", "SUBPROG: ENDSUB 'sub' not found", unended.span)]


def test_labels_without_a_jump_are_not_checked():
    """Nothing jumps: a repeated LABEL changes nothing (the checks warn of it)."""
    sim = Simulator(program([el("LABEL", label="top")], [el("LABEL", label="top")]))
    sim.step()


def subroutine_program(*calls):
    return program(
        *calls,
        [el("SUBPROG", label="twice")],
        [el("ADD", dest="n", op1="n", op2="1")],
        [el("ADD", dest="n", op1="n", op2="1")],
        [el("ENDSUB", label="twice")],
        [coil("Yafter")],
    )


def test_gosub_runs_the_subroutine_and_returns_mid_rung():
    sim = Simulator(subroutine_program(
        [contact("Xcall"), parallel(el("GOSUB", label="twice"), coil("Ycalled"))],
    ))
    sim.step()
    assert (sim.value("n"), sim.value("Ycalled"), sim.value("Yafter")) == (0, 0, 1)
    sim.set_input("Xcall", 1)
    sim.step()
    assert (sim.value("n"), sim.value("Ycalled"), sim.value("Yafter")) == (2, 1, 1)


def test_return_leaves_early():
    sim = Simulator(program(
        [el("GOSUB", label="s")],
        [el("SUBPROG", label="s")],
        [el("ADD", dest="n", op1="n", op2="1")],
        [contact("Xstop"), el("RETURN")],
        [el("ADD", dest="n", op1="n", op2="10")],
        [el("ENDSUB", label="s")],
    ))
    sim.step()
    assert sim.value("n") == 11
    sim.set_input("Xstop", 1)
    sim.step()
    assert sim.value("n") == 12


def test_gosub_stack_overflow():
    sim = Simulator(program(
        [el("GOSUB", label="r")],
        [el("SUBPROG", label="r")],
        [el("GOSUB", label="r")],
        [el("ENDSUB", label="r")],
    ))
    with pytest.raises(SimulationError) as raised:
        sim.step()
    assert raised.value.diagnostics[0].code == "LD613"


def test_return_without_call_underflows():
    sim = Simulator(program([el("RETURN")]))
    with pytest.raises(SimulationError) as raised:
        sim.step()
    assert "underflow" in raised.value.diagnostics[0].message


def test_comment_rungs_are_skipped():
    sim = Simulator(program([el("COMMENT", text="hello")], [coil("Y")]))
    sim.step()
    assert sim.value("Y") == 1


def test_lock_stops_the_simulation():
    sim = Simulator(program([contact("Xa"), el("LOCK")]))
    sim.step()
    sim.set_input("Xa", 1)
    with pytest.raises(SimulationError) as raised:
        sim.step()
    assert raised.value.diagnostics[0].code == "LD615"


def test_delay_does_not_move_time():
    sim = Simulator(program([el("DELAY", delay="5000"), coil("Y")]))
    sim.step(2)
    assert sim.time_ms == 20 and sim.value("Y") == 1


def test_energized_shows_a_jump_that_was_taken():
    sim = Simulator(program([contact("Xjump"), el("GOTO", label="end")], [coil("Y")],
                            [el("LABEL", label="end")]))
    sim.set_input("Xjump", 1)
    sim.step()
    powered = sim.energized()
    assert powered[ElementKey(0, 1)] is True and powered[ElementKey(1, 0)] is False
