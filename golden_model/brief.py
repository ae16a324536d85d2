# SPDX-License-Identifier: MIT
"""rBRIEF descriptors: 256 binary tests on the smoothed image with the sector's rotated pattern.

Test i is 1 when smoothed(p1_i) < smoothed(p2_i). Byte j of the 32-byte descriptor holds tests
8j..8j+7, test 8j+k in bit k (value 1 << k), as OpenCV orders ORB descriptors, so
cv2.BFMatcher(cv2.NORM_HAMMING) matches them.
"""

from __future__ import annotations

import numpy as np

from .pattern import rotated_patterns

DESCRIPTOR_BYTES = 32


def describe(smoothed: np.ndarray, xs: np.ndarray, ys: np.ndarray, sectors: np.ndarray, n: int) -> np.ndarray:
    """(K, 32) uint8 descriptors of the features at (xs, ys) with the given sectors."""
    pats = rotated_patterns(n)[sectors].astype(np.int64)  # (K, 256, 4)
    p1 = smoothed[ys[:, None] + pats[..., 1], xs[:, None] + pats[..., 0]]
    p2 = smoothed[ys[:, None] + pats[..., 3], xs[:, None] + pats[..., 2]]
    bits = (p1 < p2).reshape(len(xs), DESCRIPTOR_BYTES, 8)
    return np.packbits(bits, axis=2, bitorder="little").reshape(len(xs), DESCRIPTOR_BYTES)
