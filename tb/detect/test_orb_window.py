# SPDX-License-Identifier: MIT
"""orb_window against the numpy-exact window slices of the image.

Frames are streamed back to back pixel by pixel with (x, y) and random input gaps. Every input
pixel (x, y) must produce, exactly two clocks later, a window tagged (x, y) whose bottom-right
element is that pixel: element (r, c) = frame[y - WIN + 1 + r, x - WIN + 1 + c]. Every element
that lies inside the current frame is checked (all of them once x, y >= WIN - 1, the positions
FAST and NMS use); elements left of x = 0 or above y = 0 hold stale pixels the consumer masks.
"""

from __future__ import annotations

import cocotb
import pytest

from golden_model.latency import WINDOW_LAT
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, env_str, make_frame, parse_frames, random_gaps, reset, to_int


def _elements(value, win: int, bits: int) -> list[int | None]:
    """The WIN x WIN elements (raster order, element 0 at the lowest bits); None where not 0/1."""
    word = to_int(value)
    n = win * win
    mask = (1 << bits) - 1
    if word is not None:
        return [(word >> (k * bits)) & mask for k in range(n)]
    text = str(value)[::-1]  # LSB first
    out: list[int | None] = []
    for k in range(n):
        part = text[k * bits : (k + 1) * bits][::-1]
        out.append(int(part, 2) if all(c in "01" for c in part) else None)
    return out


@cocotb.test()
async def window_slices(dut) -> None:
    width, win, bits = env_int("ORB_LINE_WIDTH"), env_int("ORB_WIN"), env_int("ORB_DATA_WIDTH")
    frames = [
        make_frame(kind, width, height, bits, seed=10 + i)
        for i, (kind, height) in enumerate(parse_frames(env_str("ORB_FRAMES")))
    ]
    gap_prob = float(env_str("ORB_GAP_PROB", "0.25"))

    where_of = [(f, x, y) for f, img in enumerate(frames) for y in range(img.shape[0]) for x in range(width)]
    items = [(x, y, int(frames[f][y, x])) for f, x, y in where_of]
    gaps = random_gaps(len(items), seed=3 * width + win, prob=gap_prob, long_every=300)

    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_data": 0})
    stream = Stream(
        dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_data], [dut.out_x, dut.out_y, dut.out_win], [dut.out_valid]
    )
    await stream.run(items, gaps, tail=4)

    out_edges = [e for e, _ in stream.samples]
    expected_edges = [e + WINDOW_LAT for e in stream.in_edges]
    if out_edges != expected_edges:
        i = next((i for i, (a, b) in enumerate(zip(out_edges, expected_edges, strict=False)) if a != b), None)
        raise AssertionError(
            f"out_valid is not the input pattern delayed by {WINDOW_LAT}: {len(out_edges)} outputs for {len(items)} "
            f"inputs, first difference at output {i}"
            + (f" (frame {where_of[i][0]}, x={where_of[i][1]}, y={where_of[i][2]})" if i is not None else "")
        )
    full = 0
    for (f, x, y), (_, (x_v, y_v, win_v)) in zip(where_of, stream.samples, strict=True):
        where = f"frame {f} window at (x={x}, y={y})"
        assert (to_int(x_v), to_int(y_v)) == (x, y), f"{where}: tagged ({x_v}, {y_v})"
        r0, c0 = max(0, win - 1 - y), max(0, win - 1 - x)  # first row / column inside the frame
        if r0 >= win or c0 >= win:
            continue
        got = _elements(win_v, win, bits)
        exp = frames[f][y - win + 1 + r0 : y + 1, x - win + 1 + c0 : x + 1]
        for r in range(r0, win):
            for c in range(c0, win):
                g, e = got[r * win + c], int(exp[r - r0, c - c0])
                if g != e:
                    raise AssertionError(
                        f"{where}: element (r={r}, c={c}) = pixel (x={x - win + 1 + c}, y={y - win + 1 + r}) "
                        f"is {g}, expected {e}"
                    )
        full += r0 == 0 and c0 == 0
    assert full > 0, "no window lay entirely inside a frame: the stimulus is too small"
    dut._log.info("checked %d windows (%d entirely inside a frame)", len(where_of), full)


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_window(width: int, win: int, bits: int, frames: str, gap_prob: float = 0.25) -> None:
    run(
        "orb_window",
        "test_orb_window",
        {"LINE_WIDTH_g": width, "WIN_g": win, "DATA_WIDTH_g": bits},
        env={**SIM_ENV, "ORB_FRAMES": frames, "ORB_GAP_PROB": str(gap_prob)},
    )


@pytest.mark.parametrize(
    ("width", "win", "bits", "frames"),
    [
        (8, 7, 8, "photo:coffee@12,random@9,photo:camera@7"),  # window as wide as the line allows
        (8, 2, 8, "random@5,photo:rocket@4"),  # smallest window
        (64, 7, 8, "photo:astronaut@14,random@10"),
        (64, 3, 12, "random@8,photo:chelsea@6"),  # the NMS's score window
        (640, 7, 8, "photo:camera@8,random@7"),
    ],
)
def test_window(width: int, win: int, bits: int, frames: str) -> None:
    run_window(width, win, bits, frames)


def test_window_1920_strip() -> None:
    run_window(1920, 7, 8, "photo:astronaut@7,random@6", gap_prob=0.05)
