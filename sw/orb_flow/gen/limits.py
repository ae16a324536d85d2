#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Generate the configuration limits' three views from golden_model/data/limits.json, the one definition.

Writes hdl/common/orb_limits_pkg.vhd (per parameter <NAME>_MIN_c, <NAME>_MAX_c, the range subtype
<name>_t, <NAME>_TEXT_c and the function <name>_legal, which the entities' generics and asserts use),
golden_model/limits.py (the same as Python constants and Limit records, for the model's Config and
the CLI) and docs/limits.md (the table). Deterministic: the same data gives byte-identical files. The
data is checked first (names, min <= max, value sets inside min..max, powers of two, every legal
value fitting its read-back register field in golden_model/data/regmap.json, scale_width/scale_height
spanning width/height). Usage: python3 -m orb_flow.gen.limits [--out DIR] (DIR gets hdl/,
golden_model/ and docs/ below it; default: the repository; tb/common/test_orb_limits_pkg.py
regenerates into a temporary directory).
"""

from __future__ import annotations

import json
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path

from golden_model._fields import Limit
from orb_flow.gen.codegen import generator_main, pystr, render_views

ROOT = Path(__file__).resolve().parents[3]
DATA = ROOT / "golden_model" / "data" / "limits.json"
REGMAP = ROOT / "golden_model" / "data" / "regmap.json"
OUTPUTS = {
    "vhdl": Path("hdl") / "common" / "orb_limits_pkg.vhd",
    "python": Path("golden_model") / "limits.py",
    "markdown": Path("docs") / "limits.md",
}
SOURCE = "golden_model/data/limits.json"
NAME_RE = re.compile(r"^[a-z][a-z0-9_]*$")
GENERIC_RE = re.compile(r"^[A-Z][A-Z0-9_]*_g$")
REGISTER_RE = re.compile(r"^([A-Z][A-Z0-9_]*)\.([a-z][a-z0-9_]*)$")
REQUIRED = ("width", "height", "scales", "step_num", "step_den", "sectors", "threshold", "scale_width", "scale_height")


@dataclass(frozen=True)
class Lim(Limit):
    """A limit of the data (golden_model._fields.Limit, the class of the view) and its constants' stem."""

    @property
    def const(self) -> str:
        return self.name.upper()


def legal_text(min_: int, max_: int, values: tuple[int, ...], power_of_two: bool) -> str:
    """The legal values as messages and docs write them."""
    if values:
        return ", ".join(map(str, values[:-1])) + f" or {values[-1]}"
    if power_of_two:
        return f"a power of two in {min_}..{max_}"
    return f"{min_}..{max_}"


@dataclass(frozen=True)
class Limits:
    description: str
    notes: tuple[str, ...]
    limits: tuple[Lim, ...]

    def get(self, name: str) -> Lim:
        return next(lim for lim in self.limits if lim.name == name)


class LimitsError(ValueError):
    """The limits data is inconsistent."""


def load(path: Path = DATA, regmap: Path = REGMAP) -> Limits:
    raw = json.loads(path.read_text())
    lims = []
    for r in raw["limits"]:
        lo, hi = int(r["min"]), int(r["max"])
        values = tuple(int(v) for v in r.get("values", ()))
        power_of_two = bool(r.get("power_of_two", False))
        lims.append(
            Lim(
                name=str(r["name"]),
                min=lo,
                max=hi,
                text=legal_text(lo, hi, values, power_of_two),
                description=str(r["description"]),
                values=values,
                power_of_two=power_of_two,
                generic=r.get("generic"),
                register=r.get("register"),
                config=bool(r.get("config", False)),
            )
        )
    out = Limits(str(raw["description"]), tuple(str(n) for n in raw.get("notes", ())), tuple(lims))
    check(out, json.loads(regmap.read_text()))
    return out


def register_field_bits(regmap: dict, register: str) -> int:
    """Width in bits of the register field named REG.field in the register map data."""
    m = REGISTER_RE.match(register)
    if m is None:
        raise LimitsError(f"register {register!r} is not REGISTER.field")
    for r in regmap["registers"]:
        if r["name"] == m[1]:
            for f in r["fields"]:
                if f["name"] == m[2]:
                    msb, lsb = f["bits"]
                    return int(msb) - int(lsb) + 1
    raise LimitsError(f"register field {register} is not in the register map")


def check(lims: Limits, regmap: dict) -> None:
    names = [lim.name for lim in lims.limits]
    for need in REQUIRED:
        if need not in names:
            raise LimitsError(f"limit {need} missing")
    for lim in lims.limits:
        where = f"limit {lim.name}"
        if not NAME_RE.match(lim.name) or names.count(lim.name) != 1:
            raise LimitsError(f"{where}: bad or repeated name")
        if not 0 <= lim.min <= lim.max < 1 << 31:
            raise LimitsError(f"{where}: needs 0 <= min {lim.min} <= max {lim.max} < 2^31")
        if lim.values:
            if list(lim.values) != sorted(set(lim.values)):
                raise LimitsError(f"{where}: values {lim.values} not strictly ascending")
            if (lim.values[0], lim.values[-1]) != (lim.min, lim.max):
                raise LimitsError(f"{where}: values {lim.values} must run from min {lim.min} to max {lim.max}")
            if lim.power_of_two:
                raise LimitsError(f"{where}: a value set and power_of_two together")
        if lim.power_of_two and (lim.min & (lim.min - 1) or lim.max & (lim.max - 1) or lim.min == 0):
            raise LimitsError(f"{where}: power-of-two limits {lim.min}..{lim.max} are not powers of two")
        if lim.generic is not None and not GENERIC_RE.match(lim.generic):
            raise LimitsError(f"{where}: generic {lim.generic!r} is not NAME_g")
        if lim.register is not None:
            bits = register_field_bits(regmap, lim.register)
            if lim.max >= 1 << bits:
                raise LimitsError(f"{where}: max {lim.max} does not fit {lim.register} ({bits} bits)")
    width, height = lims.get("width"), lims.get("height")
    scale_width, scale_height = lims.get("scale_width"), lims.get("scale_height")
    if scale_width.max != width.max or scale_height.max != height.max:
        raise LimitsError("scale_width.max must be width.max and scale_height.max height.max")
    sectors = lims.get("sectors")
    if any(v % 4 or 256 % v for v in sectors.values or (sectors.min, sectors.max)):
        raise LimitsError("sectors must be multiples of 4 (four quadrants) that divide the 256 tests")


# ------------------------------------------------------------------------------------------------
# VHDL


def render_vhdl(lims: Limits) -> str:
    head = [
        "-- SPDX-License-Identifier: MIT",
        "-- orb_limits_pkg: the legal configuration values of the accelerator (docs/limits.md). Per",
        "-- parameter <NAME>_MIN_c and <NAME>_MAX_c, the range subtype <name>_t that generics are declared",
        "-- with, <NAME>_TEXT_c (the legal values as an assert's message writes them) and the function",
        "-- <name>_legal (value sets and powers of two: what a range subtype cannot say), which the",
        "-- entities assert on. sectors is the total number of orientation sectors (4N).",
        f"-- Generated by sw/orb_flow/gen/limits.py from {SOURCE}: do not edit.",
        "",
        "package orb_limits_pkg is",
        "",
    ]
    decls: list[str] = []
    for lim in lims.limits:
        k = lim.const
        decls += textwrap.wrap(f"{lim.name}: {lim.description}; legal: {lim.text}", 100,
                               initial_indent="  -- ", subsequent_indent="  -- ")  # fmt: skip
        group = [
            (f"{k}_MIN_c", f"integer := {lim.min};"),
            (f"{k}_MAX_c", f"integer := {lim.max};"),
        ]
        if lim.values:
            group.append((f"{k}_VALUES_c", f"integer_vector := ({', '.join(map(str, lim.values))});"))
        group.append((f"{k}_TEXT_c", f'string := "{lim.text}";'))
        width = max(len(n) for n, _ in group)
        decls += [f"  constant {n.ljust(width)} : {rest}" for n, rest in group]
        decls.append(f"  function {lim.name}_legal (value : integer) return boolean;")
        decls.append("")
    decls.append("  -- The range subtypes of the generics (a value set or a power-of-two rule needs <name>_legal too).")
    decls += [f"  subtype {lim.name}_t is integer range {lim.const}_MIN_c to {lim.const}_MAX_c;" for lim in lims.limits]
    decls.append("")
    body = ["end package orb_limits_pkg;", "", "package body orb_limits_pkg is", ""]
    for lim in lims.limits:
        k = lim.const
        body.append(f"  function {lim.name}_legal (value : integer) return boolean is")
        if lim.values:
            body += [
                "  begin",
                f"    for i in {k}_VALUES_c'range loop",
                f"      if value = {k}_VALUES_c(i) then",
                "        return true;",
                "      end if;",
                "    end loop;",
                "    return false;",
            ]
        elif lim.power_of_two:
            body += [
                "    variable p : integer := 1;",
                "  begin",
                f"    if value < {k}_MIN_c or value > {k}_MAX_c then",
                "      return false;",
                "    end if;",
                "    while p < value loop",
                "      p := 2 * p;",
                "    end loop;",
                "    return p = value;",
            ]
        else:
            body += ["  begin", f"    return value >= {k}_MIN_c and value <= {k}_MAX_c;"]
        body += [f"  end function {lim.name}_legal;", ""]
    body.append("end package body orb_limits_pkg;")
    return "\n".join(head + decls + body) + "\n"


# ------------------------------------------------------------------------------------------------
# Python


PY_HEADER = '''\
# SPDX-License-Identifier: MIT
"""The accelerator's legal configuration values (docs/limits.md), for the model's Config, the CLI and the tests.

Generated by sw/orb_flow/gen/limits.py from golden_model/data/limits.json: do not edit.
"""

from __future__ import annotations

from golden_model._fields import Limit
'''


def render_python(lims: Limits) -> str:
    out = [PY_HEADER.rstrip("\n")]
    for lim in lims.limits:
        k = lim.const
        out.append("")
        out.append(f"{k}_MIN = {lim.min}")
        out.append(f"{k}_MAX = {lim.max}")
        if lim.values:
            out.append(f"{k}_VALUES = ({', '.join(map(str, lim.values))})")
        args = [
            f"name={pystr(lim.name)}",
            f"min={k}_MIN",
            f"max={k}_MAX",
            f"text={pystr(lim.text)}",
            f"description={pystr(lim.description)}",
        ]
        if lim.values:
            args.append(f"values={k}_VALUES")
        if lim.power_of_two:
            args.append("power_of_two=True")
        if lim.generic is not None:
            args.append(f"generic={pystr(lim.generic)}")
        if lim.register is not None:
            args.append(f"register={pystr(lim.register)}")
        if lim.config:
            args.append("config=True")
        out.append(f"{k} = Limit(")
        out += [f"    {a}," for a in args]
        out.append(")")
    out += ["", "LIMITS: tuple[Limit, ...] = ("]
    out += [f"    {lim.const}," for lim in lims.limits]
    out.append(")")
    out.append("BY_NAME: dict[str, Limit] = {lim.name: lim for lim in LIMITS}")
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------------------------------------
# Markdown


def render_markdown(lims: Limits) -> str:
    out = [
        "# Configuration limits",
        "",
        f"<!-- Generated by sw/orb_flow/gen/limits.py from {SOURCE}: do not edit. -->",
        "",
        lims.description,
        "VHDL: `orb_limits_pkg` (hdl/common/orb_limits_pkg.vhd); Python: `golden_model.limits`.",
        "",
        "| parameter | legal values | description | generic | read back in | `Config` field |",
        "|---|---|---|---|---|---|",
    ]
    for lim in lims.limits:
        generic = f"`{lim.generic}` (`{lim.name}_t`)" if lim.generic else "-"
        register = f"`{lim.register}`" if lim.register else "-"
        config = f"`{lim.name}`" if lim.config else "-"
        out.append(f"| `{lim.name}` | {lim.text} | {lim.description} | {generic} | {register} | {config} |")
    out.append("")
    out += [f"- {n}" for n in lims.notes]
    out.append("")
    return "\n".join(out)


RENDERERS = {"vhdl": render_vhdl, "python": render_python, "markdown": render_markdown}


def render(root: Path = ROOT, data: Path | None = None) -> dict[Path, str]:
    """The views of root's limits (or of `data`), keyed by their repository-relative paths."""
    return render_views(load(data or root / SOURCE), OUTPUTS, RENDERERS)


def main() -> None:
    generator_main(__doc__ or "", "limits", DATA, ROOT, lambda data: render(ROOT, data))


if __name__ == "__main__":
    main()
