# SPDX-License-Identifier: MIT
"""`orb-accel density-bench` (orb_tools.density_bench): contrast, the per-frame measures on a flat
frame, on texture confined to one band and on a photograph, the summary and the command; and the
scale bench's grid-selection extractor (`/gBUDGET[cCELL]`), which must be the model's selection."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from golden_model.config import RECOMMENDED_THRESHOLD_LO, Config
from golden_model.pipeline import candidates
from golden_model.select import best_per_level, select_grid
from orb_tools import density_bench as dbench
from orb_tools import scale_bench as sb
from orb_tools.cli import SCALE_BENCH_DEFAULT
from orb_tools.track_bench import Settings
from orbtb.images import photo


def _by(rows: list[dict]) -> dict[str, dict]:
    return {r["extractor"]: r for r in rows}


def test_contrast() -> None:
    luma = np.array([[0, 1, 126, 128, 130, 255]], dtype=np.uint8)
    assert dbench.apply_contrast(luma, 0.25).tolist() == [[96, 96, 128, 128, 128, 160]]
    assert dbench.apply_contrast(luma, 1.0).tolist() == luma.tolist()
    assert dbench.apply_contrast(luma, 3.0).tolist() == [[0, 0, 122, 128, 134, 255]]
    assert np.all(dbench.apply_contrast(luma, 0.0) == 128)


def test_contrast_zero_has_no_features_and_no_corner_cells() -> None:
    flat = dbench.apply_contrast(photo("camera", 320, 240), 0.0)
    rows = dbench.frame_rows("camera", flat, 0.0, Settings())
    assert [r["extractor"] for r in rows] == list(dbench.EXTRACTORS)
    for r in rows:
        assert r["features"] == 0 and r["candidates"] == 0 and r["corner_cells"] == 0, r
        assert r["corner_cells_empty"] == 0 and not r["empty_with_candidates"] and r["coverage"] == 0.0
    assert _by(rows)["ours"]["unfilled_levels"] == 5 and _by(rows)["ours"]["per_level"] == "0/0/0/0/0"


def test_texture_in_one_band() -> None:
    """Noise only in x 40..199, y 20..69 of a grey 640x480 frame: every feature and candidate lies in the
    8x6 cells (0..2, 0), so coverage 3/48, one row of six, three corner cells, none left empty by ours."""
    img = np.full((480, 640), 128, np.uint8)
    img[20:70, 40:200] = np.random.default_rng(1).integers(0, 256, (50, 160), dtype=np.uint8)
    ours = _by(dbench.frame_rows("band", img, 1.0, Settings()))["ours"]
    assert ours["features"] > 50 and ours["budget"] == 1000
    assert ours["coverage"] == round(3 / 48, 4) and ours["row_share"] == round(1 / 6, 4)
    assert ours["corner_cells"] == 3 and ours["corner_cells_empty"] == 0
    assert sum(int(n) for n in ours["per_level"].split("/")) == ours["features"]


def test_photograph_measures() -> None:
    img = photo("astronaut", 320, 240)
    rows = dbench.frame_rows("astronaut", img, 1.0, Settings())
    by = _by(rows)
    cfg = Settings().config(320, 240)
    cands = candidates(img, cfg)
    assert by["ours"]["candidates"] == len(cands) > by["ours"]["features"] > 0
    assert by["ours"]["features"] == len(select_grid(cands, cfg)) <= cfg.budget
    assert by["cv-500"]["budget"] == 500 and by["cv-ours"]["budget"] == by["ours"]["features"]
    assert by["cv-ours"]["features"] <= by["ours"]["features"]
    assert len(by["cv-500"]["per_level"].split("/")) == 8
    for r in rows:
        assert 0 < r["coverage"] <= 1 and 0 < r["row_share"] <= 1
        assert 0 <= r["corner_cells_empty"] <= r["corner_cells"] <= 48 and not r["empty_with_candidates"]


def test_summary_and_command(tmp_path: Path) -> None:
    path = tmp_path / "coffee.png"
    cv2.imwrite(str(path), cv2.cvtColor(photo("coffee", 240, 180), cv2.COLOR_GRAY2BGR))
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "orb_tools.cli", "density-bench", str(path), "--sizes", "320x240", "160x120",
           "--contrast", "1", "0", "--out-dir", str(out)]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "| ours | 320x240 | 1 |" in r.stdout and "| cv-ours | 160x120 | 0 |" in r.stdout
    with open(out / "density_bench.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2 * 2 * 3
    doc = json.loads((out / "density_bench_summary.json").read_text())
    flat = [s for s in doc["summary"] if s["contrast"] == 0]
    assert len(flat) == 6 and all(s["features"] == 0 and s["corner_cells"] == 0 for s in flat)
    assert doc["candidates"]["coffee"]["320x240 c0"] == 0 < doc["candidates"]["coffee"]["320x240 c1"]
    r = subprocess.run([*cmd[:5], "--sizes", "96x72"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "37x37" in r.stderr and r.stderr.count("\n") == 1, r.stderr


# ---------------------------------------------------------------- the scale bench's grid selection


def test_scale_bench_grid_extractor_parses() -> None:
    g = sb.parse_extractor("5:4x5s64/g1000")
    assert (g.kind, g.step, g.levels, g.sectors, g.budget, g.grid, g.cells) == ("ours", (5, 4), 5, 64, 1000, True,
                                                                                 (8, 6))  # fmt: skip
    assert sb.parse_extractor("5:4x5s64/g1000c4x3").cells == (4, 3)
    host = sb.parse_extractor("5:4x5s64/1000")
    assert (host.grid, host.budget) == (False, 1000)
    for bad in (
        "5:4x5/1000c8x6",
        "5:4x5/g",
        "5:4x5/gc8x6",
        "5:4x5/g5000",
        "5:4x5/g100c16x6",
        "5:4x5/g100c8",
        "5:4x9/g100",
        "cv-5:4x5/g9",
    ):
        with pytest.raises(ValueError, match="extractor"):
            sb.parse_extractor(bad)
    assert "5:4x5s64/g1000" in SCALE_BENCH_DEFAULT and "cv-default@5:4x5s64/g1000" in SCALE_BENCH_DEFAULT
    assert "5:4x5s64/1000" in SCALE_BENCH_DEFAULT, "the host-budget row stays"


def test_scale_bench_grid_is_the_models_selection() -> None:
    img = photo("camera", 320, 240)
    got = sb.extract_ours(img, sb.parse_extractor("5:4x3s32/g200"))
    cfg = Config(320, 240, scales=3, sectors=32, threshold=20, step_num=5, step_den=4,
                 threshold_lo=RECOMMENDED_THRESHOLD_LO, selection="grid", budget=200)  # fmt: skip
    cands = candidates(img, cfg)
    want = select_grid(cands, cfg)
    wx, wy = want.full_res()
    assert len(got) == len(want) <= 200 < len(cands)
    assert np.array_equal(got.x, wx) and np.array_equal(got.y, wy)
    assert np.array_equal(got.desc, want.descriptor)
    host = best_per_level(cands.take(np.flatnonzero(~cands.low)), 200, 3)
    assert not np.array_equal(np.sort(host.full_res()[0]), np.sort(wx)), "not the host's budget"
    c = sb.extract_ours(img, sb.parse_extractor("5:4x3s32/g200c2x2"))
    assert len(c) <= 200 and not np.array_equal(c.x, got.x), "the cells option is used"


def test_scale_bench_runs_cv_default_at_the_grid_count() -> None:
    img = photo("coffee", 320, 240)
    exts = [sb.parse_extractor(t) for t in ("5:4x5s64/g300", "cv-default@5:4x5s64/g300")]
    _, summary = sb.run([("coffee", img)], exts, rotations=(0.0,), scales=(1.0,), perspectives=(0.0,))
    by = {r["extractor"]: r for r in summary}
    assert 0 < by["cv-default@5:4x5s64/g300"]["features_per_image"] <= by["5:4x5s64/g300"]["features_per_image"]
    assert by["5:4x5s64/g300"]["features_per_image"] <= 300 and by["5:4x5s64/g300"]["pooled_pct"] > 95
