# SPDX-License-Identifier: MIT
"""`orb-accel scale-bench`: how well features match under scale change (docs/evaluation.md).

Each photograph is warped by homographies about its centre: rotations x scale changes x
perspective (none or mild). For every extractor the reference image's features are matched to the
warped image's (brute-force Hamming, cross-checked); a match is correct when the warped position
of the reference feature lies within 3 pixels of the matched feature. The matching score of a
pair is correct matches / reference features whose warped position stays inside the other image
(at least DESC_BORDER pixels from its border); pooled scores sum both over pairs.

Extractors:
- ours, `NUM:DENxLEVELS[sSECTORS][/BUDGET]` (e.g. `2:1x4`, `5:4x6`, `5:4x4s64/1000`): the golden
  model level by level on the pyramid of golden_model.scaler (2:1 is the hardware's box scaler;
  other steps the fixed-phase bilinear resampler), 32 sectors unless `sSECTORS`, threshold 20; with
  `/BUDGET`, each level's best of a per-level budget (golden_model.select, what the driver's
  Frame.best keeps); a level-k feature is centred at (x + 0.5) r^k - 0.5;
- ours with the fabric's selection, `NUM:DENxLEVELS[sSECTORS]/gBUDGET[cCOLSxROWS]` (e.g. `5:4x5s64/g1000`):
  golden_model.pipeline.extract with selection "grid" (docs/spec.md section 14): BUDGET features per
  image, low threshold 14 (RECOMMENDED_THRESHOLD_LO), a grid of COLS x ROWS cells over the image, by
  default 8 x 6 (golden_model.config.RECOMMENDED_COLS, RECOMMENDED_ROWS); on an image too small for LEVELS levels
  of at least 37x37 pixels, the most levels that fit (the budget is split over those);
- `cv-STEPxLEVELS`: OpenCV ORB with that pyramid (scale factor, levels), FAST score, threshold 20,
  no feature limit;
- `cv-default@OURS` (e.g. `cv-default@5:4x6`): OpenCV ORB's defaults (8 levels x 1.2, Harris
  score) with the feature budget of that one of ours on the same image (`cv-default` alone: the
  first of ours in the list).
"""

from __future__ import annotations

import csv
import math
import re
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import cv2
import numpy as np

from golden_model import limits
from golden_model.config import RECOMMENDED_COLS, RECOMMENDED_ROWS, RECOMMENDED_THRESHOLD_LO, Config, level_size
from golden_model.features import Features
from golden_model.pipeline import DESC_BORDER, extract, extract_scale
from golden_model.scaler import pyramid
from golden_model.select import best_per_level

MATCH_RADIUS = 3.0
ROTATIONS = (0.0, 30.0, 60.0, 90.0)
SCALE_CHANGES = (1.0, 0.8, 0.6)
PERSPECTIVES = (0.0, 1.5e-4)  # h20 of the homography (a gentle keystone)
COUNTS = ("reference", "warped", "inside", "matches", "correct")
THRESHOLD = 20
SECTORS = 32
# what extract_scale reads of a configuration; a level may be smaller than a frame may be (64x48)
LEVEL_CFG = Config(64, 48, scales=1, sectors=SECTORS, threshold=THRESHOLD, mode="orb")
MIN_LEVEL = 2 * DESC_BORDER + 1  # 37: the smallest level that can hold a feature
EXTRACTOR_RE = re.compile(
    r"(?P<num>\d+):(?P<den>\d+)x(?P<levels>\d+)(?:s(?P<sectors>\d+))?(?:/(?P<grid>g)?(?P<budget>\d+)(?:c(?P<cols>\d+)x(?P<rows>\d+))?)?"
)


@dataclass(frozen=True)
class Extractor:
    name: str
    kind: str  # ours | opencv | opencv-default
    step: tuple[int, int] = (2, 1)
    levels: int = 4
    budget_of: str = ""  # opencv-default: the extractor of ours whose feature count is the budget
    sectors: int = SECTORS  # ours: orientation sectors in all
    budget: int = 0  # ours: features kept per image, each level's best (0: every feature)
    grid: bool = False  # ours: the fabric's grid selection of `budget` features instead of the host's
    cells: tuple[int, int] = (RECOMMENDED_COLS, RECOMMENDED_ROWS)  # ours, grid: the grid's columns and rows

    @property
    def factor(self) -> float:
        return self.step[0] / self.step[1]


