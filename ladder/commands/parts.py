"""`ladder parts`: the parts with pin data, and whether `ladder build`
compiles for each (lang/families.py)."""

from __future__ import annotations

from lang.devices import all_devices
from lang.families import compiled

from ._common import EXIT_OK

_ROW = "{:<12} {:<10} {:<6} {:<5} {}"


def register(subparsers) -> None:
    parser = subparsers.add_parser("parts", help="list the supported parts",
                                   description="List the parts with pin data: short name, package, "
                                               "family, whether `ladder build` compiles for it and "
                                               "LDmicro's name.")
    parser.set_defaults(func=run)


def run(args) -> int:
    print(_ROW.format("part", "package", "family", "build", "LDmicro name"))
    for device in all_devices():
        print(_ROW.format(device.part, device.package, device.family, "yes" if compiled(device) else "no",
                          device.ldmicro_name))
    return EXIT_OK
