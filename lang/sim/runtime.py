"""The Simulator: a compiled program, its state, simulated time and the
peripherals, behind the API the command line and the language server use.

Time is counted in scans: scan k runs at k x cycle time, the first at 0.
`energized()` reports the scan that ran last; `step` and `run_for` run all
but their last scan with the untraced code, so tracing costs one scan per call.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..diagnostics import error
from ..model import Program
from ..numbers import wrap
from .compile import Compiled, compile_program
from .errors import Fault, SimulationError
from .peripherals import ADC_MAX, Peripherals, PwmOutput, Uart


@dataclass(frozen=True)
class ElementKey:
    """An element's place: its rung's index and its index among the rung's
    elements in evaluation order (series left to right, branches top down)."""

    rung: int
    index: int


def register_address(name: str) -> int | None:
    """The data address a `#` name with a number (`#0x23`, `#35`) gives, else None."""
    if not name.startswith("#"):
        return None
    try:
        address = int(name[1:], 0)
    except ValueError:
        return None
    return address if 0 <= address <= 0xFFFF else None


class Simulator:
    def __init__(self, program: Program):
        self.peripherals = Peripherals(Uart(program.settings.baud))
        self._compiled = compile_program(program, self.peripherals)
        self._state = [slot.init for slot in self._compiled.slots]
        self._powered = [False] * len(self._compiled.elements)
        self.scan_count = 0

    # --- the program ---------------------------------------------------------------

    @property
    def program(self) -> Program:
        return self._compiled.program

    @property
    def cycle_us(self) -> int:
        return self.program.settings.cycle_us

    @property
    def time_ms(self) -> float:
        """The time of the next scan to run."""
        return self.scan_count * self.cycle_us / 1000

    def reload(self, program: Program) -> None:
        """Switch to an edited program. Names that still exist keep their
        values (resized if their size changed), and so does the hidden memory
        of an element that kept its kind and place; time, the UART, ADC
        readings, PWM outputs and the EEPROM carry over."""
        old_compiled, old_state = self._compiled, self._state
        compiled = compile_program(program, self.peripherals)
        state = [slot.init for slot in compiled.slots]
        for i, slot in enumerate(compiled.slots):
            j = old_compiled.index.get(slot.key)
            if j is None or old_compiled.slots[j].kind != slot.kind:
                continue
            value = old_state[j]
            state[i] = wrap(int(value), slot.size) if slot.kind == "int" else value
        self._compiled, self._state = compiled, state
        self._powered = [False] * len(compiled.elements)

    def reset(self, keep_eeprom: bool = True) -> None:
        """A power-on reset: every variable back to its start value, time 0,
        the UART and PWM outputs cleared; the EEPROM is kept unless asked
        (so PERSIST variables come back) and the ADC readings, which are
        external voltages, stay."""
        self._state = [slot.init for slot in self._compiled.slots]
        self._powered = [False] * len(self._compiled.elements)
        self.scan_count = 0
        uart = self.peripherals.uart
        uart.received.clear()
        uart.sent.clear()
        uart.busy_until_us = 0.0
        self.peripherals.pwm.clear()
        if not keep_eeprom:
            self.peripherals.eeprom.data.clear()

    # --- running -------------------------------------------------------------------

    def step(self, n: int = 1) -> None:
        """Run n scans. A fault raises SimulationError; the failing scan
        counts as run and keeps what it did before the fault."""
        if n <= 0:
            return
        if n > 1:
            self._run(self._compiled.run, n - 1)
        self._powered = [False] * len(self._compiled.elements)
        self._run(self._compiled.run_traced, 1)

    def run_for(self, ms: float) -> None:
        """Run every scan whose time falls within the next `ms` milliseconds."""
        span_us = round(ms * 1000)
        end_us = self.scan_count * self.cycle_us + span_us
        n = -(-end_us // self.cycle_us) - self.scan_count
        self.step(max(n, 0))

    def _run(self, fn, n: int) -> None:
        t0 = self.scan_count * self.cycle_us
        try:
            done = fn(self._state, n, t0, self._powered)
        except Fault as fault:
            self._fail(fault, t0)
        self.scan_count += done

    def _fail(self, fault: Fault, t0: int) -> None:
        # the generated code stored its state and how many scans it finished
        self.scan_count += fault.done + 1
        rung, _, element = self._compiled.elements[fault.element]
        time_ms = (self.scan_count - 1) * self.cycle_us / 1000
        message = f"{fault.message} (rung {rung + 1}, scan {self.scan_count - 1}, at {time_ms:g} ms)"
        raise SimulationError([error(fault.code, message, element.span)], self.scan_count - 1,
                              time_ms) from None

    # --- inputs and state ------------------------------------------------------------

    def _slot(self, name: str) -> int:
        index = self._compiled.index.get(name)
        if index is None or name.startswith(("$", "~")):
            raise KeyError(f"the program has no variable or bit named '{name}'")
        return index

    def set_input(self, name: str, value) -> None:
        """Set a bit (an X input, or any relay or output) to 0 or 1."""
        index = self._slot(name)
        if self._compiled.slots[index].kind != "bit":
            raise KeyError(f"'{name}' is an integer variable, not a bit: use set_variable")
        self._state[index] = bool(value)

    def set_variable(self, name: str, value: int) -> None:
        """Set an integer variable (truncated to its size) or a bit."""
        index = self._slot(name)
        slot = self._compiled.slots[index]
        self._state[index] = bool(value) if slot.kind == "bit" else wrap(int(value), slot.size)

    def set(self, name: str, value: int) -> None:
        """Set whatever `name` is: an ADC reading when a READ_ADC reads it,
        a register of the raw register access for `#` and an address the
        program has no variable of (`#0x23`), else a bit or an integer variable."""
        address = register_address(name)
        if any(e.kind == "READ_ADC" and e.args.get("name") == name for _, _, e in self._compiled.elements):
            self.set_adc(name, value)
        elif address is not None and name not in self._compiled.index:
            self.set_register(address, value)
        else:
            self.set_variable(name, value)

    def set_register(self, address: int, value: int) -> None:
        """The byte RSFR, TSFR and TCSFR read at data address `address`
        until the program writes it (what the hardware would show there)."""
        if not 0 <= int(value) <= 0xFF:
            raise ValueError(f"register value {value} out of range 0..255")
        self.peripherals.write_register(address, int(value))

    def register(self, address: int) -> int:
        """The byte at data address `address` of the raw register access."""
        return self.peripherals.read_register(address)

    def set_adc(self, name: str, value: int) -> None:
        """The reading READ_ADC will copy into `name` (0..1023)."""
        if not 0 <= int(value) <= ADC_MAX:
            raise ValueError(f"ADC reading {value} out of range 0..{ADC_MAX}")
        self.peripherals.adc[name] = int(value)

    def uart_receive(self, data: bytes | str) -> None:
        """Bytes arriving on the UART, available from the next scan on."""
        if isinstance(data, str):
            data = data.encode("latin-1")
        self.peripherals.uart.received.extend(data)

    def value(self, name: str) -> int:
        """A variable's or bit's value, or the byte of a register of the raw
        register access (`#0x25`, an address the program has no variable of)."""
        address = register_address(name)
        if address is not None and name not in self._compiled.index:
            return self.register(address)
        index = self._slot(name)
        return int(self._state[index])

    def width(self, name: str) -> int:
        """The bits `value(name)` holds: 1 for a bit, 8 for a register."""
        if name not in self._compiled.index and register_address(name) is not None:
            return 8
        slot = self._compiled.slots[self._slot(name)]
        return 1 if slot.kind == "bit" else 8 * slot.size

    def knows(self, name: str) -> bool:
        """Whether `name` is a signal to set, watch or expect: a variable or
        bit of the program, or a register of the raw register access."""
        return name in self.variables() or (register_address(name) is not None
                                            and name not in self._compiled.index)

    def variables(self) -> dict[str, int]:
        """Every bit and integer of the program (not the hidden ones)."""
        return {slot.key: int(self._state[i]) for i, slot in enumerate(self._compiled.slots)
                if not slot.key.startswith(("$", "~"))}

    def bits(self) -> list[str]:
        return [s.key for s in self._compiled.slots if s.kind == "bit" and not s.key.startswith(("$", "~"))]

    def energized(self) -> dict[ElementKey, bool]:
        """Whether power flowed out of each element the last time it ran in
        the last scan (False for elements that scan skipped)."""
        return {ElementKey(rung, index): self._powered[number]
                for number, (rung, index, _) in enumerate(self._compiled.elements)}

    # --- peripherals -------------------------------------------------------------------

    def uart_output(self) -> bytes:
        """Every byte transmitted so far."""
        return self.peripherals.uart.text()

    def uart_sent(self) -> list[tuple[float, int]]:
        """(time in ms the byte started, byte) for every transmitted byte."""
        return [(sent.start_us / 1000, sent.byte) for sent in self.peripherals.uart.sent]

    def pwm(self) -> dict[str, PwmOutput]:
        return dict(self.peripherals.pwm)

    @property
    def compiled(self) -> Compiled:
        return self._compiled

