# SPDX-License-Identifier: MIT
"""orb_resampler against golden_model.scaler.resample (docs/spec.md section 3, "Pyramid step").

Frames (photographs, random images) stream back to back with (x, y) and random input gaps. Each
output pixel (xo, yo) of the model's reduced image must leave exactly RESAMPLER_LAT clocks after the input
pixel that completes it, (i(xo) + 1, j(yo) + 1) with the model's left and upper taps i and j, with
its position and value; no other output may appear. Steps 5:4 (the measured best, issue 14), 3:2
and 2:1 (which must equal orb_scaler's box), at odd and even sizes.
"""

from __future__ import annotations

import cocotb
import numpy as np
import pytest

from golden_model.latency import RESAMPLER_LAT
from golden_model.scaler import _taps, resample
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, env_str, make_frame, parse_frames, random_gaps, reset, to_int


@cocotb.test()
async def resampler_frames(dut) -> None:
    width, num, den = env_int("ORB_LINE_WIDTH"), env_int("ORB_NUM"), env_int("ORB_DEN")
    height = env_int("ORB_LINE_COUNT")
    frames = [make_frame(kind, width, height, seed=30 + i).astype(np.uint8)
              for i, (kind, _) in enumerate(parse_frames(env_str("ORB_FRAMES")))]  # fmt: skip
    gaps = random_gaps(sum(f.size for f in frames), seed=width + num, prob=0.3, long_every=250)
    items = [(x, y, int(img[y, x])) for img in frames for y in range(height) for x in range(width)]
    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_data": 0})
    stream = Stream(
        dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_data], [dut.out_x, dut.out_y, dut.out_data], [dut.out_valid]
    )
    await stream.run(items, gaps, tail=RESAMPLER_LAT + 2)
    got = {e: (to_int(x), to_int(y), to_int(d)) for e, (x, y, d) in stream.samples}
    checked = 0
    for f, img in enumerate(frames):
        small = resample(img, num, den)
        ho, wo = small.shape
        ix, _ = _taps(wo, num, den, width)
        iy, _ = _taps(ho, num, den, height)
        base = f * width * height
        for yo in range(ho):
            for xo in range(wo):
                x, y = int(ix[xo]) + 1, int(iy[yo]) + 1
                edge = stream.in_edges[base + y * width + x] + RESAMPLER_LAT
                where = f"frame {f}, output (x={xo}, y={yo}), completed by input (x={x}, y={y})"
                assert edge in got, f"{where}: no output"
                out = got.pop(edge)
                assert out == (xo, yo, int(small[yo, xo])), (
                    f"{where}: (x, y, value) {out} != {(xo, yo, int(small[yo, xo]))}"
                )
                checked += 1
    assert not got, f"{len(got)} outputs the model does not have, the first {min(got.items())}"
    dut._log.info("%d resampled pixels checked over %d frames", checked, len(frames))


@pytest.mark.parametrize(
    ("width", "height", "num", "den", "frames"),
    [
        (64, 48, 5, 4, "photo:camera@48,random@48,photo:coffee@48"),
        (65, 51, 5, 4, "photo:astronaut@51,random@51"),
        (41, 29, 3, 2, "photo:chelsea@29,random@29"),
        (40, 30, 2, 1, "photo:rocket@30,random@30"),
        (128, 9, 5, 4, "random@9"),
    ],
)
def test_resampler(width: int, height: int, num: int, den: int, frames: str) -> None:
    run("orb_resampler", "test_orb_resampler",
        {"LINE_WIDTH_g": width, "LINE_COUNT_g": height, "NUM_g": num, "DEN_g": den},
        env={**SIM_ENV, "ORB_FRAMES": frames})  # fmt: skip
