"""A PIC18 part as the back end sees it: the `pic18` key of its device file
(lang/devices/pic18f*.json), read through the PIC16 back end's `Part` (the
same names: registers, bits, ports, configuration, features, Timer1, the
USART and Timer2 behind PWM). The facts come from gputils' processor header
(p18f4520.inc) and linker script (18f4520_g.lkr) and LDmicro's mcutable.h;
tests/test_pic18_parts.py checks them against those and against gpsim.

What differs from the `pic16` key:

ram, access, access_sfr
    the general-purpose RAM as [[first, last]] (banks of 256 bytes that BSR
    selects); the access RAM [first, last] that every instruction reaches
    without BSR (a = 0), as the SFRs from `access_sfr` up are.
ports
    a port letter -> [data register, direction register, output latch]:
    outputs are written in LATx (a read-modify-write of PORTx would copy
    the pins' levels into the latch).
config
    words: [{address, value}] the configuration bytes at 0x300001...
    (CONFIG1H...), each field with its header symbol: an HS crystal and
    CONFIG2L..CONFIG4L as LDmicro's HI-TECH C output for the PIC18F4520 sets
    them (its MCU table has no configuration for the part: 0xFFFF, "to see").
"""

from __future__ import annotations

from ..pic16.part import Part as Pic16Part

CONFIG_START, CONFIG_END = 0x300000, 0x30000D  # the configuration bytes the HEX carries (CONFIG1L..CONFIG7H)


class Part(Pic16Part):
    bank_bytes = 0x100
    eeprom_hex = (0xF00000, 1)  # the data EEPROM in a HEX file: a byte a byte
    pc_step = 2  # the program counter counts bytes

    @property
    def common(self) -> range:
        """The access RAM: reached whatever BSR holds."""
        first, last = self.facts["access"]
        return range(first, last + 1)

    @property
    def access_sfr(self) -> int:
        return self.facts["access_sfr"]

    def config_bytes(self, setting: int | None = None, clock_hz: int = 0) -> dict[int, int]:
        """Byte address -> value from CONFIG_START to CONFIG_END, as gpasm
        writes them (an address no configuration byte uses is 0xFF). The
        program's ConfigurationWord, when it sets one, is CONFIG1L:CONFIG1H
        (the oscillator), as LDmicro's HI-TECH C output for this part takes
        it (`__PROG_CONFIG(1, word)`); the other bytes are the part's. A
        clock beyond what the HS oscillator runs (25 MHz) selects HS with the
        PLL instead: the crystal is a quarter of the clock."""
        given = dict(self.config_words)
        if setting is not None:
            given.update({CONFIG_START: setting & 0xFF, CONFIG_START + 1: setting >> 8 & 0xFF})
        elif self.pll_crystal(clock_hz) is not None:
            osc = self.config_field("OSC")
            assert osc is not None  # every PIC18 part's CONFIG1H has one
            address = self.config_words[osc.word][0]
            given[address] = given[address] & ~osc.mask | self.feature("pll")["osc"]["value"]
        return {address: given.get(address, 0xFF) for address in range(CONFIG_START, CONFIG_END + 1)}

    def pll_crystal(self, clock_hz: int) -> int | None:
        """The crystal the PLL multiplies into the clock when the HS
        oscillator alone cannot run it, else None."""
        pll = self.feature("pll")
        return clock_hz // pll["factor"] if pll is not None and clock_hz > pll["above"] else None
