"""What a part's peripherals make of a program's settings, from the device
files: the timer setting that makes the scan cycle, the UART's baud rate
divisor, the frequency a PWM output runs at, and which pins the A/D inputs
make analog on the parts that choose analog pins in groups.

One definition for the checks, which report what a build would find
(LD706, LD707, LD708, LD709, LD713, LD714) as soon as the program names its
part, and for the back ends, which program the timers, the UART and ADCON1
from the same answers. The facts are in each device file's key for its
family (`cycle_timer`, `baud`, `pwm`, and the PIC16's `features.adc.pcfg`),
which the back ends read too. And which register a `#` name reaches
(indirect access, LD702), from each part's register table.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from .devices import Device

# beyond this the build warns that the PWM frequency is approximated (LD709)
PWM_TOLERANCE = 0.05
# the scan cycle's timer must make the cycle time this closely (LD706)
CYCLE_TOLERANCE = 0.001


def nearest_period(ticks: float, prescalers: dict[int, int], most: int) -> tuple[float, int, int] | None:
    """(relative error, select bits, counts) of the prescaler whose whole
    count (1..most) comes nearest `ticks`, the first of equals; None if none fits."""
    best = None
    for prescaler, select_bits in prescalers.items():
        counts = round(ticks / prescaler)
        if 1 <= counts <= most:
            error = abs(counts * prescaler - ticks) / ticks
            if best is None or error < best[0]:
                best = (error, select_bits, counts)
    return best


def cycle_timer(device: Device) -> dict:
    """The timer that makes the scan cycle: its clock divider, prescalers,
    counts, and on parts that can run it free, the compare units that restart
    it and the ticks a free-running count reaches."""
    return device.data[device.family]["cycle_timer"]


def _prescalers(timer: dict) -> dict[int, int]:
    return {int(text): select for text, select in timer["prescalers"].items()}


def cycle_runs_free(device: Device, crystal_hz: int, cycle_us: int, pwm_units: set[str]) -> bool:
    """True when the cycle timer runs free, its overflows counted: no compare
    unit is left by PWM to restart it, or the cycle is longer than it counts.
    False on parts whose timer always restarts by itself (AVR's CTC mode)."""
    timer = cycle_timer(device)
    units = timer.get("compare_units")
    if units is None:
        return False
    longest = timer["counts"] * max(_prescalers(timer)) * timer["clock_divider"] * 1_000_000 / crystal_hz
    return not any(unit not in pwm_units for unit in units) or cycle_us > longest


def cycle_setting(device: Device, crystal_hz: int, cycle_us: int, free: bool) -> tuple[int, int] | None:
    """(select bits, counts) making the cycle within CYCLE_TOLERANCE: the
    nearest when the timer restarts at a match, the largest prescaler when it
    runs free (the longest time between overflows); None when none does."""
    timer = cycle_timer(device)
    prescalers = _prescalers(timer)
    cycles = crystal_hz / timer["clock_divider"] * cycle_us / 1_000_000
    if free:
        for prescaler, select_bits in sorted(prescalers.items(), reverse=True):
            ticks = round(cycles / prescaler)
            if 1 <= ticks < timer["free_ticks"] and abs(ticks * prescaler - cycles) / cycles <= CYCLE_TOLERANCE:
                return select_bits, ticks
        return None
    best = nearest_period(cycles, prescalers, timer["counts"])
    if best is None or best[0] > CYCLE_TOLERANCE:
        return None
    return best[1], best[2]


def cycle_refusal(device: Device, crystal_hz: int, cycle_us: int, free: bool) -> str:
    """Why no setting makes the cycle (`cycle_setting` gave None)."""
    timer = cycle_timer(device)
    prescalers = sorted(_prescalers(timer))
    clock = f", Fosc/{timer['clock_divider']}" if timer["clock_divider"] != 1 else ""
    width = "" if free else "16 bits, "
    return (f"a {cycle_us / 1000:g} ms cycle cannot be made from a {crystal_hz / 1e6:g} MHz crystal with "
            f"Timer{timer.get('timer', 1)} "
            f"({width}prescaler {prescalers[0]} to {prescalers[-1]}{clock})")


@dataclass(frozen=True)
class BaudSetting:
    select: int  # the divider's select bit (AVR U2X, PIC16 BRGH)
    value: int  # the baud rate register (UBRR, SPBRG)
    actual: float  # the baud rate it makes
    error: float  # relative to the one asked


def baud_facts(device: Device) -> dict | None:
    """The UART's baud rate generator: its dividers (each with its select
    bit, tried in order), the largest register value, the error beyond which
    it fails and, where one is given, beyond which the build warns."""
    return device.data.get(device.family, {}).get("baud")


def _baud(device: Device) -> dict:
    facts = baud_facts(device)
    assert facts is not None, "a part without a UART: LD503"
    return facts


def baud_setting(device: Device, crystal_hz: int, baud: int) -> BaudSetting:
    """The setting nearest the baud rate (the first of equals)."""
    facts = _baud(device)
    best = None
    for divider, select in facts["divisors"]:
        value = min(max(round(crystal_hz / (divider * baud)) - 1, 0), facts["most"])
        actual = crystal_hz / (divider * (value + 1))
        error = abs(actual - baud) / baud
        if best is None or error < best.error - 1e-12:
            best = BaudSetting(select, value, actual, error)
    assert best is not None  # every part has a divider
    return best


def baud_refusal(device: Device, crystal_hz: int, baud: int) -> str | None:
    """Why the UART cannot run at the baud rate, or None."""
    facts = _baud(device)
    setting = baud_setting(device, crystal_hz, baud)
    if setting.error <= facts["limit"]:
        return None
    return (f"{baud} baud cannot be made from a {crystal_hz / 1e6:g} MHz crystal: the nearest is "
            f"{setting.actual:.0f} baud ({100 * setting.error:.1f} % off, at most {100 * facts['limit']:.1f} %)")


def baud_approximated(device: Device, crystal_hz: int, baud: int) -> BaudSetting | None:
    """The setting, when it is further off than the build warns of but
    within what a receiver follows; None otherwise."""
    facts = _baud(device)
    setting = baud_setting(device, crystal_hz, baud)
    warn = facts.get("warn")
    if warn is None or not warn < setting.error <= facts["limit"]:
        return None
    return setting


@dataclass(frozen=True)
class PwmSetting:
    select: int  # the prescaler's clock select bits
    period: int  # timer counts in one PWM period
    freq: float  # the frequency the output runs at


def pwm_timer(device: Device, unit: str) -> dict | None:
    """The timer behind a PWM unit (OC0A, CCP1): its number and, when the
    back end drives it, its clock divider, prescalers and period range."""
    return device.data.get(device.family, {}).get("pwm", {}).get(unit)


def pwm_refusal(device: Device, unit: str, freq: int) -> str | None:
    """Why the unit cannot make a PWM output at all, or None."""
    timer = pwm_timer(device, unit)
    if timer is None or "prescalers" not in timer:
        number = timer["timer"] if timer else "?"
        cycle = device.data.get(device.family, {}).get("cycle_timer", {}).get("timer", 1)  # Timer0 on the ATtiny85
        why = f"Timer{number} makes the scan cycle" if number == cycle else \
            f"Timer{number} is a 16-bit timer, not compiled"
        return f"PWM on {unit}: {why}; use an 8-bit timer's output"
    if freq <= 0:
        return f"PWM frequency {freq} Hz is not possible"
    return None


def pwm_setting(device: Device, unit: str, crystal_hz: int, freq: int) -> PwmSetting:
    """The prescaler and period whose frequency is nearest `freq` (the finest
    period of equals); the unit must pass `pwm_refusal`."""
    timer = pwm_timer(device, unit)
    assert timer is not None and freq > 0, "pwm_refusal says why not"
    divider = timer["clock_divider"]
    low, high = timer["periods"]
    choices = []
    for text, select in timer["prescalers"].items():
        prescaler = int(text)
        period = min(max(round(crystal_hz / (divider * prescaler * freq)), low), high)
        choices.append(PwmSetting(select, period, crystal_hz / (divider * prescaler * period)))
    return min(choices, key=lambda c: (abs(c.freq - freq), -c.period))


def approximated(setting: PwmSetting, freq: int) -> bool:
    return abs(setting.freq - freq) > PWM_TOLERANCE * freq


def analog_groups(device: Device) -> list[tuple[int, frozenset[int]]] | None:
    """(PCFG value, the A/D channels it makes analog) for the parts whose
    ADCON1 chooses the analog pins in fixed groups; None for the others."""
    facts = device.data.get(device.family, {})
    table = facts.get("features", {}).get("adc", {}).get("pcfg")
    if table is None or "ANSEL" in facts.get("registers", {}):
        return None  # no groups, or ANSEL sets each pin alone
    return [(value, frozenset(channels)) for value, channels in table]


def analog_group(device: Device, channels: set[int]) -> tuple[int, frozenset[int]] | None:
    """The smallest group (PCFG value, channels) holding every channel READ
    ADC reads; None when the part sets each pin alone or nothing is read."""
    groups = analog_groups(device)
    if groups is None or not channels:
        return None
    return min((group for group in groups if channels <= group[1]), key=lambda group: len(group[1]))


def clock_refusal(device: Device, crystal_hz: int, config_word: int | None) -> str | None:
    """Why the part cannot run at the program's clock: its internal
    oscillator cannot make it (internal_clock_refusal), or it is beyond the
    fastest crystal with the PLL (a PIC18: 4 x 10 MHz); None when it can."""
    refusal = internal_clock_refusal(device, crystal_hz, config_word)
    pll = device.data.get(device.family, {}).get("features", {}).get("pll")
    if refusal is None and pll is not None and crystal_hz > pll["most"]:
        refusal = (f"the {device.title} runs at {pll['most'] / 1e6:g} MHz at most ({pll['factor']} x a "
                   f"{pll['most'] / pll['factor'] / 1e6:g} MHz crystal with the PLL), not at {crystal_hz / 1e6:g} MHz")
    return refusal


# `#PORTB`, `#PINB`, `#DDRB`, `#TRISB`: a port register by the name either family gives it
_PORT_REGISTER = re.compile(r"#(PORT|PIN|DDR|TRIS)([A-Z])$", re.IGNORECASE)
# what each family calls the others' port registers: an AVR has no TRIS (it is DDR); a PIC16
# reads its pins in PORT and sets their direction in TRIS
_PORT_NAMES = {"avr": {"TRIS": "DDR"}, "pic16": {"PIN": "PORT", "DDR": "TRIS"}, "pic18": {"PIN": "PORT", "DDR": "TRIS"},
               "pic10": {"PIN": "PORT", "DDR": "TRIS"}}


def data_addresses(device: Device) -> range:
    """The data addresses a `#0x..` name may reach: an AVR's above its 32
    working registers (from 0 on the reduced core) up to the end of RAM, a
    PIC16's every bank."""
    facts = device.data[device.family]
    if "access_sfr" in facts:  # a PIC18's 4096: its RAM banks and the SFRs at the top
        return range(0, 0x1000)
    if "file_addresses" in facts:  # a baseline PIC10's one bank of 32
        return range(0, facts["file_addresses"])
    if "banks" in facts:
        return range(0, 128 * facts["banks"])
    # the reduced core (ATtiny10) has its I/O registers at 0x00..0x3F, not its working registers
    start = 0 if facts.get("core") == "reduced" else 0x20
    return range(start, facts["ram"]["start"] + facts["ram"]["size"])


def register_address(device: Device, name: str) -> int | None:
    """The data address a `#` name reaches on a part of a compiled family
    (`#PORTB`, `#TRISA`, `#0x25`), or None when it names none of the part's."""
    registers = device.data[device.family]["registers"]
    port = _PORT_REGISTER.match(name)
    if port:
        kind = port.group(1).upper()
        return registers.get(_PORT_NAMES[device.family].get(kind, kind) + port.group(2).upper())
    try:
        address = int(name[1:], 0)
    except ValueError:
        return None
    return address if address in data_addresses(device) else None


def internal_clock_refusal(device: Device, crystal_hz: int, config_word: int | None) -> str | None:
    """Why the part's internal oscillator cannot run the program's clock, when
    the configuration word (the program's, else the part's default) selects
    it; None when it can, or when a crystal or an external clock runs the part.
    The oscillator makes a few clocks only, each an OSCCON value (LDmicro's)."""
    facts = device.data.get(device.family, {})
    intosc = facts.get("features", {}).get("intosc")
    fosc = facts.get("config", {}).get("fields", {}).get("FOSC")
    if intosc is None or fosc is None:
        return None
    word = facts["config"]["words"][0]["value"] if config_word is None else config_word & 0x3FFF
    if word & fosc["mask"] != fosc["value"] or str(crystal_hz) in intosc["settings"]:
        return None
    clocks = ", ".join(f"{int(hz) / 1e6:g}" for hz in sorted(intosc["settings"], key=int, reverse=True))
    return (f"the {device.title}'s internal oscillator runs at {clocks} MHz, not at {crystal_hz / 1e6:g} MHz: "
            "choose one of them, or a configuration word with a crystal")
