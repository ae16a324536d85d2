# SPDX-License-Identifier: MIT
"""`orb-accel scale-bench` (orb_tools.scale_bench): extractor names, the homography, the counts of
one pair, a pooled run on a small photograph and the command's files."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from orb_tools import scale_bench as sb
from orbtb.images import photo


def test_parse_extractor() -> None:
    e = sb.parse_extractor("5:4x6")
    assert (e.kind, e.step, e.levels, e.factor) == ("ours", (5, 4), 6, 1.25)
    assert sb.parse_extractor("cv-2:1x4").kind == "opencv"
    d = sb.parse_extractor("cv-default@5:4x6")
    assert (d.kind, d.budget_of) == ("opencv-default", "5:4x6")
    b = sb.parse_extractor("5:4x4s64/1000")
    assert (b.kind, b.step, b.levels, b.sectors, b.budget) == ("ours", (5, 4), 4, 64, 1000)
    assert (e.sectors, e.budget) == (32, 0)
    for bad in ("5x4", "4:5x3", "2:1x0", "cv-x", "2:1", "5:4x4s24", "cv-5:4x4/100", "5:4x4/", "5:4x4s64/1000x"):
        with pytest.raises(ValueError, match="extractor"):
            sb.parse_extractor(bad)


def test_budgeted_extractor_keeps_each_levels_best() -> None:
    img = photo("camera", 320, 240)
    full = sb.extract_ours(img, sb.parse_extractor("5:4x4"))
    kept = sb.extract_ours(img, sb.parse_extractor("5:4x4/300"))
    assert len(kept) == 300 < len(full)
    # every kept feature is one of the full set (same position and descriptor)
    pos = {(round(x, 6), round(y, 6), d.tobytes()) for x, y, d in zip(full.x, full.y, full.desc, strict=True)}
    assert all(
        (round(x, 6), round(y, 6), d.tobytes()) in pos for x, y, d in zip(kept.x, kept.y, kept.desc, strict=True)
    )


def test_homography() -> None:
    shape = (480, 640)
    assert np.allclose(sb.homography(shape, 0, 1.0, 0), np.eye(3))
    h = sb.homography(shape, 90, 0.5, 0)
    c = np.array([319.5, 239.5, 1.0])
    assert np.allclose(h @ c, c), "the centre stays"
    p = h @ np.array([419.5, 239.5, 1.0])
    assert np.allclose(p[:2] / p[2], [319.5, 189.5]), "100 px right of the centre -> 50 px up"


def test_pair_counts_identity_and_a_wrong_map() -> None:
    img = photo("camera", 320, 240)
    ours = sb.extract_ours(img, sb.parse_extractor("5:4x4"))
    same = sb.pair_counts(ours, ours, np.eye(3), img.shape)
    ref, warped, inside, matches, correct = same.tolist()
    assert ref == warped == len(ours) > 100 and inside == ref and correct == matches == ref
    shifted = np.array([[1.0, 0, 10], [0, 1, 0], [0, 0, 1]])  # the truth says 10 px right: all wrong
    assert sb.pair_counts(ours, ours, shifted, img.shape)[4] == 0


def test_run_pools_and_budgets() -> None:
    img = photo("coffee", 320, 240)
    exts = [sb.parse_extractor(t) for t in ("2:1x3", "5:4x5", "cv-default@5:4x5")]
    rows, summary = sb.run([("coffee", img)], exts, rotations=(0.0, 45.0), scales=(1.0, 0.8), perspectives=(0.0,))
    assert len(rows) == 3 * 2 * 2 and {r["extractor"] for r in rows} == {"2:1x3", "5:4x5", "cv-default@5:4x5"}
    by = {r["extractor"]: r for r in summary}
    assert set(by["5:4x5"]) == {"extractor", "pooled_pct", "scale_1_pct", "scale_0.8_pct", "features_per_image"}
    ident = next(r for r in rows if r["rotation"] == 0.0 and r["scale"] == 1.0 and r["extractor"] == "5:4x5")
    assert ident["score_pct"] > 95, "an unwarped image matches itself"
    assert by["cv-default@5:4x5"]["features_per_image"] <= by["5:4x5"]["features_per_image"], "the budget"
    with pytest.raises(ValueError, match="budget"):
        sb.run([("coffee", img)], [sb.parse_extractor("cv-default@9:8x2"), exts[0]])


def test_command(tmp_path: Path) -> None:
    path = tmp_path / "camera.png"
    cv2.imwrite(str(path), photo("camera", 240, 180))
    r = subprocess.run([sys.executable, "-m", "orb_tools.cli", "scale-bench", str(path), "--extractors", "2:1x3",
                        "cv-default", "--out-dir", str(tmp_path / "out")], capture_output=True, text=True,
                       timeout=600)  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "| 2:1x3 |" in r.stdout
    with open(tmp_path / "out" / "scale_bench_summary.csv") as fh:
        assert [row["extractor"] for row in csv.DictReader(fh)] == ["2:1x3", "cv-default"]
    assert (tmp_path / "out" / "scale_bench.png").stat().st_size > 1000
    bad = subprocess.run([sys.executable, "-m", "orb_tools.cli", "scale-bench", str(path), "--extractors", "9x9"],
                         capture_output=True, text=True)  # fmt: skip
    assert bad.returncode == 2 and "extractor" in bad.stderr
