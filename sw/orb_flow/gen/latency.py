# SPDX-License-Identifier: MIT
"""Generate the block latencies' three views from golden_model/data/latency.json, the one definition.

Writes hdl/common/orb_latency_pkg.vhd (per block <NAME>_LAT_c, a sum written as the sum of its
parts' constants; a latency that depends on a generic as the function <name>_lat and its two
coefficients), golden_model/latency.py (the same as Python data: constants and Latency records of
golden_model.latency_types) and docs/latency.md (the table). Deterministic: the same data gives
byte-identical files. The data is checked first (names, parts defined before their sum, one of
clocks / sum / per_level per block). Usage: python -m orb_flow.gen.latency [--out DIR] (DIR gets hdl/,
golden_model/ and docs/ below it; default: the repository; tb/common/test_orb_latency_pkg.py
regenerates into a temporary directory).
"""

from __future__ import annotations

import json
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path

from orb_flow.gen.codegen import views_main

ROOT = Path(__file__).resolve().parents[3]
SOURCE = Path("golden_model") / "data" / "latency.json"
VHDL = Path("hdl") / "common" / "orb_latency_pkg.vhd"
PYTHON = Path("golden_model") / "latency.py"
MARKDOWN = Path("docs") / "latency.md"
GENERATOR = "sw/orb_flow/gen/latency.py"
NAME_RE = re.compile(r"^[a-z][a-z0-9_]*$")
ENTITY_RE = re.compile(r"^orb_[a-z0-9_]+$")
GENERIC_RE = re.compile(r"^[A-Z][A-Z0-9_]*_g$")
MEANING_MAX = 100  # one line of the Python view within ruff's 120 columns


class LatencyError(ValueError):
    """The latency data is inconsistent."""


@dataclass(frozen=True)
class Block:
    name: str
    entity: str
    meaning: str
    page: str
    test: str | None
    clocks: int | None
    parts: tuple[str, ...]
    per_level: int
    plus: int
    generic: str | None

    @property
    def const(self) -> str:
        return f"{self.name.upper()}_LAT"


@dataclass(frozen=True)
class Table:
    description: str
    notes: tuple[str, ...]
    blocks: tuple[Block, ...]

    def get(self, name: str) -> Block:
        return next(b for b in self.blocks if b.name == name)


def load(path: Path) -> Table:
    raw = json.loads(path.read_text())
    blocks: list[Block] = []
    for r in raw["blocks"]:
        name = str(r.get("name", ""))
        where = f"block {name!r}"
        kinds = [k for k in ("clocks", "sum", "per_level") if k in r]
        if len(kinds) != 1:
            raise LatencyError(f"{where}: needs exactly one of clocks, sum or per_level (has {kinds})")
        if not NAME_RE.match(name) or any(b.name == name for b in blocks):
            raise LatencyError(f"{where}: bad or repeated name")
        if not ENTITY_RE.match(str(r.get("entity", ""))):
            raise LatencyError(f"{where}: entity {r.get('entity')!r} is not orb_<name>")
        for key in ("meaning", "page"):
            if not isinstance(r.get(key), str) or not r[key] or "\n" in r[key] or len(r[key]) > MEANING_MAX:
                raise LatencyError(f"{where}: {key} must be one line of at most {MEANING_MAX} characters")
        if not r["page"].endswith(".md") or "/" in r["page"]:
            raise LatencyError(f"{where}: page {r['page']!r} is not a page of docs/")
        clocks: int | None = None
        parts: tuple[str, ...] = ()
        per_level = plus = 0
        generic = None
        if "clocks" in r:
            clocks = r["clocks"]
            if not isinstance(clocks, int) or clocks < 0:
                raise LatencyError(f"{where}: clocks {clocks!r} is not a natural number")
        elif "sum" in r:
            parts = tuple(str(p) for p in r["sum"])
            known = {b.name: b for b in blocks}
            if len(parts) < 2 or any(p not in known or known[p].clocks is None for p in parts):
                raise LatencyError(f"{where}: a sum of at least two fixed latencies listed before it, not {parts}")
            clocks = sum(known[p].clocks or 0 for p in parts)
        else:
            per_level, plus, generic = r["per_level"], r.get("plus", 0), r.get("generic")
            if not (isinstance(per_level, int) and per_level > 0 and isinstance(plus, int) and plus >= 0):
                raise LatencyError(f"{where}: per_level > 0 and plus >= 0, not {per_level}, {plus}")
            if not isinstance(generic, str) or not GENERIC_RE.match(generic):
                raise LatencyError(f"{where}: a latency per level names its generic NAME_g, not {generic!r}")
        test = r.get("test")
        if test is not None and not re.match(r"^tb/[a-z]+/test_\w+\.py$", str(test)):
            raise LatencyError(f"{where}: test {test!r} is not tb/<area>/test_*.py")
        blocks.append(Block(name, str(r["entity"]), r["meaning"], r["page"], test, clocks, parts, per_level, plus,
                            generic))  # fmt: skip
    return Table(str(raw["description"]), tuple(str(n) for n in raw.get("notes", ())), tuple(blocks))


def _comment(text: str, indent: str = "  ") -> list[str]:
    return textwrap.wrap(text, 100, initial_indent=f"{indent}-- ", subsequent_indent=f"{indent}-- ",
                         break_on_hyphens=False)  # fmt: skip


