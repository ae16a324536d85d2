# SPDX-License-Identifier: MIT
"""orb_line_buffer against the numpy-exact expectation from the image stream.

Frames (a photograph crop, random data) are streamed back to back pixel by pixel with their
column index and random input gaps. For every input pixel the buffer must output, exactly
LATENCY_g clocks later (1, or 2 with the output register), its column: slice 0 the pixel
itself, slice k the pixel k lines above at the same x.
Inside the current frame that is the frame's own pixel; above the frame's top it is the earlier
frame's line, which the header documents as staying in the RAM (only never-written RAM is left
unchecked). The runners cover widths 3, 8, 64, 640 and a 1920-wide strip of a few lines, at
both latencies.
"""

from __future__ import annotations

import cocotb
import numpy as np
import pytest

from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, env_str, field_of, make_frame, parse_frames, random_gaps, reset, to_int


@cocotb.test()
async def line_buffer_columns(dut) -> None:
    width, lines, bits = env_int("ORB_LINE_WIDTH"), env_int("ORB_LINES"), env_int("ORB_DATA_WIDTH")
    latency = env_int("ORB_LATENCY")
    frames = [
        make_frame(kind, width, height, bits, seed=i)
        for i, (kind, height) in enumerate(parse_frames(env_str("ORB_FRAMES")))
    ]
    gap_prob = float(env_str("ORB_GAP_PROB", "0.25"))

    rows = np.concatenate(frames)  # the stream of lines, frame after frame
    frame_of_row = np.concatenate([np.full(len(f), i) for i, f in enumerate(frames)])
    y_of_row = np.concatenate([np.arange(len(f)) for f in frames])
    items = [(x, int(rows[r, x])) for r in range(len(rows)) for x in range(width)]
    gaps = random_gaps(len(items), seed=width + lines, prob=gap_prob, long_every=200)

    await reset(dut, {"in_valid": 0, "in_col": 0, "in_data": 0})
    stream = Stream(dut.clk, dut.in_valid, [dut.in_col, dut.in_data], [dut.out_col, dut.out_data], [dut.out_valid])
    await stream.run(items, gaps, tail=4)

    out_edges = [e for e, _ in stream.samples]
    expected_edges = [e + latency for e in stream.in_edges]
    assert out_edges == expected_edges, (
        f"out_valid pattern differs from the input pattern delayed by {latency}: first difference at output "
        f"{next((i for i, (a, b) in enumerate(zip(out_edges, expected_edges, strict=False)) if a != b), None)}, "
        f"{len(out_edges)} outputs for {len(items)} inputs"
    )
    mask = (1 << bits) - 1
    checked = 0
    for i, (_, (col_v, data_v)) in enumerate(stream.samples):
        r, x = divmod(i, width)
        f, y = int(frame_of_row[r]), int(y_of_row[r])
        where = f"frame {f} (x={x}, y={y})"
        assert to_int(col_v) == x, f"{where}: out_col {col_v} != {x}"
        word = to_int(data_v)
        for k in range(lines + 1):
            if r - k < 0:
                continue  # RAM never written since power-up
            got = (word >> (k * bits)) & mask if word is not None else field_of(data_v, k * bits, bits)
            exp = int(rows[r - k, x])
            if got != exp:
                inside = "inside the frame" if k <= y else "a line of the earlier frame"
                raise AssertionError(f"{where}: slice {k} ({k} lines above, {inside}) is {got}, expected {exp}")
            checked += 1
    dut._log.info("checked %d column slices over %d frames", checked, len(frames))


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_line_buffer(width: int, lines: int, bits: int, frames: str, gap_prob: float = 0.25, latency: int = 1) -> None:
    run(
        "orb_line_buffer",
        "test_orb_line_buffer",
        {"LINE_WIDTH_g": width, "LINES_g": lines, "DATA_WIDTH_g": bits, "LATENCY_g": latency},
        env={**SIM_ENV, "ORB_FRAMES": frames, "ORB_GAP_PROB": str(gap_prob)},
    )


@pytest.mark.parametrize(
    ("width", "lines", "bits", "frames", "latency"),
    [
        (3, 1, 8, "random@9,photo:camera@5", 1),  # smallest legal line, single-line buffer
        (3, 3, 8, "random@9,photo:camera@5", 2),
        (8, 6, 8, "photo:coffee@13,random@9,photo:chelsea@3", 1),  # back to back, last frame shorter than the buffer
        (8, 6, 8, "photo:coffee@13,random@9,photo:chelsea@3", 2),
        (64, 6, 8, "photo:astronaut@12,random@10", 1),
        (64, 2, 12, "random@9,photo:rocket@7", 1),  # the NMS's score buffer shape
        (640, 6, 8, "photo:camera@8,random@7", 1),
        (640, 30, 8, "photo:camera@34,random@7", 2),  # the descriptor window's buffer (registered output)
    ],
)
def test_line_buffer(width: int, lines: int, bits: int, frames: str, latency: int) -> None:
    run_line_buffer(width, lines, bits, frames, latency=latency)


def test_line_buffer_1920_strip() -> None:
    run_line_buffer(1920, 6, 8, "photo:astronaut@4,random@3", gap_prob=0.05)
