"""Timers, counters, RES and the time-to-count converter, as LDmicro compiles
them (intcode.cpp ELEM_TON ... ELEM_CTR): the accumulator counts scans, and
each element instance has its own edge memory."""

from __future__ import annotations

from collections.abc import Sequence

from ..instructions import TIMERS
from ..values import is_literal
from .codegen import CannotSimulate, Gen, handles, timer_period
from .errors import BAD_OPERAND


def period(gen: Gen, el) -> str:
    """The timer's limit: its period in scans, or the delay variable."""
    delay = el.args["delay"]
    if isinstance(delay, int):
        return str(timer_period(gen, delay, int(el.args.get("adjust", 0) or 0), el.args["name"]))
    return gen.var(str(delay))


def _increment(gen: Gen, name: str, limit: str) -> str:
    t = gen.var(name)
    if limit.isdigit():
        return f"{t} += 1"  # stays below a literal period that fits the timer
    return f"{t} = {gen.wrap(t + ' + 1', name)}"


@handles(*TIMERS)
def timer(gen: Gen, el, p: str) -> None:
    name = el.args["name"]
    t, limit = gen.var(name), period(gen, el)
    inc = _increment(gen, name, limit)
    kind = el.kind
    if kind == "TON":
        with gen.block(f"if {p}:"):
            with gen.block(f"if {t} < {limit}:"):
                gen.emit(f"{p} = False")
                gen.emit(inc)
        gen.emit(f"else: {t} = 0")
    elif kind == "TOF":
        with gen.block(f"if not {p}:"):
            with gen.block(f"if {t} < {limit}:"):
                gen.emit(inc)
                gen.emit(f"{p} = True")
        gen.emit(f"else: {t} = 0")
    elif kind == "RTO":
        with gen.block(f"if {t} < {limit}:"):
            with gen.block(f"if {p}:"):
                gen.emit(inc)
                gen.emit(f"{p} = False")
        gen.emit(f"else: {p} = True")
    elif kind == "RTL":
        with gen.block(f"if {t} < {limit}:"):
            gen.emit(f"if not {p}: {inc}")
            gen.emit(f"else: {p} = False")
        gen.emit(f"else: {p} = True")
    elif kind == "TCY":
        phase = gen.memory("phase")
        with gen.block(f"if {p}:"):
            gen.emit(f"if {t} < {limit}: {inc}")
            with gen.block("else:"):
                gen.emit(f"{t} = 0")
                gen.emit(f"{phase} = not {phase}")
            gen.emit(f"if not {phase}: {p} = False")
        gen.emit(f"else: {t} = 0")
    elif kind == "THI":
        st = gen.memory("st")
        gen.emit(f"if {p}: {st} = True")
        with gen.block(f"if {st}:"):
            with gen.block(f"if {t} < {limit}:"):
                gen.emit(inc)
                gen.emit(f"{p} = True")
            with gen.block("else:"):
                with gen.block(f"if not {p}:"):
                    gen.emit(f"{t} = 0")
                    gen.emit(f"{st} = False")
                gen.emit(f"{p} = False")
        gen.emit(f"else: {p} = False")
    else:  # TLO
        st, hi = gen.memory("st"), gen.memory("hi")
        gen.emit(f"if not {p}: {st} = {st} or {hi}")
        gen.emit(f"else: {hi} = True")
        with gen.block(f"if {st}:"):
            with gen.block(f"if {t} < {limit}:"):
                gen.emit(inc)
                gen.emit(f"{p} = False")
            with gen.block("else:"):
                with gen.block(f"if {p}:"):
                    gen.emit(f"{t} = 0")
                    gen.emit(f"{st} = False")
                gen.emit(f"{p} = True")
        gen.emit(f"elif {hi}: {p} = True")


@handles("TIME2COUNT")
def time_to_count(gen: Gen, el, p: str) -> None:
    delay = el.args["delay"]
    if not isinstance(delay, int):
        raise CannotSimulate(BAD_OPERAND, "the T2CNT delay must be a time, not a variable")
    value = timer_period(gen, delay, 0, el.args["name"])
    gen.emit(f"if {p}: {gen.var(el.args['name'])} = {gen.wrap(str(value), el.args['name'])}")