def render_vhdl(t: Table) -> str:
    out = [
        "-- SPDX-License-Identifier: MIT",
        "-- orb_latency_pkg: the fixed latencies of the accelerator's blocks in clocks (docs/latency.md),",
        "-- the one definition. Each entity sizes its delay lines with its constant (the constant is the",
        "-- latency) and asserts what its structure cannot show by itself; consumers use the same",
        "-- constants. A latency that is the sum of other blocks' is written as that sum; one that depends",
        "-- on a generic is a function of it.",
        f"-- Generated by {GENERATOR} from {SOURCE.as_posix()}: do not edit.",
        "",
        "package orb_latency_pkg is",
        "",
    ]
    funcs: list[Block] = []
    for b in t.blocks:
        out += _comment(f"{b.entity}: {b.meaning} (docs/{b.page})")
        if b.parts:
            expr = " + ".join(f"{p.upper()}_LAT_c" for p in b.parts)
            out.append(f"  constant {b.const}_c : natural := {expr};")
        elif b.clocks is not None:
            out.append(f"  constant {b.const}_c : natural := {b.clocks};")
        else:
            funcs.append(b)
            out += [
                f"  constant {b.const}_PER_LEVEL_c : natural := {b.per_level};",
                f"  constant {b.const}_PLUS_c      : natural := {b.plus};",
                f"  -- {b.const}_PER_LEVEL_c * n + {b.const}_PLUS_c for {b.generic} = n",
                f"  function {b.name}_lat (n : natural) return natural;",
            ]
        out.append("")
    out += ["end package orb_latency_pkg;", ""]
    if funcs:
        out[-1:] = ["", "package body orb_latency_pkg is", ""]
        for b in funcs:
            out += [
                f"  function {b.name}_lat (n : natural) return natural is",
                "  begin",
                f"    return {b.const}_PER_LEVEL_c * n + {b.const}_PLUS_c;",
                f"  end function {b.name}_lat;",
                "",
            ]
        out.append("end package body orb_latency_pkg;")
    else:
        out.pop()
    return "\n".join(out) + "\n"


def _pystr(s: str) -> str:
    if '"' in s and "'" not in s:
        return "'" + s.replace("\\", "\\\\") + "'"
    return json.dumps(s, ensure_ascii=False)


def render_python(t: Table) -> str:
    out = [
        "# SPDX-License-Identifier: MIT",
        '"""The fixed latencies of the accelerator\'s blocks in clocks (docs/latency.md), for the tests and the tools.',
        "",
        f"Generated by {GENERATOR} from {SOURCE.as_posix()}: do not edit.",
        '"""',
        "",
        "from __future__ import annotations",
        "",
        "from .latency_types import Latency",
        "",
    ]
    for b in t.blocks:
        if b.parts:
            out.append(f"{b.const} = {' + '.join(f'{p.upper()}_LAT' for p in b.parts)}  # {b.clocks}")
        elif b.clocks is not None:
            out.append(f"{b.const} = {b.clocks}")
        else:
            out += [f"{b.const}_PER_LEVEL = {b.per_level}", f"{b.const}_PLUS = {b.plus}"]
    out.append("")
    for b in t.blocks:
        args = [f"name={_pystr(b.name)}", f"entity={_pystr(b.entity)}", f"meaning={_pystr(b.meaning)}",
                f"page={_pystr(b.page)}"]  # fmt: skip
        if b.clocks is not None:
            args.append(f"clocks={b.const}")
        if b.parts:
            args.append(f"parts=({', '.join(_pystr(p) for p in b.parts)})")
        if b.clocks is None:
            args += [f"per_level={b.const}_PER_LEVEL", f"plus={b.const}_PLUS", f"generic={_pystr(b.generic or '')}"]
        if b.test is not None:
            args.append(f"test={_pystr(b.test)}")
        out.append(f"{b.name.upper()} = Latency(")
        out += [f"    {a}," for a in args]
        out.append(")")
    out += ["", "LATENCIES: tuple[Latency, ...] = ("]
    out += [f"    {b.name.upper()}," for b in t.blocks]
    out.append(")")
    out.append("BY_NAME: dict[str, Latency] = {lat.name: lat for lat in LATENCIES}")
    return "\n".join(out) + "\n"


def _clocks_text(t: Table, b: Block) -> str:
    if b.parts:
        return f"{b.clocks} = " + " + ".join(f"{t.get(p).clocks} (`{p}`)" for p in b.parts)
    if b.clocks is not None:
        return str(b.clocks)
    return f"{b.per_level} n + {b.plus}, n = `{b.generic}`"


def render_markdown(t: Table) -> str:
    out = [
        "# Latencies",
        "",
        f"<!-- Generated by {GENERATOR} from {SOURCE.as_posix()}: do not edit. -->",
        "",
        t.description,
        f"VHDL: `orb_latency_pkg` ({VHDL.as_posix()}); Python: `golden_model.latency`.",
        "",
        "| block | entity | clocks | from, to | VHDL | page | measured by |",
        "|---|---|---|---|---|---|---|",
    ]
    for b in t.blocks:
        vhdl = f"`{b.const}_c`" if b.clocks is not None else f"`{b.name}_lat({b.generic})`"
        test = f"`{b.test}`" if b.test else "its parts' tests" if b.parts else "no test measures it"
        out.append(f"| `{b.name}` | `{b.entity}` | {_clocks_text(t, b)} | {b.meaning} | {vhdl} | "
                   f"[{b.page}]({b.page}) | {test} |")  # fmt: skip
    out.append("")
    out += [f"- {n}" for n in t.notes]
    out.append("")
    return "\n".join(out)


def render(root: Path) -> dict[Path, str]:
    """The three views of root/golden_model/data/latency.json, keyed by repository-relative path."""
    t = load(root / SOURCE)
    return {VHDL: render_vhdl(t), PYTHON: render_python(t), MARKDOWN: render_markdown(t)}


def main(argv: list[str] | None = None) -> None:
    views_main(__doc__, render, ROOT, argv)


if __name__ == "__main__":
    main()
