# SPDX-License-Identifier: MIT
"""Software reproduction of the thesis's accuracy experiments (section 5.3).

* ``compare-fast`` (Figs. 5.5/5.6): our FAST-9 + 3x3 NMS against OpenCV's FAST on scale 0. The raw
  segment tests must agree exactly; after suppression we report the coincident detections and the
  mean SAD score of each set (our score definition for both).
* ``rotation-bench`` (Figs. 5.8/5.9): each image rotated about its centre at every angle; features
  of the original and the rotated image (model at several sector counts, and OpenCV ORB) are matched
  by Hamming distance with cross-check, and a match is correct when it lands within 3 pixels of the
  original position mapped through the rotation. The KPI is the percentage of correct matches.
"""

from __future__ import annotations

import csv
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from golden_model.brief import DESCRIPTOR_BYTES
from golden_model.config import RECOMMENDED_THRESHOLD_LO, Config, sectors_to_per_quadrant
from golden_model.fast import fast_score
from golden_model.features import Features
from golden_model.pipeline import DESC_BORDER, describe_level, detect, extract, orb_level
from golden_model.scaler import pyramid

from .opencv_backend import extract_opencv, extract_opencv_selected, fast_keypoints, sad_score_at

Image = tuple[str, np.ndarray]
Progress = Callable[[str], None]

MATCH_RADIUS = 3.0
POSITION_EPS = 1e-6
OPENCV = "opencv"

# ----------------------------------------------------------------------------------------------
# compare-fast
# ----------------------------------------------------------------------------------------------

FAST_COLUMNS = (
    "image", "threshold", "raw_ours", "raw_opencv", "raw_identical", "nms_ours", "nms_opencv", "coincident",
    "coincident_pct", "mean_score_ours", "mean_score_opencv", "mean_score_diff_pct",
)  # fmt: skip


def _pct(num: float, den: float) -> float:
    return 100.0 * num / den if den else math.nan


def _mean(v: np.ndarray) -> float:
    return float(v.mean()) if len(v) else math.nan


def raw_corner_map_opencv(img: np.ndarray, threshold: int) -> np.ndarray:
    """Boolean map of OpenCV's FAST-9/16 corners without non-maximum suppression."""
    xs, ys = fast_keypoints(img, threshold, nonmax=False)
    out = np.zeros(img.shape, dtype=bool)
    out[ys, xs] = True
    return out


def compare_fast_one(name: str, img: np.ndarray, threshold: int) -> dict:
    """One row of :func:`compare_fast`."""
    raw_ours = fast_score(img, threshold) > 0
    raw_cv = raw_corner_map_opencv(img, threshold)
    xo, yo, *_ = detect(img, threshold)
    xc, yc = fast_keypoints(img, threshold, nonmax=True)
    w = img.shape[1]
    coincident = len(np.intersect1d(yo * w + xo, yc * w + xc))
    score_ours = _mean(sad_score_at(img, xo, yo))
    score_cv = _mean(sad_score_at(img, xc, yc))
    return {
        "image": name, "threshold": int(threshold), "raw_ours": int(raw_ours.sum()), "raw_opencv": int(raw_cv.sum()),
        "raw_identical": bool(np.array_equal(raw_ours, raw_cv)), "nms_ours": len(xo), "nms_opencv": len(xc),
        "coincident": coincident, "coincident_pct": _pct(coincident, len(xc)), "mean_score_ours": score_ours,
        "mean_score_opencv": score_cv, "mean_score_diff_pct": _pct(score_ours - score_cv, score_cv),
    }  # fmt: skip


def compare_fast(images: Sequence[Image], thresholds: Sequence[int]) -> list[dict]:
    """One row per (image, threshold), scale 0 only; see the module doc."""
    return [compare_fast_one(name, img, t) for name, img in images for t in thresholds]


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{value:.2f}"
    return str(value)


def format_table(rows: Sequence[dict], columns: Sequence[str]) -> str:
    cells = [[_fmt(r[c]) for c in columns] for r in rows]
    widths = [max([len(c)] + [len(row[i]) for row in cells]) for i, c in enumerate(columns)]
    lines = ["  ".join(c.rjust(wd) for c, wd in zip(columns, widths, strict=True))]
    lines += ["  ".join(v.rjust(wd) for v, wd in zip(row, widths, strict=True)) for row in cells]
    return "\n".join(lines)


