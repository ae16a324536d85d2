# SPDX-License-Identifier: MIT
"""orb_orient_sector against golden_model.orientation.quantise, for SECTORS_g = 16, 32 and 64 (N = 4, 8 and 16).

Every output must leave exactly ORIENT_SECTOR_LAT clocks after its input with its tag. Stimulus: the moments
of photographs' smoothed patches; exact boundary cases, for every boundary k and quadrant, pairs
(a, b) with b * 2^16 - a * TAN[k] (or b * COT[k] - a * 2^16) equal to -g, 0 and +g, g the
smallest step the constant allows (1 for odd constants), at small and large magnitudes (these
also pin each constant the VHDL computes at elaboration); the zero vector, the axes of both
signs, the extremes +-(2^21 - 1), any 24-bit value, and random vectors.
"""

from __future__ import annotations

import math

import cocotb
import numpy as np
import pytest

from golden_model.latency import ORIENT_SECTOR_LAT
from golden_model.orientation import TAN_BITS, moments, quantise, tangent_constants
from golden_model.smooth import smooth
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, random_gaps, reset, to_int

BITS = 24
MAX = (1 << 21) - 1
ONE = 1 << TAN_BITS


def from_quadrant(q: int, a: int, b: int) -> tuple[int, int]:
    """(m10, m01) whose quadrant-q magnitudes are (a, b) (golden_model.orientation's table)."""
    return [(a, b), (-b, a), (-a, -b), (b, -a)][q]


def boundary_pairs(n: int) -> list[tuple[int, int]]:
    """(a, b) pairs at each boundary's exact test value -g, 0 and +g (g = gcd(constant, 2^16): every
    difference is a multiple of it, so +-1 exactly when the constant is odd)."""
    pairs: list[tuple[int, int]] = []
    for k, (uses_cot, c) in enumerate(tangent_constants(n), start=1):
        seen: set[int] = set()
        g = math.gcd(c, ONE)
        step = ONE // g
        inv = pow(c // g, -1, step) if step > 1 else 0
        for delta in (-g, 0, g):
            # solve  x * c = ONE * y + s  with s = -delta (TAN form, x = a, y = b) or delta (COT, x = b, y = a)
            s = delta if uses_cot else -delta
            x0 = ((s // g) * inv) % step if step > 1 else 0
            for t in (0, 1, 2, 37, 1000, (MAX - x0) // step - 1, (MAX - x0) // step):
                x = x0 + t * step
                if x <= 0 or x > MAX or (x * c - s) % ONE:
                    continue
                y = (x * c - s) // ONE
                if y < 0:
                    continue
                a, b = (y, x) if uses_cot else (x, y)
                if a == 0:
                    continue
                diff = b * c - a * ONE if uses_cot else b * ONE - a * c
                assert diff == delta
                seen.add(delta)
                pairs.append((a, b))
        assert seen == {-g, 0, g}, f"boundary {k} of N = {n}: differences {seen} only"
    return pairs


async def check(dut, vectors: list[tuple[int, int]], labels: list[str], n: int, seed: int) -> None:
    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_m10": 0, "in_m01": 0})
    mask = (1 << BITS) - 1
    items = [(i % 4096, (i * 7) % 4096, m10 & mask, m01 & mask) for i, (m10, m01) in enumerate(vectors)]
    expected = quantise(np.array([v[0] for v in vectors]), np.array([v[1] for v in vectors]), n)
    stream = Stream(dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_m10, dut.in_m01],
                    [dut.out_x, dut.out_y, dut.out_sector], [dut.out_valid])  # fmt: skip
    await stream.run(items, random_gaps(len(items), seed=seed, prob=0.2, long_every=400), tail=ORIENT_SECTOR_LAT + 4)
    out_edges = [e for e, _ in stream.samples]
    assert out_edges == [e + ORIENT_SECTOR_LAT for e in stream.in_edges], (
        f"outputs are not the inputs delayed by {ORIENT_SECTOR_LAT} clocks "
        f"({len(out_edges)} outputs, {len(items)} inputs)"
    )
    for (x, y, _, _), (m10, m01), exp, label, (_, (xv, yv, sv)) in zip(
        items, vectors, expected, labels, stream.samples, strict=True
    ):
        assert (to_int(xv), to_int(yv)) == (x, y), f"{label}: tag (x={x}, y={y}) came out as {(to_int(xv), to_int(yv))}"
        got = to_int(sv)
        assert got == int(exp), f"{label}, (m10, m01) = ({m10}, {m01}), N = {n}: sector {got}, model {int(exp)}"


@cocotb.test()
async def photo_moments(dut) -> None:
    n = env_int("ORB_SECTORS") // 4  # N, the sectors per quadrant
    vectors: list[tuple[int, int]] = []
    for name in ("camera", "astronaut", "coffee"):
        img = smooth(images.photo(name, 72, 56))
        ys, xs = np.mgrid[15 : img.shape[0] - 15, 15 : img.shape[1] - 15]
        m10, m01 = moments(img, xs.ravel(), ys.ravel())
        vectors += [(int(a), int(b)) for a, b in zip(m10, m01, strict=True)]
    assert len(set(quantise(np.array([v[0] for v in vectors]), np.array([v[1] for v in vectors]), n))) == 4 * n
    await check(dut, vectors, ["photo moments"] * len(vectors), n, seed=1)


@cocotb.test()
async def directed(dut) -> None:
    n = env_int("ORB_SECTORS") // 4  # N, the sectors per quadrant
    rng = np.random.default_rng(n)
    vectors: list[tuple[int, int]] = []
    labels: list[str] = []

    def add(m10: int, m01: int, label: str) -> None:
        vectors.append((int(m10), int(m01)))
        labels.append(label)

    for q in range(4):
        for a, b in boundary_pairs(n):
            add(*from_quadrant(q, a, b), f"boundary case, quadrant {q}")
    add(0, 0, "zero")
    for m in (1, 2, 3, 1000, MAX):
        for m10, m01 in ((m, 0), (-m, 0), (0, m), (0, -m), (m, m), (-m, m), (-m, -m), (m, -m)):
            add(m10, m01, "axis or diagonal")
    for m10 in (-MAX, -1, 0, 1, MAX):
        for m01 in (-MAX, -1, 0, 1, MAX):
            add(m10, m01, "extreme")
    full = (1 << (BITS - 1)) - 1
    for m10 in (-full - 1, -full, full):
        for m01 in (-full - 1, -full, 0, 1, full):
            add(m10, m01, "24-bit extreme")
    for _ in range(1500):
        add(*rng.integers(-MAX, MAX + 1, 2), "random")
    for _ in range(500):
        mag = np.exp(rng.uniform(0, math.log(MAX), 2)).astype(np.int64)
        add(*(mag * rng.choice((-1, 1), 2)), "random, log-uniform magnitude")
    await check(dut, vectors, labels, n, seed=2)


@pytest.mark.parametrize("sectors", [16, 32, 64])
def test_orient_sector(sectors: int) -> None:
    run("orb_orient_sector", "test_orb_orient_sector", {"SECTORS_g": sectors}, env=SIM_ENV)
