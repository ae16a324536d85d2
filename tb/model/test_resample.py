# SPDX-License-Identifier: MIT
"""The num:den pyramid resampler (golden_model.scaler.resample, docs/spec.md section 3): the 2:1
step is the box scaler bit for bit; other steps against a direct float evaluation of the rule
(bilinear at ((x + 0.5) r - 0.5), one rounding half up), directed rounding cases, sizes, phases."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from golden_model.scaler import downscale, pyramid, resample
from orbtb.images import noise, photo

STEPS = ((5, 4), (4, 3), (6, 5), (3, 2), (2, 1), (8, 5))


def reference(img: np.ndarray, num: int, den: int) -> np.ndarray:
    """The rule evaluated with exact fractions, pixel by pixel (slow, small images only)."""
    h, w = img.shape
    ho, wo = h * den // num, w * den // num
    r = Fraction(num, den)
    out = np.zeros((ho, wo), dtype=np.uint8)
    for y in range(ho):
        py = (y + Fraction(1, 2)) * r - Fraction(1, 2)
        y0 = int(py // 1)
        fy = py - y0
        for x in range(wo):
            px = (x + Fraction(1, 2)) * r - Fraction(1, 2)
            x0 = int(px // 1)
            fx = px - x0
            v = (1 - fy) * (1 - fx) * int(img[y0, x0])
            if fx:
                v += (1 - fy) * fx * int(img[y0, x0 + 1])
            if fy:
                v += fy * (1 - fx) * int(img[y0 + 1, x0])
            if fx and fy:
                v += fy * fx * int(img[y0 + 1, x0 + 1])
            out[y, x] = int((v + Fraction(1, 2)) // 1)  # half up
    return out


@pytest.mark.parametrize("name", ["astronaut", "camera", "coffee"])
@pytest.mark.parametrize("size", [(640, 480), (127, 95), (65, 49)])
def test_two_to_one_is_the_box_scaler(name: str, size: tuple[int, int]) -> None:
    img = photo(name, *size)
    assert np.array_equal(resample(img, 2, 1), downscale(img))
    assert all(np.array_equal(a, b) for a, b in zip(pyramid(img, 4), pyramid(img, 4, (2, 1)), strict=True))


@pytest.mark.parametrize("step", STEPS)
def test_against_the_exact_rule(step: tuple[int, int]) -> None:
    for img in (photo("camera", 41, 29), noise(23, 17, seed=5), np.full((9, 11), 255, np.uint8)):
        got, want = resample(img, *step), reference(img, *step)
        bad = np.argwhere(got != want)
        assert len(bad) == 0, (
            f"{step}: {len(bad)} pixels differ, first at {bad[0]}: {got[tuple(bad[0])]} != {want[tuple(bad[0])]}"
        )


def test_rounding_half_up_and_phases() -> None:
    # 5:4 in x only (one row repeated): positions 0.125, 1.375, 2.625, 3.875, then 5.125 (phase repeats)
    row = np.array([0, 8, 16, 24, 32, 40, 48, 56, 64, 72, 80], dtype=np.uint8)
    img = np.tile(row, (6, 1))
    out = resample(img, 5, 4)
    assert out.shape == (4, 8)
    assert out[0].tolist() == [1, 11, 21, 31, 41, 51, 61, 71]  # 8 * position, 1.0 exactly at 0.125
    half = np.array([[0, 1], [0, 1]], dtype=np.uint8)  # 3:2 of a 2-wide image: one output at 0.25
    assert resample(np.tile(half, (3, 2)), 3, 2)[0, 0] == 0  # 0.25 -> 0
    assert resample(np.array([[1, 0, 0], [1, 0, 0]] * 2, dtype=np.uint8)[:3], 3, 2)[0, 0] == 1  # 0.75 -> 1
    for num, den in STEPS:
        img = noise(num * 7, den * 7, seed=num)
        assert resample(img, num, den).shape == (den * 7 * den // num, num * 7 * den // num)


@pytest.mark.parametrize("bad", [(4, 5), (1, 1), (5, 0), (2.0, 1)])
def test_illegal_steps(bad: tuple) -> None:
    with pytest.raises(ValueError, match="num > den"):
        resample(np.zeros((8, 8), np.uint8), *bad)
