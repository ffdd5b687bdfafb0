"""Writing a Program as text in LDmicro's layout: the formatter.

The diagram is LDmicro's Export as Text (17-character cells, end-of-line
elements right-justified, `%04d` rung numbers, the END rung), except that
nothing is truncated: a cell that needs more room widens, and a rung wider
than the diagram grows alone, so an edit inside one rung changes only that
rung's lines."""

from __future__ import annotations

from decimal import Decimal

from ..devices import find_device
from ..drawing import CELL, Box, center_offset, with_wires
from ..iolist import MODBUS_TYPES, io_list
from ..model import Element, Program, Rung
from . import details
from .layout import Grid, layout, natural_width

COMMENT_MARGIN = 8  # LDmicro keeps a comment line 8 characters short of the right rail


def element_text(element: Element) -> tuple[str, str, bool]:
    """The element's name line text, its glyph, and whether the glyph is a
    box (LDmicro's field formatter: no wire before it, one after)."""
    instruction = element.spec
    args = {**instruction.consts, **element.args}
    kinds = instruction.kinds
    top = instruction.top.render(args, kinds, instruction.cells) if instruction.top else ""
    glyph = instruction.glyph.render(args, kinds, instruction.cells) if instruction.glyph else ""
    return top, glyph, isinstance(instruction.glyph, Box)


def _needed_width(element: Element) -> int:
    """Characters the element needs so that no text is cut: the name line
    keeps its last character free for a connector; a glyph may fill its slot
    (LDmicro draws a 17-character glyph with no wire either side)."""
    if element.kind == "PLACEHOLDER":
        return CELL
    top, glyph, boxed = element_text(element)
    return max(CELL * element.spec.cells, len(top) + 1, len(glyph) + (1 if boxed else 0))


