"""Rules about values: constants, tables, timer periods, formatted strings (LD3xx)."""

from __future__ import annotations

from builders import coil, contact, counter, el, found, move, none, one, program, span_of, timer

# --- LD301 constants out of range -----------------------------------------------------------


def test_mov_constant_too_big_for_a_one_byte_variable():
    m = move("small", 300)
    d = one(program([contact("Xa"), m], sizes={"small": 1}), "LD301")
    assert d.severity == "warning" and d.span == span_of(m, "src")
    assert "300" in d.message and "'small'" in d.message and "-128 to 127" in d.message


def test_constants_that_fit():
    prog = program([contact("Xa"), move("small", 127)], [contact("Xb"), move("small", "0xFF")],
                   [contact("Xc"), move("word", -32768)], [contact("Xd"), move("small", "'A'")],
                   sizes={"small": 1})
    none(prog, "LD301")


def test_compare_and_counter_limits():
    cmp = el("GEQ", op1="x", op2="40000")
    ctu = counter("CTU", "Cbig", 70000, init=-70000)
    prog = program([cmp, coil("Ya")], [contact("Xa"), ctu, coil("Yb")], [contact("Xb"), move("x", 1)])
    hits = found(prog, "LD301")
    assert {d.span for d in hits} == {span_of(cmp, "op2"), span_of(ctu, "max"), span_of(ctu, "init")}
    assert all(d.severity == "warning" for d in hits)
    none(program([el("GEQ", op1="x", op2="40000"), coil("Ya")], sizes={"x": 4}), "LD301")


def test_math_operand_against_destination():
    add = el("ADD", dest="b", op1="b", op2="200")
    d = one(program([contact("Xa"), add], sizes={"b": 1}), "LD301")
    assert d.span == span_of(add, "op2")


# --- LD302 shift counts ------------------------------------------------------------------------


def test_shift_count_out_of_range():
    s = el("SHL", dest="x", op1="x", op2="17")
    d = one(program([contact("Xa"), s]), "LD302")
    assert d.severity == "error" and d.span == span_of(s, "op2")
    assert "17" in d.message and "0 to 16" in d.message
    none(program([contact("Xa"), el("ROR", dest="x", op1="x", op2="16")]), "LD302")
    one(program([contact("Xa"), el("SHR", dest="b", op1="b", op2="9")], sizes={"b": 1}), "LD302")


# --- LD303 literal destination -------------------------------------------------------------------


def test_constant_as_a_destination():
    m = move("5", "x")
    d = one(program([contact("Xa"), m]), "LD303")
    assert d.severity == "error" and d.span == span_of(m, "dest")
    assert "MOV" in d.message and "'5' is not a valid destination" in d.message
    none(program([contact("Xa"), move("x", 5)]), "LD303")


# --- LD304 malformed constants --------------------------------------------------------------------


def test_bad_character_literal():
    m = move("x", "'AB'")
    d = one(program([contact("Xa"), m]), "LD304")
    assert d.severity == "error" and d.span == span_of(m, "src")
    assert "'AB'" in d.message and "MOV" in d.message


def test_bad_table_entry_and_good_constants():
    lut = el("LOOK_UP_TABLE", dest="y", index="i", values=("1", "x2", "0x1G"), table="t")
    hits = found(program([contact("Xa"), lut]), "LD304")
    assert len(hits) == 2 and all(d.span == span_of(lut, "values") for d in hits)
    assert "entry 1" in hits[0].message and "entry 2" in hits[1].message
    good = program([contact("Xa"), move("x", "'\\n'")], [contact("Xb"), move("x", "0b101")],
                   [contact("Xc"), move("x", "017")], [contact("Xd"), move("x", "-0x10")])
    none(good, "LD304")


# --- LD305-LD307 piecewise linear --------------------------------------------------------------------


def _pwl(points):
    return el("PIECEWISE_LINEAR", dest="y", index="x", points=tuple((str(a), str(b)) for a, b in points), table="t")


def test_pwl_without_points():
    p = _pwl([])
    d = one(program([contact("Xa"), p]), "LD305")
    assert d.severity == "error" and d.span == span_of(p) and "no points" in d.message
    none(program([contact("Xa"), _pwl([(0, 0), (10, 100)])]), "LD305")


def test_pwl_x_not_increasing():
    p = _pwl([(0, 0), (10, 5), (10, 7)])
    d = one(program([contact("Xa"), p]), "LD306")
    assert d.severity == "error" and d.span == span_of(p, "points")
    assert "point 2" in d.message and "strictly increasing" in d.message
    none(program([contact("Xa"), _pwl([(0, 0), (10, 5), (11, 7)])]), "LD306")


def test_pwl_segment_overflow():
    p = _pwl([(0, 0), (100, 400)])
    d = one(program([contact("Xa"), p]), "LD307")
    assert d.severity == "error" and d.span == span_of(p, "points")
    assert "40000" in d.message
    none(program([contact("Xa"), _pwl([(0, 0), (100, 300)])]), "LD307")
    one(program([contact("Xa"), _pwl([(0, 0), (128, -256)])]), "LD307")  # -32768 is out too


# --- LD308 / LD309 look-up tables ---------------------------------------------------------------------


def test_lut_without_values():
    lut = el("LOOK_UP_TABLE", dest="y", index="i", values=(), table="tab")
    d = one(program([contact("Xa"), lut]), "LD308")
    assert d.severity == "error" and d.span == span_of(lut) and "'tab'" in d.message


