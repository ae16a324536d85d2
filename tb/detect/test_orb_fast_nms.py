# SPDX-License-Identifier: MIT
"""orb_fast_nms against golden_model.nms.nms3x3 on the combined map of docs/spec.md section 5.

The input is the stream orb_fast_score and orb_harris produce: stream position (px, py) carries
the score S(px - 3, py - 3) of a score map S (0 for px < 3 or py < 3), the main-corner flag M and
the response code there. Maps: golden_model.fast.fast_score of photographs at a main and a low
threshold (M: a corner at the main one; S: the score at the low one) with their
golden_model.response codes, the densest corner patterns, and synthetic maps full of ties and
plateaus with random main flags (main and low corners of equal score side by side) and random
codes, including every combination of three values over the last-column / last-row cells that
orb_fast_nms decides specially. Frames follow each other back to back with random input gaps.

Checked per frame: the survivors equal nms3x3(S + 4096 M) (x, y, score, low = not M, code), each
is emitted 3 clocks after the stream position that decides it ((x + 4, y + 4), or W - 1 / H - 1
for the last column / row of centres), and frame_done pulses exactly once, 3 clocks after
position (W - 1, H - 1).
"""

from __future__ import annotations

import itertools

import cocotb
import numpy as np
import pytest

from golden_model.fast import fast_score
from golden_model.latency import FAST_NMS_LAT
from golden_model.nms import nms3x3
from golden_model.pipeline import MAIN_LIFT
from golden_model.response import response_map
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, env_int, env_str, random_gaps, reset, to_int


def interior(w: int, h: int) -> tuple[slice, slice]:
    """The centres FAST can score: 3 <= x <= W - 4, 3 <= y <= H - 4."""
    return slice(3, h - 3), slice(3, w - 3)


