#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Generate the register map's three views from golden_model/data/regmap.json, the one definition.

Writes hdl/host/orb_regs_pkg.vhd (offsets, field positions, write masks, reset values, ID and version
constants, and the register-file tables REGS_c and REG_LIMITS_c that orb_axil_regs decodes with),
golden_model/regs.py (the same as Python dataclasses for the
on-target driver and the testbenches) and docs/registers.md (the table). Deterministic: the same
data gives byte-identical files. The data is checked first (aligned unique offsets below MEM_BASE,
fields inside 32 bits and not overlapping, resets and maxima that fit their fields, known reset
names). Usage: python3 -m orb_flow.gen.regmap [--out DIR] (DIR gets hdl/, golden_model/ and docs/ below it;
default: the repository; tb/host/test_orb_regs_pkg.py regenerates into a temporary directory).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path

from golden_model._fields import RegField, Register
from orb_flow.gen.codegen import align_colons, generator_main, pystr, render_views

ROOT = Path(__file__).resolve().parents[3]
DATA = ROOT / "golden_model" / "data" / "regmap.json"
OUTPUTS = {
    "vhdl": Path("hdl") / "host" / "orb_regs_pkg.vhd",
    "python": Path("golden_model") / "regs.py",
    "markdown": Path("docs") / "registers.md",
}
ACCESS = ("ro", "rw", "w1c", "wo")
GENERIC_RE = re.compile(r"^[A-Z][A-Z0-9_]*_g$")
NAME_RE = re.compile(r"^[A-Z][A-Z0-9_]*$")
FIELD_RE = re.compile(r"^[a-z][a-z0-9_]*$")
SOURCE = "golden_model/data/regmap.json"


@dataclass(frozen=True)
class Const:
    name: str
    value: int
    hex: bool
    description: str


@dataclass(frozen=True)
class Fld(RegField):
    """A field of the data (golden_model._fields.RegField, the class of the view): its reset is an
    integer, a constant's name or a generic's name (ending _g); values names some of its values;
    max_generic: the largest legal written value is this generic of orb_axil_regs minus 1."""

    reset: int | str  # type: ignore[assignment]
    values: dict[int, str] = field(default_factory=dict)

    @property
    def limited(self) -> bool:
        """Whether a written value of this field is checked against a minimum or a maximum."""
        return self.max is not None or self.min is not None or self.max_generic is not None


@dataclass(frozen=True)
class Reg(Register):
    """A register of the data (golden_model._fields.Register, the class of the view)."""

    fields: tuple[Fld, ...]  # type: ignore[assignment]


@dataclass(frozen=True)
class RegMap:
    name: str
    description: str
    constants: tuple[Const, ...]
    notes: tuple[str, ...]
    registers: tuple[Reg, ...]

    def const(self, name: str) -> int:
        return next(c.value for c in self.constants if c.name == name)


class RegMapError(ValueError):
    """The register map data is inconsistent."""


def load(path: Path = DATA) -> RegMap:
    raw = json.loads(path.read_text())
    consts = tuple(
        Const(name, int(c["value"]), bool(c.get("hex", False)), str(c["description"]))
        for name, c in raw["constants"].items()
    )
    regs = []
    for r in raw["registers"]:
        fields = []
        for f in r["fields"]:
            msb, lsb = f["bits"]
            values = {int(k): str(v) for k, v in f.get("values", {}).items()}
            fields.append(
                Fld(
                    name=f["name"],
                    lsb=int(lsb),
                    width=int(msb) - int(lsb) + 1,
                    reset=f["reset"],
                    description=str(f["description"]),
                    port=f.get("port"),
                    max=f.get("max"),
                    pulse=bool(f.get("pulse", False)),
                    values=values,
                    min=f.get("min"),
                    max_generic=f.get("max_generic"),
                )
            )
        regs.append(Reg(name=r["name"], offset=int(r["offset"]), access=r["access"], fields=tuple(fields),
                        description=str(r["description"])))  # fmt: skip
    rm = RegMap(raw["name"], raw["description"], consts, tuple(raw.get("notes", ())), tuple(regs))
    check(rm)
    return rm


