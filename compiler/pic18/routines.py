"""The PIC18's own routine: mulN on the hardware multiplier. The others
(division, BCD) are the PIC16 back end's (compiler/pic16/routines.py),
written through the same patterns.

mulN: C = A * B modulo 2^(8N), the sum of the byte products A_i * B_j
(MULWF: PRODH:PRODL = W * f, one cycle) with i + j < N, each added at byte
i + j with its carry taken up through C_(N-1) (ADDWFC). No loop: 10 products
for 32 bits.
"""

from __future__ import annotations

from ..pic16.emit import Emitter, F, W
from ..pic16.integers import Scratch
from .part import Part


def hardware_multiply(part: Part):
    """The mulN writer for write_routines."""
    low, high = part.reg("PRODL"), part.reg("PRODH")

    def mul(e: Emitter, s: Scratch, n: int) -> None:
        A, B, R = s.A[:n], s.B[:n], s.C[:n]
        for reg in R:
            e.ins("clrf", reg)
        for i in range(n):
            for j in range(n - i):
                k = i + j
                e.load(A[i])
                e.ins("mulwf", B[j])
                e.ins("movf", low, W)
                e.ins("addwf", R[k], F)
                if k + 1 < n:
                    e.ins("movf", high, W)
                    e.ins("addwfc", R[k + 1], F)
                    for reg in R[k + 2:]:
                        e.ins("movlw", 0)  # MOVLW leaves the carry
                        e.ins("addwfc", reg, F)
        e.ins("return")

    return mul
