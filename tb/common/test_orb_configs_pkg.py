# SPDX-License-Identifier: MIT
"""The named configurations' generated views against their one definition, golden_model/data/configs.json.

No simulator here (the top built with no generics reads the default back in
tb/top/test_orb_accel_top.py, test_accel_defaults): orb_flow.gen.configs regenerated into a
temporary directory must give the committed hdl/common/orb_configs_pkg.vhd, golden_model/configs.py
and docs/configurations.md byte for byte; the generator must refuse inconsistent data; the VHDL
constants, parsed from the text, and golden_model.config's NamedConfig objects must equal the JSON
(read here, not from the generated module); orb_accel_top's generic defaults must be
TOPS_DEFAULT_c's fields and orb_accel_zynq's literal defaults the same values; the recommended
constants of golden_model.config must be the recommended configuration's; every test file a
configuration says verifies it must exist and name it.
"""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path
from typing import Any

import pytest

from golden_model import config as cfgmod
from golden_model.config import Config, ConfigError, named
from orb_flow.gen import configs as gen

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "golden_model" / "data" / "configs.json"
VIEWS = (gen.VHDL, gen.PYTHON, gen.MARKDOWN)
RAW: dict[str, Any] = json.loads(DATA.read_text())
HARDWARE = RAW["hardware"]
VHDL_FIELDS = gen.VHDL_FIELDS  # the record's numeric generics (mem_kind is the string generic MEM_KIND_g)


@pytest.mark.parametrize("view", VIEWS, ids=lambda p: p.name)
def test_views_are_what_the_generator_writes(tmp_path: Path, view: Path) -> None:
    gen.main(["--out", str(tmp_path)])
    assert (tmp_path / view).read_bytes() == (ROOT / view).read_bytes(), (
        f"{view} is stale: run `.venv/bin/python -m orb_flow.gen.configs` (or make views)"
    )


def _broken(what: str) -> dict[str, Any]:
    raw = copy.deepcopy(RAW)
    c = raw["configs"]
    if what == "unknown field":
        c["board-vga"]["colour"] = "red"
    elif what == "missing field":
        del c["board-vga"]["sectors"]
    elif what == "budget over the bank":
        c["board-vga"]["budget"] = 1024
    elif what == "too many levels for the frame":
        c["test-tiny"]["scales"] = 8
    elif what == "illegal sectors":
        c["board-vga"]["sectors"] = 48
    elif what == "memory depth not a power of two":
        c["board-vga"]["mem_depth"] = 1000
    elif what == "overlay block too small for the levels":
        c["recommended-vga"]["block_log2"] = 2
    elif what == "bad name":
        c["Board_VGA"] = c.pop("board-vga")
    elif what == "unknown tops default":
        raw["tops_default"] = "thesis-qvga"
    elif what == "no recommended configuration":
        del c["recommended-vga"]
    elif what == "low threshold not the register's reset":
        c["recommended-vga"]["threshold_lo"] = 12
    elif what == "unknown memory kind":
        c["board-vga"]["mem_kind"] = "sram"
    elif what == "nothing verifies it":
        c["sim-qvga"]["verified_by"] = []
    return raw


@pytest.mark.parametrize(
    "what",
    [
        "unknown field",
        "missing field",
        "budget over the bank",
        "too many levels for the frame",
        "illegal sectors",
        "memory depth not a power of two",
        "overlay block too small for the levels",
        "bad name",
        "unknown tops default",
        "no recommended configuration",
        "low threshold not the register's reset",
        "unknown memory kind",
        "nothing verifies it",
    ],
)
def test_generator_refuses_inconsistent_data(tmp_path: Path, what: str) -> None:
    path = tmp_path / "configs.json"
    path.write_text(json.dumps(_broken(what)))
    (tmp_path / "regmap.json").write_bytes((DATA.parent / "regmap.json").read_bytes())  # read beside the data
    gen.load(DATA)  # the committed data is fine
    with pytest.raises(gen.ConfigsError):
        gen.load(path)


def test_python_view_matches_the_data() -> None:
    assert list(cfgmod.NAMES) == list(RAW["configs"])
    for name, entry in RAW["configs"].items():
        nc = named(name)
        for field, value in entry.items():
            got = getattr(nc, field)
            assert (list(got) if isinstance(got, tuple) else got) == value, f"{name}.{field}"
        want_budget = entry.get("budget", min(nc.capacity, cfgmod.recommended_budget(nc.width, nc.height)))
        assert nc.budget == want_budget, name
        c = Config.named(name)
        assert (c.width, c.height, c.scales, c.step, c.sectors, c.budget) == (
            nc.width, nc.height, nc.scales, (nc.step_num, nc.step_den), nc.sectors, nc.budget
        )  # fmt: skip
        assert Config.named(name, threshold=33).threshold == 33
    with pytest.raises(ConfigError, match="known: thesis-vga"):
        named("no-such-config")
    with pytest.raises(ConfigError, match="not Config fields"):
        Config.named("board-vga", mem_depth=16)


