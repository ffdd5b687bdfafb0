"""The C back end: intermediate code to portable C that keeps the contract of
LDmicro 5.4's ANSI C output, so that a runtime written for LDmicro's C links
ours unchanged (docs/c.md).

`FILE.c` holds the program's variables and `void PlcCycle(void)`, one scan
(the start values are set by its first call, as LDmicro's are), and an empty
`setupPlc()`; `FILE.h` declares them and the functions the user's runtime
provides: `Read_Ub_Xname()`, `Read_Ub_Yname()`/`Write_Ub_Yname(v)`, and
LDmicro's hooks for A/D, PWM, UART, EEPROM and delays. `ladder.h` (the types
`BOOLEAN_t`, `SBYTE`, `SWORD`, `SDWORD` and the macros `_STATIC_`, `PROTO`,
`LDSTUB*`) is the user's; `default_ladder_h()` is one to start from.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from lang.semantics import ir

from .emit import STACK_DEPTH, Writer, c_constant, comment_safe, label_name, write_ops
from .helpers import helper_text
from .names import Names

INIT_FLAG = "Ib_once_0_INIT_VARS"  # LDmicro's name for it


@dataclass(frozen=True)
class Unit:
    """What the C back end knows besides the code: the files' stem, the
    source it comes from, each rung's drawing (for the comment above its
    code) and the cycle time the runtime must call PlcCycle() at."""

    stem: str
    source: str
    drawing: Callable[[int], list[str]]
    cycle_us: int


@dataclass(frozen=True)
class CSources:
    c: str
    h: str
    # every program name the code uses -> (what it is, its C name): "input" and "output" are
    # the runtime's Read_/Write_ functions of that name, "bit" and "int" variables of FILE.c
    symbols: dict[str, tuple[str, str]]
    hooks: tuple[str, ...]  # the functions the runtime provides, as their prototypes


_HOOK_DECLARATIONS = {
    "UART_Transmit": "void UART_Transmit(unsigned char b)",
    "UART_Transmit_Ready": "BOOLEAN_t UART_Transmit_Ready(void)",
    "UART_Receive": "unsigned char UART_Receive(void)",
    "UART_Receive_Avail": "BOOLEAN_t UART_Receive_Avail(void)",
    "EEPROM_read": "unsigned char EEPROM_read(int address)",
    "EEPROM_write": "void EEPROM_write(int address, unsigned char b)",
    "EEPROM_busy": "BOOLEAN_t EEPROM_busy(void)",
    "delay_us": "void delay_us(SDWORD us)",
}


def _declaration(hook: str) -> tuple[str, str]:
    """The hook's prototype and the LDSTUB macro that stubs it."""
    if hook in _HOOK_DECLARATIONS:
        text = _HOOK_DECLARATIONS[hook]
        return text, "LDSTUB0" if not text.startswith("void") else "LDSTUB"
    if hook.startswith("Read_Ub_A"):
        return f"SWORD {hook}(void)", "LDSTUB0"
    if hook.startswith("Write_Ub_P"):
        return f"void {hook}(SWORD duty)", "LDSTUB"
    if hook.startswith("Read_"):
        return f"BOOLEAN_t {hook}(void)", "LDSTUB0"
    return f"void {hook}(BOOLEAN_t v)", "LDSTUB"


def generate(code: ir.Code, unit: Unit) -> CSources:
    names = Names(code)
    w = Writer(names, unit.drawing)
    w.used.add(INIT_FLAG)
    w.line(f"if (!{INIT_FLAG}) {{")
    w.line(f"{INIT_FLAG} = 1;", 2)
    start = len(w.lines)
    write_ops(w, code.init)
    w.lines[start:] = ["    " + line if line else line for line in w.lines[start:]]
    w.line("}")
    if any(isinstance(op, (ir.Call, ir.Return)) for op in code.scan):
        w.line("ld_sp = 0;")
    write_ops(w, code.scan)
    # C warns of a label nothing jumps to
    targets = {label_name(t) for t in w.targets}
    body = [line for line in w.lines
            if not (line.endswith(":;") and not line.startswith((" ", "ld_return")) and line[:-2] not in targets)]
    if w.calls or w.returns:
        body += ["    return;", "ld_dispatch:", "    if (ld_sp == 0) {", "        return;", "    }",
                 "    ld_sp--;", "    switch (ld_stack[ld_sp]) {"]
        for k in range(1, w.calls + 1):
            body += [f"    case {k}:", f"        goto ld_return{k};"]
        body += ["    default:", "        return;", "    }"]
    return CSources(_c_file(unit, names, w, body), _h_file(unit, names, w), _symbols(names, w),
                    tuple(text for text, _ in _hooks(w)))


def _symbols(names: Names, w: Writer) -> dict[str, tuple[str, str]]:
    found: dict[str, tuple[str, str]] = {}
    for name, cname in names.bits.items():
        kind = names.classes[name]
        if name[0] not in "~$" and (cname in w.used or f"Read_{cname}" in w.hooks or f"Write_{cname}" in w.hooks):
            found[name] = (kind if kind in (ir.INPUT, ir.OUTPUT) else "bit", cname)
    for name, cname in names.vars.items():
        if name[0] not in "~$" and cname in w.used:
            found[name] = ("int", cname)
    return found


def _guard(stem: str) -> str:
    return "LADDER_" + re.sub(r"[^A-Za-z0-9]", "_", stem).upper() + "_H"


