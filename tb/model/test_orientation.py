# SPDX-License-Identifier: MIT
"""Circular patch, intensity-centroid moments and the fixed-point sector quantiser."""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden_model.orientation import (
    PATCH_RADIUS,
    UMAX,
    boundaries,
    moments,
    patch_mask,
    quantise,
    sector_angle_deg,
    tangent_constants,
)

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")
NS = (4, 8, 16)
HAND_UMAX = (15, 15, 15, 15, 14, 14, 14, 13, 13, 12, 11, 10, 9, 8, 6, 3)


def sector_of(m10: int, m01: int, n: int) -> int:
    out = quantise(np.array([m10]), np.array([m01]), n)
    return int(out[0])


def vector_at(angle_deg: float, radius: float = 1_000_000.0) -> tuple[int, int]:
    """Integer (m10, m01) at the given angle, clockwise on screen from +x (y down)."""
    a = math.radians(angle_deg)
    return round(radius * math.cos(a)), round(radius * math.sin(a))


# ---- patch ---------------------------------------------------------------------------------------


def test_umax_is_the_hand_table() -> None:
    assert tuple(UMAX) == HAND_UMAX
    assert PATCH_RADIUS == 15


def test_patch_mask_is_the_hand_built_shape() -> None:
    mask = patch_mask()
    assert mask.shape == (31, 31) and mask.dtype == bool
    for v in range(-15, 16):
        for u in range(-15, 16):
            expected = abs(u) <= HAND_UMAX[abs(v)]
            assert bool(mask[v + 15, u + 15]) == expected, f"mask at (u={u}, v={v})"


def test_patch_mask_pixel_count() -> None:
    # Row v has 2 UMAX[|v|] + 1 pixels: 31 + 2 * sum_{v=1..15} (2 UMAX[v] + 1) = 31 + 2 * 359 = 749.
    assert int(patch_mask().sum()) == 749


def test_patch_mask_symmetries() -> None:
    mask = patch_mask()
    assert np.array_equal(mask, mask.T), "not symmetric under transposition"
    for k in (1, 2, 3):
        assert np.array_equal(np.rot90(mask, k), mask), f"not symmetric under rotation by {90 * k} degrees"
    assert np.array_equal(mask[::-1], mask) and np.array_equal(mask[:, ::-1], mask)


def test_patch_mask_is_a_disc_of_radius_15() -> None:
    mask = patch_mask()
    for v in range(-15, 16):
        for u in range(-15, 16):
            r2 = u * u + v * v
            if r2 <= 225:
                assert mask[v + 15, u + 15], f"(u={u}, v={v}) within radius 15 but outside the patch"
            if r2 > 15.5**2:
                assert not mask[v + 15, u + 15], f"(u={u}, v={v}) beyond radius 15.5 but inside the patch"


def test_column_half_heights_equal_umax() -> None:
    # The column form of the docstring: column u spans |v| <= UMAX[|u|].
    mask = patch_mask()
    spec_heights = [7, 13, 17, 19, 21, 23, 25, 27, 27, 29, 29, 29, 31, 31, 31, 31, 31, 31, 31, 29, 29, 29, 27, 27, 25,
                    23, 21, 19, 17, 13, 7]  # fmt: skip
    assert mask.sum(axis=0).tolist() == spec_heights, "column heights 2 UMAX[|u|] + 1 of docs/spec.md section 8"
    for u in range(-15, 16):
        col = mask[:, u + 15]
        vs = [v for v in range(-15, 16) if col[v + 15]]
        assert vs == list(range(-HAND_UMAX[abs(u)], HAND_UMAX[abs(u)] + 1)), f"column u={u}"


# ---- moments -------------------------------------------------------------------------------------

INSIDE = [(0, 0), (15, 0), (-15, 0), (0, 15), (0, -15), (3, 15), (-3, -15), (15, 3), (11, 10), (10, 11),
          (-9, 12), (6, -14), (14, 6), (8, 13), (-13, -8), (1, -1)]  # fmt: skip
OUTSIDE = [(4, 15), (15, 4), (-4, -15), (12, 10), (10, 12), (15, 15), (7, 14), (-9, 13), (14, -7), (-15, -15)]


@pytest.mark.parametrize("val", [1, 255])
@pytest.mark.parametrize(("u", "v"), INSIDE + OUTSIDE)
def test_moments_of_a_single_bright_pixel(u: int, v: int, val: int) -> None:
    p = np.zeros((41, 43), dtype=np.uint8)
    p[20 + v, 21 + u] = val
    m10, m01 = moments(p, np.array([21]), np.array([20]))
    inside = (u, v) in INSIDE
    expected = (u * val, v * val) if inside else (0, 0)
    got = (int(m10[0]), int(m01[0]))
    assert got == expected, f"pixel {val} at (u={u}, v={v}) ({'inside' if inside else 'outside'}): {got} != {expected}"


