"""What the UART sends, seen: `ladder sim --watch uart` (its lines, plot and
VCD), the messages they are made of, and `expect uart` giving the same
verdicts on the simulator and on every compiled target, every expectation
of a scenario reported even when others fail or the run stops."""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree

import pytest
from corpus import CORPUS
from test_compiler_harness import IN_CI

from compiler.run import c as c_run
from compiler.run import gpsim
from compiler.run import simavr as sa
from ladder.cli import main
from lang.sim.uart import Messages, SentByte, messages, show_bytes

SAMPLES = CORPUS / "ldmicro" / "sample"
HELLO = SAMPLES / "hello.ld"  # ATmega8, 9600 baud, 10 ms cycle: "Hello, world:     N\r\n" every second


def run(capsys, *argv) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


# --- messages -------------------------------------------------------------------------------

BYTE_US = 1e7 / 9600  # a frame at 9600 baud


def test_bytes_sent_back_to_back_are_one_message_up_to_a_line_end():
    # one character a 10 ms scan: each starts within a cycle of the frame before it ending
    sent = [SentByte(10_000 * i, 10_000 * i, b) for i, b in enumerate(b"OK\r\nNO")]
    assert [(m.scan_us, bytes(m.data)) for m in messages(sent, BYTE_US, 10_000)] == \
        [(0, b"OK\r\n"), (40_000, b"NO")]


def test_a_pause_longer_than_a_cycle_ends_a_message():
    sent = [SentByte(0, 0, ord("a")), SentByte(10_000, 10_000, ord("b")), SentByte(30_000, 30_000, ord("c"))]
    assert [bytes(m.data) for m in messages(sent, BYTE_US, 10_000)] == [b"ab", b"c"]


def test_a_stream_that_never_ends_a_line_shows_80_bytes_a_message():
    sent = [SentByte(10_000 * i, 10_000 * i, ord("x")) for i in range(170)]
    assert [len(m.data) for m in messages(sent, BYTE_US, 10_000)] == [80, 80, 10]


def test_a_message_is_complete_once_no_byte_of_the_next_scan_can_join_it():
    grouping = Messages(BYTE_US, 10_000)
    assert grouping.add(SentByte(0, 0, ord("a"))) == []
    assert grouping.idle(10_000) == []  # the scan at 10 ms may still send the next one
    assert [bytes(m.data) for m in grouping.idle(20_000)] == [b"a"]
    assert grouping.close() == []


def test_bytes_show_as_a_scenario_writes_them():
    assert show_bytes(b'Hi "x"\\\r\n\x00\x1b\x0c\xe9') == '"Hi \\"x\\"\\\\\\r\\n\\0\\e\\x0C\\xE9"'
    assert show_bytes(b"") == "nothing"


# --- ladder sim -------------------------------------------------------------------------------

def test_sim_watch_uart_prints_a_line_a_message_at_its_first_bytes_time(capsys):
    status, out, _ = run(capsys, "sim", str(HELLO), "--for", "2.5s", "--watch", "uart,Rosc")
    assert status == 0
    assert out.splitlines() == [
        "0 Rosc 1", '0 uart "Hello, world:      1\\r\\n"',
        "1000 Rosc 0",
        "1010 Rosc 1", '1010 uart "Hello, world:      2\\r\\n"',
        "2010 Rosc 0",
        "2020 Rosc 1", '2020 uart "Hello, world:      3\\r\\n"']


def test_sim_watches_the_uart_by_default_when_the_program_sends(capsys):
    _, out, _ = run(capsys, "sim", str(HELLO), "--for", "500ms")
    assert '0 uart "Hello, world:      1\\r\\n"' in out.splitlines()
    _, out, _ = run(capsys, "sim", str(SAMPLES / "traffic.ld"), "--for", "500ms")
    assert "uart" not in out


def test_a_message_cut_by_the_end_of_the_run_is_printed_as_far_as_it_went(capsys):
    _, out, _ = run(capsys, "sim", str(HELLO), "--cycles", "5", "--watch", "uart")
    assert out.splitlines() == ['0 uart "Hello"']


def test_plot_shows_the_messages_and_vcd_the_bytes_on_an_8_bit_wire(capsys, tmp_path):
    vcd = tmp_path / "hello.vcd"
    status, out, _ = run(capsys, "sim", str(HELLO), "--for", "1.2s", "--watch", "uart", "--plot",
                         "--vcd", str(vcd))
    assert status == 0
    plot = out.splitlines()[-2:]
    assert plot[0].startswith("time (ms)")
    assert plot[1].startswith('uart      "Hello, world:') and '"Hello' in plot[1][20:]
    text = vcd.read_text()
    assert '$var wire 8 ! uart $end' in text
    lines = text.splitlines()
    # 'H' from 0 to its frame's end (1042 us), then idle until 'e' at 10 ms
    assert lines[lines.index("$end") + 1:lines.index("$end") + 6] == \
        ["b01001000 !", "#1042", "bzzzzzzzz !", "#10000", "b01100101 !"]


