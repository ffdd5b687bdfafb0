"""Rules about the shape of rungs and the program's flow (LD2xx)."""

from __future__ import annotations

from builders import coil, contact, el, found, move, none, one, par, program, ser, span_of, timer

# --- LD201 / LD202 end-of-line instructions ------------------------------------------------


def test_coil_followed_by_a_contact():
    c = coil("Ya")
    d = one(program([contact("Xa"), c, contact("Xb")]), "LD201")
    assert d.severity == "error" and d.span == span_of(c)
    assert "coil 'Ya' in rung 1" in d.message and "contact 'Xb' follows" in d.message


def test_eol_inside_a_branch_followed_in_that_branch():
    m = move("x", 1)
    d = one(program([contact("Xa"), par([m, contact("Xb")], [contact("Xc")]), coil("Ya")]), "LD201")
    assert d.span == span_of(m) and "MOV" in d.message


def test_eol_last_everywhere_is_fine():
    prog = program([contact("Xa"), par([contact("Xb"), coil("Ya")], [move("x", 1)], [el("RES", name="C1")])])
    none(prog, "LD201")
    none(prog, "LD202")


def test_element_after_a_parallel_with_an_eol_branch():
    a = coil("Ya")
    after = contact("Xc")
    d = one(program([contact("Xa"), par([a], [contact("Xb")]), after, coil("Yb")]), "LD202")
    assert d.severity == "error" and d.span == span_of(after)
    assert "contact 'Xc' in rung 1" in d.message and "coil 'Ya'" in d.message
    assert d.related[0].span == span_of(a)


def test_parallel_without_eol_may_be_followed():
    none(program([par([contact("Xa")], [contact("Xb")]), timer("TON", "T1", 100000), coil("Ya")]), "LD202")


# --- LD203 / LD204 alone in their rung ----------------------------------------------------------


def test_comment_with_other_elements():
    c = el("COMMENT", text="hello")
    d = one(program([c, contact("Xa"), coil("Ya")]), "LD203")
    assert d.severity == "error" and d.span == span_of(c)
    assert "rung 1" in d.message and "alone" in d.message
    none(program([el("COMMENT", text="hello")], [contact("Xa"), coil("Ya")]), "LD203")


def test_subprog_not_alone():
    s = el("SUBPROG", label="init")
    prog = program([contact("Xa"), s], [el("ENDSUB", label="init")])
    d = one(prog, "LD204")
    assert d.severity == "error" and d.span == span_of(s)
    assert "SUBPROG 'init'" in d.message and "only element" in d.message
    none(program([el("SUBPROG", label="init")], [el("ENDSUB", label="init")]), "LD204")


# --- LD205 / LD206 subroutine pairs -------------------------------------------------------------


def test_subprog_without_endsub_and_endsub_without_subprog():
    s = el("SUBPROG", label="a")
    e = el("ENDSUB", label="b")
    prog = program([s], [contact("Xa"), coil("Ya")], [e])
    hits = sorted((d.span, d.message) for d in found(prog, "LD205"))
    assert [span for span, _ in hits] == [span_of(s, "label"), span_of(e, "label")]
    assert "no ENDSUB 'a'" in hits[0][1] and "no SUBPROG 'b'" in hits[1][1]


def test_endsub_before_its_subprog():
    e = el("ENDSUB", label="a")
    s = el("SUBPROG", label="a")
    hits = found(program([e], [s]), "LD205")
    assert {h.span for h in hits} == {span_of(e, "label"), span_of(s, "label")}


def test_paired_subroutine_is_fine():
    prog = program([el("SUBPROG", label="a")], [contact("Xa"), coil("Ya")], [el("ENDSUB", label="a")],
                   [contact("Xb"), el("GOSUB", label="a")])
    none(prog, "LD205")
    none(prog, "LD206")
    none(prog, "LD208")


def test_subprog_declared_twice():
    first = el("SUBPROG", label="a")
    second = el("SUBPROG", label="a")
    prog = program([first], [el("ENDSUB", label="a")], [second], [el("ENDSUB", label="b")])
    d = one(prog, "LD206")
    assert d.severity == "error" and d.span == span_of(second, "label")
    assert "already a SUBPROG 'a' in rung 1" in d.message
    assert d.related[0].span == span_of(first, "label")


