"""The checks: one rule per module, one diagnostic code per rule.

Each rule module has `CODE = register(...)` (its code, summary and
documentation, see `lang.codes`) and `check(program, index)` returning its
diagnostics. `RULES` below lists them all; `check_program` builds the shared
`ProgramIndex` once and runs every rule on it. docs/diagnostics.md documents
every code.
"""

from __future__ import annotations

from ..diagnostics import Diagnostic
from ..model import Program
from . import (
    adc_prefix,
    adc_written,
    after_eol_parallel,
    bad_literal,
    bit_as_integer,
    coil_on_input,
    coil_prefix,
    comment_alone,
    constant_range,
    contact_prefix,
    counter_prefix,
    cycle_zero,
    empty_rung,
    eol_not_last,
    fstring_escape,
    fstring_multiple,
    fstring_var,
    gosub_number,
    gosub_target,
    goto_target,
    label_unique,
    literal_dest,
    lut_empty,
    lut_too_long,
    master_relay,
    modbus_register,
    never_written,
    operand_prefix,
    part_no_data,
    part_unknown,
    pin_no_adc,
    pin_no_pwm,
    pin_non_io_name,
    pin_not_io,
    pin_not_on_part,
    pin_shared,
    pin_uart,
    pin_unassigned,
    pin_unused,
    pwl_empty,
    pwl_order,
    pwl_overflow,
    pwm_conflict,
    pwm_prefix,
    relay_never_written,
    res_prefix,
    res_unassigned,
    rung_without_elements,
    shift_range,
    subprog_alone,
    subprog_pairs,
    subprog_unique,
    table_conflict,
    target_adc,
    target_layer,
    target_pwm,
    target_uart,
    timer_adjust_big,
    timer_adjust_total,
    timer_delay,
    timer_name_used,
    timer_prefix,
    timer_shared,
    timer_too_long,
    timer_too_short,
    timer_written,
    truncated_name,
)
from .index import ProgramIndex

# Every rule, grouped as the codes are: names, structure, values, pins, targets.
RULES = (
    truncated_name,
    contact_prefix,
    coil_on_input,
    coil_prefix,
    timer_prefix,
    counter_prefix,
    res_prefix,
    pwm_prefix,
    adc_written,
    adc_prefix,
    bit_as_integer,
    modbus_register,
    operand_prefix,
    timer_shared,
    timer_name_used,
    timer_written,
    pwm_conflict,
    table_conflict,
    res_unassigned,
    relay_never_written,
    never_written,
    eol_not_last,
    after_eol_parallel,
    comment_alone,
    subprog_alone,
    subprog_pairs,
    subprog_unique,
    goto_target,
    gosub_target,
    gosub_number,
    label_unique,
    master_relay,
    empty_rung,
    rung_without_elements,
    constant_range,
    shift_range,
    literal_dest,
    bad_literal,
    pwl_empty,
    pwl_order,
    pwl_overflow,
    lut_empty,
    lut_too_long,
    timer_delay,
    timer_too_short,
    timer_adjust_total,
    timer_adjust_big,
    timer_too_long,
    cycle_zero,
    fstring_escape,
    fstring_multiple,
    fstring_var,
    pin_shared,
    pin_not_on_part,
    pin_not_io,
    pin_no_adc,
    pin_no_pwm,
    pin_uart,
    pin_unassigned,
    part_no_data,
    part_unknown,
    pin_non_io_name,
    pin_unused,
    target_layer,
    target_adc,
    target_uart,
    target_pwm,
)

__all__ = ["RULES", "ProgramIndex", "check_program", "position"]


def position(diagnostic: Diagnostic) -> tuple:
    """Sort key: source position (diagnostics without one first), then code."""
    span = diagnostic.span
    if span is None:
        return (-1, -1, diagnostic.code, diagnostic.message)
    return (span.line, span.col, diagnostic.code, diagnostic.message)


def check_program(program: Program, for_build: bool = False) -> list[Diagnostic]:
    """Every rule's diagnostics for the program, sorted by position;
    `for_build` when it is about to be compiled (`ladder build`, compile on
    save), where a rule may be stricter (LD501)."""
    index = ProgramIndex(program, for_build)
    found: list[Diagnostic] = []
    for rule in RULES:
        found.extend(rule.check(program, index))
    found.sort(key=position)
    return found
