# SPDX-License-Identifier: MIT
"""orb_orient_moments against golden_model.orientation.moments, position by position.

Frames are streamed as 31-pixel column words in raster order of the positions (x, y), y >= 30:
the word at (x, y) holds rows y-30..y of column x, slice k = row y - k. The output for (x, y) is
the patch whose rightmost column is x and bottom row y, i.e. centred at (x - 15, y - 15); it is
compared with the model wherever the patch lies on one line (x >= 30), and every output must leave
exactly ORIENT_MOMENTS_LAT clocks after its input with its tag. The entity never clears its sums, so frames
simply follow each other in one stream. Stimulus: smoothed photograph crops; flat 0 and 255;
one bright pixel at every (u, v) of the 31 x 31 square around the centre and just beyond it in u
(the circle's shape, pixel by pixel); ramps and steps in x and y of both signs (large moments);
random noise.
"""

from __future__ import annotations

import cocotb
import numpy as np

from golden_model.latency import ORIENT_MOMENTS_LAT
from golden_model.orientation import moments
from golden_model.smooth import smooth
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, random_gaps, reset, to_int

SPAN = 31  # patch diameter: column word height and window width
BITS = 24


def signed(value: int | None) -> int | None:
    if value is None:
        return None
    return value - (1 << BITS) if value >> (BITS - 1) else value


class Frames:
    """Accumulates column-word items and the expected moments of the positions to check."""

    def __init__(self) -> None:
        self.items: list[tuple[int, int, int]] = []
        self.expected: list[tuple[int, int] | None] = []  # None: patch not on one line
        self.labels: list[str] = []

    def add(self, img: np.ndarray, label: str) -> None:
        img = np.ascontiguousarray(img, dtype=np.uint8)
        h, w = img.shape
        assert h >= SPAN and w >= SPAN
        ys, xs = np.mgrid[SPAN - 1 : h, SPAN - 1 : w]
        m10, m01 = moments(img, xs.ravel() - 15, ys.ravel() - 15)
        ref = {(int(x), int(y)): (int(a), int(b)) for x, y, a, b in zip(xs.ravel(), ys.ravel(), m10, m01, strict=True)}
        for y in range(SPAN - 1, h):
            for x in range(w):
                col = img[y - SPAN + 1 : y + 1, x][::-1]  # slice k = row y - k
                self.items.append((x, y, int.from_bytes(col.tobytes(), "little")))
                self.expected.append(ref.get((x, y)))
                self.labels.append(label)


async def check(dut, frames: Frames, seed: int) -> None:
    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_col": 0})
    outputs = [dut.out_x, dut.out_y, dut.out_m10, dut.out_m01]
    stream = Stream(dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_col], outputs, [dut.out_valid])
    n = len(frames.items)
    await stream.run(frames.items, random_gaps(n, seed=seed, prob=0.2, long_every=500), tail=ORIENT_MOMENTS_LAT + 4)
    out_edges = [e for e, _ in stream.samples]
    assert out_edges == [e + ORIENT_MOMENTS_LAT for e in stream.in_edges], (
        f"outputs are not the inputs delayed by {ORIENT_MOMENTS_LAT} clocks ({len(out_edges)} outputs, {n} inputs)"
    )
    checked = 0
    for (x, y, _), exp, label, (_, (xv, yv, m10v, m01v)) in zip(
        frames.items, frames.expected, frames.labels, stream.samples, strict=True
    ):
        assert (to_int(xv), to_int(yv)) == (x, y), f"{label}: tag (x={x}, y={y}) came out as {(to_int(xv), to_int(yv))}"
        if exp is None:
            continue
        got = (signed(to_int(m10v)), signed(to_int(m01v)))
        assert got == exp, f"{label}, centre (x={x - 15}, y={y - 15}): (m10, m01) = {got}, model {exp}"
        checked += 1
    assert checked > 0.4 * n, f"only {checked} of {n} positions checked"


@cocotb.test()
async def photos(dut) -> None:
    frames = Frames()
    for name in ("camera", "astronaut", "coffee"):
        frames.add(smooth(images.photo(name, 64, 40)), f"photo {name}")
    await check(dut, frames, seed=1)


@cocotb.test()
async def synthetic(dut) -> None:
    frames = Frames()
    frames.add(np.full((32, 64), 255), "flat 255")
    frames.add(np.zeros((31, 64)), "flat 0")
    # one bright pixel per row v of the window, 40 columns apart: as the window slides over it,
    # it takes every offset u in -15..15 (and beyond) of that row
    pitch = 40
    dots = np.zeros((SPAN, pitch * (SPAN + 1)), dtype=np.uint8)
    for r in range(SPAN):
        dots[r, pitch + pitch * r] = 255 - 3 * r
    frames.add(dots, "single pixel")
    xx = np.arange(64)[None, :].repeat(32, axis=0)
    yy = np.arange(32)[:, None].repeat(64, axis=1)
    frames.add(4 * xx, "ramp in x")
    frames.add(255 - 4 * xx, "falling ramp in x")
    frames.add(8 * yy, "ramp in y")
    frames.add(255 - 8 * yy, "falling ramp in y")
    frames.add(np.where(xx >= 32, 255, 0), "step in x")
    frames.add(np.where(xx < 32, 255, 0), "falling step in x")
    frames.add(np.where(yy >= 16, 255, 0), "step in y")
    frames.add(np.where(yy < 16, 255, 0), "falling step in y")
    frames.add(images.noise(64, 40, seed=5), "random noise")
    await check(dut, frames, seed=2)


def test_orient_moments() -> None:
    run("orb_orient_moments", "test_orb_orient_moments", {}, env=SIM_ENV)
