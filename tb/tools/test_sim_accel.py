# SPDX-License-Identifier: MIT
"""`make sim`'s script (scripts/flow/sim_accel.py) end to end on a small colour photograph and on a bad
argument: the report says bit-exact (features and overlay), nothing dropped, one clock per pixel,
and the features CSV equals the model's."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import cv2

from golden_model import Config, extract, first_difference
from golden_model.features import read_csv
from golden_model.luma import rgb_to_luma
from orbtb.images import colour_photo

ROOT = Path(__file__).resolve().parents[2]


def test_sim_accel_small_photo(tmp_path: Path) -> None:
    rgb = colour_photo("coffee", 160, 96)
    image = tmp_path / "coffee.png"
    cv2.imwrite(str(image), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    out = tmp_path / "sim"
    cmd = [sys.executable, str(ROOT / "scripts" / "flow" / "sim_accel.py"), "--image", str(image), "--scales", "3",
           "--step", "5:4", "--sectors", "16", "--threshold", "15", "--out-dir", str(out)]  # fmt: skip
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout + done.stderr
    report = json.loads((out / "report.json").read_text())
    assert report["bit_exact"] and report["overlay_bit_exact"], report
    assert (report["dropped"], report["cycles_per_pixel"]) == (0, 1.0), report
    assert 0 < report["latency_cycles"] <= 1000, report
    cfg = Config(160, 96, scales=3, sectors=16, threshold=15, step_num=5, step_den=4)
    expected = extract(rgb_to_luma(rgb), cfg)
    assert report["features"] == len(expected) > 0
    assert first_difference(read_csv(out / "features.csv", sectors_total=16), expected) is None
    assert report["step"] == "5:4" and set(expected.scale.tolist()) == {0, 1, 2}
    assert (out / "overlay.png").stat().st_size > 0


def test_sim_accel_bad_arguments(tmp_path: Path) -> None:
    script = str(ROOT / "scripts" / "flow" / "sim_accel.py")
    missing = subprocess.run([sys.executable, script, "--image", str(tmp_path / "none.png"), "--out-dir",
                              str(tmp_path)], capture_output=True, text=True, timeout=120)  # fmt: skip
    assert missing.returncode == 2 and "no such file" in missing.stderr, missing.stderr
    bad = subprocess.run([sys.executable, script, "--sectors", "12", "--out-dir", str(tmp_path)],
                         capture_output=True, text=True, timeout=120)  # fmt: skip
    assert bad.returncode == 2 and "error" in bad.stderr, bad.stderr
