# SPDX-License-Identifier: MIT
"""rBRIEF orbit pattern: seeds, member tables (float rotation, exact quarter turns), per-sector permutations."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from golden_model.pattern import (
    base_tests,
    member_tables,
    orbit_patterns,
    orbit_permutation,
    rotate_points,
    rotated_patterns,
    round_half_away,
    seeds,
)
from golden_model.pattern_data import ORBIT_SEEDS

ROOT = Path(__file__).resolve().parents[2]
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


@pytest.mark.parametrize("sectors", [16, 32, 64])
def test_seeds_are_256_over_4n_tests_on_the_1_16_grid_within_radius_15(sectors: int) -> None:
    q = seeds(sectors)
    assert q.shape == (256 // sectors, 4) and q.tolist() == [list(t) for t in ORBIT_SEEDS[sectors]]
    assert np.array_equal(q * 16, np.round(q * 16)), "seed coordinates must be multiples of 1/16"
    r2 = q[:, 0::2] ** 2 + q[:, 1::2] ** 2
    assert (r2 <= 225).all(), f"seed {np.argwhere(r2 > 225)[0][0]} has a point outside radius 15"


@pytest.mark.parametrize("n", NS)
def test_rotated_tables_shape_type_and_range(n: int) -> None:
    r = rotated_patterns(n)
    assert r.shape == (4 * n, 256, 4) and r.dtype == np.int8 and not r.flags.writeable
    bad = np.argwhere(np.abs(r.astype(np.int64)) > 15)
    where = f"sector {bad[0][0]} test {bad[0][1]}" if len(bad) else ""
    assert len(bad) == 0, f"N={n}: {where} leaves [-15, 15]"


@pytest.mark.parametrize("n", NS)
def test_base_tests_are_256_distinct_non_degenerate_tests(n: int) -> None:
    b = base_tests(n)
    assert b.shape == (256, 4) and b.dtype == np.int64
    assert np.array_equal(b, rotated_patterns(n)[0])
    assert len({tuple(t) for t in b.tolist()}) == 256, "duplicate test"
    assert not (b[:, :2] == b[:, 2:]).all(axis=1).any(), "a test compares a point with itself"


@pytest.mark.parametrize("n", NS)
def test_sector_0_holds_member_k_of_orbit_j_at_test_j4n_plus_k(n: int) -> None:
    sectors = 4 * n
    b = base_tests(n)
    for j, seed in enumerate(ORBIT_SEEDS[sectors]):
        for k in range(sectors):
            _, expected = rotate_points(np.array([seed]), k * 360.0 / sectors)
            got = b[j * sectors + k]
            assert got.tolist() == expected[0].tolist(), f"N={n}, orbit {j}, member {k}"


@pytest.mark.parametrize("n", NS)
def test_every_sector_is_sector_0_permuted_within_the_orbits(n: int) -> None:
    r = rotated_patterns(n)
    for s in range(4 * n):
        expected = r[0][orbit_permutation(4 * n, s)]
        assert np.array_equal(r[s], expected), f"N={n}, sector {s}: " + first_bad_test(r[s], expected)


def test_orbit_permutation_hand_values() -> None:
    assert orbit_permutation(16, 0).tolist() == list(range(256))
    p = orbit_permutation(16, 1).tolist()
    assert p[:17] == [*range(1, 16), 0, 17] and p[-1] == 240
    p = orbit_permutation(64, 63).tolist()
    assert p[:3] == [63, 0, 1] and p[64:66] == [127, 64] and p[192] == 255


@pytest.mark.parametrize("sectors", [16, 32, 64])
def test_orbit_permutations_compose_and_stay_within_their_orbit(sectors: int) -> None:
    i = np.arange(256)
    for s in (1, 3, sectors // 4, sectors - 1):
        p = orbit_permutation(sectors, s)
        assert sorted(p.tolist()) == list(range(256)), f"{sectors} sectors, s={s}: not a permutation"
        assert np.array_equal(p // sectors, i // sectors), f"{sectors} sectors, s={s}: leaves an orbit"
        for t in (1, 5):
            composed = orbit_permutation(sectors, t)[p]
            assert np.array_equal(composed, orbit_permutation(sectors, (s + t) % sectors)), (sectors, s, t)


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
def test_quadrant_sectors_are_integer_rotations_of_sector_0(n: int) -> None:
    r = rotated_patterns(n)
    base = r[0].astype(np.int64)
    x1, y1, x2, y2 = (base[:, i] for i in range(4))
    expected = {
        n: np.stack([-y1, x1, -y2, x2], axis=1),  # 90 degrees: (x, y) -> (-y, x)
        2 * n: -base,  # 180 degrees
        3 * n: np.stack([y1, -x1, y2, -x2], axis=1),  # 270 degrees: (x, y) -> (y, -x)
    }
    for s, e in expected.items():
        assert np.array_equal(r[s], e), f"N={n}, sector {s}: " + first_bad_test(r[s], e)


@pytest.mark.parametrize("n", NS)
def test_members_of_later_quadrants_are_quarter_turns_and_agree_with_float_rotation(n: int) -> None:
    sectors = 4 * n
    q = seeds(sectors)
    m = member_tables(q, sectors)
    for k in range(n, sectors):
        assert np.array_equal(m[k], quarter_turn(m[k - n])), f"N={n}, member {k}"
        _, rounded = rotate_points(q, k * 360.0 / sectors)
        assert np.array_equal(m[k], rounded), f"N={n}, member {k}: " + first_bad_test(m[k], rounded)


@pytest.mark.parametrize("n", NS)
def test_every_sector_against_naive_rotation(ref, n: int) -> None:
    r = rotated_patterns(n)
    for s in range(4 * n):
        expected = np.array(ref.rotated_pattern(n, s))
        assert np.array_equal(r[s], expected), f"N={n}, sector {s}: " + first_bad_test(r[s], expected)


@pytest.mark.parametrize("n", NS)
def test_no_rotated_value_is_near_a_rounding_tie(n: int) -> None:
    sectors = 4 * n
    for k in range(sectors):
        a = math.radians(k * 360.0 / sectors)
        for j, (x1, y1, x2, y2) in enumerate(ORBIT_SEEDS[sectors]):
            for v in (x1 * math.cos(a) - y1 * math.sin(a), x1 * math.sin(a) + y1 * math.cos(a),
                      x2 * math.cos(a) - y2 * math.sin(a), x2 * math.sin(a) + y2 * math.cos(a)):  # fmt: skip
                frac = abs(v) - math.floor(abs(v))
                assert abs(frac - 0.5) > 1e-6, f"N={n}, member {k}, orbit {j}: {v!r} is within 1e-6 of a tie"


def test_a_seed_on_a_rounding_tie_is_refused() -> None:
    with pytest.raises(ValueError, match="rounding tie"):
        member_tables(np.array([[2.5, 1.0, -3.0, 4.0]]), 16)


def test_seed_count_must_fill_256_tests() -> None:
    with pytest.raises(ValueError, match="256"):
        orbit_patterns(seeds(16)[:15], 16)
    with pytest.raises(ValueError, match="no pattern"):
        seeds(24)


def test_pattern_data_is_what_the_generator_writes(tmp_path: Path) -> None:
    out = tmp_path / "pattern_data.py"
    subprocess.run([sys.executable, "-m", "orb_flow.gen.pattern", "--out", str(out)], check=True)
    committed = (ROOT / "golden_model" / "pattern_data.py").read_bytes()
    assert out.read_bytes() == committed, "golden_model/pattern_data.py is stale: run `make pattern`"


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
    # real-valued seeds by 30 degrees: (1.25, -0.75) -> (1.458, -0.025) -> (1, 0); (0, 4) -> (-2.0, 3.464) -> (-2, 3)
    _, rounded = rotate_points(np.array([[1.25, -0.75, 0.0, 4.0]]), 30.0)
    assert rounded.tolist() == [[1, 0, -2, 3]]
