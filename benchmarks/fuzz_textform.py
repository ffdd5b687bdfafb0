"""Time-boxed fuzzing of the text reader: mutated corpus exports, checked for
crashes (any exception) and for diagnostics without a usable location.

`python benchmarks/fuzz_textform.py [SECONDS]` (default 60); prints how many
inputs it reached. A crashing input is written to fuzz-crash-<n>.txt."""

from __future__ import annotations

import random
import sys
import time
import traceback
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from corpus import EXPORTS  # noqa: E402
from lang.checks import check_program  # noqa: E402
from lang.textform.reader import read_text  # noqa: E402
from mutations import mutate  # noqa: E402


def main() -> int:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    texts = [path.read_text(encoding="cp1252") for path in sorted(EXPORTS.glob("*.txt"))]
    rng = random.Random(1)
    deadline = time.monotonic() + seconds
    inputs = crashes = located = 0
    while time.monotonic() < deadline:
        mutated = mutate(rng.choice(texts), rng, rng.randint(1, 8))
        inputs += 1
        try:
            program, problems = read_text(mutated)
            if not problems:
                check_program(program)
            located += sum(1 for p in problems if p.span is not None)
        except Exception:  # the point of the run: anything that escapes is a bug
            crashes += 1
            Path(f"fuzz-crash-{crashes}.txt").write_text(mutated + "\n\n" + traceback.format_exc())
    print(f"{inputs} inputs in {seconds:.0f} s, {crashes} crashes, {located} located diagnostics")
    return 1 if crashes else 0


if __name__ == "__main__":
    sys.exit(main())
