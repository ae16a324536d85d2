# SPDX-License-Identifier: MIT
"""The corner response: an integer Harris measure of every pixel, coded as a small number that ranks
features (docs/spec.md section 15).

On a level's own pixels P (not smoothed), for 3 <= x <= W-4, 3 <= y <= H-4 (FAST's interior):

    Ix(u, v) = (2 (P(u+1, v) - P(u-1, v)) + P(u+1, v-1) - P(u-1, v-1) + P(u+1, v+1) - P(u-1, v+1)) >> 3
    Iy(u, v) = (2 (P(u, v+1) - P(u, v-1)) + P(u-1, v+1) - P(u-1, v-1) + P(u+1, v+1) - P(u+1, v-1)) >> 3
    a = (sum Ix^2) >> 3,  b = (sum Iy^2) >> 3,  c = (sum Ix Iy) >> 3     over the 5x5 block around (x, y)
    R = a b - c^2 - ((a + b)^2 >> 5)

(`>>` is the arithmetic shift, a floor; Ix, Iy lie in -128..127, a and b in 0..51200, so a b < 2^32.)
The response code of R is 0 when R < 2^B; otherwise, with e = floor(log2 R) (B <= e <= 31) and m the
B bits that follow R's leading one, it is 2^B (e - B + 1) + m: a floating-point number with
MANTISSA_BITS = B mantissa bits, monotone in R, RESPONSE_BITS bits wide. Elsewhere the code is 0.
"""

from __future__ import annotations

import numpy as np

GRAD_SHIFT = 3  # gradients >> 3: -128..127 (8 bits: two products in one DSP48)
BLOCK = 5  # the box of the sums
SUM_SHIFT = 3  # a, b, c >> 3: a, b <= 51200, so a b < 2^32
K_SHIFT = 5  # k = 1 / 32
MANTISSA_BITS = 1
RESPONSE_BITS = 6  # codes 0 .. 2^B (32 - B) + 2^B - 1 = 63 for B = 1
MAX_CODE = (1 << MANTISSA_BITS) * (32 - MANTISSA_BITS) + (1 << MANTISSA_BITS) - 1
BORDER = 3


def gradients(img: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(Ix, Iy) int64 maps, the scaled Sobel derivatives; 0 in the outermost rows and columns."""
    v = img.astype(np.int64)
    ix = np.zeros_like(v)
    iy = np.zeros_like(v)
    ix[1:-1, 1:-1] = (
        2 * (v[1:-1, 2:] - v[1:-1, :-2]) + (v[:-2, 2:] - v[:-2, :-2]) + (v[2:, 2:] - v[2:, :-2])
    ) >> GRAD_SHIFT
    iy[1:-1, 1:-1] = (
        2 * (v[2:, 1:-1] - v[:-2, 1:-1]) + (v[2:, :-2] - v[:-2, :-2]) + (v[2:, 2:] - v[:-2, 2:])
    ) >> GRAD_SHIFT
    return ix, iy


def _box(a: np.ndarray) -> np.ndarray:
    """Sum over the BLOCK x BLOCK box around each pixel of FAST's interior (0 elsewhere)."""
    h, w = a.shape
    r = BLOCK // 2
    c = np.pad(a, ((1, 0), (1, 0))).cumsum(0).cumsum(1)
    out = np.zeros_like(a)
    s = c[BLOCK:, BLOCK:] - c[:-BLOCK, BLOCK:] - c[BLOCK:, :-BLOCK] + c[:-BLOCK, :-BLOCK]  # centres r .. h-1-r
    out[r : h - r, r : w - r] = s
    return out


def harris(img: np.ndarray) -> np.ndarray:
    """R of the module docstring for every pixel (int64); 0 outside FAST's interior."""
    if img.ndim != 2 or img.dtype != np.uint8:
        raise ValueError("harris expects a 2-D uint8 image")
    h, w = img.shape
    out = np.zeros((h, w), dtype=np.int64)
    if h < 2 * BORDER + 1 or w < 2 * BORDER + 1:
        return out
    ix, iy = gradients(img)
    a = _box(ix * ix) >> SUM_SHIFT
    b = _box(iy * iy) >> SUM_SHIFT
    c = _box(ix * iy) >> SUM_SHIFT
    r = a * b - c * c - (((a + b) * (a + b)) >> K_SHIFT)
    inner = np.zeros((h, w), dtype=bool)
    inner[BORDER : h - BORDER, BORDER : w - BORDER] = True
    return np.where(inner, r, 0)


def code(r: np.ndarray) -> np.ndarray:
    """The response code of R (module docstring), int64."""
    r = np.asarray(r, dtype=np.int64)
    bits = MANTISSA_BITS
    pos = np.maximum(r, 1)
    e = np.floor(np.log2(pos.astype(np.float64))).astype(np.int64)
    # exact floor(log2) for integers below 2^53: correct the float estimate by one either way
    e = np.where((np.int64(1) << e) > pos, e - 1, e)
    e = np.where((np.int64(1) << np.minimum(e + 1, 62)) <= pos, e + 1, e)
    m = (pos >> np.maximum(e - bits, 0)) & ((1 << bits) - 1)
    return np.where(r >= (1 << bits), (1 << bits) * (e - bits + 1) + m, 0)


def response_map(img: np.ndarray) -> np.ndarray:
    """The response code of every pixel of a level (int64; 0 outside FAST's interior)."""
    return code(harris(img))
