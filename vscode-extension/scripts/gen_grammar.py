"""Writes the TextMate grammars of the extension: syntaxes/ladder.tmLanguage.json (text form) and
syntaxes/ldmicro.tmLanguage.json (LDmicro .ld). The instruction words come from the repository's
instruction table. Edit this file (or the table), run `python3 scripts/gen_grammar.py`, then
`npm test` (vscode-tmgrammar-test over test/grammar/)."""
import json
import os
import re
import sys
# the repository's instruction table (lang/instructions.py) is the one list of instructions
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
from lang.instructions import INSTRUCTIONS  # noqa: E402

WORD = re.compile(r"(?<![A-Za-z0-9])[A-Z][A-Z0-9]+[a-z]?(?![A-Za-z0-9])")


def drawn_words():
    """Every word an instruction's drawing shows (TON, MOV, T2CNT...), and END."""
    words = {"END"}
    for instruction in INSTRUCTIONS.values():
        for drawing in (instruction.top, instruction.glyph):
            for template in drawing.templates() if drawing is not None else ():
                for part in template.parts():
                    texts = [part[1]] if part[0] == "lit" else [alt for alt in part[3:5] if alt]
                    for text in texts:
                        words.update(WORD.findall(text))
    # longest first: the regex alternation takes the first that matches
    return "|".join(sorted(words, key=lambda w: (-len(w), w)))


KEYWORDS = drawn_words()
PREFIX = [("X", "input"), ("Y", "output"), ("R", "relay"), ("T", "timer"), ("C", "counter"),
          ("A", "adc"), ("P", "pwm")]

def names(sfx):
    pats = [{"match": r"\b%s[A-Za-z0-9_]*(?:\[[A-Za-z0-9_]+\])?" % p, "name": "variable.other.%s.%s" % (k, sfx)}
            for p, k in PREFIX]
    pats.append({"match": r"(?<![\w$])\$?_*[A-Za-z][A-Za-z0-9_]*(?:\[[A-Za-z0-9_]+\])?", "name": "variable.other.%s" % sfx})
    return pats

def numbers(sfx):
    return [
        {"match": r"\b0[xX][0-9A-Fa-f]+\b", "name": "constant.numeric.hex.%s" % sfx},
        {"match": r"\b0[bB][01]+\b", "name": "constant.numeric.binary.%s" % sfx},
        {"match": r"(?<![\w.])([-+]?[0-9]+(?:\.[0-9]+)?)(?:\s*(ns|us|ms|s|min|h|MHz|kHz|Hz|%)\b)?",
         "captures": {"1": {"name": "constant.numeric.%s" % sfx},
                      "2": {"name": "keyword.other.unit.%s" % sfx}}},
        {"match": r"'(?:\\.|[^'\\])'", "name": "constant.character.%s" % sfx},
    ]

