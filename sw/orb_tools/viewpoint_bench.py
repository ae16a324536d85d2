# SPDX-License-Identifier: MIT
"""`orb-accel viewpoint-bench`: matching under a change of viewpoint (docs/evaluation.md).

Each photograph is taken as a textured plane and seen again by a camera whose view of it is tilted
by an angle about an axis in the plane (the image's vertical axis, `y`, or its horizontal one,
`x`), combined with an in-plane rotation and a scale change. The map between the two images is an
exact homography (`tilt_homography`): the plane's points (u, v, 0), centred on the image, are seen
by a pinhole camera of focal length `FOCAL` image widths at a distance of one focal length over the
scale, after the tilt and the rotation. A tilt of 0 is the scale bench's plain rotation and scale.

Per pair and extractor (the extractors of `orb-accel scale-bench`): the matching score (correct
cross-checked matches / reference features that stay inside the other image, a match correct
within 3 pixels of the exact map), and the homography-inlier ratio (the matches a RANSAC fit of a
homography, 3-pixel threshold, keeps, over the reference features inside) with whether that fit is
right (its four image corners within `CORNER_PX` pixels of the exact map's). Pooled over the
images, by tilt angle.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import cv2
import numpy as np

from . import scale_bench as sb

TILTS = (0.0, 20.0, 30.0, 40.0, 50.0, 60.0)
AXES = ("x", "y")
ROTATIONS = (0.0, 30.0)
SCALES = (1.0, 0.75)
FOCAL = 1.0  # the camera's focal length in image widths (a 53-degree horizontal field of view)
RANSAC_PX = 3.0
CORNER_PX = 5.0
COUNTS = ("reference", "warped", "inside", "matches", "correct", "inliers", "h_ok")


def tilt_homography(shape: tuple[int, ...], tilt: float, axis: str, rotation: float = 0.0,
                    scale: float = 1.0, focal: float = FOCAL) -> np.ndarray:  # fmt: skip
    """3x3, reference pixel -> view pixel: the image as a plane through its centre, rotated in
    plane by `rotation` degrees (counter-clockwise on screen), tilted by `tilt` degrees about its
    `axis` ("x": the horizontal axis through the centre, "y": the vertical one), seen by a camera
    of focal length `focal` image widths at a distance of one focal length / `scale`."""
    if axis not in AXES:
        raise ValueError(f"tilt axis {axis!r}: expected one of {', '.join(AXES)}")
    if not (0.0 <= tilt < 90.0 and scale > 0.0 and focal > 0.0):
        raise ValueError(f"tilt {tilt} (0 <= tilt < 90), scale {scale} and focal {focal} (> 0)")
    h, w = shape[:2]
    cx, cy = (w - 1) / 2.0, (h - 1) / 2.0
    f = focal * w
    t, a = math.radians(tilt), math.radians(rotation)
    # in-plane rotation: counter-clockwise on screen (y down), as scale_bench.homography
    rz = np.array([[math.cos(a), math.sin(a), 0], [-math.sin(a), math.cos(a), 0], [0, 0, 1]])
    if axis == "x":
        rt = np.array([[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])
    else:
        rt = np.array([[math.cos(t), 0, math.sin(t)], [0, 1, 0], [-math.sin(t), 0, math.cos(t)]])
    r = rt @ rz
    k = np.array([[f, 0, cx], [0, f, cy], [0, 0, 1]])
    plane = np.column_stack([r[:, 0], r[:, 1], [0.0, 0.0, f / scale]])
    centred = np.array([[1, 0, -cx], [0, 1, -cy], [0, 0, 1]])
    hm = k @ plane @ centred
    return hm / hm[2, 2]


def corners_error(h_est: np.ndarray, h_true: np.ndarray, shape: tuple[int, ...]) -> float:
    """The largest distance, in view pixels, between the four image corners mapped by each."""
    h, w = shape[:2]
    c = np.array([[0, 0, 1], [w - 1, 0, 1], [w - 1, h - 1, 1], [0, h - 1, 1]], dtype=np.float64).T
    pe, pt = h_est @ c, h_true @ c
    return float(np.max(np.hypot(pe[0] / pe[2] - pt[0] / pt[2], pe[1] / pe[2] - pt[1] / pt[2])))


def pair_counts(ref: sb.Points, got: sb.Points, hmat: np.ndarray, shape: tuple[int, ...],
                seed: int = 1) -> np.ndarray:  # fmt: skip
    """reference, warped, inside, matches, correct (scale_bench.pair_counts), then the RANSAC
    homography's inliers and whether it is right (1/0)."""
    h, w = shape[:2]
    ph = hmat @ np.vstack([ref.x, ref.y, np.ones(len(ref))])
    mx, my = ph[0] / ph[2], ph[1] / ph[2]
    b = sb.DESC_BORDER
    inside = int(((mx >= b) & (mx <= w - 1 - b) & (my >= b) & (my <= h - 1 - b)).sum())
    matches = correct = inliers = h_ok = 0
    if len(ref) and len(got):
        found = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(ref.desc, got.desc)
        q = np.array([m.queryIdx for m in found], dtype=np.int64)
        t = np.array([m.trainIdx for m in found], dtype=np.int64)
        matches = len(found)
        correct = int((np.hypot(got.x[t] - mx[q], got.y[t] - my[q]) <= sb.MATCH_RADIUS).sum())
        if matches >= 4:
            src = np.column_stack([ref.x[q], ref.y[q]]).astype(np.float32)
            dst = np.column_stack([got.x[t], got.y[t]]).astype(np.float32)
            cv2.setRNGSeed(seed)
            h_est, mask = cv2.findHomography(src, dst, cv2.RANSAC, RANSAC_PX, maxIters=2000, confidence=0.995)
            if h_est is not None and mask is not None:
                inliers = int(mask.sum())
                h_ok = int(corners_error(h_est, hmat, shape) <= CORNER_PX)
    return np.array([len(ref), len(got), inside, matches, correct, inliers, h_ok], dtype=np.int64)


