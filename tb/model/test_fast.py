# SPDX-License-Identifier: MIT
"""FAST-9 segment test and SAD score: hand-built rings, a naive loop reference and OpenCV's FAST."""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np
import pytest

from golden_model.fast import ARC_TABLE, CIRCLE, fast_score, has_arc

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")
SIZE = 9  # 9x9 test images: the ring around the centre (4, 4) fits with a 1-pixel margin
CX = CY = SIZE // 2


def ring_image(ref, c: int, ring: Sequence[int], fill: int | None = None) -> np.ndarray:
    """SIZE x SIZE image, value ``fill`` (default c), centre c and the 16 ring values in circle order."""
    img = np.full((SIZE, SIZE), c if fill is None else fill, dtype=np.uint8)
    img[CY, CX] = c
    for (dx, dy), v in zip(ref.circle, ring, strict=True):
        img[CY + dy, CX + dx] = v
    return img


def arc_ring(c: int, start: int, length: int, delta: int) -> list[int]:
    """Ring equal to c except ``length`` cyclically contiguous pixels from ``start``, set to c + delta."""
    ring = [c] * 16
    for i in range(length):
        ring[(start + i) % 16] = c + delta
    return ring


def centre_score(ref, c: int, ring: Sequence[int], t: int) -> int:
    return int(fast_score(ring_image(ref, c, ring), t)[CY, CX])


def test_circle_is_the_clockwise_bresenham_circle_from_straight_up(ref) -> None:
    assert tuple(CIRCLE) == ref.circle, f"CIRCLE {CIRCLE} != derived {ref.circle}"
    assert CIRCLE[0] == (0, -3), "bit 0 must be straight up (y grows downwards)"
    assert CIRCLE[4] == (3, 0), "clockwise on screen: a quarter turn from up is +x"


@pytest.mark.parametrize("start", range(16))
@pytest.mark.parametrize(("t", "sign"), [(0, 1), (20, 1), (100, 1), (0, -1), (20, -1), (100, -1)])
def test_nine_contiguous_beyond_threshold_is_a_corner(ref, start: int, t: int, sign: int) -> None:
    c = 100 if sign > 0 else 150
    ring = arc_ring(c, start, 9, sign * (t + 1))
    assert centre_score(ref, c, ring, t) == 9 * (t + 1), f"arc of 9 from bit {start}, t={t}: centre (x=4, y=4)"


@pytest.mark.parametrize("start", range(16))
@pytest.mark.parametrize(("t", "sign"), [(1, 1), (20, 1), (100, 1), (1, -1), (20, -1), (100, -1)])
def test_nine_contiguous_at_exactly_threshold_is_not_a_corner(ref, start: int, t: int, sign: int) -> None:
    c = 100 if sign > 0 else 150
    ring = arc_ring(c, start, 9, sign * t)  # p - c == t: the comparison is strict
    assert centre_score(ref, c, ring, t) == 0, f"arc of 9 differing by exactly t={t}: centre (x=4, y=4)"


@pytest.mark.parametrize("start", range(16))
@pytest.mark.parametrize("sign", [1, -1])
def test_eight_contiguous_is_not_a_corner(ref, start: int, sign: int) -> None:
    ring = arc_ring(128, start, 8, sign * 127)
    assert centre_score(ref, 128, ring, 0) == 0, f"arc of 8 from bit {start}: centre (x=4, y=4)"


@pytest.mark.parametrize("sign", [1, -1])
def test_wrap_around_arc_across_bit_15_to_0(ref, sign: int) -> None:
    # Bits 12, 13, 14, 15, 0, 1, 2, 3, 4: contiguous only cyclically.
    ring = arc_ring(100, 12, 9, sign * 30)
    assert [i for i in range(16) if ring[i] != 100] == [0, 1, 2, 3, 4, 12, 13, 14, 15]
    assert centre_score(ref, 100, ring, 20) == 9 * 30
    ring[4] = 100  # now 8 cyclically contiguous
    assert centre_score(ref, 100, ring, 20) == 0


def test_fifteen_with_one_gap_is_a_corner_two_sevens_are_not(ref) -> None:
    ring = [140] * 16
    ring[7] = 100  # one gap: the other 15 are contiguous through bit 15 -> 0
    assert centre_score(ref, 100, ring, 20) == 15 * 40
    ring[15] = 100  # runs 0..6 and 8..14: fourteen brighter pixels, none 9 contiguous
    assert centre_score(ref, 100, ring, 20) == 0


def test_brighter_and_darker_do_not_combine(ref) -> None:
    ring = arc_ring(100, 0, 8, 50)
    ring[8] = 50  # 8 brighter then 1 darker: 9 beyond the threshold but not one kind
    assert centre_score(ref, 100, ring, 20) == 0
    ring = arc_ring(100, 0, 8, -50)
    ring[8] = 150
    assert centre_score(ref, 100, ring, 20) == 0


def test_sad_score_hand_summed(ref) -> None:
    # Centre 100, t = 10: bits 0..8 are 111..119 (> 110), bit 14 is 110 (= c + t, not brighter).
    ring = [111, 112, 113, 114, 115, 116, 117, 118, 119, 105, 95, 100, 100, 90, 110, 101]
    # |p - c|: 11+12+13+14+15+16+17+18+19 = 135, then 5 + 5 + 0 + 0 + 10 + 10 + 1 = 31.
    assert centre_score(ref, 100, ring, 10) == 166
    ring[4] = 110  # bit 4 no longer strictly brighter: runs of 4 and 4
    assert centre_score(ref, 100, ring, 10) == 0


