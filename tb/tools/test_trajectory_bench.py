# SPDX-License-Identifier: MIT
"""`orb-accel trajectory-bench`: the renderer against the pinhole geometry (orb_tools.scene), the
ORB-SLAM-style extractor's quotas, quadtree and descriptors (orb_tools.orbslam_extractor), the
tracker's stereo points and its motion on a rendered clip (orb_tools.vo), the metrics on the truth
itself, and the command's files and errors."""

from __future__ import annotations

import csv
import itertools
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from golden_model.config import RECOMMENDED_SCALES, RECOMMENDED_SECTORS, RECOMMENDED_STEP
from orb_tools import orbslam_extractor as ox
from orb_tools import scene, vo
from orb_tools import trajectory_bench as tjb
from orbtb.images import photo


def _photos() -> list[np.ndarray]:
    return [photo(n, 320, 240) for n in ("camera", "coffee", "astronaut")]


def test_a_fronto_parallel_quad_renders_its_texture_and_depth() -> None:
    tex = photo("camera", 320, 240)
    cam = scene.Camera(320, 240, 300.0)
    # a 320 x 240 texture 3.2 x 2.4 m wide at 3 m: 1 cm a texel, and f / z = 100 px a metre: a texel a pixel
    quad = scene.Quad(np.array([-1.6, -1.2, 3.0]), np.array([3.2, 0, 0]), np.array([0, 2.4, 0]), tex)
    img, depth = scene.render([quad], cam, np.eye(4))
    assert np.allclose(depth, 3.0, atol=1e-4)
    assert np.abs(img[4:-4, 4:-4].astype(int) - tex[4:-4, 4:-4]).mean() < 4.0, "the texture, one texel a pixel"
    # moved 1 m sideways: the quad shifts 100 px left and the uncovered part is the background
    shifted, d2 = scene.render([quad], cam, scene.pose(np.eye(3), (1.0, 0.0, 0.0)), background=0)
    assert np.isinf(d2[:, -90:]).all() and (shifted[:, -90:] == 0).all()
    assert np.abs(shifted[8:-8, 8:200].astype(int) - tex[8:-8, 108:300]).mean() < 4.0


def test_poses_quaternions_and_the_tum_file(tmp_path: Path) -> None:
    poses = scene.wall_path(20, fps=10.0, speed=1.0)
    assert math.isclose(poses[-1][0, 3], 1.9), "1 m/s for 19 frames at 10 fps"
    steps = [np.linalg.norm(b[:3, 3] - a[:3, 3]) for a, b in itertools.pairwise(poses)]
    assert max(steps) < 0.2, "a smooth swim"
    for p in poses:
        r = p[:3, :3]
        assert np.allclose(r @ r.T, np.eye(3)) and math.isclose(np.linalg.det(r), 1.0)
        w, x, y, z = scene.quaternion_wxyz(r)
        q = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])  # fmt: skip
        assert np.allclose(q, r, atol=1e-9)
    scene.write_tum(tmp_path / "t.tum", np.arange(20) / 30.0, poses)
    rows = np.loadtxt(tmp_path / "t.tum")
    assert rows.shape == (20, 8) and np.allclose(rows[:, 1:4], [p[:3, 3] for p in poses], atol=1e-6)
    with pytest.raises(ValueError, match="texture"):
        scene.wall_scene([])


def test_orbslam_quotas_quadtree_and_descriptors() -> None:
    q = ox.level_quotas(1000, 8, 1.2)
    assert sum(q) == 1000 and q[0] == round(1000 * (1 - 1 / 1.2) / (1 - 1.2**-8)) and q == sorted(q, reverse=True)
    rng = np.random.default_rng(3)
    pts = np.column_stack([rng.uniform(16, 304, 500), rng.uniform(16, 224, 500), rng.uniform(0, 100, 500)])
    keep = ox.distribute(pts, 50, (16, 304, 16, 224))
    assert 40 <= len(keep) <= 50 and len(set(keep.tolist())) == len(keep)
    # spread: every quarter of the area keeps some
    kx, ky = pts[keep, 0], pts[keep, 1]
    for xs in (kx < 160, kx >= 160):
        for ys in (ky < 120, ky >= 120):
            assert (xs & ys).sum() >= 5
    img = photo("astronaut", 320, 240)
    x, _, d = ox.extract(img, ox.OrbSlamParams(budget=400))
    assert 300 <= len(x) <= 400 and d.shape == (len(x), 32) and d.dtype == np.uint8
    # the angle is the intensity centroid's: a patch brighter to the right points along +x, below along +y
    ramp = np.tile(np.arange(64, dtype=np.uint8) * 3, (64, 1))
    assert np.allclose(ox.ic_angles(ramp, np.array([32.0]), np.array([32.0])), 0.0, atol=1.0)
    assert np.allclose(ox.ic_angles(ramp.T.copy(), np.array([32.0]), np.array([32.0])), 90.0, atol=1.0)


