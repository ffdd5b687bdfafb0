"""The scan-cycle simulator: the reference semantics of a ladder program.

`Simulator(program)` compiles the program once into Python code and runs it
scan by scan; see docs/semantics.md for every decision it makes.
"""

from .errors import SimulationError
from .peripherals import PwmOutput
from .runtime import ElementKey, Simulator

__all__ = ["ElementKey", "PwmOutput", "SimulationError", "Simulator"]
