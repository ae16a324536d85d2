# SPDX-License-Identifier: MIT
"""OpenCV's own FAST / ORB with settings matching an accelerator configuration, for comparison.

The result is a :class:`Features` list like the model's, so the CLI, the CSV and the evaluation
treat both backends alike. The score column is always *our* SAD score (sum of |p - c| over the 16
circle pixels) computed at the reported position, so scores compare across backends; OpenCV's own
FAST response (the largest threshold that still passes the segment test) is not reported.
"""

from __future__ import annotations

import cv2
import numpy as np

from golden_model.brief import DESCRIPTOR_BYTES
from golden_model.config import Config
from golden_model.fast import BORDER, CIRCLE
from golden_model.features import NO_SECTOR, Features
from golden_model.scaler import pyramid

ORB_EDGE_THRESHOLD = 31
ORB_PATCH_SIZE = 31


def sad_score_at(img: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """Our SAD score (sum of |p - c| over the 16 circle pixels) at (xs, ys), corner or not.

    Positions closer than 3 pixels to the border (where the circle leaves the image) score 0.
    """
    h, w = img.shape
    xs = np.asarray(xs, dtype=np.int64)
    ys = np.asarray(ys, dtype=np.int64)
    inside = (xs >= BORDER) & (xs <= w - 1 - BORDER) & (ys >= BORDER) & (ys <= h - 1 - BORDER)
    cx, cy = np.where(inside, xs, BORDER), np.where(inside, ys, BORDER)
    d = np.array(CIRCLE, dtype=np.int64)  # (16, 2)
    v = img.astype(np.int64)
    ring = v[cy[:, None] + d[None, :, 1], cx[:, None] + d[None, :, 0]]  # (K, 16)
    sad = np.abs(ring - v[cy, cx][:, None]).sum(axis=1)
    return np.where(inside, sad, 0).astype(np.int64)


def fast_keypoints(img: np.ndarray, threshold: int, nonmax: bool) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) int64 arrays of OpenCV's FAST-9/16 corners (``nonmax`` selects its 3x3 suppression)."""
    det = cv2.FastFeatureDetector_create(threshold, nonmax, cv2.FastFeatureDetector_TYPE_9_16)
    pts = np.array([kp.pt for kp in det.detect(img, None)], dtype=np.float64).reshape(-1, 2)
    return np.rint(pts[:, 0]).astype(np.int64), np.rint(pts[:, 1]).astype(np.int64)


def _extract_fast(img: np.ndarray, cfg: Config) -> Features:
    parts = []
    for s, level in enumerate(pyramid(img, cfg.scales, cfg.step)):
        xs, ys = fast_keypoints(level, cfg.threshold, nonmax=True)
        n = len(xs)
        parts.append(
            Features(
                np.full(n, s, dtype=np.int64), xs, ys, sad_score_at(level, xs, ys),
                np.full(n, NO_SECTOR, dtype=np.int64), np.zeros((n, 0), dtype=np.uint8), cfg.sectors,
            )
        )  # fmt: skip
    return Features.concat(parts, cfg.sectors, 0, cfg.step)


def orb_detector(cfg: Config) -> cv2.ORB:
    """OpenCV ORB with the accelerator's pyramid (step num/den, ``cfg.scales`` levels) and FAST threshold."""
    return cv2.ORB_create(
        nfeatures=1_000_000, scaleFactor=cfg.factor, nlevels=cfg.scales, edgeThreshold=ORB_EDGE_THRESHOLD,
        firstLevel=0, WTA_K=2, scoreType=cv2.ORB_FAST_SCORE, patchSize=ORB_PATCH_SIZE,
        fastThreshold=cfg.threshold,
    )  # fmt: skip


def angle_to_sector(angle_deg: np.ndarray, sectors: int) -> np.ndarray:
    """Nearest of ``sectors`` centred sectors: round(angle / (360 / sectors)) mod sectors."""
    return (np.rint(np.asarray(angle_deg, dtype=np.float64) * sectors / 360.0).astype(np.int64)) % sectors


