# SPDX-License-Identifier: MIT
"""The block latencies' generated views against their one definition, golden_model/data/latency.json.

No simulation: orb_flow.gen.latency regenerated into a temporary directory must give the committed
hdl/common/orb_latency_pkg.vhd, golden_model/latency.py and docs/latency.md byte for byte (a stale
view fails); the generator must refuse inconsistent data; the VHDL constants, parsed and summed from
the text, and the Python view must equal the data (read here from the JSON); every page and test the
data names must exist; GHDL must analyse the package; and no HDL file outside the package may state
a latency as a literal (a `..._LAT_c` constant with a number, `MEM_LATENCY_g => 3`). The entity
tests measure each latency against golden_model.latency; tb/house/test_latency_claims.py checks the
docs' and headers' numbers.
"""

from __future__ import annotations

import copy
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from golden_model import latency
from orb_flow.gen import latency as gen
from orbtb.runner import ghdl_path_env

ROOT = Path(__file__).resolve().parents[2]
HDL = ROOT / "hdl"
DATA = ROOT / gen.SOURCE
RAW = {r["name"]: r for r in json.loads(DATA.read_text())["blocks"]}
VIEWS = (gen.VHDL, gen.PYTHON, gen.MARKDOWN)


def fixed_clocks(name: str) -> int:
    """A fixed latency straight from the JSON (a sum added up here)."""
    r = RAW[name]
    return r["clocks"] if "clocks" in r else sum(fixed_clocks(p) for p in r["sum"])


# ------------------------------------------------------------------------------------------------
# generated views


@pytest.fixture(scope="module")
def regenerated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("latency")
    subprocess.run([sys.executable, "-m", "orb_flow.gen.latency", "--out", str(out)], check=True,
                   capture_output=True, cwd=ROOT)  # fmt: skip
    return out


@pytest.mark.parametrize("view", VIEWS, ids=lambda p: p.name)
def test_views_are_what_the_generator_writes(regenerated: Path, view: Path) -> None:
    assert (regenerated / view).read_bytes() == (ROOT / view).read_bytes(), (
        f"{view} is stale: run `.venv/bin/python -m orb_flow.gen.latency`"
    )
    assert gen.render(ROOT)[view] == (ROOT / view).read_text()


def _broken(raw: dict, what: str) -> dict:
    raw = copy.deepcopy(raw)
    blocks = {r["name"]: r for r in raw["blocks"]}
    if what == "negative clocks":
        blocks["window"]["clocks"] = -1
    elif what == "clocks and sum":
        blocks["cand_lead"]["clocks"] = 14
    elif what == "sum of a later block":
        blocks["window"]["sum"] = ["harris", "fast_nms"]
        del blocks["window"]["clocks"]
    elif what == "sum of an unknown block":
        blocks["cand_lead"]["sum"] = ["orient_moments", "orient_angle"]
    elif what == "repeated name":
        raw["blocks"].append(copy.deepcopy(blocks["smooth"]))
    elif what == "bad entity":
        blocks["smooth"]["entity"] = "smooth"
    elif what == "two-line meaning":
        blocks["smooth"]["meaning"] = "in_valid\nto out_valid"
    elif what == "page outside docs":
        blocks["smooth"]["page"] = "../README.md"
    elif what == "per level without a generic":
        del blocks["core_split"]["generic"]
    elif what == "bad test path":
        blocks["smooth"]["test"] = "test_orb_smooth.py"
    return raw


@pytest.mark.parametrize(
    "what",
    ["negative clocks", "clocks and sum", "sum of a later block", "sum of an unknown block", "repeated name",
     "bad entity", "two-line meaning", "page outside docs", "per level without a generic", "bad test path"],
)  # fmt: skip
def test_generator_refuses_inconsistent_data(tmp_path: Path, what: str) -> None:
    path = tmp_path / "latency.json"
    path.write_text(json.dumps(_broken(json.loads(DATA.read_text()), what)))
    with pytest.raises(gen.LatencyError):
        gen.load(path)


