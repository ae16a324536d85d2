# SPDX-License-Identifier: MIT
"""orb_video_check against its beat-level reference model (tb/orbtb/video_check.py).

The source drives beats with random idle gaps and honours tready; a monitor records, at every
clock edge, the output beat and the frame_end / frame_bad / frame_fault outputs. The model predicts
the output pixel stream (input pixels and padding zeros, tuser/tlast), each frame's bad flag and
faults, and the counters; the RTL must match exactly. Besides: every frame the model calls good is
checked to be the input image itself, every bad frame's padding must leave at one pixel per clock,
frame_end must come with the frame's last pixel, and tready must stay high through good input.

Fault scenarios, each followed by a good frame that must come out unchanged: short line (also at
the first pixel and in the last line), long line (also the last line), a missing tlast on the
frame's last pixel, too few lines, too many lines, missing start of frame (and pixels before the
first frame), tuser in mid-line, tuser on the second line. Further: back-to-back good frames with
random gaps; rst in mid-frame then a good frame; a seeded random mix of all of these; a source
that cannot stall (documented recovery after a fault).
"""

from __future__ import annotations

from collections.abc import Callable

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge

from orbtb import images
from orbtb.runner import run
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int
from orbtb.video_check import Beat, OutBeat, VideoCheckModel, lines_to_beats

RESET = None  # an event in the beat list: rst for a few clocks (the source idle)
Event = Beat | None


