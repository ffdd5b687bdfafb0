"""How names are used across the program: LDmicro's CheckVariableNames
(LD120-LD125, order dependent) and names read but never written (LD130, LD131)."""

from __future__ import annotations

from builders import coil, contact, counter, el, found, move, none, one, program, span_of, timer

# --- LD120 two timers, one name -------------------------------------------------------


def test_ton_then_tof_on_one_name():
    first = timer("TON", "T1", 100000)
    second = timer("TOF", "T1", 100000)
    d = one(program([contact("Xa"), first, coil("Ya")], [contact("Xb"), second, coil("Yb")]), "LD120")
    assert d.severity == "error"
    assert d.span == span_of(second, "name")
    assert "TOF: variable can only be used for RES elsewhere" in d.message
    assert "TON timer of rung 1" in d.message and "rung 2" in d.message
    assert [r.span for r in d.related] == [span_of(first, "name")]


def test_two_tons_on_one_name():
    d = one(program([contact("Xa"), timer("TON", "T1", 100000), coil("Ya")],
                    [contact("Xb"), timer("TON", "T1", 200000), coil("Yb")]), "LD120")
    assert "also the TON timer of rung 1" in d.message


def test_rto_with_its_res_is_fine():
    prog = program([contact("Xa"), timer("RTO", "T1", 100000), coil("Ya")],
                   [contact("Xr"), el("RES", name="T1")])
    for code in ("LD120", "LD121", "LD122", "LD125"):
        none(prog, code)


# --- LD121 / LD122 order dependence -----------------------------------------------------


def test_mov_before_a_timer_fails_at_the_timer():
    m = move("T1", 0)
    t = timer("RTO", "T1", 100000)
    d = one(program([contact("Xa"), m], [contact("Xb"), t, coil("Yb")]), "LD121")
    assert d.severity == "error" and d.span == span_of(t, "name")
    assert "MOV in rung 1" in d.message and "RES" in d.message
    assert d.related[0].span == span_of(m, "dest")
    none(program([contact("Xa"), m], [contact("Xb"), t, coil("Yb")]), "LD122")


def test_mov_after_rto_passes_but_after_ton_fails():
    after_rto = program([contact("Xb"), timer("RTO", "T1", 100000), coil("Yb")], [contact("Xa"), move("T1", 0)])
    for code in ("LD120", "LD121", "LD122"):
        none(after_rto, code)
    m = move("T1", 0)
    after_ton = program([contact("Xb"), timer("TON", "T1", 100000), coil("Yb")], [contact("Xa"), m])
    d = one(after_ton, "LD122")
    assert d.severity == "error" and d.span == span_of(m, "dest")
    assert "TON timer of rung 1" in d.message
    assert "TON: variable can only be used for RES elsewhere" in d.message


def test_compare_reads_of_a_timer_are_fine():
    prog = program([contact("Xb"), timer("TON", "T1", 100000), coil("Yb")],
                   [el("GRT", op1="T1", op2="5"), coil("Yc")])
    none(prog, "LD122")


def test_counter_and_mov_share_a_name():
    prog = program([contact("Xa"), counter("CTU", "C1", 5), coil("Ya")],
                   [contact("Xb"), counter("CTD", "C1", 0), coil("Yb")],
                   [contact("Xc"), move("C1", 3)])
    for code in ("LD120", "LD121", "LD122", "LD123", "LD124"):
        none(prog, code)


# --- LD123 PWM, LD124 table -----------------------------------------------------------------


def test_set_pwm_on_a_name_a_mov_wrote():
    s = el("SET_PWM", duty="50", freq=1000, name="Pout")
    d = one(program([contact("Xa"), move("Pout", 1)], [contact("Xb"), s]), "LD123")
    assert d.severity == "error" and d.span == span_of(s, "name")
    assert "MOV in rung 1" in d.message
    two = program([contact("Xa"), el("SET_PWM", duty="20", freq=1000, name="Pout")],
                  [contact("Xb"), el("SET_PWM", duty="50", freq=1000, name="Pout")],
                  [contact("Xc"), el("RES", name="Pout")])
    none(two, "LD123")
    none(two, "LD125")


def test_table_name_used_as_a_variable():
    lut = el("LOOK_UP_TABLE", dest="out", index="i", values=("1", "2"), table="tab")
    d = one(program([contact("Xa"), move("tab", 1)], [contact("Xb"), move("i", 0)], [contact("Xc"), lut]), "LD124")
    assert d.severity == "error" and d.span == span_of(lut, "table")
    assert "'tab'" in d.message and "MOV in rung 1" in d.message
    same = el("LOOK_UP_TABLE", dest="out2", index="i", values=("1", "2"), table="tab")
    none(program([contact("Xb"), move("i", 0)], [contact("Xc"), lut], [contact("Xd"), same]), "LD124")


# --- LD125 RES on nothing ----------------------------------------------------------------------


def test_res_on_a_name_nothing_else_uses():
    r = el("RES", name="Ctypo")
    prog = program([contact("Xa"), counter("CTU", "Cparts", 5), coil("Ya")], [contact("Xb"), r])
    d = one(prog, "LD125")
    assert d.severity == "error" and d.span == span_of(r, "name")
    assert "Ctypo" in d.message and "rung 2" in d.message
    none(program([contact("Xa"), counter("CTU", "Cparts", 5), coil("Ya")], [contact("Xb"), el("RES", name="Cparts")]),
         "LD125")


# --- LD130 / LD131 read but never written ---------------------------------------------------


def test_relay_read_never_written():
    c = contact("Rready")
    prog = program([c, coil("Ya")], [contact("Rready", 1), coil("Yb")])
    d = one(prog, "LD130")
    assert d.severity == "warning" and d.span == span_of(c, "name")
    assert "Rready" in d.message and "rung 1" in d.message
    none(program([contact("Xa"), coil("Rready")], [contact("Rready"), coil("Yb")]), "LD130")
    none(program([el("GRT", op1="x", op2="1"), coil("ROverflowFlagV")]), "LD130")
    none(program([contact("ROverflowFlagV"), coil("Yerr")]), "LD130")


def test_variable_read_never_written():
    g = el("GRT", op1="speed", op2="100")
    d = one(program([g, coil("Yfast")]), "LD131")
    assert d.severity == "warning" and d.span == span_of(g, "op1")
    assert "'speed'" in d.message and "GRT" in d.message and "rung 1" in d.message
    written = program([g, coil("Yfast")], [contact("Xa"), move("speed", 3)])
    none(written, "LD131")


def test_read_never_written_exemptions():
    prog = program(
        [contact("Xin"), contact("Iremote"), coil("Yout")],
        [el("EQU", op1="Hreg", op2="#PINB"), el("EQU", op1="$scratch", op2="1"), coil("Yb")],
        [contact("Rnever"), coil("Yc")],  # LD130's business
        [contact("Xa"), timer("TON", "Tt", 100000), coil("Yd")],
        [el("GRT", op1="Tt", op2="3"), coil("Ye")],
    )
    none(prog, "LD131")


def test_shift_register_first_stage_must_be_written():
    s = el("SHIFT_REGISTER", name="reg", stages=4)
    d = one(program([contact("Xa"), s], [el("EQU", op1="reg3", op2="1"), coil("Yb")]), "LD131")
    assert "'reg0'" in d.message
    fine = program([contact("Xa"), move("reg0", 1)], [contact("Xa"), s], [el("EQU", op1="reg3", op2="1"), coil("Yb")])
    assert not found(fine, "LD131")