def test_python_view_matches_the_data() -> None:
    assert [lat.name for lat in latency.LATENCIES] == list(RAW)
    for lat in latency.LATENCIES:
        r = RAW[lat.name]
        assert (lat.entity, lat.meaning, lat.page, lat.test) == (r["entity"], r["meaning"], r["page"], r["test"])
        if "per_level" in r:
            assert lat.clocks is None and (lat.per_level, lat.plus, lat.generic) == (
                r["per_level"], r["plus"], r["generic"])  # fmt: skip
            assert [lat.at(n) for n in (1, 4, 8)] == [r["per_level"] * n + r["plus"] for n in (1, 4, 8)]
        else:
            assert lat.clocks == fixed_clocks(lat.name), lat.name
            assert getattr(latency, f"{lat.name.upper()}_LAT") == lat.clocks
            assert lat.parts == tuple(r.get("sum", ()))


def test_vhdl_constants_equal_the_data() -> None:
    text = (ROOT / gen.VHDL).read_text()
    consts = dict(re.findall(r"constant\s+(\w+)_c\s*:\s*natural\s*:=\s*([^;]+);", text))
    values: dict[str, int] = {}
    for name, expr in consts.items():
        terms = [t.strip() for t in expr.split("+")]
        values[name] = sum(int(t) if t.isdigit() else values[t.removesuffix("_c")] for t in terms)
    for name, r in RAW.items():
        k = f"{name.upper()}_LAT"
        if "per_level" in r:
            assert (values[f"{k}_PER_LEVEL"], values[f"{k}_PLUS"]) == (r["per_level"], r["plus"]), name
            assert f"function {name}_lat (n : natural) return natural;" in text, name
        else:
            assert values[k] == fixed_clocks(name), name
            if "sum" in r:  # written as the sum of its parts, not as a number
                assert consts[k] == " + ".join(f"{p.upper()}_LAT_c" for p in r["sum"]), name


def test_pages_tests_and_entities_exist() -> None:
    units = {p.stem for p in HDL.rglob("*.vhd")}
    for name, r in RAW.items():
        assert (ROOT / "docs" / r["page"]).is_file(), f"{name}: docs/{r['page']}"
        assert r["entity"] in units, f"{name}: {r['entity']}"
        if r["test"] is not None:
            assert (ROOT / r["test"]).is_file(), f"{name}: {r['test']}"


def test_docs_list_every_latency() -> None:
    text = (ROOT / gen.MARKDOWN).read_text()
    for name, r in RAW.items():
        assert f"| `{name}` | `{r['entity']}` |" in text, name


# ------------------------------------------------------------------------------------------------
# the HDL uses the package


def test_ghdl_analyses_the_package(tmp_path: Path) -> None:
    env = {**os.environ, **ghdl_path_env()}
    proc = subprocess.run(["ghdl", "-a", "--std=08", str(ROOT / gen.VHDL)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, check=False)  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_no_hdl_file_restates_a_latency() -> None:
    """Latency constants and the top's memory latency come from orb_latency_pkg, never a literal."""
    stale = []
    literal = re.compile(r"^\s*constant\s+(\w*(?:_LAT|LATENCY|_LEAD)_c)\s*:\s*\w+\s*:=\s*\d+\s*;", re.M | re.I)
    mem = re.compile(r"MEM_LATENCY_g\s*=>\s*\d", re.I)
    for path in sorted(HDL.rglob("*.vhd")):
        if path.name == "orb_latency_pkg.vhd":
            continue
        text = path.read_text()
        stale += [f"{path.relative_to(HDL)}: {m[0].strip()}" for m in literal.finditer(text)]
        stale += [f"{path.relative_to(HDL)}: {m[0]}" for m in mem.finditer(text)]
    assert not stale, "take these from orb_latency_pkg: " + "; ".join(stale)
