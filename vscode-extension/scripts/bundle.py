"""Fills bundled/libs with textladder and its dependencies, so that the .vsix carries its language server.

Run by `npm run bundle` (and so by `npm run package`, through `vscode:prepublish`) with a Python 3
that has pip. It builds the wheel of the repository around this extension, installs it and its
dependencies with `pip install --target bundled/libs --no-compile`, accepting only pure-Python
wheels, and writes bundled/tool/python.json: the Python versions the package supports
(`requires-python`), which the extension checks an interpreter against before starting the server.

The dependencies get the versions installed in the Python that runs this script when it has them
(the repository's virtual environment: what the tests ran with), otherwise the newest that fit.
"""

from __future__ import annotations

import fnmatch
import json
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from importlib import metadata
from pathlib import Path

EXTENSION = Path(__file__).resolve().parents[1]
REPO = EXTENSION.parent
LIBS = EXTENSION / "bundled" / "libs"
PYTHON_JSON = EXTENSION / "bundled" / "tool" / "python.json"

# what an installed dependency carries that the server never reads
DROPPED_DIRS = {"__pycache__", "tests", "test", "__pyinstaller"}
DROPPED_FILES = ("test.py", "test_*.py", "*_test.py", "*.pyc")
# what a .dist-info keeps: the licences, and METADATA's headers (importlib.metadata reads the version there)
KEPT_DIST_INFO = ("LICENSE*", "LICENCE*", "COPYING*", "NOTICE*", "AUTHORS*", "licenses")


class BundleError(Exception):
    pass


def minimum_python(requires: str) -> str:
    """'3.11' for '>=3.11': the version pip resolves the dependencies for."""
    found = re.search(r">=\s*(\d+\.\d+)", requires)
    if not found:
        raise BundleError(f"pyproject.toml: requires-python {requires!r} names no lower bound (>=X.Y)")
    return found.group(1)


def source_tree(project: dict, into: Path) -> Path:
    """A copy of what the wheel is built from: pyproject.toml, its readme and the packages it includes.

    The wheel is built from a copy because setuptools builds in place, leaving build/ and an
    .egg-info in the checkout, whose stale files would end up in the next wheel."""
    tree = into / "src"
    tree.mkdir()
    shutil.copy2(REPO / "pyproject.toml", tree)
    readme = project["project"].get("readme")
    if isinstance(readme, str):
        shutil.copy2(REPO / readme, tree)
    include = project["tool"]["setuptools"]["packages"]["find"]["include"]
    packages = [p for p in sorted(REPO.iterdir())
                if (p / "__init__.py").exists() and any(fnmatch.fnmatch(p.name, pattern) for pattern in include)]
    if not packages:
        raise BundleError(f"no package of {REPO} matches {include}")
    for package in packages:
        shutil.copytree(package, tree / package.name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return tree


def constraints(into: Path, own: str) -> Path:
    """Pins every distribution the running Python has, so that the bundle carries the versions tested."""
    pins = sorted({f"{d.metadata['Name']}=={d.version}" for d in metadata.distributions()
                   if d.metadata["Name"] and d.metadata["Name"].lower() != own.lower()})
    path = into / "constraints.txt"
    path.write_text("\n".join(pins) + "\n")
    return path


def run(*args: str) -> None:
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode != 0:
        raise BundleError(f"{' '.join(args)} failed ({done.returncode}):\n{done.stdout}{done.stderr}")


def check_pure(libs: Path) -> None:
    """Every installed wheel is pure Python: the bundle runs on any platform's Python."""
    for wheel in libs.glob("*.dist-info/WHEEL"):
        text = wheel.read_text()
        tags = re.findall(r"^Tag:\s*(\S+)", text, re.M)
        if "Root-Is-Purelib: true" not in text or not tags or not all(t.endswith("-none-any") for t in tags):
            raise BundleError(f"{wheel.parent.name} is not a pure-Python wheel ({', '.join(tags)}): it cannot be bundled")
    compiled = [p for p in libs.rglob("*") if p.suffix in {".so", ".pyd", ".dll", ".dylib"}]
    if compiled:
        raise BundleError(f"compiled code in the bundle: {', '.join(str(p.relative_to(libs)) for p in compiled)}")


def prune(libs: Path, own_packages: set[str]) -> None:
    shutil.rmtree(libs / "bin", ignore_errors=True)  # console scripts, written for the bundler's Python
    for info in libs.glob("*.dist-info"):
        for item in info.iterdir():
            if item.name == "METADATA":
                # the headers end at the first blank line; the long description after it is the README
                item.write_text(item.read_text().split("\n\n", 1)[0] + "\n")
            elif not any(fnmatch.fnmatch(item.name, keep) for keep in KEPT_DIST_INFO):
                shutil.rmtree(item) if item.is_dir() else item.unlink()
    for top in libs.iterdir():
        if top.name in own_packages or not top.is_dir() or top.suffix == ".dist-info":
            continue
        for path in sorted(top.rglob("*"), reverse=True):
            if path.is_dir() and path.name in DROPPED_DIRS:
                shutil.rmtree(path)
            elif path.is_file() and any(fnmatch.fnmatch(path.name, pattern) for pattern in DROPPED_FILES):
                path.unlink()
    for cache in list(libs.rglob("__pycache__")):
        shutil.rmtree(cache)


def bundle() -> None:
    project = tomllib.loads((REPO / "pyproject.toml").read_text())
    requires = project["project"]["requires-python"]
    name = project["project"]["name"]
    python = minimum_python(requires)
    with tempfile.TemporaryDirectory(prefix="textladder-bundle-") as tmp:
        work = Path(tmp)
        tree = source_tree(project, work)
        run(sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet", "--wheel-dir", str(work / "wheel"), str(tree))
        wheels = list((work / "wheel").glob("*.whl"))
        if len(wheels) != 1:
            raise BundleError(f"pip wheel made {len(wheels)} wheels")
        staging = work / "libs"
        # --platform any --implementation py --abi none: pip refuses any wheel with compiled code
        run(sys.executable, "-m", "pip", "install", "--quiet", "--no-compile", "--target", str(staging),
            "--only-binary=:all:", "--platform", "any", "--implementation", "py", "--abi", "none",
            "--python-version", python, "--constraint", str(constraints(work, name)), str(wheels[0]))
        check_pure(staging)
        prune(staging, {p.name for p in tree.iterdir() if p.is_dir()})
        shutil.rmtree(LIBS, ignore_errors=True)
        LIBS.parent.mkdir(parents=True, exist_ok=True)
        shutil.move(str(staging), LIBS)
    PYTHON_JSON.parent.mkdir(parents=True, exist_ok=True)
    PYTHON_JSON.write_text(json.dumps({"requiresPython": requires, "textladder": project["project"]["version"]}, indent=2) + "\n")
    size = sum(p.stat().st_size for p in LIBS.rglob("*") if p.is_file())
    print(f"bundled/libs: {len(list(LIBS.iterdir()))} entries, {size / 1e6:.1f} MB; Python {requires}")


def main() -> int:
    try:
        bundle()
    except KeyError as exc:
        print(f"bundle: pyproject.toml has no {exc.args[0]!r}", file=sys.stderr)
        return 1
    except (BundleError, OSError, tomllib.TOMLDecodeError) as exc:
        print(f"bundle: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
