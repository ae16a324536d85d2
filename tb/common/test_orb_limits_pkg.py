# SPDX-License-Identifier: MIT
"""The configuration limits' generated views against their one definition, golden_model/data/limits.json.

No simulator: sw/orb_flow/gen/limits.py regenerated into a temporary directory must give the committed
hdl/common/orb_limits_pkg.vhd, golden_model/limits.py and docs/limits.md byte for byte (a stale view
fails); the generator must refuse inconsistent data; the VHDL constants, parsed from the text, must
equal golden_model.limits; Config and the CLI's option checks must accept exactly the legal values
of the data (read here from the JSON, not from the generated module) and refuse every other one;
every SECTORS_g is declared with sectors_t (the total, 16, 32 or 64, never the per-quadrant N);
GHDL must elaborate orb_orient_sector for every legal SECTORS_g and refuse the others, a value
inside sectors_t's range with the entity-naming assert.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import re
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from golden_model import limits
from golden_model.config import Config, ConfigError
from orb_flow.gen import limits as gen_limits
from orbtb.runner import ghdl_path_env
from orbtb.views import assert_view_fresh

ROOT = Path(__file__).resolve().parents[2]
HDL = ROOT / "hdl"
DATA = ROOT / "golden_model" / "data" / "limits.json"
VIEWS = (Path("hdl") / "common" / "orb_limits_pkg.vhd", Path("golden_model") / "limits.py", Path("docs") / "limits.md")
RAW: dict[str, dict[str, Any]] = {r["name"]: r for r in json.loads(DATA.read_text())["limits"]}
CONFIG_LIMITS = [name for name, r in RAW.items() if r.get("config")]
LEGAL: dict[str, Any] = {"width": 1920, "height": 1080, "scales": 2, "sectors": 32, "threshold": 20, "mode": "orb"}
# The pyramid step's fields are probed beside a partner value (step_den < step_num <= 2 step_den):
# step_num beside step_den 8 (legal 9..16), step_den beside step_num 5 (legal 4 only, a power of two).
STEP_PARTNER: dict[str, tuple[dict[str, int], Callable[[int], bool]]] = {
    "step_num": ({"step_den": 8}, lambda v: 8 < v <= 16),
    "step_den": ({"step_num": 5}, lambda v: v < 5 <= 2 * v),
}


def legal_in_data(name: str, value: int) -> bool:
    """Legality straight from the JSON data (independent of the generated golden_model.limits)."""
    r = RAW[name]
    if r.get("values"):
        return value in r["values"]
    if not r["min"] <= value <= r["max"]:
        return False
    return not r.get("power_of_two") or value & (value - 1) == 0


def probe(name: str) -> range:
    """Every value from a little below the limit's minimum to a little above its maximum."""
    r = RAW[name]
    return range(r["min"] - 3, r["max"] + 4)


# ------------------------------------------------------------------------------------------------
# generated views


@pytest.mark.parametrize("view", VIEWS, ids=lambda p: p.name)
def test_views_are_what_the_generator_writes(view: Path) -> None:
    assert_view_fresh(gen_limits, view, ROOT)


def _broken(raw: dict, what: str) -> dict:
    raw = copy.deepcopy(raw)
    lims = {r["name"]: r for r in raw["limits"]}
    if what == "min above max":
        lims["width"]["min"] = 2000
    elif what == "values not from min to max":
        lims["sectors"]["values"] = [16, 32]
    elif what == "values not ascending":
        lims["sectors"]["values"] = [16, 64, 32]
    elif what == "sectors not a multiple of 4":
        lims["sectors"]["values"] = [16, 30, 64]
    elif what == "register too narrow":
        lims["threshold"]["max"] = 256
    elif what == "unknown register":
        lims["width"]["register"] = "CFG_SIZE.breadth"
    elif what == "smallest-scale limit not spanning the frame":
        lims["scale_width"]["max"] = 1280
    elif what == "power-of-two bounds":
        lims["mem_depth"]["min"] = 24
    elif what == "bad generic name":
        lims["scales"]["generic"] = "SCALES"
    elif what == "missing limit":
        raw["limits"] = [r for r in raw["limits"] if r["name"] != "threshold"]
    elif what == "repeated name":
        raw["limits"].append(copy.deepcopy(lims["width"]))
    return raw


