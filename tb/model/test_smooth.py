# SPDX-License-Identifier: MIT
"""7x7 binomial smoothing, (sum k[i] k[j] I + 2048) >> 12: hand values and a naive reference."""

from __future__ import annotations

import numpy as np
import pytest

from golden_model.smooth import smooth

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")

# Impulse of 255 at the centre: s = (k[i] k[j] * 255 + 2048) >> 12, by (|dx|, |dy|), hand-computed.
IMPULSE_255 = {
    (0, 0): 25,  # 400 * 255 = 102000 / 4096 = 24.90 -> 25
    (1, 0): 19,  # 300 * 255 = 76500 / 4096 = 18.68 -> 19
    (2, 0): 7,  # 120 * 255 = 30600 / 4096 = 7.47 -> 7
    (3, 0): 1,  # 20 * 255 = 5100 / 4096 = 1.25 -> 1
    (1, 1): 14,  # 225 * 255 = 57375 / 4096 = 14.01 -> 14
    (2, 1): 6,  # 90 * 255 = 22950 / 4096 = 5.60 -> 6
    (3, 1): 1,  # 15 * 255 = 3825 / 4096 = 0.93 -> 1
    (2, 2): 2,  # 36 * 255 = 9180 / 4096 = 2.24 -> 2
    (3, 2): 0,  # 6 * 255 = 1530 / 4096 = 0.37 -> 0
    (3, 3): 0,  # 1 * 255 / 4096 = 0.06 -> 0
}


def border_of(out: np.ndarray) -> np.ndarray:
    mask = np.ones(out.shape, dtype=bool)
    mask[3:-3, 3:-3] = False
    return out[mask]


@pytest.mark.parametrize("c", [0, 1, 77, 128, 254, 255])
def test_constant_image_is_unchanged_inside_and_zero_on_the_border(c: int) -> None:
    out = smooth(np.full((12, 15), c, dtype=np.uint8))
    assert out.dtype == np.uint8 and out.shape == (12, 15)
    inner = out[3:-3, 3:-3]
    assert (inner == c).all(), f"constant {c}: first change at {np.argwhere(inner != c)[:1] + 3} (y, x)"
    assert not border_of(out).any(), f"constant {c}: non-zero border"


def test_impulse_of_255_gives_the_rounded_kernel() -> None:
    img = np.zeros((13, 13), dtype=np.uint8)
    img[6, 6] = 255
    out = smooth(img)
    for y in range(13):
        for x in range(13):
            dx, dy = abs(x - 6), abs(y - 6)
            key = (max(dx, dy), min(dx, dy))
            expected = IMPULSE_255.get(key, 0) if 3 <= x <= 9 and 3 <= y <= 9 else 0
            assert int(out[y, x]) == expected, f"impulse: (x={x}, y={y}) = {out[y, x]}, expected {expected}"


@pytest.mark.parametrize(
    ("background", "centre", "expected"),
    [
        (0, 128, 13),  # 400 * 128 / 4096 = 12.5 exactly: half rounds up
        (0, 127, 12),  # 12.40
        (0, 129, 13),  # 12.60
        (100, 228, 113),  # 100 + 400 * 128 / 4096 = 112.5 exactly -> 113
    ],
)
def test_rounding_tie_rounds_half_up(background: int, centre: int, expected: int) -> None:
    img = np.full((7, 7), background, dtype=np.uint8)
    img[3, 3] = centre
    out = smooth(img)
    assert int(out[3, 3]) == expected, f"centre (x=3, y=3) = {out[3, 3]}, expected {expected}"
    assert np.count_nonzero(out) == int(expected > 0), "a 7x7 image has exactly one defined pixel"


@pytest.mark.parametrize(("w", "h"), [(6, 6), (6, 20), (20, 6), (0, 0)])
def test_images_without_interior_are_all_zero(w: int, h: int) -> None:
    out = smooth(np.full((h, w), 200, dtype=np.uint8))
    assert out.shape == (h, w) and not out.any()


@pytest.mark.parametrize(("seed", "lo", "hi"), [(0, 0, 256), (1, 250, 256), (2, 0, 3), (3, 0, 2)])
def test_random_images_against_naive_reference(ref, seed: int, lo: int, hi: int) -> None:
    img = np.random.default_rng(seed).integers(lo, hi, (21, 26), dtype=np.uint8)
    got = smooth(img)
    expected = ref.smooth(img)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"smooth seed={seed}")
    assert not border_of(got).any()


@pytest.mark.parametrize("name", PHOTOS)
def test_photograph_crop_against_naive_reference(ref, photographs, name: str) -> None:
    img = ref.center_crop(photographs[name], 40, 40)
    got = smooth(img)
    expected = ref.smooth(img)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"{name} crop smooth")