def test_moments_of_a_bright_right_half_hand_summed() -> None:
    # sum over the patch of u for u > 0: per row U (U + 1) / 2, rows 0 and +-1..15:
    # 120 + 2 * (120 * 3 + 105 * 3 + 91 * 2 + 78 + 66 + 55 + 45 + 36 + 21 + 6) = 120 + 2 * 1164 = 2448.
    p = np.zeros((31, 31), dtype=np.uint8)
    p[:, 16:] = 255
    m10, m01 = moments(p, np.array([15]), np.array([15]))
    assert (int(m10[0]), int(m01[0])) == (255 * 2448, 0)
    assert 255 * 2448 < 1 << 21
    m10, m01 = moments(p.T.copy(), np.array([15]), np.array([15]))
    assert (int(m10[0]), int(m01[0])) == (0, 255 * 2448), "bright lower half: m01 = 624240"


@pytest.mark.parametrize("seed", range(3))
def test_moments_against_naive_double_loop(ref, seed: int) -> None:
    rng = np.random.default_rng(seed)
    p = rng.integers(0, 256, (37, 41), dtype=np.uint8)
    ys, xs = np.mgrid[15:22, 15:26]
    xs, ys = xs.ravel(), ys.ravel()
    m10, m01 = moments(p, xs, ys)
    assert m10.dtype == np.int64 and m01.dtype == np.int64
    for i, (x, y) in enumerate(zip(xs.tolist(), ys.tolist(), strict=True)):
        expected = ref.moments(p, x, y)
        assert (int(m10[i]), int(m01[i])) == expected, f"moments at (x={x}, y={y})"


@pytest.mark.parametrize("name", PHOTOS)
def test_moments_of_a_photograph_crop_against_naive_double_loop(ref, photographs, name: str) -> None:
    p = ref.center_crop(photographs[name], 40, 40)
    ys, xs = np.mgrid[15:25, 15:25]
    xs, ys = xs.ravel(), ys.ravel()
    m10, m01 = moments(p, xs, ys)
    for i, (x, y) in enumerate(zip(xs.tolist(), ys.tolist(), strict=True)):
        expected = ref.moments(p, x, y)
        assert (int(m10[i]), int(m01[i])) == expected, f"{name} crop moments at (x={x}, y={y})"


def test_moments_of_a_flat_patch_are_zero() -> None:
    p = np.full((31, 31), 255, dtype=np.uint8)
    m10, m01 = moments(p, np.array([15]), np.array([15]))
    assert (int(m10[0]), int(m01[0])) == (0, 0)


# ---- quantiser -----------------------------------------------------------------------------------


def test_tangent_constants_hand_table_for_n4() -> None:
    # tan(11.25 deg) = tan(pi/16) = 1/sin(pi/8) - cot(pi/8) = 0.198912..., * 65536 = 13035.99 -> 13036.
    # tan(33.75 deg) = 1/sin(3pi/8) - cot(3pi/8) = 0.668179..., * 65536 = 43789.77 -> 43790.
    # Boundaries 56.25 and 78.75 use cot = tan(33.75) and tan(11.25).
    t1 = 1 / math.sin(math.pi / 8) - (1 + math.sqrt(2))
    t3 = 1 / math.sin(3 * math.pi / 8) - (math.sqrt(2) - 1)
    assert (round(t1 * 65536), round(t3 * 65536)) == (13036, 43790)
    assert tangent_constants(4) == ((False, 13036), (False, 43790), (True, 43790), (True, 13036))
    assert boundaries(4) == [11.25, 33.75, 56.25, 78.75]


# docs/spec.md section 9, "*" (the cotangent form) written as True.
SPEC_CONSTANTS = {
    8: [(False, 6455), (False, 19880), (False, 35030), (False, 53784),
        (True, 53784), (True, 35030), (True, 19880), (True, 6455)],
    16: [(False, 3220), (False, 9721), (False, 16416), (False, 23449), (False, 30996), (False, 39281), (False, 48605),
         (False, 59398), (True, 59398), (True, 48605), (True, 39281), (True, 30996), (True, 23449), (True, 16416),
         (True, 9721), (True, 3220)],
}  # fmt: skip


@pytest.mark.parametrize("n", [8, 16])
def test_tangent_constants_spec_table(ref, n: int) -> None:
    assert list(tangent_constants(n)) == SPEC_CONSTANTS[n]
    assert list(ref.tangent_constants(n)) == SPEC_CONSTANTS[n], "the spec table is round(tan * 2^16)"


@pytest.mark.parametrize("n", NS)
def test_tangent_constants_follow_the_docstring(ref, n: int) -> None:
    assert tangent_constants(n) == ref.tangent_constants(n)
    assert all(0 < c < 1 << 16 for _, c in tangent_constants(n)), "every constant is below 2^16"
    assert boundaries(n) == [(k - 0.5) * 90 / n for k in range(1, n + 1)]
    assert 45.0 not in boundaries(n)


