"""LDmicro 5.4.1.1 itself, run as the tests' oracle under wine with no display:
its compiler through the `ldmicro` wrapper (../shared/tools/ldmicro/build.sh
installs it at /opt/ldmicro, or LDMICRO=) and its save (tests/ldmicro/build-save.sh
adds the batch command `/s IN OUT` and installs it at /opt/ldmicro-save, or
LDMICRO_SAVE=).

A run that crashed in wine is run again, three runs at most. Once, in CI, a
save died of a page fault on a file LDmicro saved in each of dozens of runs on
this machine before and after, loaded or idle, and the module-scoped fixture
that held every save failed the LDmicro step's 67 tests on it. A crash of the
emulated program says nothing about the file it was given; LDmicro's own
answers (a refusal, its message boxes, the exception handler that saves a
`tmpfile_*.ld`) are not crashes and are never retried."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

LDMICRO = Path(os.environ.get("LDMICRO", "/opt/ldmicro/ldmicro"))
SAVER = Path(os.environ.get("LDMICRO_SAVE", "/opt/ldmicro-save/ldmicro.exe"))
RUNS = 3
# what wine prints when the program dies under it (the wrapper passes it on as "wine: ...")
CRASHED = re.compile(r"Unhandled (page fault|exception|illegal instruction)|starting debugger")


def installed() -> Path:
    if not LDMICRO.exists():
        pytest.fail(f"LDmicro is not installed at {LDMICRO}: run ../shared/tools/ldmicro/build.sh")
    return LDMICRO


def ldmicro_compile(source: Path, out: Path, check: bool = False) -> subprocess.CompletedProcess[str]:
    """`ldmicro compile SOURCE OUT`: LDmicro's HEX (or C, by OUT's extension);
    its console lines ("Compiled okay...") on stdout, a refusal's reasons on
    stderr, the wrapper's status (0 done, 1 refused or failed). `check`: fail
    the test unless LDmicro compiled it."""
    installed()
    for _ in range(RUNS):
        done = subprocess.run([str(LDMICRO), "compile", str(source), str(out)], capture_output=True, text=True,
                              timeout=300)
        if not CRASHED.search(done.stderr):
            break
    assert not check or done.returncode == 0, done.stdout + done.stderr
    return done


def ldmicro_save(path: Path, scratch: Path) -> bytes:
    """The .ld file at `path` as LDmicro loads and saves it (about half a second)."""
    if not SAVER.exists():
        pytest.fail(f"LDmicro with its save command is not installed at {SAVER}: run tests/ldmicro/build-save.sh")
    shutil.copyfile(path, scratch / "prog.ld")
    env = {key: value for key, value in os.environ.items() if key not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env.update(WINEPREFIX=str(SAVER.parent / "wineprefix"), WINEDLLOVERRIDES="mscoree,mshtml=", WINEDEBUG="-all",
               LC_ALL="C", LANG="C")
    for _ in range(RUNS):
        (scratch / "saved.ld").unlink(missing_ok=True)
        # without a display a message box LDmicro opens (an unknown part...) closes at once; the
        # output goes to a file, not a pipe that wine's server would hold open for seconds
        with open(scratch / "wine.log", "wb") as log:
            done = subprocess.run(["wine", str(SAVER), "/s", "prog.ld", "saved.ld"], cwd=scratch, env=env,
                                  timeout=60, stdout=log, stderr=log)
        said = (scratch / "wine.log").read_text("latin-1")
        if not CRASHED.search(said):
            break
    assert done.returncode == 0 and (scratch / "saved.ld").exists(), said
    return (scratch / "saved.ld").read_bytes()
