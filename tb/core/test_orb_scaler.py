# SPDX-License-Identifier: MIT
"""orb_scaler against golden_model.scaler.downscale.

Frames of odd and even widths and heights (photographs and random images) are streamed back to
back with (x, y) and random input gaps. Every 2x2 block must produce exactly one output, two clocks
after its bottom-right input pixel, tagged with its position in the reduced image and equal to
downscale(frame); an odd last column or row must produce nothing. The chained runners feed the
scaler what a first scaler emits (the reduced image at a quarter rate, in bursts on odd lines) and
compare with the second reduction.
"""

from __future__ import annotations

import cocotb
import numpy as np
import pytest

from golden_model.latency import SCALER_LAT
from golden_model.scaler import downscale
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, env_str, make_frame, parse_frames, random_gaps, reset, to_int


def chained_gaps(w: int, h: int) -> list[int]:
    """Idle clocks before each pixel of a w x h image when it is the output of a first scaler fed
    one pixel per clock with a 2w x 2h image: outputs every other clock on odd input lines."""
    gaps = []
    for y in range(h):
        for x in range(w):
            gaps.append(2 * w + 1 if x == 0 and y > 0 else (2 if x == 0 else 1))
    return gaps


@cocotb.test()
async def scaler_frames(dut) -> None:
    width = env_int("ORB_LINE_WIDTH")
    chained = env_str("ORB_CHAINED", "0") == "1"
    frames: list[np.ndarray] = []
    gaps: list[int] = []
    for i, (kind, height) in enumerate(parse_frames(env_str("ORB_FRAMES"))):
        if chained:  # the frame a first scaler makes of a (2 W) x (2 H) image, at its pace
            img = downscale(make_frame(kind, 2 * width, 2 * height, seed=20 + i).astype(np.uint8))
            gaps += chained_gaps(width, height)
        else:
            img = make_frame(kind, width, height, seed=20 + i).astype(np.uint8)
            gaps += random_gaps(img.size, seed=width + 7 * i, prob=0.3, long_every=300)
        frames.append(img)
    where_of = [(f, x, y) for f, img in enumerate(frames) for y in range(img.shape[0]) for x in range(width)]
    items = [(x, y, int(frames[f][y, x])) for f, x, y in where_of]

    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_data": 0})
    stream = Stream(
        dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_data], [dut.out_x, dut.out_y, dut.out_data], [dut.out_valid]
    )
    await stream.run(items, gaps, tail=4)

    got = {e: (to_int(x), to_int(y), to_int(d)) for e, (x, y, d) in stream.samples}
    checked = 0
    for f, img in enumerate(frames):
        h = img.shape[0]
        small = downscale(img)
        base = sum(fr.size for fr in frames[:f])
        for y in range(h):
            for x in range(width):
                edge = stream.in_edges[base + y * width + x] + SCALER_LAT
                where = f"frame {f} ({width}x{h}), input pixel (x={x}, y={y})"
                if x % 2 == 1 and y % 2 == 1 and x < 2 * (width // 2) and y < 2 * (h // 2):
                    exp = (x // 2, y // 2, int(small[y // 2, x // 2]))
                    assert edge in got, f"{where}: no output for reduced pixel (x={exp[0]}, y={exp[1]})"
                    out = got.pop(edge)
                    assert out == exp, f"{where}: output (x, y, value) {out} != expected {exp}"
                    checked += 1
                elif edge in got:
                    raise AssertionError(f"{where}: unexpected output {got[edge]} (no block completes here)")
    assert not got, f"{len(got)} outputs at no input's expected time, first {min(got.items())}"
    assert checked == sum((fr.shape[0] // 2) * (width // 2) for fr in frames)
    dut._log.info("%d reduced pixels checked over %d frames", checked, len(frames))


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_scaler(width: int, frames: str, chained: bool = False) -> None:
    run(
        "orb_scaler",
        "test_orb_scaler",
        {"LINE_WIDTH_g": width},
        env={**SIM_ENV, "ORB_FRAMES": frames, "ORB_CHAINED": "1" if chained else "0"},
    )


@pytest.mark.parametrize(
    ("width", "frames"),
    [
        (2, "random@2,random@3,photo:camera@4"),  # smallest line; an odd last row
        (9, "photo:coffee@7,random@8,photo:rocket@3"),  # odd width, odd and even heights
        (64, "photo:astronaut@48,random@5"),
        (65, "photo:chelsea@49,random@4"),
        (640, "photo:camera@5,random@2"),
    ],
)
def test_scaler(width: int, frames: str) -> None:
    run_scaler(width, frames)


@pytest.mark.parametrize(("width", "frames"), [(32, "photo:astronaut@24,photo:coffee@24"), (33, "photo:rocket@25")])
def test_scaler_chained(width: int, frames: str) -> None:
    run_scaler(width, frames, chained=True)
