# SPDX-License-Identifier: MIT
"""Generate the named configurations' three views from golden_model/data/configs.json, the one definition.

Writes hdl/common/orb_configs_pkg.vhd (the record type orb_config_t of the generics and one constant
per configuration; TOPS_DEFAULT_c is the tops' generic defaults), golden_model/configs.py (the same
as plain data, which golden_model.config turns into NamedConfig and Config.named) and
docs/configurations.md (the table). The data is checked first: every configuration is a legal
Config (golden_model.limits), its memory depth and overlay block legal, its budget within its bank,
the tops' default one of them, and the register map's THRESHOLD.low reset equal to the recommended
configuration's low threshold. A budget left out is resolved here (the recommended one of the frame
size within the bank), so that every view shows the number. Deterministic.
Usage: python -m orb_flow.gen.configs [--out DIR] (default: the repository).
"""

from __future__ import annotations

import json
import re
import textwrap
from pathlib import Path
from typing import Any

from orb_flow.gen.codegen import views_main

ROOT = Path(__file__).resolve().parents[3]
SOURCE = "golden_model/data/configs.json"
DATA = ROOT / SOURCE
VHDL = Path("hdl") / "common" / "orb_configs_pkg.vhd"
PYTHON = Path("golden_model") / "configs.py"
MARKDOWN = Path("docs") / "configurations.md"
GENERATOR = "orb_flow.gen.configs"
NAME_RE = re.compile(r"^[a-z][a-z0-9]*(-[a-z0-9]+)*$")
HARDWARE = ("width", "height", "scales", "step_num", "step_den", "sectors", "mem_depth", "block_log2", "mem_kind")
# the VHDL record holds the numeric generics; mem_kind is the tops' string generic MEM_KIND_g
VHDL_FIELDS = tuple(f for f in HARDWARE if f != "mem_kind")
MEM_KINDS = ("bram", "ddr")  # orb_feat_mem's banks, orb_feat_dma's ring (MEM_KIND_g "BRAM", "DDR")
RUNTIME = ("threshold", "threshold_lo", "selection", "budget", "cols", "rows")
TEXT = ("about", "used_by", "verified_by")
RECOMMENDED = "recommended-vga"  # golden_model.config's RECOMMENDED_* are this one's values


class ConfigsError(ValueError):
    """configs.json breaks a rule (the message names the configuration and the field)."""


