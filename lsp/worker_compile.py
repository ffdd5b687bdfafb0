"""The code that attrs and cattrs generate as the server starts, compiled
once by the browser build instead of at each page load.

attrs writes the methods of each class as Python source and compiles it:
lsprotocol defines about a thousand classes, and on Pyodide compiling their
methods is most of the time the server takes to import. The source is the
same at every start, so the build (web/pyodide-files.mjs) records what
`compile` makes of it while the server starts (`record`), and the browser's
worker looks the code up instead of compiling it again (`install`). The
code objects are those of the same Python (Pyodide's, in both), for the
same source, file name, mode and flags, so the server runs the same code.
Source that was not recorded is compiled as before."""

from __future__ import annotations
import __future__

import builtins
import marshal
import sys
from collections.abc import Callable
from types import CodeType
from typing import Any

# the flags that compile() takes over from the code that calls it, unless dont_inherit
_INHERITED = 0
for _feature in __future__.all_feature_names:
    _INHERITED |= getattr(__future__, _feature).compiler_flag

Key = tuple[str, str, str, int, int]
Compile = Callable[..., Any]

_compile: Compile = builtins.compile


def _compiler(known: dict[Key, CodeType], learn: bool) -> Compile:
    """compile(), answered from `known` where it can be; with learn, what
    it compiles from a string is added to `known`."""

    def compile(source: Any, filename: Any, mode: str, flags: int = 0, dont_inherit: bool = False,
                optimize: int = -1, **more: Any) -> Any:
        if not isinstance(source, str) or flags & ~_INHERITED or more:
            # bytes (imports), ASTs, or flags that change what comes out: as they are
            return _compile(source, filename, mode, flags, dont_inherit, optimize, **more)
        if not dont_inherit:
            flags |= sys._getframe(1).f_code.co_flags & _INHERITED
        key = (source, str(filename), mode, flags, optimize)
        code = known.get(key)
        if code is None:
            code = _compile(source, filename, mode, flags, True, optimize)
            if learn:
                known[key] = code
        return code

    return compile


def record() -> dict[Key, CodeType]:
    """From now until `stop`, what is compiled from source text: the build's."""
    known: dict[Key, CodeType] = {}
    builtins.compile = _compiler(known, learn=True)
    return known


def stop() -> None:
    builtins.compile = _compile


def save(known: dict[Key, CodeType], path: str) -> None:
    with open(path, "wb") as out:
        marshal.dump(known, out)


def install(path: str) -> None:
    """compile() answers from the code recorded at `path` by the build."""
    with open(path, "rb") as data:
        builtins.compile = _compiler(marshal.load(data), learn=False)
