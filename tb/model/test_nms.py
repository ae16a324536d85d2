# SPDX-License-Identifier: MIT
"""3x3 non-maximum suppression with the raster-order tie rule: hand cases and a naive reference."""

from __future__ import annotations

import numpy as np
import pytest

from golden_model.fast import fast_score
from golden_model.nms import nms3x3

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")
NEIGHBOURS = [(dx, dy) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if (dx, dy) != (0, 0)]


def survivors(score: np.ndarray) -> list[tuple[int, int]]:
    """(x, y) of the survivors in raster order."""
    ys, xs = np.nonzero(nms3x3(score))
    return [(int(x), int(y)) for x, y in zip(xs, ys, strict=True)]


def score_map(w: int, h: int, points: dict[tuple[int, int], int]) -> np.ndarray:
    s = np.zeros((h, w), dtype=np.int32)
    for (x, y), v in points.items():
        s[y, x] = v
    return s


def test_isolated_corner_survives() -> None:
    assert survivors(score_map(7, 6, {(3, 2): 50})) == [(3, 2)]


def test_zero_scores_never_survive() -> None:
    assert survivors(np.zeros((5, 5), dtype=np.int32)) == []


@pytest.mark.parametrize(
    ("a", "b", "winner"),
    [
        ((3, 3), (4, 3), (3, 3)),  # horizontal: the left one is earlier
        ((3, 3), (3, 4), (3, 3)),  # vertical: the upper one
        ((3, 3), (4, 4), (3, 3)),  # diagonal down-right: the upper-left one
        ((4, 3), (3, 4), (4, 3)),  # diagonal down-left: the upper-right one (earlier row)
    ],
    ids=["horizontal", "vertical", "diagonal", "anti-diagonal"],
)
def test_equal_adjacent_pair_keeps_the_raster_earlier(a: tuple[int, int], b: tuple[int, int], winner: tuple) -> None:
    for v in (1, 9, 4080):
        assert survivors(score_map(8, 8, {a: v, b: v})) == [winner], f"equal {v} at {a} and {b}"


@pytest.mark.parametrize("horizontal", [True, False])
def test_three_long_plateau_keeps_only_the_first(horizontal: bool) -> None:
    pts = [(2 + i, 3) if horizontal else (3, 2 + i) for i in range(3)]
    # The third corner loses to the second even though the second itself lost: not iterated.
    assert survivors(score_map(8, 8, dict.fromkeys(pts, 7))) == [pts[0]]


def test_3x3_plateau_keeps_the_top_left() -> None:
    pts = {(x, y): 5 for x in range(2, 5) for y in range(2, 5)}
    assert survivors(score_map(8, 8, pts)) == [(2, 2)]


@pytest.mark.parametrize(("dx", "dy"), NEIGHBOURS)
def test_stronger_neighbour_suppresses(dx: int, dy: int) -> None:
    c = (3, 3)
    n = (3 + dx, 3 + dy)
    assert survivors(score_map(7, 7, {c: 10, n: 11})) == [n], f"stronger neighbour at offset ({dx}, {dy})"
    assert survivors(score_map(7, 7, {c: 11, n: 10})) == [c], f"weaker neighbour at offset ({dx}, {dy})"


def test_neighbours_two_apart_do_not_interact() -> None:
    pts = {(2, 2): 5, (4, 2): 9, (2, 4): 9, (4, 4): 1}
    assert survivors(score_map(7, 7, pts)) == [(2, 2), (4, 2), (2, 4), (4, 4)]


def test_suppressed_corner_still_suppresses_weaker_neighbours() -> None:
    # 5 9 7 in a row: 9 wins. 3 4 5: only 5. 5 4 3: 5 wins and 3 loses to the (suppressed) 4.
    assert survivors(score_map(9, 3, {(2, 1): 5, (3, 1): 9, (4, 1): 7})) == [(3, 1)]
    assert survivors(score_map(9, 3, {(2, 1): 3, (3, 1): 4, (4, 1): 5})) == [(4, 1)]
    assert survivors(score_map(9, 3, {(2, 1): 5, (3, 1): 4, (4, 1): 3})) == [(2, 1)]


@pytest.mark.parametrize(("x", "y"), [(0, 0), (5, 0), (0, 4), (5, 4), (2, 0), (0, 2), (5, 2), (2, 4)])
def test_neighbours_outside_the_image_count_as_zero(x: int, y: int) -> None:
    assert survivors(score_map(6, 5, {(x, y): 1})) == [(x, y)], f"corner on the edge at (x={x}, y={y})"


def test_edge_pair_follows_the_same_tie_rule() -> None:
    assert survivors(score_map(6, 5, {(4, 4): 3, (5, 4): 3})) == [(4, 4)]
    assert survivors(score_map(6, 5, {(5, 3): 3, (5, 4): 3})) == [(5, 3)]
    assert survivors(score_map(6, 5, {(0, 0): 3, (1, 1): 4})) == [(1, 1)]


@pytest.mark.parametrize(("seed", "hi"), [(0, 2), (1, 3), (2, 5), (3, 50), (4, 4081)])
def test_random_score_maps_against_naive_reference(ref, seed: int, hi: int) -> None:
    rng = np.random.default_rng(seed)
    score = rng.integers(0, hi, (40, 37)).astype(np.int32)
    score[rng.random(score.shape) < 0.3] = 0
    got = nms3x3(score)
    expected = ref.nms(score)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"nms seed={seed}")


@pytest.mark.parametrize("seed", range(4))
def test_survivors_are_never_8_adjacent(seed: int) -> None:
    score = np.random.default_rng(seed).integers(0, 3, (60, 60)).astype(np.int32)
    keep = nms3x3(score)
    for y, x in zip(*np.nonzero(keep), strict=True):
        block = keep[max(y - 1, 0) : y + 2, max(x - 1, 0) : x + 2]
        assert block.sum() == 1, f"survivor at (x={x}, y={y}) has a surviving neighbour"


@pytest.mark.parametrize("name", PHOTOS)
def test_photograph_crop_against_naive_reference(ref, photographs, name: str) -> None:
    img = ref.center_crop(photographs[name], 40, 40)
    score = ref.fast_score(img, 5).astype(np.int32)
    got = nms3x3(score)
    expected = ref.nms(score)
    assert np.array_equal(got, expected), ref.mismatch(got, expected, f"{name} crop nms")
    assert np.array_equal(nms3x3(fast_score(img, 5)), expected), f"{name}: NMS of the model's own FAST map"