def _extract_orb(img: np.ndarray, cfg: Config, nfeatures: int | None = None) -> Features:
    if nfeatures is None:
        detector = orb_detector(cfg)
    else:  # OpenCV's own selection (Harris ranking, its retain-best) at this count
        detector = cv2.ORB_create(nfeatures=max(1, nfeatures), scaleFactor=cfg.factor, nlevels=cfg.scales,
                                  edgeThreshold=ORB_EDGE_THRESHOLD, patchSize=ORB_PATCH_SIZE,
                                  fastThreshold=cfg.threshold)  # fmt: skip
    kps, desc = detector.detectAndCompute(img, None)
    n = len(kps)
    octave = np.array([kp.octave for kp in kps], dtype=np.int64)
    pt = np.array([kp.pt for kp in kps], dtype=np.float64).reshape(n, 2)
    angle = np.array([kp.angle for kp in kps], dtype=np.float64)
    # OpenCV detects at integer level coordinates and reports pt = level_xy * r^octave. Inverting
    # the pixel-centre convention of Features.full_res, round((pt + 0.5) / r^octave - 0.5), gives
    # back exactly level_xy for that convention too (the offset is below half a pixel), so it is
    # robust to either convention.
    f = cfg.factor ** octave.astype(np.float64)
    xs = np.rint((pt[:, 0] + 0.5) / f - 0.5).astype(np.int64)
    ys = np.rint((pt[:, 1] + 0.5) / f - 0.5).astype(np.int64)
    levels = pyramid(img, cfg.scales, cfg.step)
    score = np.zeros(n, dtype=np.int64)
    for s, level in enumerate(levels):
        at = octave == s
        score[at] = sad_score_at(level, xs[at], ys[at])
    descriptor = desc if desc is not None else np.zeros((0, DESCRIPTOR_BYTES), dtype=np.uint8)
    return Features(octave, xs, ys, score, angle_to_sector(angle, cfg.sectors), descriptor, cfg.sectors, cfg.step)


def extract_opencv(img: np.ndarray, cfg: Config) -> Features:
    """OpenCV's features of one luma frame, in canonical order, with the configuration's settings.

    ``fast`` mode: ``cv2.FastFeatureDetector`` (FAST-9/16, its own 3x3 non-maximum suppression,
    threshold ``cfg.threshold``) on each level of *our* pyramid (``golden_model.scaler``), so
    that a comparison with the model isolates the detector from the scaler. Sector -1, no descriptor.

    ``orb`` mode: ``cv2.ORB`` with scale factor num/den, ``cfg.scales`` levels (OpenCV's own pyramid,
    bilinear resize), edge threshold 31, patch 31, FAST score, threshold ``cfg.threshold`` and no
    feature limit. Positions are converted from OpenCV's full-resolution ``pt`` to that octave's
    pixel coordinates; the sector is OpenCV's float angle rounded to the nearest of ``cfg.sectors``
    centred sectors; the descriptor is OpenCV's 32 bytes (same bit order as the model's).

    In both modes the score is our SAD score at the position, in our pyramid's level image (for ORB
    above scale 0 only informative, since OpenCV's pyramid differs).
    """
    if img.ndim != 2 or img.dtype != np.uint8:
        raise ValueError(f"expected a 2-D uint8 luma frame, got {img.dtype} with shape {img.shape}")
    feats = _extract_fast(img, cfg) if cfg.mode == "fast" else _extract_orb(img, cfg)
    return feats.sorted()


def extract_opencv_selected(img: np.ndarray, cfg: Config, nfeatures: int) -> Features:
    """OpenCV ORB's features with its own selection at ``nfeatures`` (its default Harris ranking and
    per-level quotas; pyramid and threshold of ``cfg``), as ``extract_opencv``'s orb mode otherwise."""
    return _extract_orb(img, cfg, nfeatures).sorted()
