# SPDX-License-Identifier: MIT
"""FAST-9 segment test on the 16-pixel Bresenham circle of radius 3, and the SAD corner score.

A pixel c at (x, y) with 3 <= x <= W-4 and 3 <= y <= H-4 is a corner when at least 9 contiguous
circle pixels p (cyclically) are all brighter (p > c + t) or all darker (p < c - t). Its score is
the sum of |p - c| over all 16 circle pixels (0..4080, 12 bits). Pixels that are not corners,
including the 3-pixel border, have score 0; every corner scores at least 9.
"""

from __future__ import annotations

import numpy as np

# (dx, dy) of the 16 circle pixels, clockwise on screen (y grows downwards), starting straight up.
# Bit i of the brighter/darker masks belongs to CIRCLE[i].
CIRCLE: tuple[tuple[int, int], ...] = (
    (0, -3), (1, -3), (2, -2), (3, -1), (3, 0), (3, 1), (2, 2), (1, 3),
    (0, 3), (-1, 3), (-2, 2), (-3, 1), (-3, 0), (-3, -1), (-2, -2), (-1, -3),
)  # fmt: skip
ARC = 9
BORDER = 3


def _arc_table() -> np.ndarray:
    """Boolean table over all 16-bit masks: True when the mask holds ARC cyclically contiguous ones."""
    masks = np.arange(1 << 16, dtype=np.uint32)
    doubled = masks | (masks << 16)
    run = (1 << ARC) - 1
    hit = np.zeros(1 << 16, dtype=bool)
    for start in range(16):
        hit |= ((doubled >> start) & run) == run
    return hit


ARC_TABLE = _arc_table()


def has_arc(mask: int) -> bool:
    """True when the 16-bit mask holds 9 cyclically contiguous ones."""
    return bool(ARC_TABLE[mask & 0xFFFF])


def circle_masks(img: np.ndarray, threshold: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Brighter mask, darker mask and SAD score for every interior pixel.

    Returns three arrays of shape (H-6, W-6) for the pixels 3..W-4, 3..H-4.
    """
    h, w = img.shape
    v = img.astype(np.int16)
    c = v[BORDER : h - BORDER, BORDER : w - BORDER]
    bright = np.zeros(c.shape, dtype=np.uint16)
    dark = np.zeros(c.shape, dtype=np.uint16)
    sad = np.zeros(c.shape, dtype=np.int32)
    for bit, (dx, dy) in enumerate(CIRCLE):
        p = v[BORDER + dy : h - BORDER + dy, BORDER + dx : w - BORDER + dx]
        d = p - c
        bright |= (d > threshold).astype(np.uint16) << bit
        dark |= (d < -threshold).astype(np.uint16) << bit
        sad += np.abs(d)
    return bright, dark, sad


def fast_score(img: np.ndarray, threshold: int) -> np.ndarray:
    """(H, W) int32 map: the SAD score where the segment test passes, 0 elsewhere (border included)."""
    if img.ndim != 2 or img.dtype != np.uint8:
        raise ValueError("fast_score expects a 2-D uint8 image")
    h, w = img.shape
    out = np.zeros((h, w), dtype=np.int32)
    if h < 2 * BORDER + 1 or w < 2 * BORDER + 1:
        return out
    bright, dark, sad = circle_masks(img, threshold)
    corner = ARC_TABLE[bright] | ARC_TABLE[dark]
    out[BORDER : h - BORDER, BORDER : w - BORDER] = np.where(corner, sad, 0)
    return out
