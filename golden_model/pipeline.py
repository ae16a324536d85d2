# SPDX-License-Identifier: MIT
"""The whole accelerator, frame in, features out: the executable specification.

Per scale (scale 0 is the input, scale s+1 the pyramid step of scale s: the 2:1 box average, or for
any other num:den the fixed-phase bilinear resample of golden_model.scaler):
FAST-9 score maps at the main and the low threshold -> one 3x3 NMS on their combination -> border
rule -> corner response -> (orb mode) smoothing, moments, sector, rBRIEF; then, in `grid`
selection, each level's budget of the candidates (golden_model.select).

Border rule: in ``fast`` mode every NMS survivor is reported (FAST itself only tests
3 <= x <= W-4, 3 <= y <= H-4). In ``orb`` mode only survivors with
DESC_BORDER <= x <= W-1-DESC_BORDER and DESC_BORDER <= y <= H-1-DESC_BORDER are reported, each
with a sector and a descriptor: the radius-15 patch plus the 7x7 smoothing then reads only real
pixels. The border rule is applied after NMS, so a corner outside it can still suppress one
inside. No feature is ever dropped for lack of capacity: the model has none to predict.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .brief import DESCRIPTOR_BYTES, describe
from .config import Config
from .fast import fast_score
from .features import NO_SECTOR, Features
from .nms import nms3x3
from .orientation import PATCH_RADIUS, moments, quantise
from .response import response_map
from .scaler import pyramid
from .select import select_grid, streamed_grid
from .smooth import RADIUS as SMOOTH_RADIUS
from .smooth import smooth

DESC_BORDER = PATCH_RADIUS + SMOOTH_RADIUS  # 18
MAIN_LIFT = 4096  # added to a main corner's score in the combined NMS map: above every SAD score


def check_frame(img: np.ndarray, cfg: Config) -> None:
    if img.ndim != 2 or img.dtype != np.uint8:
        raise ValueError(f"expected a 2-D uint8 luma frame, got {img.dtype} with shape {img.shape}")
    if img.shape != (cfg.height, cfg.width):
        raise ValueError(f"frame is {img.shape[1]}x{img.shape[0]}, configuration is {cfg.width}x{cfg.height}")


def combined_score(img: np.ndarray, threshold: int, threshold_lo: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(S', main): the combined map S' = S_t + 4096 where the pixel is a corner at the main
    threshold t, S_lo (the score at the low threshold) elsewhere, and the map of main corners
    (docs/spec.md section 5). With threshold_lo None or equal to t, S' is S_t lifted: the same NMS."""
    s_hi = fast_score(img, threshold)
    main = s_hi > 0
    if threshold_lo is None or threshold_lo >= threshold:
        return np.where(main, s_hi + MAIN_LIFT, 0), main
    return np.where(main, s_hi + MAIN_LIFT, fast_score(img, threshold_lo)), main


def detect(img: np.ndarray, threshold: int, threshold_lo: int | None = None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """NMS survivors of one scale in raster order: (x, y, score, low). `low` marks a corner at the
    low threshold only; the score is the SAD score either way."""
    comb, main = combined_score(img, threshold, threshold_lo)
    ys, xs = np.nonzero(nms3x3(comb))
    low = ~main[ys, xs]
    score = comb[ys, xs] - np.where(low, 0, MAIN_LIFT)
    return xs.astype(np.int64), ys.astype(np.int64), score.astype(np.int64), low


def in_desc_border(xs: np.ndarray, ys: np.ndarray, width: int, height: int) -> np.ndarray:
    b = DESC_BORDER
    return (xs >= b) & (xs <= width - 1 - b) & (ys >= b) & (ys <= height - 1 - b)


@dataclass(frozen=True)
class OrbLevel:
    """What orb mode computes on one scale before the sector count N matters."""

    scale: int
    xs: np.ndarray
    ys: np.ndarray
    score: np.ndarray
    smoothed: np.ndarray
    m10: np.ndarray
    m01: np.ndarray
    response: np.ndarray
    low: np.ndarray


def orb_level(img: np.ndarray, scale: int, threshold: int, threshold_lo: int | None = None) -> OrbLevel:
    """Detection, border rule, response, smoothing and moments of one scale."""
    xs, ys, score, low = detect(img, threshold, threshold_lo)
    h, w = img.shape
    keep = in_desc_border(xs, ys, w, h)
    xs, ys, score, low = xs[keep], ys[keep], score[keep], low[keep]
    response = response_map(img)[ys, xs]
    smoothed = smooth(img)
    m10, m01 = moments(smoothed, xs, ys)
    return OrbLevel(scale, xs, ys, score, smoothed, m10, m01, response, low)


def describe_level(level: OrbLevel, n: int) -> Features:
    """Sectors and descriptors of one scale's features for N sectors per quadrant."""
    sector = quantise(level.m10, level.m01, n)
    desc = describe(level.smoothed, level.xs, level.ys, sector, n)
    scale = np.full(len(level.xs), level.scale, dtype=np.int64)
    return Features(scale, level.xs, level.ys, level.score, sector, desc, 4 * n, (2, 1), level.response, level.low)


def level_threshold_lo(cfg: Config) -> int | None:
    """The low threshold a level's detection uses: only the `grid` selection reports low corners."""
    return cfg.low_threshold if cfg.selection == "grid" else None


def extract_scale(img: np.ndarray, scale: int, cfg: Config) -> Features:
    """One scale's candidates: every feature of `all` mode, low corners too in `grid` mode."""
    t_lo = level_threshold_lo(cfg)
    if cfg.mode == "orb":
        return describe_level(orb_level(img, scale, cfg.threshold, t_lo), cfg.sectors_per_quadrant)
    xs, ys, score, low = detect(img, cfg.threshold, t_lo)
    n = len(xs)
    return Features(np.full(n, scale, dtype=np.int64), xs, ys, score, np.full(n, NO_SECTOR, dtype=np.int64),
                    np.zeros((n, 0), dtype=np.uint8), cfg.sectors, (2, 1), response_map(img)[ys, xs],
                    low)  # fmt: skip


def candidates(img: np.ndarray, cfg: Config) -> Features:
    """Every level's candidates before the selection, in canonical order (scale, y, x)."""
    check_frame(img, cfg)
    parts = [extract_scale(level, s, cfg) for s, level in enumerate(pyramid(img, cfg.scales, cfg.step))]
    return Features.concat(parts, cfg.sectors, DESCRIPTOR_BYTES if cfg.mode == "orb" else 0, cfg.step).sorted()


def extract(img: np.ndarray, cfg: Config) -> Features:
    """The features of one frame, in canonical order (scale, y, x): every one in `all` selection,
    each level's budget in `grid` selection (golden_model.select)."""
    feats = candidates(img, cfg)
    if cfg.selection == "grid":
        return select_grid(feats, cfg)
    return feats


def streamed(img: np.ndarray, cfg: Config) -> Features:
    """The features the feature stream carries, which the HDMI overlay marks (docs/spec.md section
    14, "What the stream carries"): extract's in `all` selection, in `grid` also those a later
    candidate replaced in the bank (golden_model.select.streamed_grid); canonical order."""
    feats = candidates(img, cfg)
    return streamed_grid(feats, cfg) if cfg.selection == "grid" else feats
