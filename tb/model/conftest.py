# SPDX-License-Identifier: MIT
"""Shared fixtures of the golden-model unit tests: the photographs and the naive loop references.

The references in ``NaiveReference`` are written straight from the golden_model module docstrings,
pixel by pixel with plain Python integers, and share no code with the model. The only model data
they use is the rBRIEF orbit seeds (``pattern_data.ORBIT_SEEDS``), which are an input of the
specification, not a computation.
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest

from golden_model.features import Features
from golden_model.pattern_data import ORBIT_SEEDS
from orb_tools.images import sample_photographs

Grid = list[list[int]]
Row = tuple[int, int, int, int, int, str]  # (scale, y, x, score, sector, descriptor hex)

# Every constant below is transcribed from a docstring (or derived from it as commented).
KERNEL = (5, 8, 12, 14, 12, 8, 5)  # smooth.py
UMAX = (15, 15, 15, 15, 14, 14, 14, 13, 13, 12, 11, 10, 9, 8, 6, 3)  # OpenCV's radius-15 table, by hand
DESC_BORDER = 18  # pipeline.py: patch radius 15 + smoothing radius 3
ONE = 1 << 16  # orientation.py: 16-bit fixed point


def _bresenham_circle() -> tuple[tuple[int, int], ...]:
    """The 16-pixel radius-3 Bresenham circle, clockwise on screen (y down) from straight up.

    Derived, not copied: its pixels are exactly those with 8 <= dx^2 + dy^2 <= 10.
    """
    pts = [(dx, dy) for dy in range(-3, 4) for dx in range(-3, 4) if 8 <= dx * dx + dy * dy <= 10]
    # Clockwise on screen from "up" (0, -3): the angle atan2(dx, -dy) grows from 0 to 2 pi.
    pts.sort(key=lambda p: math.atan2(p[0], -p[1]) % (2 * math.pi))
    return tuple(pts)


CIRCLE = _bresenham_circle()


def _round_half_away(v: float) -> int:
    return math.floor(abs(v) + 0.5) * (1 if v >= 0 else -1)


@cache
def _rotated_pattern(n: int, sector: int) -> tuple[tuple[int, int, int, int], ...]:
    """Spec section 10, one point at a time: test j*4N + k of sector s is the seed of orbit j rotated
    by ((k + s) mod 4N) * 360 / 4N degrees (y down), rounded half away from zero."""
    sectors = 4 * n
    out = []
    for i in range(256):
        j, k = divmod(i, sectors)
        x1, y1, x2, y2 = ORBIT_SEEDS[sectors][j]
        alpha = math.radians(((k + sector) % sectors) * 360.0 / sectors)
        c, s = math.cos(alpha), math.sin(alpha)
        out.append(
            (
                _round_half_away(x1 * c - y1 * s),
                _round_half_away(x1 * s + y1 * c),
                _round_half_away(x2 * c - y2 * s),
                _round_half_away(x2 * s + y2 * c),
            )
        )
    return tuple(out)


@cache
def _tangent_constants(n: int) -> tuple[tuple[bool, int], ...]:
    """(uses_cot, constant) per boundary k = 1..N, from the orientation.py docstring and spec section 9."""
    out = []
    for k in range(1, n + 1):
        beta = (k - 0.5) * 90.0 / n
        if beta < 45.0:
            out.append((False, _round_half_away(math.tan(math.radians(beta)) * ONE)))
        else:
            out.append((True, _round_half_away(math.tan(math.radians(90.0 - beta)) * ONE)))
    return tuple(out)


class NaiveReference:
    """Deliberately naive per-pixel implementations of every stage, from the docstrings."""

    circle = CIRCLE
    umax = UMAX
    kernel = KERNEL

    # ---- luma ----------------------------------------------------------------------------------
    @staticmethod
    def luma(r: int, g: int, b: int) -> int:
        return (77 * r + 150 * g + 29 * b + 128) >> 8

    # ---- FAST ----------------------------------------------------------------------------------
    @staticmethod
    def segment_test(c: int, ring: list[int], t: int) -> bool:
        """At least 9 cyclically contiguous ring pixels all brighter (p > c + t) or all darker."""
        for flags in ([p > c + t for p in ring], [p < c - t for p in ring]):
            for start in range(16):
                if all(flags[(start + i) % 16] for i in range(9)):
                    return True
        return False

    @classmethod
    def fast_score(cls, img: np.ndarray, t: int) -> np.ndarray:
        h, w = img.shape
        px: Grid = img.astype(int).tolist()
        out = np.zeros((h, w), dtype=np.int64)
        for y in range(3, h - 3):
            for x in range(3, w - 3):
                c = px[y][x]
                ring = [px[y + dy][x + dx] for dx, dy in cls.circle]
                if cls.segment_test(c, ring, t):
                    out[y, x] = sum(abs(p - c) for p in ring)
        return out

    # ---- NMS -----------------------------------------------------------------------------------
    @staticmethod
    def nms(score: np.ndarray) -> np.ndarray:
        h, w = score.shape
        s: Grid = score.astype(int).tolist()
        keep = np.zeros((h, w), dtype=bool)
        for y in range(h):
            for x in range(w):
                v = s[y][x]
                if v <= 0:
                    continue
                ok = True
                for dy in (-1, 0, 1):
                    for dx in (-1, 0, 1):
                        if dx == 0 and dy == 0:
                            continue
                        yy, xx = y + dy, x + dx
                        nb = s[yy][xx] if 0 <= yy < h and 0 <= xx < w else 0
                        earlier = dy < 0 or (dy == 0 and dx < 0)
                        if (earlier and not v > nb) or (not earlier and not v >= nb):
                            ok = False
                keep[y, x] = ok
        return keep

    # ---- smoothing -----------------------------------------------------------------------------
    @staticmethod
    def smooth_at(px: Grid, x: int, y: int) -> int:
        total = 0
        for j in range(7):
            for i in range(7):
                total += KERNEL[i] * KERNEL[j] * px[y + j - 3][x + i - 3]
        return (total + 2048) >> 12

    @classmethod
    def smooth(cls, img: np.ndarray) -> np.ndarray:
        h, w = img.shape
        px: Grid = img.astype(int).tolist()
        out = np.zeros((h, w), dtype=np.int64)
        for y in range(3, h - 3):
            for x in range(3, w - 3):
                out[y, x] = cls.smooth_at(px, x, y)
        return out

    # ---- scaler --------------------------------------------------------------------------------
    @staticmethod
    def downscale(img: np.ndarray) -> np.ndarray:
        h, w = img.shape
        px: Grid = img.astype(int).tolist()
        out = np.zeros((h // 2, w // 2), dtype=np.uint8)
        for y in range(h // 2):
            for x in range(w // 2):
                total = px[2 * y][2 * x] + px[2 * y][2 * x + 1] + px[2 * y + 1][2 * x] + px[2 * y + 1][2 * x + 1]
                out[y, x] = (total + 2) // 4
        return out

    # ---- orientation ---------------------------------------------------------------------------
    @staticmethod
    def in_patch(u: int, v: int) -> bool:
        return abs(v) <= 15 and abs(u) <= UMAX[abs(v)]

    @classmethod
    def moments(cls, p: np.ndarray | Grid, x: int, y: int) -> tuple[int, int]:
        """m10 = sum u * p(x+u, y+v), m01 = sum v * p(x+u, y+v) over the circular patch."""
        m10 = m01 = 0
        for v in range(-15, 16):
            for u in range(-15, 16):
                if cls.in_patch(u, v):
                    val = int(p[y + v][x + u])
                    m10 += u * val
                    m01 += v * val
        return m10, m01

    @staticmethod
    def tangent_constants(n: int) -> tuple[tuple[bool, int], ...]:
        return _tangent_constants(n)

    @staticmethod
    def sector(m10: int, m01: int, n: int) -> int:
        if m10 == 0 and m01 == 0:
            return 0
        if m10 > 0 and m01 >= 0:
            q, a, b = 0, m10, m01
        elif m10 <= 0 and m01 > 0:
            q, a, b = 1, m01, -m10
        elif m10 < 0 and m01 <= 0:
            q, a, b = 2, -m10, -m01
        else:
            q, a, b = 3, -m01, m10
        j = 0
        for uses_cot, const in _tangent_constants(n):
            if uses_cot:
                j += b * const >= a * ONE
            else:
                j += b * ONE >= a * const
        return (q * n + j) % (4 * n)

    # ---- pattern and descriptor ----------------------------------------------------------------
    @staticmethod
    def rotated_pattern(n: int, sector: int) -> tuple[tuple[int, int, int, int], ...]:
        return _rotated_pattern(n, sector)

    @staticmethod
    def descriptor(sm: np.ndarray | Grid, x: int, y: int, sector: int, n: int) -> bytes:
        out = bytearray(32)
        for i, (x1, y1, x2, y2) in enumerate(_rotated_pattern(n, sector)):
            if int(sm[y + y1][x + x1]) < int(sm[y + y2][x + x2]):
                out[i // 8] |= 1 << (i % 8)
        return bytes(out)

    # ---- the whole pipeline --------------------------------------------------------------------
    @classmethod
    def extract(cls, img: np.ndarray, scales: int, n: int, t: int, mode: str) -> list[Row]:
        """Rows (scale, y, x, score, sector, descriptor hex) in raster order per scale."""
        levels = [img]
        for _ in range(scales - 1):
            levels.append(cls.downscale(levels[-1]))
        rows: list[Row] = []
        for s, level in enumerate(levels):
            h, w = level.shape
            score = cls.fast_score(level, t)
            keep = cls.nms(score)
            sm: Grid = cls.smooth(level).tolist() if mode == "orb" else []
            for y in range(h):
                for x in range(w):
                    if not keep[y, x]:
                        continue
                    if mode == "fast":
                        rows.append((s, y, x, int(score[y, x]), -1, ""))
                    elif DESC_BORDER <= x <= w - 1 - DESC_BORDER and DESC_BORDER <= y <= h - 1 - DESC_BORDER:
                        m10, m01 = cls.moments(sm, x, y)
                        sec = cls.sector(m10, m01, n)
                        rows.append((s, y, x, int(score[y, x]), sec, cls.descriptor(sm, x, y, sec, n).hex()))
        return rows

    # ---- test helpers --------------------------------------------------------------------------
    @staticmethod
    def center_crop(img: np.ndarray, width: int, height: int) -> np.ndarray:
        h, w = img.shape
        y0, x0 = (h - height) // 2, (w - width) // 2
        return np.ascontiguousarray(img[y0 : y0 + height, x0 : x0 + width])

    @staticmethod
    def rows(f: Features) -> list[Row]:
        """A model feature list as reference rows, in the list's own order."""
        return [
            (
                int(f.scale[i]),
                int(f.y[i]),
                int(f.x[i]),
                int(f.score[i]),
                int(f.sector[i]),
                f.descriptor[i].tobytes().hex(),
            )
            for i in range(len(f))
        ]

    @staticmethod
    def rows_diff(got: list[Row], expected: list[Row]) -> str:
        """Where two row lists first differ (scale and coordinates named)."""
        for i, (g, e) in enumerate(zip(got, expected, strict=False)):
            if g != e:
                return (
                    f"row {i}: model has scale {g[0]} (x={g[2]}, y={g[1]}) score={g[3]} sector={g[4]} desc={g[5]}, "
                    f"reference has scale {e[0]} (x={e[2]}, y={e[1]}) score={e[3]} sector={e[4]} desc={e[5]}"
                )
        if len(got) != len(expected):
            longer, who = (got, "model") if len(got) > len(expected) else (expected, "reference")
            g = longer[min(len(got), len(expected))]
            return f"the {who} has {abs(len(got) - len(expected))} extra rows, first scale {g[0]} (x={g[2]}, y={g[1]})"
        return "no difference"

    @staticmethod
    def mismatch(got: np.ndarray, expected: np.ndarray, what: str = "value") -> str:
        """Message naming the first (raster-order) pixel where two maps differ."""
        if got.shape != expected.shape:
            return f"{what}: shape {got.shape} != expected {expected.shape}"
        bad = np.argwhere(np.asarray(got) != np.asarray(expected))
        if len(bad) == 0:
            return f"{what}: no mismatch"
        y, x = (int(v) for v in bad[0])
        return (
            f"{what}: {len(bad)} mismatches, first at (x={x}, y={y}): "
            f"model {got[y, x]!r} != reference {expected[y, x]!r}"
        )


@pytest.fixture(scope="session")
def ref() -> NaiveReference:
    return NaiveReference()


@cache
def _photographs() -> dict[str, np.ndarray]:
    return sample_photographs()


@pytest.fixture(scope="session")
def photographs() -> dict[str, np.ndarray]:
    """scikit-image's real photographs as luma (astronaut, camera, coffee, chelsea, rocket)."""
    return _photographs()