def load(data: Path = DATA) -> dict[str, Any]:
    """The checked data, every budget resolved."""
    from golden_model import limits
    from golden_model.config import Config, ConfigError, recommended_budget
    from golden_model.overlay import check_marker_config

    raw = json.loads(data.read_text())
    if tuple(raw.get("hardware", ())) != HARDWARE or tuple(raw.get("runtime", ())) != RUNTIME:
        raise ConfigsError(f"'hardware' must list {HARDWARE} and 'runtime' {RUNTIME}")
    configs: dict[str, dict[str, Any]] = {}
    for name, entry in raw["configs"].items():
        if not NAME_RE.match(name):
            raise ConfigsError(f"{name!r}: names are lower-case words joined by '-'")
        extra = set(entry) - set(HARDWARE) - set(RUNTIME) - set(TEXT)
        missing = (set(HARDWARE) | set(RUNTIME) | set(TEXT)) - {"budget"} - set(entry)
        if extra or missing:
            raise ConfigsError(f"{name}: unknown fields {sorted(extra)}, missing fields {sorted(missing)}")
        e = dict(entry)
        capacity = e["mem_depth"] - 1
        if "budget" not in e:
            e["budget"] = min(capacity, recommended_budget(e["width"], e["height"])) if e["selection"] == "grid" else 0
        try:
            Config(**{k: e[k] for k in HARDWARE + RUNTIME if k not in ("mem_depth", "block_log2", "mem_kind")})
            check_marker_config(e["scales"], e["block_log2"])
        except (ConfigError, ValueError) as exc:
            raise ConfigsError(f"{name}: {exc}") from None
        if e["mem_kind"] not in MEM_KINDS:
            raise ConfigsError(f"{name}: mem_kind must be one of {MEM_KINDS}, got {e['mem_kind']!r}")
        if not limits.MEM_DEPTH.legal(e["mem_depth"]):
            raise ConfigsError(f"{name}: mem_depth must be {limits.MEM_DEPTH.text}, got {e['mem_depth']}")
        if e["budget"] > capacity:
            raise ConfigsError(f"{name}: budget {e['budget']} over the bank's {capacity} features")
        if not (isinstance(e["used_by"], list) and isinstance(e["verified_by"], list) and e["verified_by"]):
            raise ConfigsError(f"{name}: used_by and verified_by are lists (verified_by not empty)")
        configs[name] = e
    default = raw["tops_default"]
    if default not in configs:
        raise ConfigsError(f"tops_default {default!r} is not a configuration")
    if RECOMMENDED not in configs:
        raise ConfigsError(f"{RECOMMENDED!r} is missing (golden_model.config's RECOMMENDED_* come from it)")
    regmap = json.loads((data.parent / "regmap.json").read_text())  # the register map beside the data
    low = next(f for r in regmap["registers"] if r["name"] == "THRESHOLD" for f in r["fields"] if f["name"] == "low")
    if low["reset"] != configs[RECOMMENDED]["threshold_lo"]:
        want = configs[RECOMMENDED]["threshold_lo"]
        raise ConfigsError(f"regmap THRESHOLD.low resets to {low['reset']}, {RECOMMENDED}'s threshold_lo is {want}")
    return {"about": raw["about"], "tops_default": default, "configs": configs}


def const_name(name: str) -> str:
    return name.upper().replace("-", "_") + "_c"


def render_vhdl(d: dict[str, Any]) -> str:
    out = [
        "-- SPDX-License-Identifier: MIT",
        "-- orb_configs_pkg: the named configurations of the accelerator (docs/configurations.md), the",
        "-- generics of each as a constant of orb_config_t. TOPS_DEFAULT_c is the generic defaults of",
        f"-- orb_accel_top ({d['tops_default']}); orb_accel_zynq repeats it as literals (Vivado's module",
        "-- reference), which tb/common/test_orb_configs_pkg.py checks.",
        f"-- Generated by {GENERATOR} from {SOURCE}: do not edit.",
        "",
        "library work;",
        "  use work.orb_limits_pkg.all;",
        "",
        "package orb_configs_pkg is",
        "",
        "  type orb_config_t is record",
    ]
    width = max(map(len, VHDL_FIELDS))
    out += [f"    {f.ljust(width)} : {f}_t;" for f in VHDL_FIELDS]
    out += ["  end record orb_config_t;", ""]
    for name, e in d["configs"].items():
        out += textwrap.wrap(
            f"{name}: {e['about']}", 100, break_on_hyphens=False, initial_indent="  -- ", subsequent_indent="  -- "
        )
        out.append(f"  constant {const_name(name)} : orb_config_t := (")
        last = len(VHDL_FIELDS) - 1
        out += [f"    {f.ljust(width)} => {e[f]}{',' if i < last else ''}" for i, f in enumerate(VHDL_FIELDS)]
        out += ["  );", ""]
    out.append("  -- the generic defaults of the tops")
    out.append(f"  constant TOPS_DEFAULT_c : orb_config_t := {const_name(d['tops_default'])};")
    out += ["", "end package orb_configs_pkg;", ""]
    return "\n".join(out)


def _py(value: Any) -> str:
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "(" + ", ".join(_py(v) for v in value) + ",)" if value else "()"
    return str(value)


