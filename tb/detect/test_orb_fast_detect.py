# SPDX-License-Identifier: MIT
"""orb_fast_detect (one scale: window, FAST score, NMS) against golden_model.pipeline.detect.

Whole frames (photographs, the densest corner patterns, a flat image, corners at every border
distance, noise) stream back to back with (x, y), random input gaps and per-frame thresholds
(0, 20, 255, ...). The threshold port holds the frame's threshold only at the frame's first pixel
(0, 0) and is changed right after it and on every line, so a frame must still be detected with the
value sampled at (0, 0). Sizes include the smallest per-scale frames (8x6, scale 3 of 64x48) and
odd ones. Checked per frame: the features between two frame_done pulses equal detect(frame, t)
(x, y, score), and frame_done pulses exactly once, a few clocks after the frame's last pixel.
"""

from __future__ import annotations

import cocotb
import numpy as np
import pytest

from golden_model.pipeline import detect
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, env_str, random_gaps, reset, to_int

DONE_MAX_DELAY = 16  # "a few clocks" after the last pixel


def first_difference(got: list[tuple[int, int, int]], exp: list[tuple[int, int, int]]) -> str | None:
    """Both lists of (x, y, score) in raster order; names the first differing feature."""
    for i, (g, e) in enumerate(zip(got, exp, strict=False)):
        if g != e:
            return f"feature {i}: RTL (x={g[0]}, y={g[1]}) score {g[2]}, model (x={e[0]}, y={e[1]}) score {e[2]}"
    if len(got) != len(exp):
        who, longer = ("RTL", got) if len(got) > len(exp) else ("model", exp)
        x, y, s = longer[min(len(got), len(exp))]
        return f"the {who} has {abs(len(got) - len(exp))} more features, first (x={x}, y={y}) score {s}"
    return None


@cocotb.test()
async def detect_frames(dut) -> None:
    w, h = env_int("ORB_LINE_WIDTH"), env_int("ORB_FRAME_HEIGHT")
    specs = [part.rsplit("@", 1) for part in env_str("ORB_FRAMES").split(",")]
    frames = [(kind, images.make(kind, w, h), int(t)) for kind, t in specs]
    rng = np.random.default_rng(w + h)

    items = []
    for _, img, t in frames:
        line_thr = rng.integers(0, 256, h)
        line_thr[line_thr == t] = (t + 128) % 256  # every other value differs from the frame's
        for y in range(h):
            for x in range(w):
                thr = t if (x, y) == (0, 0) else int(line_thr[y])
                items.append((x, y, int(img[y, x]), thr))
    gap_prob = float(env_str("ORB_GAP_PROB", "0.2"))
    gaps = random_gaps(len(items), seed=w * h + 1, prob=gap_prob, long_every=500 if gap_prob > 0 else 0)

    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_data": 0, "threshold": 0})
    stream = Stream(
        dut.clk,
        dut.in_valid,
        [dut.in_x, dut.in_y, dut.in_data, dut.threshold],
        [dut.feat_valid, dut.feat_x, dut.feat_y, dut.feat_score, dut.frame_done],
        [dut.feat_valid, dut.frame_done],
    )
    await stream.run(items, gaps, tail=2 * DONE_MAX_DELAY)

    dones = [e for e, (*_, d) in stream.samples if d == 1]
    assert len(dones) == len(frames), f"{len(dones)} frame_done pulses for {len(frames)} frames"
    feats = [(e, (to_int(x), to_int(y), to_int(s))) for e, (v, x, y, s, _) in stream.samples if v == 1]
    n = w * h
    total = 0
    for f, (kind, img, t) in enumerate(frames):
        where = f"frame {f} ({kind}, {w}x{h}, threshold {t})"
        last_in = stream.in_edges[(f + 1) * n - 1]
        assert last_in < dones[f] <= last_in + DONE_MAX_DELAY, (
            f"{where}: frame_done {dones[f] - last_in} clocks after the last pixel"
        )
        lo = dones[f - 1] if f else -1
        got = sorted((xyz for e, xyz in feats if lo < e <= dones[f]), key=lambda v: (v[1], v[0]))
        xs, ys, score, _ = detect(img, t)
        exp = [(int(x), int(y), int(s)) for x, y, s in zip(xs, ys, score, strict=True)]
        diff = first_difference(got, exp)
        assert diff is None, f"{where}: {diff}"
        total += len(exp)
    assert not [e for e, _ in feats if e > dones[-1]], "features after the last frame_done"
    dut._log.info("%d frames, %d features checked", len(frames), total)


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_detect(width: int, height: int, frames: str, gap_prob: float = 0.2) -> None:
    run(
        "orb_fast_detect",
        "test_orb_fast_detect",
        {"LINE_WIDTH_g": width, "FRAME_HEIGHT_g": height},
        env={**SIM_ENV, "ORB_FRAMES": frames, "ORB_GAP_PROB": str(gap_prob)},
    )


@pytest.mark.parametrize(
    ("width", "height", "frames", "gap_prob"),
    [
        (64, 48, "photo:camera@20,photo:astronaut@0,photo:coffee@255,photo:chelsea@20", 0.2),  # t = 0/20/255
        (65, 48, "dots@20,checker@0,flat@0,border@20,noise@30", 0.0),  # back to back, no gaps at all
        (8, 6, "noise@0,dots@0,flat@20", 0.2),  # smallest scale: no room for a corner, frame_done still
        (16, 12, "dots@10,photo:rocket@0,checker4@5", 0.3),
        (33, 25, "photo:astronaut@5,border@15,dots@0", 0.2),  # odd scale size
    ],
)
def test_fast_detect(width: int, height: int, frames: str, gap_prob: float) -> None:
    # every runner has its own (width, height): orbtb.runner shares one build per generic set
    run_detect(width, height, frames, gap_prob)
