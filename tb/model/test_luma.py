# SPDX-License-Identifier: MIT
"""RGB-to-luma conversion: Y = (77 R + 150 G + 29 B + 128) >> 8, and the image loader's to_luma."""

from __future__ import annotations

import numpy as np
import pytest

from golden_model.images import ImageError, to_luma
from golden_model.luma import rgb_to_luma


def _one(r: int, g: int, b: int) -> int:
    return int(rgb_to_luma(np.array([[[r, g, b]]], dtype=np.uint8))[0, 0])


@pytest.mark.parametrize(
    ("rgb", "expected"),
    [
        ((0, 0, 0), 0),
        ((255, 255, 255), 255),  # (256 * 255 + 128) >> 8 = 255: weights sum to 256
        ((255, 0, 0), 77),  # 19635 / 256 = 76.70 -> 77
        ((0, 255, 0), 149),  # 38250 / 256 = 149.41 -> 149
        ((0, 0, 255), 29),  # 7395 / 256 = 28.89 -> 29
        ((1, 1, 1), 1),
        ((1, 0, 0), 0),  # 0.30 -> 0
        ((0, 1, 0), 1),  # 0.59 -> 1
        ((0, 0, 1), 0),  # 0.11 -> 0
        ((0, 0, 128), 15),  # 3712 / 256 = 14.5 exactly: rounds half up to 15
        ((0, 0, 127), 14),  # 3683 / 256 = 14.39 -> 14
        ((128, 0, 0), 39),  # 9856 / 256 = 38.5 exactly: rounds half up to 39
        ((0, 128, 0), 75),  # 19200 / 256 = 75 exactly
        ((128, 128, 128), 128),
        ((255, 255, 254), 255),  # 65251 / 256 = 254.89 -> 255
        ((200, 100, 50), 124),  # 15400 + 15000 + 1450 = 31850 / 256 = 124.41 -> 124
    ],
)
def test_luma_hand_values(rgb: tuple[int, int, int], expected: int) -> None:
    assert _one(*rgb) == expected, f"luma{rgb} = {_one(*rgb)}, expected {expected}"


def test_luma_random_image_against_naive_formula(ref) -> None:
    rng = np.random.default_rng(1)
    rgb = rng.integers(0, 256, (37, 53, 3), dtype=np.uint8)
    got = rgb_to_luma(rgb)
    assert got.shape == (37, 53) and got.dtype == np.uint8
    expected = np.array(
        [[ref.luma(*(int(c) for c in rgb[y, x])) for x in range(53)] for y in range(37)], dtype=np.int64
    )
    assert np.array_equal(got, expected), ref.mismatch(got, expected, "luma")


def test_luma_is_within_one_of_bt601() -> None:
    rng = np.random.default_rng(2)
    rgb = rng.integers(0, 256, (64, 64, 3), dtype=np.uint8)
    exact = rgb.astype(np.float64) @ np.array([0.299, 0.587, 0.114])
    err = np.abs(rgb_to_luma(rgb).astype(np.float64) - exact)
    y, x = np.unravel_index(int(np.argmax(err)), err.shape)
    assert err.max() < 1.0, f"luma off BT.601 by {err.max():.3f} at (x={x}, y={y})"


@pytest.mark.parametrize("shape", [(4, 4), (4, 4, 4), (4, 4, 1), (4,)])
def test_luma_rejects_non_rgb_shapes(shape: tuple[int, ...]) -> None:
    with pytest.raises(ValueError, match="RGB"):
        rgb_to_luma(np.zeros(shape, dtype=np.uint8))


def test_to_luma_keeps_grey_and_converts_colour() -> None:
    rng = np.random.default_rng(3)
    grey = rng.integers(0, 256, (5, 6), dtype=np.uint8)
    assert np.array_equal(to_luma(grey), grey), "8-bit grey must pass through unchanged"
    grey16 = grey.astype(np.uint16) * 257 + 3  # high byte is the 8-bit value
    assert np.array_equal(to_luma(grey16), grey), "16-bit grey must be scaled by >> 8"
    rgba = np.zeros((1, 3, 4), dtype=np.uint8)
    rgba[0, :, :3] = [(255, 0, 0), (0, 255, 0), (0, 0, 128)]
    rgba[0, :, 3] = (0, 77, 255)  # alpha is ignored
    assert to_luma(rgba).tolist() == [[77, 149, 15]]


@pytest.mark.parametrize(
    "img", [np.zeros((4, 4), dtype=np.float32), np.zeros((4, 4, 2), dtype=np.uint8), np.zeros(4, dtype=np.uint8)]
)
def test_to_luma_rejects_unsupported_images(img: np.ndarray) -> None:
    with pytest.raises(ImageError):
        to_luma(img)
