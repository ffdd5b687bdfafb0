"""The `ladder` settings section (docs/lsp-protocol.md), read from
`workspace/didChangeConfiguration` and, when the client offers it, pulled with
`workspace/configuration`."""

from __future__ import annotations

import codecs
from dataclasses import dataclass, field

from lang.config import NONE, ConfigError, Severities, parse

# the debounce when diagnosticsDelayMs is not set: none while a check is quick
# (an edit is checked incrementally: a few ms even for thousands of rungs), this
# much after one that took longer (a whole check of a big document), so that
# typing right after it is not held up by another
ADAPTIVE_DELAY_MS = 150
QUICK_CHECK_MS = 100


@dataclass
class Settings:
    compile_on_save: bool = True
    encoding: str = "cp1252"
    diagnostics_delay_ms: int | None = None  # None: adaptive
    severities: Severities = field(default=NONE)  # `ladder.diagnostics`, over the project's

    def delay_ms(self, last_check_ms: float) -> int:
        """The debounce to use after a change, given how long the last check took."""
        if self.diagnostics_delay_ms is not None:
            return self.diagnostics_delay_ms
        return 0 if last_check_ms < QUICK_CHECK_MS else ADAPTIVE_DELAY_MS

    def update(self, section: object) -> list[str]:
        """Apply a `ladder` settings object; returns complaints about values
        that were ignored (never raises on bad input)."""
        problems: list[str] = []
        if not isinstance(section, dict):
            return problems
        if "compileOnSave" in section:
            value = section["compileOnSave"]
            if isinstance(value, bool):
                self.compile_on_save = value
            else:
                problems.append("ladder.compileOnSave must be true or false")
        if "encoding" in section:
            value = section["encoding"]
            try:
                if not isinstance(value, str):
                    raise LookupError
                codecs.lookup(value)
                self.encoding = value
            except LookupError:
                problems.append(f"ladder.encoding: unknown encoding {value!r}")
        if "diagnosticsDelayMs" in section:
            value = section["diagnosticsDelayMs"]
            if value is None:
                self.diagnostics_delay_ms = None
            elif isinstance(value, (int, float)) and not isinstance(value, bool) and 0 <= value <= 10000:
                self.diagnostics_delay_ms = int(value)
            else:
                problems.append("ladder.diagnosticsDelayMs must be a number of milliseconds (0..10000), "
                                "or null for the adaptive default")
        if "diagnostics" in section:
            try:
                self.severities = parse(section["diagnostics"] or {}, "ladder.diagnostics")
            except ConfigError as bad:
                problems.append(str(bad))
        return problems


def ladder_section(settings: object) -> object:
    """The `ladder` object inside whatever a client sent: `{"ladder": {...}}`,
    dotted keys (`{"ladder.encoding": ...}`) or the section itself."""
    if not isinstance(settings, dict):
        return None
    if isinstance(settings.get("ladder"), dict):
        return settings["ladder"]
    dotted = {key[len("ladder."):]: value for key, value in settings.items()
              if isinstance(key, str) and key.startswith("ladder.")}
    if dotted:
        return dotted
    if any(key in settings for key in ("compileOnSave", "encoding", "diagnosticsDelayMs", "diagnostics")):
        return settings
    return None
