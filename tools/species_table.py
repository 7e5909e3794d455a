#!/usr/bin/env python3
"""The species parameters of engine/model/species.def as Markdown tables (docs/MODEL.md "Parameters").

Reads every AF_SPECIES_PARAM(name, default, unit, rule, max) line, its trailing `//` comment (the
meaning) and the comment block just above a group of them (its section, e.g. "Table 1 of the
paper."), and prints one table per section: name, default with its unit, rule, max, meaning.

A `plain` parameter's unit is the one its comment names first ("cm: ...", "..., Hz (eq. 4)"); none
named, it has none. A parameter without a comment of its own (f_max after f_min), or whose comment
goes on from the line above ("//   pitches up ...") or only adds an aside ("// (MODEL.md: 2)"),
belongs with the commented parameter above it.

usage: tools/species_table.py                      print the tables
       tools/species_table.py --write docs/MODEL.md  replace the part between the markers
       tools/species_table.py --check docs/MODEL.md  exit 0 if that part is current, 1 if not
(2: species.def or the document cannot be read, or the document lacks the markers)
"""
import argparse
import os
import re
import sys
import textwrap

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_DEF = os.path.join(ROOT, "engine", "model", "species.def")
BEGIN = "<!-- species.def table: tools/species_table.py -->"
END = "<!-- end of species.def table -->"

PARAM = re.compile(
    r"^AF_SPECIES_PARAM\(\s*(\w+)\s*,\s*([^,]+?)\s*,\s*(\w+)\s*,\s*(\w+)\s*,\s*([^)]+?)\s*\)\s*(?://(.*))?$")
# The units a `plain` parameter's comment may name (cm, g, s as in species.def's struct).
PLAIN_UNITS = ["cm/s^2", "cm/s", "cm^2", "cm", "Hz/s", "Hz", "1/s", "s", "g", "dyn"]
UNIT_AT_START = re.compile(r"^(" + "|".join(re.escape(u) for u in PLAIN_UNITS) + r")(?=[:\s]|$)")
# What validate() asks of one parameter on its own (species.def's header).
RULES = {
    "positive": "> 0",
    "non_negative": ">= 0",
    "fraction": "0 < v < 1",
    "within_90": "\\|v\\| < 90 deg",
    "bank": "0 <= v < 90 deg",
    "any": "any",
}
UNIT_WORDS = {"degrees": "deg", "degrees_per_second": "deg/s"}


def fail(message):
    """A species.def or document this script cannot read: exit 2 (1 is "out of date")."""
    print(message, file=sys.stderr)
    sys.exit(2)


class Param:
    def __init__(self, name, default, unit, rule, largest, comment):
        self.name, self.default, self.unit, self.rule, self.max = name, default, unit, rule, largest
        self.comment = comment  # None: no comment; the text after "//" otherwise, spaces kept


def unit_named(comment):
    """The unit a plain parameter's comment names: at its start or as one of its comma parts."""
    text = comment.strip()
    m = UNIT_AT_START.match(text)
    if m:
        return m.group(1)
    for part in text.split(","):
        part = re.sub(r"\s*\(.*\)\s*$", "", part).strip()
        if part in PLAIN_UNITS:
            return part
    return ""


def parse(path):
    """[(section text, [Param])] in the file's order."""
    sections = []
    block = []  # the comment lines read since the last blank or parameter line
    for number, raw in enumerate(read(path).splitlines(), 1):
        line = raw.strip()
        if not line:
            block = []
        elif line.startswith("//"):
            block.append(line[2:].strip())
        elif line.startswith("AF_SPECIES_PARAM"):
            m = PARAM.match(line)
            if not m:
                fail(f"{path}:{number}: cannot read: {line}")
            if block or not sections:
                sections.append((" ".join(block), []))
                block = []
            sections[-1][1].append(Param(*m.groups()))
        else:
            fail(f"{path}:{number}: neither a comment nor AF_SPECIES_PARAM: {line}")
    return sections


