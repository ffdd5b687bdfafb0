"""Hypothesis strategies for random valid programs, from the instruction table:
every instruction, every field kind, series and parallel nesting as LDmicro
allows it (end-of-line elements last in their branch, a parallel holding one
last in its series)."""

from __future__ import annotations

from hypothesis import strategies as st

from lang.instructions import INSTRUCTIONS, Instruction
from lang.model import Element, Parallel, PinAssignment, Program, Rung, Series, Settings, rung_circuit

SUFFIX = st.text("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_", min_size=1, max_size=8)
LETTERS = "abcdefghijklmnopqrstuvwxyzBDEFGJKLNOQSUVWZ"


def name_with(prefixes: str):
    first = st.sampled_from(prefixes) if prefixes else st.sampled_from(LETTERS)
    return st.builds(lambda a, b: a + b, first, SUFFIX)


def literal():
    return st.one_of(
        st.integers(-32768, 32767).map(str),
        st.integers(0, 255).map(lambda v: f"0x{v:X}"),
        st.sampled_from(["'A'", "'z'", "'\\n'"]),
    )


def value_for(instruction: Instruction, field):
    kind, prefixes = field.kind, field.prefixes
    if kind in ("bit", "var"):
        return name_with(prefixes)
    if kind == "operand":
        return st.one_of(name_with(""), literal())
    if kind == "label":
        return name_with("")
    if kind == "delay":
        return st.one_of(st.integers(1, 10**9), name_with(""))
    if kind == "edge":
        return st.sampled_from("/\\-o")
    if kind == "coil":
        return st.sampled_from(" /SRT")
    if kind == "flag":
        return st.integers(0, 1)
    if kind == "int":
        return st.integers(1, 254)
    if kind == "token":
        return name_with("")
    if kind == "text":
        return st.text("abcdefghij ABC:%.,!0123456789\\", min_size=1, max_size=30).filter(
            lambda t: t.strip() == t)
    if kind == "values":
        return st.lists(literal(), min_size=1, max_size=8).map(tuple)
    if kind == "points":
        return st.lists(st.tuples(st.integers(0, 1000).map(str), st.integers(-100, 100).map(str)),
                        min_size=2, max_size=6).map(tuple)
    raise AssertionError(f"no strategy for field kind {kind}")


SPECIAL = {"COMMENT", "PLACEHOLDER"}
# instructions whose every field kind survives a drawing
DRAWABLE = [i for i in INSTRUCTIONS.values() if i.key not in SPECIAL]


@st.composite
def element_of(draw, instruction: Instruction) -> Element:
    args = {}
    for field in instruction.fields:
        args[field.name] = draw(value_for(instruction, field))
    if instruction.key == "SET_PWM":
        args["freq"] = draw(st.integers(1, 100000))
    if instruction.key == "SHIFT_REGISTER":
        args["stages"] = draw(st.integers(1, 30))
    if instruction.key in ("TIME2COUNT", "TIME2DELAY"):
        args["delay"] = draw(st.integers(1, 10**7))
    if instruction.key == "DELAY":
        args["delay"] = draw(st.one_of(st.integers(1, 10000).map(str), name_with("")))
    if instruction.key == "QUAD_ENCOD":
        args["z"] = draw(name_with("X"))
        args["dir"] = draw(name_with("YR"))
    if instruction.key == "FORMATTED_STRING":
        args["var"] = draw(name_with(""))
    return Element(instruction.key, args)


def elements(eol: bool):
    pool = [i for i in DRAWABLE if i.eol == eol]
    return st.sampled_from(pool).flatmap(element_of)


@st.composite
def series(draw, depth: int, ends_line: bool):
    items = draw(st.lists(inline(depth), min_size=0 if ends_line else 1, max_size=3))
    if ends_line:
        items.append(draw(st.one_of(elements(eol=True), eol_parallel(depth)) if depth else elements(eol=True)))
    return Series(items)


def inline(depth: int):
    options = [elements(eol=False)]
    if depth:
        options.append(st.lists(series(depth - 1, False), min_size=2, max_size=3).map(Parallel))
    return st.one_of(*options)


def eol_parallel(depth: int):
    return st.lists(series(depth - 1, True), min_size=2, max_size=3).map(Parallel)


@st.composite
def rungs(draw):
    if draw(st.integers(0, 9)) == 0:
        text = draw(st.lists(value_for(None, INSTRUCTIONS["COMMENT"].fields[0]), min_size=1, max_size=3))
        # the blanks that end its lines in an .ld file (kept in DETAILS by the text form)
        ends = draw(st.one_of(st.just(()), st.lists(st.integers(0, 3).map(str), min_size=len(text),
                                                     max_size=len(text)).map(tuple)))
        return Rung(Series([Element("COMMENT", {"text": "\n".join(text), "line_ends": ends})]))
    circuit = draw(series(2, ends_line=draw(st.booleans())))
    return Rung(rung_circuit(circuit))


@st.composite
def programs(draw):
    settings = Settings(
        mcu=draw(st.sampled_from([None, "Atmel AVR ATmega328 28-PDIP", "Microchip PIC16F877 40-PDIP"])),
        cycle_us=draw(st.integers(100, 100000)),
        crystal_hz=draw(st.integers(1000000, 40000000)),
        baud=draw(st.sampled_from([9600, 2400, 115200])),
    )
    program = Program(settings=settings, rungs=draw(st.lists(rungs(), min_size=1, max_size=5)))
    names = sorted({str(e.args["name"]) for _, e in program.elements()
                    if e.kind in ("CONTACTS", "COIL") and str(e.args["name"])[:1] in "XY"})
    for index, name in enumerate(names):
        if draw(st.booleans()):
            program.pins[name] = PinAssignment(name, index + 2)
    return program