S = "ladder"
ladder = {
    "$schema": "https://raw.githubusercontent.com/martinring/tmlanguage/master/tmlanguage.json",
    "name": "Ladder (LDmicro text)",
    "scopeName": "source.ladder",
    "fileTypes": ["ladder"],
    "patterns": [
        {"include": "#preamble"},
        {"include": "#comment-line"},
        {"include": "#diagram-line"},
        {"include": "#io-table"},
        {"include": "#var-list"},
        {"include": "#settings"},
        {"include": "#details"},
        {"include": "#section-title"},
    ],
    "repository": {
        "preamble": {"patterns": [
            {"match": r"^LDmicro export text\.?\s*$", "name": "comment.line.header.ladder"},
            {"match": r"^Source file:.*$", "name": "comment.line.source.ladder"},
            {"begin": r"^(?=for\s+'|no MCU assigned)", "end": r"$", "name": "meta.header.ladder", "patterns": [
                {"match": r"\b(for|no MCU assigned|crystal|cycle time)\b", "name": "keyword.other.header.ladder"},
                {"match": r"(')([^']*)(')", "captures": {
                    "0": {"name": "string.quoted.single.ladder"},
                    "2": {"name": "entity.name.type.part.ladder"}}},
                {"include": "#numbers"},
                {"match": ",", "name": "punctuation.separator.comma.ladder"},
            ]},
        ]},
        "section-title": {"match": r"^[A-Za-z/][^:|]*:\s*$", "name": "markup.heading.section.ladder entity.name.section.ladder"},
        "rail-prefix": {"match": r"^([ \t]*)([0-9]*)(\|[|+])", "captures": {
            "2": {"name": "constant.numeric.rung-number.ladder"},
            "3": {"name": "punctuation.definition.rail.left.ladder"}}},
        "comment-line": {
            "match": r"^([ \t]*)([0-9]*)(\|[|+])([ \t]*)(;.*?)(?:([ \t]*)(\|\|))?[ \t]*$",
            "name": "meta.diagram.comment.ladder",
            "captures": {
                "2": {"name": "constant.numeric.rung-number.ladder"},
                "3": {"name": "punctuation.definition.rail.left.ladder"},
                "5": {"name": "comment.line.semicolon.ladder"},
                "7": {"name": "punctuation.definition.rail.right.ladder"}}},
        "diagram-line": {
            "begin": r"^([ \t]*)([0-9]*)(\|[|+])",
            "beginCaptures": {
                "2": {"name": "constant.numeric.rung-number.ladder"},
                "3": {"name": "punctuation.definition.rail.left.ladder"}},
            "end": r"$",
            "name": "meta.diagram.line.ladder",
            "patterns": [
                {"match": r"\|\|[ \t]*$", "name": "punctuation.definition.rail.right.ladder"},
                {"include": "#element"},
            ]},
        "element": {"patterns": [
            {"match": r"\{\"(?:[^\"]|\"(?!\}))*\"\}", "name": "string.quoted.double.ladder"},
            {"match": r"\]/\[", "name": "keyword.control.contact.normally-closed.ladder"},
            {"match": r"\] \[", "name": "keyword.control.contact.normally-open.ladder"},
            {"match": r"\(/\)", "name": "keyword.control.coil.negated.ladder"},
            {"match": r"\(S\)", "name": "keyword.control.coil.set.ladder"},
            {"match": r"\(R\)", "name": "keyword.control.coil.reset.ladder"},
            {"match": r"\(T\)", "name": "keyword.control.coil.toggle.ladder"},
            {"match": r"\( \)", "name": "keyword.control.coil.ladder"},
            {"match": r"\[END\]", "name": "keyword.control.end.ladder"},
            {"begin": r"[/\\o^]?\[", "end": r"\]|(?=\|\||$)", "name": "meta.box.ladder",
             "beginCaptures": {"0": {"name": "punctuation.definition.box.begin.ladder"}},
             "endCaptures": {"0": {"name": "punctuation.definition.box.end.ladder"}},
             "patterns": [{"include": "#box-content"}]},
            {"begin": r"[/\\o^]?\{", "end": r"\}|(?=\|\||$)", "name": "meta.box.ladder",
             "beginCaptures": {"0": {"name": "punctuation.definition.box.begin.ladder"}},
             "endCaptures": {"0": {"name": "punctuation.definition.box.end.ladder"}},
             "patterns": [{"include": "#box-content"}]},
            {"match": r"-+", "name": "punctuation.definition.wire.ladder"},
            {"match": r"(?<![\w$])_+(?![\w$])", "name": "punctuation.definition.edge.ladder"},
            {"match": r"\+", "name": "punctuation.definition.junction.ladder"},
            {"match": r"\?", "name": "punctuation.definition.box.sfr.ladder"},
            {"match": r"\|", "name": "punctuation.definition.connector.ladder"},
            {"include": "#names"},
            {"include": "#numbers"},
        ]},
        "box-content": {"patterns": [
            {"match": r"_/ | \\_|_/|\\_", "name": "punctuation.definition.edge.ladder"},
            {"match": r"(?<![A-Za-z0-9$])(%s)(?![A-Za-z0-9])" % KEYWORDS, "name": "support.function.instruction.ladder"},
            {"match": r":=|->|==|!=|>=|<=|[<>+*/%&^~-]", "name": "keyword.operator.ladder"},
            {"match": r"\"(?:[^\"\\]|\\.)*\"", "name": "string.quoted.double.ladder"},
            {"include": "#numbers"},
            {"include": "#names"},
        ]},
        "names": {"patterns": names(S)},
        "numbers": {"patterns": numbers(S)},
        "io-table": {
            "begin": r"^((?:I/O ASSIGNMENT|E/S ASIGNACI.N|[A-Za-z/ ]*ASSIGN[A-Za-z]*)\s*:)\s*$",
            "beginCaptures": {"1": {"name": "markup.heading.section.ladder entity.name.section.ladder"}},
            "end": r"^(?=\S)",
            "name": "meta.io-table.ladder",
            "patterns": [
                {"match": r"^\s*(Name)\s*(\|)\s*(Type)\s*(\|)\s*(Pin)\s*(\|)\s*(Port)\s*(\|)\s*(Pin name)\s*$",
                 "name": "meta.table.header.ladder",
                 "captures": {str(i): {"name": "markup.bold.table-header.ladder" if i % 2 else "punctuation.separator.column.ladder"}
                              for i in range(1, 10)}},
                {"match": r"^\s*-+(?:\+-+)*\s*$", "name": "punctuation.separator.table.ladder"},
                {"match": r"^(\s*)(\S+)(\s*)(\|)([^|]*)(\|)([^|]*)(\|)([^|]*)(?:(\|)(.*))?$",
                 "name": "meta.table.row.ladder",
                 "captures": {
                     "2": {"patterns": [{"include": "#names"}]},
                     "4": {"name": "punctuation.separator.column.ladder"},
                     "5": {"name": "storage.type.io.ladder"},
                     "6": {"name": "punctuation.separator.column.ladder"},
                     "7": {"patterns": [
                         {"match": r"\b[0-9]+\b", "name": "constant.numeric.pin.ladder"},
                         {"match": r"\b[A-Z]{1,3}[0-9]{1,2}\b", "name": "constant.other.port.ladder"}]},
                     "8": {"name": "punctuation.separator.column.ladder"},
                     "9": {"patterns": [{"match": r"\S+", "name": "constant.other.port.ladder"}]},
                     "10": {"name": "punctuation.separator.column.ladder"},
                     "11": {"name": "string.unquoted.pin-name.ladder"}}},
            ]},
        "var-list": {
            "begin": r"^(VAR LIST\s*:)\s*$",
            "beginCaptures": {"1": {"name": "markup.heading.section.ladder entity.name.section.ladder"}},
            "end": r"^(?=\S)",
            "name": "meta.var-list.ladder",
            "patterns": [
                {"match": r"^\s*([0-9]+)\s+(bytes?)\s+(total)\b",
                 "captures": {"1": {"name": "constant.numeric.ladder"}, "2": {"name": "keyword.other.ladder"},
                              "3": {"name": "keyword.other.ladder"}}},
                {"match": r"^\s*([0-9]+)\s+(bytes?)\s+(\S+)(.*)$",
                 "captures": {"1": {"name": "constant.numeric.ladder"}, "2": {"name": "keyword.other.ladder"},
                              "3": {"patterns": [{"include": "#names"}]},
                              "4": {"name": "comment.line.ladder"}}},
            ]},
        "settings": {
            "begin": r"^(SETTINGS\s*:)\s*$",
            "beginCaptures": {"1": {"name": "markup.heading.section.ladder entity.name.section.ladder"}},
            "end": r"^(?=\S)",
            "name": "meta.settings.ladder",
            "patterns": [
                {"match": r"^\s+([^:]+?)\s*(:)\s*(.*)$",
                 "captures": {"1": {"name": "support.type.property-name.ladder"},
                              "2": {"name": "punctuation.separator.key-value.ladder"},
                              "3": {"patterns": [
                                  {"match": r"\b(yes|no)\b", "name": "constant.language.ladder"},
                                  {"include": "#numbers"},
                                  {"match": r"\S+", "name": "string.unquoted.ladder"}]}}},
            ]},
        "details": {
            "begin": r"^(DETAILS\s*:)\s*$",
            "beginCaptures": {"1": {"name": "markup.heading.section.ladder entity.name.section.ladder"}},
            "end": r"^(?=\S)",
            "name": "meta.details.ladder",
            "patterns": [
                # `TON Tdly: ...`, `SPI SPI in rung 12 #2: ...`, `COMMENT in rung 4: ...`
                {"match": r"^\s+([A-Z][A-Z0-9_ ]*?)(?:\s+(?!in\s+rung\b)(\S+?))?"
                          r"(?:\s+(in\s+rung)\s+([0-9]+))?\s*(#[0-9]+)?(:)(.*)$",
                 "captures": {"1": {"name": "support.function.instruction.ladder"},
                              "2": {"patterns": [{"include": "#names"}]},
                              "3": {"name": "keyword.other.rung.ladder"},
                              "4": {"name": "constant.numeric.rung-number.ladder"},
                              "5": {"name": "constant.numeric.index.ladder"},
                              "6": {"name": "punctuation.separator.key-value.ladder"},
                              "7": {"patterns": [
                                  {"match": r"(?<=[:,])\s*([a-z][a-z_ ]*?)(?=\s)", "captures": {
                                      "1": {"name": "support.type.property-name.ladder"}}},
                                  {"match": ",", "name": "punctuation.separator.comma.ladder"},
                                  {"match": r"\"(?:[^\"\\]|\\.)*\"", "name": "string.quoted.double.ladder"},
                                  {"match": r"\b(yes|no)\b", "name": "constant.language.ladder"},
                                  {"include": "#numbers"}]}}},
            ]},
    },
}

