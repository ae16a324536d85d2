# SPDX-License-Identifier: MIT
"""Image scalers of the pyramid.

2:1 (the hardware's orb_scaler, `downscale`): scale s+1 has size (W >> 1, H >> 1) of scale s;
pixel (x, y) is (I(2x, 2y) + I(2x+1, 2y) + I(2x, 2y+1) + I(2x+1, 2y+1) + 2) >> 2. An odd last
column or row of the larger scale is not used.

A rational step num:den (`resample`, num > den, e.g. 5:4; docs/spec.md "Pyramid step"): output
pixel (x, y) is the bilinear sample of the input at the centre-aligned position
((x + 0.5) * num / den - 0.5, (y + 0.5) * num / den - 0.5). With D = 2 * den and
P = (2x + 1) * num - den, the left tap is i = P // D and its weight D - a, the right tap i + 1
with weight a = P mod D (the same in y); the output is the weighted sum of the 2x2 taps, rounded
half up once: (S + D*D/2) // (D*D). The phases repeat every den outputs (fixed-phase streaming
resampling). The output is floor(W * den / num) x floor(H * den / num). For 2:1 the rule is the
2x2 box above, bit for bit. A level-k pixel (x, y) is centred at ((x + 0.5) * r^k - 0.5, ...) in
full-resolution pixels, r = num / den.
"""

from __future__ import annotations

import numpy as np


def downscale(img: np.ndarray) -> np.ndarray:
    h, w = img.shape
    h2, w2 = h >> 1, w >> 1
    v = img[: 2 * h2, : 2 * w2].astype(np.uint16)
    total = v[0::2, 0::2] + v[0::2, 1::2] + v[1::2, 0::2] + v[1::2, 1::2]
    return ((total + 2) >> 2).astype(np.uint8)


def _taps(n_out: int, num: int, den: int, n_in: int) -> tuple[np.ndarray, np.ndarray]:
    """Left-tap index and right-tap weight (in units of 1 / (2 den)) of each output position."""
    p = (2 * np.arange(n_out, dtype=np.int64) + 1) * num - den
    i, a = p // (2 * den), p % (2 * den)
    if n_out and (i.min() < 0 or (i + (a > 0)).max() > n_in - 1):
        raise ValueError(f"a {num}:{den} step leaves the {n_in}-pixel input")
    return i, a


def resample(img: np.ndarray, num: int, den: int) -> np.ndarray:
    """The next pyramid level for a num:den step (module docstring); num > den >= 1."""
    if not (isinstance(num, int) and isinstance(den, int) and num > den >= 1):
        raise ValueError(f"a pyramid step num:den needs integers num > den >= 1, got {num}:{den}")
    h, w = img.shape
    ho, wo = h * den // num, w * den // num
    d = 2 * den
    iy, ay = _taps(ho, num, den, h)
    ix, ax = _taps(wo, num, den, w)
    v = img.astype(np.int64)
    iy1, ix1 = np.minimum(iy + 1, h - 1), np.minimum(ix + 1, w - 1)  # a weight-0 tap may point past the edge
    rows0 = (d - ay)[:, None] * v[iy] + ay[:, None] * v[iy1]  # (ho, w): vertical pass, no rounding
    s = (d - ax)[None, :] * rows0[:, ix] + ax[None, :] * rows0[:, ix1]
    return ((s + d * d // 2) // (d * d)).astype(np.uint8)


def pyramid(img: np.ndarray, scales: int, step: tuple[int, int] = (2, 1)) -> list[np.ndarray]:
    """`scales` levels, each the `step` (num, den) reduction of the one before; (2, 1) is the 2:1
    box of `downscale`."""
    levels = [img]
    for _ in range(scales - 1):
        levels.append(downscale(levels[-1]) if step == (2, 1) else resample(levels[-1], *step))
    return levels
