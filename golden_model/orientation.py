# SPDX-License-Identifier: MIT
"""Intensity-centroid orientation over a circular radius-15 patch, quantised into 4N sectors.

Patch: the pixels (u, v) with |v| <= 15 and |u| <= UMAX[|v|]. UMAX follows OpenCV's construction:
round(sqrt(15^2 - v^2)) for the rows up to 15*sqrt(2)/2, and the rest filled so that the shape is
symmetric under transposition, hence under 90-degree rotation. By that symmetry UMAX[|u|] is also
the half-height of column u, so the moments have a column form the hardware can follow:

    S_u = sum_{|v| <= UMAX[|u|]} p(x+u, y+v)          (column sum at offset u)
    T_u = sum_{|v| <= UMAX[|u|]} v * p(x+u, y+v)      (column first moment)
    m10 = sum_u u * S_u,    m01 = sum_u T_u

p is the smoothed image. The moments are exact integers (|m| < 2^21).

Quantisation: sector s covers the angles within half a sector of s * 360 / (4N) degrees, where
the angle is atan2(m01, m10) with y growing downwards (so sectors advance clockwise on screen).
The quadrant q comes from the signs; (a, b) are the magnitudes along the quadrant's first and
second axes:

    q=0: m10 > 0,  m01 >= 0: a = m10,  b = m01
    q=1: m10 <= 0, m01 > 0:  a = m01,  b = -m10
    q=2: m10 < 0,  m01 <= 0: a = -m10, b = -m01
    q=3: m10 >= 0, m01 < 0:  a = -m01, b = m10

The local sector j (0..N) counts the boundaries beta_k = (k - 1/2) * 90/N degrees, k = 1..N,
that the angle atan(b/a) has reached, each tested in 16-bit fixed point without division:

    beta_k < 45 degrees: b * 2^16 >= a * TAN[k]       TAN[k] = round(tan(beta_k) * 2^16)
    beta_k > 45 degrees: b * COT[k] >= a * 2^16       COT[k] = round(tan(90deg - beta_k) * 2^16)

(45 degrees is never a boundary for N = 4, 8, 16; every constant is below 2^16.)
sector = (q * N + j) mod 4N. m10 = m01 = 0 (a perfectly balanced patch) gives sector 0.
Because a 90-degree rotation maps (m10, m01) to (-m01, m10) and the rule only uses (a, b) and q,
it moves every sector by exactly N.
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

PATCH_RADIUS = 15
TAN_BITS = 16


def _umax() -> tuple[int, ...]:
    r = PATCH_RADIUS
    vmax = math.floor(r * math.sqrt(2.0) / 2 + 1)
    vmin = math.ceil(r * math.sqrt(2.0) / 2)
    umax = [0] * (r + 1)
    for v in range(vmax + 1):
        umax[v] = round(math.sqrt(r * r - v * v))
    # Fill the steep rows from the flat ones so that the shape is symmetric under transposition.
    v0 = 0
    for v in range(r, vmin - 1, -1):
        while umax[v0] == umax[v0 + 1]:
            v0 += 1
        umax[v] = v0
        v0 += 1
    return tuple(umax)


UMAX: tuple[int, ...] = _umax()


def patch_mask() -> np.ndarray:
    """(31, 31) boolean mask of the circular patch, indexed [v + 15, u + 15]."""
    r = PATCH_RADIUS
    off = np.arange(-r, r + 1)
    limit = np.array(UMAX)[np.abs(off)]
    return np.abs(off)[None, :] <= limit[:, None]


def moments(smoothed: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """m10, m01 (int64) of the patches centred at (xs, ys), in the column form of the module doc.

    Every centre must be at least 15 pixels from the border.
    """
    r = PATCH_RADIUS
    off = np.arange(-r, r + 1)
    # cols[k, v, u] = p(x_k + u, y_k + v)
    cols = smoothed[ys[:, None, None] + off[None, :, None], xs[:, None, None] + off[None, None, :]]
    cols = cols.astype(np.int64)
    inside = patch_mask()
    s_u = np.where(inside, cols, 0).sum(axis=1)  # (K, 31) column sums
    t_u = np.where(inside, cols * off[None, :, None], 0).sum(axis=1)  # (K, 31) column moments
    m10 = (s_u * off[None, :]).sum(axis=1)
    m01 = t_u.sum(axis=1)
    return m10, m01


def boundaries(n: int) -> list[float]:
    """Sector boundary angles beta_k in degrees, k = 1..N."""
    return [(k - 0.5) * 90.0 / n for k in range(1, n + 1)]


@cache
def tangent_constants(n: int) -> tuple[tuple[bool, int], ...]:
    """Per boundary k = 1..N: (uses_cot, constant). See the module doc."""
    out = []
    for beta in boundaries(n):
        uses_cot = beta > 45.0
        value = math.tan(math.radians(90.0 - beta if uses_cot else beta)) * (1 << TAN_BITS)
        out.append((uses_cot, math.floor(value + 0.5)))  # round half away from zero (value > 0)
    return tuple(out)


def quantise(m10: np.ndarray, m01: np.ndarray, n: int) -> np.ndarray:
    """Sector index 0..4N-1 for each (m10, m01) pair."""
    m10 = np.asarray(m10, dtype=np.int64)
    m01 = np.asarray(m01, dtype=np.int64)
    q = np.select(
        [(m10 > 0) & (m01 >= 0), (m10 <= 0) & (m01 > 0), (m10 < 0) & (m01 <= 0), (m10 >= 0) & (m01 < 0)],
        [0, 1, 2, 3],
        default=0,
    )
    a = np.select([q == 0, q == 1, q == 2, q == 3], [m10, m01, -m10, -m01])
    b = np.select([q == 0, q == 1, q == 2, q == 3], [m01, -m10, -m01, m10])
    one = 1 << TAN_BITS
    j = np.zeros(m10.shape, dtype=np.int64)
    for uses_cot, const in tangent_constants(n):
        reached = (b * const >= a * one) if uses_cot else (b * one >= a * const)
        j += reached
    sector = (q * n + j) % (4 * n)
    zero = (m10 == 0) & (m01 == 0)
    return np.where(zero, 0, sector).astype(np.int64)


def sector_angle_deg(sector: np.ndarray | int, n: int) -> np.ndarray | float:
    """Centre angle of a sector in degrees (clockwise on screen from the +x axis)."""
    return np.asarray(sector) * (360.0 / (4 * n))