T = "ldmicro"
ldmicro = {
    "$schema": "https://raw.githubusercontent.com/martinring/tmlanguage/master/tmlanguage.json",
    "name": "LDmicro program",
    "scopeName": "source.ldmicro",
    "patterns": [
        {"match": r"^LDmicro[0-9.]*\s*$", "name": "keyword.other.version.ldmicro"},
        {"match": r"^\s*(COMMENT)\b(.*)$",
         "captures": {"1": {"name": "support.function.instruction.ldmicro"}, "2": {"name": "comment.line.ldmicro"}}},
        {"match": r"^\s*(IO LIST|PROGRAM|VAR LIST|RUNG|END|PARALLEL|SERIES)\s*$", "name": "keyword.control.structure.ldmicro"},
        {"match": r"^([A-Z_]+)(=)(.*)$",
         "captures": {"1": {"name": "support.type.property-name.ldmicro"},
                      "2": {"name": "punctuation.separator.key-value.ldmicro"},
                      "3": {"patterns": [
                          {"match": r"([A-Za-z_]+)(=)", "captures": {
                              "1": {"name": "support.type.property-name.ldmicro"},
                              "2": {"name": "punctuation.separator.key-value.ldmicro"}}},
                          {"include": "#numbers"}]}}},
        {"match": r"^\s+(\S+)\s+(at)\s+(.*)$",
         "captures": {"1": {"patterns": [{"include": "#names"}]}, "2": {"name": "keyword.other.ldmicro"},
                      "3": {"patterns": [{"include": "#numbers"}]}}},
        {"match": r"^\s+([A-Z][A-Z0-9_]*)\b(.*)$",
         "captures": {"1": {"name": "support.function.instruction.ldmicro"},
                      "2": {"patterns": [
                          {"match": r"\"(?:[^\"\\]|\\.)*\"", "name": "string.quoted.double.ldmicro"},
                          {"include": "#numbers"}, {"include": "#names"}]}}},
    ],
    "repository": {"names": {"patterns": names(T)}, "numbers": {"patterns": numbers(T)}},
}

for fn, g in (("ladder", ladder), ("ldmicro", ldmicro)):
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "syntaxes", "%s.tmLanguage.json" % fn), "w") as f:
        json.dump(g, f, indent=2)
        f.write("\n")