def diagram_width(program: Program) -> int:
    """LDmicro's C: the widest rung, end-of-line elements counted as one, and
    enough cells for the longest comment line (so no comment pushes its rung
    past the right rail)."""
    widths = [natural_width(rung.circuit) for rung in program.rungs if not rung.is_comment]
    comments = [-(-(len(part) + 3 + COMMENT_MARGIN) // CELL) for rung in program.rungs if rung.is_comment
                for part in comment_text(rung).split("\n")]
    return max(widths + comments, default=1)


def comment_text(rung: Rung) -> str:
    """The text of a comment rung."""
    comment = rung.circuit.items[0]
    assert isinstance(comment, Element)  # is_comment: the rung holds its COMMENT alone
    return str(comment.args.get("text", ""))


def margin_width(rungs: int) -> int:
    """The width of the rung numbers' margin: LDmicro's four digits, wider
    for a program of 10,000 rungs or more (LDmicro loads 9,999), so that every
    line of the diagram keeps its left rail in one column."""
    return max(4, len(str(rungs)))


def render_rung(rung: Rung, number: int, columns: int, margin: int = 4) -> list[str]:
    """The lines of one rung, without the separator line after it; `margin`:
    `margin_width` of the program's rungs."""
    if rung.is_comment:
        return _render_comment(comment_text(rung), number, columns, margin)
    grid = layout(rung.circuit, max(columns, natural_width(rung.circuit)))
    widths = _column_widths(grid)
    offsets = [0]
    for width in widths:
        offsets.append(offsets[-1] + width)
    total = offsets[-1]
    lines = [[" "] * total for _ in range(3 * grid.height)]

    def write(line: int, col: int, text: str) -> None:
        for i, ch in enumerate(text):
            if 0 <= col + i < total:
                lines[line][col + i] = ch

    for placed in grid.placed:
        start = offsets[placed.col]
        slot = offsets[placed.col + placed.cells] - start
        symbol = 3 * placed.row + 1
        if placed.element is None:
            write(symbol, start, "-" * slot)
            continue
        if placed.element.kind == "PLACEHOLDER":
            write(symbol, start, "--")
            continue
        top, glyph, _ = element_text(placed.element)
        if top:
            write(symbol - 1, start + max(0, center_offset(slot, len(top))), top)
        write(symbol, start, with_wires(glyph, slot))
    rail_junction_rows: set[int] = set()
    for k, row in grid.connectors:
        if k < 0:
            rail_junction_rows.update((row - 1, row))
            continue
        x = offsets[k + 1] - 1
        write(3 * row - 2, x, "+")
        write(3 * row + 1, x, "+")
        write(3 * row - 1, x, "|")
        write(3 * row, x, "|")
    result = []
    for index, chars in enumerate(lines):
        label = f"{number:0{margin}d}" if index == 1 else " " * margin
        rail = "|+" if index % 3 == 1 and index // 3 in rail_junction_rows else "||"
        result.append(label + rail + "".join(chars) + "||")
    return result


def _column_widths(grid: Grid) -> list[int]:
    count = max([p.col + p.cells for p in grid.placed] + [grid.columns])
    widths = [CELL] * count
    for placed in grid.placed:
        if placed.element is None:
            continue
        need = _needed_width(placed.element)
        have = sum(widths[placed.col:placed.col + placed.cells])
        if need > have:
            widths[placed.col + placed.cells - 1] += need - have
    # a glyph filling its slot would lose its last character to a junction there
    for placed in grid.placed:
        if placed.element is None or placed.element.kind == "PLACEHOLDER":
            continue
        last = placed.col + placed.cells - 1
        if ((last, placed.row) in grid.connectors or (last, placed.row + 1) in grid.connectors) and \
                len(element_text(placed.element)[1]) >= sum(widths[placed.col:last + 1]):
            widths[last] += 1
    return widths


def _render_comment(text: str, number: int, columns: int, margin: int) -> list[str]:
    parts = [" ; " + part for part in text.split("\n")]
    width = max([CELL * columns] + [len(p) + COMMENT_MARGIN for p in parts])
    rows = max(1, -(-len(parts) // 3)) if len(parts) > 2 else 1
    lines = []
    for index in range(3 * rows):
        body = parts[index] if index < len(parts) else ""
        label = f"{number:0{margin}d}" if index == 1 else " " * margin
        lines.append(label + "||" + body.ljust(width) + "||")
    return lines


def render_diagram(program: Program, columns: int | None = None) -> list[str]:
    """The LADDER DIAGRAM block. `columns` keeps a file's existing width
    (its END rung shows it); by default the widest rung sets it."""
    # a file narrower than its widest rung (typed by hand) gets the width that rung needs
    columns = max(columns or 0, diagram_width(program))
    width = CELL * columns
    margin = margin_width(len(program.rungs))
    blank = " " * margin + "||" + " " * width + "||"
    lines = [blank]
    pending = None  # the number of an empty rung, shown on the next line
    for number, rung in enumerate(program.rungs, 1):
        drawn = render_rung(rung, number, columns, margin) if rung.circuit.items else []
        if pending is not None:
            drawn = drawn or [blank]
            drawn[0] = pending + drawn[0][margin:]
            pending = None
        lines.extend(drawn)
        lines.append(blank)
        if not rung.circuit.items:
            pending = f"{number:0{margin}d}"
    end = with_wires("[END]", CELL) + "-" * (width - CELL)
    lines += [(pending or " " * margin) + blank[margin:], f"{len(program.rungs):{margin}d}||{end}||", blank, blank]
    return lines


def _format_mhz(hertz: int) -> str:
    text = f"{hertz / 1e6:.9g}"
    if Decimal(text) * 1000000 != hertz:
        text = format((Decimal(hertz) / 1000000).normalize(), "f")
    return text


def header_line(program: Program) -> str:
    settings = program.settings
    timing = f"{_format_mhz(settings.crystal_hz)} MHz crystal, {settings.cycle_us / 1000:.3f} ms cycle time"
    if settings.mcu:
        return f"for '{settings.mcu}', {timing}"
    return f"no MCU assigned, {timing}"


def io_rows(program: Program) -> list[str]:
    """The I/O table: LDmicro's I/O list, in its order and with its type
    names; a Modbus name takes no pin, so shows none."""
    device = find_device(program.settings.mcu) if program.settings.mcu else None
    rows = []
    for io in io_list(program):
        assignment = program.pins.get(io.name)
        pin_text, port, label = "", "", ""
        if assignment is not None and assignment.assigned:
            pin_text = str(assignment.pin)
            pin = device.pin(assignment.pin) if device else None
            if pin is not None and pin.is_io:
                port, label = pin.name, pin.label
        elif program.settings.mcu and io.type not in MODBUS_TYPES:
            pin_text = "(not assigned)"
        row = f"  {io.name:<27}| {io.type_name:<19}| {pin_text:>3} | {port:<5} | {label}"
        rows.append(row.rstrip())
    return rows


def render_program(program: Program, columns: int | None = None) -> str:
    lines = ["LDmicro export text.", header_line(program), "", "LADDER DIAGRAM:"]
    lines += render_diagram(program, columns)
    lines += ["", "I/O ASSIGNMENT:",
              "  Name                       | Type               | Pin | Port | Pin name",
              " ----------------------------+--------------------+-----+------+-----------"]
    lines += io_rows(program)
    lines += ["", "VAR LIST:"]
    lines += [f"  {size:3d} bytes {name}{program.var_notes.get(name, '')}"
              for name, size in sorted(program.var_sizes.items())]
    settings = details.write_settings(program)
    if settings:
        lines += ["", "SETTINGS:"] + settings
    extra = details.write_details(program)
    if extra:
        lines += ["", "DETAILS:"] + extra
    properties = [line.text.strip() for line in program.properties]
    while properties and not properties[-1]:
        properties.pop()
    while properties and not properties[0]:
        properties.pop(0)
    if properties:
        lines += ["", "PROPERTIES:"] + [f"  {text}" if text else "" for text in properties]
    return "\n".join(line.rstrip() for line in lines) + "\n"