def check(rm: RegMap) -> None:
    names = {c.name for c in rm.constants}
    for need in ("ORB_ID", "VERSION_MAJOR", "VERSION_MINOR", "MEM_BASE", "BANKS"):
        if need not in names:
            raise RegMapError(f"constant {need} missing")
    for c in rm.constants:
        if not NAME_RE.match(c.name) or not 0 <= c.value < 1 << 32:
            raise RegMapError(f"constant {c.name} = {c.value}: bad name or not a 32-bit unsigned value")
    mem_base = rm.const("MEM_BASE")
    if mem_base & (mem_base - 1):
        raise RegMapError(f"MEM_BASE {mem_base:#x} is not a power of two")
    seen: dict[int, str] = {}
    reg_names: set[str] = set()
    for r in rm.registers:
        where = f"register {r.name}"
        if not NAME_RE.match(r.name) or r.name in reg_names:
            raise RegMapError(f"{where}: bad or repeated name")
        reg_names.add(r.name)
        if r.offset % 4 or not 0 <= r.offset < mem_base:
            raise RegMapError(f"{where}: offset {r.offset:#x} not 32-bit aligned below MEM_BASE {mem_base:#x}")
        if r.offset in seen:
            raise RegMapError(f"{where}: offset {r.offset:#x} already used by {seen[r.offset]}")
        seen[r.offset] = r.name
        if r.access not in ACCESS:
            raise RegMapError(f"{where}: access {r.access!r} not one of {ACCESS}")
        if not r.fields:
            raise RegMapError(f"{where}: no fields")
        used = 0
        fnames: set[str] = set()
        for f in r.fields:
            fw = f"{where} field {f.name}"
            if not FIELD_RE.match(f.name) or f.name in fnames:
                raise RegMapError(f"{fw}: bad or repeated name")
            fnames.add(f.name)
            if not 0 <= f.lsb <= f.msb <= 31:
                raise RegMapError(f"{fw}: bits [{f.msb}, {f.lsb}] outside 31..0")
            if used & f.mask:
                raise RegMapError(f"{fw}: overlaps another field")
            used |= f.mask
            if isinstance(f.reset, str):
                if not (GENERIC_RE.match(f.reset) or f.reset in names):
                    raise RegMapError(f"{fw}: reset {f.reset!r} is neither a constant nor a generic (NAME_g)")
                if GENERIC_RE.match(f.reset) and r.access != "ro":
                    raise RegMapError(f"{fw}: a generic reset value needs a ro register")
                value = rm.const(f.reset) if f.reset in names else 0
            else:
                value = int(f.reset)
            if not 0 <= value < 1 << f.width:
                raise RegMapError(f"{fw}: reset {value} does not fit {f.width} bits")
            if f.max is not None and not (0 <= f.max < (1 << f.width) - 1 and value <= f.max):
                raise RegMapError(f"{fw}: max {f.max} must be below the field's all-ones value and >= reset")
            if f.min is not None and not (0 < f.min <= value and (f.max is None or f.min <= f.max)):
                raise RegMapError(f"{fw}: min {f.min} must be above 0 and <= reset and max")
            if f.max_generic is not None and (f.max is not None or not GENERIC_RE.match(f.max_generic)):
                raise RegMapError(f"{fw}: max_generic names a generic (NAME_g) and excludes max")
            if (f.limited or f.pulse) and r.access not in ("rw", "wo"):
                raise RegMapError(f"{fw}: min, max and pulse need a rw or wo register")
            if f.port is not None and r.access != "ro":
                raise RegMapError(f"{fw}: a field following an input port must be ro")


# ------------------------------------------------------------------------------------------------
# VHDL


def vhex(value: int, bits: int = 32) -> str:
    return f'x"{value:0{bits // 4}X}"'


def vnat(value: int, hexa: bool = False) -> str:
    return f"16#{value:X}#" if hexa else str(value)


