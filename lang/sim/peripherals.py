"""The simulated MCU peripherals: ADC readings, the UART, PWM outputs, the
EEPROM and the registers raw register access reaches. Their state lives outside the scan's variables because the user (or
a scenario) drives it from outside, and the EEPROM outlives a reset."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

from .uart import SentByte

ADC_MAX = 1023  # LDmicro's converters are 10 bits


@dataclass
class Uart:
    """A transmitter that stays busy for 10 bit times per byte at `baud`,
    and a receive queue the user fills."""

    baud: int
    received: deque = field(default_factory=deque)
    sent: list[SentByte] = field(default_factory=list)
    busy_until_us: float = 0.0

    @property
    def byte_time_us(self) -> float:
        return 10e6 / self.baud

    def ready(self, now_us: int) -> bool:
        return now_us >= self.busy_until_us

    def send(self, now_us: float, byte: int, wait: bool = False) -> None:
        """Start sending. A byte written while the transmitter is busy is
        lost, as the AVR ignores a write to UDR when UDRE is 0; a `wait`
        send is queued behind the byte in progress (the MCU busy-waits)."""
        start = now_us
        if start < self.busy_until_us:
            if not wait:
                return
            start = self.busy_until_us
        self.sent.append(SentByte(int(now_us), start, byte & 0xFF))
        self.busy_until_us = start + self.byte_time_us

    def available(self) -> bool:
        return bool(self.received)

    def take(self) -> int:
        return self.received.popleft()

    def text(self) -> bytes:
        return bytes(sent.byte for sent in self.sent)


@dataclass
class PwmOutput:
    duty: int  # in the element's resolution units (percent for 0-100%)
    freq_hz: int
    resolution: str
    on: bool = True


@dataclass
class Eeprom:
    """Starts erased (every byte 0xFF); PERSIST variables live here."""

    data: dict = field(default_factory=dict)

    def read(self, address: int, size: int) -> int:
        raw = bytes(self.data.get(address + i, 0xFF) for i in range(size))
        return int.from_bytes(raw, "little", signed=True)

    def write(self, address: int, size: int, value: int) -> None:
        raw = (value & ((1 << (8 * size)) - 1)).to_bytes(size, "little")
        for i, byte in enumerate(raw):
            self.data[address + i] = byte


@dataclass
class Peripherals:
    uart: Uart
    adc: dict = field(default_factory=dict)  # A name -> reading
    pwm: dict = field(default_factory=dict)  # P name -> PwmOutput
    eeprom: Eeprom = field(default_factory=Eeprom)
    # data address -> byte: the registers RSFR...TCSFR reach, plain storage with no hardware
    # behind it (a write stays until the program or the user changes it; unset cells read 0)
    registers: dict = field(default_factory=dict)

    def read_register(self, address: int) -> int:
        return self.registers.get(address & 0xFFFF, 0)

    def write_register(self, address: int, value: int) -> None:
        self.registers[address & 0xFFFF] = value & 0xFF

    def read_adc(self, name: str) -> int:
        return self.adc.get(name, 0)

    def set_pwm(self, name: str, duty: int, freq_hz: int, resolution: str) -> None:
        self.pwm[name] = PwmOutput(duty, freq_hz, resolution)

    def pwm_off(self, name: str) -> None:
        if name in self.pwm:
            self.pwm[name].on = False
