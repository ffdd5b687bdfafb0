"""`ladder check` reports a program too large for its part's flash (LD703)
or RAM (LD704), from the same compile as `ladder build`, at the same place:
the part's name in the file. ATmega8: 8 KB of flash, 1 KB of RAM."""

from __future__ import annotations

from builders import contact, el, move, program

from ladder.cli import main
from lang.model import PinAssignment
from lang.textform.writer import render_program

M8 = "Atmel AVR ATmega8 28-PDIP"


def _file(tmp_path, prog, sizes: dict[str, int]):
    prog.settings.mcu = M8
    prog.pins = {"Xa": PinAssignment("Xa", "PD2")}
    prog.var_sizes.update(sizes)
    path = tmp_path / "big.ladder"
    path.write_text(render_program(prog), encoding="utf-8")
    return path


def _lines(capsys, *argv) -> tuple[int, list[str]]:
    status = main(list(argv))
    return status, capsys.readouterr().out.splitlines()


def _part_line(path) -> int:
    """The 1-based line that names the part (the export header's second line)."""
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if M8 in line)


def test_flash_the_part_does_not_have(tmp_path, capsys):
    rungs = [[contact("Xa"), el("MUL", dest=f"v{i}", op1=f"w{i % 100}", op2="1000")] for i in range(700)]
    path = _file(tmp_path, program(*rungs), {f"v{i}": 1 for i in range(700)} | {f"w{i}": 1 for i in range(100)})
    status, checked = _lines(capsys, "check", str(path))
    assert status == 1
    [line] = [line for line in checked if " LD703 " in line]
    assert line.startswith(f"{path}:{_part_line(path)}:") and "error LD703" in line and "8192" in line
    status, built = _lines(capsys, "build", str(path), "-o", str(tmp_path / "big.hex"))
    assert status == 1 and line in built
    assert not (tmp_path / "big.hex").exists()


def test_ram_the_part_does_not_have(tmp_path, capsys):
    path = _file(tmp_path, program(*[[contact("Xa"), move(f"v{i}", 1)] for i in range(300)]),
                 {f"v{i}": 4 for i in range(300)})
    status, checked = _lines(capsys, "check", str(path))
    assert status == 1
    [line] = [line for line in checked if " LD704 " in line]
    status, built = _lines(capsys, "build", str(path), "-o", str(tmp_path / "big.hex"))
    assert line in built


def test_a_program_that_fits_is_clean(tmp_path, capsys):
    path = _file(tmp_path, program(*[[contact("Xa"), move(f"v{i}", 1)] for i in range(30)]),
                 {f"v{i}": 4 for i in range(30)})
    status, checked = _lines(capsys, "check", str(path))
    assert status == 0 and not [line for line in checked if " LD70" in line]


def test_no_compile_when_the_checks_found_errors(tmp_path, capsys):
    # 300 4-byte variables do not fit, but a timer without a delay (LD310) is an error the build
    # would stop on first: the check reports it and does not compile
    rungs = [[contact("Xa"), move(f"v{i}", 1)] for i in range(300)]
    rungs.append([contact("Xa"), el("TON", name="Tbad", delay=0)])
    path = _file(tmp_path, program(*rungs), {f"v{i}": 4 for i in range(300)})
    status, checked = _lines(capsys, "check", str(path))
    assert status == 1
    assert [line for line in checked if " LD310 " in line] and not [line for line in checked if " LD704 " in line]