def parse_extractor(text: str) -> Extractor:
    """`2:1x4`, `5:4x6`, `5:4x4s64/1000` (ours), `5:4x5s64/g1000`, `5:4x5s64/g1000c8x6` (ours, grid
    selection), `cv-2:1x4` (OpenCV with that pyramid), `cv-default[@OURS]`."""
    if text == "cv-default" or text.startswith("cv-default@"):
        return Extractor(text, "opencv-default", budget_of=text.partition("@")[2])
    kind = "opencv" if text.startswith("cv-") else "ours"
    body = text[3:] if kind == "opencv" else text
    m = EXTRACTOR_RE.fullmatch(body)
    if m is None or (kind == "opencv" and (m["sectors"] or m["budget"])) or (m["cols"] and not m["grid"]):
        raise ValueError(
            f"extractor {text!r}: expected NUM:DENxLEVELS[sSECTORS][/BUDGET], "
            "NUM:DENxLEVELS[sSECTORS]/gBUDGET[cCOLSxROWS], "
            "cv-NUM:DENxLEVELS or cv-default"
        )
    num, den, levels = int(m["num"]), int(m["den"]), int(m["levels"])
    ext = Extractor(text, kind, (num, den), levels, sectors=int(m["sectors"] or SECTORS),
                    budget=int(m["budget"] or 0), grid=bool(m["grid"]))  # fmt: skip
    if m["cols"]:
        ext = replace(ext, cells=(int(m["cols"]), int(m["rows"])))
    if not (num > den >= 1 and 1 <= ext.levels <= 12 and ext.sectors in (16, 32, 64)):
        raise ValueError(f"extractor {text!r}: need num > den >= 1, 1..12 levels and 16, 32 or 64 sectors")
    if ext.grid:
        if not (1 <= ext.levels <= limits.SCALES.max and limits.BUDGET.legal(ext.budget)):
            raise ValueError(f"extractor {text!r}: the grid selection needs levels {limits.SCALES.text} and a budget "
                             f"{limits.BUDGET.text}")  # fmt: skip
        if not (limits.COLS.legal(ext.cells[0]) and limits.ROWS.legal(ext.cells[1])):
            raise ValueError(f"extractor {text!r}: the cells must be {limits.COLS.text} x {limits.ROWS.text}")
    return ext


@dataclass
class Points:
    """Keypoints at full resolution with descriptors (N x 32 uint8)."""

    x: np.ndarray
    y: np.ndarray
    desc: np.ndarray

    def __len__(self) -> int:
        return len(self.x)


def max_levels(width: int, height: int, step: tuple[int, int]) -> int:
    """The most pyramid levels whose smallest is at least MIN_LEVEL x MIN_LEVEL (0: not even the frame)."""
    n = 0
    while min(level_size(width, height, n, step)) >= MIN_LEVEL:
        n += 1
    return n


def extract_grid(img: np.ndarray, ext: Extractor) -> Features:
    """The fabric's grid selection (`/gBUDGET[cCOLSxROWS]`) on as many of the extractor's levels as fit."""
    h, w = img.shape
    levels = min(ext.levels, max_levels(w, h, ext.step))
    if levels < 1:
        raise ValueError(f"{ext.name}: a {w}x{h} image is smaller than a level may be ({MIN_LEVEL}x{MIN_LEVEL})")
    cfg = Config(w, h, scales=levels, sectors=ext.sectors, threshold=THRESHOLD, step_num=ext.step[0],
                 step_den=ext.step[1], threshold_lo=RECOMMENDED_THRESHOLD_LO, selection="grid", budget=ext.budget,
                 cols=ext.cells[0], rows=ext.cells[1])  # fmt: skip
    return extract(img, cfg)


