"""LDmicro 5.4.1.1 itself is the oracle of the `.ld` round trip: each corpus
file, loaded and saved by LDmicro (tests/ldmicro/build-save.sh adds the batch
command `/s IN OUT` to it and installs it at /opt/ldmicro-save, or
LDMICRO_SAVE=), then taken through `.ld -> .ladder -> .ld`, must come back as
LDmicro saved it, byte for byte."""

from __future__ import annotations

from pathlib import Path

import pytest
from corpus import all_ld_files
from ldmicro_oracle import ldmicro_save
from test_ldfile_bytes import rel, through_the_text_form

pytestmark = pytest.mark.ldmicro


@pytest.mark.parametrize("path", all_ld_files(), ids=rel)
def test_a_file_ldmicro_saved_comes_back_byte_for_byte(path, tmp_path):
    saved = ldmicro_save(path, tmp_path)
    assert through_the_text_form(saved) == saved


def test_every_corpus_file_is_taken():
    assert len(all_ld_files()) == 66


def test_the_io_list_takes_every_name_ldmicro_lists(tmp_path):
    """tests/ldmicro/io-names.ld uses a name in every operand LDmicro's I/O
    list takes (contacts and coils of each letter, MOV, arithmetic, counter
    limits, bit tests, segments, BUS, SWAP, READ ADC, SET PWM, SPI and I2C
    buses, encoder, pulse outputs, the cycle duty pin), and in operands it
    does not (comparisons, BIN2BCD, timers); two Modbus names have an address
    and no pin. LDmicro saves its IO LIST; ours is the same, byte for byte."""
    saved = ldmicro_save(Path(__file__).parent / "ldmicro" / "io-names.ld", tmp_path)
    assert saved.count(b" at 0 0 0\r\n") == 43 and b"    Id at 0 7 8\r\n" in saved
    assert through_the_text_form(saved) == saved