class Bench:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.w, self.h = env_int("ORB_WIDTH"), env_int("ORB_HEIGHT")
        self.edge = 0
        self.out: list[tuple[int, OutBeat]] = []  # (edge, beat)
        self.ends: list[tuple[int, int, int]] = []  # (edge, bad, faults)
        self.ready_low_edges = 0

    async def start(self) -> None:
        dut = self.dut
        dut.rst.value = 1
        for name in ("tvalid", "tuser", "tlast", "tdata"):
            getattr(dut, f"s_axis_video_{name}").value = 0
        dut.m_axis_video_tready.value = 1
        cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
        await ClockCycles(dut.clk, 3)
        dut.rst.value = 0
        cocotb.start_soon(self._monitor())
        await RisingEdge(dut.clk)

    async def _monitor(self) -> None:
        dut = self.dut
        while True:
            await RisingEdge(dut.clk)
            self.edge += 1
            if dut.m_axis_video_tvalid.value == 1:
                beat = OutBeat(
                    int(dut.m_axis_video_tdata.value),
                    int(dut.m_axis_video_tuser.value),
                    int(dut.m_axis_video_tlast.value),
                    False,
                )
                self.out.append((self.edge, beat))
            if dut.frame_end.value == 1:
                self.ends.append((self.edge, int(dut.frame_bad.value), int(dut.frame_fault.value)))

    async def drive(self, events: list[Event], seed: int, idle_prob: float = 0.2) -> None:
        """Send the beats (with random idle clocks before some), RESET events as rst pulses."""
        dut = self.dut
        rng = np.random.default_rng(seed)
        idles = np.where(rng.random(len(events)) < idle_prob, rng.integers(1, 4, len(events)), 0).tolist()
        for ev, idle in zip(events, idles, strict=True):
            if ev is RESET:
                # wait for the checker to be idle (tready high: no padding, no held pixel), since
                # the model applies a reset between beats
                dut.s_axis_video_tvalid.value = 0
                await RisingEdge(dut.clk)
                while dut.s_axis_video_tready.value != 1:
                    await RisingEdge(dut.clk)
                dut.rst.value = 1
                await ClockCycles(dut.clk, 2)
                dut.rst.value = 0
                await RisingEdge(dut.clk)
                continue
            if idle:
                dut.s_axis_video_tvalid.value = 0
                await ClockCycles(dut.clk, idle)
            dut.s_axis_video_tdata.value = ev.data
            dut.s_axis_video_tuser.value = ev.user
            dut.s_axis_video_tlast.value = ev.last
            dut.s_axis_video_tvalid.value = 1
            while True:
                await RisingEdge(dut.clk)
                if dut.s_axis_video_tready.value == 1:
                    break
                self.ready_low_edges += 1
        dut.s_axis_video_tvalid.value = 0
        dut.s_axis_video_tuser.value = 0
        dut.s_axis_video_tlast.value = 0
        await ClockCycles(dut.clk, self.w * self.h + 8)  # any padding under way ends

    def check(self, events: list[Event], what: str, good_images: list[np.ndarray] | None = None) -> VideoCheckModel:
        model = VideoCheckModel(self.w, self.h)
        for ev in events:
            if ev is RESET:
                model.reset()
            else:
                model.beat(ev)
        got = [b for _, b in self.out]
        exp = [OutBeat(b.data, b.user, b.last, False) for b in model.out]
        if got != exp:
            i = next((i for i, (a, b) in enumerate(zip(got, exp, strict=False)) if a != b), min(len(got), len(exp)))
            raise AssertionError(
                f"{what}: output beat {i} is {got[i] if i < len(got) else None}, model "
                f"{model.out[i] if i < len(exp) else None} ({len(got)} beats out, model {len(exp)})"
            )
        got_ends = [(bad, faults) for _, bad, faults in self.ends]
        exp_ends = [(int(e.bad), e.faults) for e in model.ends]
        assert got_ends == exp_ends, f"{what}: frame_end (bad, faults) {got_ends}, model {exp_ends}"
        out_edges = [e for e, _ in self.out]
        for (edge, _, _), e in zip(self.ends, model.ends, strict=True):
            assert edge == out_edges[e.beat], f"{what}: frame_end at edge {edge}, its last pixel at {out_edges[e.beat]}"
        # padding at one pixel per clock: a run of padding beats leaves on consecutive edges
        for i in range(1, len(model.out)):
            if model.out[i].pad and model.out[i - 1].pad:
                assert out_edges[i] == out_edges[i - 1] + 1, f"{what}: padding beat {i} not one clock after the last"
        errors, discarded = int(self.dut.protocol_errors.value), int(self.dut.discarded_pixels.value)
        assert (errors, discarded) == (model.protocol_errors, model.discarded_pixels), (
            f"{what}: protocol_errors, discarded_pixels = {errors}, {discarded}; "
            f"model {model.protocol_errors}, {model.discarded_pixels}"
        )
        # the model's good frames are the input images themselves
        good = [model.out[e.beat - self.w * self.h + 1 : e.beat + 1] for e in model.ends if not e.bad]
        for k, img in enumerate(good_images or []):
            frame = np.array([b.data for b in good[k]]).reshape(self.h, self.w)
            assert np.array_equal(frame, img), f"{what}: good frame {k} is not the input image"
        self.dut._log.info(
            "%s: %d beats out (%d padding), %d frames (%d bad), %d discarded, all as the model",
            what,
            len(got),
            sum(b.pad for b in model.out),
            len(model.ends),
            model.protocol_errors,
            model.discarded_pixels,
        )
        return model


def image(w: int, h: int, k: int) -> np.ndarray:
    names = ("astronaut", "camera", "coffee", "chelsea", "rocket")
    return images.photo(names[k % len(names)], w, h).astype(np.int64)


def rows(img: np.ndarray) -> list[list[int]]:
    return [list(map(int, r)) for r in img]


