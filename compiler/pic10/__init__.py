"""The baseline PIC10F200/202 back end: intermediate code and a Machine to
12-bit program words, the configuration word and a gpasm listing. Registers
itself with `compiler.backend`."""

from ..backend import register
from .backend import Pic10Backend

register(Pic10Backend())
