"""Timers, edge elements and counters, scan by scan.

The patterns reproduce the timing diagrams of the Spanish LDmicro v5.4 manual
(seeds/000_...txt, "TEMPORIZADOR ...", "DETECCION DE FLANCO ...", "CONTADOR
...") at a period of P = 3 scans (30 ms at a 10 ms cycle), and the per-type
patterns of ldmicro-formats.md §5.3. Each string is one character per scan.
"""

from __future__ import annotations

import pytest
from builders import coil, contact, el, program
from builders import par as parallel
from test_sim_helpers import drive, through

from lang.sim import Simulator


def timer(kind: str, delay: int = 30000, adjust: int = 0):
    return el(kind, name="Tt", delay=delay, adjust=adjust)


# (in, out) per timer: ldmicro-formats.md §5.3's patterns, P = 3
SPEC_PATTERNS = {
    "TON": ("01111111000000110000", "00001111000000000000"),
    "TOF": ("01111111000000110000", "01111111111000111110"),
    "RTO": ("01111111000000110000", "00001111111111111111"),
    "RTL": ("01111111000000110000", "00000000001111111111"),
    "THI": ("01111111000000110000", "01110000000000111000"),
    "TLO": ("01111111000000110000", "01111111000111110001"),
}


@pytest.mark.parametrize("kind", sorted(SPEC_PATTERNS))
def test_timer_patterns(kind):
    given, expected = SPEC_PATTERNS[kind]
    assert drive(through(timer(kind)), "Xin", given, "Yout") == expected


def test_ton_manual_diagram():
    # a long pulse turns the output on t after the rise and off with the fall;
    # a pulse shorter than t does nothing
    given = "0111111110000111000"
    assert drive(through(timer("TON")), "Xin", given, "Yout") == "0000111110000000000"


def test_tof_manual_diagram():
    # a one-scan pulse stretches to t after its fall; a gap shorter than t
    # keeps the output on
    given = "0100000000111010000000"
    assert drive(through(timer("TOF")), "Xin", given, "Yout") == "0111100000111111110000"


def test_tof_output_starts_false():
    sim = through(timer("TOF"))
    assert sim.value("Tt") == 3
    assert drive(sim, "Xin", "0000", "Yout") == "0000"


def test_rto_accumulates_pulses_until_reset():
    # t1 + t2 + ... >= t, then RES clears the output at once
    sim = Simulator(program(
        [contact("Xin"), timer("RTO"), coil("Yout")],
        [contact("Xres"), el("RES", name="Tt")],
    ))
    assert drive(sim, "Xin", "0110011000", "Yout") == "0000001111"
    sim.set_input("Xres", 1)
    sim.set_input("Xin", 0)
    sim.step()
    assert sim.value("Tt") == 0 and sim.value("Yout") == 1  # the output follows on the next evaluation
    sim.set_input("Xres", 0)
    sim.step()
    assert sim.value("Yout") == 0


def test_rtl_accumulates_low_time():
    assert drive(through(timer("RTL")), "Xin", "1101011000111", "Yout") == "0000000011111"


def test_tcy_square_wave():
    # half period P + 1 scans while the input is 1; 0 when it is 0
    given = "1" * 16 + "0000"
    assert drive(through(timer("TCY")), "Xin", given, "Yout") == "00011110000111100000"


def test_tcy_spec_one_second_is_51_scans():
    sim = through(timer("TCY", delay=500000))
    sim.set_input("Xin", 1)
    levels = []
    for _ in range(200):
        sim.step()
        levels.append(sim.value("Yout"))
    first = levels.index(1)
    assert first == 50 and levels[first:first + 52] == [1] * 51 + [0]


def test_thi_not_retriggerable():
    # a pulse of exactly t from each rising edge, re-armed only after the input was 0
    given = "0100000011111111000"
    assert drive(through(timer("THI")), "Xin", given, "Yout") == "0111000011100000000"


def test_tlo_manual_diagram():
    given = "1101111111100000011111"
    assert drive(through(timer("TLO")), "Xin", given, "Yout") == "1100011111100011111111"


def test_ton_one_second_at_10ms():
    # P = 100: the output goes true on the 101st scan with the input true
    sim = through(timer("TON", delay=1000000))
    sim.set_input("Xin", 1)
    sim.step(100)
    assert sim.value("Yout") == 0
    sim.step()
    assert sim.value("Yout") == 1 and sim.time_ms == 1010


def test_adjust_adds_cycles():
    # an LDmicro0.1 file reads as adjust -1: P = 2
    assert drive(through(timer("TON", adjust=-1)), "Xin", "011111", "Yout") == "000111"


def test_variable_delay_counts_scans():
    sim = Simulator(program([contact("Xin"), el("TON", name="Tt", delay="d", adjust=0), coil("Yout")]))
    sim.set_variable("d", 2)
    assert drive(sim, "Xin", "01111", "Yout") == "00011"


def test_timer_variable_sized_to_its_period():
    sim = through(timer("TON", delay=10_000_000))  # 1000 scans: 2 bytes
    assert sim.compiled.slots[sim.compiled.index["Tt"]].size == 2
    sim = through(timer("TON", delay=1_000_000))  # 100 scans: 1 byte
    assert sim.compiled.slots[sim.compiled.index["Tt"]].size == 1


def test_time_to_count():
    sim = Simulator(program([el("TIME2COUNT", name="n", delay=250000)]))
    sim.step()
    assert sim.value("n") == 25


# --- edges -------------------------------------------------------------------------


