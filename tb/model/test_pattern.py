# SPDX-License-Identifier: MIT
"""rBRIEF base pattern and its per-sector rotations (rounded half away from zero, exact quarter turns)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden_model.pattern import base_pattern, rotate_points, rotated_patterns, round_half_away
from golden_model.pattern_data import PATTERN

NS = (4, 8, 16)


def quarter_turn(p: np.ndarray) -> np.ndarray:
    """(x, y) -> (-y, x) on both points: 90 degrees clockwise on screen with y down."""
    x1, y1, x2, y2 = (p[:, i].astype(np.int64) for i in range(4))
    return np.stack([-y1, x1, -y2, x2], axis=1)


def first_bad_test(got: np.ndarray, expected: np.ndarray) -> str:
    bad = np.nonzero((np.asarray(got) != np.asarray(expected)).any(axis=1))[0]
    if len(bad) == 0:
        return "no difference"
    i = int(bad[0])
    return f"{len(bad)} tests differ, first test {i}: {got[i].tolist()} != expected {np.asarray(expected)[i].tolist()}"


def test_base_pattern_has_256_tests_within_radius_15() -> None:
    p = base_pattern()
    assert p.shape == (256, 4) and p.dtype == np.int64
    assert p.tolist() == [list(t) for t in PATTERN]
    for i, (x1, y1, x2, y2) in enumerate(p.tolist()):
        assert x1 * x1 + y1 * y1 <= 225, f"test {i}: point 1 ({x1}, {y1}) outside radius 15"
        assert x2 * x2 + y2 * y2 <= 225, f"test {i}: point 2 ({x2}, {y2}) outside radius 15"


@pytest.mark.parametrize("n", NS)
def test_rotated_tables_shape_type_and_range(n: int) -> None:
    r = rotated_patterns(n)
    assert r.shape == (4 * n, 256, 4) and r.dtype == np.int8
    bad = np.argwhere(np.abs(r.astype(np.int64)) > 15)
    where = f"sector {bad[0][0]} test {bad[0][1]}" if len(bad) else ""
    assert len(bad) == 0, f"N={n}: {where} leaves [-15, 15]"


@pytest.mark.parametrize("n", NS)
def test_sector_0_is_the_base_pattern(n: int) -> None:
    got = rotated_patterns(n)[0]
    assert np.array_equal(got, base_pattern()), first_bad_test(got, base_pattern())


@pytest.mark.parametrize("n", NS)
def test_sector_s_plus_n_is_the_exact_quarter_turn_of_sector_s(n: int) -> None:
    r = rotated_patterns(n)
    for s in range(4 * n):
        got = r[(s + n) % (4 * n)]
        expected = quarter_turn(r[s])
        assert np.array_equal(got, expected), f"N={n}, sector {s} -> {(s + n) % (4 * n)}: " + first_bad_test(
            got, expected
        )


@pytest.mark.parametrize("n", NS)
def test_quadrant_sectors_are_integer_rotations_of_the_base(n: int) -> None:
    base = base_pattern()
    r = rotated_patterns(n)
    x1, y1, x2, y2 = (base[:, i] for i in range(4))
    expected = {
        n: np.stack([-y1, x1, -y2, x2], axis=1),  # 90 degrees: (x, y) -> (-y, x)
        2 * n: -base,  # 180 degrees
        3 * n: np.stack([y1, -x1, y2, -x2], axis=1),  # 270 degrees: (x, y) -> (y, -x)
    }
    for s, e in expected.items():
        assert np.array_equal(r[s], e), f"N={n}, sector {s}: " + first_bad_test(r[s], e)


@pytest.mark.parametrize("n", NS)
def test_every_sector_against_naive_rotation(ref, n: int) -> None:
    r = rotated_patterns(n)
    for s in range(4 * n):
        expected = np.array(ref.rotated_pattern(n, s))
        assert np.array_equal(r[s], expected), f"N={n}, sector {s}: " + first_bad_test(r[s], expected)


def test_same_angle_gives_the_same_table_for_every_n() -> None:
    r4, r8, r16 = rotated_patterns(4), rotated_patterns(8), rotated_patterns(16)
    for s in range(16):
        assert np.array_equal(r4[s], r8[2 * s]) and np.array_equal(r4[s], r16[4 * s]), f"angle {s * 22.5} deg"


@pytest.mark.parametrize("n", NS)
def test_no_rotated_value_is_near_a_rounding_tie(n: int) -> None:
    base = base_pattern()
    for s in range(4 * n):
        a = math.radians(s * 360.0 / (4 * n))
        for i, (x1, y1, x2, y2) in enumerate(base.tolist()):
            for v in (x1 * math.cos(a) - y1 * math.sin(a), x1 * math.sin(a) + y1 * math.cos(a),
                      x2 * math.cos(a) - y2 * math.sin(a), x2 * math.sin(a) + y2 * math.cos(a)):  # fmt: skip
                frac = abs(v) - math.floor(abs(v))
                assert abs(frac - 0.5) > 1e-6, f"N={n}, sector {s}, test {i}: {v!r} is within 1e-6 of a tie"


@pytest.mark.parametrize(
    ("v", "expected"),
    [(0.5, 1), (-0.5, -1), (1.5, 2), (-1.5, -2), (2.5, 3), (-2.5, -3), (14.5, 15), (-14.5, -15),
     (0.4999, 0), (-0.4999, 0), (0.0, 0), (-0.0, 0), (1.49, 1), (-1.51, -2), (7.0, 7)],
)  # fmt: skip
def test_round_half_away_from_zero(v: float, expected: int) -> None:
    got = round_half_away(np.array([v]))
    assert int(got[0]) == expected, f"rnd({v}) = {got[0]}, expected {expected}"


def test_rotate_points_hand_values() -> None:
    p = np.array([[2, 5, 10, 0], [0, 15, -15, 0]], dtype=np.int64)
    # 45 degrees: (2, 5) -> (-3 / sqrt 2, 7 / sqrt 2) = (-2.12, 4.95) -> (-2, 5); (10, 0) -> (7.07, 7.07) -> (7, 7)
    # (0, 15) -> (-10.61, 10.61) -> (-11, 11); (-15, 0) -> (-10.61, -10.61) -> (-11, -11)
    raw, rounded = rotate_points(p, 45.0)
    assert rounded.tolist() == [[-2, 5, 7, 7], [-11, 11, -11, -11]]
    assert np.allclose(raw[0], [-3 / math.sqrt(2), 7 / math.sqrt(2), 10 / math.sqrt(2), 10 / math.sqrt(2)])
    # 90 degrees clockwise on screen: +x goes to +y (down), +y goes to -x.
    _, rounded = rotate_points(p, 90.0)
    assert rounded.tolist() == [[-5, 2, 0, 10], [-15, 0, 0, -15]]
