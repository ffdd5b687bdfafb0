"""LD503: UART instructions on a part without a UART."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import UART_KINDS, describe, rung_no

CODE = register(
    "LD503", "UART instruction on a part without UART",
    "The selected part has no UART, so UART SEND, UART RECV, their ready/available tests and "
    "formatted strings cannot be compiled for it. LDmicro: \"UART function used but not supported "
    "for this micro.\"",
)


def check(program, index):
    device = index.device
    if device is None or device.uart:
        return []
    return [
        error(CODE, f"{describe(element)} in {rung_no(rung)}: the {device.title} has no UART", element.span)
        for rung, element in index.of_kind(*UART_KINDS)
    ]