def test_recommended_constants_are_the_recommended_configuration() -> None:
    rec = RAW["configs"]["recommended-vga"]
    assert cfgmod.RECOMMENDED_SCALES == rec["scales"]
    assert cfgmod.RECOMMENDED_STEP == (rec["step_num"], rec["step_den"])
    assert cfgmod.RECOMMENDED_SECTORS == rec["sectors"]
    assert cfgmod.RECOMMENDED_THRESHOLD_LO == rec["threshold_lo"]
    assert (cfgmod.RECOMMENDED_COLS, cfgmod.RECOMMENDED_ROWS) == (rec["cols"], rec["rows"])
    assert named("recommended-vga").budget == cfgmod.RECOMMENDED_BUDGET


def _vhdl_constants() -> dict[str, dict[str, int]]:
    text = (ROOT / gen.VHDL).read_text()
    out: dict[str, dict[str, int]] = {}
    for const, body in re.findall(r"constant\s+(\w+)_c\s*:\s*orb_config_t\s*:=\s*\((.*?)\);", text, re.S):
        out[const] = {k: int(v) for k, v in re.findall(r"(\w+)\s*=>\s*(\d+)", body)}
    alias = re.search(r"constant\s+TOPS_DEFAULT_c\s*:\s*orb_config_t\s*:=\s*(\w+)_c;", text)
    assert alias, "TOPS_DEFAULT_c is missing"
    out["TOPS_DEFAULT"] = out[alias.group(1)]
    return out


def test_vhdl_constants_equal_the_data() -> None:
    consts = _vhdl_constants()
    for name, entry in RAW["configs"].items():
        assert consts[name.upper().replace("-", "_")] == {f: entry[f] for f in VHDL_FIELDS}, name
    assert consts["TOPS_DEFAULT"] == {f: RAW["configs"][RAW["tops_default"]][f] for f in VHDL_FIELDS}


def _generic_defaults(path: Path) -> dict[str, str]:
    text = path.read_text()
    block = re.search(r"entity\s+\w+\s+is\s+generic\s*\((.*?)\);\s*(?:--[^\n]*\n\s*)*port", text, re.S | re.I)
    assert block, path
    return dict(re.findall(r"^\s*(\w+)_g\s*:\s*\w+\s*:=\s*([^;\s]+)", block.group(1), re.M))


def test_tops_generic_defaults_are_the_tops_default() -> None:
    want = {f.upper(): RAW["configs"][RAW["tops_default"]][f] for f in VHDL_FIELDS}
    top = _generic_defaults(ROOT / "hdl" / "top" / "orb_accel_top.vhd")
    for generic in want:
        assert top[generic] == f"TOPS_DEFAULT_c.{generic.lower()}", f"orb_accel_top {generic}_g := {top[generic]}"
    kind = '"' + RAW["configs"][RAW["tops_default"]]["mem_kind"].upper() + '"'  # a string generic in both
    assert top["MEM_KIND"] == kind, f"orb_accel_top MEM_KIND_g := {top['MEM_KIND']}, TOPS_DEFAULT has {kind}"
    zynq = _generic_defaults(ROOT / "hdl" / "top" / "orb_accel_zynq.vhd")
    for generic, value in want.items():
        assert zynq[generic] == str(value), f"orb_accel_zynq {generic}_g := {zynq[generic]}, TOPS_DEFAULT has {value}"
    assert zynq["MEM_KIND"] == kind, f"orb_accel_zynq MEM_KIND_g := {zynq['MEM_KIND']}, TOPS_DEFAULT has {kind}"


def test_verifying_tests_name_the_configuration() -> None:
    """A configuration's verified_by entries that are test files exist and use it by name; the make
    targets it names exist in the Makefile."""
    makefile = (ROOT / "Makefile").read_text()
    for name, entry in RAW["configs"].items():
        for claim in entry["verified_by"]:
            if claim.startswith("tb/"):
                path = ROOT / claim.split()[0]
                assert path.is_file(), f"{name}: {claim} does not exist"
                assert f'"{name}"' in path.read_text(), f"{name}: {claim} does not use Config.named({name!r})"
            elif claim.startswith("make "):
                target = claim.split()[1]
                assert re.search(rf"^{re.escape(target)}:", makefile, re.M), f"{name}: no make target {target}"
