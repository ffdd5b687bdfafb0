"""`ladder build FILE`: compile a program for a part `lang.families` lists,
or to portable C.

With `--emit c` writes FILE.c and FILE.h beside FILE (or OUT.c and OUT.h),
and a ladder.h there when the folder has none (docs/c.md); the part plays no
part. Otherwise, on success prints `PART: flash N/M bytes (P%), RAM N/M bytes (P%)` (flash in
words for PIC) and the scan's worst case, `scan: at most N cycles = T µs of
the C ms cycle (P%)` (compiler/budget.py), and writes the Intel HEX (default:
beside FILE, same stem) and the assembly listing beside the HEX (the back
end's suffix: .lst for AVR). Problems are `path:line:col: error CODE message`
lines and exit 1; warnings go to stderr and do not stop the build.
"""

from __future__ import annotations

import sys
from pathlib import Path

from compiler.c.arduino import BOARDS
from lang import codes, config
from lang.devices import find_device
from lang.families import compiled, parts_text

from ._common import (
    EXIT_OK,
    EXIT_PROBLEMS,
    EXIT_USAGE,
    add_encoding,
    has_errors,
    load,
    report,
    write_output,
    writing,
)


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "build", help="compile a program to an Intel HEX file",
        description=f"Compile a ladder program for one of these parts: {parts_text()}. Writes OUT.hex and "
                    "the listing beside it (OUT.lst for AVR); exit 1 on errors, 2 when FILE cannot be read.")
    parser.add_argument("file", metavar="FILE")
    parser.add_argument("-o", "--output", metavar="OUT",
                        help="the file to write (default: FILE with .hex, or .c for --emit c)")
    parser.add_argument("--emit", choices=("hex", "c", "arduino"), default="hex",
                        help="what to write: an Intel HEX image for the part (default), portable C "
                             "(FILE.c and FILE.h, with a ladder.h when the folder has none), or an Arduino "
                             "sketch (the folder FILE/ with FILE.ino and the C; needs --board)")
    parser.add_argument("--board", choices=sorted(BOARDS), help="the Arduino board of --emit arduino")
    parser.add_argument("--keep-port-bits", action="store_true",
                        help="with --board, build a program drawn for another chip than the board's keeping each "
                             "pin's port bit (PD2 stays PD2: D2 on the Uno, D19 on the Mega); each moved pin is "
                             "shown as a warning")
    parser.add_argument("--target", metavar="PART",
                        help="compile for this part instead of the program's (LDmicro name or short name, "
                             "e.g. atmega328p); pins given by port name carry over, package pin numbers "
                             "must exist on the new part")
    add_encoding(parser)
    parser.set_defaults(func=run)


def run(args) -> int:
    import compiler

    if args.emit != "hex" and args.target is not None:
        print(f"ladder build: error: --target names a part; the C output (--emit {args.emit}) has none "
              "(an Arduino sketch takes --board)", file=sys.stderr)
        return EXIT_USAGE
    if (args.emit == "arduino") != (args.board is not None):
        print("ladder build: error: --board goes with --emit arduino, and --emit arduino needs it "
              f"({', '.join(sorted(BOARDS))})", file=sys.stderr)
        return EXIT_USAGE
    if args.keep_port_bits and args.board is None:
        print("ladder build: error: --keep-port-bits goes with --board", file=sys.stderr)
        return EXIT_USAGE
    if args.target is not None:
        device = find_device(args.target)
        if device is None or not compiled(device):
            known = "unknown part" if device is None else "a part ladder build does not compile"
            print(f"ladder build: error: --target {args.target}: {known}; it compiles for {parts_text()}",
                  file=sys.stderr)
            return EXIT_USAGE
    loaded = load(args.file, args.encoding)
    if loaded is None:
        return EXIT_USAGE
    if any(d.code == codes.UNREADABLE for d in loaded.diagnostics):
        report(args.file, loaded.diagnostics, stream=sys.stdout)
        return EXIT_USAGE
    if has_errors(loaded.diagnostics):
        report(args.file, loaded.diagnostics, stream=sys.stdout)
        return EXIT_PROBLEMS
    if args.emit != "hex":
        return _emit_c(args, loaded.program)
    build = _compiled(args.file, lambda: compiler.build(loaded.program, args.target, config.find(Path(args.file))))
    if isinstance(build, int):
        return build
    report(args.file, build.warnings, stream=sys.stderr)
    output = Path(args.output) if args.output else Path(args.file).with_suffix(".hex")
    if not writing(output, lambda: build.write(output)):
        return EXIT_USAGE
    print(build.summary())
    if build.budget is not None:
        print(build.budget.summary())
    return EXIT_OK


def _compiled(path: str, compile_it):
    """What `compile_it()` returns, or the exit status after reporting why it could not."""
    from compiler.errors import CompileError

    try:
        return compile_it()
    except config.ConfigError as bad:
        print(f"ladder build: {bad}", file=sys.stderr)
        return EXIT_USAGE
    except CompileError as problem:
        report(path, problem.diagnostics, stream=sys.stdout)
        return EXIT_PROBLEMS


def _emit_c(args, program) -> int:
    """--emit c: FILE.c, FILE.h (and ladder.h); --emit arduino: the sketch
    folder FILE/ with FILE.ino, FILE.c, FILE.h and ladder.h."""
    import compiler
    from compiler.c import default_ladder_h

    source = Path(args.file)
    if args.emit == "arduino":
        folder = Path(args.output) if args.output else source.with_suffix("")
        if folder.suffix == ".ino":
            # the Arduino IDE opens a sketch only in a folder of its own name: `-o blink/blink.ino` is that folder
            if folder.parent.name != folder.stem:
                print(f"ladder build: error: -o {args.output}: --emit arduino writes a sketch folder, and the "
                      f"Arduino IDE needs the .ino in a folder of the same name: -o {folder.with_suffix('')}",
                      file=sys.stderr)
                return EXIT_USAGE
            folder = folder.parent
        output = folder / f"{folder.name}.c"
    else:
        output = Path(args.output) if args.output else source.with_suffix(".c")
    if args.emit == "arduino":
        built = _compiled(args.file, lambda: compiler.build_arduino(program, output.stem, source.name, args.board,
                                                                    config.find(source), args.keep_port_bits))
    else:
        built = _compiled(args.file, lambda: (compiler.build_c(program, output.stem, source.name,
                                                               config.find(source)), None, []))
    if isinstance(built, int):
        return built
    sources, sketch, warnings = built
    report(args.file, warnings, stream=sys.stderr)
    header, ladder_h = output.with_suffix(".h"), output.with_name("ladder.h")
    files = [(output, sources.c), (header, sources.h)]
    if sketch is not None:
        files.insert(0, (output.with_suffix(".ino"), sketch))
    if not ladder_h.exists():
        files.append((ladder_h, default_ladder_h()))
    for path, text in files:
        if not write_output(path, text.encode()):
            return EXIT_USAGE
    written = ", ".join(str(path) for path, _ in files)
    if sketch is not None:
        board = BOARDS[args.board]
        print(f"wrote {written}: a complete sketch for the {board.title} (Arduino IDE, or arduino-cli compile "
              f"--fqbn {board.fqbn} {output.parent})")
        return EXIT_OK
    hooks = len(sources.hooks)
    print(f"wrote {written}: PlcCycle() is one scan, to call every {program.settings.cycle_us / 1000:g} ms; "
          f"your runtime provides {hooks} function{'s' * (hooks != 1)} ({header.name} lists them)")
    return EXIT_OK