def _hooks(w: Writer) -> list[tuple[str, str]]:
    return [_declaration(hook) for hook in sorted(w.hooks)]


def _storage(names: Names, w: Writer) -> list[tuple[str, str, str]]:
    found = [entry for entry in names.storage() if entry[1] in w.used]
    return [("BOOLEAN_t", INIT_FLAG, "")] + found


def _c_file(unit: Unit, names: Names, w: Writer, body: list[str]) -> str:
    out = [f"/* {unit.stem}.c: generated by textladder from {comment_safe(unit.source)}; do not edit, change the",
           "   ladder program and build again. Call PlcCycle() once every "
           f"{unit.cycle_us / 1000:g} ms (the program's cycle time);",
           f"   {unit.stem}.h lists the functions your runtime provides. */",
           "",
           "#include <stdint.h>",
           "",
           '#include "ladder.h"',
           f'#include "{unit.stem}.h"',
           ""]
    for ctype, cname, name in _storage(names, w):
        note = f" /* {comment_safe(name)} */" if name and cname[3:] != name else ""
        out.append(f"_STATIC_ {ctype} {cname} = 0;{note}")
    if w.calls or w.returns:
        out += ["", f"static unsigned char ld_stack[{STACK_DEPTH}]; /* GOSUB return sites */",
                "static unsigned char ld_sp;"]
        if w.keeps:
            out.append(f"static BOOLEAN_t ld_kept[{STACK_DEPTH}][{w.keeps}]; /* the caller's temporaries */")
    for i, values in enumerate(w.tables, 1):
        out += ["", f"static const int32_t ld_table{i}[{len(values)}] = {{"
                    + ", ".join(c_constant(v) for v in values) + "};"]
    hooks = _hooks(w)
    if hooks:
        out += ["", "/* You provide these functions (DO_LDSTUBS in ladder.h makes empty ones). */"]
        out += [f"{macro}( {text} )" for text, macro in hooks]
    helpers = helper_text(w.helpers)
    if helpers:
        out += ["", helpers]
    out += ["", "/* One scan of the ladder program. */", "void PlcCycle(void)", "{"]
    out += body
    out += ["}", "",
            "/* Nothing to set up in portable C: the runtime configures its I/O and the cycle timer. */",
            "void setupPlc(void)", "{", "}", ""]
    return "\n".join(out)


def _h_file(unit: Unit, names: Names, w: Writer) -> str:
    guard = _guard(unit.stem)
    out = [f"/* {unit.stem}.h: generated by textladder from {comment_safe(unit.source)}; do not edit. */",
           f"#ifndef {guard}", f"#define {guard}", "", '#include "ladder.h"', "",
           "void PlcCycle(void); /* one scan: call it once every "
           f"{unit.cycle_us / 1000:g} ms */",
           "void setupPlc(void);"]
    hooks = _hooks(w)
    old = [hook for hook in sorted(w.hooks) if re.match(r"(Read|Write)_Ub_[XYAP]", hook)]
    if old:
        # older LDmicro releases spelled the I/O functions Read_U_b_Xname: a runtime written for them
        # defines LDMICRO_OLD_NAMES in its ladder.h, and every call and prototype below follows
        out += ["", "#ifdef LDMICRO_OLD_NAMES"]
        out += [f"#define {hook} {hook.replace('_Ub_', '_U_b_', 1)}" for hook in old]
        out += ["#endif"]
    if hooks:
        out += ["", "/* You provide these functions. */"]
        out += [f"PROTO({text};)" for text, _ in hooks]
    storage = _storage(names, w)
    out += ["", "#ifdef EXTERN_EVERYTHING"]
    out += [f"extern {ctype} {cname};" for ctype, cname, _ in storage]
    out += ["#endif", "", f"#endif /* {guard} */", ""]
    return "\n".join(out)


def default_ladder_h() -> str:
    """A ladder.h for a C99 compiler: written beside the C when the folder
    has none, for the user to adapt (the same macros as LDmicro's example)."""
    return """\
/* ladder.h: the types and macros the C from textladder (and LDmicro) uses.
   Written once by `ladder build --emit c` because this folder had none; it is
   yours to change. */
#ifndef LADDER_H
#define LADDER_H

#include <stdint.h>

/* Define EXTERN_EVERYTHING to make every ladder variable visible to your runtime. */
#ifdef EXTERN_EVERYTHING
  #define _STATIC_
#else
  #define _STATIC_ static
#endif

/* Define NO_PROTOTYPES to declare the I/O functions yourself. */
#ifdef NO_PROTOTYPES
  #define PROTO(x)
#else
  #define PROTO(x) x
#endif

/* Define LDMICRO_OLD_NAMES if your I/O functions are spelled as older LDmicro releases did
   (Read_U_b_Xname, Write_U_b_Yname). */

/* Define DO_LDSTUBS to get empty I/O functions (to check that the files compile). */
#ifdef DO_LDSTUBS
  #define LDSTUB(x)   x { ; }
  #define LDSTUB0(x)  x { return 0; }
  #define LDSTUB1(x)  x { return 1; }
#else
  #define LDSTUB(x)   PROTO(extern x;)
  #define LDSTUB0(x)  PROTO(extern x;)
  #define LDSTUB1(x)  PROTO(extern x;)
#endif

typedef unsigned char BOOLEAN_t;
typedef int8_t  SBYTE;
typedef int16_t SWORD;
typedef int32_t SDWORD;

#endif
"""
