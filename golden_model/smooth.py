# SPDX-License-Identifier: MIT
"""7x7 smoothing: kernel (5 8 12 14 12 8 5) outer itself, divided by 4096 (spec section 7).

The kernel is an integer approximation of OpenCV ORB's 7x7 Gaussian blur (sigma 2; ours has
sigma 1.67) with the row sum 64 of the thesis's binomial (1 6 15 20 15 6 1), so the division
stays a shift by 12; it replaced the binomial in issue 14 (docs/evaluation.md: +1 point on the
scale benchmark).

s(x, y) = (sum_{i,j} k[i] k[j] I(x+i-3, y+j-3) + 2048) >> 12, i.e. rounded half up, for
3 <= x <= W-4 and 3 <= y <= H-4. The sum is exact (at most 255 * 4096); the separable order of
evaluation does not change it. Pixels nearer the border than 3 are not defined; the model stores
0 there and no feature's descriptor or orientation ever reads them (the descriptor border is 18).
"""

from __future__ import annotations

import numpy as np

KERNEL = (5, 8, 12, 14, 12, 8, 5)
RADIUS = 3
SHIFT = 12


def smooth(img: np.ndarray) -> np.ndarray:
    """(H, W) uint8 smoothed image, 0 on the 3-pixel border."""
    h, w = img.shape
    out = np.zeros((h, w), dtype=np.uint8)
    if h < 2 * RADIUS + 1 or w < 2 * RADIUS + 1:
        return out
    v = img.astype(np.int32)
    rows = sum(k * v[:, i : w - 2 * RADIUS + i] for i, k in enumerate(KERNEL))
    full = sum(k * rows[j : h - 2 * RADIUS + j, :] for j, k in enumerate(KERNEL))
    out[RADIUS : h - RADIUS, RADIUS : w - RADIUS] = (full + (1 << (SHIFT - 1))) >> SHIFT
    return out
