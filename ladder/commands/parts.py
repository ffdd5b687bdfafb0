"""`ladder parts`: the parts with pin data."""

from __future__ import annotations

from lang.devices import all_devices

from ._common import EXIT_OK


def register(subparsers) -> None:
    parser = subparsers.add_parser("parts", help="list the supported parts",
                                   description="List the parts with pin data: short name, package, "
                                               "family and LDmicro's name.")
    parser.set_defaults(func=run)


def run(args) -> int:
    for device in all_devices():
        print(f"{device.part:<12} {device.package:<10} {device.family:<6} {device.ldmicro_name}")
    return EXIT_OK
