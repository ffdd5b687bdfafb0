"""What a back end produces, for every family: the program memory image,
extra segments, the listing and the figures, and the Intel HEX file made
from them.

Program memory is a list of words, each stored little-endian at byte address
2 x word address: AVR's 16-bit words, PIC's 14-bit ones (the HEX layout
Microchip's tools and LDmicro use). A PIC image also carries segments beyond
program memory at the byte addresses of that layout: the configuration
word(s) at word 0x2007 (byte 0x400E), EEPROM data at word 0x2100 (byte
0x4200, one EEPROM byte per word). A segment is raw bytes; its back end lays
them out.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from intelhex import IntelHex

from lang.devices import Device
from lang.diagnostics import Diagnostic
from lang.files import write_whole
from lang.model import Program

if TYPE_CHECKING:
    from .budget import Budget

HEX_RECORD_BYTES = 16


@dataclass(frozen=True)
class Symbol:
    """Where a name lives in the part's data memory."""

    address: int
    size: int  # bytes, 1 for a bit
    bit: int | None = None


@dataclass(frozen=True)
class LoopBound:
    """A loop of the generated code: at most `iterations` passes through its
    head each time it is entered (None: no bound the compiler knows), and
    what it is, for the scan-time budget's report (compiler/budget.py). A
    wait on hardware may be bounded in time instead: it is left within
    `cycles` CPU cycles of being entered (and one more pass)."""

    iterations: int | None
    what: str
    cycles: int | None = None


@dataclass
class Image:
    words: list[int]  # program memory from word address 0
    listing: str
    ram_bytes: int  # data memory the program uses
    ram_size: int
    flash_size: int  # program memory, in flash_unit
    flash_unit: str  # "bytes" (AVR) or "words" (PIC)
    warnings: list[Diagnostic]
    symbols: dict[str, Symbol]  # name -> where it lives
    labels: dict[str, int]  # listing label -> word address
    segments: dict[int, bytes] = field(default_factory=dict)  # byte address -> data past program memory
    listing_suffix: str = ".lst"
    loops: dict[str, LoopBound] = field(default_factory=dict)  # loop-head label -> its bound
    # a cycle timer running free loses time when a scan lasts longer than this (CPU cycles, with why)
    scan_limit: tuple[int, str] | None = None

    def __post_init__(self):
        if self.flash_unit not in ("bytes", "words"):
            raise ValueError(f"flash unit {self.flash_unit!r}: 'bytes' or 'words'")
        end = 2 * len(self.words)
        for address in self.segments:
            if address < end:
                raise ValueError(f"segment at byte 0x{address:X} overlaps program memory (ends at 0x{end:X})")

    @property
    def flash_used(self) -> int:
        return 2 * len(self.words) if self.flash_unit == "bytes" else len(self.words)

    def program_bytes(self) -> bytes:
        return b"".join(w.to_bytes(2, "little") for w in self.words)

    def hex(self) -> str:
        data = IntelHex()
        data.frombytes(self.program_bytes(), offset=0)
        for address, segment in sorted(self.segments.items()):
            data.frombytes(segment, offset=address)
        out = io.StringIO()
        data.write_hex_file(out, byte_count=HEX_RECORD_BYTES)
        return out.getvalue()


@dataclass
class Build:
    """A compiled program: `compiler.build`'s result."""

    program: Program  # as compiled (with the target part selected)
    device: Device
    image: Image
    warnings: list[Diagnostic]  # the compiler's and the back end's
    budget: Budget | None = None  # the worst case of one scan (compiler/budget.py)

    def summary(self) -> str:
        """`PART: flash N/M bytes (P%), RAM N/M bytes (P%)` (flash in words for PIC)."""
        image = self.image
        return (f"{self.device.title}: flash {image.flash_used}/{image.flash_size} {image.flash_unit} "
                f"({100 * image.flash_used / image.flash_size:.1f}%), RAM {image.ram_bytes}/{image.ram_size} "
                f"bytes ({100 * image.ram_bytes / image.ram_size:.1f}%)")

    def listing_path(self, hex_path) -> Path:
        return Path(hex_path).with_suffix(self.image.listing_suffix)

    def write(self, hex_path) -> None:
        """The HEX file and the listing beside it (same stem, the back end's
        listing suffix). Each appears whole or not at all: it is written to
        a temporary file in the same folder and renamed."""
        hex_path = Path(hex_path)
        write_whole(hex_path, self.image.hex().encode("ascii"))
        write_whole(self.listing_path(hex_path), self.image.listing.encode("utf-8"))

