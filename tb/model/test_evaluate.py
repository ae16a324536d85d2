# SPDX-License-Identifier: MIT
"""The thesis's accuracy experiments in software: compare-fast and rotation-bench, and their CLI."""

from __future__ import annotations

import csv
from pathlib import Path

import cv2
import numpy as np
import pytest

from golden_model.config import Config
from golden_model.fast import fast_score
from golden_model.features import read_csv
from golden_model.pipeline import extract
from orb_tools.cli import main
from orb_tools.evaluate import (
    BENCH_COLUMNS,
    FAST_COLUMNS,
    SUMMARY_COLUMNS,
    bench_angles,
    compare_fast,
    extract_orb_multi,
    method_names,
    rotate,
    rotation_bench,
    rotation_matrix,
)
from orb_tools.images import sample_photographs

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def photos() -> dict[str, np.ndarray]:
    return sample_photographs()


def _square(img: np.ndarray, side: int = 320) -> np.ndarray:
    h, w = img.shape
    y, x = (h - side) // 2, (w - side) // 2
    return np.ascontiguousarray(img[y : y + side, x : x + side])


def _read(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


# ---------------------------------------------------------------------------------------- compare-fast


def test_compare_fast_raw_corners_identical_to_opencv(photos: dict[str, np.ndarray]) -> None:
    images = [("camera", photos["camera"]), ("coffee", photos["coffee"])]
    rows = compare_fast(images, [10, 40])
    assert [(r["image"], r["threshold"]) for r in rows] == [
        ("camera", 10),
        ("camera", 40),
        ("coffee", 10),
        ("coffee", 40),
    ]
    for r in rows:
        assert set(r) == set(FAST_COLUMNS)
        assert r["raw_identical"] is True, r
        assert r["raw_ours"] == r["raw_opencv"] > 0
        assert 0 < r["coincident"] <= min(r["nms_ours"], r["nms_opencv"])
        assert r["coincident_pct"] == pytest.approx(100.0 * r["coincident"] / r["nms_opencv"])
        assert r["mean_score_ours"] > 0 and r["mean_score_opencv"] > 0
        assert abs(r["mean_score_diff_pct"]) < 20.0
    # A higher threshold keeps fewer, stronger corners.
    assert rows[1]["raw_ours"] < rows[0]["raw_ours"]
    assert rows[1]["mean_score_ours"] > rows[0]["mean_score_ours"]


def test_compare_fast_handles_a_featureless_image() -> None:
    (row,) = compare_fast([("flat", np.full((48, 64), 7, dtype=np.uint8))], [20])
    assert row["raw_identical"] and row["nms_ours"] == row["nms_opencv"] == row["coincident"] == 0
    assert np.isnan(row["coincident_pct"]) and np.isnan(row["mean_score_diff_pct"])


# ---------------------------------------------------------------------------------------- multi-N helper


@pytest.mark.parametrize("name,scales", [("camera", 1), ("astronaut", 3)])
def test_extract_orb_multi_equals_extract(photos: dict[str, np.ndarray], name: str, scales: int) -> None:
    img = photos[name]
    h, w = img.shape
    multi = extract_orb_multi(img, 20, scales, [4, 8, 16])
    assert sorted(multi) == [4, 8, 16]
    for n, feats in multi.items():
        expected = extract(img, Config(w, h, scales, 4 * n, 20, "orb"))
        assert feats == expected
        assert feats.sectors_total == expected.sectors_total == 4 * n


# ---------------------------------------------------------------------------------------- rotation bench


def test_bench_angles() -> None:
    assert bench_angles(90) == [0, 90, 180, 270]
    assert bench_angles(1) == list(range(360))
    a = bench_angles(0.7)
    assert len(a) == 515 and a[-1] < 360 and a[1] == pytest.approx(0.7)


def test_quarter_turns_are_exact_pixel_permutations(photos: dict[str, np.ndarray]) -> None:
    """The precondition of the 90-degree covariance: warpAffine about the grid centre is np.rot90."""
    sq = _square(photos["astronaut"])
    for k in (1, 2, 3):
        rotated = rotate(sq, rotation_matrix(sq.shape, 90 * k))
        np.testing.assert_array_equal(rotated, np.rot90(sq, k))
        np.testing.assert_array_equal(fast_score(rotated, 20), np.rot90(fast_score(sq, 20), k))
    np.testing.assert_array_equal(rotate(sq, rotation_matrix(sq.shape, 0)), sq)


def test_rotation_bench_angle_zero_is_perfect(photos: dict[str, np.ndarray]) -> None:
    images = [("coffee", photos["coffee"]), ("chelsea", photos["chelsea"])]
    bench = rotation_bench(images, [16, 32, 64], [0.0], 20, 1)
    assert bench.methods == method_names([16, 32, 64]) == ["model-16", "model-32", "model-64", "opencv"]
    assert bench.counts.shape == (2, 1, 4, 5)
    original, rotated, matches, correct, visible = np.moveaxis(bench.counts, -1, 0)
    np.testing.assert_array_equal(original, rotated)
    np.testing.assert_array_equal(original[:, :, :3], matches[:, :, :3])  # the model: every feature matches itself
    np.testing.assert_array_equal(correct, matches)
    np.testing.assert_array_equal(visible, original)
    assert (bench.correct_pct()[0, :3] == 100.0).all()


def test_rotation_bench_quarter_turn_is_almost_exact(photos: dict[str, np.ndarray]) -> None:
    """On a square image, a 90-degree turn permutes pixels; the model is covariant except for NMS ties.

    FAST scores rotate exactly and sectors move by exactly N, but 3x3 NMS breaks ties between equal
    adjacent scores by raster order, which a rotation changes; a few survivors move by one pixel.
    """
    sq = _square(photos["camera"])
    bench = rotation_bench([("camera", sq)], [16, 32, 64], [90.0, 180.0, 270.0], 20, 1)
    original, rotated, matches, _, _ = np.moveaxis(bench.pooled(), -1, 0)
    assert (np.abs(rotated - original)[:, :3] <= 0.02 * original[:, :3]).all()
    assert (matches[:, :3] >= 0.97 * original[:, :3]).all()
    assert (bench.correct_pct()[:, :3] > 99.0).all()


def test_rotation_bench_model_32_sectors_close_to_opencv(photos: dict[str, np.ndarray]) -> None:
    bench = rotation_bench([("camera", photos["camera"])], [32], list(range(0, 360, 30)), 20, 1)
    summary = {row["method"]: row for row in bench.summary()}
    assert set(summary) == {"model-32", "opencv"}
    assert summary["model-32"]["mean_correct_pct"] >= 0.9 * summary["opencv"]["mean_correct_pct"]
    assert summary["model-32"]["vs_opencv"] >= 0.9
    assert 0 < summary["model-32"]["mean_recall_pct"] <= 100


def test_rotation_bench_with_the_grid_selection(photos: dict[str, np.ndarray]) -> None:
    """--budget: the model's grid selection (at most the budget, the selection's own features at
    angle 0) against OpenCV's own selection at the model's count."""
    img = photos["coffee"]
    bench = rotation_bench([("coffee", img)], [32], [0.0, 90.0], 20, 1, budget=150)
    original, _, matches, correct, _ = np.moveaxis(bench.counts[0], -1, 0)
    h, w = img.shape
    want = extract(img, Config(w, h, 1, 32, 20, "orb", threshold_lo=7, selection="grid",
                               budget=150))  # fmt: skip
    assert original[0, 0] == len(want) <= 150
    assert abs(int(original[0, 1]) - len(want)) <= 0.05 * len(want), "OpenCV keeps about the model's count"
    assert matches[0, 0] == correct[0, 0] == original[0, 0], "angle 0: every selected feature matches itself"


def test_rotation_bench_rows_pool_over_images(photos: dict[str, np.ndarray]) -> None:
    images = [("chelsea", photos["chelsea"]), ("coffee", photos["coffee"])]
    bench = rotation_bench(images, [16], [0.0, 45.0], 20, 1)
    rows = bench.rows()
    assert len(rows) == 3 * 2 * 2 and all(set(r) == set(BENCH_COLUMNS) for r in rows)
    for angle in (0.0, 45.0):
        for method in bench.methods:
            mine = {r["image"]: r for r in rows if r["angle"] == angle and r["method"] == method}
            assert mine["pooled"]["correct"] == mine["chelsea"]["correct"] + mine["coffee"]["correct"]
            assert mine["pooled"]["matches"] == mine["chelsea"]["matches"] + mine["coffee"]["matches"]
    assert [s["method"] for s in bench.summary()] == ["model-16", "opencv"]


# ---------------------------------------------------------------------------------------- CLI end to end


@pytest.fixture(scope="module")
def photo_png(tmp_path_factory: pytest.TempPathFactory, photos: dict[str, np.ndarray]) -> Path:
    path = tmp_path_factory.mktemp("img") / "chelsea.png"
    assert cv2.imwrite(str(path), photos["chelsea"])
    return path


def _is_png(path: Path) -> bool:
    data = path.read_bytes()
    return data.startswith(PNG_MAGIC) and len(data) > 5000


def test_cli_compare_fast(photo_png: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["compare-fast", str(photo_png), "--threshold", "15", "30", "--out-dir", str(tmp_path)]) == 0
    rows = _read(tmp_path / "compare_fast.csv")
    assert [(r["image"], r["threshold"], r["raw_identical"]) for r in rows] == [
        ("chelsea", "15", "True"),
        ("chelsea", "30", "True"),
    ]
    assert list(rows[0]) == list(FAST_COLUMNS)
    assert all(int(r["coincident"]) <= min(int(r["nms_ours"]), int(r["nms_opencv"])) for r in rows)
    assert _is_png(tmp_path / "compare_fast.png")
    assert "identical" in capsys.readouterr().out


def test_cli_rotation_bench(photo_png: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["rotation-bench", str(photo_png), "--step", "90", "--sectors", "16", "32", "--out-dir", str(tmp_path)]
    assert main(argv) == 0
    rows = _read(tmp_path / "rotation_bench.csv")
    assert len(rows) == 2 * 4 * 3  # (image + pooled) x angles x methods
    assert {float(r["angle"]) for r in rows} == {0.0, 90.0, 180.0, 270.0}
    zero = [r for r in rows if float(r["angle"]) == 0.0 and r["method"].startswith("model")]
    assert all(float(r["correct_pct"]) == 100.0 for r in zero)
    summary = _read(tmp_path / "rotation_summary.csv")
    assert [r["method"] for r in summary] == ["model-16", "model-32", "opencv"] and list(summary[0]) == list(
        SUMMARY_COLUMNS
    )
    assert all(50.0 < float(r["mean_correct_pct"]) <= 100.0 for r in summary)
    assert _is_png(tmp_path / "rotation_bench.png")
    assert "model-32 / opencv" in capsys.readouterr().out


@pytest.mark.parametrize("fast_only", [False, True])
def test_cli_extract_opencv_backend(photo_png: Path, tmp_path: Path, fast_only: bool) -> None:
    out = tmp_path / "features.csv"
    argv = ["extract", str(photo_png), "--backend", "opencv", "--scales", "2", "--step", "2:1", "--sectors", "32",
            "--budget", "0", "--out", str(out)]  # fmt: skip
    assert main(argv + (["--fast-only"] if fast_only else [])) == 0
    feats = read_csv(out)
    assert len(feats) > 100 and set(feats.scale.tolist()) == {0, 1}
    if fast_only:
        assert not feats.has_descriptors and (feats.sector == -1).all()
    else:
        assert feats.descriptor.shape == (len(feats), 32) and ((feats.sector >= 0) & (feats.sector < 32)).all()
    assert (feats.score > 0).all()