# --- LD207-LD210 jumps and labels -------------------------------------------------------------------


def test_goto_to_a_missing_label():
    g = el("GOTO", label="lopp")
    d = one(program([contact("Xa"), g], [el("LABEL", label="loop")]), "LD207")
    assert d.severity == "error" and d.span == span_of(g, "label")
    assert "GOTO 'lopp'" in d.message and "did you mean 'loop'" in d.message


def test_goto_to_a_label_or_a_rung_number():
    none(program([contact("Xa"), el("GOTO", label="loop")], [el("LABEL", label="loop")],
                 [contact("Xb"), el("GOTO", label="3")]), "LD207")


def test_gosub_to_a_missing_subprog():
    g = el("GOSUB", label="nothere")
    d = one(program([contact("Xa"), g]), "LD208")
    assert d.severity == "error" and d.span == span_of(g, "label")
    assert "no SUBPROG 'nothere'" in d.message


def test_gosub_to_a_number():
    g = el("GOSUB", label="5")
    prog = program([contact("Xa"), g])
    d = one(prog, "LD209")
    assert d.severity == "error" and d.span == span_of(g, "label")
    assert "rung number" in d.message
    none(prog, "LD208")
    none(program([el("SUBPROG", label="s")], [el("ENDSUB", label="s")], [contact("Xa"), el("GOSUB", label="s")]),
         "LD209")


def test_duplicate_label():
    first, second = el("LABEL", label="top"), el("LABEL", label="top")
    d = one(program([first, contact("Xa"), coil("Ya")], [second, contact("Xb"), coil("Yb")]), "LD210")
    assert d.severity == "error" and d.span == span_of(second, "label")
    assert "already a LABEL 'top' in rung 1" in d.message and d.related[0].span == span_of(first, "label")
    none(program([el("LABEL", label="top"), contact("Xa"), coil("Ya")]), "LD210")


# --- LD211 master relay ------------------------------------------------------------------------------


def test_unclosed_master_relay_zone():
    opener = el("MASTER_RELAY")
    prog = program([contact("Xa"), el("MASTER_RELAY")], [contact("Xb"), coil("Ya")], [el("MASTER_RELAY")],
                   [contact("Xc"), opener], [contact("Xd"), coil("Yb")])
    d = one(prog, "LD211")
    assert d.severity == "warning" and d.span == span_of(opener)
    assert "rung 4" in d.message and "closes" in d.message


def test_paired_master_relays():
    none(program([contact("Xa"), el("MASTER_RELAY")], [contact("Xb"), coil("Ya")], [el("MASTER_RELAY")]), "LD211")


# --- LD212 / LD213 empty rungs ---------------------------------------------------------------------


def test_placeholder_rung():
    p = el("PLACEHOLDER")
    d = one(program([contact("Xa"), coil("Ya")], [p]), "LD212")
    assert d.severity == "error" and d.span == span_of(p)
    assert "rung 2 is empty" in d.message
    none(program([contact("Xa"), coil("Ya")]), "LD212")


def test_rung_without_elements():
    prog = program([contact("Xa"), coil("Ya")], ser())
    d = one(prog, "LD213")
    assert d.severity == "warning" and d.span == prog.rungs[1].span and "rung 2" in d.message
    none(prog, "LD212")
    none(program([contact("Xa"), coil("Ya")]), "LD213")


def test_more_rungs_than_ldmicro_loads_is_the_same_warning_in_both_formats(tmp_path):
    from lang.loader import load_file
    from lang.textform.writer import render_program

    big = program(*[[contact("Xa"), coil("Ra")] for _ in range(10000)])
    source = tmp_path / "big.ladder"
    source.write_text(render_program(big), encoding="utf-8")
    loaded = load_file(source)
    from lang.checks import check_program

    found_in_text = [d for d in check_program(loaded.program) if d.code == "LD214"]
    assert len(found_in_text) == 1 and found_in_text[0].severity == "warning"
    none(program(*[[contact("Xa"), coil("Ra")] for _ in range(9999)]), "LD214")
