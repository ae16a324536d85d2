# SPDX-License-Identifier: MIT
"""orb_fast_detect (one scale: window, FAST score at two thresholds, response, NMS) against
golden_model.pipeline.detect and golden_model.response.

Whole frames (photographs, the densest corner patterns, a flat image, corners at every border
distance, noise) stream back to back with (x, y), random input gaps and per-frame thresholds
`t/t_lo` (0, 20, 255, ...; a low threshold below, equal to or above the main one). The threshold
ports hold the frame's values only at the frame's first pixel (0, 0) and are changed right after
it and on every line, so a frame must still be detected with the values sampled at (0, 0). Sizes
include the smallest per-scale frames (8x6, scale 3 of 64x48) and odd ones. Checked per frame:
the features between two frame_done pulses equal detect(frame, t, t_lo) (x, y, score, low) with
response_map(frame)'s code, each survivor (x, y) away from the right and bottom borders exactly
FAST_DETECT_LAT clocks after the pixel (x + 4, y + 4) that completes its NMS neighbourhood, and
frame_done pulses exactly once, a few clocks after the frame's last pixel.
"""

from __future__ import annotations

import cocotb
import numpy as np
import pytest

from golden_model.latency import FAST_DETECT_LAT
from golden_model.pipeline import detect
from golden_model.response import response_map
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, env_str, random_gaps, reset, to_int

DONE_MAX_DELAY = 32  # "a few clocks" after the last pixel (the window, orb_harris's 17, the NMS)
Feat = tuple[int, int, int, int, int]  # (x, y, score, low, code)


def first_difference(got: list[Feat], exp: list[Feat]) -> str | None:
    """Both lists of (x, y, score, low, code) in raster order; names the first differing feature."""
    for i, (g, e) in enumerate(zip(got, exp, strict=False)):
        if g != e:
            return (f"feature {i}: RTL (x={g[0]}, y={g[1]}) score {g[2]} low {g[3]} code {g[4]}, model (x={e[0]}, "
                    f"y={e[1]}) score {e[2]} low {e[3]} code {e[4]}")  # fmt: skip
    if len(got) != len(exp):
        who, longer = ("RTL", got) if len(got) > len(exp) else ("model", exp)
        x, y, s, *_ = longer[min(len(got), len(exp))]
        return f"the {who} has {abs(len(got) - len(exp))} more features, first (x={x}, y={y}) score {s}"
    return None


@cocotb.test()
async def detect_frames(dut) -> None:
    w, h = env_int("ORB_LINE_WIDTH"), env_int("ORB_FRAME_HEIGHT")
    specs = [part.rsplit("@", 1) for part in env_str("ORB_FRAMES").split(",")]
    frames = []
    for kind, thr in specs:
        t, _, tl = thr.partition("/")
        frames.append((kind, images.make(kind, w, h), int(t), int(tl or t)))
    rng = np.random.default_rng(w + h)

    items = []
    for _, img, t, tl in frames:
        line_thr = rng.integers(0, 256, h)
        line_thr[line_thr == t] = (t + 128) % 256  # every other value differs from the frame's
        line_lo = rng.integers(0, 256, h)
        line_lo[line_lo == tl] = (tl + 77) % 256
        for y in range(h):
            for x in range(w):
                first = (x, y) == (0, 0)
                items.append((x, y, int(img[y, x]), t if first else int(line_thr[y]), tl if first else int(line_lo[y])))
    gap_prob = float(env_str("ORB_GAP_PROB", "0.2"))
    gaps = random_gaps(len(items), seed=w * h + 1, prob=gap_prob, long_every=500 if gap_prob > 0 else 0)

    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_data": 0, "threshold": 0, "threshold_lo": 0})
    stream = Stream(
        dut.clk,
        dut.in_valid,
        [dut.in_x, dut.in_y, dut.in_data, dut.threshold, dut.threshold_lo],
        [dut.feat_valid, dut.feat_x, dut.feat_y, dut.feat_score, dut.feat_low, dut.feat_code, dut.frame_done],
        [dut.feat_valid, dut.frame_done],
    )
    await stream.run(items, gaps, tail=2 * DONE_MAX_DELAY)

    dones = [e for e, (*_, d) in stream.samples if d == 1]
    assert len(dones) == len(frames), f"{len(dones)} frame_done pulses for {len(frames)} frames"
    feats = [
        (e, (to_int(x), to_int(y), to_int(s), to_int(lo), to_int(c)))
        for e, (v, x, y, s, lo, c, _) in stream.samples
        if v == 1
    ]
    n = w * h
    total = low_total = timed = 0
    for f, (kind, img, t, tl) in enumerate(frames):
        where = f"frame {f} ({kind}, {w}x{h}, threshold {t}, low {tl})"
        last_in = stream.in_edges[(f + 1) * n - 1]
        assert last_in < dones[f] <= last_in + DONE_MAX_DELAY, (
            f"{where}: frame_done {dones[f] - last_in} clocks after the last pixel"
        )
        lo = dones[f - 1] if f else -1
        got = sorted((xyz for e, xyz in feats if lo < e <= dones[f]), key=lambda v: (v[1], v[0]))
        xs, ys, score, low = detect(img, t, tl)
        codes = response_map(img)
        exp = [(int(x), int(y), int(s), int(lw), int(codes[y, x]))
               for x, y, s, lw in zip(xs, ys, score, low, strict=True)]  # fmt: skip
        diff = first_difference(got, exp)
        assert diff is None, f"{where}: {diff}"
        late = [(x, y, e - stream.in_edges[f * n + (y + 4) * w + x + 4])
                for e, (x, y, *_) in feats if lo < e <= dones[f] and x + 4 < w and y + 4 < h]  # fmt: skip
        assert all(d == FAST_DETECT_LAT for *_, d in late), (
            f"{where}: survivors (x, y, clocks after pixel (x + 4, y + 4)) not {FAST_DETECT_LAT} clocks late: "
            + str([v for v in late if v[2] != FAST_DETECT_LAT][:5])
        )
        timed += len(late)
        total += len(exp)
        low_total += int(low.sum())
    assert not [e for e, _ in feats if e > dones[-1]], "features after the last frame_done"
    if w >= 16 and any(tl < t for *_, t, tl in frames):  # (8x6 has no room for any corner)
        assert low_total, "frames with a low threshold but no low corner: the low path is untested"
    if total:
        assert timed, "no survivor away from the right and bottom borders: the latency is untested"
    dut._log.info("%d frames, %d features checked (%d low, %d timed)", len(frames), total, low_total, timed)


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
        # t = 0/20/255, low thresholds below, equal, above
        (64, 48, "photo:camera@20/7,photo:astronaut@0,photo:coffee@255/20,photo:chelsea@20/40", 0.2),
        (65, 48, "dots@20/3,checker@0,flat@0/0,border@20/7,noise@30/10", 0.0),  # back to back, no gaps at all
        (8, 6, "noise@0,dots@0,flat@20/5", 0.2),  # smallest scale: no room for a corner, frame_done still
        (16, 12, "dots@10,photo:rocket@0,checker4@5/1,photo:astronaut@30/4", 0.3),
        (33, 25, "photo:astronaut@5,border@15/2,dots@0", 0.2),  # odd scale size
    ],
)
def test_fast_detect(width: int, height: int, frames: str, gap_prob: float) -> None:
    # every runner has its own (width, height): orbtb.runner shares one build per generic set
    run_detect(width, height, frames, gap_prob)
