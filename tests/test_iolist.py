"""The I/O list: what `.ld` files write in IO LIST and the text form shows in
I/O ASSIGNMENT. LDmicro itself checks which names and types it takes
(test_ldmicro_saves); these are the cases LDmicro cannot show."""

from __future__ import annotations

from lang.diagnostics import ERROR
from lang.ldfile import read_ld, write_ld
from lang.loader import load_bytes
from lang.textform.writer import render_program

HEAD = "LDmicro0.2\nMICRO=Atmel AVR ATmega16 40-PDIP\n\n"
PROGRAM = "PROGRAM\nRUNG 1\n  CONTACTS Xb 0 0\n  COIL Yout 0 0 0 0\nEND\n"


def io_section(text: str) -> list[str]:
    lines = text.splitlines()
    return lines[lines.index("IO LIST") + 1:lines.index("PROGRAM") - 2]


def test_a_pin_given_to_a_name_the_program_no_longer_uses_is_kept_in_its_place():
    """LDmicro forgets it on its next save; LD411 warns about it instead, and
    the user decides."""
    program, _ = read_ld(HEAD + "IO LIST\n    Ystale at 12 0 0\n    Xb at 3 0 0\nEND\n\n" + PROGRAM)
    assert io_section(write_ld(program)) == ["    Xb at 3 0 0", "    Yout at 0 0 0", "    Ystale at 12 0 0"]


def test_a_modbus_address_without_a_pin_survives_the_text_form():
    program, _ = read_ld(HEAD + "IO LIST\n    Mflag at 0 3 40\nEND\n\n" + PROGRAM.replace("Yout", "Mflag"))
    text = render_program(program)
    assert "  Modbus Mflag: slave 3, address 40" in text.splitlines()
    assert "  Mflag                      | modbus coil        |     |       |" in text.splitlines()
    back = load_bytes(text.encode(), "x.ladder")
    assert not back.diagnostics
    assert io_section(write_ld(back.program)) == ["    Xb at 0 0 0", "    Mflag at 0 3 40"]


def test_a_modbus_address_comes_with_a_pin_in_any_order_of_the_sections():
    program, _ = read_ld(HEAD + "IO LIST\n    Xb at 3 1 2\nEND\n\n" + PROGRAM)
    text = render_program(program)
    io, settings = text.index("I/O ASSIGNMENT:"), text.index("SETTINGS:")
    moved = text[:io] + text[settings:] + "\n" + text[io:settings]
    for source in (text, moved):
        back = load_bytes(source.encode(), "x.ladder")
        assert not back.diagnostics
        assert io_section(write_ld(back.program))[0] == "    Xb at 3 1 2"


def test_a_bad_modbus_setting_is_located():
    text = render_program(read_ld(HEAD + "IO LIST\nEND\n\n" + PROGRAM)[0])
    text += "\nSETTINGS:\n  Modbus Mx: slave three\n"
    problems = [d for d in load_bytes(text.encode(), "x.ladder").diagnostics if d.severity == ERROR]
    assert [(d.span.line, d.message) for d in problems] == [
        (text.splitlines().index("  Modbus Mx: slave three"),
         "bad Modbus address 'slave three' for 'Mx': expected `Modbus NAME: slave N, address N`")]


def test_an_ldmicro01_file_lists_x_y_and_a_names_and_keeps_every_pin():
    """LDmicro's 0.1 writer would drop Pout's pin, with a warning; LDmicro
    reads the line back in either dialect."""
    text = ("LDmicro0.1\nIO LIST\n    Pout at 17\nEND\n\nPROGRAM\nRUNG\n  CONTACTS Mx 0 0\n  SET_PWM d 1000 Pout\n"
            "END\nRUNG\n  CONTACTS Xb 0 0\n  SET_PWM d 1000 Pdim\nEND\nRUNG\n  CONTACTS Xb 0 0\n  READ_ADC Apot 0\nEND\n")
    assert io_section(write_ld(read_ld(text)[0])) == ["    Xb at 0 0 0", "    Apot at 0 0 0", "    Pout at 17 0 0"]


def test_a_pin_on_a_name_ldmicro_does_not_list_is_kept_last():
    """A relay given a pin in the text form's table (LD410 reports it) is not
    in LDmicro's list (its .ld reader skips such a line); the pin the user
    wrote is kept, after every listed name."""
    text = render_program(read_ld(HEAD + "IO LIST\nEND\n\n" + PROGRAM)[0])
    lines = text.splitlines()
    table = lines.index(" ----------------------------+--------------------+-----+------+-----------")
    lines.insert(table + 1, "  Rrelay                     | int. relay         |   5 |")
    program = load_bytes("\n".join(lines).encode(), "x.ladder").program
    assert io_section(write_ld(program)) == ["    Xb at 0 0 0", "    Yout at 0 0 0", "    Rrelay at 5 0 0"]
    assert "  Rrelay                     | general var        |   5 |" in render_program(program)
