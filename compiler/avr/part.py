"""An AVR part as the back end sees it: the `avr` key of its device file
(lang/devices/atmega*.json, taken from avr-libc's headers) behind names.

Register addresses are data-space addresses. Below 0x60 a register is also
reachable with IN/OUT (I/O address = data address - 0x20), below 0x40 with
the bit instructions SBI/CBI/SBIS/SBIC; from 0x60 on ("extended I/O", such as
the UART and timer registers of the ATmega328P or PORTF/G of the ATmega128)
only LDS/STS reach it. On the reduced core (`"core": "reduced"`, the
ATtiny10) the I/O registers are data addresses 0x00..0x3F themselves
(`isa.Core.io_offset`). Bit positions that are the same on every part are
constants here; tests/test_compiler_parts.py checks them against avr-libc.

Its `cycle_timer` (Timer1 in CTC mode: clock divider, prescalers, counts),
`baud` (the UART's dividers with their U2X bit, the largest UBRR, the 2 %
error LDmicro tolerates) and, for each 8-bit timer's PWM output in `pwm`,
its prescalers and period are what lang/hardware.py reads, for the checks
and this back end alike.
"""

from __future__ import annotations

from dataclasses import dataclass

from lang.devices import Device

from . import isa

# bit positions common to all the parts
WGM12 = 3  # TCCR1B: clear timer on compare match
TXC, UDRE, RXC, U2X = 6, 5, 7, 1  # UCSRA
RXEN, TXEN = 4, 3  # UCSRB
URSEL = 7  # UCSRC/UBRRH shared address: 0 selects UBRRH
ADEN, ADSC = 7, 6  # ADCSRA
EERE, EEWE, EEMWE = 0, 1, 2  # EECR (EEPE/EEMPE on the newer parts)


@dataclass(frozen=True)
class Part:
    device: Device
    avr: dict

    @classmethod
    def of(cls, device: Device) -> Part:
        return cls(device, device.data["avr"])

    @property
    def title(self) -> str:
        return self.device.title

    @property
    def mmcu(self) -> str:
        return self.avr["mmcu"]

    @property
    def flash(self) -> int:
        return self.avr["flash"]

    @property
    def ram_start(self) -> int:
        return self.avr["ram"]["start"]

    @property
    def ram_end(self) -> int:
        """The last RAM address (the stack starts there)."""
        return self.avr["ram"]["start"] + self.avr["ram"]["size"] - 1

    @property
    def long_jumps(self) -> bool:
        return self.avr["long_jumps"]

    @property
    def core(self) -> isa.Core:
        return isa.CORES[self.avr.get("core", "classic")]

    @property
    def has_mul(self) -> bool:
        """MUL and its kin: not on the ATtiny85's core nor the reduced one."""
        return self.avr.get("mul", True) and self.core.has("mul")

    @property
    def measures_stack(self) -> bool:
        """The stack's depth is read from the image (stack.py): the ATtiny10,
        whose 32 bytes of RAM cannot spare the other parts' fixed reserve."""
        return self.avr.get("stack") == "measured"

    @property
    def stack_reserve(self) -> int:
        """RAM kept for the stack before the code is written: none where the
        image is measured, else room for eight levels of calls with their
        saved registers."""
        return 0 if self.measures_stack else 8 * (self.pc_bytes + 2) + 4 * self.pc_bytes + 8

    @property
    def pc_bytes(self) -> int:
        return self.avr["pc_bytes"]

    def reg(self, name: str) -> int:
        """A register's data address."""
        return self.avr["registers"][name]

    def has(self, name: str) -> bool:
        return name in self.avr["registers"]

    def port(self, kind: str, letter: str) -> int:
        """PIN, DDR or PORT register of a port letter."""
        return self.reg(f"{kind}{letter}")

    @property
    def uart(self) -> dict | None:
        return self.avr.get("uart")

    @property
    def adc(self) -> dict | None:
        return self.avr.get("adc")

    def pwm(self, unit: str) -> dict | None:
        return self.avr["pwm"].get(unit)