def views(tilts: Sequence[float] = TILTS, axes: Sequence[str] = AXES, rotations: Sequence[float] = ROTATIONS,
          scales: Sequence[float] = SCALES) -> list[tuple[float, str, float, float]]:  # fmt: skip
    """(tilt, axis, rotation, scale) of every pair; a tilt of 0 once (its axis is "-")."""
    out = []
    for tilt in tilts:
        for axis in ("-",) if tilt == 0 else axes:
            for rot in rotations:
                for sc in scales:
                    out.append((float(tilt), axis, float(rot), float(sc)))
    return out


score = sb.score  # correct / inside, the scale bench's


def inlier_ratio(c: np.ndarray) -> float:
    return 100.0 * c[..., 5].sum() / max(c[..., 2].sum(), 1)


def run(images: Sequence[tuple[str, np.ndarray]], extractors: Sequence[sb.Extractor],
        tilts: Sequence[float] = TILTS, axes: Sequence[str] = AXES, rotations: Sequence[float] = ROTATIONS,
        scales: Sequence[float] = SCALES,
        progress: Callable[[str], None] | None = None) -> tuple[list[dict], list[dict]]:  # fmt: skip
    """(one row per image x extractor x view, one row per extractor x tilt and one pooled)."""
    sb.check_budgets(extractors)
    pairs = views(tilts, axes, rotations, scales)
    rows: list[dict] = []
    totals = {e.name: np.zeros((len(tilts), len(COUNTS)), dtype=np.int64) for e in extractors}
    n_pairs = np.zeros(len(tilts), dtype=np.int64)
    t0 = time.perf_counter()
    for name, img in images:
        refs, budgets = sb.references(img, extractors)
        for tilt, axis, rot, sc in pairs:
            ti = list(tilts).index(tilt)
            n_pairs[ti] += 1
            hmat = tilt_homography(img.shape, tilt, axis if axis != "-" else "x", rot, sc)
            warped = sb.warp(img, hmat)
            for e in extractors:
                c = pair_counts(refs[e.name], sb._extract(warped, e, budgets), hmat, img.shape)
                totals[e.name][ti] += c
                rows.append({"image": name, "extractor": e.name, "tilt": tilt, "axis": axis, "rotation": rot,
                             "scale": sc, **dict(zip(COUNTS, c.tolist(), strict=True)),
                             "score_pct": round(score(c), 2), "inlier_pct": round(inlier_ratio(c), 2)})  # fmt: skip
        if progress:
            done = ", ".join(f"{e.name} {score(totals[e.name]):.1f}%" for e in extractors)
            progress(f"{name}: done ({time.perf_counter() - t0:.0f} s); pooled so far: {done}")
    summary = []
    for e in extractors:
        t = totals[e.name]
        for ti, tilt in enumerate(tilts):
            summary.append({"extractor": e.name, "tilt": f"{tilt:g}", "pairs": int(n_pairs[ti]),
                            "score_pct": round(score(t[ti]), 2), "inlier_pct": round(inlier_ratio(t[ti]), 2),
                            "h_ok_pct": round(100.0 * t[ti, 6] / max(int(n_pairs[ti]), 1), 1),
                            "features": round(t[ti, 0] / max(int(n_pairs[ti]), 1), 1)})  # fmt: skip
        summary.append({"extractor": e.name, "tilt": "pooled", "pairs": int(n_pairs.sum()),
                        "score_pct": round(score(t), 2), "inlier_pct": round(inlier_ratio(t), 2),
                        "h_ok_pct": round(100.0 * t[:, 6].sum() / max(int(n_pairs.sum()), 1), 1),
                        "features": round(t[:, 0].sum() / max(int(n_pairs.sum()), 1), 1)})  # fmt: skip
    return rows, summary


def plot(summary: Sequence[dict], path: Path) -> None:
    """Matching score and homography-inlier ratio by tilt, one line per extractor."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    names = list(dict.fromkeys(r["extractor"] for r in summary))
    for name in names:
        pts = [r for r in summary if r["extractor"] == name and r["tilt"] != "pooled"]
        x = [float(r["tilt"]) for r in pts]
        axes[0].plot(x, [r["score_pct"] for r in pts], marker="o", label=name)
        axes[1].plot(x, [r["inlier_pct"] for r in pts], marker="o", label=name)
    for ax, label in zip(axes, ("matching score (%)", "homography inliers / features inside (%)"), strict=True):
        ax.set_xlabel("tilt (degrees)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Matching under a change of viewpoint (orb-accel viewpoint-bench)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