def test_stereo_points_give_the_depth_of_the_disparity() -> None:
    k = np.array([[500.0, 0, 319.5], [0, 500.0, 239.5], [0, 0, 1]])
    rng = np.random.default_rng(1)
    desc = rng.integers(0, 256, (5, 32), dtype=np.uint8)
    lx, ly = np.array([100.0, 200, 300, 400, 500]), np.array([50.0, 100, 150, 200, 250])
    disp = np.array([10.0, 20, 30, 40, 0.5])  # the last below MIN_DISPARITY
    idx, pts = vo.stereo_points((lx, ly, desc), (lx - disp, ly + 1.0, desc), k, 0.12)
    assert idx.tolist() == [0, 1, 2, 3]
    assert np.allclose(pts[:, 2], 500.0 * 0.12 / disp[:4])
    assert np.allclose(pts[:, 0], (lx[:4] - 319.5) * pts[:, 2] / 500.0)


def test_the_tracker_follows_a_rendered_clip_and_counts_lost_frames() -> None:
    seq = tjb.render_wall(_photos(), frames=8, size=(320, 240))
    tr = vo.run(seq.frames, tjb.extractor("orbslam", 500), seq.k, seq.baseline, seq.truth[0])
    assert not tr.lost and min(tr.inliers) >= vo.MIN_INLIERS
    err = [np.linalg.norm(p[:3, 3] - t[:3, 3]) for p, t in zip(tr.poses, seq.truth, strict=True)]
    assert max(err) < 0.06, err  # the frame's motion is 1.7 cm; a wrong motion's error grows by that each frame
    m = tjb.metrics(seq, tr)
    assert m["ate_m"] < 0.05 and m["rpe_deg"] < 1.0
    truth = tjb.metrics(seq, vo.Track(poses=list(seq.truth)))
    assert truth["ate_m"] < 1e-9 and truth["rpe_m"] < 1e-9, "the truth has no error"
    blank = [vo.Frame(np.full((240, 320), 90, np.uint8), right=np.full((240, 320), 90, np.uint8))] * 3
    lost = vo.run(seq.frames[:2] + blank, tjb.extractor("orbslam", 500), seq.k, seq.baseline)
    assert lost.lost == [2, 3, 4], "a frame without features is lost and counted"


def test_extractor_names() -> None:
    for name in ("orbslam", "cv-default", "5:4x5s32/g500"):
        x, _, d = tjb.extractor(name, 500)(photo("coffee", 320, 240))
        assert 0 < len(x) <= 500 and d.shape == (len(x), 32)
    for bad in ("cv-2:1x4", "nonsense"):
        with pytest.raises(ValueError, match="extractor"):
            tjb.extractor(bad, 500)


def test_command(tmp_path: Path) -> None:
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "orb_tools.cli", "trajectory-bench", "--frames", "4", "--size",
                        "320x240", "--budget", "300", "--out-dir", str(out)], capture_output=True, text=True,
                       timeout=600)  # fmt: skip
    assert r.returncode == 0, r.stderr
    with open(out / "trajectory_bench.csv") as fh:
        rows = list(csv.DictReader(fh))
    ours = f"{RECOMMENDED_STEP[0]}:{RECOMMENDED_STEP[1]}x{RECOMMENDED_SCALES}s{RECOMMENDED_SECTORS}/g300"
    assert [row["extractor"] for row in rows] == [ours, "cv-default", "orbslam"]
    assert all(row["frames"] == "4" and row["lost"] == "0" for row in rows)
    assert (out / "wall" / "trajectory.png").stat().st_size > 1000 and (out / "wall" / "truth.tum").is_file()
    (tmp_path / "seq").mkdir()
    for bad in (["--no-render"], ["--tum", str(tmp_path / "seq"), "--no-render"], ["--extractors", "cv-2:1x4"]):
        b = subprocess.run([sys.executable, "-m", "orb_tools.cli", "trajectory-bench", *bad], capture_output=True,
                           text=True, timeout=120)  # fmt: skip
        assert b.returncode == 2 and len(b.stderr.strip().splitlines()) == 1, (bad, b.stderr)
