"""A PIC16 part as the back end sees it: the `pic16` key of its device file
(lang/devices/pic*.json), behind names. The facts come from gputils' processor
header (p16f877a.inc) and linker script (16f877a_g.lkr) and from LDmicro's
mcutable.h and pic16.cpp; tests/test_pic16_parts.py checks them against those
and against gpsim.

Addresses are data addresses: bank * 0x80 + the 7-bit file address an
instruction carries (STATUS RP1:RP0 pick the bank, IRP:FSR the same 9 bits).

The `pic16` key:

processor, gpsim
    gpasm's -p name ("p16f877a") and the gpsim processor its builds run in
    (null: gpsim has no model of the part or of a sibling with its pins).
    `gpsim_exact` is false when gpsim has no model of the part and runs a
    sibling: the PIC16F72 runs as "p16f73", whose registers are a superset
    but whose RAM is 192 bytes without the 16F72's mirrors.
flash_words, page_words, eeprom
    program words, words per page (CALL/GOTO reach one page; PCLATH<4:3>
    picks it), data EEPROM bytes (0: none).
banks, ram, common, mirrors
    RAM banks; the general-purpose bytes as [[first, last], ...], each
    physical byte once; [first, last] of the bytes every bank reaches, in
    bank-0 addresses, or null; [[first, last, target], ...] the data
    addresses that reach other bytes (first..last are target.. again).
ports
    a Pin's port letter -> [data register, direction register]; "P" is the
    PIC12F's GPIO/TRISIO.
registers
    every SFR the header names -> its data address (a mirror of INDF, STATUS,
    PCLATH... in another bank is not listed).
bits
    register -> {bit name: position}, the header's bit names of that
    register (the same name means different bits in different registers).
config
    words: [{address, value}] as the HEX carries them; `ldmicro` true when
    they are LDmicro's own words for the part, false when chosen here with
    the same meaning (crystal or, on the PIC12F, internal oscillator; watchdog
    off; power-up timer on; brown-out reset on; LVP off; no protection).
    fields: name -> {word, mask, value, symbol}: every field of the words,
    its bits, its value in the words and the header symbol meaning that value
    (a listing writes __CONFIG as the AND of the symbols of a word).
core
    "enhanced" on the enhanced mid-range parts (BSR banks, 32 of them, the
    core registers at 0x00-0x0B of each, FSR0/FSR1, MOVLP pages, LATx),
    which compiler/pic16/enhanced/ builds for; absent on the mid-range ones.
cycle_timer, baud, pwm
    what lang/hardware.py makes of the program's settings, for the checks and
    this back end alike: Timer1 as the scan's timer (Fosc/4, its T1CKPS
    prescalers, 65536 counts; the CCP modules whose special event trigger
    restarts it; the 23 bits of ticks a free-running count reaches), the
    USART's dividers ([16, BRGH 1], [64, BRGH 0]), the largest SPBRG and the
    errors that fail (4.5 %) and warn (2 %), and Timer2 behind each CCP's PWM
    (T2CKPS prescalers 1, 4, 16, periods of 1 to 256 counts).
features
    adc: {bits, result: [result registers, high byte first], pcfg}, absent
    without an A/D converter; pcfg, on the parts whose ADCON1 PCFG bits pick
    the analog pins: [[PCFG value, [the channels it makes analog]], ...], the
    combinations with VDD/VSS references (the datasheet's ADCON1 table). digital_io: {register: value} written at start-up to make
    every analog pin digital (ADCON1's PCFG, or ANSEL/ANSELH). comparators_off:
    {register: value} written at start-up where the comparators' reset state
    is on (the pins read as analog until then). cycle_timers: the scan timers
    the part offers, as LDmicro does: "timer0" (TMR0 and a software divisor),
    "timer1" (TMR1 reset by CCP1's special event trigger, CCP1CON = 0b1011).
    uart: the USART is there. eeprom: {data, address, control, unlock, flag}:
    the data EEPROM's registers and the PIR register holding EEIF. intosc:
    {register, settings}: where the configuration selects the internal
    oscillator, OSCCON's value for each clock it makes (Hz -> value: IRCF,
    and SPLLEN for 32 MHz). osccal:
    {address, register}: the factory calibration (a RETLW) in the last program
    word: keep it, CALL it and store W in the register.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Self

from lang.devices import Device

BANK_BYTES = 0x80


@dataclass(frozen=True)
class ConfigField:
    name: str
    word: int  # index into the configuration words
    mask: int
    value: int  # the field's bits in the words (value & ~mask == 0)
    symbol: str  # the header's name of that value, e.g. "_WDTE_OFF"


@dataclass(frozen=True)
class Part:
    device: Device
    facts: dict  # the device file's family key ("pic16")
    bank_bytes = BANK_BYTES  # the addresses one bank selection reaches: a variable stays in one
    eeprom_hex = (0x4200, 2)  # where a HEX file holds the data EEPROM: byte address, bytes per EEPROM byte
    pc_step = 1  # program counter counts per word

    @classmethod
    def of(cls, device: Device) -> Self:
        return cls(device, device.data[device.family])

    @property
    def title(self) -> str:
        return self.device.title

    @property
    def processor(self) -> str:
        return self.facts["processor"]

    @property
    def gpsim(self) -> str:
        return self.facts["gpsim"]

    @property
    def enhanced(self) -> bool:
        """The enhanced mid-range core (PIC12F1840, PIC16F1512...: compiler/pic16/enhanced/)."""
        return self.facts.get("core") == "enhanced"

    @property
    def gpsim_exact(self) -> bool:
        return self.facts["gpsim_exact"]

    @property
    def flash_words(self) -> int:
        return self.facts["flash_words"]

    @property
    def page_words(self) -> int:
        return self.facts["page_words"]

    @property
    def pages(self) -> int:
        return -(-self.flash_words // self.page_words)

    @property
    def eeprom(self) -> int:
        return self.facts["eeprom"]

    @property
    def banks(self) -> int:
        return self.facts["banks"]

    def reg(self, name: str) -> int:
        """A register's data address."""
        return self.facts["registers"][name]

    def has(self, name: str) -> bool:
        return name in self.facts["registers"]

    def bit(self, register: str, name: str) -> int:
        """A bit's position in its register, by the header's names."""
        return self.facts["bits"][register][name]

    def bits(self, register: str) -> dict[str, int]:
        """The named bits of a register (none for a register the part lacks)."""
        return self.facts["bits"].get(register, {})

    @staticmethod
    def bank(address: int) -> int:
        return address // BANK_BYTES

    def ram_ranges(self) -> list[range]:
        """The general-purpose bytes, each physical byte once."""
        return [range(first, last + 1) for first, last in self.facts["ram"]]

    @property
    def common(self) -> range | None:
        """The bytes every bank reaches, in bank-0 addresses."""
        span = self.facts["common"]
        return range(span[0], span[1] + 1) if span else None

    def physical(self, address: int) -> int:
        """The byte a data address reaches: itself, or what it mirrors."""
        for first, last, target in self.facts["mirrors"]:
            if first <= address <= last:
                return target + address - first
        return address

    def port(self, letter: str) -> int:
        """The data register of a Pin's port letter (PORTB, GPIO)."""
        return self.reg(self.facts["ports"][letter][0])

    def tris(self, letter: str) -> int:
        """The direction register of a Pin's port letter (TRISB, TRISIO)."""
        return self.reg(self.facts["ports"][letter][1])

    def latch(self, letter: str) -> int:
        """The register an output of a Pin's port letter is written in: its
        latch where the part has one apart (LATB), else the port."""
        names = self.facts["ports"][letter]
        return self.reg(names[2]) if len(names) > 2 else self.port(letter)

    def pullup_switch(self) -> tuple[int, int] | None:
        """(register, bit) whose clearing turns the weak pull-ups on (RBPU,
        GPPU; WPUEN on the enhanced core), None when the part has none."""
        for register, named in self.facts["bits"].items():
            for bit in ("NOT_RBPU", "NOT_GPPU", "NOT_WPUEN"):
                if bit in named:
                    return self.reg(register), named[bit]
        return None

    @property
    def config_words(self) -> tuple[tuple[int, int], ...]:
        """(program address, value) of each configuration word."""
        return tuple((w["address"], w["value"]) for w in self.facts["config"]["words"])

    @property
    def ldmicro_config(self) -> bool:
        """The configuration words are LDmicro's own for this part."""
        return self.facts["config"]["ldmicro"]

    def config_field(self, name: str) -> ConfigField | None:
        """A field of the configuration words ("FOSC", "WDTE", "MCLRE"...)."""
        entry = self.facts["config"]["fields"].get(name)
        return ConfigField(name, **entry) if entry else None

    def config_symbols(self, word: int = 0) -> list[str]:
        """The header symbols whose AND is configuration word `word`."""
        return [f["symbol"] for f in self.facts["config"]["fields"].values() if f["word"] == word]

    def feature(self, name: str, default=None):
        return self.facts["features"].get(name, default)
