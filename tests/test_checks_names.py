"""Rules about names and prefixes (LD010, LD1xx): one test that triggers each
rule and one that does not."""

from __future__ import annotations

from builders import coil, contact, counter, el, found, move, none, one, par, program, span_of, timer, words

# --- LD010 truncated name ----------------------------------------------------------


def test_truncated_name_is_an_error_at_the_operand():
    t = timer("TON", "TveryLongTimer~", 100000)
    d = one(program([contact("Xa"), t]), "LD010")
    assert d.severity == "error"
    assert d.span == span_of(t, "name")
    words(d, "TveryLongTimer~", "rung 1", "cut")


def test_truncated_label_table_and_shift_register():
    g = el("GOTO", label="somewhereFarA~")
    s = el("SHIFT_REGISTER", name="longRegist~", stages=3)
    lut = el("LOOK_UP_TABLE", dest="y", index="i", values=("1",), table="longTableNa~")
    hits = found(program([contact("Xa"), g], [contact("Xb"), s], [contact("Xc"), lut]), "LD010")
    assert {d.span for d in hits} == {span_of(g, "label"), span_of(s, "name"), span_of(lut, "table")}


def test_truncated_pin_name_and_clean_names():
    prog = program([contact("XveryLongInputN~"), coil("Yout")], pins={"XveryLongInputN~": 2})
    hits = found(prog, "LD010")
    assert len(hits) == 2
    assert {d.span for d in hits} == {prog.pins["XveryLongInputN~"].span, prog.rungs[0].circuit.items[0].arg_spans["name"]}
    none(program([contact("Xa"), coil("Yb")]), "LD010")


# --- LD101-LD107 prefixes ----------------------------------------------------------------


def test_contact_on_a_timer():
    c = contact("Tdelay")
    d = one(program([c, coil("Yout")]), "LD101")
    assert d.severity == "error" and d.span == span_of(c, "name")
    words(d, "Tdelay", "rung 1", "timer", "compare")


def test_contact_on_bits_is_fine():
    none(program([contact("Xa"), contact("Yb"), contact("Rc"), contact("Pd"), contact("Ie"),
                  contact("Mf"), coil("Yout")]), "LD101")


def test_coil_on_an_input():
    c = coil("Xbutton", "S")
    d = one(program([contact("Ra"), c]), "LD102")
    assert d.severity == "error" and d.span == span_of(c, "name")
    words(d, "set coil", "Xbutton", "input", "rung 1")
    none(program([contact("Ra"), coil("Yled", "R")]), "LD102")


def test_coil_on_a_variable():
    c = coil("count")
    d = one(program([contact("Xa"), c]), "LD103")
    assert d.severity == "error" and d.span == span_of(c, "name")
    words(d, "count", "rung 1", "Y", "R", "M")
    none(program([contact("Xa"), coil("Xin")]), "LD103")  # X has its own rule
    none(program([par([contact("Xa"), coil("Ra")], [coil("Mb")], [coil("Yc")])]), "LD103")


def test_timer_name_without_t():
    t = timer("TOF", "delay", 100000)
    d = one(program([contact("Xa"), t, coil("Yb")]), "LD104")
    assert d.severity == "warning" and d.span == span_of(t, "name")
    words(d, "TOF", "'delay'", "rung 1", "start with T")
    none(program([contact("Xa"), timer("TOF", "Tdelay", 100000), coil("Yb")]), "LD104")


def test_counter_name_without_c():
    c = counter("CTU", "parts", 10)
    d = one(program([contact("Xa"), c, coil("Yb")]), "LD105")
    assert d.severity == "warning" and d.span == span_of(c, "name")
    words(d, "CTU", "parts", "start with C")
    none(program([contact("Xa"), counter("CTU", "Cparts", 10), coil("Yb")]), "LD105")


def test_res_on_a_variable():
    r = el("RES", name="total")
    prog = program([contact("Xa"), r], [contact("Xb"), move("total", 3)])
    d = one(prog, "LD106")
    assert d.severity == "warning" and d.span == span_of(r, "name")
    words(d, "RES", "total", "MOV 0")
    none(program([contact("Xa"), counter("CTU", "Cn", 3), coil("Yb")], [contact("Xc"), el("RES", name="Cn")]),
         "LD106")


def test_set_pwm_name_without_p():
    s = el("SET_PWM", duty="50", freq=1000, name="motor")
    d = one(program([contact("Xa"), s]), "LD107")
    assert d.severity == "error" and d.span == span_of(s, "name")
    words(d, "SET PWM", "motor", "P")
    none(program([contact("Xa"), el("SET_PWM", duty="50", freq=1000, name="Pmotor")]), "LD107")


# --- LD108-LD112 names used in the wrong place --------------------------------------------


def test_a_name_written_by_mov():
    m = move("Alevel", 5)
    d = one(program([contact("Xa"), m]), "LD108")
    assert d.severity == "warning" and d.span == span_of(m, "dest")
    words(d, "MOV", "Alevel", "READ ADC")


def test_a_name_read_by_compare_and_written_by_read_adc():
    prog = program([contact("Xa"), el("READ_ADC", name="Alevel")],
                   [el("GRT", op1="Alevel", op2="512"), coil("Yhigh")])
    none(prog, "LD108")


def test_read_adc_into_a_name_without_a():
    r = el("READ_ADC", name="level")
    d = one(program([contact("Xa"), r]), "LD109")
    assert d.severity == "warning" and d.span == span_of(r, "name")
    words(d, "READ ADC", "level", "start with A")
    none(program([contact("Xa"), el("READ_ADC", name="Alevel")]), "LD109")


def test_output_name_used_as_an_integer():
    m = move("Ycount", 3)
    prog = program([contact("Xa"), m], [el("EQU", op1="Ycount", op2="3"), coil("Yb")])
    d = one(prog, "LD110")  # once per name, at the first integer use
    assert d.severity == "warning" and d.span == span_of(m, "dest")
    words(d, "Ycount", "MOV", "rung 1", "output pin")


def test_bits_as_bits_and_t_names_as_integers_are_fine():
    prog = program([contact("Xa"), timer("TON", "Tx", 100000), coil("Yb")],
                   [el("GRT", op1="Tx", op2="5"), coil("Mflag")])
    none(prog, "LD110")


def test_h_name_is_a_modbus_register():
    m = move("Hvalue", 3)
    d = one(program([contact("Xa"), m], [el("EQU", op1="Hvalue", op2="3"), coil("Yb")]), "LD111")
    assert d.severity == "warning" and d.span == span_of(m, "dest")
    words(d, "Hvalue", "Modbus holding register")
    none(program([contact("Xa"), move("value", 3)]), "LD111")


def test_quad_encoder_input_not_x():
    q = el("QUAD_ENCOD", counter="pos", a="Ra", b="XqB", z="", dir="", zkind="/")
    d = one(program([contact("Xen"), q]), "LD112")
    assert d.severity == "error" and d.span == span_of(q, "a")
    words(d, "QUAD ENCOD", "'a'", "Ra", "X (input pin)")
    ok = el("QUAD_ENCOD", counter="pos", a="XqA", b="XqB", z="", dir="YqDir", zkind="/")
    none(program([contact("Xen"), ok]), "LD112")