@pytest.mark.parametrize(
    "what",
    [
        "min above max",
        "values not from min to max",
        "values not ascending",
        "sectors not a multiple of 4",
        "register too narrow",
        "unknown register",
        "smallest-scale limit not spanning the frame",
        "power-of-two bounds",
        "bad generic name",
        "missing limit",
        "repeated name",
    ],
)
def test_generator_refuses_inconsistent_data(tmp_path: Path, what: str) -> None:
    gen = gen_limits
    path = tmp_path / "limits.json"
    path.write_text(json.dumps(_broken(json.loads(DATA.read_text()), what)))
    with pytest.raises(gen.LimitsError):
        gen.load(path)


def test_python_view_matches_the_data() -> None:
    assert [lim.name for lim in limits.LIMITS] == list(RAW)
    for lim in limits.LIMITS:
        r = RAW[lim.name]
        assert (lim.min, lim.max, lim.values) == (r["min"], r["max"], tuple(r.get("values", ()))), lim.name
        assert (lim.generic, lim.register, lim.config) == (r.get("generic"), r.get("register"), bool(r.get("config")))
        assert lim.power_of_two == bool(r.get("power_of_two")), lim.name


def test_vhdl_constants_equal_the_python_view() -> None:
    text = (ROOT / VIEWS[0]).read_text()
    ints = {n: int(v) for n, v in re.findall(r"constant\s+(\w+)_c\s*:\s*integer\s*:=\s*(-?\d+);", text)}
    texts = dict(re.findall(r'constant\s+(\w+)_TEXT_c\s*:\s*string\s*:=\s*"([^"]*)";', text))
    vectors = dict(re.findall(r"constant\s+(\w+)_VALUES_c\s*:\s*integer_vector\s*:=\s*\(([^)]*)\);", text))
    subtypes = dict(re.findall(r"subtype\s+(\w+)_t\s+is\s+integer\s+range\s+(\w+)_MIN_c\s+to\s+\2_MAX_c;", text))
    for lim in limits.LIMITS:
        k = lim.name.upper()
        assert (ints[f"{k}_MIN"], ints[f"{k}_MAX"]) == (lim.min, lim.max), k
        assert texts[k] == lim.text, k
        assert subtypes[lim.name] == k, f"subtype {lim.name}_t"
        assert f"function {lim.name}_legal (value : integer) return boolean;" in text
        if lim.values:
            assert tuple(int(v) for v in vectors[k].split(",")) == lim.values, k
        else:
            assert k not in vectors, k


def test_docs_list_every_limit() -> None:
    text = (ROOT / VIEWS[2]).read_text()
    for lim in limits.LIMITS:
        assert f"| `{lim.name}` | {lim.text} |" in text, lim.name


# ------------------------------------------------------------------------------------------------
# the model's Config and the CLI follow the data exactly


@pytest.mark.parametrize("name", CONFIG_LIMITS)
def test_config_accepts_exactly_the_legal_values(name: str) -> None:
    wrong = []
    partner, pair_legal = STEP_PARTNER.get(name, ({}, lambda v: True))
    for value in probe(name):
        try:
            Config(**{**LEGAL, **partner, name: value})
            accepted = True
        except ConfigError:
            accepted = False
        if accepted != (legal_in_data(name, value) and pair_legal(value)):
            wrong.append(value)
    assert not wrong, f"Config {name}: accepted/refused against {DATA.name} wrongly for {wrong[:10]}"


def test_config_fields_are_the_config_limits() -> None:
    fields = [f for f in Config.__dataclass_fields__ if f not in ("mode", "selection")]
    assert fields == CONFIG_LIMITS