def extract_ours(img: np.ndarray, ext: Extractor) -> Points:
    if ext.grid:
        grid = extract_grid(img, ext)
        gx, gy = grid.full_res()
        return Points(gx, gy, grid.descriptor.reshape(-1, 32))
    cfg = replace(LEVEL_CFG, sectors=ext.sectors)
    parts = []
    for k, level in enumerate(pyramid(img, ext.levels, ext.step)):
        h, w = level.shape
        if w < 2 * DESC_BORDER + 1 or h < 2 * DESC_BORDER + 1:
            break
        parts.append(extract_scale(level, k, cfg))
    feats = Features.concat(parts, ext.sectors, 32, ext.step)
    if ext.budget:
        feats = best_per_level(feats, ext.budget, ext.levels)
    x0, y0 = feats.full_res()
    return Points(x0, y0, feats.descriptor.reshape(-1, 32))


def extract_opencv_orb(img: np.ndarray, ext: Extractor, budget: int) -> Points:
    if ext.kind == "opencv-default":
        orb = cv2.ORB_create(nfeatures=max(budget, 1))
    else:
        orb = cv2.ORB_create(nfeatures=1_000_000, scaleFactor=ext.factor, nlevels=ext.levels, edgeThreshold=31,
                             patchSize=31, fastThreshold=THRESHOLD, scoreType=cv2.ORB_FAST_SCORE)  # fmt: skip
    kps, desc = orb.detectAndCompute(img, None)
    pts = np.array([kp.pt for kp in kps], dtype=np.float64).reshape(-1, 2)
    return Points(pts[:, 0], pts[:, 1], desc if desc is not None else np.zeros((0, 32), np.uint8))


def _extract(img: np.ndarray, ext: Extractor, budgets: dict[str, int]) -> Points:
    return extract_ours(img, ext) if ext.kind == "ours" else extract_opencv_orb(img, ext, budgets.get(ext.name, 0))


def homography(shape: tuple[int, ...], angle: float, scale: float, persp: float) -> np.ndarray:
    """3x3: about the image centre, rotate by `angle` degrees (counter-clockwise on screen), scale by
    `scale`, then a keystone of strength `persp`."""
    h, w = shape[:2]
    cx, cy = (w - 1) / 2.0, (h - 1) / 2.0
    t = math.radians(angle)
    rs = np.array([[scale * math.cos(t), scale * math.sin(t), 0], [-scale * math.sin(t), scale * math.cos(t), 0],
                   [0, 0, 1]])  # fmt: skip
    p = np.array([[1, 0, 0], [0, 1, 0], [persp, persp / 2, 1]])
    to_c = np.array([[1, 0, -cx], [0, 1, -cy], [0, 0, 1]])
    back = np.array([[1, 0, cx], [0, 1, cy], [0, 0, 1]])
    return back @ p @ rs @ to_c


