# SPDX-License-Identifier: MIT
"""The register map's generated views against their one definition, golden_model/data/regmap.json.

No simulator: scripts/gen/gen_regmap.py regenerated into a temporary directory must give the committed
hdl/host/orb_regs_pkg.vhd, golden_model/regs.py and docs/registers.md byte for byte (a stale view
fails); the generator must refuse inconsistent data; the VHDL constants, parsed from the text, must
equal golden_model.regs; GHDL must synthesise orb_axil_regs with the package for extreme generics
and refuse an illegal SECTORS_g with a message naming the entity.
"""

from __future__ import annotations

import copy
import importlib.util
import json
import os
import re
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from golden_model import regs
from orbtb.runner import ghdl_path_env

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "gen" / "gen_regmap.py"
DATA = ROOT / "golden_model" / "data" / "regmap.json"
VIEWS = (Path("hdl") / "host" / "orb_regs_pkg.vhd", Path("golden_model") / "regs.py", Path("docs") / "registers.md")


def gen_module() -> ModuleType:
    spec = importlib.util.spec_from_file_location("gen_regmap", SCRIPT)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules["gen_regmap"] = mod  # dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("view", VIEWS, ids=lambda p: p.name)
def test_views_are_what_the_generator_writes(tmp_path: Path, view: Path) -> None:
    subprocess.run([sys.executable, str(SCRIPT), "--out", str(tmp_path)], check=True, capture_output=True)
    assert (tmp_path / view).read_bytes() == (ROOT / view).read_bytes(), (
        f"{view} is stale: run `.venv/bin/python scripts/gen/gen_regmap.py`"
    )


def test_generator_is_deterministic(tmp_path: Path) -> None:
    for d in ("a", "b"):
        subprocess.run([sys.executable, str(SCRIPT), "--out", str(tmp_path / d)], check=True, capture_output=True)
    for view in VIEWS:
        assert (tmp_path / "a" / view).read_bytes() == (tmp_path / "b" / view).read_bytes()


def _broken(raw: dict, what: str) -> dict:
    raw = copy.deepcopy(raw)
    regs_ = {r["name"]: r for r in raw["registers"]}
    if what == "overlap":
        regs_["CTRL"]["fields"][2]["bits"] = [5, 1]
    elif what == "misaligned":
        regs_["THRESHOLD"]["offset"] = 26
    elif what == "duplicate offset":
        regs_["THRESHOLD"]["offset"] = regs_["CTRL"]["offset"]
    elif what == "reset too wide":
        regs_["THRESHOLD"]["fields"][0]["reset"] = 256
    elif what == "beyond MEM_BASE":
        regs_["THRESHOLD"]["offset"] = raw["constants"]["MEM_BASE"]["value"]
    elif what == "bad access":
        regs_["CTRL"]["access"] = "rc"
    elif what == "generic in rw":
        regs_["THRESHOLD"]["fields"][0]["reset"] = "WIDTH_g"
    elif what == "unknown reset name":
        regs_["ID"]["fields"][0]["reset"] = "NO_SUCH"
    elif what == "max of ro":
        regs_["STATUS"]["fields"][1]["max"] = 0
    return raw


@pytest.mark.parametrize(
    "what",
    [
        "overlap",
        "misaligned",
        "duplicate offset",
        "reset too wide",
        "beyond MEM_BASE",
        "bad access",
        "generic in rw",
        "unknown reset name",
        "max of ro",
    ],
)
def test_generator_refuses_inconsistent_data(tmp_path: Path, what: str) -> None:
    gen = gen_module()
    path = tmp_path / "regmap.json"
    path.write_text(json.dumps(_broken(json.loads(DATA.read_text()), what)))
    with pytest.raises(gen.RegMapError):
        gen.load(path)


def test_python_view_matches_the_data() -> None:
    raw = json.loads(DATA.read_text())
    assert [r["name"] for r in raw["registers"]] == [r.name for r in regs.REGISTERS]
    for rj, r in zip(raw["registers"], regs.REGISTERS, strict=True):
        assert (rj["offset"], rj["access"]) == (r.offset, r.access), r.name
        assert [(f["name"], f["bits"][1], f["bits"][0] - f["bits"][1] + 1) for f in rj["fields"]] == [
            (f.name, f.lsb, f.width) for f in r.fields
        ], r.name
    assert regs.ORB_ID == 0x4F524231 and regs.MEM_BASE == 0x10000
    assert regs.ORB_ID.to_bytes(4, "big") == b"ORB1"


