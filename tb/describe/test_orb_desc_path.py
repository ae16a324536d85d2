# SPDX-License-Identifier: MIT
"""orb_desc_path against the golden model: sector and descriptor of every feature inside the border.

The smoothed stream is driven with orb_smooth's tagging (the value tagged (x, y) is the model's
smoothed pixel (x - 3, y - 3), 0 off the image) and each NMS survivor (x, y) is offered in the
clock of tag (x + 4, y + 4), about when orb_fast_nms reports it. Expected: the model's features
of that frame (border rule, moments, quantised sector, orbit-pattern rBRIEF) in raster order, one
frame_done per frame after its last feature, `lost` unchanged; with ROTATE_g false (as orb_core
builds it) the descriptor is the sector-0 table's tests, which orb_desc_rotate rotates later.
Cases: photographs at 16, 32 and 64 sectors with and without input gaps, back-to-back frames;
the densest legal feature pattern (one feature per 2x2 block over the whole frame, on a random
smoothed image); a frame cut short, whose waiting features must be counted in `lost` exactly and
must not disturb the next frame. Each survivor carries its low flag and response code through
(photographs: detect at a main and a low threshold, golden_model.response's codes; the patterns:
random ones), and every feature must be shown on cand_* exactly CAND_LEAD_LAT = 14 clocks before it
leaves, with the same position, low flag and code.
"""

from __future__ import annotations

import cocotb
import numpy as np
import pytest
from cocotb.triggers import RisingEdge

from golden_model.brief import describe
from golden_model.latency import CAND_LEAD_LAT
from golden_model.orientation import moments, quantise
from golden_model.pipeline import DESC_BORDER, detect, in_desc_border
from golden_model.response import response_map
from golden_model.smooth import smooth
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, env_int, random_gaps, reset, to_int

DETECT_DELAY = 4  # a survivor (x, y) is offered with the stream tag (x + 4, y + 4)
# x, y, score, low, code, sector, descriptor (bit i = test i)
Feature = tuple[int, int, int, int, int, int, int]
Offer = tuple[int, int, int]  # a survivor's score, low flag and code


def expected(smoothed: np.ndarray, xs: np.ndarray, ys: np.ndarray, offer: list[Offer], n: int) -> list[Feature]:
    """With ROTATE_g false the descriptor is the sector-0 table's tests (orb_desc_rotate's input)."""
    h, w = smoothed.shape
    keep = in_desc_border(xs, ys, w, h)
    xs, ys = xs[keep], ys[keep]
    offer = [o for o, k in zip(offer, keep, strict=True) if k]
    m10, m01 = moments(smoothed, xs, ys)
    sector = quantise(m10, m01, n)
    desc = describe(smoothed, xs, ys, sector if env_int("ORB_ROTATE") else np.zeros_like(sector), n)
    return [
        (int(x), int(y), *o, int(q), int.from_bytes(d.tobytes(), "little"))
        for x, y, o, q, d in zip(xs, ys, offer, sector, desc, strict=True)
    ]


def random_offers(rng: np.random.Generator, count: int) -> list[Offer]:
    return [(int(s), int(lo), int(c)) for s, lo, c in zip(rng.integers(1, 4081, count), rng.integers(0, 2, count),
                                                           rng.integers(0, 64, count), strict=True)]  # fmt: skip


def tagged(smoothed: np.ndarray) -> np.ndarray:
    """Stream value at tag (x, y): smoothed (x - 3, y - 3), 0 where that is off the image."""
    h, w = smoothed.shape
    out = np.zeros((h, w), dtype=np.int64)
    out[3:, 3:] = smoothed[: h - 3, : w - 3]
    return out


class Bench:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.out: list[Feature] = []
        self.out_edges: list[int] = []
        self.cands: list[tuple[int, tuple[int, int, int, int]]] = []  # (edge, (x, y, low, code))
        self.done_at: list[int] = []  # number of features seen when each frame_done pulsed
        self.edge = 0

    def sample(self) -> None:
        d = self.dut
        if d.feat_valid.value == 1:
            self.out.append(
                (to_int(d.feat_x.value), to_int(d.feat_y.value), to_int(d.feat_score.value),
                 to_int(d.feat_low.value), to_int(d.feat_code.value), to_int(d.feat_sector.value),
                 to_int(d.feat_desc.value))
            )  # fmt: skip
            self.out_edges.append(self.edge)
        if d.cand_valid.value == 1:
            self.cands.append((self.edge, (to_int(d.cand_x.value), to_int(d.cand_y.value), to_int(d.cand_low.value),
                                           to_int(d.cand_code.value))))  # fmt: skip
        if d.frame_done.value == 1:
            self.done_at.append(len(self.out))

    async def tick(self) -> None:
        await RisingEdge(self.dut.clk)
        self.edge += 1
        self.sample()

    async def frame(self, stream: np.ndarray, feats: dict[tuple[int, int], Offer], gaps: list[int] | None,
                    stop: int | None = None) -> None:  # fmt: skip
        """Drive one frame (stream values by tag, survivors by their own position -> score, low,
        code); stop after `stop` pixels when given (a frame cut short)."""
        d = self.dut
        h, w = stream.shape
        n = h * w if stop is None else stop
        for i in range(n):
            y, x = divmod(i, w)
            if gaps and gaps[i]:
                d.in_valid.value = 0
                d.det_valid.value = 0
                for _ in range(gaps[i]):
                    await self.tick()
            d.in_valid.value = 1
            d.in_x.value = x
            d.in_y.value = y
            d.in_data.value = int(stream[y, x])
            f = feats.get((x - DETECT_DELAY, y - DETECT_DELAY))
            if f is None:
                d.det_valid.value = 0
            else:
                d.det_valid.value = 1
                d.det_x.value = x - DETECT_DELAY
                d.det_y.value = y - DETECT_DELAY
                d.det_score.value, d.det_low.value, d.det_code.value = f
            await self.tick()
        d.in_valid.value = 0
        d.det_valid.value = 0

    async def idle(self, n: int) -> None:
        for _ in range(n):
            await self.tick()