def test_score_is_sum_over_all_sixteen_not_just_the_arc(ref) -> None:
    ring = arc_ring(100, 3, 9, 50)
    for i in range(16):
        if ring[i] == 100:
            ring[i] = 100 + (i % 3) * 7 - 7  # 93, 100 or 107: within the threshold
    expected = 9 * 50 + sum(abs(p - 100) for p in ring if abs(p - 100) < 50)
    assert centre_score(ref, 100, ring, 20) == expected


def test_threshold_255_never_detects_and_254_gives_the_maximum_score(ref) -> None:
    assert centre_score(ref, 0, [255] * 16, 255) == 0, "255 - 0 is not > 255"
    assert centre_score(ref, 255, [0] * 16, 255) == 0
    assert centre_score(ref, 0, [255] * 16, 254) == 4080, "16 * 255, the 12-bit maximum"
    assert centre_score(ref, 255, [0] * 16, 254) == 4080


def test_threshold_0_detects_a_difference_of_one(ref) -> None:
    assert centre_score(ref, 7, arc_ring(7, 5, 9, 1), 0) == 9
    assert centre_score(ref, 7, arc_ring(7, 5, 9, -1), 0) == 9
    assert centre_score(ref, 7, arc_ring(7, 5, 8, 1), 0) == 0


@pytest.mark.parametrize(("w", "h"), [(12, 10), (7, 7), (8, 11)])
def test_only_pixels_three_from_the_border_can_be_corners(w: int, h: int) -> None:
    for y in range(h):
        for x in range(w):
            img = np.zeros((h, w), dtype=np.uint8)
            img[y, x] = 200  # an isolated bright dot: 16 darker ring pixels wherever it is interior
            score = fast_score(img, 20)
            interior = 3 <= x <= w - 4 and 3 <= y <= h - 4
            assert int(score[y, x]) == (3200 if interior else 0), f"dot at (x={x}, y={y}) in {w}x{h}"
            assert np.count_nonzero(score) == int(interior), f"extra corners for a dot at (x={x}, y={y})"


@pytest.mark.parametrize(("w", "h"), [(6, 10), (10, 6), (1, 1), (0, 0)])
def test_images_without_interior_have_no_corners(w: int, h: int) -> None:
    img = np.random.default_rng(0).integers(0, 256, (h, w), dtype=np.uint8)
    score = fast_score(img, 0)
    assert score.shape == (h, w) and not score.any()


@pytest.mark.parametrize(
    "img",
    [np.zeros((9, 9), dtype=np.int16), np.zeros((9, 9), dtype=np.float64), np.zeros((9, 9, 3), dtype=np.uint8)],
    ids=["int16", "float64", "rgb"],
)
def test_non_uint8_or_non_2d_input_raises(img: np.ndarray) -> None:
    with pytest.raises(ValueError, match="2-D uint8"):
        fast_score(img, 20)


def test_arc_table_against_string_search() -> None:
    for mask in range(1 << 16):
        bits = "".join("1" if mask >> i & 1 else "0" for i in range(16))
        expected = "1" * 9 in bits + bits
        assert bool(ARC_TABLE[mask]) == expected, f"mask {mask:#06x}"
    assert has_arc(0x01FF) and has_arc(0xF01F) and has_arc(0xFFFF) and has_arc(0x1FF80)
    assert not has_arc(0x00FF) and not has_arc(0x7F7F) and not has_arc(0xF00F) and not has_arc(0)


@pytest.mark.parametrize(
    ("seed", "lo", "hi", "t"),
    [(0, 0, 256, 0), (1, 0, 256, 20), (2, 0, 256, 60), (3, 0, 4, 0), (4, 0, 4, 1), (5, 0, 2, 0), (6, 90, 110, 9)],
)
def test_random_images_against_naive_reference(ref, seed: int, lo: int, hi: int, t: int) -> None:
    img = np.random.default_rng(seed).integers(lo, hi, (30, 34), dtype=np.uint8)
    got = fast_score(img, t)
    assert got.dtype == np.int32
    expected = ref.fast_score(img, t)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"fast_score t={t}")
    corners = got[got > 0]
    assert corners.min(initial=9) >= 9 and corners.max(initial=0) <= 4080


@pytest.mark.parametrize("t", [0, 10, 20, 40])
@pytest.mark.parametrize("name", PHOTOS)
def test_photograph_crop_against_naive_reference(ref, photographs, name: str, t: int) -> None:
    img = ref.center_crop(photographs[name], 40, 40)
    got = fast_score(img, t)
    expected = ref.fast_score(img, t)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"{name} crop fast_score t={t}")


@pytest.mark.parametrize("t", [0, 1, 10, 20, 40, 100, 255])
@pytest.mark.parametrize("name", PHOTOS)
def test_corners_identical_to_opencv_fast(ref, photographs, name: str, t: int) -> None:
    img = photographs[name]
    h, w = img.shape
    detector = cv2.FastFeatureDetector_create(t, False, cv2.FastFeatureDetector_TYPE_9_16)
    opencv = np.zeros((h, w), dtype=bool)
    for kp in detector.detect(img):
        x, y = round(kp.pt[0]), round(kp.pt[1])
        assert (x, y) == kp.pt, f"OpenCV keypoint off the pixel grid: {kp.pt}"
        assert not opencv[y, x], f"OpenCV reported (x={x}, y={y}) twice"
        opencv[y, x] = True
    ours = fast_score(img, t) > 0
    assert np.array_equal(ours, opencv), ref.mismatch(ours, opencv, f"{name} corners t={t} vs OpenCV")
    for region in (ours[:3], ours[-3:], ours[:, :3], ours[:, -3:]):
        assert not region.any(), f"{name}: a corner in the 3-pixel border at t={t}"