def render_python(d: dict[str, Any]) -> str:
    out = [
        "# SPDX-License-Identifier: MIT",
        f"# Generated by {GENERATOR} from {SOURCE}: do not edit.",
        '"""The named configurations (docs/configurations.md) as data; golden_model.config makes',
        'NamedConfig objects of them (Config.named, named)."""',
        "",
        "from __future__ import annotations",
        "",
        f"TOPS_DEFAULT = {_py(d['tops_default'])}",
        "",
        "CONFIGS: dict[str, dict[str, int | str | tuple[str, ...]]] = {",
    ]
    for name, e in d["configs"].items():
        out.append(f"    {_py(name)}: {{")
        for f in ("about", *HARDWARE, *RUNTIME, "used_by", "verified_by"):
            line = f"        {_py(f)}: {_py(e[f])},"
            if len(line) > 120 and isinstance(e[f], str):
                parts = textwrap.wrap(e[f], 100 - len(f), drop_whitespace=False, break_on_hyphens=False)
                out.append(f"        {_py(f)}: (")
                out += [f"            {_py(p)}" for p in parts]
                out.append("        ),")
            elif isinstance(e[f], list) and len(e[f]) > 1:
                out.append(f"        {_py(f)}: (")
                out += [f"            {_py(v)}," for v in e[f]]
                out.append("        ),")
            else:
                out.append(line)
        out.append("    },")
    out += ["}", ""]
    return "\n".join(out)


def _pyramid(e: dict[str, Any]) -> str:
    return f"{e['scales']} x {e['step_num']}:{e['step_den']}"


def _selection(e: dict[str, Any]) -> str:
    if e["selection"] == "all":
        return f"all, t {e['threshold']}"
    return f"grid {e['cols']}x{e['rows']}, budget {e['budget']:,}, t {e['threshold']} / {e['threshold_lo']}"


def render_markdown(d: dict[str, Any]) -> str:
    out = [
        "# Named configurations",
        "",
        f"<!-- Generated by {GENERATOR} from {SOURCE}: do not edit. -->",
        "",
        "Every device this project builds, simulates or measures has a name. The generics (frame, pyramid,",
        "sectors, the feature memory: block-RAM banks or a DDR ring, and its slots a frame, overlay block)",
        "are fixed when the bitstream or the simulation is built;",
        "the selection (budget, cells, thresholds t / t_lo) is what the driver writes to the registers",
        "at start-up. `Config.named(NAME)` (golden_model.config) gives the model's configuration,",
        "`orb-accel extract --config NAME`, `make sim CONFIG=NAME`, `orb-accel sim-server --config NAME` and",
        "`orb-accel ros --sim ... --sim-config NAME` use one, and `orb_configs_pkg` holds each as a VHDL",
        f"constant. The tops' generic defaults are **{d['tops_default']}**.",
        "",
        "| name | frame | pyramid | sectors | feature memory | overlay block | selection | used by | verified by |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, e in d["configs"].items():
        cells = [
            f"`{name}`",
            f"{e['width']}x{e['height']}",
            _pyramid(e),
            str(e["sectors"]),
            (
                f"DDR ring, {e['mem_depth']:,} slots a buffer"
                if e["mem_kind"] == "ddr"
                else f"2 banks of {e['mem_depth']:,} slots"
            ),
            f"{1 << e['block_log2']}x{1 << e['block_log2']}",
            _selection(e),
            "; ".join(e["used_by"]) or "-",
            "; ".join(e["verified_by"]),
        ]
        out.append("| " + " | ".join(cells) + " |")
    out += ["", "## What each is for", ""]
    for name, e in d["configs"].items():
        out += [f"- **`{name}`**: {e['about']}"]
    out.append("")
    return "\n".join(out)


def render(root: Path = ROOT) -> dict[Path, str]:
    """The three views' text, keyed by repository-relative path."""
    d = load(root / SOURCE)
    return {VHDL: render_vhdl(d), PYTHON: render_python(d), MARKDOWN: render_markdown(d)}


def main(argv: list[str] | None = None) -> None:
    views_main(__doc__, render, ROOT, argv)


if __name__ == "__main__":
    main()