async def start(dut) -> Bench:
    zero = dict.fromkeys(("in_valid", "in_x", "in_y", "in_data", "det_valid", "det_x", "det_y", "det_score", "det_low",
                          "det_code"), 0)  # fmt: skip
    await reset(dut, zero)
    return Bench(dut)


def queue_depth(w: int) -> int:
    """orb_desc_path's QDEPTH_c: the waiting bound 8 * ceil((W - 36) / 2) + 40, in 512-entry blocks."""
    return -(-(8 * ((w - 2 * DESC_BORDER + 1) // 2) + 40) // 512) * 512


def check_cands(bench: Bench) -> None:
    """Every feature shown on cand_* exactly CAND_LEAD_LAT clocks before it leaves, and nothing else."""
    want = [(e - CAND_LEAD_LAT, (f[0], f[1], f[3], f[4])) for e, f in zip(bench.out_edges, bench.out, strict=True)]
    assert bench.cands == want, f"{len(bench.cands)} candidates for {len(want)} features; first difference: " + str(
        next(((a, b) for a, b in zip(bench.cands, want, strict=False) if a != b), "in the counts")
    )


def check(got: list[Feature], exp: list[Feature], what: str) -> None:
    for i, (g, e) in enumerate(zip(got, exp, strict=False)):
        if g != e:
            fields = ("x", "y", "score", "low", "code", "sector", "descriptor")
            diff = [f"{f}: rtl {a:#x} model {b:#x}" for f, a, b in zip(fields, g, e, strict=True) if a != b]
            raise AssertionError(f"{what}: feature {i} at (x={e[0]}, y={e[1]}) differs: {'; '.join(diff)}")
    assert len(got) == len(exp), f"{what}: {len(got)} features out, model has {len(exp)}"


def photo_case(name: str, w: int, h: int, threshold: int, n: int, low_threshold: int | None = None):
    img = images.photo(name, w, h)
    xs, ys, score, low = detect(img, threshold, low_threshold)
    codes = response_map(img)
    sm = smooth(img)
    offer = [(int(s), int(lo), int(codes[y, x])) for x, y, s, lo in zip(xs, ys, score, low, strict=True)]
    feats = {(int(x), int(y)): o for x, y, o in zip(xs, ys, offer, strict=True)}
    return tagged(sm), feats, expected(sm, xs, ys, offer, n)


@cocotb.test()
async def photographs(dut) -> None:
    """Real photographs back to back, with and without input gaps."""
    n = env_int("ORB_SECTORS") // 4  # N, the sectors per quadrant
    w, h = env_int("ORB_LINE_WIDTH"), env_int("ORB_FRAME_HEIGHT")
    bench = await start(dut)
    lost0 = to_int(dut.lost.value)
    total: list[Feature] = []
    for k, (name, thr, low, gap_prob) in enumerate((("astronaut", 10, 4, 0.0), ("coffee", 8, None, 0.3),
                                                     ("camera", 20, 7, 0.0))):  # fmt: skip
        stream, feats, exp = photo_case(name, w, h, thr, n, low)
        assert len(exp) > 12, f"{name}: too few features to be a test ({len(exp)})"
        gaps = random_gaps(w * h, seed=k, prob=gap_prob, long_every=500) if gap_prob else None
        await bench.frame(stream, feats, gaps)
        total += exp
    await bench.idle(60)
    check(bench.out, total, "photographs")
    check_cands(bench)
    assert any(f[3] for f in total) and len({f[4] for f in total}) > 10, "low flags and codes are not exercised"
    assert len(bench.done_at) == 3, f"frame_done pulsed {len(bench.done_at)} times for 3 frames"
    assert to_int(dut.lost.value) == lost0, "features lost on legal frames"


@cocotb.test()
async def densest(dut) -> None:
    """One survivor per 2x2 block over the whole frame (the densest 3x3 NMS output)."""
    n = env_int("ORB_SECTORS") // 4  # N, the sectors per quadrant
    w, h = env_int("ORB_LINE_WIDTH"), env_int("ORB_FRAME_HEIGHT")
    rng = np.random.default_rng(5)
    img = rng.integers(0, 256, (h, w)).astype(np.uint8)
    sm = smooth(img)
    ys, xs = np.mgrid[0:h:2, 0:w:2]
    xs, ys = xs.ravel(), ys.ravel()
    offer = random_offers(rng, len(xs))
    feats = {(int(x), int(y)): o for x, y, o in zip(xs, ys, offer, strict=True)}
    exp = expected(sm, xs, ys, offer, n)
    bench = await start(dut)
    await bench.frame(tagged(sm), feats, None)
    await bench.idle(60)
    check(bench.out, exp, "densest pattern")
    check_cands(bench)
    assert len(exp) == ((w - 2 * DESC_BORDER + 1) // 2) * ((h - 2 * DESC_BORDER + 1) // 2)
    assert to_int(dut.lost.value) == 0, f"densest legal pattern lost {to_int(dut.lost.value)} features"


@cocotb.test()
async def cut_frame(dut) -> None:
    """A frame cut short: its waiting features are counted in `lost`, also when they straddle the
    wrap of the queue's pointers; the next frame is exact."""
    n = env_int("ORB_SECTORS") // 4  # N, the sectors per quadrant
    w, h = env_int("ORB_LINE_WIDTH"), env_int("ORB_FRAME_HEIGHT")
    stream, feats, exp = photo_case("astronaut", w, h, 10, n)
    stop = (h - 20) * w + w // 3  # pixels delivered before the cut
    last = divmod(stop - 1, w)  # (y, x) of the last delivered tag
    # offered (tag (x+4, y+4) delivered) but never reached (tag (x+18, y+18) not delivered)
    pending = [
        f for f in exp
        if (f[1] + DETECT_DELAY, f[0] + DETECT_DELAY) <= last < (f[1] + DESC_BORDER, f[0] + DESC_BORDER)
    ]  # fmt: skip
    reached = [f for f in exp if (f[1] + DESC_BORDER, f[0] + DESC_BORDER) <= last]
    assert pending and reached
    bench = await start(dut)
    # A first frame of dense features leaves the queue's pointers just short of its depth, so the
    # cut frame's waiting features straddle the wrap (the count of a wrapped queue is checked).
    ys0, xs0 = np.mgrid[DESC_BORDER : h - DESC_BORDER : 2, DESC_BORDER : w - DESC_BORDER : 2]
    k = queue_depth(w) - len(reached) - 3  # at the cut: read pointer 2 short of the wrap (the head holds one)
    assert 0 < k <= ys0.size, f"no pre-frame of {k} features fits {w}x{h}"
    xs0, ys0 = xs0.ravel()[:k], ys0.ravel()[:k]
    sm0 = smooth(np.random.default_rng(6).integers(0, 256, (h, w)).astype(np.uint8))
    offer0 = random_offers(np.random.default_rng(7), k)
    await bench.frame(tagged(sm0), {(int(x), int(y)): o for x, y, o in zip(xs0, ys0, offer0, strict=True)}, None)
    await bench.idle(60)
    check(bench.out, expected(sm0, xs0, ys0, offer0, n), "pre-frame")
    bench.out.clear()
    bench.done_at.clear()
    await bench.frame(stream, feats, None, stop=stop)
    await bench.idle(40)
    check(bench.out, reached, "cut frame, features before the cut")
    assert not bench.done_at, "frame_done for a frame cut short"
    stream2, feats2, exp2 = photo_case("coffee", w, h, 15, n)
    await bench.frame(stream2, feats2, None)
    await bench.idle(60)
    assert to_int(dut.lost.value) == len(pending), f"lost {to_int(dut.lost.value)}, expected {len(pending)}"
    check(bench.out[len(reached) :], exp2, "frame after the cut")
    assert len(bench.done_at) == 1


# 300 wide: the feature queue's depth (the bound 8 * 132 + 40 = 1096, rounded up to 1536) is not a
# power of two, and the densest pattern's 2,376 features wrap its pointers.
CASES = [(16, True, 128), (32, True, 128), (64, True, 128), (32, False, 300), (64, False, 128)]


@pytest.mark.parametrize(("sectors", "rotate", "width"), CASES)
def test_desc_path(sectors: int, rotate: bool, width: int) -> None:
    run("orb_desc_path", "test_orb_desc_path",
        {"LINE_WIDTH_g": width, "FRAME_HEIGHT_g": 72, "SECTORS_g": sectors, "ROTATE_g": rotate},
        env={**SIM_ENV, "ORB_ROTATE": str(int(rotate))})  # fmt: skip