def tie_map(w: int, h: int, seed: int) -> np.ndarray:
    """Dense small scores with many equal neighbours, plus constant rectangles (plateaus)."""
    rng = np.random.default_rng(seed)
    s = np.zeros((h, w), dtype=np.int64)
    ys, xs = interior(w, h)
    region = s[ys, xs]
    region[:] = rng.choice([0, 0, 9, 10, 10, 11, 12], size=region.shape)
    for _ in range(max(1, region.size // 12)):
        rh, rw = int(rng.integers(1, 5)), int(rng.integers(1, 5))
        y0, x0 = int(rng.integers(0, region.shape[0])), int(rng.integers(0, region.shape[1]))
        region[y0 : y0 + rh, x0 : x0 + rw] = int(rng.choice([10, 11, 4095]))
    return s


def edge_map(w: int, h: int, seed: int) -> np.ndarray:
    """Ties in the last three columns and rows of centres (the ones orb_fast_nms decides at the
    end of a line or in the last line), and a last corner (W - 4, H - 4) that survives."""
    rng = np.random.default_rng(seed)
    s = np.zeros((h, w), dtype=np.int64)
    ys, xs = interior(w, h)
    region = s[ys, xs]
    region[:] = rng.choice([0, 10, 11, 12], size=region.shape)
    region[:-3, :-3] = 0
    region[-2:, -2:] = [[12, 12], [12, 13]]
    return s


Maps = tuple[np.ndarray, np.ndarray, np.ndarray]  # (score S, main flag M, response code)


def score_map(kind: str, w: int, h: int) -> Maps:
    """`photo:<name>:<t>[:<t_lo>]` / `dots:<t>` / `checker:<t>` (fast_score of that image at t_lo,
    main corners at t, its response codes), and the synthetic maps of `synthetic_score_map` with
    main flags and codes drawn at random (seeded by the kind)."""
    name, _, arg = kind.partition(":")
    if name == "photo":
        photo, t, *tl = arg.split(":")
        img = images.photo(photo, w, h)
        lo = min(int(tl[0]), int(t)) if tl else int(t)
        return (fast_score(img, lo).astype(np.int64), fast_score(img, int(t)) > 0, response_map(img))
    if name in ("dots", "checker"):
        img = images.make(name, w, h)
        s = fast_score(img, int(arg)).astype(np.int64)
        return s, s > 0, response_map(img)
    s = synthetic_score_map(kind, w, h)
    name = kind.partition(":")[0]
    rng = np.random.default_rng(sum(map(ord, kind)))
    # edges: every corner main (its last corner must survive); the others: half of them main
    main = (s > 0) & (rng.random(s.shape) < (1.0 if name == "edges" else 0.5))
    return s, main, rng.integers(0, 64, s.shape)


def synthetic_score_map(kind: str, w: int, h: int) -> np.ndarray:
    """`ties:<seed>`, `edges:<seed>`, `zero`, `plateau` (one value over the whole interior),
    `random12` (random 12-bit scores)."""
    name, _, arg = kind.partition(":")
    if name == "ties":
        return tie_map(w, h, int(arg))
    if name == "edges":
        return edge_map(w, h, int(arg))
    s = np.zeros((h, w), dtype=np.int64)
    ys, xs = interior(w, h)
    if name == "zero":
        return s
    if name == "plateau":
        s[ys, xs] = 77
        return s
    if name == "random12":
        s[ys, xs] = np.random.default_rng(9).integers(0, 4096, s[ys, xs].shape)
        return s
    raise ValueError(f"unknown score map {kind!r}")


def corner_cases_8x8() -> list[np.ndarray]:
    """For an 8x8 frame the interior is the 2x2 block (3..4, 3..4): every cell is in the last
    column or row, so all four candidates are decided together at (7, 7). All 3^4 assignments of
    {0, 5, 6} cover every tie and order among them."""
    maps = []
    for vals in itertools.product((0, 5, 6), repeat=4):
        s = np.zeros((8, 8), dtype=np.int64)
        s[3:5, 3:5] = np.array(vals).reshape(2, 2)
        maps.append(s)
    return maps


@cocotb.test()
async def nms_frames(dut) -> None:
    w, h = env_int("ORB_LINE_WIDTH"), env_int("ORB_FRAME_HEIGHT")
    kinds = env_str("ORB_MAPS").split(",")
    maps: list[tuple[str, np.ndarray]] = []
    for kind in kinds:
        if kind == "all8x8":
            rng = np.random.default_rng(8)
            for i, m in enumerate(corner_cases_8x8()):
                # the flags half the time: a low corner of equal or higher score beside a main one
                main = (m > 0) & (rng.random(m.shape) < (0.5 if i % 2 else 0.0))
                maps.append((f"8x8 case {i}", (m, main, rng.integers(0, 64, m.shape))))
        else:
            maps.append((kind, score_map(kind, w, h)))
    for label, (s, main, _code) in maps:
        assert s.shape == (h, w) and s.max() < 4096, label
        assert not s[:3].any() and not s[:, :3].any() and not s[h - 3 :].any() and not s[:, w - 3 :].any(), label
        assert not (main & (s == 0)).any(), f"{label}: a main corner without a score"

    # the stream: position (px, py) carries S(px - 3, py - 3) and the flag and code there
    items = []
    for _, (s, main, code) in maps:
        pads = []
        for a in (s, main.astype(np.int64), code):
            padded = np.zeros((h, w), dtype=np.int64)
            padded[3:, 3:] = a[: h - 3, : w - 3]
            pads.append(padded)
        items += [(px, py, *(int(p[py, px]) for p in pads)) for py in range(h) for px in range(w)]
    gaps = random_gaps(len(items), seed=w * h, prob=0.2, long_every=400)

    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_score": 0, "in_main": 0, "in_code": 0})
    stream = Stream(
        dut.clk,
        dut.in_valid,
        [dut.in_x, dut.in_y, dut.in_score, dut.in_main, dut.in_code],
        [dut.feat_valid, dut.feat_x, dut.feat_y, dut.feat_score, dut.feat_low, dut.feat_code, dut.frame_done],
        [dut.feat_valid, dut.frame_done],
    )
    await stream.run(items, gaps, tail=8)

    feats = [
        (e, (to_int(x), to_int(y), to_int(sc), to_int(lo), to_int(cd)))
        for e, (v, x, y, sc, lo, cd, _) in stream.samples
        if v == 1
    ]
    dones = [e for e, (*_, d) in stream.samples if d == 1]
    n = w * h
    expected_dones = [stream.in_edges[(f + 1) * n - 1] + FAST_NMS_LAT for f in range(len(maps))]
    assert len(dones) == len(maps), f"{len(dones)} frame_done pulses for {len(maps)} frames (at edges {dones[:10]})"

    total = 0
    low_survivors = 0
    for f, (label, (s, main, code)) in enumerate(maps):
        lo = dones[f - 1] if f else -1
        got = [(e, xyz) for e, xyz in feats if lo < e <= dones[f]]
        keep = nms3x3(s + MAIN_LIFT * main)
        exp = [(int(x), int(y), int(s[y, x]), int(not main[y, x]), int(code[y, x]))
               for y, x in zip(*np.nonzero(keep), strict=True)]  # fmt: skip
        low_survivors += sum(e[3] for e in exp)
        got_set, exp_set = {xyz for _, xyz in got}, set(exp)
        where = f"frame {f} ({label}, {w}x{h})"
        missing = sorted(exp_set - got_set, key=lambda t: (t[1], t[0]))
        extra = sorted(got_set - exp_set, key=lambda t: (t[1] or 0, t[0] or 0))
        if missing or extra:
            parts = [f"{len(missing)} survivors missing, {len(extra)} extra features"]
            if missing:
                parts.append(f"first missing (x={missing[0][0]}, y={missing[0][1]}) score {missing[0][2]}")
            if extra:
                parts.append(f"first extra (x={extra[0][0]}, y={extra[0][1]}) score {extra[0][2]}")
            raise AssertionError(f"{where}: " + "; ".join(parts))
        assert len(got) == len(exp), f"{where}: a survivor was reported twice"
        # timing: emitted 3 clocks after the stream position that decides it
        for e, (x, y, *_) in got:
            px = x + 4 if x + 4 <= w - 1 else w - 1
            py = y + 4 if y + 4 <= h - 1 else h - 1
            want = stream.in_edges[f * n + py * w + px] + FAST_NMS_LAT
            assert e == want, (
                f"{where}: survivor (x={x}, y={y}) emitted at edge {e}, expected {want} (decided at ({px}, {py}))"
            )
        assert dones[f] == expected_dones[f], (
            f"{where}: frame_done at edge {dones[f]}, expected {expected_dones[f]} (3 clocks after position (W-1, H-1))"
        )
        total += len(exp)
    assert all(e <= dones[-1] for e, _ in feats), "features after the last frame_done"
    # the stimulus must reach the special decisions: survivors in the last column, the last row
    # and the last corner of centres
    combined = [nms3x3(s + MAIN_LIFT * main) for _, (s, main, _) in maps]
    last_col = sum(int(k[3 : h - 3, w - 4].sum()) for k in combined)
    last_row = sum(int(k[h - 4, 3 : w - 3].sum()) for k in combined)
    last_both = sum(int(k[h - 4, w - 4]) for k in combined)
    assert last_col and last_row and last_both, (
        f"no survivor in the last column/row/corner: {last_col, last_row, last_both}"
    )
    # and both kinds of survivor, and main corners that win against higher low neighbours
    assert low_survivors and total - low_survivors, f"survivors: {low_survivors} low of {total}"
    beaten = sum(int((nms3x3(s) & ~k).sum()) for (_, (s, _, _)), k in zip(maps, combined, strict=True))
    assert beaten, "no corner that the score alone keeps is suppressed by a main neighbour: the lift is untested"
    dut._log.info("%d frames, %d survivors checked", len(maps), total)


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_nms(width: int, height: int, maps: str) -> None:
    run(
        "orb_fast_nms",
        "test_orb_fast_nms",
        {"LINE_WIDTH_g": width, "FRAME_HEIGHT_g": height},
        env={**SIM_ENV, "ORB_MAPS": maps},
    )


@pytest.mark.parametrize(
    ("width", "height", "maps"),
    [
        (8, 8, "all8x8,ties:1"),  # smallest line: every decision is a last-column/last-row one
        (37, 21, "photo:camera:0,photo:astronaut:10:3,ties:2,ties:3,edges:3,dots:20,checker:20,zero,plateau,random12"),
        (64, 48, "photo:coffee:0,photo:rocket:20:7,photo:chelsea:30:7,ties:4,edges:1"),
        (640, 10, "photo:astronaut:5,photo:camera:20:7,ties:5,edges:2"),
    ],
)
def test_nms(width: int, height: int, maps: str) -> None:
    run_nms(width, height, maps)
