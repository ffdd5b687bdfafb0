"""The PIC18 back end: intermediate code and a Machine to a program-memory
image, its configuration bytes and a gpasm listing. Registers itself with
`compiler.backend`."""

from ..backend import register
from .backend import Pic18Backend

register(Pic18Backend())
