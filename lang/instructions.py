"""The instruction table: everything the tools know about each instruction.

One entry per instruction: its `.ld` keyword and legacy aliases, its operands
(kind, allowed name prefixes, whether the instruction reads or writes them,
the default a legacy `.ld` line leaves out), its two-line drawing, whether it
must end its rung, which layers support it, and the hover text. Parsing,
checks, hover, rendering, simulation and code generation all read it from here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .drawing import Box, Text, box, text

# Layers that may support an instruction; a layer that does not is a located
# diagnostic, never a crash or a silent gap.
LAYERS = ("parse", "check", "sim", "avr", "pic16", "pic18", "pic10", "c")
ALL = frozenset(LAYERS)
DRAWN_ONLY = frozenset({"parse", "check"})
SIM_ONLY = frozenset({"parse", "check", "sim"})


@dataclass(frozen=True)
class Field:
    name: str
    kind: str  # bit var operand label delay edge int flag token text values points
    prefixes: str = ""  # allowed first letters of a name ("" = any)
    access: str = "read"  # read | write | rw | "" (not a variable)
    default: object = None  # what a short legacy .ld line or an undrawn detail leaves
    drawn: bool = True  # shown in the text drawing (else kept in DETAILS)
    optional: bool = False  # a trailing .ld operand some files leave out: absent is None, written back absent
    # how LDmicro's I/O list takes the name (lang.iolist): "bit" by its first letter of XYPIM, "auto"
    # by its first letter of XYAMH, "adc"/"pwm" whatever its letter, "spi"/"i2c" a bus's pins
    io: str = ""

    def __post_init__(self):
        if self.kind == "bit" and not self.io:
            object.__setattr__(self, "io", "bit")


@dataclass(frozen=True)
class Instruction:
    key: str  # model kind; also the .ld keyword LDmicro 5.4 writes
    title: str
    fields: tuple[Field, ...]
    top: Text | Box | None
    glyph: Text | Box | None
    doc: str
    category: str
    eol: bool = False  # must be the last element of its rung (right-justified)
    cells: int = 1
    aliases: tuple[str, ...] = ()  # other .ld keywords read as this one
    ld_form: str = "fields"  # how the .ld line is laid out (see lang.ldfile)
    consts: dict = field(default_factory=dict)  # fixed values the drawing uses (a comparison's "op")
    support: frozenset = ALL
    # what several layers treat alike: "timer" (a T variable counting scans to a delay),
    # "counter" (a C variable with a limit and a start value), "jump" (changes where the scan goes)
    family: str = ""
    # LDmicro's editor default for a new element, as an .ld line: what the editor inserts, and the
    # example the reference draws ("" for the bare keyword)
    example: str = ""
    # how messages name it: the word LDmicro draws ("" for the key with blanks: "READ ADC")
    label: str = ""
    # the operands LDmicro's variable check (CheckVariableNames) counts as written by a general
    # instruction (its ANY flag; lang/checks/varflags.py), some of them read ones (IF_BIT_SET's)
    ldmicro_written: tuple[str, ...] = ()

    def __post_init__(self):
        object.__setattr__(self, "example", self.example or self.key)
        object.__setattr__(self, "label", self.label or self.key.replace("_", " "))

    @property
    def kinds(self) -> dict[str, str]:
        """Field kinds for the drawing; `?` marks a field that may be empty."""
        return {f.name: f.kind + ("?" if f.default == "" else "") for f in self.fields}

    def get_field(self, name: str) -> Field:
        for f in self.fields:
            if f.name == name:
                return f
        raise KeyError(name)

    def supports(self, layer: str) -> bool:
        return layer in self.support


def bit(name: str, prefixes: str, access: str = "read") -> Field:
    return Field(name, "bit", prefixes, access)


def var(name: str, access: str = "write", prefixes: str = "", io: str = "") -> Field:
    return Field(name, "var", prefixes, access, io=io)


def operand(name: str, io: str = "") -> Field:
    return Field(name, "operand", io=io)


def flag(name: str, default: int = 0, drawn: bool = True) -> Field:
    return Field(name, "flag", access="", default=default, drawn=drawn)


def integer(name: str, default: int | None = None, drawn: bool = True) -> Field:
    return Field(name, "int", access="", default=default, drawn=drawn)


def token(name: str, default: str | None = None, drawn: bool = True) -> Field:
    # an undrawn token comes back from a text export with its default, and an empty
    # one would shift every later field of the .ld line: it needs LDmicro's own default
    if default is None and not drawn:
        raise ValueError(f"the undrawn token {name!r} needs a default")
    return Field(name, "token", access="", default=default, drawn=drawn)


def label(name: str) -> Field:
    return Field(name, "label", access="")


_TABLE: list[Instruction] = []


def define(*args, **kwargs) -> None:
    _TABLE.append(Instruction(*args, **kwargs))


# --- contacts and coils --------------------------------------------------------

define(
    "CONTACTS", "contact", (bit("name", "XYRPIM"), flag("negated"), flag("set1")),
    text("{name}"), text("{set1?^|-}]{negated?/| }[-"),
    "Passes power when its bit is 1 (normally open, `] [`) or when it is 0 "
    "(normally closed, `]/[`). The bit is an input pin (X), an output latch (Y), "
    "an internal relay (R), a PWM pin (P) or a Modbus bit (I, M). `^` marks an "
    "X input that the simulator starts at 1.",
    "contacts",
    example='CONTACTS Xnew 0 0', label='contact',
)
define(
    "COIL", "coil",
    (bit("name", "YRM", "write"), Field("type", "coil", access="", default=" ")),
    text("{name}"), text("({type})"),
    "Writes its bit from the rung: `( )` copies the rung state, `(/)` its "
    "inverse, `(S)` sets the bit while the rung is true, `(R)` clears it, `(T)` "
    "toggles it on each rising edge of the rung. Must end its rung.",
    "coils", eol=True, ld_form="coil",
    example='COIL Ynew 0 0 0 0', label='coil',
)

# --- edges and oscillator ---------------------------------------------------------

_EDGES = {
    # LDmicro's name-line and glyph strings, placed by centring like any other
    "OSR": ("one-shot rising", "    _     _    ", "[_/ OSR_/ \\_]",
            "Passes power for exactly one scan when its input goes from 0 to 1."),
    "OSF": ("one-shot falling", "  _       _    ", "[ \\_OSF_/ \\_]",
            "Passes power for exactly one scan after its input goes from 1 to 0."),
    "ODF": ("one drop falling", "  _     _   _  ", "[ \\_ODF \\_/ ]",
            "Follows its input, except that it drops to 0 for the first scan after "
            "the input falls; 0 until the input has once been 1."),
    "ODR": ("one drop rising", "    _   _   _  ", "[_/ ODR \\_/ ]",
            "Passes power while its input is 0 and, once the input is 1, from the "
            "second scan on: it drops to 0 for the first scan of each rising edge."),
    "OSC": ("oscillator", "      _   _    ", "[OSC/ \\_/ \\_]",
            "While its input is 1, passes power on every other scan (1, 0, 1, ...): "
            "a square wave at half the scan frequency."),
}
for _key, (_title, _top, _glyph, _doc) in _EDGES.items():
    define(_key, _title, (), text(_top), text(_glyph), _doc, "edges",
           aliases=("OSL",) if _key == "ODF" else ())

# --- timers ------------------------------------------------------------------------

_TIMERS = {
    "TON": ("turn-on delay", "", "Passes power once its input has been 1 for the delay; "
            "drops at once when the input falls."),
    "TOF": ("turn-off delay", "", "Passes power while its input is 1 and for the delay "
            "after the input falls."),
    "RTO": ("retentive turn-on delay", "", "Accumulates the time its input is 1; passes "
            "power once the total reaches the delay, and keeps doing so until reset with RES."),
    "RTL": ("retentive turn-on delay, low input", "o", "Accumulates the time its input is 0; "
            "passes power once the total reaches the delay, until reset with RES."),
    "TCY": ("cyclic timer", "", "While its input is 1, alternates its output every delay: "
            "a square wave with a period of twice the delay."),
    "THI": ("high pulse timer", "", "On each rising edge of its input, passes power for "
            "exactly the delay; not retriggered until the input has been 0."),
    "TLO": ("low pulse timer", "o", "After each falling edge of its input, stays 0 for "
            "the delay; otherwise passes power once the input has been 1."),
}
for _key, (_title, _pre, _doc) in _TIMERS.items():
    define(
        _key, _title,
        (Field("name", "var", "T", "rw"), Field("delay", "delay"),
         Field("adjust", "int", access="", default=0, drawn=False)),
        text("{name}"), text(_pre + "[" + _key + " {delay:delay}]"),
        _doc + " The delay is a time, or a variable holding a number of scan cycles; "
        "the timer counts scan cycles in its T variable.",
        "timers", family="timer", example=f"{_key} Tnew 100000 0",
    )

define(
    "TIME2COUNT", "time to count converter",
    # LDmicro 5.4 writes an adjust as for timers (older releases wrote none) but its
    # loader never reads it back, so it is 0 in every program LDmicro compiles:
    # kept as the file has it (None: absent), not used
    (var("name"), Field("delay", "delay", access=""),
     Field("adjust", "int", access="", drawn=False, optional=True)),
    text("{name}"), text("[T2CNT {delay:delay}]"),
    "While its input is 1, stores in its variable the number of scan cycles that "
    "makes the given time, for use as a variable timer delay.",
    "timers", support=SIM_ONLY | {"avr", "pic16", "pic18", "pic10", "c"},
    example='TIME2COUNT Tnew 100000 0', label='T2CNT',
    ldmicro_written=('name',),
)
define(
    "TIME2DELAY", "time to delay converter", (var("name"), Field("delay", "delay", access="")),
    text("{name}"), text("[T2DLY {delay:delay}]"),
    "While its input is 1, stores in its variable the loop count that makes a "
    "DELAY last the given time on the selected part.",
    "timers", support=frozenset({"parse", "check", "avr", "pic16", "pic18", "pic10"}),
    example='TIME2DELAY delay 10', label='T2DLY',
    ldmicro_written=('name',),
)
define(
    "DELAY", "busy-wait delay", (Field("delay", "operand"),),
    text("{delay:us}"), text("[DELAY]"),
    "While its input is 1, busy-waits the given number of microseconds (or the "
    "loop count in a variable) inside the scan.",
    "timers", support=frozenset({"parse", "check", "sim", "avr", "pic16", "pic18", "pic10", "c"}),
    example='DELAY 10',
)
define(
    "RES", "reset", (Field("name", "var", "TCP", "write"),),
    text("{name}"), text("{{RES}}"),
    "While its input is 1, resets a timer or counter: a counter goes back to its "
    "start value, a timer to 0; on a P name it switches that PWM output off.",
    "timers", eol=True,
    example='RES Tnew',
)

# --- counters --------------------------------------------------------------------

_COUNTERS = {
    "CTU": ("up counter", "{name}:{init}", "{kind}[CTU>={max}]",
            "On each counting edge adds one to its counter, stopping at the limit; "
            "passes power while the count is at or above the limit."),
    "CTD": ("down counter", "{name}:{init}", "{kind}[CTD>{max}]",
            "On each counting edge subtracts one from its counter, stopping at the limit; "
            "passes power while the count is above the limit."),
    "CTC": ("circular counter", "{name}", "{kind}[CTC  {init}:{max}]",
            "On each counting edge adds one; past the limit the count wraps to the "
            "start value and the output passes power for that one scan."),
    "CTR": ("circular down counter", "{name}", "{kind}[CTR  {init}:{max}]",
            "On each counting edge subtracts one; below the limit the count wraps to "
            "the start value and the output passes power for that one scan."),
}
_COUNTER_LIMITS = {"CTU": 10, "CTD": -10, "CTC": 9, "CTR": -9}  # LDmicro's editor defaults
for _key, (_title, _top, _glyph, _doc) in _COUNTERS.items():
    define(
        _key, _title,
        (Field("name", "var", "C", "rw"), operand("max", io="auto"),
         Field("init", "operand", default="0"), Field("kind", "edge", access="", default="/")),
        text(_top), text(_glyph),
        _doc + " The counting edge is `/` rising (default), `\\` falling, `-` every scan "
        "with the input 1, `o` every scan with the input 0.",
        "counters", family="counter", example=f"{_key} Cnew {_COUNTER_LIMITS[_key]} 0 /",
    )

# --- comparisons --------------------------------------------------------------------

for _key, _op, _title in (("EQU", "==", "equal"), ("NEQ", "!=", "not equal"), ("GRT", ">", "greater than"),
                          ("GEQ", ">=", "greater or equal"), ("LES", "<", "less than"),
                          ("LEQ", "<=", "less or equal")):
    define(
        _key, _title, (operand("op1"), operand("op2")),
        box("[", "{op1}", "", _op, "]", width="compare"),
        box("[", "", "", "{op2}", "]", width="compare"),
        f"Passes power when its input is 1 and the first operand is {_title} "
        "the second (signed comparison).",
        "compare", consts={"op": _op}, example=f"{_key} var 1",
    )

define(
    "IF_BIT_SET", "if bit set", (var("var", "read", io="auto"), operand("bit")),
    box("[", "", "", "{var}", "]"), box("[", "if Bit SET ", "", "{bit}", "]"),
    "Passes power when its input is 1 and the given bit (a bit number) of the variable is 1.",
    "bits",
    example='IF_BIT_SET var bit', label='IF BIT SET',
    ldmicro_written=('var',),
)
define(
    "IF_BIT_CLEAR", "if bit clear", (var("var", "read", io="auto"), operand("bit")),
    box("[", "", "", "{var}", "]"), box("[", "if Bit CLR ", "", "{bit}", "]"),
    "Passes power when its input is 1 and the given bit (a bit number) of the variable is 0.",
    "bits",
    example='IF_BIT_CLEAR var bit', label='IF BIT CLR',
    ldmicro_written=('var',),
)

# --- moves and arithmetic ---------------------------------------------------------------

define(
    "MOVE", "move", (var("dest", io="auto"), operand("src", io="auto")),
    box("{MOV ", "", "", "{dest}", ":=}"), box("{", "", "", "{src}", "}"),
    "While its input is 1, copies the source (a variable or a constant) into the destination.",
    "math", eol=True,
    example='MOVE dest src', label='MOV',
    ldmicro_written=('dest',),
)
for _key, _sym, _title, _eol in (("ADD", "+", "add", True), ("SUB", "-", "subtract", True),
                                 ("MUL", "*", "multiply", True), ("DIV", "/", "divide", True),
                                 ("MOD", "%", "remainder", True), ("AND", "&", "bitwise and", False),
                                 ("OR", "|", "bitwise or", False), ("XOR", "^", "bitwise xor", False),
                                 ("SHL", "<<", "shift left", False), ("SHR", ">>", "arithmetic shift right", False),
                                 ("SR0", "sr0", "logical shift right", False), ("ROL", "rol", "rotate left", False),
                                 ("ROR", "ror", "rotate right", False)):
    define(
        _key, _title, (var("dest", io="auto"), operand("op1", io="auto"), operand("op2", io="auto")),
        box("{" + _key + " ", "", "", "{dest}", ":=}"), box("{", "{op1}", _sym, "{op2}", "}"),
        f"While its input is 1, sets the destination to op1 {_sym} op2 "
        "(signed integers of the destination's size; ADD and SUB set ROverflowFlagV on overflow).",
        "math", eol=_eol, support=ALL, example=f"{_key} dest src 1", ldmicro_written=("dest",),
    )
for _key, _sym, _title in (("NEG", "-", "negate"), ("NOT", "~", "bitwise not")):
    define(
        _key, _title, (var("dest", io="auto"), operand("op1", io="auto")),
        box("{" + _key + " ", "", "", "{dest}", ":=}"), box("{", "", _sym, "{op1}", "}"),
        f"While its input is 1, sets the destination to {_sym}op1.",
        "math", example=f"{_key} dest src", ldmicro_written=("dest",),
    )
define(
    "SET_BIT", "set bit", (var("var", "rw", io="auto"), operand("bit")),
    box("{", "", "", "{var}", "}"), box("{", "SET Bit ", "", "{bit}", "}"),
    "While its input is 1, sets the given bit (a bit number) of the variable.",
    "bits",
    example='SET_BIT var bit', label='SET BIT',
    ldmicro_written=('var',),
)
define(
    "CLEAR_BIT", "clear bit", (var("var", "rw", io="auto"), operand("bit")),
    box("{", "", "", "{var}", "}"), box("{", "CLR Bit ", "", "{bit}", "}"),
    "While its input is 1, clears the given bit (a bit number) of the variable.",
    "bits",
    example='CLEAR_BIT var bit', label='CLR BIT',
    ldmicro_written=('var',),
)
for _key, _title, _doc in (("BIN2BCD", "binary to BCD", "converts the source to unpacked BCD (one decimal digit per byte)"),
                           ("BCD2BIN", "BCD to binary", "converts unpacked BCD (one decimal digit per byte) to binary")):
    define(
        _key, _title, (var("dest"), operand("src")),
        box("{" + _key + " ", "", "", "{dest}", ":=}"), box("{", "", "", "{src}", "}"),
        f"While its input is 1, {_doc} into the destination.",
        "math", example=f"{_key} dest src", ldmicro_written=("dest",),
    )
for _key, _doc in (("SWAP", "swaps the source's nibbles (1 byte) or reverses its byte order"),
                   ("OPPOSITE", "reverses the order of the source's bits")):
    define(
        _key, _key.lower(), (var("dest", io="auto"), operand("src", io="auto")),
        box("{", "", "", "{dest}", ":=}"), box("{" + _key + " ", "", "", "{src}", "}"),
        f"While its input is 1, {_doc} and stores the result in the destination.",
        "math", example=f"{_key} dest src", ldmicro_written=("dest",),
    )
define(
    "RANDOM", "random number", (var("name"),),
    text("{name}"), text("{{RAND}}"),
    "While its input is 1, stores the next pseudo-random number (a linear congruential "
    "sequence, seeded by SRAND) in the variable.",
    "math",
    example='RANDOM Rand', label='RAND',
    ldmicro_written=('name',),
)
define(
    "SEED_RANDOM", "seed random numbers", (var("name", "write"), operand("seed")),
    box("{SRAND ", "", "", "{name}", "}"), box("{", "$seed", ":=", "{seed}", "}"),
    "While its input is 1, sets the seed of the variable's random sequence.",
    "math",
    example='SEED_RANDOM Rand newSeed', label='SRAND',
)

# --- tables and shift register ------------------------------------------------------------

define(
    "SHIFT_REGISTER", "shift register", (var("name", "rw"), integer("stages")),
    box("{", "SHIFT REG", "", "", "}", width="shift"), box("{", "{name}", "", "0..{stages:last}", "}", width="shift"),
    "On each rising edge of its input shifts name0 -> name1 -> ... -> name(n-1); "
    "name0 is the input stage the program writes.",
    "tables", eol=True,
    example='SHIFT_REGISTER reg 7', label='SHIFT REG',
)
define(
    "LOOK_UP_TABLE", "look-up table",
    (var("dest"), operand("index"), Field("values", "values", access="", default=(), drawn=False),
     flag("as_string", drawn=False), Field("table", "token", access="", default="")),
    box("{", "{dest}", "", "", ":=}"), box("{", "LUT ", "{table}", "[{index}]", "}"),
    "While its input is 1, sets the destination to table[index] (index 0 to count-1). "
    "The values are listed in the DETAILS section.",
    "tables", eol=True, ld_form="lut",
    example='LOOK_UP_TABLE dest index 4 0 10 20 30 40 tabName', label='LUT',
    ldmicro_written=('dest', 'index'),
)
define(
    "PIECEWISE_LINEAR", "piecewise linear",
    (var("dest"), operand("index"), Field("points", "points", access="", default=(), drawn=False),
     Field("table", "token", access="", default="")),
    box("{", "{dest}", "", "", ":=}"), box("{", "PWL ", "{table}", "[{index}]", "}"),
    "While its input is 1, sets the destination by linear interpolation between "
    "the table's (x, y) points at x = index. The points are listed in DETAILS.",
    "tables", eol=True, ld_form="pwl",
    example='PIECEWISE_LINEAR yvar xvar 2 0 0 10 100 name', label='PWL',
    ldmicro_written=('dest', 'index'),
)

# --- analog, PWM, EEPROM ----------------------------------------------------------------------

define(
    "READ_ADC", "read A/D converter", (var("name", "write", "A", io="adc"), integer("refs", 0, drawn=False)),
    text("{name}"), text("{{READ ADC}}"),
    "While its input is 1, reads the analog input pin assigned to the A name into "
    "that variable (0 to 1023 on 10-bit converters).",
    "analog", eol=True,
    example='READ_ADC ADCnew 0', label='READ ADC',
    ldmicro_written=('name',),
)
define(
    "SET_PWM", "set PWM duty cycle",
    (operand("duty"), Field("freq", "int", access=""), Field("name", "var", "P", "write", io="pwm"),
     token("resolution", "", drawn=False)),
    box("", "{duty}", " ", "{freq:hz}", ""), box("{", "PWM", " ", "{name}", "}"),
    "While its input is 1, drives the PWM pin at the given frequency with the given "
    "duty cycle (0-100 % by default). RES on the P name switches it off.",
    "analog", eol=True, ld_form="setpwm",
    example='SET_PWM duty_cycle 1000 PWMoutpin 0-100%', label='SET PWM',
)
define(
    "PERSIST", "make persistent", (var("var", "rw"),),
    text("{var}"), text("{{PERSIST}}"),
    "Keeps the variable in EEPROM: read back at start-up, written whenever it changes.",
    "analog", eol=True,
    example='PERSIST saved',
)

# --- serial and strings ---------------------------------------------------------------------------

define(
    "UART_SEND", "UART send",
    (var("var", "read"), integer("bytes", 1, drawn=False), flag("wait", drawn=False)),
    text("{var}"), text("{{UART SEND}}"),
    "When its input is 1 and the transmitter is free, sends the variable's low byte "
    "over the UART; passes power while the transmitter is busy.",
    "serial",
    example='UART_SEND var 1 0', label='UART SEND',
)
define(
    "UART_RECV", "UART receive",
    (var("var", "write"), integer("bytes", 1, drawn=False), flag("wait", drawn=False)),
    text("{var}"), text("{{UART RECV}}"),
    "When its input is 1 and a byte has arrived, stores it in the variable and "
    "passes power for that scan.",
    "serial",
    example='UART_RECV var 1 0', label='UART RECV',
    ldmicro_written=('var',),
)
define(
    "UART_SEND_READY", "UART ready to send", (), text(" Is ready? "), text("[UART SEND]"),
    "Passes power when its input is 1 and the UART transmitter is free.",
    "serial", aliases=("UART_SEND_BUSY", "UART_UDRE"),
    label='UART SEND ready test',
)
define(
    "UART_RECV_AVAIL", "UART byte available", (), text(" Is avail? "), text("[UART RECV]"),
    "Passes power when its input is 1 and a received byte is waiting.",
    "serial",
    label='UART RECV available test',
)
define(
    "FORMATTED_STRING", "formatted string over UART",
    (Field("var", "operand", default=""), Field("text", "text", access="", default="")),
    box("", "", "{var}", "", ""), text('{{"{text}"}}'),
    "On a rising edge of its input, sends the text over the UART, one character per "
    "scan; `\\3` or `\\-3` inserts the variable with 3 digits (with sign), `\\r\\n` etc. "
    "are control characters. Passes power while sending.",
    "serial", cells=2, ld_form="fstring",
    example='FORMATTED_STRING var value:\\x20\\\\3\\\\r\\\\n', label='formatted string',
)
define(
    "STRING", "format into a string",
    (Field("dest", "var", access="write", default=""), Field("var", "operand", default=""),
     Field("text", "text", access="", default="")),
    box("{", "FRMT STR", "", "{dest}", ":=}"), box("{", '"{text}",', "", "{var}", "}"),
    "While its input is 1, formats the text with the variable into the string variable.",
    "serial", cells=2, ld_form="string", support=DRAWN_ONLY,
    example='STRING dest var frmtString',
    ldmicro_written=('dest',),
)

# --- program flow ---------------------------------------------------------------------------------

define("MASTER_RELAY", "master control relay", (), None, text("{{MASTER RLY}}"),
       "A rung ending in a false master relay switches off every rung after it, up to "
       "the next master relay rung, which always switches them back on.",
       "flow", eol=True, label='MASTER RLY')
define("SHORT", "short circuit", (), None, text("+------+"),
       "Always passes its input on (a wire you can see).", "flow")
define("OPEN", "open circuit", (), None, text("+      +"),
       "Never passes power.", "flow")
define("GOTO", "go to", (label("label"),), text("{label}"), text("{{GOTO}}"),
       "When its input is 1, continues the scan at the rung holding LABEL of that name "
       "(or at that rung number); the rungs in between are skipped.",
       "flow", eol=True, family="jump", example='GOTO loop')
define("LABEL", "label", (label("label"),), text("{label}"), text("[LABEL]"),
       "Marks its rung as a GOTO target; passes power through.", "flow", example='LABEL loop')
define("SUBPROG", "subroutine start", (label("label"),), text("{label}"), text("[SUBPROG]"),
       "Starts a subroutine that runs only when called with GOSUB; must be alone in its rung.",
       "flow", family="jump", example='SUBPROG sub')
define("ENDSUB", "subroutine end", (label("label"),), text("{label}"), text("[ENDSUB]"),
       "Ends a subroutine and returns to the rung after the GOSUB; must be alone in its rung.",
       "flow", family="jump", example='ENDSUB sub')
define("GOSUB", "call subroutine", (label("label"),), text("{label}"), text("{{GOSUB}}"),
       "When its input is 1, runs the subroutine of that name and comes back.",
       "flow", eol=True, family="jump", example='GOSUB sub')
define("RETURN", "return", (), None, text("{{RETURN}}"),
       "When its input is 1, returns from the current subroutine.", "flow", eol=True, family="jump")
define("CLRWDT", "clear watchdog", (), None, text("{{CLRWDT}}"),
       "Clears the watchdog timer an extra time within the scan.", "flow", eol=True)
define("LOCK", "lock", (), None, text("{{LOCK}}"),
       "When its input is 1, stops the program in an endless loop (a watchdog test).",
       "flow", eol=True)
define("SLEEP", "sleep", (Field("name", "token", access="", default="", drawn=False),
                          Field("delay", "token", access="", default="", drawn=False)),
       None, text("{{SLEEP}}"),
       "When its input is 1, puts the microcontroller into power-down sleep.",
       "flow", eol=True, ld_form="sleep", support=frozenset({"parse", "check", "avr", "pic10", "pic16", "pic18"}))
define("PLACEHOLDER", "empty rung", (), None, text("--"),
       "Marks an empty rung; a program with one cannot be compiled.", "flow",
       support=frozenset({"parse", "check"}), label='empty rung')
define("COMMENT", "comment",
       # the blanks that end each line in an .ld file (a count of spaces per line; left out
       # when no line has any): the drawing cannot show them
       (Field("text", "text", access=""), Field("line_ends", "values", access="", default=(), drawn=False)),
       None, None,
       "A comment rung; it does nothing.", "flow", ld_form="comment", example="COMMENT a note")

# --- displays, bus and target-specific elements ------------------------------------------------

for _n in ("7", "9", "14", "16"):
    define(
        _n + "SEGMENTS", f"{_n}-segment decoder",
        (var("dest", io="auto"), operand("src"), Field("common", "token", access="", default="C")),
        box("{" + _n + "SEG ", "", "", "{dest}", ":=}"), box("{", "{common}", "", "{src}", "}"),
        f"While its input is 1, sets the destination to the {_n}-segment pattern of the "
        "source character (C common cathode, A common anode).",
        "display",
        example=f"{_n}SEGMENTS dest src {'A' if _n == '16' else 'C'}", ldmicro_written=("dest",),
    )
define(
    "BUS", "bus tracer",
    # .ld order: the source bit for destination bit 7 first, bit 0 last
    (var("dest", io="auto"), operand("src", io="auto")) + tuple(integer(f"b{i}", i, drawn=False) for i in range(7, -1, -1)),
    box("{BUS ", "", "", "{dest}", ":=}"), box("{", "", "", "{src}", "}"),
    "While its input is 1, copies each bit j of the source to bit b_j of the destination "
    "(the .ld line lists b7 first; the default 7 6 5 4 3 2 1 0 copies the byte).",
    "display",
    example='BUS dest src 7 6 5 4 3 2 1 0',
    ldmicro_written=('dest',),
)

_SPI_DETAILS = (token("mode", "Master", drawn=False), token("modes", "0", drawn=False),
                token("size", "8", drawn=False), token("first", "MSB", drawn=False),
                token("bitrate", "1000000", drawn=False))
define("SPI", "SPI transfer",
       (Field("name", "token", access="", io="spi"), Field("send", "operand"), Field("recv", "var", access="write"))
       + _SPI_DETAILS,
       box("{SPI ", "", "", "{name}", "}"), box("{->", "{recv}", "", "{send}", "->}"),
       "Sends and receives a byte over the SPI bus (C back ends only in LDmicro).",
       "target", support=DRAWN_ONLY, example='SPI SPI1 send recv Master 0 8 MSB 1000000', ldmicro_written=('send', 'recv'))
define("SPI_WR", "SPI write",
       (Field("name", "token", access="", io="spi"), Field("send", "operand"), token("recv", "recv", drawn=False))
       + _SPI_DETAILS,
       box("{SPI WR ", "", "", "{name}", "}"), box("{", "", '"', "{send}", '"->}'),
       "Writes a string over the SPI bus (C back ends only in LDmicro).",
       "target", support=DRAWN_ONLY, example='SPI_WR SPI1 send recv Master 0 8 MSB 1000000')
define("I2C_RD", "I2C read",
       (Field("name", "token", access="", io="i2c"), token("send", "send", drawn=False), Field("recv", "var", access="write"),
        token("mode", "Master", drawn=False), token("address"), token("register"),
        token("first", "MSB", drawn=False), token("bitrate", "100000", drawn=False)),
       box("{I2C RD ", "", "", "{name}", "}"), box("{->", "{recv}", "{address}", "{register}", "}"),
       "Reads a register of an I2C device (C back ends only in LDmicro).",
       "target", support=DRAWN_ONLY, example='I2C_RD I2C1 send recv Master 0 0 MSB 100000')
define("I2C_WR", "I2C write",
       (Field("name", "token", access="", io="i2c"), Field("send", "operand"), token("recv", "recv", drawn=False),
        token("mode", "Master", drawn=False), token("address"), token("register"),
        token("first", "MSB", drawn=False), token("bitrate", "100000", drawn=False)),
       box("{I2C WR ", "", "", "{name}", "}"), box("{", "{address}", "{register}", "{send}", "->}"),
       "Writes a register of an I2C device (C back ends only in LDmicro).",
       "target", support=DRAWN_ONLY, example='I2C_WR I2C1 send recv Master 0 0 MSB 100000')
# LDmicro compiles NPULSE OFF for the AVRs alone, and no NPULSE for any part (docs/compiler.md)
define("NPULSE_OFF", "N pulse off", (), None, text("{{NPULSE OFF}}"),
       "Stops the N PULSE generator; since no generator runs (see N PULSE), it does nothing.", "target", eol=True,
       support=SIM_ONLY | {"avr"})
define("QUAD_ENCOD", "quadrature encoder",
       (Field("counter", "var", access="write"), integer("int01", 0, drawn=False),
        bit("a", "X"), bit("b", "X"), Field("z", "bit", "X", default=""), Field("dir", "bit", "YR", "write", default=""),
        Field("zkind", "edge", access="", default="/"), integer("counts", 0, drawn=False)),
       box("~~[{a} {b}", "", "", "", "{dir}]-"), box("-{zkind}[{z}", "", " QUAD ENCOD ", "{counter}", "]^"),
       "Counts the pulses of a quadrature encoder on inputs A and B.",
       "target", cells=2, ld_form="quad", example='QUAD_ENCOD qCount0 0 XqA0 XqB0 XqZ0 YqDir0 / 0',
       ldmicro_written=('counter',))
define("PULSER", "pulser",
       (token("p1"), token("p0"), token("accel"), Field("counter", "operand"), bit("coil", "YR", "write")),
       box("[PULSER ", "{counter}", "", " {coil}", "]->"), box("[", "", "{p1} {p0} {accel}", "", "]--"),
       "Generates pulses with the given high and low times (in scans).",
       "target", cells=2, example='PULSER D1 D0 accel_decel counter Ypulse')
define("STEPPER", "stepper motor",
       (token("name"), token("max"), token("p"), integer("size"), integer("graph"), bit("coil", "Y", "write")),
       box("[STEPPER ", "{name} {max}", "", " {coil}", "]->"), box("[", "{p}", "", " {size} {graph}", "]--"),
       "Drives a stepper motor output with an acceleration table.",
       "target", cells=2, example='STEPPER step stepMax P 100 1 Ystep')
define("NPULSE", "N pulse generator",
       (Field("counter", "var", access="rw"), Field("freq", "int", access=""), bit("coil", "Y", "write")),
       box("[N PULSE ", "{counter}", "", "{coil}", "]->"), box("[", "", "{freq:hz}", "", "]--"),
       ("Meant to generate the counted number of pulses at the given frequency; LDmicro 5.4.1.1 refuses "
        "every program with one (docs/compiler.md), so neither the simulator nor a back end has it."),
       "target", cells=2, support=DRAWN_ONLY, example='NPULSE counter 1000 YNpulse')
# raw register access, its operands in the order LDmicro's compiler reads them (its editor's
# dialog names them the other way round for all but WSFR: docs/compiler.md): `sfr` is a
# data-space address, a number or a variable holding one; the PIC and C back ends of LDmicro
# refuse these
_SFR_WHERE = " sfr is a data address: an AVR's I/O register n is at n + 0x20 (at n on the ATtiny10)."
_SFR_ORDER = (" LDmicro's editor names the two operands the other way round (its new element reads"
              " `sfr` first); its compiler reads them in this order.")
for _key, _word, _fields, _doc in (
        ("RSFR", "Read", (var("dest"), operand("sfr")), "Copies the register at address sfr into dest (0 to 255)."),
        ("WSFR", "Write", (operand("sfr"), operand("src")), "Writes the low byte of src to the register at address sfr."),
        ("SSFR", "Sbit", (operand("mask"), operand("sfr")), "Sets the bits of the mask in the register at address sfr."),
        ("CSFR", "Cbit", (operand("mask"), operand("sfr")), "Clears the bits of the mask in the register at address sfr."),
        ("TSFR", "IsBitS", (operand("mask"), operand("sfr")),
         "Passes power when every bit of the mask is set in the register at address sfr."),
        ("TCSFR", "IsBitC", (operand("mask"), operand("sfr")),
         "Passes power when every bit of the mask is clear in the register at address sfr.")):
    _first, _second = (f.name for f in _fields)
    define(_key, f"special function register {_word.lower()}", _fields,
           box("?", "{" + _first + "} " + _word, "", "", "?", width="sfr"),
           box("? ", "{" + _second + "}", "", "", "?", width="sfr"),
           _doc + _SFR_WHERE + ("" if _key == "WSFR" else _SFR_ORDER), "target", support=SIM_ONLY | {"avr"},
           consts={"word": _word, "first": _first, "second": _second},
           example=f"{_key} sfr {({'RSFR': 'dest', 'WSFR': 'srs'}).get(_key, '1')}")  # LDmicro's editor default


INSTRUCTIONS: dict[str, Instruction] = {i.key: i for i in _TABLE}


# instructions that must end their branch (coils, MOV, RES...)
EOL_KINDS = frozenset(i.key for i in _TABLE if i.eol)


def of_family(family: str) -> tuple[str, ...]:
    return tuple(i.key for i in _TABLE if i.family == family)


TIMERS, COUNTERS, JUMPS = of_family("timer"), of_family("counter"), of_family("jump")
# comparison -> its C/Python relation, as its drawing shows it
RELATIONS: dict[str, str] = {i.key: i.consts["op"] for i in _TABLE if i.category == "compare"}

# .ld keywords (including legacy aliases) -> instruction
LD_KEYWORDS: dict[str, Instruction] = {}
for _instruction in _TABLE:
    LD_KEYWORDS[_instruction.key] = _instruction
    for _alias in _instruction.aliases:
        LD_KEYWORDS[_alias] = _instruction


def shift_width(args: dict) -> int:
    return min(17, max(11, 1 + len(str(args["name"]))))


def sfr_width(args: dict) -> int:
    return max(3 + len(args["word"]) + len(str(args[args["first"]])), 3 + len(str(args[args["second"]])))


def _register_widths() -> None:
    from .drawing import BOX_WIDTHS

    BOX_WIDTHS["shift"] = shift_width
    BOX_WIDTHS["sfr"] = sfr_width


_register_widths()