def reset_word(rm: RegMap, r: Reg) -> int | None:
    """The register's reset value when no field depends on a generic or an input port."""
    word = 0
    for f in r.fields:
        if f.port is not None or (isinstance(f.reset, str) and GENERIC_RE.match(f.reset)):
            return None
        value = rm.const(f.reset) if isinstance(f.reset, str) else f.reset
        word |= value << f.lsb
    return word


def fixed_word(rm: RegMap, r: Reg) -> int:
    """The reset (or, for ro registers, constant) value of the fields that follow no generic and no port."""
    word = 0
    for f in r.fields:
        if f.port is None and not (isinstance(f.reset, str) and GENERIC_RE.match(f.reset)):
            word |= (rm.const(f.reset) if isinstance(f.reset, str) else f.reset) << f.lsb
    return word


def live_mask(r: Reg) -> int:
    """The bits of the fields that follow a generic or an input port (wired in orb_axil_regs)."""
    m = 0
    for f in r.fields:
        if f.port is not None or (isinstance(f.reset, str) and GENERIC_RE.match(f.reset)):
            m |= f.mask
    return m


def pulse_mask(r: Reg) -> int:
    m = 0
    for f in r.fields:
        if f.pulse:
            m |= f.mask
    return m


def render_vhdl_tables(rm: RegMap) -> list[str]:
    out = [f"  constant REG_COUNT_c : positive := {len(rm.registers)};", ""]
    out.append("  constant REGS_c : reg_desc_array_t(0 to REG_COUNT_c - 1) :=")
    out.append("  (")
    width = max(len(f"REG_{r.name}_IDX_c") for r in rm.registers)
    out.append(f"    -- {'register'.ljust(width - 3)} => (offset, access, mask, reset, live, pulse)")
    for i, r in enumerate(rm.registers):
        acc = f"access_{r.access}"
        words = ", ".join(vhex(w) for w in (r.mask, fixed_word(rm, r), live_mask(r), pulse_mask(r)))
        sep = "," if i < len(rm.registers) - 1 else ""
        out.append(f"    {f'REG_{r.name}_IDX_c'.ljust(width)} => (REG_{r.name}_c, {acc}, {words}){sep}")
    out.append("  );")
    limits = [(r, f) for r in rm.registers for f in r.fields if f.limited]
    out.append("")
    out.append(f"  constant REG_LIMITS_c : reg_limit_array_t(0 to {max(len(limits), 1) - 1}) :=")
    out.append("  (")
    out.append("    -- field => (register, mask, min, max, depth, lsb)")
    if not limits:
        out.append(f"    0 => (0, {vhex(0)}, {vhex(0)}, {vhex(0)}, false, 0)")

    def limit_row(r: Reg, f: Fld) -> str:
        top = f.mask if f.max is None else f.max << f.lsb
        depth = "true" if f.max_generic is not None else "false"
        return f"(REG_{r.name}_IDX_c, {vhex(f.mask)}, {vhex((f.min or 0) << f.lsb)}, {vhex(top)}, {depth}, {f.lsb})"

    rows = [f"    {k} => {limit_row(r, f)}" + ("," if k < len(limits) - 1 else "") for k, (r, f) in enumerate(limits)]
    width = max((len(row) for row in rows), default=0)
    out += [f"{row.ljust(width)} -- {r.name}.{f.name}" for row, (r, f) in zip(rows, limits, strict=True)]
    out.append("  );")
    out.append("")
    return out


