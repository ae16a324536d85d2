#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Generate the feature word's three views from golden_model/data/featword.json, the one definition.

The data describes the 320-bit feature stream word (m_axis_feat_tdata of orb_core: a feature beat
and an end-of-frame beat, told apart by a flag that equals tlast) and the 64-byte feature-memory
slot the CPU reads (orb_feat_mem: a feature slot and the end-of-frame record, told apart by a flag
bit). Writes hdl/common/orb_feat_pkg.vhd (field positions and widths as VHDL constants),
golden_model/featword.py (the same as Python data for golden_model.featcodec, the one codec) and
docs/feature-word.md (the tables). Deterministic: the same data gives byte-identical files. The
data is checked first (fields inside the word, not overlapping each other or the flag, slot fields
inside the used words and no wider than the stream field they carry, unique names). Usage:
sw/orb_flow/gen/featword.py [--out DIR] (DIR gets hdl/, golden_model/ and docs/ below it; default:
the repository; tb/common/test_orb_feat_pkg.py regenerates into a temporary directory).
"""

from __future__ import annotations

import json
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path

from golden_model._fields import WordField
from orb_flow.gen.codegen import align_colons, generator_main, pystr, render_views

ROOT = Path(__file__).resolve().parents[3]
DATA = ROOT / "golden_model" / "data" / "featword.json"
OUTPUTS = {
    "vhdl": Path("hdl") / "common" / "orb_feat_pkg.vhd",
    "python": Path("golden_model") / "featword.py",
    "markdown": Path("docs") / "feature-word.md",
}
SOURCE = "golden_model/data/featword.json"
GENERATOR = "sw/orb_flow/gen/featword.py"
NAME_RE = re.compile(r"^[a-z][a-z0-9_]*$")
VHDL_RE = re.compile(r"^[A-Z][A-Z0-9_]*$")
CHUNK = 32  # the codec decodes words as arrays of 32-bit chunks
LINE = 120  # ruff's and vsg's line length


@dataclass(frozen=True)
class Fld(WordField):
    """A field of the data (golden_model._fields.WordField, the class of the view; lsb counts in the
    whole word, a slot's words concatenated, word k from bit 32 k) and its VHDL constant stem:
    <stem>_LO_c and <stem>_BITS_c, or <stem>_BIT_c for one bit."""

    vhdl: str = ""


@dataclass(frozen=True)
class Lay:
    name: str
    pyname: str  # the Python constant: <NAME>_BEAT or SLOT_<NAME>
    flag_value: int
    description: str
    fields: tuple[Fld, ...]
    beat: str | None = None  # slot layouts: the stream beat they are filled from


@dataclass(frozen=True)
class FeatWord:
    name: str
    description: str
    port: str
    bits: int
    vhdl_bits: str
    eof_flag: Fld
    beats: tuple[Lay, ...]
    aliases: tuple[tuple[str, str], ...]
    slot_bytes: int
    word_bits: int
    words_used: int
    slot_vhdl: str
    slot_description: str
    record_flag: Fld
    slots: tuple[Lay, ...]

    @property
    def slot_words(self) -> int:
        return self.slot_bytes * 8 // self.word_bits

    @property
    def slot_bits(self) -> int:
        return self.words_used * self.word_bits

    def beat(self, name: str) -> Lay:
        return next(b for b in self.beats if b.name == name)


class FeatWordError(ValueError):
    """The feature word data is inconsistent."""


def _fld(raw: dict, word_bits: int | None = None) -> Fld:
    if word_bits is None:
        lsb = int(raw["lsb"] if "lsb" in raw else raw["bit"])
    else:
        lsb = int(raw["word"]) * word_bits + int(raw["lsb"] if "lsb" in raw else raw["bit"])
    width = int(raw.get("width", 1))
    return Fld(name=str(raw["name"]), lsb=lsb, width=width, vhdl=str(raw["vhdl"]), meaning=str(raw["meaning"]),
               source=raw.get("from"))  # fmt: skip


def load(path: Path = DATA) -> FeatWord:
    raw = json.loads(path.read_text())
    st, sl = raw["stream"], raw["slot"]
    wb = int(sl["word_bits"])
    beats = tuple(
        Lay(b["name"], f"{b['name'].upper()}_BEAT", int(b["tlast"]), str(b["description"]),
            tuple(_fld(f) for f in b["fields"]))
        for b in st["beats"]
    )  # fmt: skip
    slots = tuple(
        Lay(s["name"], f"SLOT_{s['name'].upper()}", int(s["flag"]), str(s["description"]),
            tuple(_fld(f, wb) for f in s["fields"]), str(s["beat"]))
        for s in sl["layouts"]
    )  # fmt: skip
    fw = FeatWord(
        name=str(raw["name"]),
        description=str(raw["description"]),
        port=str(st["port"]),
        bits=int(st["bits"]),
        vhdl_bits=str(st["vhdl_bits"]),
        eof_flag=_fld(st["flag"]),
        beats=beats,
        aliases=tuple((str(k), str(v)) for k, v in st.get("vhdl_aliases", {}).items()),
        slot_bytes=int(sl["bytes"]),
        word_bits=wb,
        words_used=int(sl["words_used"]),
        slot_vhdl=str(sl["vhdl"]),
        slot_description=str(sl["description"]),
        record_flag=_fld(sl["flag"], wb),
        slots=slots,
    )
    check(fw)
    return fw


def _check_layout(lay: Lay, flag: Fld, bits: int, where: str) -> None:
    if lay.flag_value not in (0, 1):
        raise FeatWordError(f"{where}: flag value {lay.flag_value} is not 0 or 1")
    names: set[str] = set()
    used = flag.mask
    for f in lay.fields:
        fw = f"{where} field {f.name}"
        if not NAME_RE.match(f.name) or f.name in names or f.name == flag.name:
            raise FeatWordError(f"{fw}: bad or repeated name")
        names.add(f.name)
        if f.width < 1 or f.lsb < 0 or f.msb >= bits:
            raise FeatWordError(f"{fw}: bits [{f.msb}:{f.lsb}] outside the {bits}-bit word")
        if used & f.mask:
            raise FeatWordError(f"{fw}: overlaps another field or the flag")
        used |= f.mask
        if f.width > CHUNK and (f.lsb % 8 or f.width % 8):
            raise FeatWordError(f"{fw}: a field wider than {CHUNK} bits must be whole bytes (the codec's byte view)")


def check(fw: FeatWord) -> None:
    if fw.bits % CHUNK or fw.bits <= 0:
        raise FeatWordError(f"stream word of {fw.bits} bits: not a multiple of {CHUNK}")
    if fw.eof_flag.width != 1 or not 0 <= fw.eof_flag.lsb < fw.bits:
        raise FeatWordError("the stream flag must be one bit inside the word")
    if sorted(b.flag_value for b in fw.beats) != [0, 1]:
        raise FeatWordError("the stream needs one beat with tlast 0 and one with tlast 1")
    for b in fw.beats:
        _check_layout(b, fw.eof_flag, fw.bits, f"beat {b.name}")
    if fw.word_bits != CHUNK:
        raise FeatWordError(f"slot words of {fw.word_bits} bits: the CPU reads {CHUNK}-bit words")
    if fw.slot_bytes * 8 % fw.word_bits or fw.slot_bytes & (fw.slot_bytes - 1):
        raise FeatWordError(f"slot of {fw.slot_bytes} bytes: not a power of two of whole words")
    if not 0 < fw.words_used <= fw.slot_words:
        raise FeatWordError(f"{fw.words_used} words used of a {fw.slot_words}-word slot")
    if fw.record_flag.width != 1 or not 0 <= fw.record_flag.lsb < fw.slot_bits:
        raise FeatWordError("the slot flag must be one bit inside the used words")
    if sorted(s.flag_value for s in fw.slots) != [0, 1]:
        raise FeatWordError("the slot needs one layout with flag 0 and one with flag 1")
    beats = {b.name: b for b in fw.beats}
    for s in fw.slots:
        where = f"slot {s.name}"
        _check_layout(s, fw.record_flag, fw.slot_bits, where)
        if s.beat not in beats:
            raise FeatWordError(f"{where}: filled from unknown beat {s.beat!r}")
        src = {f.name: f for f in beats[s.beat].fields}
        for f in s.fields:
            off = f.lsb % fw.word_bits
            if off + f.width > fw.word_bits and (off or f.width % fw.word_bits):
                raise FeatWordError(f"{where} field {f.name}: crosses a word boundary without filling whole words")
            if f.source is not None:
                if f.source not in src:
                    raise FeatWordError(f"{where} field {f.name}: beat {s.beat} has no field {f.source!r}")
                if src[f.source].width > f.width:
                    raise FeatWordError(f"{where} field {f.name}: narrower than the beat's {f.source}")
    constants: set[str] = set()
    for f in (fw.eof_flag, fw.record_flag, *(f for lay in (*fw.beats, *fw.slots) for f in lay.fields)):
        if not VHDL_RE.match(f.vhdl):
            raise FeatWordError(f"field {f.name}: bad VHDL stem {f.vhdl!r}")
        for c in vhdl_names(f):
            if c in constants:
                raise FeatWordError(f"VHDL constant {c}_c defined twice")
            constants.add(c)
    for alias, target in fw.aliases:
        if target not in constants or alias in constants:
            raise FeatWordError(f"VHDL alias {alias} = {target}: unknown target or repeated name")


def vhdl_names(f: Fld) -> tuple[str, ...]:
    return (f"{f.vhdl}_BIT",) if f.width == 1 else (f"{f.vhdl}_LO", f"{f.vhdl}_BITS")


def bits_text(lsb: int, msb: int) -> str:
    return f"[{lsb}]" if lsb == msb else f"[{msb}:{lsb}]"


def reserved_ranges(used: int, bits: int) -> list[tuple[int, int]]:
    """(lsb, msb) of the runs of bits below `bits` not set in `used`."""
    out: list[tuple[int, int]] = []
    b = 0
    while b < bits:
        if used >> b & 1:
            b += 1
            continue
        start = b
        while b < bits and not used >> b & 1:
            b += 1
        out.append((start, b - 1))
    return out


def summary(lay: Lay, flag: Fld, bits: int) -> list[str]:
    """`[11:0] score`, `[23:12] x`, ..., `[38] 0`, `[39] eof = 0`, ...: the layout in bit order."""
    items = [(f.lsb, f"{bits_text(f.lsb, f.msb)} {f.name}") for f in lay.fields]
    items.append((flag.lsb, f"{bits_text(flag.lsb, flag.lsb)} {flag.name} = {lay.flag_value}"))
    used = flag.mask
    for f in lay.fields:
        used |= f.mask
    items += [(lo, f"{bits_text(lo, hi)} 0") for lo, hi in reserved_ranges(used, bits)]
    return [text for _, text in sorted(items)]


def wrap_items(head: str, items: list[str], width: int = 100) -> list[str]:
    """`-- head item, item, ...` as comment lines of at most `width` characters, items kept whole."""
    lines, line = [], f"--   {head}"
    for i, item in enumerate(items):
        text = item + ("," if i < len(items) - 1 else "")
        if len(line) + 1 + len(text) > width:
            lines.append(line)
            line = "--     " + text
        else:
            line += " " + text
    return [*lines, line]


# ------------------------------------------------------------------------------------------------
# VHDL


def render_vhdl(fw: FeatWord) -> str:
    def comment(text: str) -> list[str]:
        return textwrap.wrap(text, 100, initial_indent="-- ", subsequent_indent="--   ")

    out = [
        "-- SPDX-License-Identifier: MIT",
        f"-- orb_feat_pkg: layout of the feature stream word ({fw.port}, {fw.bits} bits) and of",
        "-- the feature-memory slot of orb_feat_mem (docs/feature-word.md).",
    ]
    for b in fw.beats:
        out += wrap_items(f"{b.name} beat (tlast = {b.flag_value}):", summary(b, fw.eof_flag, fw.bits))
    out += comment(
        f"Slot: {fw.slot_bytes} bytes = {fw.slot_words} words of {fw.word_bits} bits, words 0 .. "
        f"{fw.words_used - 1} used; SLOT_/REC_ positions count in those words concatenated (word k at "
        f"bits {fw.word_bits} k + {fw.word_bits - 1} downto {fw.word_bits} k), as orb_feat_mem stores them."
    )
    for s in fw.slots:
        out += wrap_items(f"{s.name} slot:", summary(s, fw.record_flag, fw.slot_bits))
    out += [
        f"-- Generated by {GENERATOR} from {SOURCE}: do not edit.",
        "",
        "library ieee;",
        "use ieee.std_logic_1164.all;",
        "",
        "package orb_feat_pkg is",
        "",
        f"  -- stream word ({fw.port})",
        f"  constant {fw.vhdl_bits}_c : positive := {fw.bits};",
    ]

    def consts(f: Fld) -> list[str]:
        if f.width == 1:
            return [f"  constant {f.vhdl}_BIT_c : natural := {f.lsb};"]
        return [
            f"  constant {f.vhdl}_LO_c : natural := {f.lsb};",
            f"  constant {f.vhdl}_BITS_c : positive := {f.width};",
        ]

    out += [f"  -- {fw.eof_flag.meaning}", *consts(fw.eof_flag)]
    for b in fw.beats:
        out += ["", f"  -- {b.name} beat (tlast = {b.flag_value})"]
        for f in b.fields:
            out += consts(f)
    if fw.aliases:
        out += ["", "  -- other names"]
    for alias, target in fw.aliases:
        out.append(f"  constant {alias}_c : positive := {target}_c;")
    out += [
        "",
        f"  -- feature-memory slot: {fw.slot_bytes} bytes, {fw.slot_words} words of {fw.word_bits} bits, "
        f"words 0 .. {fw.words_used - 1} used",
        f"  constant {fw.slot_vhdl}_BYTES_c : positive := {fw.slot_bytes};",
        f"  constant {fw.slot_vhdl}_WORDS_c : positive := {fw.slot_words};",
        f"  constant {fw.slot_vhdl}_WORD_BITS_c : positive := {fw.word_bits};",
        f"  constant {fw.slot_vhdl}_WORDS_USED_c : positive := {fw.words_used};",
        f"  -- {fw.record_flag.meaning}",
        *consts(fw.record_flag),
    ]
    for s in fw.slots:
        out += ["", f"  -- {s.name} slot ({fw.record_flag.name} flag = {s.flag_value})"]
        for f in s.fields:
            out += consts(f)
    out += ["", "end package orb_feat_pkg;"]
    lines = align_colons(out)
    for line in lines:
        if len(line) > LINE:
            raise FeatWordError(f"VHDL line longer than {LINE}: {line}")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------------------------------
# Python


PY_HEADER = f'''\
# SPDX-License-Identifier: MIT
"""The feature stream word (m_axis_feat_tdata) and the feature-memory slot layout
(docs/feature-word.md), as data for golden_model.featcodec, the one codec.

A slot's positions count in its 32-bit words concatenated (word k at bits 32 k .. 32 k + 31).
Generated by {GENERATOR} from {SOURCE}: do not edit.
"""

from __future__ import annotations

from golden_model._fields import Layout
from golden_model._fields import WordField as Field
'''


def py_field(f: Fld, indent: str, trailer: str = ",") -> list[str]:
    lines = [f"{indent}Field("]
    args = [f"name={pystr(f.name)}", f"lsb={f.lsb}", f"width={f.width}", f"meaning={pystr(f.meaning)}"]
    if f.source is not None:
        args.append(f"source={pystr(f.source)}")
    lines += [f"{indent}    {a}," for a in args]
    lines.append(f"{indent}){trailer}")
    return lines


def py_layout(lay: Lay, bits: int, flag_name: str) -> list[str]:
    out = [
        f"{lay.pyname} = Layout(",
        f"    name={pystr(lay.name)},",
        f"    bits={bits},",
        f"    flag={flag_name},",
        f"    flag_value={lay.flag_value},",
        "    fields=(",
    ]
    for f in lay.fields:
        out += py_field(f, "        ")
    out += ["    ),", ")"]
    return out


def render_python(fw: FeatWord) -> str:
    eof_flag = f"{fw.eof_flag.name.upper()}_FLAG"
    rec_flag = f"{fw.record_flag.name.upper()}_FLAG"
    out = [PY_HEADER.rstrip("\n"), ""]
    out.append(f"FEAT_BITS = {fw.bits}  # bits of the stream word ({fw.port})")
    lines = py_field(fw.eof_flag, "", "")
    out += [f"{eof_flag} = {lines[0]}", *lines[1:]]
    for b in fw.beats:
        out += py_layout(b, fw.bits, eof_flag)
    out += [
        f"BEATS: tuple[Layout, ...] = ({', '.join(b.pyname for b in fw.beats)})",
        "",
        f"SLOT_BYTES = {fw.slot_bytes}  # bytes of a feature-memory slot",
        f"SLOT_WORD_BITS = {fw.word_bits}  # bits of a word the CPU reads",
        f"SLOT_WORDS = {fw.slot_words}  # words of a slot",
        f"SLOT_WORDS_USED = {fw.words_used}  # words 0 .. {fw.words_used - 1} carry data; the others read 0",
        f"SLOT_BITS = {fw.slot_bits}  # bits of the used words",
    ]
    lines = py_field(fw.record_flag, "", "")
    out += [f"{rec_flag} = {lines[0]}", *lines[1:]]
    for s in fw.slots:
        out += py_layout(s, fw.slot_bits, rec_flag)
    out.append(f"SLOTS: tuple[Layout, ...] = ({', '.join(s.pyname for s in fw.slots)})")
    for s in fw.slots:
        words = max(f.msb for f in (*s.fields, fw.record_flag)) // fw.word_bits + 1
        out.append(f"{s.pyname}_WORDS = {words}  # words 0 .. {words - 1} hold its fields")
    out.append("SLOT_BEAT: dict[str, Layout] = {  # the stream beat each slot layout is filled from")
    out += [f"    {pystr(s.name)}: {fw.beat(s.beat).pyname}," for s in fw.slots if s.beat is not None]
    out.append("}")
    text = "\n".join(out) + "\n"
    for line in text.splitlines():
        if len(line) > LINE:
            raise FeatWordError(f"Python line longer than {LINE} (shorten the data's text): {line}")
    return text


# ------------------------------------------------------------------------------------------------
# Markdown


def md_rows(lay: Lay, flag: Fld, bits: int, word_bits: int | None) -> list[str]:
    """Table rows in bit order: fields, the flag and the reserved runs."""
    rows: list[tuple[int, str]] = []
    used = flag.mask

    def where(lo: int, hi: int) -> str:
        if word_bits is None:
            return f"| {bits_text(lo, hi)} "
        k0, k1 = lo // word_bits, hi // word_bits
        if k0 != k1:
            return f"| {k0} .. {k1} | all "
        return f"| {k0} | {bits_text(lo % word_bits, hi % word_bits)} "

    for f in lay.fields:
        used |= f.mask
        src = "" if word_bits is None else f"| {f.source or '-'} "
        rows.append((f.lsb, f"{where(f.lsb, f.msb)}| `{f.name}` | {f.width} {src}| {f.meaning} |"))
    src = "" if word_bits is None else "| - "
    rows.append(
        (flag.lsb, f"{where(flag.lsb, flag.lsb)}| `{flag.name}` = {lay.flag_value} | 1 {src}| {flag.meaning} |")
    )
    if word_bits is None:
        for lo, hi in reserved_ranges(used, bits):
            rows.append((lo, f"{where(lo, hi)}| 0 | {hi - lo + 1} | reserved |"))
    else:
        # a reserved run as its part in a first word, the whole words and its part in a last word
        for lo, hi in reserved_ranges(used, bits):
            k = lo
            while k <= hi:
                end = min(hi, (k // word_bits + 1) * word_bits - 1)
                if k % word_bits == 0 and end % word_bits == word_bits - 1:
                    end = (hi + 1) // word_bits * word_bits - 1
                rows.append((k, f"{where(k, end)}| 0 | {end - k + 1} | - | reserved |"))
                k = end + 1
    return [text for _, text in sorted(rows)]


def vhdl_list(fields: tuple[Fld, ...]) -> str:
    return ", ".join(f"`{c}_c`" for f in fields for c in vhdl_names(f))


def render_markdown(fw: FeatWord) -> str:
    out = [
        "# Feature word and feature-memory slot",
        "",
        f"<!-- Generated by {GENERATOR} from {SOURCE}: do not edit. -->",
        "",
        *textwrap.wrap(fw.description, 100),
        "",
        "One definition, three views: `hdl/common/orb_feat_pkg.vhd` (VHDL constants), `golden_model/featword.py`",
        "(Python data) with its codec `golden_model/featcodec.py`, and this page. The stream's protocol:",
        "[rtl-detection.md](rtl-detection.md); the memory's: [feature-memory.md](feature-memory.md).",
        "",
        f"## Stream word (`{fw.port}`, {fw.bits} bits)",
        "",
        *textwrap.wrap(
            f"Bit `{fw.eof_flag.lsb}` is the {fw.eof_flag.meaning}. Package constant `{fw.vhdl_bits}_c` = {fw.bits}.",
            100,
        ),
        "",
    ]
    for b in fw.beats:
        out += [
            f"### {b.name} beat (tlast = {b.flag_value})",
            "",
            f"{b.description[0].upper()}{b.description[1:]}.",
            "",
            "| bits | field | width | meaning |",
            "|---|---|---|---|",
            *md_rows(b, fw.eof_flag, fw.bits, None),
            "",
            *textwrap.wrap(f"VHDL: {vhdl_list((fw.eof_flag, *b.fields))}.", 100),
            "",
        ]
    if fw.aliases:
        out += ["Also " + ", ".join(f"`{a}_c` = `{t}_c`" for a, t in fw.aliases) + ".", ""]
    out += [
        f"## Feature-memory slot ({fw.slot_bytes} bytes)",
        "",
        *textwrap.wrap(
            f"{fw.slot_description} Words {fw.words_used} .. {fw.slot_words - 1} are not stored and read 0. "
            f"Bit {fw.record_flag.lsb % fw.word_bits} of word {fw.record_flag.lsb // fw.word_bits} is the "
            f"{fw.record_flag.meaning}.",
            100,
        ),
        "",
        *textwrap.wrap(
            f"VHDL positions count in the used words concatenated (word k at bits {fw.word_bits} k + "
            f"{fw.word_bits - 1} downto {fw.word_bits} k, as orb_feat_mem stores a slot in one RAM word): "
            f"`{fw.slot_vhdl}_BYTES_c` = {fw.slot_bytes}, `{fw.slot_vhdl}_WORDS_c` = {fw.slot_words}, "
            f"`{fw.slot_vhdl}_WORD_BITS_c` = {fw.word_bits}, `{fw.slot_vhdl}_WORDS_USED_c` = {fw.words_used}.",
            100,
        ),
        "",
    ]
    for s in fw.slots:
        out += [
            f"### {s.name} slot ({fw.record_flag.name} flag = {s.flag_value})",
            "",
            *textwrap.wrap(
                f"{s.description[0].upper()}{s.description[1:]}; `from` names the field of the {s.beat} beat.", 100
            ),
            "",
            "| word | bits | field | width | from | meaning |",
            "|---|---|---|---|---|---|",
            *md_rows(s, fw.record_flag, fw.slot_bits, fw.word_bits),
            f"| {fw.words_used} .. {fw.slot_words - 1} | all | 0 | | - | not stored |",
            "",
            *textwrap.wrap(f"VHDL: {vhdl_list((fw.record_flag, *s.fields))}.", 100),
            "",
        ]
    return "\n".join(out)


RENDERERS = {"vhdl": render_vhdl, "python": render_python, "markdown": render_markdown}


def render(root: Path = ROOT, data: Path | None = None) -> dict[Path, str]:
    """The views of root's feature word (or of `data`), keyed by their repository-relative paths."""
    return render_views(load(data or root / SOURCE), OUTPUTS, RENDERERS)


def main() -> None:
    generator_main(__doc__ or "", "feature word", DATA, ROOT, lambda data: render(ROOT, data))


if __name__ == "__main__":
    main()
