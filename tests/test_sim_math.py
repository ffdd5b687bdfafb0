"""Moves and arithmetic: widths, wrap-around, overflow flag, C division,
bit operations, shifts within the operand's width, conversions, tables."""

from __future__ import annotations

import pytest
from builders import el, program

from lang.sim import SimulationError, Simulator


def compute(*elements, sizes=None, values=None) -> Simulator:
    sim = Simulator(program(*[[e] for e in elements], sizes=sizes))
    for name, value in (values or {}).items():
        sim.set_variable(name, value)
    sim.step()
    return sim


@pytest.mark.parametrize("size, a, b, result, overflow", [
    (1, 100, 27, 127, 0),
    (1, 100, 28, -128, 1),
    (2, 32767, 1, -32768, 1),
    (2, -32768, -1, 32767, 1),
    (3, 8388607, 1, -8388608, 1),
    (4, 2147483647, 1, -2147483648, 1),
    (2, 1000, 2000, 3000, 0),
])
def test_add_wraps_and_flags_signed_overflow(size, a, b, result, overflow):
    sim = compute(el("ADD", dest="d", op1="a", op2="b"), sizes={"d": size, "a": size, "b": size},
                  values={"a": a, "b": b})
    assert sim.value("d") == result and sim.value("ROverflowFlagV") == overflow


def test_overflow_flag_stays_set():
    sim = Simulator(program([el("ADD", dest="d", op1="d", op2="30000")]))
    sim.step(2)
    assert sim.value("ROverflowFlagV") == 1
    sim.step()
    assert sim.value("ROverflowFlagV") == 1


def test_sub_overflow():
    sim = compute(el("SUB", dest="d", op1="-32768", op2="1"))
    assert sim.value("d") == 32767 and sim.value("ROverflowFlagV") == 1


def test_mul_truncates_without_flag():
    sim = compute(el("MUL", dest="d", op1="300", op2="300"))
    assert sim.value("d") == (90000 & 0xFFFF) - 65536 * ((90000 & 0xFFFF) >= 32768)
    assert "ROverflowFlagV" not in sim.variables()


@pytest.mark.parametrize("a, b, q, r", [(7, 2, 3, 1), (-7, 2, -3, -1), (7, -2, -3, 1), (-7, -2, 3, -1)])
def test_division_truncates_toward_zero(a, b, q, r):
    sim = compute(el("DIV", dest="q", op1=str(a), op2=str(b)), el("MOD", dest="r", op1=str(a), op2=str(b)))
    assert (sim.value("q"), sim.value("r")) == (q, r)


def test_division_by_zero_is_a_located_error():
    div = el("DIV", dest="q", op1="5", op2="z")
    sim = Simulator(program([div]))
    with pytest.raises(SimulationError) as raised:
        sim.step()
    assert raised.value.diagnostics[0].code == "LD610"
    assert raised.value.scan == 0 and sim.scan_count == 1


def test_move_truncates_to_the_destination():
    sim = compute(el("MOVE", dest="b", src="0x1FF"), el("MOVE", dest="w", src="'A'"), sizes={"b": 1})
    assert sim.value("b") == -1 and sim.value("w") == 65


def test_literal_destination_is_an_error():
    with pytest.raises(SimulationError) as raised:
        Simulator(program([el("MOVE", dest="5", src="1")]))
    assert raised.value.diagnostics[0].code == "LD604"


def test_bitwise_and_unary():
    sim = compute(el("AND", dest="a", op1="0x0F0F", op2="0x00FF"), el("OR", dest="o", op1="0x0F00", op2="0x00F0"),
                  el("XOR", dest="x", op1="0xFF", op2="0x0F"), el("NOT", dest="n", op1="0"),
                  el("NEG", dest="m", op1="-32768"))
    assert (sim.value("a"), sim.value("o"), sim.value("x"), sim.value("n"), sim.value("m")) == \
        (0x000F, 0x0FF0, 0xF0, -1, -32768)