def write_rows(path: Path, rows: Sequence[dict], columns: Sequence[str]) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(columns), extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({c: (f"{r[c]:.4f}" if isinstance(r[c], float) else r[c]) for c in columns})


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_compare_fast(rows: Sequence[dict], path: Path) -> None:
    plt = _pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for name in dict.fromkeys(r["image"] for r in rows):
        mine = [r for r in rows if r["image"] == name]
        t = [r["threshold"] for r in mine]
        left.plot(t, [r["coincident_pct"] for r in mine], marker="o", label=name)
        right.plot(t, [r["mean_score_diff_pct"] for r in mine], marker="o", label=name)
    left.set(xlabel="FAST threshold", ylabel="coincident detections (% of OpenCV's)", title="(a) coincidence")
    right.set(xlabel="FAST threshold", ylabel="mean score difference (%)", title="(b) mean SAD score, ours vs OpenCV")
    right.axhline(0.0, color="grey", linewidth=0.8)
    for ax in (left, right):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def run_compare_fast(images: Sequence[Image], thresholds: Sequence[int], out_dir: Path) -> int:
    """Compute, print, write ``compare_fast.csv`` and ``compare_fast.png``; 1 if a raw set differs."""
    rows = compare_fast(images, thresholds)
    print(format_table(rows, FAST_COLUMNS))
    out_dir.mkdir(parents=True, exist_ok=True)
    write_rows(out_dir / "compare_fast.csv", rows, FAST_COLUMNS)
    plot_compare_fast(rows, out_dir / "compare_fast.png")
    print(f"-> {out_dir / 'compare_fast.csv'}, {out_dir / 'compare_fast.png'}")
    bad = [f"{r['image']} t={r['threshold']}" for r in rows if not r["raw_identical"]]
    if bad:
        print(f"FAIL: raw FAST corners differ from OpenCV's for {', '.join(bad)}")
        return 1
    print("raw FAST corners identical to OpenCV's for every image and threshold")
    return 0


# ----------------------------------------------------------------------------------------------
# model features at several sector counts
# ----------------------------------------------------------------------------------------------


def extract_orb_multi(img: np.ndarray, threshold: int, scales: int, ns: Sequence[int]) -> dict[int, Features]:
    """The model's orb-mode features for several sectors-per-quadrant N at once.

    Equal to ``extract(img, Config(w, h, scales, 4 * n, threshold, "orb"))`` for each n in ``ns``:
    detection, smoothing and moments do not depend on N and are computed once.
    """
    levels = [orb_level(level, s, threshold) for s, level in enumerate(pyramid(img, scales))]
    return {n: Features.concat([describe_level(lv, n) for lv in levels], 4 * n, DESCRIPTOR_BYTES).sorted() for n in ns}


# ----------------------------------------------------------------------------------------------
# rotation-bench
# ----------------------------------------------------------------------------------------------

# Per (method, angle) counts, in this order.
COUNTS = ("original", "rotated", "matches", "correct", "visible")
BENCH_COLUMNS = ("image", "angle", "method", *COUNTS, "correct_pct", "recall_pct")
SUMMARY_COLUMNS = ("method", "mean_correct_pct", "min_correct_pct", "mean_recall_pct", "mean_matches", "vs_opencv")


def rotation_matrix(shape: tuple[int, ...], angle: float) -> np.ndarray:
    """2x3 matrix of a rotation by ``angle`` degrees (counter-clockwise on screen) about the centre.

    The centre ((W-1)/2, (H-1)/2) is that of the pixel grid, so 90-degree multiples of a square image
    are exact pixel permutations.
    """
    h, w = shape[:2]
    return cv2.getRotationMatrix2D(((w - 1) / 2.0, (h - 1) / 2.0), float(angle), 1.0)