def _counter_init(gen: Gen, el) -> None:
    """A variable start value is copied into the counter the first time the
    element runs (a numeric one is set before the first scan)."""
    init = str(el.args.get("init", "0"))
    if not is_literal(init):
        done, c = gen.memory("init"), gen.var(el.args["name"])
        with gen.block(f"if not {done}:"):
            gen.emit(f"{done} = True")
            gen.emit(f"{c} = {gen.wrap(gen.var(init), el.args['name'])}")


def _edge(gen: Gen, el, p: str, act: list[str], idle: Sequence[str] = ()) -> None:
    """Run `act` when the counting edge happens; `idle` on the scans where
    the input is in its resting state (the edge kinds follow intcode.cpp)."""
    kind = el.args.get("kind", "/")
    if kind in "/\\":
        st = gen.memory("edge")
        level, rest = (p, f"not {p}") if kind == "/" else (f"not {p}", p)
        with gen.block(f"if {level}:"):
            for line in idle:
                gen.emit(line)
            with gen.block(f"if {'not ' if kind == '/' else ''}{st}:"):
                gen.emit(f"{st} = {kind == '/'}")
                for line in act:
                    gen.emit(line)
        with gen.block("else:"):
            gen.emit(f"{st} = {kind != '/'}")
            if kind == "\\":
                for line in idle:
                    gen.emit(line)
    else:
        with gen.block(f"if {p if kind == '-' else 'not ' + p}:"):
            for line in act:
                gen.emit(line)


@handles("CTU", "CTD")
def up_down_counter(gen: Gen, el, p: str) -> None:
    name = el.args["name"]
    c, limit = gen.var(name), gen.operand(el.args["max"])
    _counter_init(gen, el)
    if el.kind == "CTU":
        step = f"if {c} < {limit}: {c} = {gen.wrap(c + ' + 1', name)}"
        _edge(gen, el, p, [step])
        gen.emit(f"{p} = {c} >= {limit}")
    else:
        step = f"if {c} > {limit}: {c} = {gen.wrap(c + ' - 1', name)}"
        _edge(gen, el, p, [step])
        gen.emit(f"{p} = {c} > {limit}")


@handles("CTC", "CTR")
def circular_counter(gen: Gen, el, p: str) -> None:
    name = el.args["name"]
    c, limit = gen.var(name), gen.operand(el.args["max"])
    start = gen.wrap(gen.operand(el.args.get("init", "0")), name)
    up = el.kind == "CTC"
    step = f"{c} = {gen.wrap(c + (' + 1' if up else ' - 1'), name)}"
    past = f"{c} {'>' if up else '<'} {limit}"
    kind = el.args.get("kind", "/")
    _counter_init(gen, el)
    if kind == "-":
        # LDmicro's code leaves the rung true on the wrap (its "impulse" is
        # the input itself) and clears it otherwise
        with gen.block(f"if {p}:"):
            gen.emit(step)
            gen.emit(f"if {past}: {c} = {start}")
            gen.emit(f"else: {p} = False")
        return
    wrapped = [step, f"if {past}:", f"    {c} = {start}", f"    {p} = True"]
    if kind == "o":
        with gen.block(f"if not {p}:"):
            for line in wrapped:
                gen.emit(line)
        gen.emit(f"else: {p} = False")
        return
    _edge(gen, el, p, wrapped, idle=[f"{p} = False"])


@handles("RES")
def reset(gen: Gen, el, p: str) -> None:
    name = el.args["name"]
    if name.startswith("P"):
        with gen.block(f"if {p}:"):
            gen.emit(f"PER.pwm_off({name!r})")
            gen.emit(f"{gen.bit(name)} = False")
        return
    target = gen.var(name)
    value = "0"
    if name.startswith("C"):
        counter = gen.counter_defs.get(name)
        if counter is not None:
            value = gen.wrap(gen.operand(counter.args.get("init", "0")), name)
    gen.emit(f"if {p}: {target} = {value}")