def is_zero(text):
    try:
        return float(text) == 0.0
    except ValueError:
        return False


def read(path):
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except OSError as e:
        fail(f"{path}: {e.strerror}")


def cell(text):
    return text.replace("|", "\\|")


def render(sections):
    out = [
        "Generated from `engine/model/species.def` by `tools/species_table.py`; do not edit by hand.",
        "Defaults are in the unit shown (angles in degrees in the file, radians inside). \"must be",
        "set\": a `positive` parameter whose default is 0, so every species gives it. Rules: what",
        "`validate()` asks of the value alone; max: its largest size (either sign for `any`).",
        "",
    ]
    for text, params in sections:
        if text:
            out.extend(textwrap.wrap(f"*{cell(text)}*", 100, break_on_hyphens=False))
            out.append("")
        out.append("| Name | Default | Rule | Max | Meaning |")
        out.append("| --- | --- | --- | --- | --- |")
        head = None  # index of the last parameter with a comment of its own
        meanings, units = [], []
        for p in params:
            text = (p.comment or "").strip()
            goes_on = bool(text) and p.comment.startswith("  ")
            aside = text.startswith("(")
            if text and not goes_on and not aside:
                head = len(meanings)
                unit = unit_named(text) if p.unit == "plain" else ""
                # "cm: it sees no farther": the unit goes to the Default column.
                if unit and text.startswith(unit + ":") and text[len(unit) + 1:].strip():
                    text = text[len(unit) + 1:].strip()
                meanings.append(text)
                units.append(unit)
            else:
                if goes_on and head is not None:
                    meanings[head] += " " + text
                if head is None:
                    meanings.append("see the note above the table")
                    units.append("")
                else:
                    meanings.append(f"with `{params[head].name}`" + (" " + text if aside else ""))
                    units.append(units[head] if p.unit == "plain" else "")
        for p, unit_of_row in zip(params, units):
            p.shown_unit = UNIT_WORDS.get(p.unit, unit_of_row)
        for p, meaning in zip(params, meanings):
            unit = f" {p.shown_unit}" if p.shown_unit else ""
            if p.rule == "positive" and is_zero(p.default):
                default = "must be set"
            else:
                default = f"{p.default}{unit}"
            largest = ("±" if p.rule == "any" else "") + f"{p.max}{unit}"
            rule = RULES.get(p.rule)
            if rule is None:
                fail(f"unknown rule {p.rule} of {p.name}")
            out.append(f"| `{p.name}` | {default} | {rule} | {largest} | {cell(meaning)} |")
        out.append("")
    return "\n".join(out).rstrip("\n") + "\n"


def replace_between(doc, table, path):
    start, end = doc.find(BEGIN), doc.find(END)
    if start < 0 or end < 0 or end < start:
        fail(f"{path}: the markers are missing; it needs the lines\n{BEGIN}\n{END}")
    head = doc[: start + len(BEGIN)]
    return head + "\n\n" + table + "\n" + doc[end:]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    what = ap.add_mutually_exclusive_group()
    what.add_argument("--write", metavar="DOC", help="replace DOC's table between the markers")
    what.add_argument("--check", metavar="DOC", help="exit 1 unless DOC's table is current")
    ap.add_argument("--def", dest="def_path", default=DEFAULT_DEF, help="species.def to read")
    args = ap.parse_args()
    table = render(parse(args.def_path))
    doc_path = args.write or args.check
    if not doc_path:
        sys.stdout.write(table)
        return 0
    doc = read(doc_path)
    current = replace_between(doc, table, doc_path)
    if args.check:
        if current == doc:
            return 0
        print(f"{doc_path}: the species.def table is out of date; regenerate it with\n"
              f"  python3 tools/species_table.py --write {doc_path}", file=sys.stderr)
        return 1
    if current != doc:
        with open(doc_path, "w", encoding="utf-8") as f:
            f.write(current)
    return 0


if __name__ == "__main__":
    sys.exit(main())
