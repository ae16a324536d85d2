# SPDX-License-Identifier: MIT
"""`orb-accel viewpoint-bench` (orb_tools.viewpoint_bench): the tilt homography against the pinhole
geometry, the counts of one pair (matches, RANSAC inliers, the fit's corners), a pooled run on a
small photograph and the command's files and errors."""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from orb_tools import scale_bench as sb
from orb_tools import viewpoint_bench as vb
from orbtb.images import photo

SHAPE = (480, 640)
CENTRE = (319.5, 239.5)


def _map(h: np.ndarray, x: float, y: float) -> tuple[float, float]:
    p = h @ np.array([x, y, 1.0])
    return float(p[0] / p[2]), float(p[1] / p[2])


def test_no_tilt_is_the_scale_benchs_rotation_and_scale() -> None:
    assert np.allclose(vb.tilt_homography(SHAPE, 0, "x"), np.eye(3))
    for rot, sc in ((90, 0.5), (30, 0.75), (-45, 1.2)):
        assert np.allclose(vb.tilt_homography(SHAPE, 0, "y", rot, sc), sb.homography(SHAPE, rot, sc, 0))


@pytest.mark.parametrize("tilt", [20.0, 40.0, 60.0])
def test_tilt_is_the_pinhole_view_of_the_tilted_plane(tilt: float) -> None:
    f = vb.FOCAL * SHAPE[1]
    t = math.radians(tilt)
    for axis in ("x", "y"):
        h = vb.tilt_homography(SHAPE, tilt, axis)
        assert np.allclose(_map(h, *CENTRE), CENTRE), "the centre stays"
        for d in (-150.0, 100.0):
            # across the axis: the plane point at d from the centre is d cos t aside, at depth f - d sin t
            # (about y: the right side comes nearer) or f + d sin t (about x: the top comes nearer)
            sign = -1.0 if axis == "y" else 1.0
            want = d * math.cos(t) * f / (f + sign * d * math.sin(t))
            if axis == "y":
                got = _map(h, CENTRE[0] + d, CENTRE[1])
                assert np.allclose(got, (CENTRE[0] + want, CENTRE[1])), (axis, d, got)
                on_axis = _map(h, CENTRE[0], CENTRE[1] + d)
            else:
                got = _map(h, CENTRE[0], CENTRE[1] + d)
                assert np.allclose(got, (CENTRE[0], CENTRE[1] + want)), (axis, d, got)
                on_axis = _map(h, CENTRE[0] + d, CENTRE[1])
            if sign * d > 0:
                assert abs(want) < abs(d), "the far side shrinks"
            assert np.allclose(on_axis, (CENTRE[0] + d, CENTRE[1]) if axis == "x" else (CENTRE[0], CENTRE[1] + d))


def test_bad_views_are_refused() -> None:
    with pytest.raises(ValueError, match="axis"):
        vb.tilt_homography(SHAPE, 30, "z")
    for tilt, sc in ((90.0, 1.0), (-1.0, 1.0), (30.0, 0.0)):
        with pytest.raises(ValueError, match="tilt"):
            vb.tilt_homography(SHAPE, tilt, "x", 0.0, sc)
    assert len(vb.views((0.0, 30.0), ("x", "y"), (0.0,), (1.0, 0.5))) == 2 + 2 * 2


def test_pair_counts_identity_and_a_wrong_map() -> None:
    img = photo("camera", 320, 240)
    ours = sb.extract_ours(img, sb.parse_extractor("5:4x4"))
    ref, warped, inside, matches, correct, inliers, h_ok = vb.pair_counts(ours, ours, np.eye(3), img.shape).tolist()
    assert ref == warped == inside == matches == correct == inliers == len(ours) > 100 and h_ok == 1
    shifted = np.array([[1.0, 0, 10], [0, 1, 0], [0, 0, 1]])  # the truth says 10 px right: the fit is wrong
    c = vb.pair_counts(ours, ours, shifted, img.shape)
    assert c[4] == 0 and c[6] == 0 and c[5] == c[3], "the matches agree with each other, not with the truth"


def test_run_pools_by_tilt() -> None:
    img = photo("coffee", 320, 240)
    exts = [sb.parse_extractor(t) for t in ("5:4x4s32/g400", "cv-default@5:4x4s32/g400")]
    rows, summary = vb.run([("coffee", img)], exts, tilts=(0.0, 40.0), axes=("y",), rotations=(0.0,), scales=(1.0,))
    assert len(rows) == 2 * 2 and {r["extractor"] for r in rows} == {e.name for e in exts}
    assert [(r["extractor"], r["tilt"]) for r in summary] == [
        (n, t) for n in (e.name for e in exts) for t in ("0", "40", "pooled")
    ]
    ident = next(r for r in rows if r["tilt"] == 0.0 and r["extractor"] == "5:4x4s32/g400")
    assert ident["score_pct"] > 95 and ident["h_ok"] == 1, "an unwarped image matches itself"
    tilted = next(r for r in summary if r["tilt"] == "40" and r["extractor"] == "5:4x4s32/g400")
    assert 0 < tilted["score_pct"] < ident["score_pct"] and tilted["pairs"] == 1
    assert rows[0]["reference"] <= 400 and rows[1]["reference"] <= rows[0]["reference"], "the budgets"
    with pytest.raises(ValueError, match="budget"):
        vb.run([("coffee", img)], [sb.parse_extractor("cv-default@9:8x2"), exts[0]])


def test_command(tmp_path: Path) -> None:
    path = tmp_path / "camera.png"
    cv2.imwrite(str(path), photo("camera", 240, 180))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "orb_tools.cli", "viewpoint-bench", str(path), "--extractors",
                        "5:4x3s32/g300", "cv-default", "--tilts", "0", "50", "--axes", "x", "--rotations", "0",
                        "--scales", "1", "--out-dir", str(out)], capture_output=True, text=True,
                       timeout=600)  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "| 5:4x3s32/g300 | pooled |" in r.stdout
    with open(out / "viewpoint_bench_summary.csv") as fh:
        assert [(row["extractor"], row["tilt"]) for row in csv.DictReader(fh)] == [
            ("5:4x3s32/g300", "0"), ("5:4x3s32/g300", "50"), ("5:4x3s32/g300", "pooled"),
            ("cv-default", "0"), ("cv-default", "50"), ("cv-default", "pooled"),
        ]  # fmt: skip
    assert (out / "viewpoint_bench.png").stat().st_size > 1000
    for bad in (["--tilts", "90"], ["--axes", "z"], ["--extractors", "9x9"]):
        b = subprocess.run([sys.executable, "-m", "orb_tools.cli", "viewpoint-bench", str(path), *bad],
                           capture_output=True, text=True, timeout=120)  # fmt: skip
        assert b.returncode == 2 and len(b.stderr.strip().splitlines()) == 1, (bad, b.stderr)
