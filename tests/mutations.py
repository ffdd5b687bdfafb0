"""Damaging a drawing the way a hand edit or a bad paste would: characters
replaced, deleted or inserted, lines swapped. Used by the fuzz test and the
time-boxed fuzz benchmark."""

from __future__ import annotations

import random

GLYPH_CHARS = "-+| []{}()/\\o^~X;\""


def mutate(text: str, rng: random.Random, count: int) -> str:
    lines = text.splitlines()
    start = lines.index("LADDER DIAGRAM:") + 1 if "LADDER DIAGRAM:" in lines else 0
    if start >= len(lines):
        return text
    for _ in range(count):
        number = rng.randrange(start, len(lines))
        line = lines[number]
        col = rng.randrange(len(line) + 1)
        edit = rng.choice(["replace", "delete", "insert", "swap-lines"])
        glyph = rng.choice(GLYPH_CHARS)
        if edit == "replace" and line:
            line = line[:col] + glyph + line[col + 1:]
        elif edit == "delete":
            line = line[:col] + line[col + 1:]
        elif edit == "insert":
            line = line[:col] + glyph + line[col:]
        else:
            other = rng.randrange(start, len(lines))
            lines[other], line = line, lines[other]
        lines[number] = line
    return "\n".join(lines)
