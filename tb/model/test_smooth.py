# SPDX-License-Identifier: MIT
"""7x7 smoothing, k = (5 8 12 14 12 8 5), (sum k[i] k[j] I + 2048) >> 12: hand values and a naive reference."""

from __future__ import annotations

import numpy as np
import pytest

from golden_model.smooth import smooth

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")

# Impulse of 255 at the centre: s = (k[i] k[j] * 255 + 2048) >> 12, by (|dx|, |dy|), hand-computed.
IMPULSE_255 = {
    (0, 0): 12,  # 196 * 255 = 49980 / 4096 = 12.20 -> 12
    (1, 0): 10,  # 168 * 255 = 42840 / 4096 = 10.46 -> 10
    (2, 0): 7,  # 112 * 255 = 28560 / 4096 = 6.97 -> 7
    (3, 0): 4,  # 70 * 255 = 17850 / 4096 = 4.36 -> 4
    (1, 1): 9,  # 144 * 255 = 36720 / 4096 = 8.96 -> 9
    (2, 1): 6,  # 96 * 255 = 24480 / 4096 = 5.98 -> 6
    (3, 1): 4,  # 60 * 255 = 15300 / 4096 = 3.74 -> 4
    (2, 2): 4,  # 64 * 255 = 16320 / 4096 = 3.98 -> 4
    (3, 2): 2,  # 40 * 255 = 10200 / 4096 = 2.49 -> 2
    (3, 3): 2,  # 25 * 255 = 6375 / 4096 = 1.56 -> 2
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
    ("background", "value", "expected"),
    [
        (0, 32, 1),  # weight 8 * 8 = 64 at (x=1, y=1): 64 * 32 / 4096 = 0.5 exactly: half rounds up
        (0, 31, 0),  # 0.48
        (0, 33, 1),  # 0.52
        (0, 96, 2),  # 1.5 exactly -> 2
        (100, 132, 101),  # 100 + 64 * 32 / 4096 = 100.5 exactly -> 101
    ],
)
def test_rounding_tie_rounds_half_up(background: int, value: int, expected: int) -> None:
    img = np.full((7, 7), background, dtype=np.uint8)
    img[1, 1] = value
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
