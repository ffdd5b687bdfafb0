"""Peripheral instructions: ADC, PWM, PERSIST (EEPROM) and the UART
elements, including FORMATTED_STRING. They call the simulator's peripheral
objects (`PER`, `U`) that the user drives from outside."""

from __future__ import annotations

from ..strings import make_sender, parse_format
from .codegen import CannotSimulate, Gen, handles
from .errors import BAD_OPERAND, UART_STALL


@handles("READ_ADC")
def read_adc(gen: Gen, el, p: str) -> None:
    d, name = gen.dest("name")
    gen.emit(f"if {p}: {d} = {gen.wrap(f'PER.read_adc({name!r})', name)}")


@handles("SET_PWM")
def set_pwm(gen: Gen, el, p: str) -> None:
    name = el.args["name"]
    duty = gen.operand(el.args["duty"])
    with gen.block(f"if {p}:"):
        gen.emit(f"PER.set_pwm({name!r}, {duty}, {int(el.args['freq'])}, "
                 f"{str(el.args.get('resolution') or '0-100%')!r})")
        gen.emit(f"{gen.bit(name)} = True")


@handles("PERSIST")
def persist(gen: Gen, el, p: str) -> None:
    v, name = gen.dest("var")
    size = gen.size(name)
    address = gen.eeprom_next
    gen.eeprom_next += size
    loaded = gen.memory("loaded")
    with gen.block(f"if {p}:"):
        # the first powered scan loads the variable from EEPROM; later ones
        # write it back whenever it differs from the EEPROM copy
        with gen.block(f"if not {loaded}:"):
            gen.emit(f"{loaded} = True")
            gen.emit(f"{v} = PER.eeprom.read({address}, {size})")
        gen.emit(f"elif PER.eeprom.read({address}, {size}) != {v}: PER.eeprom.write({address}, {size}, {v})")


def _byte(value: str, index: int) -> str:
    return f"({value} >> {8 * index}) & 255" if index else f"{value} & 255"


@handles("UART_SEND")
def uart_send(gen: Gen, el, p: str) -> None:
    gen.uses_time = True
    value = gen.operand(el.args["var"])
    count = int(el.args.get("bytes", 1) or 1)
    if count == 1:
        gen.emit(f"if {p}: U.send(now, {value} & 255)")
    elif el.args.get("wait"):
        # all bytes in this scan, the MCU waiting for each (low byte first)
        with gen.block(f"if {p}:"):
            for i in range(count):
                gen.emit(f"U.send(now, {_byte(value, i)}, True)")
    else:
        # one byte per scan from a copy taken when sending starts
        active, saved, sent = gen.memory("active"), gen.memory("saved", "int"), gen.memory("sent", "int")
        with gen.block(f"if {p} and not {active}:"):
            gen.emit(f"{active} = True")
            gen.emit(f"{saved} = {value}")
            gen.emit(f"{sent} = 0")
        with gen.block(f"if {active}:"):
            with gen.block(f"if {sent} < {count} and U.ready(now):"):
                gen.emit(f"U.send(now, ({saved} >> (8 * {sent})) & 255)")
                gen.emit(f"{sent} += 1")
            gen.emit(f"if {sent} >= {count}: {active} = False")
        gen.emit(f"{p} = True if {active} else not U.ready(now)")
        return
    # the rung's output is the transmitter's busy flag, whatever the input
    gen.emit(f"{p} = not U.ready(now)")


@handles("UART_RECV")
def uart_recv(gen: Gen, el, p: str) -> None:
    d, name = gen.dest("var")
    count = int(el.args.get("bytes", 1) or 1)
    if count > gen.size(name):
        raise CannotSimulate(BAD_OPERAND, f"UART RECV of {count} bytes into '{name}' "
                                        f"of {gen.size(name)} bytes")
    if count == 1:
        with gen.block(f"if {p}:"):
            gen.emit(f"{p} = U.available()")
            gen.emit(f"if {p}: {d} = {gen.wrap('U.take()', name)}")
    elif el.args.get("wait"):
        with gen.block(f"if {p}:"):
            gen.emit(f"{p} = U.available()")
            with gen.block(f"if {p}:"):
                gen.emit(f"if len(U.received) < {count}: "
                         + gen.fault(UART_STALL, f"f'UART RECV waits for {count} bytes, "
                                                 f"{{len(U.received)}} received'"))
                r = gen.temp("r")
                gen.emit(f"{r} = 0")
                for i in range(count):
                    gen.emit(f"{r} |= U.take() << {8 * i}")
                gen.emit(f"{d} = {gen.wrap(r, name)}")
    else:
        saved, got = gen.memory("saved", "int"), gen.memory("got", "int")
        with gen.block(f"if {p}:"):
            with gen.block(f"if {got} < {count} and U.available():"):
                gen.emit(f"{saved} = ({saved} & ~(255 << (8 * {got}))) | (U.take() << (8 * {got}))")
                gen.emit(f"{got} += 1")
            with gen.block(f"if {got} >= {count}:"):
                gen.emit(f"{d} = {gen.wrap(saved, name)}")
                gen.emit(f"{got} = 0")
                gen.emit(f"{p} = True")
            gen.emit(f"else: {p} = False")


@handles("UART_SEND_READY")
def uart_send_ready(gen: Gen, el, p: str) -> None:
    gen.uses_time = True
    gen.emit(f"{p} = {p} and U.ready(now)")


@handles("UART_RECV_AVAIL")
def uart_recv_avail(gen: Gen, el, p: str) -> None:
    gen.emit(f"{p} = {p} and U.available()")


@handles("FORMATTED_STRING")
def formatted_string(gen: Gen, el, p: str) -> None:
    gen.uses_time = True
    try:
        fmt = parse_format(str(el.args.get("text") or ""))
    except ValueError as bad:
        raise CannotSimulate(BAD_OPERAND, str(bad)) from None
    var = str(el.args.get("var") or "")
    if fmt.digits and not var:
        raise CannotSimulate(BAD_OPERAND, "a variable is interpolated into the formatted string, "
                                        "but none is specified")
    sender = gen.constant(make_sender(fmt), "FS")
    # a variable the text never inserts is not read (LD323 warns), as in LDmicro's code
    value = gen.operand(var) if var and fmt.digits else "0"
    state = [gen.memory("one"), gen.memory("busy"), gen.memory("seq", "int"),
             gen.memory("conv", "int"), gen.memory("lead")]
    gen.emit(f"{p}, {', '.join(state)} = {sender}(now, {p}, {value}, {', '.join(state)}, U)")