def warp(img: np.ndarray, hmat: np.ndarray) -> np.ndarray:
    h, w = img.shape[:2]
    return cv2.warpPerspective(img, hmat, (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)


def pair_counts(ref: Points, got: Points, hmat: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    h, w = shape[:2]
    ph = hmat @ np.vstack([ref.x, ref.y, np.ones(len(ref))])
    mx, my = ph[0] / ph[2], ph[1] / ph[2]
    b = DESC_BORDER
    inside = int(((mx >= b) & (mx <= w - 1 - b) & (my >= b) & (my <= h - 1 - b)).sum())
    matches = correct = 0
    if len(ref) and len(got):
        found = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(ref.desc, got.desc)
        q = np.array([m.queryIdx for m in found], dtype=np.int64)
        t = np.array([m.trainIdx for m in found], dtype=np.int64)
        matches = len(found)
        correct = int((np.hypot(got.x[t] - mx[q], got.y[t] - my[q]) <= MATCH_RADIUS).sum())
    return np.array([len(ref), len(got), inside, matches, correct], dtype=np.int64)


def score(counts: np.ndarray) -> float:
    """Matching score in percent: correct / inside (counts summed over whatever axes)."""
    return 100.0 * counts[..., 4].sum() / max(counts[..., 2].sum(), 1)


def check_budgets(extractors: Sequence[Extractor]) -> None:
    """An OpenCV-defaults extractor takes its budget from one of ours in the same list."""
    ours = {e.name for e in extractors if e.kind == "ours"}
    for e in extractors:
        if e.kind == "opencv-default" and (not ours or (e.budget_of and e.budget_of not in ours)):
            listed = ", ".join(sorted(ours)) or "none"
            raise ValueError(f"{e.name}: the budget needs one of ours in the list ({listed})")


def references(img: np.ndarray, extractors: Sequence[Extractor]) -> tuple[dict[str, Points], dict[str, int]]:
    """Every extractor's features of the reference image, and the budget of each opencv-default one:
    the feature count of its ours (`budget_of`, else the first of ours)."""
    refs = {e.name: extract_ours(img, e) for e in extractors if e.kind == "ours"}
    first_ours = next(iter(refs), "")
    budgets = {e.name: len(refs[e.budget_of or first_ours]) for e in extractors if e.kind == "opencv-default"}
    for e in extractors:
        if e.kind != "ours":
            refs[e.name] = _extract(img, e, budgets)
    return refs, budgets


def run(images: Sequence[tuple[str, np.ndarray]], extractors: Sequence[Extractor],
        rotations: Sequence[float] = ROTATIONS, scales: Sequence[float] = SCALE_CHANGES,
        perspectives: Sequence[float] = PERSPECTIVES,
        progress: Callable[[str], None] | None = None) -> tuple[list[dict], list[dict]]:  # fmt: skip
    """(one row per image x extractor x homography, one summary row per extractor)."""
    check_budgets(extractors)
    rows: list[dict] = []
    totals = {e.name: np.zeros((len(scales), len(COUNTS)), dtype=np.int64) for e in extractors}
    per_image = {e.name: [] for e in extractors}
    t0 = time.perf_counter()
    for name, img in images:
        refs, budgets = references(img, extractors)
        for e in extractors:
            per_image[e.name].append(len(refs[e.name]))
        for angle in rotations:
            for si, sc in enumerate(scales):
                for persp in perspectives:
                    hmat = homography(img.shape, angle, sc, persp)
                    warped = warp(img, hmat)
                    for e in extractors:
                        c = pair_counts(refs[e.name], _extract(warped, e, budgets), hmat, img.shape)
                        totals[e.name][si] += c
                        rows.append({"image": name, "extractor": e.name, "rotation": angle, "scale": sc,
                                     "perspective": persp, **dict(zip(COUNTS, c.tolist(), strict=True)),
                                     "score_pct": round(score(c), 2)})  # fmt: skip
        if progress:
            done = ", ".join(f"{e.name} {score(totals[e.name]):.1f}%" for e in extractors)
            progress(f"{name}: done ({time.perf_counter() - t0:.0f} s); pooled so far: {done}")
    summary = []
    for e in extractors:
        t = totals[e.name]
        row = {"extractor": e.name, "pooled_pct": round(float(score(t)), 2)}
        row.update({f"scale_{sc:g}_pct": round(float(score(t[i])), 2) for i, sc in enumerate(scales)})
        row["features_per_image"] = round(float(np.mean(per_image[e.name])), 1)
        summary.append(row)
    return rows, summary


def write_csv(path: Path, rows: Sequence[dict]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def plot(summary: Sequence[dict], scales: Sequence[float], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.5))
    cols = [f"scale_{sc:g}_pct" for sc in scales] + ["pooled_pct"]
    labels = [f"scale {sc:g}" for sc in scales] + ["pooled"]
    width = 0.8 / max(len(summary), 1)
    for i, row in enumerate(summary):
        ax.bar(np.arange(len(cols)) + i * width, [row[c] for c in cols], width, label=row["extractor"])
    ax.set_xticks(np.arange(len(cols)) + 0.4 - width / 2, labels)
    ax.set_ylabel("matching score (%)")
    ax.set_title("Matching under rotation x scale x perspective (orb-accel scale-bench)")
    ax.legend(fontsize=8, ncol=2)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
