# SPDX-License-Identifier: MIT
"""2:1 scaler, (a + b + c + d + 2) >> 2 per 2x2 block, and the pyramid sizes."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from golden_model.config import Config
from golden_model.scaler import downscale, pyramid

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")


@pytest.mark.parametrize(
    ("block", "expected"),
    [
        ((0, 0, 0, 0), 0),
        ((1, 0, 0, 0), 0),  # 0.25 -> 0
        ((1, 1, 0, 0), 1),  # 0.5 -> 1: half rounds up
        ((1, 1, 1, 0), 1),  # 0.75 -> 1
        ((1, 1, 1, 1), 1),
        ((0, 0, 0, 2), 1),  # 0.5 -> 1
        ((2, 2, 1, 1), 2),  # 1.5 -> 2
        ((3, 3, 3, 2), 3),  # 2.75 -> 3
        ((10, 11, 12, 13), 12),  # 11.5 -> 12
        ((255, 254, 254, 254), 254),  # 254.25 -> 254
        ((255, 255, 254, 254), 255),  # 254.5 -> 255
        ((255, 255, 255, 255), 255),  # no overflow
        ((0, 255, 0, 255), 128),  # 127.5 -> 128
    ],
)
def test_2x2_block_rounding(block: tuple[int, int, int, int], expected: int) -> None:
    for a, b, c, d in set(itertools.permutations(block)):
        img = np.array([[a, b], [c, d]], dtype=np.uint8)
        out = downscale(img)
        assert out.shape == (1, 1) and out.dtype == np.uint8
        assert int(out[0, 0]) == expected, f"block [[{a}, {b}], [{c}, {d}]] -> {out[0, 0]}, expected {expected}"


def test_blocks_map_to_their_own_output_pixel() -> None:
    img = np.zeros((4, 6), dtype=np.uint8)
    img[2:4, 4:6] = 200  # the block of output pixel (x=2, y=1)
    img[0, 1] = 4  # one pixel of the block of output (x=0, y=0): 4 / 4 = 1
    assert downscale(img).tolist() == [[1, 0, 0], [0, 0, 200]]


@pytest.mark.parametrize(("w", "h"), [(5, 7), (7, 5), (3, 3), (65, 49)])
def test_odd_sizes_drop_the_last_row_and_column(w: int, h: int) -> None:
    img = np.zeros((h, w), dtype=np.uint8)
    img[-1, :] = 255
    img[:, -1] = 255
    out = downscale(img)
    assert out.shape == (h // 2, w // 2), f"{w}x{h} -> {out.shape[1]}x{out.shape[0]}"
    assert not out.any(), f"the dropped last row/column leaked in at (y, x) {np.argwhere(out)[:1].tolist()}"


@pytest.mark.parametrize(
    ("w", "h", "sizes"),
    [
        (1920, 1080, [(1920, 1080), (960, 540), (480, 270), (240, 135)]),
        (1919, 1079, [(1919, 1079), (959, 539), (479, 269), (239, 134)]),
        (64, 48, [(64, 48), (32, 24), (16, 12), (8, 6)]),
        (451, 300, [(451, 300), (225, 150), (112, 75), (56, 37)]),
    ],
)
def test_pyramid_sizes(w: int, h: int, sizes: list[tuple[int, int]]) -> None:
    levels = pyramid(np.zeros((h, w), dtype=np.uint8), 4)
    assert [(lv.shape[1], lv.shape[0]) for lv in levels] == sizes
    cfg = Config(width=w, height=h, scales=4)
    assert [cfg.scale_size(s) for s in range(4)] == sizes
    assert all(lv.dtype == np.uint8 for lv in levels)


def test_pyramid_of_one_scale_is_the_input_and_levels_chain() -> None:
    img = np.random.default_rng(0).integers(0, 256, (16, 20), dtype=np.uint8)
    levels = pyramid(img, 1)
    assert len(levels) == 1 and np.array_equal(levels[0], img)
    levels = pyramid(img, 3)
    assert np.array_equal(levels[2], downscale(downscale(img)))


@pytest.mark.parametrize(("seed", "w", "h"), [(0, 30, 20), (1, 31, 21), (2, 2, 2), (3, 64, 48)])
def test_random_images_against_naive_reference(ref, seed: int, w: int, h: int) -> None:
    img = np.random.default_rng(seed).integers(0, 256, (h, w), dtype=np.uint8)
    got = downscale(img)
    expected = ref.downscale(img)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"downscale {w}x{h}")


@pytest.mark.parametrize("name", PHOTOS)
def test_photograph_crop_against_naive_reference(ref, photographs, name: str) -> None:
    img = ref.center_crop(photographs[name], 41, 40)
    got = downscale(img)
    expected = ref.downscale(img)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"{name} crop downscale")
    got2 = pyramid(img, 3)[2]
    expected2 = ref.downscale(expected)
    assert np.array_equal(got2, expected2), ref.mismatch(got2, expected2, f"{name} crop pyramid level 2")
