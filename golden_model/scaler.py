# SPDX-License-Identifier: MIT
"""2:1 image scaler: 2x2 box average with rounding half up.

Scale s+1 has size (W >> 1, H >> 1) of scale s; pixel (x, y) is
(I(2x, 2y) + I(2x+1, 2y) + I(2x, 2y+1) + I(2x+1, 2y+1) + 2) >> 2. An odd last column or row of
the larger scale is not used.
"""

from __future__ import annotations

import numpy as np


def downscale(img: np.ndarray) -> np.ndarray:
    h, w = img.shape
    h2, w2 = h >> 1, w >> 1
    v = img[: 2 * h2, : 2 * w2].astype(np.uint16)
    total = v[0::2, 0::2] + v[0::2, 1::2] + v[1::2, 0::2] + v[1::2, 1::2]
    return ((total + 2) >> 2).astype(np.uint8)


def pyramid(img: np.ndarray, scales: int) -> list[np.ndarray]:
    levels = [img]
    for _ in range(scales - 1):
        levels.append(downscale(levels[-1]))
    return levels