# --- every expectation reported -------------------------------------------------------------

def test_a_stopped_simulation_lists_each_expectation_it_leaves_unchecked(capsys, tmp_path):
    program = tmp_path / "div.ld"
    program.write_text("LDmicro0.2\nCYCLE=10000\n\nPROGRAM\nRUNG\n  CONTACTS Xgo 0\n  DIV q 1 z\nEND\n"
                       "RUNG\n  CONTACTS Xgo 0\n  COIL Yon 0 0 0\nEND\n", encoding="ascii")
    scenario = tmp_path / "div.scn"
    scenario.write_text("program div.ld\n"
                        "scenario a division by zero at 50 ms\n"
                        "at 0 expect Yon = 0\n"
                        "at 50 ms set Xgo = 1\n"
                        "from 0 to 100 ms expect Yon = 0\n"
                        "sometime from 0 to 20 ms expect Yon = 0\n"
                        "at 45 ms expect Yon = 1\n"
                        "at 40 ms expect Yon = 1\n", encoding="utf-8")
    status, out, _ = run(capsys, "test", str(scenario))
    assert status == 1
    assert f"{scenario}:2: at 50 ms: the simulation stopped: error LD610 division by zero" in out
    assert f"{scenario}:5: at 50 ms: Yon: not checked (Yon = 0): the simulation stopped at 50 ms" in out
    assert f"{scenario}:7: at 50 ms: Yon: not checked (Yon = 1): the simulation stopped at 50 ms" in out
    assert f"{scenario}:8: at 40 ms: Yon: expected Yon = 1, got 0" in out
    assert f"{scenario}:3:" not in out and f"{scenario}:6:" not in out  # decided, and held


def _mixed(tmp_path: Path, mcu: str) -> Path:
    """hello.ld for `mcu`, and a scenario whose UART expectations fail
    before and between ones that hold or fail for other reasons."""
    program = tmp_path / "hello.ld"
    program.write_text(HELLO.read_text(encoding="ascii").replace("Atmel AVR ATmega8 28-PDIP", mcu), encoding="ascii")
    scenario = tmp_path / "mixed.scn"
    scenario.write_text("program hello.ld\n"
                        "at 500 ms expect uart \"Hello\"\n"
                        "at 500 ms expect uart \"Hello, world:      1\\r\\n\"\n"
                        "at 1.5 s expect uart contains \"world:      3\"\n"
                        "at 1.5 s expect Rosc = 0\n"
                        "sometime from 1 s to 1.2 s expect uart contains \"world:      2\"\n", encoding="utf-8")
    return scenario


MIXED_FAILURES = [
    '2: at 500 ms: uart: expected UART output "Hello", got "Hello, world:      1\\r\\n"',
    '4: at 1500 ms: uart: expected UART output containing "world:      3", got "Hello, world:      1\\r\\n'
    'Hello, world:      2\\r\\n"',
    "5: at 1500 ms: Rosc: expected Rosc = 0, got 1",
]

needs_simavr = pytest.mark.skipif(not sa.available() and not IN_CI, reason="gcc + libsimavr-dev not installed")
needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")
needs_cc = pytest.mark.skipif(not c_run.available(), reason="no C compiler (Debian: gcc)")


@pytest.mark.parametrize("target", [
    pytest.param(None, id="sim"),
    pytest.param("c", marks=needs_cc, id="c"),
    pytest.param("avr", marks=[needs_simavr, pytest.mark.slow], id="avr"),
    pytest.param("pic16", marks=[needs_gpsim, pytest.mark.slow], id="pic16"),
])
def test_uart_expectations_give_the_same_verdicts_everywhere_and_hide_nothing(target, capsys, tmp_path):
    mcu = "Microchip PIC16F877 40-PDIP" if target == "pic16" else "Atmel AVR ATmega8 28-PDIP"
    scenario = _mixed(tmp_path, mcu)
    junit = tmp_path / "results.xml"
    status, out, _ = run(capsys, "test", str(scenario), "--junit", str(junit), *(["--on", target] if target else []))
    assert status == 1
    failures = [line.strip()[len(str(scenario)) + 1:] for line in out.splitlines()
                if line.strip().startswith(f"{scenario}:")]
    assert failures == MIXED_FAILURES, out
    failure = ElementTree.parse(junit).getroot()[0][0][0]
    assert failure.tag == "failure" and failure.get("message").endswith("(and 2 more)")
    assert [line for line in failure.text.splitlines() if line.startswith(str(scenario))] == \
        [f"{scenario}:{text}" for text in MIXED_FAILURES]
