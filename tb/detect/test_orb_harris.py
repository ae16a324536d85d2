# SPDX-License-Identifier: MIT
"""orb_harris against golden_model.response, window by window in raster order.

The flat 49 x 8-bit window is driven directly, as orb_window would present a frame: for every
pixel (x, y) of the frame in raster order the 7x7 window whose newest (bottom-right) pixel it is,
with the previous line's (or frame's) pixels where the window reaches past the left or top border.
The centre is (x - 3, y - 3); the expected code is response_map(frame) there, and 0 whenever
x < 6 or y < 6 (the border rule). Every output must appear exactly HARRIS_LAT_c = 17 clocks after
its input, keep its tag, and hold the model's code. Random input gaps (the sums slide with the
valid windows, not with the clock).

Frames: real photographs at several sizes, random noise (negative and positive R of every size),
full-contrast patterns that reach the widths' extremes (a step edge, a one-pixel checkerboard, a
corner, two-pixel checks), a flat frame (R = 0), and frames back to back (a frame's first
positions hold the previous frame's columns). A check that the stimulus reaches every code range
makes the test fail if the frames stop exercising them.
"""

from __future__ import annotations

import re
from pathlib import Path

import cocotb
import numpy as np

from golden_model import response
from golden_model.latency import HARRIS_LAT
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, random_gaps, reset, to_int, window_word

ROOT = Path(__file__).resolve().parents[2]


def raster_windows(img: np.ndarray, prev: np.ndarray | None) -> list[int]:
    """The window words orb_window presents for img in raster order (prev: the frame before)."""
    h, w = img.shape
    before = prev if prev is not None else np.zeros_like(img)
    # the stream as orb_window sees it: previous frame, then this one, line after line
    stream = np.concatenate([before.reshape(-1), img.reshape(-1)])
    lines = stream.reshape(-1, w)
    out = []
    first = before.shape[0]
    for y in range(h):
        for x in range(w):
            win = np.zeros((7, 7), dtype=np.uint8)
            for r in range(7):
                line = lines[first + y - 6 + r]
                for c in range(7):
                    xx = x - 6 + c
                    # left of the border: the previous line's pixels (the column registers' past)
                    win[r, c] = line[xx] if xx >= 0 else lines[first + y - 6 + r - 1][w + xx]
            out.append(window_word(win))
    return out


def frame_items(img: np.ndarray, prev: np.ndarray | None) -> tuple[list[tuple[int, int, int]], list[int]]:
    h, w = img.shape
    codes = response.response_map(img)
    items, expected = [], []
    for (y, x), word in zip(np.ndindex(h, w), raster_windows(img, prev), strict=True):
        items.append((x, y, word))
        expected.append(int(codes[y - 3, x - 3]) if x >= 6 and y >= 6 else 0)
    return items, expected


async def check_frames(dut, frames: list[tuple[str, np.ndarray]], seed: int) -> list[int]:
    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_win": 0})
    items: list[tuple[int, int, int]] = []
    expected: list[int] = []
    labels: list[str] = []
    prev = None
    for name, img in frames:
        it, ex = frame_items(img, prev)
        items += it
        expected += ex
        labels += [name] * len(it)
        prev = img
    stream = Stream(dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_win], [dut.out_x, dut.out_y, dut.out_code],
                    [dut.out_valid])  # fmt: skip
    await stream.run(items, random_gaps(len(items), seed=seed, prob=0.2, long_every=700), tail=HARRIS_LAT + 3)
    out_edges = [e for e, _ in stream.samples]
    want_edges = [e + HARRIS_LAT for e in stream.in_edges]
    if out_edges != want_edges:
        i = next((i for i, (a, b) in enumerate(zip(out_edges, want_edges, strict=False)) if a != b), len(want_edges))
        raise AssertionError(f"outputs are not the inputs delayed by {HARRIS_LAT} clocks: {len(out_edges)} outputs for "
                             f"{len(items)} inputs, first difference at output {i}")  # fmt: skip
    bad = []
    for (x, y, _), exp, label, (_, (xv, yv, cv)) in zip(items, expected, labels, stream.samples, strict=True):
        assert (to_int(xv), to_int(yv)) == (x, y), f"{label}: tag (x={x}, y={y}) came out as ({xv}, {yv})"
        got = to_int(cv)
        if got != exp:
            bad.append(f"{label}: centre (x={x - 3}, y={y - 3}): code {got}, model {exp}")
    assert not bad, f"{len(bad)} mismatches, the first: " + "; ".join(bad[:12])
    return expected


@cocotb.test()
async def photographs(dut) -> None:
    """Photograph crops back to back, with input gaps."""
    frames = [(f"{n} {w}x{h}", images.photo(n, w, h)) for n, w, h in
              (("camera", 40, 24), ("astronaut", 40, 24), ("coffee", 40, 24), ("chelsea", 40, 24))]  # fmt: skip
    got = await check_frames(dut, frames, seed=1)
    assert len(set(got)) > 20, f"the photographs reach only {len(set(got))} distinct codes"


@cocotb.test()
async def extremes(dut) -> None:
    """Noise (R of every sign and size) and full-contrast patterns at the widths' limits."""
    rng = np.random.default_rng(7)
    yy, xx = np.mgrid[0:16, 0:18]
    patterns = {
        "step edge": (xx >= 9) * 255,
        "checkerboard 1": ((xx + yy) % 2) * 255,
        "corner": ((xx >= 9) & (yy >= 8)) * 255,
        "checks 2": ((xx // 2 + yy // 2) % 2) * 255,
        "checks 3": ((xx // 3 + yy // 3) % 2) * 255,
        "grid lines": (((xx % 4) == 0) | ((yy % 4) == 0)) * 255,
        "inverted corner": 255 - ((xx >= 9) & (yy >= 8)) * 255,
        "flat": np.full((16, 18), 77),
        "noise": rng.integers(0, 256, (16, 18)),
        "dim noise": rng.integers(100, 108, (16, 18)),
    }
    frames = [(name, p.astype(np.uint8)) for name, p in patterns.items()]
    got = await check_frames(dut, frames, seed=2)
    codes = set(got)
    # the grid lines reach 56, the largest code an 8-bit image was found to give (R <= 0.07 * 2^32)
    assert 0 in codes and max(codes) >= 56, f"codes {sorted(codes)}: the largest responses are not reached"
    assert min(c for c in codes if c) <= 6, f"codes {sorted(codes)}: the smallest responses are not reached"


def test_response_constants_match_the_model() -> None:
    """orb_fast_pkg's RESPONSE_BITS_c against the model (HARRIS_LAT_c: tb/common/test_orb_latency_pkg.py)."""
    text = (ROOT / "hdl" / "detect" / "orb_fast_pkg.vhd").read_text()
    consts = {m[0]: int(m[1]) for m in re.findall(r"constant (\w+)_c\s*:\s*positive\s*:=\s*(\d+);", text)}
    assert consts["RESPONSE_BITS"] == response.RESPONSE_BITS
    assert (1 << response.RESPONSE_BITS) > response.MAX_CODE


def test_orb_harris() -> None:
    run("orb_harris", "test_orb_harris", {}, env=SIM_ENV)