def parse_vhdl_constants(text: str) -> dict[str, int]:
    out = {}
    for name, value in re.findall(r"constant\s+(\w+)_c\s*:\s*\w+(?:\(31 downto 0\))?\s*:=\s*([^;]+);", text):
        value = value.strip()
        if m := re.fullmatch(r'x"([0-9A-F]+)"', value):
            out[name] = int(m[1], 16)
        elif m := re.fullmatch(r"16#([0-9A-F]+)#", value):
            out[name] = int(m[1], 16)
        elif value.isdigit():
            out[name] = int(value)
        else:
            out[name] = out[value.removesuffix("_c")]
    return out


def test_vhdl_constants_equal_the_python_view() -> None:
    c = parse_vhdl_constants((ROOT / VIEWS[0]).read_text())
    assert c["ORB_ID"] == regs.ORB_ID and c["MEM_BASE"] == regs.MEM_BASE and c["BANKS"] == regs.BANKS
    assert (c["VERSION_MAJOR"], c["VERSION_MINOR"]) == (regs.VERSION_MAJOR, regs.VERSION_MINOR)
    for r in regs.REGISTERS:
        assert c[f"REG_{r.name}"] == r.offset, r.name
        assert c[f"REG_{r.name}_MASK"] == r.mask, r.name
        if all(f.generic is None and f.port is None for f in r.fields):
            assert c[f"REG_{r.name}_RESET"] == r.reset_value(), r.name
        for f in r.fields:
            p = f"{r.name}_{f.name.upper()}"
            assert (c[f"{p}_LSB"], c[f"{p}_MSB"]) == (f.lsb, f.lsb + f.width - 1), p
            if f.max is not None:
                assert c[f"{p}_MAX"] == f.max, p


def test_docs_list_every_register() -> None:
    text = (ROOT / VIEWS[2]).read_text()
    for r in regs.REGISTERS:
        assert f"| 0x{r.offset:03X} | [{r.name}](#{r.name.lower()}) | {r.access} |" in text, r.name
    assert "mem_rd_en" in text and "MEM_LATENCY_g" in text, "the memory port contract is missing"


def _ghdl(args: list[str], cwd: Path, check: bool = True) -> subprocess.CompletedProcess:
    env = {**os.environ, **ghdl_path_env()}
    proc = subprocess.run(["ghdl", *args], cwd=cwd, env=env, capture_output=True, text=True, check=False)
    if check and proc.returncode != 0:
        raise AssertionError(f"ghdl {' '.join(args)} failed:\n{proc.stdout}{proc.stderr}")
    return proc


@pytest.mark.parametrize(
    "generics",
    [{}, {"MEM_LATENCY_g": 1, "ADDR_BITS_g": 20, "SCALES_g": 4, "SECTORS_g": 16, "MEM_DEPTH_g": 16777215}],
    ids=["defaults", "extremes"],
)
def test_ghdl_synth_of_the_register_bank(tmp_path: Path, generics: dict[str, int]) -> None:
    files = [str(ROOT / "hdl" / "host" / f) for f in ("orb_regs_pkg.vhd", "orb_axil_regs.vhd")]
    _ghdl(["-a", "--std=08", *files], tmp_path)
    gargs = [f"-g{k}={v}" for k, v in generics.items()]
    proc = _ghdl(["synth", "--std=08", *gargs, "--out=none", "orb_axil_regs"], tmp_path)
    assert "error" not in (proc.stdout + proc.stderr).lower(), proc.stdout + proc.stderr


def test_illegal_sectors_generic_is_refused(tmp_path: Path) -> None:
    files = [str(ROOT / "hdl" / "host" / f) for f in ("orb_regs_pkg.vhd", "orb_axil_regs.vhd")]
    _ghdl(["-a", "--std=08", *files], tmp_path)
    proc = _ghdl(["synth", "--std=08", "-gSECTORS_g=5", "--out=none", "orb_axil_regs"], tmp_path, check=False)
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0 and "orb_axil_regs: SECTORS_g" in out, out