def test_lut_too_long():
    lut = el("LOOK_UP_TABLE", dest="y", index="i", values=tuple(str(n) for n in range(65)), table="tab")
    d = one(program([contact("Xa"), lut]), "LD309")
    assert d.severity == "error" and d.span == span_of(lut, "values") and "65 values" in d.message
    ok = el("LOOK_UP_TABLE", dest="y", index="i", values=tuple(str(n) for n in range(64)), table="tab")
    prog = program([contact("Xa"), ok])
    none(prog, "LD309")
    none(prog, "LD308")


# --- LD310-LD315 timer periods -------------------------------------------------------------------------


def test_timer_delay_zero():
    t = timer("TON", "T1", 0)
    d = one(program([contact("Xa"), t, coil("Ya")]), "LD310")
    assert d.severity == "error" and d.span == span_of(t, "delay") and "TON 'T1'" in d.message
    none(program([contact("Xa"), t, coil("Ya")]), "LD311")


def test_timer_shorter_than_the_cycle():
    t = timer("TON", "T1", 2000)
    d = one(program([contact("Xa"), t, coil("Ya")], cycle_us=10000), "LD311")
    assert d.severity == "error" and d.span == span_of(t, "delay")
    assert "2 ms" in d.message and "10 ms" in d.message
    none(program([contact("Xa"), timer("TON", "T1", 10000), coil("Ya")], cycle_us=10000), "LD311")


def test_adjust_leaves_no_delay():
    t = timer("TON", "T1", 10000, adjust=-1)  # an old 0.1 file: one cycle, adjust -1
    d = one(program([contact("Xa"), t, coil("Ya")]), "LD312")
    assert d.severity == "error" and d.span == span_of(t, "delay") and "adjust -1" in d.message
    none(program([contact("Xa"), timer("TON", "T1", 20000, adjust=-1), coil("Ya")]), "LD312")


def test_adjust_as_large_as_the_period():
    t = timer("TON", "T1", 50000, adjust=5)
    d = one(program([contact("Xa"), t, coil("Ya")]), "LD313")
    assert d.severity == "error" and "adjust 5" in d.message and "5 cycle" in d.message
    none(program([contact("Xa"), timer("TON", "T1", 50000, adjust=4), coil("Ya")]), "LD313")


def test_timer_too_long():
    t = timer("TON", "T1", 3_000_000_000)
    d = one(program([contact("Xa"), t, coil("Ya")]), "LD314")
    assert d.severity == "error" and d.span == span_of(t, "delay") and "2147483647" in d.message
    none(program([contact("Xa"), timer("TON", "T1", 2_000_000_000), coil("Ya")]), "LD314")


def test_variable_delay_is_not_checked():
    prog = program([contact("Xa"), timer("TON", "T1", "Tvar"), coil("Ya")], [contact("Xb"), move("Tvar", 5)])
    for code in ("LD310", "LD311", "LD312", "LD313", "LD314"):
        none(prog, code)


def test_timers_with_cycle_zero():
    t = timer("TON", "T1", 100000)
    d = one(program([contact("Xa"), t, coil("Ya")], [contact("Xb"), timer("TOF", "T2", 5), coil("Yb")],
                    cycle_us=0), "LD315")
    assert d.severity == "warning" and d.span == span_of(t) and "cycle time is 0" in d.message
    none(program([contact("Xa"), t, coil("Ya")], cycle_us=0), "LD311")
    none(program([contact("Xa"), coil("Ya")], cycle_us=0), "LD315")


# --- LD320-LD323 formatted strings ----------------------------------------------------------------------


def _fs(var, text):
    return el("FORMATTED_STRING", var=var, text=text)


def test_bad_escapes():
    f = _fs("", "a\\qb \\x4 \\7")
    hits = found(program([contact("Xa"), f]), "LD320")
    assert [d.span for d in hits] == [span_of(f, "text")] * 3
    assert all(d.severity == "error" for d in hits)
    text = " ".join(d.message for d in hits)
    assert "'\\q'" in text and "\\xAB" in text and "1 to 5" in text


def test_good_escapes():
    none(program([contact("Xa"), _fs("v", "v=\\-5\\r\\n\\t\\\\\\x41\\e")], [contact("Xb"), move("v", 1)]), "LD320")


def test_two_interpolations():
    f = _fs("v", "\\3 and \\-2")
    d = one(program([contact("Xa"), f], [contact("Xb"), move("v", 1)]), "LD321")
    assert d.severity == "error" and d.span == span_of(f, "text") and "2 times" in d.message
    none(program([contact("Xa"), _fs("v", "\\3")], [contact("Xb"), move("v", 1)]), "LD321")


def test_escape_without_variable_is_an_error():
    no_var = _fs("", "value \\3")
    d = one(program([contact("Xa"), no_var]), "LD322")
    assert d.severity == "error" and d.span == span_of(no_var, "text") and "names none" in d.message
    none(program([contact("Xa"), _fs("", "hello\\r\\n")]), "LD322")


def test_variable_without_escape_is_a_warning():
    # LDmicro reports it but compiles the program, which sends the text as written
    no_escape = _fs("v", "hello")
    d = one(program([contact("Xa"), no_escape], [contact("Xb"), move("v", 1)]), "LD323")
    assert d.severity == "warning" and d.span == span_of(no_escape, "var") and "'v'" in d.message
    none(program([contact("Xa"), no_escape], [contact("Xb"), move("v", 1)]), "LD322")