@pytest.mark.parametrize("kind, value, count, size, result", [
    ("SHL", 0x40, 1, 1, -128),
    ("SHL", 1, 16, 2, 0),
    ("SHR", -8, 2, 2, -2),
    ("SR0", -8, 2, 2, 0x3FFE),
    ("ROL", 0x81, 1, 1, 3),
    ("ROR", 0x0001, 1, 2, -32768),
    ("ROL", 0x1234, 4, 2, 0x2341),
])
def test_shifts_within_the_width(kind, value, count, size, result):
    sim = compute(el(kind, dest="d", op1="v", op2=str(count)), sizes={"d": size, "v": size}, values={"v": value})
    assert sim.value("d") == result


def test_shift_count_out_of_range_is_an_error():
    with pytest.raises(SimulationError):
        Simulator(program([el("SHL", dest="d", op1="v", op2="17")]))


def test_set_clear_and_test_bits():
    sim = Simulator(program(
        [el("SET_BIT", var="v", bit="3"), el("CLEAR_BIT", var="v", bit="0")],
        [el("IF_BIT_SET", var="v", bit="3"), el("IF_BIT_CLEAR", var="v", bit="n"), el("COIL", name="Yok", type=" ")],
    ))
    sim.set_variable("v", 1)
    sim.set_variable("n", 0)
    sim.step()
    assert sim.value("v") == 8 and sim.value("Yok") == 1


def test_a_bit_number_far_past_the_width_reads_the_sign_and_writes_nothing_at_once():
    sim = Simulator(program(
        [el("SET_BIT", var="v", bit="n")],
        [el("IF_BIT_SET", var="w", bit="n"), el("COIL", name="Ysign", type=" ")],
        sizes={"n": 4},
    ))
    sim.set_variable("v", 5)
    sim.set_variable("w", -1)
    sim.set_variable("n", 1_073_741_814)  # a mask of a billion bits would take seconds a scan
    sim.step(1000)
    assert sim.value("v") == 5 and sim.value("Ysign") == 1


def test_bcd_unpacked():
    sim = compute(el("BIN2BCD", dest="b", src="1234"), el("BCD2BIN", dest="n", src="0x0906"),
                  sizes={"b": 4})
    assert sim.value("b") == 0x01020304 and sim.value("n") == 96


@pytest.mark.parametrize("kind, src", [("BIN2BCD", "-1"), ("BIN2BCD", "10000"), ("BCD2BIN", "0x0A")])
def test_bcd_out_of_range_is_an_error(kind, src):
    with pytest.raises(SimulationError) as raised:
        compute(el(kind, dest="d", src=src), sizes={"d": 4})
    assert raised.value.diagnostics[0].code == "LD614"


def test_swap_and_opposite():
    sim = compute(el("SWAP", dest="s1", src="a"), el("SWAP", dest="s2", src="b"), el("SWAP", dest="s4", src="c"),
                  el("OPPOSITE", dest="o", src="a"),
                  sizes={"a": 1, "s1": 1, "c": 4, "s4": 4, "o": 1}, values={"a": 0x12, "b": 0x1234, "c": 0x01020304})
    assert (sim.value("s1"), sim.value("s2"), sim.value("s4"), sim.value("o")) == (0x21, 0x3412, 0x04030201, 0x48)


def test_random_sequence_and_seed():
    sim = Simulator(program([el("RANDOM", name="r")]))
    sim.step(2)
    seed = (69069 * 1 + 1) & 0xFFFFFFFF  # from 0: 1, then 69070
    assert sim.value("r") == (seed >> 16) - (65536 if seed >> 16 >= 32768 else 0)
    seeded = Simulator(program([el("SEED_RANDOM", name="r", seed="0")], [el("RANDOM", name="r")]))
    seeded.step()
    assert seeded.value("r") == 0  # (0 * 69069 + 1) >> 16


def test_default_srand_seed_is_fixed():
    def first() -> int:
        sim = Simulator(program([el("RANDOM", name="r")], [el("OPEN"), el("SEED_RANDOM", name="r", seed="9")]))
        sim.step()
        return sim.value("r")
    assert first() == first() == ((1 * 69069 + 1) >> 16)


