# SPDX-License-Identifier: MIT
"""`make sim`'s command (`orb-accel sim`, sw/orb_tools/sim_accel.py) end to end on a small colour photograph (in GHDL,
and with `--fast`) and on a bad argument: the report says bit-exact (features and overlay),
nothing lost, one clock per pixel, and the features CSV equals the model's (the grid selection;
every feature with a small bank: the truncation reported and the stored features checked against
the arrival order)."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import cv2

from golden_model import Config, extract, first_difference
from golden_model.config import RECOMMENDED_THRESHOLD_LO, recommended_budget
from golden_model.features import read_csv
from golden_model.luma import rgb_to_luma
from golden_model.select import truncation_difference
from orbtb.images import colour_photo

SIM = [sys.executable, "-m", "orb_tools.cli", "sim"]  # orb-accel sim, make sim's command


def _sim(tmp_path: Path, rgb, *extra: str) -> tuple[Path, dict]:
    image = tmp_path / "coffee.png"
    cv2.imwrite(str(image), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    out = tmp_path / "sim"
    cmd = [*SIM, "--image", str(image), "--size", "native", "--scales", "3",
           "--step", "5:4", "--sectors", "16", "--threshold", "15", "--out-dir", str(out), *extra]  # fmt: skip
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout + done.stderr
    return out, json.loads((out / "report.json").read_text())


def test_sim_accel_small_photo(tmp_path: Path) -> None:
    """The default selection: the grid at the recommended budget, 8 x 6 cells and low threshold."""
    rgb = colour_photo("coffee", 160, 96)
    out, report = _sim(tmp_path, rgb)
    assert report["bit_exact"] and report["overlay_bit_exact"], report
    assert (report["dropped"], report["truncated"], report["cycles_per_pixel"]) == (0, 0, 1.0), report
    assert 0 < report["latency_cycles"] <= 1000, report
    cfg = Config(160, 96, scales=3, sectors=16, threshold=15, step_num=5, step_den=4, selection="grid",
                 budget=recommended_budget(160, 96),
                 threshold_lo=RECOMMENDED_THRESHOLD_LO)  # fmt: skip
    expected = extract(rgb_to_luma(rgb), cfg)
    every = extract(rgb_to_luma(rgb), replace(cfg, selection="all"))
    assert report["features"] == len(expected) and 0 < len(expected) <= cfg.budget < len(every), "a budget that bites"
    assert first_difference(read_csv(out / "features.csv", sectors_total=16), expected) is None
    assert report["step"] == "5:4" and set(expected.scale.tolist()) == {0, 1, 2}
    assert (out / "overlay.png").stat().st_size > 0


def test_sim_accel_every_feature_truncated(tmp_path: Path) -> None:
    """Selection `all` with a bank smaller than the frame's features (`make sim FAST=1`: the netlist in
    Verilator; the report's code is the same for both engines, and the RTL's truncation in GHDL is
    test_orb_accel_top's): the truncation is reported and the stored features are checked against
    the model's arrival order, not reported as a mismatch."""
    rgb = colour_photo("coffee", 160, 96)
    out, report = _sim(tmp_path, rgb, "--selection", "all", "--mem-depth", "64", "--fast")
    assert report["engine"] == "verilator-netlist"
    cfg = Config(160, 96, scales=3, sectors=16, threshold=15, step_num=5, step_den=4)
    every = extract(rgb_to_luma(rgb), cfg)
    assert report["bit_exact"] and report["overlay_bit_exact"], report
    assert (report["features"], report["truncated"], report["dropped"]) == (63, len(every) - 63, 0), report
    got = read_csv(out / "features.csv", sectors_total=16, step=(5, 4))
    assert truncation_difference(got, every, 63, cfg) is None


def test_sim_accel_bad_arguments(tmp_path: Path) -> None:
    missing = subprocess.run([*SIM, "--image", str(tmp_path / "none.png"), "--out-dir",
                              str(tmp_path)], capture_output=True, text=True, timeout=120)  # fmt: skip
    assert missing.returncode == 2 and "no such file" in missing.stderr, missing.stderr
    bad = subprocess.run([*SIM, "--sectors", "12", "--out-dir", str(tmp_path)],
                         capture_output=True, text=True, timeout=120)  # fmt: skip
    assert bad.returncode == 2 and "error" in bad.stderr, bad.stderr
