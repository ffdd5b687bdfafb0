"""C names for the intermediate code's storage, as LDmicro names them.

LDmicro's C calls a user's name `U<t>_<name>` and one of its own
`I<t>_<name>`, `<t>` being `b` for a bit and `i` for an integer; inputs and
outputs are functions the user's runtime provides (`Read_Ub_Xname()`,
`Write_Ub_Yname(v)`, `Read_Ub_Yname()`). The front end's own storage
(temporaries `~t3`, element memory `~m2.0.loaded`, `$mcr`, `$seed_x`) gets
an `I` name; every character C does not allow in a name becomes `_`, and a
name that would then clash with another gets a number.
"""

from __future__ import annotations

import re

from lang.semantics import ir

C_TYPES = {1: "SBYTE", 2: "SWORD", 3: "SDWORD", 4: "SDWORD"}  # LDmicro's ladder.h types by size


def _ident(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_]", "_", text.lstrip("~$"))


class Names:
    """Every bit and variable of a program's code, with its C name."""

    def __init__(self, code: ir.Code):
        self.classes = code.bits
        self.sizes = code.vars
        self._taken: set[str] = set()
        self.bits = {name: self._unique(("I" if name[0] in "~$" else "U") + "b_" + _ident(name))
                     for name in sorted(code.bits)}
        self.vars = {name: self._unique(("I" if name[0] in "~$" else "U") + "i_" + _ident(name))
                     for name in sorted(code.vars)}

    def _unique(self, name: str) -> str:
        candidate, n = name, 1
        while candidate in self._taken:
            n += 1
            candidate = f"{name}_{n}"
        self._taken.add(candidate)
        return candidate

    def read_bit(self, bit: ir.Bit) -> str:
        if self.classes[bit.name] in (ir.INPUT, ir.OUTPUT):
            return f"Read_{self.bits[bit.name]}()"
        return self.bits[bit.name]

    def write_bit(self, bit: ir.Bit, value: str) -> str:
        if self.classes[bit.name] == ir.OUTPUT:
            return f"Write_{self.bits[bit.name]}({value});"
        return f"{self.bits[bit.name]} = {value};"

    def storage(self) -> list[tuple[str, str, str]]:
        """(C type, C name, program name) of every variable this file holds:
        the program's relays and integers and the front end's own."""
        found = [("BOOLEAN_t", c, name) for name, c in self.bits.items() if self.classes[name] in (ir.MEMORY, ir.TEMP)]
        found += [(C_TYPES[self.sizes[name]], c, name) for name, c in self.vars.items()]
        return found
