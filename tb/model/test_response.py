# SPDX-License-Identifier: MIT
"""golden_model.response: the corner response (spec section 15) against a pixel-by-pixel reference
written from the spec, the code's boundaries, and the ranges the hardware's widths rely on."""

from __future__ import annotations

import numpy as np
import pytest

from golden_model import response


def naive_r(img: np.ndarray, x: int, y: int) -> int:
    """R at (x, y) in plain Python integers, straight from docs/spec.md section 15."""
    p = [[int(v) for v in row] for row in img]

    def ix(u: int, v: int) -> int:
        return (
            2 * (p[v][u + 1] - p[v][u - 1]) + p[v - 1][u + 1] - p[v - 1][u - 1] + p[v + 1][u + 1] - p[v + 1][u - 1]
        ) >> 3

    def iy(u: int, v: int) -> int:
        return (
            2 * (p[v + 1][u] - p[v - 1][u]) + p[v + 1][u - 1] - p[v - 1][u - 1] + p[v + 1][u + 1] - p[v - 1][u + 1]
        ) >> 3

    a = b = c = 0
    for v in range(y - 2, y + 3):
        for u in range(x - 2, x + 3):
            gx, gy = ix(u, v), iy(u, v)
            a, b, c = a + gx * gx, b + gy * gy, c + gx * gy
    a, b, c = a >> 3, b >> 3, c >> 3
    return a * b - c * c - (((a + b) * (a + b)) >> 5)


def naive_code(r: int) -> int:
    if r < 2:
        return 0
    e = r.bit_length() - 1
    return 2 * e + ((r >> (e - 1)) & 1)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_response_map_equals_the_reference(seed: int, photographs) -> None:
    rng = np.random.default_rng(seed)
    img = (
        rng.integers(0, 256, (14, 17), dtype=np.uint8)
        if seed == 0
        else photographs["camera"][100 + 20 * seed :][:16, :20]
    )
    r = response.harris(img)
    codes = response.response_map(img)
    h, w = img.shape
    for y in range(h):
        for x in range(w):
            if 3 <= x <= w - 4 and 3 <= y <= h - 4:
                assert r[y, x] == naive_r(img, x, y), (x, y)
                assert codes[y, x] == naive_code(naive_r(img, x, y)), (x, y)
            else:
                assert r[y, x] == 0 and codes[y, x] == 0, (x, y)


def test_code_boundaries_and_monotonicity() -> None:
    values = np.array([-(2**34), -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 2**31 - 1, 2**31, 3 * 2**30, 2**32 - 1])
    assert response.code(values).tolist() == [naive_code(int(v)) for v in values]
    assert response.code(np.array([2**32 - 1]))[0] == response.MAX_CODE == 63
    r = np.arange(0, 1 << 20)
    c = response.code(r)
    assert (np.diff(c) >= 0).all() and c.max() < 1 << response.RESPONSE_BITS


def test_extreme_patterns_stay_inside_the_widths() -> None:
    """The hardware's widths: -128 <= Ix, Iy <= 127, a, b <= 51200, R < 2^32 on the most extreme 8-bit
    patterns (a step edge of full contrast, a checkerboard, a corner)."""
    yy, xx = np.mgrid[0:16, 0:16]
    for img in ((xx >= 8) * 255, ((xx + yy) % 2) * 255, ((xx >= 8) & (yy >= 8)) * 255, ((xx // 2 + yy // 2) % 2) * 255):
        img = img.astype(np.uint8)
        ix, iy = response.gradients(img)
        assert -128 <= min(ix.min(), iy.min()) and max(ix.max(), iy.max()) <= 127
        assert response.harris(img).max() < 2**32
