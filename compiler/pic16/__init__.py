"""The PIC16 back end: intermediate code and a Machine to a program-memory
image, its configuration word(s) and a gpasm listing, for the mid-range
parts and, through compiler/pic16/enhanced/, the enhanced mid-range ones.
Registers itself with `compiler.backend`."""

from ..backend import register
from .backend import Pic16Backend
from .enhanced.backend import compile_enhanced

register(Pic16Backend(compile_enhanced))
