"""Recursion over ladder trees without Python's recursion limit: a program may
nest parallel blocks hundreds deep (LDmicro reads them), and every reader and
writer must take it. A recursive function is written as a generator that
`yield`s its recursive calls (each a generator) and receives their results;
`run` drives them on an explicit stack."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any, TypeVar

T = TypeVar("T")
Call = Generator[Any, Any, T]


def run(call: Call[T]) -> T:
    """The result of `call`, its nested calls run one after another on a list."""
    stack: list[Call] = [call]
    value: Any = None
    while stack:
        try:
            child = stack[-1].send(value)
        except StopIteration as done:
            stack.pop()
            value = done.value
            continue
        stack.append(child)
        value = None
    return value
