# SPDX-License-Identifier: MIT
"""rBRIEF descriptors: test i is smoothed(p1) < smoothed(p2), test 8j+k in bit k of byte j."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from golden_model.brief import describe

NS = (4, 8, 16)
SIZE = 64
C = 32  # feature centre (C, C) of the SIZE x SIZE test images


def pack(bits: list[bool]) -> bytes:
    """Test 8j + k into bit k (value 1 << k) of byte j, written out by hand."""
    assert len(bits) == 256
    out = bytearray(32)
    for j in range(32):
        for k in range(8):
            if bits[8 * j + k]:
                out[j] += 1 << k
    return bytes(out)


def describe_one(sm: np.ndarray, x: int, y: int, sector: int, n: int) -> bytes:
    d = describe(sm, np.array([x]), np.array([y]), np.array([sector]), n)
    assert d.shape == (1, 32) and d.dtype == np.uint8
    return d[0].tobytes()


def bit_diff(got: bytes, expected: bytes) -> str:
    for i in range(256):
        g, e = got[i // 8] >> (i % 8) & 1, expected[i // 8] >> (i % 8) & 1
        if g != e:
            return f"first differing test {i} (byte {i // 8}, bit {i % 8}): got {g}, expected {e}"
    return "no difference"


RAMPS: dict[str, Callable[[int, int], int]] = {
    "x": lambda x, y: x,
    "y": lambda x, y: y,
    "x+2y": lambda x, y: x + 2 * y + 40,
}


def ramp(name: str) -> np.ndarray:
    f = RAMPS[name]
    return np.array([[f(x, y) for x in range(SIZE)] for y in range(SIZE)], dtype=np.uint8)


# Expected bits on each ramp, from the test's points after rotation by 0, 90, 180 and 270 degrees:
# a quarter turn maps (x, y) to (-y, x), so on the x ramp sector N compares -y1 < -y2, i.e. y1 > y2.
HAND_RULES: dict[tuple[str, int], Callable[[int, int, int, int], bool]] = {
    ("x", 0): lambda x1, y1, x2, y2: x1 < x2,
    ("x", 1): lambda x1, y1, x2, y2: y1 > y2,
    ("x", 2): lambda x1, y1, x2, y2: x1 > x2,
    ("x", 3): lambda x1, y1, x2, y2: y1 < y2,
    ("y", 0): lambda x1, y1, x2, y2: y1 < y2,
    ("y", 1): lambda x1, y1, x2, y2: x1 < x2,
    ("y", 2): lambda x1, y1, x2, y2: y1 > y2,
    ("x+2y", 0): lambda x1, y1, x2, y2: x1 + 2 * y1 < x2 + 2 * y2,
    ("x+2y", 1): lambda x1, y1, x2, y2: -y1 + 2 * x1 < -y2 + 2 * x2,
}


@pytest.mark.parametrize("n", NS)
@pytest.mark.parametrize(("ramp_name", "quarter"), list(HAND_RULES))
def test_ramps_give_hand_predictable_bits(ref, n: int, ramp_name: str, quarter: int) -> None:
    rule = HAND_RULES[(ramp_name, quarter)]
    expected = pack([rule(*t) for t in ref.rotated_pattern(n, 0)])
    got = describe_one(ramp(ramp_name), C, C, quarter * n, n)
    assert got == expected, f"{ramp_name} ramp, sector {quarter * n} of {4 * n}, (x={C}, y={C}): " + bit_diff(
        got, expected
    )


def test_bit_order_first_test_is_bit_0_of_byte_0(ref) -> None:
    _, _, x2, y2 = ref.rotated_pattern(8, 0)[0]
    sm = np.full((SIZE, SIZE), 100, dtype=np.uint8)
    sm[C + y2, C + x2] = 101  # test 0 sees p1 = 100 < p2 = 101
    d = describe_one(sm, C, C, 0, 8)
    assert d[0] & 1 == 1, f"test 0 must be bit 0 (value 1) of byte 0, got byte 0 = {d[0]:#04x}"


@pytest.mark.parametrize("i", [0, 1, 7, 8, 9, 100, 127, 128, 254, 255])
def test_single_raised_point_sets_exactly_the_tests_that_use_it_as_p2(ref, i: int) -> None:
    pattern = ref.rotated_pattern(4, 0)
    point = (pattern[i][2], pattern[i][3])
    sm = np.full((SIZE, SIZE), 100, dtype=np.uint8)
    sm[C + point[1], C + point[0]] = 101
    # Test m is 1 exactly when its p2 is the raised point and its p1 is not.
    bits = [(x2, y2) == point and (x1, y1) != point for x1, y1, x2, y2 in pattern]
    assert bits[i], "the chosen test must be one of them"
    got = describe_one(sm, C, C, 0, 4)
    assert got[i // 8] >> (i % 8) & 1, f"test {i} not in bit {i % 8} of byte {i // 8}: {got.hex()}"
    assert got == pack(bits), bit_diff(got, pack(bits))


@pytest.mark.parametrize("n", NS)
@pytest.mark.parametrize("value", [0, 37, 255])
def test_flat_image_gives_all_zero_descriptors(n: int, value: int) -> None:
    sm = np.full((SIZE, SIZE), value, dtype=np.uint8)
    sectors = np.arange(4 * n)
    xs = np.full(4 * n, C)
    d = describe(sm, xs, xs.copy(), sectors, n)
    assert d.shape == (4 * n, 32) and not d.any(), "p1 < p2 is strict: equal pixels give 0 in every sector"


@pytest.mark.parametrize("n", NS)
def test_random_images_every_sector_against_naive_reference(ref, n: int) -> None:
    rng = np.random.default_rng(n)
    sm = rng.integers(0, 256, (50, 47), dtype=np.uint8)
    sectors = np.arange(4 * n)
    xs = rng.integers(15, 47 - 15, 4 * n)
    ys = rng.integers(15, 50 - 15, 4 * n)
    d = describe(sm, xs, ys, sectors, n)
    for k in range(4 * n):
        expected = ref.descriptor(sm, int(xs[k]), int(ys[k]), int(sectors[k]), n)
        got = d[k].tobytes()
        assert got == expected, f"N={n}, sector {k} at (x={xs[k]}, y={ys[k]}): " + bit_diff(got, expected)


def test_low_contrast_image_with_many_equal_pairs_against_naive_reference(ref) -> None:
    rng = np.random.default_rng(7)
    sm = rng.integers(0, 2, (40, 40), dtype=np.uint8)
    xs, ys = np.array([15, 20, 24]), np.array([24, 19, 15])
    sectors = np.array([0, 5, 31])
    d = describe(sm, xs, ys, sectors, 8)
    for k in range(3):
        expected = ref.descriptor(sm, int(xs[k]), int(ys[k]), int(sectors[k]), 8)
        assert d[k].tobytes() == expected, f"(x={xs[k]}, y={ys[k]}): " + bit_diff(d[k].tobytes(), expected)


def test_no_features_gives_an_empty_array() -> None:
    empty = np.zeros(0, dtype=np.int64)
    d = describe(np.zeros((40, 40), dtype=np.uint8), empty, empty, empty, 8)
    assert d.shape == (0, 32) and d.dtype == np.uint8
