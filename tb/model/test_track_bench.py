# SPDX-License-Identifier: MIT
"""`orb-accel track-bench` (orb_tools.track_bench): the camera clip, the pair measures (a textured
clip tracks, independent noise frames do not), the 8x6 coverage, the summary, the level check and the
command's files and refusals."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from golden_model.config import ConfigError
from orb_tools import track_bench as tb
from orbtb.images import photo

SIZE = (320, 240)


@pytest.fixture(scope="module")
def textured_clip() -> list[np.ndarray]:
    return tb.camera_clip(photo("astronaut", 480, 360), 3, *SIZE, tb.clip_seed(1, "astronaut"))


def test_camera_clip_is_seeded_noisy_and_moves(textured_clip: list[np.ndarray]) -> None:
    again = tb.camera_clip(photo("astronaut", 480, 360), 3, *SIZE, tb.clip_seed(1, "astronaut"))
    assert all(np.array_equal(a, b) for a, b in zip(textured_clip, again, strict=True)), "same seed, same clip"
    other = tb.camera_clip(photo("astronaut", 480, 360), 3, *SIZE, tb.clip_seed(2, "astronaut"))
    assert not np.array_equal(textured_clip[0], other[0])
    assert textured_clip[0].shape == (SIZE[1], SIZE[0]) and textured_clip[0].dtype == np.uint8
    assert np.abs(textured_clip[1].astype(int) - textured_clip[0]).mean() > 5, "the camera moves"
    flat = tb.camera_clip(np.full((480, 640), 100, np.uint8), 2, *SIZE, np.random.default_rng(0))
    assert abs(float(flat[0].std()) - tb.NOISE_SIGMA) < 0.1 and abs(float(flat[0].mean()) - 100) < 0.1


def test_textured_clip_tracks_for_both(textured_clip: list[np.ndarray]) -> None:
    cfg = tb.Settings().config(*SIZE)
    rows = tb.clip_rows("astronaut", "photo", textured_clip, (1,), cfg, seed=1)
    assert [(r["frame"], r["extractor"]) for r in rows] == [(0, "ours"), (0, "opencv"), (1, "ours"), (1, "opencv")]
    for r in rows:
        assert r["features"] > 100 and r["inliers"] >= tb.FAIL_INLIERS and not r["failed"], r
        assert 0 < r["coverage"] <= 1 and r["inliers_per_feature"] == r["inliers"] / r["features"]
    ours = [r for r in rows if r["extractor"] == "ours"]
    assert all(r["features"] <= cfg.budget for r in ours)
    cv = [r for r in rows if r["extractor"] == "opencv"]
    assert all(c["features"] <= o["features"] for o, c in zip(ours, cv, strict=True)), "OpenCV gets our count"


def test_independent_noise_frames_do_not_track() -> None:
    rng = np.random.default_rng(5)
    noise = [rng.integers(0, 256, (SIZE[1], SIZE[0]), dtype=np.uint8) for _ in range(2)]
    rows = tb.clip_rows("noise", "photo", noise, (1,), tb.Settings().config(*SIZE), seed=1)
    for r in rows:
        assert r["features"] > 100 and r["matches"] > 8, r
        assert r["failed"] and r["inliers"] < tb.FAIL_INLIERS and r["inliers_per_feature"] < 0.05, r


def test_pair_stats_repeat_with_the_seed(textured_clip: list[np.ndarray]) -> None:
    cfg = tb.Settings().config(*SIZE)
    a, b = tb.extract_ours(textured_clip[0], cfg), tb.extract_ours(textured_clip[2], cfg)
    assert tb.pair_stats(a, b, *SIZE, seed=3) == tb.pair_stats(a, b, *SIZE, seed=3)
    empty = tb.extract_opencv(textured_clip[0], 0)
    assert len(empty) == 0 and tb.pair_stats(empty, b, *SIZE, seed=3)["failed"]


def test_coverage_of_one_corner_and_of_everything() -> None:
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0, 79.9, 200), rng.uniform(0, 79.9, 200)
    assert tb.coverage(x, y, 640, 480) == 1 / 48
    assert tb.coverage(560 + x, 400 + y, 640, 480) == 1 / 48
    gx, gy = np.meshgrid(np.arange(8) * 80 + 40, np.arange(6) * 80 + 40)
    assert tb.coverage(gx.ravel(), gy.ravel(), 640, 480) == 1.0
    assert tb.coverage(np.zeros(0), np.zeros(0), 640, 480) == 0.0
    occ = tb.occupancy(np.array([639.9, 0.0]), np.array([0.0, 479.9]), 640, 480)
    assert occ[0, 7] and occ[5, 0] and occ.sum() == 2


def test_summary_counts_failures_alone() -> None:
    def row(e: str, frame: int, inliers: int) -> dict:
        return {"clip": "c", "gap": 1, "frame": frame, "extractor": e, "features": 100, "inliers": inliers,
                "inliers_per_feature": inliers / 100, "coverage": 0.5, "failed": inliers < 30}  # fmt: skip

    rows = [row("ours", 0, 10), row("opencv", 0, 50), row("ours", 1, 10), row("opencv", 1, 10),
            row("ours", 2, 40), row("opencv", 2, 20)]  # fmt: skip
    by = {r["extractor"]: r for r in tb.summarise(rows)}
    assert by["ours"]["failed_share"] == round(2 / 3, 4) and by["ours"]["failed_alone"] == 1
    assert by["opencv"]["failed_alone"] == 1 and by["opencv"]["inliers"] == round(80 / 3, 4)


def test_too_many_levels_are_refused() -> None:
    with pytest.raises(ConfigError, match="37x37"):
        tb.Settings(scales=8).config(160, 120)
    assert tb.Settings(scales=5).config(160, 120).scales == 5


def test_command(tmp_path: Path) -> None:
    path = tmp_path / "camera.png"
    cv2.imwrite(str(path), photo("camera", 400, 300))
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "orb_tools.cli", "track-bench", str(path), "--frames", "3", "--gaps", "1", "2",
           "--size", "320x240", "--out-dir", str(out)]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "| ours | 1 |" in r.stdout and "| opencv | 2 |" in r.stdout
    with open(out / "track_bench.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == (2 + 1) * 2 and {r["clip"] for r in rows} == {"camera"}
    doc = json.loads((out / "track_bench_summary.json").read_text())
    assert doc["settings"]["budget_used"] == 500 and doc["settings"]["cells_used"] == "8x6"
    assert [(s["extractor"], s["gap"]) for s in doc["summary"]] == [("ours", 1), ("opencv", 1), ("ours", 2),
                                                                    ("opencv", 2)]  # fmt: skip
    assert (out / "track_bench.png").stat().st_size > 1000
    for bad, what in ((["--frames", "3", "--gaps", "3"], "gap 3"), (["--size", "64x48"], "37x37"),
                      (["--scales", "9"], "scales")):  # fmt: skip
        r = subprocess.run([*cmd[:5], *bad], capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and what in r.stderr and r.stderr.count("\n") == 1, r.stderr