def fault_frames(w: int, h: int, rng: np.random.Generator) -> dict[str, tuple[Callable[[np.ndarray], list[Beat]], str]]:
    """Every fault kind: a function of an image giving its malformed beats, and what must come out
    of it: "bad" (one frame, padded, bad), "good" (the frame itself was complete: too many lines,
    the extra lines discarded) or "none" (no frame opens: every pixel discarded)."""

    def rand_line(n: int) -> list[int]:
        return [int(v) for v in rng.integers(0, 256, n)]

    def with_line(img: np.ndarray, r: int, line: list[int]) -> list[Beat]:
        lines = rows(img)
        lines[r] = line
        return lines_to_beats(lines)

    mid = h // 2
    return {
        "short line": (lambda img: with_line(img, mid, rows(img)[mid][: w // 2]), "bad"),
        "short line at the first pixel": (lambda img: with_line(img, 0, rows(img)[0][:1]), "bad"),
        "short last line": (lambda img: with_line(img, h - 1, rows(img)[h - 1][: w - 1]), "bad"),
        "long line": (lambda img: with_line(img, mid, rows(img)[mid] + rand_line(3)), "bad"),
        "long last line": (lambda img: with_line(img, h - 1, rows(img)[h - 1] + rand_line(2)), "bad"),
        "no tlast on the last pixel": (lambda img: lines_to_beats(rows(img), last_tlast=False), "bad"),
        "too few lines": (lambda img: lines_to_beats(rows(img)[: h - 2]), "bad"),
        "one line only": (lambda img: lines_to_beats(rows(img)[:1]), "bad"),
        "too many lines": (lambda img: lines_to_beats([*rows(img), rand_line(w), rand_line(w)]), "good"),
        "missing start of frame": (lambda img: lines_to_beats(rows(img), sof=False), "none"),
        "tuser in mid-line": (
            lambda img: lines_to_beats([*rows(img)[:mid], rows(img)[mid][: w // 3]], last_tlast=False),
            "bad",
        ),
    }


@cocotb.test()
async def each_fault_then_good(dut) -> None:
    """Every fault kind, each followed by a good frame that must come out unchanged."""
    b = Bench(dut)
    await b.start()
    rng = np.random.default_rng(11)
    events: list[Event] = [Beat(7), Beat(8, last=1)]  # pixels before any frame: discarded
    goods: list[np.ndarray] = []
    outcome: list[bool] = []  # expected frame_bad of every frame_end
    for k, (name, (make, result)) in enumerate(fault_frames(b.w, b.h, rng).items()):
        dut._log.info("scenario %d: %s (%s)", k, name, result)
        img = image(b.w, b.h, k)
        events += make(img)
        if result != "none":
            outcome.append(result == "bad")
        if result == "good":
            goods.append(img)
        good = image(b.w, b.h, k + 1)[::-1]
        events += lines_to_beats(rows(good))
        outcome.append(False)
        goods.append(good)
    await b.drive(events, seed=1)
    model = b.check(events, "each fault then a good frame", goods)
    assert [e.bad for e in model.ends] == outcome, "model: frames ending bad/good not as the scenarios say"


@cocotb.test()
async def good_frames_with_gaps(dut) -> None:
    """Back-to-back good frames with random gaps: unchanged, never bad, tready always high."""
    b = Bench(dut)
    await b.start()
    imgs = [image(b.w, b.h, k) for k in range(4)]
    events: list[Event] = [beat for img in imgs for beat in lines_to_beats(rows(img))]
    await b.drive(events, seed=2, idle_prob=0.3)
    model = b.check(events, "good frames", imgs)
    assert len(model.ends) == len(imgs) and not any(e.bad for e in model.ends)
    assert b.ready_low_edges == 0, f"tready low at {b.ready_low_edges} edges with well-formed input"
    assert (int(dut.protocol_errors.value), int(dut.discarded_pixels.value)) == (0, 0)


@cocotb.test()
async def reset_mid_frame(dut) -> None:
    """rst in mid-frame: the open frame is abandoned (no frame_end), the rest of it after reset is
    discarded (counters restart at 0), and the next frame comes out unchanged."""
    b = Bench(dut)
    await b.start()
    first, second = image(b.w, b.h, 0), image(b.w, b.h, 1)
    beats = lines_to_beats(rows(first))
    cut = len(beats) // 2 + 3
    events: list[Event] = [*beats[:cut], RESET, *beats[cut:], *lines_to_beats(rows(second))]
    await b.drive(events, seed=3)
    model = b.check(events, "reset in mid-frame", [second])
    assert len(model.ends) == 1 and model.discarded_pixels == len(beats) - cut


@cocotb.test()
async def random_mix(dut) -> None:
    """A seeded random mix of good and faulty frames (and resets) against the model."""
    b = Bench(dut)
    await b.start()
    rng = np.random.default_rng(env_int("ORB_SEED", 5))
    faults = fault_frames(b.w, b.h, rng)
    names = list(faults)
    events: list[Event] = []
    for k in range(24):
        img = image(b.w, b.h, k)
        pick = rng.integers(0, len(names) + 3)
        if pick < len(names):
            events += faults[names[pick]][0](img)
        elif pick == len(names) and events:
            cut = int(rng.integers(1, 2 * b.w))
            events += [*lines_to_beats(rows(img))[:cut], RESET]
        else:
            events += lines_to_beats(rows(img))
    await b.drive(events, seed=4, idle_prob=0.25)
    b.check(events, "random mix")


@cocotb.test()
async def non_stallable_source(dut) -> None:
    """A source that ignores tready (HDMI-like: one pixel per clock in active video, blanking of 4
    clocks per line and 3 lines per frame): after a frame with too few lines, the next frame
    loses the pixels sent during the padding and ends bad too; the frame after it is good again."""
    b = Bench(dut)
    await b.start()
    imgs = [image(b.w, b.h, k) for k in range(5)]
    frames = [rows(img) for img in imgs]
    frames[1] = frames[1][: b.h - 2]
    for lines in frames:
        for beat in lines_to_beats(lines):
            dut.s_axis_video_tdata.value = beat.data
            dut.s_axis_video_tuser.value = beat.user
            dut.s_axis_video_tlast.value = beat.last
            dut.s_axis_video_tvalid.value = 1
            await RisingEdge(dut.clk)
            if beat.last:
                dut.s_axis_video_tvalid.value = 0
                await ClockCycles(dut.clk, 4)
        dut.s_axis_video_tvalid.value = 0
        await ClockCycles(dut.clk, 3 * b.w)
    await ClockCycles(dut.clk, b.w * b.h + 8)
    flags = [(bad, faults) for _, bad, faults in b.ends]
    assert [bad for bad, _ in flags] == [0, 1, 1, 0, 0], f"frame_end (bad, faults) {flags}"
    out = [beat.data for _, beat in b.out]
    n = b.w * b.h
    for k in (0, 3, 4):
        assert np.array_equal(np.array(out[k * n : (k + 1) * n]).reshape(b.h, b.w), imgs[k]), f"frame {k} differs"
    dut._log.info("non-stallable source: frame_end (bad, faults) %s", flags)


# ------------------------------------------------------------------------------------------------
# pytest runners


def test_video_check_16x6() -> None:
    run("orb_video_check", "test_orb_video_check", {"WIDTH_g": 16, "HEIGHT_g": 6}, env=SIM_ENV)


def test_video_check_33x5() -> None:
    run("orb_video_check", "test_orb_video_check", {"WIDTH_g": 33, "HEIGHT_g": 5}, env={**SIM_ENV, "ORB_SEED": "9"})


def test_feed_arrays_is_beat_by_beat() -> None:
    """The model's bulk path (feed_arrays, used by the fault campaign, orbtb.campaign) against beat()
    on the fault kinds above and cuts, each beat sequence split at random points: the same output
    beats, frame ends and counters. Python only (no simulation)."""
    w, h = 13, 5
    rng = np.random.default_rng(17)
    faults = fault_frames(w, h, rng)
    names = list(faults)
    beats: list[Beat] = []
    for k in range(60):
        img = image(w, h, k)
        pick = int(rng.integers(0, len(names) + 5))
        frame = faults[names[pick]][0](img) if pick < len(names) else lines_to_beats(rows(img))
        if pick == len(names):  # a cable cut: the frame stops anywhere, the next one may start anywhere
            frame = frame[: int(rng.integers(1, len(frame)))] + lines_to_beats(rows(img))[int(rng.integers(1, w * h)) :]
        beats += frame
    one, bulk = VideoCheckModel(w, h), VideoCheckModel(w, h)
    one.feed(beats)
    cuts = sorted(int(c) for c in rng.integers(0, len(beats), 40))
    for a, b in zip([0, *cuts], [*cuts, len(beats)], strict=True):
        part = beats[a:b]
        bulk.feed_arrays(np.array([x.data for x in part], dtype=np.int64), np.array([x.user for x in part]),
                         np.array([x.last for x in part]))  # fmt: skip
    assert len(one.ends) > 40 and sum(not e.bad for e in one.ends) > 10
    assert bulk.out == one.out and bulk.ends == one.ends
    assert (bulk.protocol_errors, bulk.discarded_pixels) == (one.protocol_errors, one.discarded_pixels)