def render_vhdl(rm: RegMap) -> str:
    out = [
        "-- SPDX-License-Identifier: MIT",
        "-- orb_regs_pkg: the register map of orb_axil_regs (docs/registers.md): identification and",
        "-- version constants, the feature-memory window base MEM_BASE_c, and per register its byte",
        "-- offset REG_<NAME>_c, its index REG_<NAME>_IDX_c in the register file REGS_c, its",
        "-- defined-bits mask REG_<NAME>_MASK_c and, when no field follows a generic or an input port,",
        "-- its reset value REG_<NAME>_RESET_c; per field <REG>_<FIELD>_LSB_c, _MSB_c, _RESET_c (integer",
        "-- or constant resets) and _MAX_c (largest legal written value). REGS_c and REG_LIMITS_c are",
        "-- the tables orb_axil_regs decodes with, so a new register needs no decode code there; their",
        "-- types are orb_regs_types_pkg's.",
        f"-- Generated by sw/orb_flow/gen/regmap.py from {SOURCE}: do not edit.",
        "",
        "library ieee;",
        "use ieee.std_logic_1164.all;",
        "",
        "use work.orb_regs_types_pkg.all;",
        "",
        "package orb_regs_pkg is",
        "",
    ]
    for c in rm.constants:
        out.append(f"  -- {c.description}")
        if c.name == "ORB_ID":
            out.append(f"  constant {c.name}_c : std_logic_vector(31 downto 0) := {vhex(c.value)};")
        else:
            out.append(f"  constant {c.name}_c : natural := {vnat(c.value, c.hex)};")
    out.append("")
    for i, r in enumerate(rm.registers):
        out.append(f"  -- {r.name} ({r.access}): {r.description}")
        out.append(f"  constant REG_{r.name}_c : natural := 16#{r.offset:03X}#;")
        out.append(f"  constant REG_{r.name}_IDX_c : natural := {i};")
        out.append(f"  constant REG_{r.name}_MASK_c : std_logic_vector(31 downto 0) := {vhex(r.mask)};")
        word = reset_word(rm, r)
        if word is not None:
            out.append(f"  constant REG_{r.name}_RESET_c : std_logic_vector(31 downto 0) := {vhex(word)};")
        for f in r.fields:
            p = f"{r.name}_{f.name.upper()}"
            out.append(f"  constant {p}_LSB_c : natural := {f.lsb};")
            out.append(f"  constant {p}_MSB_c : natural := {f.msb};")
            if isinstance(f.reset, int):
                out.append(f"  constant {p}_RESET_c : natural := {f.reset};")
            elif not GENERIC_RE.match(f.reset):
                if f.reset == "ORB_ID":
                    continue
                out.append(f"  constant {p}_RESET_c : natural := {f.reset}_c;")
            if f.max is not None:
                out.append(f"  constant {p}_MAX_c : natural := {f.max};")
            if f.min is not None:
                out.append(f"  constant {p}_MIN_c : natural := {f.min};")
        out.append("")
    out += render_vhdl_tables(rm)
    out.append("end package orb_regs_pkg;")
    return "\n".join(align_colons(out)) + "\n"


# ------------------------------------------------------------------------------------------------
# Python


def pyfield(rm: RegMap, f: Fld) -> list[str]:
    names = {c.name for c in rm.constants}
    args = [f"name={pystr(f.name)}", f"lsb={f.lsb}", f"width={f.width}"]
    if isinstance(f.reset, int):
        args.append(f"reset={f.reset}")
    elif f.reset in names:
        args.append(f"reset={f.reset}")
    else:
        args += ["reset=None", f"generic={pystr(f.reset)}"]
    if f.port is not None:
        args.append(f"port={pystr(f.port)}")
    if f.max is not None:
        args.append(f"max={f.max}")
    if f.min is not None:
        args.append(f"min={f.min}")
    if f.max_generic is not None:
        args.append(f"max_generic={pystr(f.max_generic)}")
    if f.pulse:
        args.append("pulse=True")
    lines = ["        Field("]
    lines += [f"            {a}," for a in args]
    lines.append(f"            description={pystr(f.description)},")
    lines.append("        ),")
    return lines


PY_HEADER = '''\
# SPDX-License-Identifier: MIT
"""The accelerator's register map (docs/registers.md), for the on-target driver and the testbenches.

Generated by sw/orb_flow/gen/regmap.py from golden_model/data/regmap.json: do not edit.
"""

from __future__ import annotations

from golden_model._fields import RegField as Field
from golden_model._fields import Register
'''