@pytest.mark.parametrize("n", NS)
@pytest.mark.parametrize("r", [1, 7, 1000, (1 << 21) - 1])
def test_axes_and_diagonals(n: int, r: int) -> None:
    cases = {
        (r, 0): 0,  # +x
        (0, r): n,  # +y: down on screen, a quarter turn clockwise
        (-r, 0): 2 * n,
        (0, -r): 3 * n,
        (r, r): n // 2,  # 45 degrees is the centre of sector N/2
        (-r, r): n + n // 2,
        (-r, -r): 2 * n + n // 2,
        (r, -r): 3 * n + n // 2,
    }
    for (m10, m01), expected in cases.items():
        assert sector_of(m10, m01, n) == expected, f"N={n}: (m10={m10}, m01={m01})"


@pytest.mark.parametrize("n", NS)
def test_zero_vector_is_sector_0(n: int) -> None:
    assert sector_of(0, 0, n) == 0
    assert int(quantise(0, 0, n)) == 0, "scalar inputs"


@pytest.mark.parametrize("n", NS)
@pytest.mark.parametrize("margin", [0.2, 0.01])
def test_angles_either_side_of_every_boundary(n: int, margin: float) -> None:
    step = 360.0 / (4 * n)
    for k in range(4 * n):  # the boundary between sector k and k + 1 is at (k + 0.5) * step
        for offset, expected in ((-margin, k), (margin, (k + 1) % (4 * n))):
            angle = (k + 0.5 + offset) * step
            m10, m01 = vector_at(angle)
            got = sector_of(m10, m01, n)
            assert got == expected, f"N={n}: angle {angle:.4f} deg (m10={m10}, m01={m01}) -> {got}, expected {expected}"


@pytest.mark.parametrize("n", NS)
def test_fixed_point_boundary_test_is_inclusive(ref, n: int) -> None:
    # On the fixed-point boundary itself the comparison is '>=': the boundary is reached.
    one = 1 << 16
    for k, (uses_cot, const) in enumerate(ref.tangent_constants(n), start=1):
        if uses_cot:  # b * COT >= a * 2^16
            on, below = (const, one), (const + 1, one)
        else:  # b * 2^16 >= a * TAN
            on, below = (one, const), (one, const - 1)
        assert sector_of(*on, n) == k % (4 * n), f"N={n}, boundary {k}: (m10, m01)={on} is on it"
        assert sector_of(*below, n) == k - 1, f"N={n}, boundary {k}: (m10, m01)={below} is just below it"


@pytest.mark.parametrize("n", NS)
def test_small_vectors_exhaustively_against_naive_rule(ref, n: int) -> None:
    r = 24
    m10, m01 = np.mgrid[-r : r + 1, -r : r + 1]
    got = quantise(m10.ravel(), m01.ravel(), n)
    for a, b, s in zip(m10.ravel().tolist(), m01.ravel().tolist(), got.tolist(), strict=True):
        assert s == ref.sector(a, b, n), f"N={n}: (m10={a}, m01={b}) -> {s}, expected {ref.sector(a, b, n)}"


@pytest.mark.parametrize("n", NS)
def test_90_degree_rotation_moves_the_sector_by_n(n: int) -> None:
    rng = np.random.default_rng(n)
    big = rng.integers(-(1 << 21) + 1, 1 << 21, (20000, 2))
    small = np.mgrid[-3:4, -3:4].reshape(2, -1).T
    v = np.concatenate([big, small])
    v = v[(v[:, 0] != 0) | (v[:, 1] != 0)]
    m10, m01 = v[:, 0], v[:, 1]
    s = quantise(m10, m01, n)
    for turns, (r10, r01) in enumerate([(-m01, m10), (-m10, -m01), (m01, -m10)], start=1):
        rot = quantise(r10, r01, n)
        bad = np.nonzero(rot != (s + turns * n) % (4 * n))[0]
        i = int(bad[0]) if len(bad) else 0
        assert len(bad) == 0, (
            f"N={n}, {90 * turns} deg: (m10={m10[i]}, m01={m01[i]}) is sector {s[i]}, rotated ({r10[i]}, {r01[i]}) "
            f"is {rot[i]}"
        )


@pytest.mark.parametrize("n", NS)
def test_against_float_atan2_away_from_boundaries(n: int) -> None:
    rng = np.random.default_rng(100 + n)
    v = rng.integers(-(1 << 20), 1 << 20, (50000, 2))
    m10, m01 = v[:, 0], v[:, 1]
    pos = np.degrees(np.arctan2(m01.astype(np.float64), m10.astype(np.float64))) % 360.0 / (360.0 / (4 * n))
    near = np.abs(pos - np.floor(pos) - 0.5) < 0.001  # within a thousandth of a sector of a boundary
    expected = np.floor(pos + 0.5).astype(np.int64) % (4 * n)
    got = quantise(m10, m01, n)
    bad = np.nonzero((got != expected) & ~near)[0]
    i = int(bad[0]) if len(bad) else 0
    assert len(bad) == 0, f"N={n}: (m10={m10[i]}, m01={m01[i]}) -> {got[i]}, atan2 says {expected[i]}"
    assert near.mean() < 0.01


def test_sector_angle_deg() -> None:
    assert float(sector_angle_deg(0, 8)) == 0.0
    assert float(sector_angle_deg(8, 8)) == 90.0
    assert float(sector_angle_deg(3, 4)) == 67.5
    assert float(sector_angle_deg(63, 16)) == 354.375