@pytest.mark.parametrize(("n", "sectors"), [(4, 16), (8, 32), (16, 64)])
def test_sectors_is_the_total_and_n_is_derived(n: int, sectors: int) -> None:
    cfg = Config(**{**LEGAL, "sectors": sectors})
    assert (cfg.sectors, cfg.sectors_per_quadrant) == (sectors, n)
    if n != limits.SECTORS_MIN:  # N = 16 is also the smallest total
        with pytest.raises(ConfigError, match="sectors"):
            Config(**{**LEGAL, "sectors": n})  # N, the sectors per quadrant, is not a sector count


@pytest.mark.parametrize(
    ("option", "name"), [("--threshold", "threshold"), ("--scales", "scales"), ("--sectors", "sectors")]
)
def test_cli_options_accept_exactly_the_legal_values(option: str, name: str) -> None:
    from orb_tools import cli

    check = {"threshold": cli._threshold, "scales": cli._scales, "sectors": cli._sectors}[name]
    for value in probe(name):
        try:
            check(str(value))
            accepted = True
        except argparse.ArgumentTypeError:
            accepted = False
        assert accepted == legal_in_data(name, value), f"orb-accel {option} {value}"


# ------------------------------------------------------------------------------------------------
# the HDL uses the package


def test_every_sectors_generic_is_the_total() -> None:
    decls = {}
    for path in sorted(HDL.rglob("*.vhd")):
        for m in re.finditer(r"^\s*SECTORS_g\s*:\s*(\w+)(?:\s+range[^:]*)?\s*:=\s*(\d+)", path.read_text(), re.M):
            decls[path.relative_to(HDL).as_posix()] = (m[1], int(m[2]))
    assert len(decls) >= 7, decls
    for rel, (subtype, default) in decls.items():
        # orb_accel_zynq stays plain VHDL-93 (integer generics); orb_accel_top below it checks them
        assert subtype == ("integer" if rel == "top/orb_accel_zynq.vhd" else "sectors_t"), rel
        assert limits.SECTORS.legal(default), f"{rel}: default SECTORS_g {default} is not a total"


def test_no_hdl_file_restates_a_limit() -> None:
    stale = []
    for path in sorted(HDL.rglob("*.vhd")):
        if path.name == "orb_limits_pkg.vhd":
            continue
        text = path.read_text()
        for lim in limits.LIMITS:
            if lim.generic and re.search(rf"\b{lim.generic}\s*:\s*\w+\s+range\s+{lim.min}\s+to\s+{lim.max}\b", text):
                stale.append(f"{path.relative_to(HDL)}: {lim.generic} range {lim.min} to {lim.max}")
    assert not stale, "declare these generics with the orb_limits_pkg subtypes: " + "; ".join(stale)


def _ghdl(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, **ghdl_path_env()}
    return subprocess.run(["ghdl", *args], cwd=cwd, env=env, capture_output=True, text=True, check=False)


def test_ghdl_refuses_exactly_the_illegal_sectors(tmp_path: Path) -> None:
    files = [
        str(HDL / "common" / "orb_util_pkg.vhd"),
        str(HDL / "common" / "orb_latency_pkg.vhd"),
        str(ROOT / VIEWS[0]),
        str(HDL / "describe" / "orb_orient_sector.vhd"),
    ]
    proc = _ghdl(["-a", "--std=08", *files], tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for sectors in (16, 24, 32, 64, 8):
        proc = _ghdl(["synth", "--std=08", f"-gSECTORS_g={sectors}", "--out=none", "orb_orient_sector"], tmp_path)
        out = proc.stdout + proc.stderr
        if limits.SECTORS.legal(sectors):
            assert proc.returncode == 0, f"SECTORS_g={sectors}: {out}"
        elif limits.SECTORS.min <= sectors <= limits.SECTORS.max:
            assert proc.returncode != 0 and "orb_orient_sector: SECTORS_g" in out and limits.SECTORS.text in out, out
        else:
            assert proc.returncode != 0 and "out of bounds" in out, f"SECTORS_g={sectors}: {out}"