EDGES = {
    "OSR": ("0111001100", "0100001000"),
    "OSF": ("0111001100", "0000100010"),
    "ODR": ("0111001100", "1011110111"),  # 0 on the first scan of each rise, else 1
    "ODF": ("0111001100", "0111011101"),  # 0 on the first scan after each fall, 0 before any high
    "OSC": ("0111110110", "0101010100"),
}


@pytest.mark.parametrize("kind", sorted(EDGES))
def test_edges(kind):
    given, expected = EDGES[kind]
    assert drive(through(el(kind)), "Xin", given, "Yout") == expected


def test_osr_true_in_first_scan_gives_a_pulse():
    sim = Simulator(program([el("OSR"), coil("Yfirst")]))
    sim.step()
    assert sim.value("Yfirst") == 1
    sim.step()
    assert sim.value("Yfirst") == 0


def test_each_edge_element_has_its_own_memory():
    sim = Simulator(program(
        [contact("Xin"), el("OSR"), coil("Y1")],
        [contact("Xin"), el("OSR"), coil("Y2")],
    ))
    sim.set_input("Xin", 1)
    sim.step()
    assert (sim.value("Y1"), sim.value("Y2")) == (1, 1)


def test_toggle_coil():
    sim = Simulator(program([contact("Xin"), coil("Yt", "T")]))
    assert drive(sim, "Xin", "0110101100", "Yt") == "0111001111"


# --- counters --------------------------------------------------------------------


def counter(kind: str, limit: str, init: str = "0", edge: str = "/"):
    return el(kind, name="Cc", max=limit, init=init, kind=edge)


def test_ctu_manual_diagram():
    # CTU(3): 1, 2, 3 on rising edges, stays 3; RES -> 0, then counts again
    sim = Simulator(program(
        [contact("Xin"), counter("CTU", "3"), coil("Yout")],
        [contact("Xres"), el("RES", name="Cc")],
    ))
    counts, outs = [], []
    for level, res in zip("0100110100100000100", "0000000000000110000"):
        sim.set_input("Xin", int(level))
        sim.set_input("Xres", int(res))
        sim.step()
        counts.append(str(sim.value("Cc")))
        outs.append(str(sim.value("Yout")))
    assert "".join(counts) == "0111222333333000111"
    assert "".join(outs) == "0000000111111100000"  # RES acts after the CTU rung


def test_ctd_counts_down_to_its_limit():
    sim = Simulator(program([contact("Xin"), counter("CTD", "0", init="4"), coil("Yout")]))
    assert sim.value("Cc") == 4
    assert drive(sim, "Xin", "0101010101", "Cc") == "4332211000"
    assert sim.value("Yout") == 0


def test_ctc_wraps_with_a_one_scan_carry():
    # CTC 0:3 (the manual's CTC(3)): 1, 2, 3, 0 with the output for that scan
    sim = Simulator(program([contact("Xin"), counter("CTC", "3"), coil("Yout")]))
    assert drive(sim, "Xin", "0101010101010", "Cc") == "0112233001122"
    sim2 = Simulator(program([contact("Xin"), counter("CTC", "3"), coil("Yout")]))
    assert drive(sim2, "Xin", "0101010111010", "Yout") == "0000000100000"


def test_ctr_wraps_below_its_minimum_to_the_start_value():
    sim = Simulator(program([contact("Xin"), counter("CTR", "0", init="4"), coil("Yout")]))
    assert drive(sim, "Xin", "01010101010", "Cc") == "43322110044"
    sim2 = Simulator(program([contact("Xin"), counter("CTR", "0", init="4"), coil("Yout")]))
    assert drive(sim2, "Xin", "01010101010", "Yout") == "00000000010"


@pytest.mark.parametrize("edge, given, counts", [
    ("/", "011010", "011122"),
    ("\\", "011010", "000112"),
    ("-", "011010", "012233"),
    ("o", "011010", "111223"),
])
def test_counter_edge_kinds(edge, given, counts):
    assert drive(through(counter("CTU", "100", edge=edge)), "Xin", given, "Cc") == counts


def test_counter_true_in_first_scan_counts_once():
    sim = Simulator(program([counter("CTU", "10")]))
    sim.step(3)
    assert sim.value("Cc") == 1


def test_counter_with_variable_start_value():
    sim = Simulator(program(
        [contact("Xin"), el("CTU", name="Cc", max="10", init="start", kind="/")],
        [contact("Xres"), el("RES", name="Cc")],
    ))
    sim.set_variable("start", 5)
    assert drive(sim, "Xin", "0101", "Cc") == "5667"
    sim.set_variable("start", 2)
    sim.set_input("Xres", 1)
    sim.step()
    assert sim.value("Cc") == 2


def test_ctu_and_ctd_share_a_count():
    sim = Simulator(program(
        [contact("Xup"), counter("CTU", "10")],
        [contact("Xdown"), el("CTD", name="Cc", max="-10", init="0", kind="/")],
    ))
    drive(sim, "Xup", "010101", "Cc")
    assert sim.value("Cc") == 3
    assert drive(sim, "Xdown", "01", "Cc") == "32"


def test_ctc_level_kind_keeps_the_input_on_the_wrap():
    sim = through(counter("CTC", "2", edge="-"))
    assert drive(sim, "Xin", "11111", "Yout") == "00100"


def test_parallel_counters_see_the_same_input():
    sim = Simulator(program([contact("Xin"), parallel(counter("CTU", "5"), counter("CTU", "5"))]))
    drive(sim, "Xin", "01", "Cc")
    assert sim.value("Cc") == 2  # two elements, two edge memories, one count
