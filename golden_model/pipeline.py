# SPDX-License-Identifier: MIT
"""The whole accelerator, frame in, features out: the executable specification.

Per scale (scale 0 is the input, scale s+1 the pyramid step of scale s: the 2:1 box average, or for
any other num:den the fixed-phase bilinear resample of golden_model.scaler):
FAST-9 score map -> 3x3 NMS -> border rule -> (orb mode) smoothing, moments, sector, rBRIEF.

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
from .scaler import pyramid
from .smooth import RADIUS as SMOOTH_RADIUS
from .smooth import smooth

DESC_BORDER = PATCH_RADIUS + SMOOTH_RADIUS  # 18


def check_frame(img: np.ndarray, cfg: Config) -> None:
    if img.ndim != 2 or img.dtype != np.uint8:
        raise ValueError(f"expected a 2-D uint8 luma frame, got {img.dtype} with shape {img.shape}")
    if img.shape != (cfg.height, cfg.width):
        raise ValueError(f"frame is {img.shape[1]}x{img.shape[0]}, configuration is {cfg.width}x{cfg.height}")


def detect(img: np.ndarray, threshold: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """NMS survivors of one scale in raster order: (x, y, score)."""
    score = fast_score(img, threshold)
    ys, xs = np.nonzero(nms3x3(score))
    return xs.astype(np.int64), ys.astype(np.int64), score[ys, xs].astype(np.int64)


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


def orb_level(img: np.ndarray, scale: int, threshold: int) -> OrbLevel:
    """Detection, border rule, smoothing and moments of one scale."""
    xs, ys, score = detect(img, threshold)
    h, w = img.shape
    keep = in_desc_border(xs, ys, w, h)
    xs, ys, score = xs[keep], ys[keep], score[keep]
    smoothed = smooth(img)
    m10, m01 = moments(smoothed, xs, ys)
    return OrbLevel(scale, xs, ys, score, smoothed, m10, m01)


def describe_level(level: OrbLevel, n: int) -> Features:
    """Sectors and descriptors of one scale's features for N sectors per quadrant."""
    sector = quantise(level.m10, level.m01, n)
    desc = describe(level.smoothed, level.xs, level.ys, sector, n)
    scale = np.full(len(level.xs), level.scale, dtype=np.int64)
    return Features(scale, level.xs, level.ys, level.score, sector, desc, 4 * n)


def extract_scale(img: np.ndarray, scale: int, cfg: Config) -> Features:
    if cfg.mode == "orb":
        return describe_level(orb_level(img, scale, cfg.threshold), cfg.sectors_per_quadrant)
    xs, ys, score = detect(img, cfg.threshold)
    n = len(xs)
    return Features(np.full(n, scale, dtype=np.int64), xs, ys, score, np.full(n, NO_SECTOR, dtype=np.int64),
                    np.zeros((n, 0), dtype=np.uint8), cfg.sectors)  # fmt: skip


def extract(img: np.ndarray, cfg: Config) -> Features:
    """All features of one frame, in canonical order (scale, y, x)."""
    check_frame(img, cfg)
    parts = [extract_scale(level, s, cfg) for s, level in enumerate(pyramid(img, cfg.scales, cfg.step))]
    return Features.concat(parts, cfg.sectors, DESCRIPTOR_BYTES if cfg.mode == "orb" else 0, cfg.step).sorted()
