"""LDmicro 5.4.1.1 itself is the oracle of the `.ld` round trip: each corpus
file, loaded and saved by LDmicro (tests/ldmicro/build-save.sh adds the batch
command `/s IN OUT` to it and installs it at /opt/ldmicro-save, or
LDMICRO_SAVE=), then taken through `.ld -> .ladder -> .ld`, must come back as
LDmicro saved it, byte for byte."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest
from corpus import all_ld_files
from test_ldfile_bytes import rel, through_the_text_form

pytestmark = pytest.mark.ldmicro

SAVER = Path(os.environ.get("LDMICRO_SAVE", "/opt/ldmicro-save/ldmicro.exe"))


def saved_by_ldmicro(path: Path, scratch: Path) -> bytes:
    if not SAVER.exists():
        pytest.fail(f"LDmicro with its save command is not installed at {SAVER}: run tests/ldmicro/build-save.sh")
    shutil.copyfile(path, scratch / "prog.ld")
    env = {key: value for key, value in os.environ.items() if key not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env.update(WINEPREFIX=str(SAVER.parent / "wineprefix"), WINEDLLOVERRIDES="mscoree,mshtml=", WINEDEBUG="-all",
               LC_ALL="C", LANG="C")
    # without a display a message box LDmicro opens (an unknown part...) closes at once; the
    # output goes to a file, not a pipe that wine's server would hold open for seconds
    with open(scratch / "wine.log", "wb") as log:
        done = subprocess.run(["wine", str(SAVER), "/s", "prog.ld", "saved.ld"], cwd=scratch, env=env, timeout=60,
                              stdout=log, stderr=log)
    assert done.returncode == 0 and (scratch / "saved.ld").exists(), (scratch / "wine.log").read_text("latin-1")
    return (scratch / "saved.ld").read_bytes()


@pytest.fixture(scope="module")
def saves(tmp_path_factory) -> dict[Path, bytes]:
    """Every corpus file as LDmicro saves it (each save about half a second)."""
    found = {}
    for number, path in enumerate(all_ld_files()):
        scratch = tmp_path_factory.mktemp(f"save{number}")
        found[path] = saved_by_ldmicro(path, scratch)
    return found


@pytest.mark.parametrize("path", all_ld_files(), ids=rel)
def test_a_file_ldmicro_saved_comes_back_byte_for_byte(path, saves):
    saved = saves[path]
    assert through_the_text_form(saved) == saved


def test_every_corpus_file_was_saved(saves):
    assert len(saves) == 66


def test_the_io_list_takes_every_name_ldmicro_lists(tmp_path):
    """tests/ldmicro/io-names.ld uses a name in every operand LDmicro's I/O
    list takes (contacts and coils of each letter, MOV, arithmetic, counter
    limits, bit tests, segments, BUS, SWAP, READ ADC, SET PWM, SPI and I2C
    buses, encoder, pulse outputs, the cycle duty pin), and in operands it
    does not (comparisons, BIN2BCD, timers); two Modbus names have an address
    and no pin. LDmicro saves its IO LIST; ours is the same, byte for byte."""
    saved = saved_by_ldmicro(Path(__file__).parent / "ldmicro" / "io-names.ld", tmp_path)
    assert saved.count(b" at 0 0 0\r\n") == 43 and b"    Id at 0 7 8\r\n" in saved
    assert through_the_text_form(saved) == saved
