"""Raw register access (ReadSfr, WriteSfr): the address is a data-space
address, as in LDmicro's AVR back end (its LD/ST through X). A constant one
is reached directly, by IN/OUT below the I/O space's end and LDS/STS above;
a variable one, or a constant in the working registers below the I/O space
(which IN/OUT/LDS/STS do not reach, and LD702 refuses before a build:
lang/checks/register_name.py), through X, which takes the variable's low
16 bits (its value modulo 65536, as the simulator's)."""

from __future__ import annotations

from lang.semantics import ir

from . import integers
from .emit import A

X = (26, 27)


def _direct(cx, address: ir.Operand) -> int | None:
    """The constant address IN/OUT or LDS/STS reach, else None (X is loaded)."""
    if isinstance(address, ir.Const) and address.value >= cx.e.core.io_offset:
        return address.value
    integers.load(cx, address, X)
    return None


def read_sfr(cx, op: ir.ReadSfr) -> None:
    e = cx.e
    address = _direct(cx, op.address)
    if address is None:
        e.ins("ld_x", A[0])
    else:
        e.load_byte(address, A[0], False)
    n = integers.target_size(cx, op.dst)
    integers.extend(cx, A[:n], 1, signed=False)
    integers.store(cx, op.dst, A[:n])


def write_sfr(cx, op: ir.WriteSfr) -> None:
    e = cx.e
    integers.load(cx, op.value, A[:1])
    address = _direct(cx, op.address)
    if address is None:
        e.ins("st_x", A[0])
        e.forget_memory()
    else:
        e.store_byte(address, A[0], False)
        e.forget_address(address)  # an address in RAM changes what a register may hold
