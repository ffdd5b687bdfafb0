"""A project's choice of diagnostic severities, as ruff and LuaLS let users
make it: `[tool.ladder.diagnostics]` in the nearest `pyproject.toml`, or
`[diagnostics]` in a `ladder.toml`, searched upward from the program's folder.

    [tool.ladder.diagnostics]
    LD131 = "off"
    LD211 = "error"

Only codes the registry marks configurable can be set (not reading errors nor
simulation faults), and a build never lowers an error (docs/diagnostics.md,
"Choosing severities").
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

from .codes import CODES
from .diagnostics import ERROR, INFO, WARNING, Diagnostic

OFF = "off"
CHOICES = (ERROR, WARNING, INFO, OFF)
# file name -> the keys leading to its table of severities
_TABLES = (("ladder.toml", ("diagnostics",)), ("pyproject.toml", ("tool", "ladder", "diagnostics")))


class ConfigError(Exception):
    """A settings file that cannot be used; the message names the file and the entry."""


@dataclass(frozen=True)
class Severities:
    """The chosen severity of each code a project sets, and where it was set."""

    chosen: Mapping[str, str]
    source: str = ""

    def apply(self, diagnostics: list[Diagnostic], building: bool = False) -> list[Diagnostic]:
        """The diagnostics with the chosen severities; those turned off are
        left out. When `building`, an error stays an error."""
        kept = []
        for diagnostic in diagnostics:
            choice = self.chosen.get(diagnostic.code)
            if choice is None or not CODES[diagnostic.code].configurable or \
                    (building and diagnostic.severity == ERROR):
                kept.append(diagnostic)
            elif choice != OFF:
                kept.append(replace(diagnostic, severity=choice))
        return kept

    def merged(self, other: Severities) -> Severities:
        """These choices with `other`'s on top (the editor's setting over the file's)."""
        return Severities({**self.chosen, **other.chosen}, other.source or self.source)


NONE = Severities({})


def parse(table: object, source: str) -> Severities:
    """Check a table of `CODE = "error" | "warning" | "info" | "off"`."""
    if not isinstance(table, dict):
        raise ConfigError(f"{source}: the diagnostics setting must be a table of CODE = \"error\" | "
                          "\"warning\" | \"info\" | \"off\"")
    chosen = {}
    for key, value in table.items():
        code = str(key).upper()
        if code not in CODES:
            raise ConfigError(f"{source}: {key}: no such diagnostic code (`ladder explain` lists them)")
        if not CODES[code].configurable:
            raise ConfigError(f"{source}: {key}: cannot be changed: reading errors (LD0xx) and simulation "
                              "faults (LD6xx) keep their severity")
        if value not in CHOICES:
            raise ConfigError(f"{source}: {key} = {value!r}: expected \"error\", \"warning\", \"info\" or \"off\"")
        chosen[code] = value
    return Severities(chosen, source)


def find(start: Path) -> Severities:
    """The severities set by the nearest `ladder.toml` or `pyproject.toml`
    with a diagnostics table, from `start` (a file or folder) upward."""
    folder = start if start.is_dir() else start.parent
    for directory in (folder.resolve(), *folder.resolve().parents):
        for name, keys in _TABLES:
            path = directory / name
            if not path.is_file():
                continue
            try:
                document = tomllib.loads(path.read_text(encoding="utf-8"))
            except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as bad:
                raise ConfigError(f"{path}: cannot read: {bad}") from None
            table: object = document
            for key in keys:
                table = table.get(key) if isinstance(table, dict) else None
            if table is not None:
                return parse(table, f"{path} [{'.'.join(keys)}]")
    return NONE