def rotate(img: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """The image warped by ``matrix``: same size, bilinear, constant black border."""
    h, w = img.shape[:2]
    return cv2.warpAffine(img, matrix, (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)


def match_counts(orig: Features, rot: Features, matrix: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """``COUNTS`` of one original/rotated pair: cross-checked Hamming matches and the correct ones.

    ``visible`` counts the original features whose mapped position lies in the rotated image at
    least DESC_BORDER pixels from its border (the recall denominator).
    """
    h, w = shape[:2]
    x0, y0 = orig.full_res()
    mx = matrix[0, 0] * x0 + matrix[0, 1] * y0 + matrix[0, 2]
    my = matrix[1, 0] * x0 + matrix[1, 1] * y0 + matrix[1, 2]
    lo = DESC_BORDER - POSITION_EPS  # the matrix's float rounding must not push 18 to 17.999...
    visible = int(((mx >= lo) & (mx <= w - 1 - lo) & (my >= lo) & (my <= h - 1 - lo)).sum())
    matches = correct = 0
    if len(orig) and len(rot):
        found = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(orig.descriptor, rot.descriptor)
        q = np.array([m.queryIdx for m in found], dtype=np.int64)
        t = np.array([m.trainIdx for m in found], dtype=np.int64)
        xr, yr = rot.full_res()
        dist = np.hypot(xr[t] - mx[q], yr[t] - my[q])
        matches, correct = len(found), int((dist <= MATCH_RADIUS).sum())
    return np.array([len(orig), len(rot), matches, correct, visible], dtype=np.int64)


def method_names(sectors: Sequence[int]) -> list[str]:
    return [f"model-{s}" for s in sectors] + [OPENCV]


@dataclass
class RotationBench:
    """Counts of the rotation benchmark: ``counts[image, angle, method]`` holds ``COUNTS``."""

    images: list[str]
    angles: list[float]
    methods: list[str]
    counts: np.ndarray  # (images, angles, methods, len(COUNTS)) int64

    def pooled(self) -> np.ndarray:
        """Counts summed over the images: (angles, methods, len(COUNTS))."""
        return self.counts.sum(axis=0)

    @staticmethod
    def _pcts(counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        c = counts.astype(np.float64)
        with np.errstate(invalid="ignore", divide="ignore"):
            correct_pct = 100.0 * c[..., 3] / c[..., 2]
            recall_pct = 100.0 * c[..., 3] / c[..., 4]
        return correct_pct, recall_pct

    def correct_pct(self) -> np.ndarray:
        """Pooled percentage of correct matches, (angles, methods)."""
        return self._pcts(self.pooled())[0]

    def rows(self) -> list[dict]:
        """One row per image x angle x method, then the pooled rows (image ``pooled``)."""
        out = []
        blocks = [*zip(self.images, self.counts, strict=True), ("pooled", self.pooled())]
        for name, block in blocks:
            cpct, rpct = self._pcts(block)
            for a, angle in enumerate(self.angles):
                for m, method in enumerate(self.methods):
                    row = {"image": name, "angle": float(angle), "method": method}
                    row.update({k: int(v) for k, v in zip(COUNTS, block[a, m], strict=True)})
                    row.update(correct_pct=float(cpct[a, m]), recall_pct=float(rpct[a, m]))
                    out.append(row)
        return out

    def summary(self) -> list[dict]:
        """Per method: mean (over angles) of the pooled correct and recall percentages."""
        pooled = self.pooled()
        cpct, rpct = self._pcts(pooled)
        mean = np.nanmean(cpct, axis=0)
        ref = mean[self.methods.index(OPENCV)] if OPENCV in self.methods else math.nan
        return [
            {
                "method": method,
                "mean_correct_pct": float(mean[m]),
                "min_correct_pct": float(np.nanmin(cpct[:, m])),
                "mean_recall_pct": float(np.nanmean(rpct[:, m])),
                "mean_matches": float(pooled[:, m, 2].mean()),
                "vs_opencv": float(mean[m] / ref),
            }
            for m, method in enumerate(self.methods)
        ]


def _extract_all(img: np.ndarray, sectors: Sequence[int], threshold: int, scales: int, budget: int = 0
                 ) -> list[Features]:  # fmt: skip
    """Features per method (model at each sector count, then OpenCV). With a budget: the model's
    grid selection (recommended cells and low threshold) and OpenCV's own selection at the count of
    the model's first sector count."""
    h, w = img.shape
    if budget > 0:
        model = [extract(img, Config(w, h, scales, s, threshold, "orb", threshold_lo=RECOMMENDED_THRESHOLD_LO,
                                     selection="grid", budget=budget))
                 for s in sectors]  # fmt: skip
        return [*model, extract_opencv_selected(img, Config(w, h, scales, 32, threshold, "orb"), len(model[0]))]
    ns = [sectors_to_per_quadrant(s) for s in sectors]
    multi = extract_orb_multi(img, threshold, scales, ns)
    cv_feats = extract_opencv(img, Config(w, h, scales, 32, threshold, "orb"))
    return [multi[n] for n in ns] + [cv_feats]


def _bench_image(
    name: str, img: np.ndarray, sectors: Sequence[int], angles: Sequence[float], threshold: int, scales: int,
    progress: Progress | None, budget: int = 0,
) -> np.ndarray:  # fmt: skip
    methods = method_names(sectors)
    counts = np.zeros((len(angles), len(methods), len(COUNTS)), dtype=np.int64)
    originals = _extract_all(img, sectors, threshold, scales, budget)
    if progress:
        sizes = ", ".join(f"{m} {len(f)}" for m, f in zip(methods, originals, strict=True))
        progress(f"{name} {img.shape[1]}x{img.shape[0]}: features {sizes}")
    t0, next_report = time.perf_counter(), 30.0
    for a, angle in enumerate(angles):
        matrix = rotation_matrix(img.shape, angle)
        rotated = _extract_all(rotate(img, matrix), sectors, threshold, scales, budget)
        for m, (orig, rot) in enumerate(zip(originals, rotated, strict=True)):
            counts[a, m] = match_counts(orig, rot, matrix, img.shape)
        if progress and (angle >= next_report or a == len(angles) - 1):
            next_report = (math.floor(angle / 30.0) + 1) * 30.0
            so_far = counts[: a + 1].sum(axis=0)
            pct = ", ".join(f"{m} {_pct(c[3], c[2]):.1f}%" for m, c in zip(methods, so_far, strict=True))
            progress(f"  {name}: {angle:g} deg done ({time.perf_counter() - t0:.0f} s); correct so far: {pct}")
    return counts


def rotation_bench(
    images: Sequence[Image], sectors: Sequence[int], angles: Sequence[float], threshold: int, scales: int,
    progress: Progress | None = None, budget: int = 0,
) -> RotationBench:  # fmt: skip
    """The thesis's Fig. 5.8 experiment on every image at every angle (see the module doc); with a
    budget, the grid selection against OpenCV's own selection at the same count."""
    counts = np.stack([_bench_image(n, img, sectors, angles, threshold, scales, progress, budget)
                       for n, img in images])  # fmt: skip
    return RotationBench([n for n, _ in images], [float(a) for a in angles], method_names(sectors), counts)


def bench_angles(step: float) -> list[float]:
    """0 <= angle < 360 in ``step`` increments."""
    count = math.ceil(360.0 / step - 1e-9)
    return [i * step for i in range(count) if i * step < 360.0]


def plot_rotation_bench(bench: RotationBench, path: Path) -> None:
    plt = _pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw={"width_ratios": [2.2, 1]})
    cpct = bench.correct_pct()
    for m, method in enumerate(bench.methods):
        left.plot(bench.angles, cpct[:, m], label=method, linewidth=1.0)
    left.set(xlabel="rotation (degrees)", ylabel="correct matches (%)", title="(a) correct matches vs rotation")
    left.set_xlim(0, 360)
    left.set_xticks(range(0, 361, 45))
    left.grid(True, alpha=0.3)
    left.legend(fontsize="small")
    summary = bench.summary()
    names = [s["method"] for s in summary]
    means = [s["mean_correct_pct"] for s in summary]
    bars = right.bar(names, means, color=[f"C{i}" for i in range(len(names))])
    right.bar_label(bars, fmt="%.1f")
    right.set(ylabel="mean correct matches (%)", title="(b) mean over all angles")
    right.set_ylim(0, 105)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def run_rotation_bench(
    images: Sequence[Image],
    sectors: Sequence[int],
    step: float,
    threshold: int,
    scales: int,
    out_dir: Path,
    budget: int = 0,
) -> int:
    """Run :func:`rotation_bench` over 0..360 degrees; print a summary, write CSVs and a plot."""
    angles = bench_angles(step)
    sectors = list(dict.fromkeys(sectors))
    listed = ", ".join(map(str, sectors))
    print(f"rotation bench: {len(images)} image(s), {len(angles)} angles (step {step:g}), sectors {listed}"
          f" + OpenCV ORB, threshold {threshold}, {scales} scale(s)"
          + (f", grid selection of {budget} (OpenCV: its own at our count)" if budget else ""), flush=True)  # fmt: skip
    t0 = time.perf_counter()
    bench = rotation_bench(images, sectors, angles, threshold, scales, progress=lambda s: print(s, flush=True),
                           budget=budget)  # fmt: skip
    summary = bench.summary()
    print(f"done in {time.perf_counter() - t0:.1f} s; pooled over images, mean over angles:")
    print(format_table(summary, SUMMARY_COLUMNS))
    if 32 in sectors:
        print(f"model-32 / opencv mean correct_pct: {summary[sectors.index(32)]['vs_opencv']:.3f}")
    out_dir.mkdir(parents=True, exist_ok=True)
    write_rows(out_dir / "rotation_bench.csv", bench.rows(), BENCH_COLUMNS)
    write_rows(out_dir / "rotation_summary.csv", summary, SUMMARY_COLUMNS)
    plot_rotation_bench(bench, out_dir / "rotation_bench.png")
    print(f"-> {out_dir / 'rotation_bench.csv'}, {out_dir / 'rotation_summary.csv'}, {out_dir / 'rotation_bench.png'}")
    return 0