def render_python(rm: RegMap) -> str:
    out = [PY_HEADER.rstrip("\n"), ""]
    for c in rm.constants:
        value = f"0x{c.value:X}" if c.hex else str(c.value)
        out.append(f"{c.name} = {value}  # {c.description}")
    out.append("")
    for r in rm.registers:
        out.append("")
        out.append(f"{r.name} = Register(")
        out.append(f"    name={pystr(r.name)},")
        out.append(f"    offset=0x{r.offset:03X},")
        out.append(f"    access={pystr(r.access)},")
        out.append("    fields=(")
        for f in r.fields:
            out += pyfield(rm, f)
        out.append("    ),")
        out.append(f"    description={pystr(r.description)},")
        out.append(")")
    out.append("")
    out.append("REGISTERS: tuple[Register, ...] = (")
    out += [f"    {r.name}," for r in rm.registers]
    out.append(")")
    out.append("BY_NAME: dict[str, Register] = {r.name: r for r in REGISTERS}")
    out.append("BY_OFFSET: dict[int, Register] = {r.offset: r for r in REGISTERS}")
    text = "\n".join(out) + "\n"
    return text


# ------------------------------------------------------------------------------------------------
# Markdown


def md_reset(rm: RegMap, f: Fld) -> str:
    if f.port is not None:
        return f"input `{f.port}`"
    if isinstance(f.reset, str):
        if GENERIC_RE.match(f.reset):
            return f"generic `{f.reset}`"
        return f"`{f.reset}` = {rm.const(f.reset):#x}"
    return str(f.reset) if f.reset < 10 else f"{f.reset} ({f.reset:#x})"


def md_bits(f: Fld) -> str:
    return f"{f.msb}" if f.msb == f.lsb else f"{f.msb}:{f.lsb}"


def render_markdown(rm: RegMap) -> str:
    out = [
        "# Registers of orb_axil_regs",
        "",
        f"<!-- Generated by sw/orb_flow/gen/regmap.py from {SOURCE}: do not edit. -->",
        "",
        rm.description,
        "The entity, its ports and the design decisions: [axil-regs.md](axil-regs.md).",
        "",
        "## Constants",
        "",
        "| name | value | meaning |",
        "|---|---|---|",
    ]
    for c in rm.constants:
        value = f"0x{c.value:X}" if c.hex else str(c.value)
        out.append(f"| `{c.name}` | {value} | {c.description} |")
    out += [
        "",
        "## Register map",
        "",
        "| offset | register | access | defined bits | description |",
        "|---|---|---|---|---|",
    ]
    for r in rm.registers:
        out.append(
            f"| 0x{r.offset:03X} | [{r.name}](#{r.name.lower()}) | {r.access} | 0x{r.mask:08X} | {r.description} |"
        )
    out += ["", "Access: ro read only, rw read/write, w1c write 1 to clear, wo write only.", "", "## Bus rules", ""]
    for n in rm.notes:
        out += [f"- {n}"]
    out += ["", "## Fields", ""]
    for r in rm.registers:
        out += [f"### {r.name}", "", f"Offset 0x{r.offset:03X}, {r.access}: {r.description}.", ""]
        out += ["| bits | field | reset | legal writes | description |", "|---|---|---|---|---|"]
        for f in r.fields:
            if r.access == "ro":
                legal = "-"
            elif f.pulse:
                legal = "1 pulses, 0 does nothing"
            else:
                top = str(f.max) if f.max is not None else str((1 << f.width) - 1)
                if f.max_generic is not None:
                    top = f"`{f.max_generic}` - 1"
                legal = f"{f.min or 0} .. {top}"
            desc = f.description
            if f.values:
                desc += "; " + ", ".join(f"{k} = {v}" for k, v in sorted(f.values.items()))
            out.append(f"| {md_bits(f)} | `{f.name}` | {md_reset(rm, f)} | {legal} | {desc} |")
        out.append("")
    return "\n".join(out)


RENDERERS = {"vhdl": render_vhdl, "python": render_python, "markdown": render_markdown}


def render(root: Path = ROOT, data: Path | None = None) -> dict[Path, str]:
    """The views of root's register map (or of `data`), keyed by their repository-relative paths."""
    return render_views(load(data or root / SOURCE), OUTPUTS, RENDERERS)


def main() -> None:
    generator_main(__doc__ or "", "register map", DATA, ROOT, lambda data: render(ROOT, data))


if __name__ == "__main__":
    main()
