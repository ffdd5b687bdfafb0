"""Where the shared corpus is, and the facts about it the tests rely on."""

from __future__ import annotations

from pathlib import Path

SHARED = Path(__file__).resolve().parents[2] / "shared"
CORPUS = SHARED / "corpus"
EXPORTS = CORPUS / "ldmicro-export"


def all_ld_files() -> list[Path]:
    return sorted(CORPUS.rglob("*.ld"))


def export_pairs() -> list[tuple[Path, Path]]:
    """Each real LDmicro export beside the .ld it was made from."""
    return [(txt, txt.with_suffix(".ld")) for txt in sorted(EXPORTS.glob("*.txt"))]
