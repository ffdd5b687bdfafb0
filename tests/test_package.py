"""The package as users get it: the sdist and the wheel built from the files
git knows (as a clone has them), every file of the packages in the wheel and
nothing else. An editable install reads the checkout, so only a real build
shows a data file left out (compiler/c/boards.json once was)."""

import shutil
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("lang", "compiler", "ide", "lsp", "ladder")


def _source_files() -> list[str]:
    """The tracked files and the new ones not ignored, as they are in the work tree."""
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
        cwd=ROOT, capture_output=True, check=True,
    ).stdout.decode().split("\0")
    return sorted(name for name in listed if name and (ROOT / name).is_file())


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> tuple[set[str], set[str], list[str], str]:
    """(the wheel's files, the sdist's files relative to its top folder, the source files,
    the wheel's entry points)."""
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("needs the git checkout")
    work = tmp_path_factory.mktemp("package")
    source = work / "src"
    files = _source_files()
    for name in files:
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, source / name)
    dist = work / "dist"
    run = subprocess.run([sys.executable, "-m", "build", "-o", str(dist), str(source)],
                         capture_output=True, text=True, timeout=240)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "deprecated" not in run.stdout + run.stderr, "the build warns of a deprecation:\n" + run.stdout + run.stderr
    (wheel,) = dist.glob("*.whl")
    (sdist,) = dist.glob("*.tar.gz")
    with zipfile.ZipFile(wheel) as archive:
        wheel_files = {name for name in archive.namelist() if not name.endswith("/")}
        (entry_points,) = [name for name in wheel_files if name.endswith(".dist-info/entry_points.txt")]
        commands = archive.read(entry_points).decode()
    with tarfile.open(sdist) as archive:
        sdist_files = {member.name.split("/", 1)[1] for member in archive.getmembers() if member.isfile()}
    return wheel_files, sdist_files, files, commands


def _package_files(files: list[str]) -> set[str]:
    return {name for name in files
            if name.split("/", 1)[0] in PACKAGES and "__pycache__" not in name and not name.endswith(".pyc")}


def test_the_wheel_holds_every_file_of_the_packages(built):
    wheel_files, _, files, _ = built
    missing = sorted(_package_files(files) - wheel_files)
    assert not missing, f"files of the packages the wheel leaves out (pyproject.toml's package-data): {missing}"


def test_the_wheel_holds_nothing_else(built):
    wheel_files, _, files, _ = built
    extra = sorted(name for name in wheel_files - _package_files(files)
                   if not name.startswith("textladder-") or ".dist-info/" not in name)
    assert not extra, f"files in the wheel that are no package file git knows: {extra}"


def test_the_wheel_installs_the_ladder_command(built):
    commands = built[3]
    assert "[console_scripts]\nladder = ladder.cli:main" in commands, commands


def test_the_sdist_is_a_source_tree_the_readme_command_works_in(built):
    _, sdist_files, files, _ = built
    needed = _package_files(files) | {"pyproject.toml", "README.md", "MANIFEST.in"}
    needed |= {name for name in files if name.startswith("examples/")}
    missing = sorted(needed - sdist_files)
    assert not missing, f"files the sdist leaves out: {missing}"
