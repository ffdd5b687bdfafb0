"""The PIC16 back end: intermediate code and a Machine to a program-memory
image, its configuration word(s) and a gpasm listing. Registers itself with
`compiler.target`."""

from ..target import register
from .backend import Pic16Backend

register(Pic16Backend())