def test_shift_register_moves_on_rising_edges():
    sim = Simulator(program([el("CONTACTS", name="Xclk", negated=0, set1=0),
                             el("SHIFT_REGISTER", name="reg", stages=3)]))
    sim.set_variable("reg0", 5)
    for level in "0101":
        sim.set_input("Xclk", int(level))
        sim.step()
        sim.set_variable("reg0", sim.value("reg0") + 1)
    assert (sim.value("reg0"), sim.value("reg1"), sim.value("reg2")) == (9, 8, 6)


def test_look_up_table():
    lut = el("LOOK_UP_TABLE", dest="d", index="i", values=("10", "20", "0x1E"), as_string=0, table="t")
    sim = compute(lut, values={"i": 2})
    assert sim.value("d") == 30
    sim.set_variable("i", 3)
    with pytest.raises(SimulationError) as raised:
        sim.step()
    assert raised.value.diagnostics[0].code == "LD611"


@pytest.mark.parametrize("x, y", [(0, 0), (5, 50), (10, 100), (15, 110), (20, 120), (-5, -50), (25, 77)])
def test_piecewise_linear(x, y):
    pwl = el("PIECEWISE_LINEAR", dest="y", index="x", points=(("0", "0"), ("10", "100"), ("20", "120")), table="t")
    # beyond the last point the destination keeps its value (77 here)
    sim = compute(pwl, values={"x": x, "y": 77})
    assert sim.value("y") == y


def test_piecewise_linear_must_increase():
    pwl = el("PIECEWISE_LINEAR", dest="y", index="x", points=(("0", "0"), ("0", "1")), table="t")
    with pytest.raises(SimulationError):
        Simulator(program([pwl]))


def test_seven_segments():
    sim = compute(el("7SEGMENTS", dest="c", src="v", common="C"), el("7SEGMENTS", dest="a", src="'3'", common="A"),
                  sizes={"c": 1, "a": 1}, values={"v": 7})
    assert sim.value("c") == 0x07 and sim.value("a") == (~0x4F & 0xFF) - 256
    degree = compute(el("7SEGMENTS", dest="c", src="v", common="C"), values={"v": 0xB0})
    assert degree.value("c") == 0x63 and degree.value("v") == 128  # LDmicro rewrites the source


def test_bus_permutes_bits():
    # as LDmicro's compiled code reads `BUS d s 7 6 5 4 3 2 1 0`: source bit j goes to bit b<j>
    identity = compute(el("BUS", dest="d", src="s"), values={"s": 0b00000011})
    assert identity.value("d") == 0b00000011
    reverse = {f"b{j}": 7 - j for j in range(8)}
    sim = compute(el("BUS", dest="d", src="s", **reverse), values={"s": 0b00000011})
    assert sim.value("d") == 0b11000000


def test_a_bus_bit_number_past_the_byte_sends_its_bit_nowhere():
    # LDmicro's files take any integer there; the bus is one byte (docs/semantics.md)
    bits = {"b0": 8, "b1": 300, "b2": -1}
    sim = compute(el("BUS", dest="d", src="s", **bits), values={"s": 0xFF})
    assert sim.value("d") == 0b11111000


def test_nine_fourteen_and_sixteen_segments():
    """LDmicro's fonts (display.cpp): 'A' on 14 segments lights a b c e f g1 g2;
    '0' on 16 segments a1 a2 b c d1 d2 e f and the slash j m; anode inverts."""
    sim = compute(el("14SEGMENTS", dest="c", src="v", common="C"), el("16SEGMENTS", dest="s", src="'0'", common="C"),
                  el("9SEGMENTS", dest="a", src="w", common="A"),
                  sizes={"c": 2, "s": 4, "a": 2}, values={"v": ord("A"), "w": 0xB0})
    assert sim.value("c") == 0x4077 and sim.value("s") == 0x1833F
    assert sim.value("a") == ~0x0063 and sim.value("w") == 128  # the degree sign; the source rewritten
