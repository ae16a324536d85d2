# SPDX-License-Identifier: MIT
"""orb_video_check against its reference models (tb/orbtb/video_check.py): the beat-level model with
IDLE_TIMEOUT_g = 0 (a source that can wait), the clock-level model with IDLE_TIMEOUT_g > 0 (a live
source: tready stays high, pixels arriving while a frame is padded are discarded, an open frame idle
for IDLE_TIMEOUT_g clocks is padded at once).

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

With IDLE_TIMEOUT_g > 0 (the live tests; every input pixel taken and every reset is recorded per
clock edge and replayed through the clock-level model, which must give the same output beats at the
same edges, the same frame ends and counters): the idle timeout at its boundary (an idle gap of
IDLE_TIMEOUT_g - 1 clocks in mid-line leaves the frame good, IDLE_TIMEOUT_g pads it at once), at a
line start, after the first pixel only, before the last pixel, and a source coming back while the
cut frame is padded (that frame lost, the next good); every fault kind followed by the next frame
after a gap shorter than the timeout (a start of frame in an open frame: that frame lost, the one
after it unchanged) and after one longer than it (the timeout closes the faulty frame first: the
next frame unchanged); a seeded random mix with long gaps and resets; tready never low.
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
from orbtb.video_check import (
    EARLY_SOF,
    FEW_LINES,
    IDLE,
    LONG_LINE,
    SHORT_LINE,
    Beat,
    LiveVideoCheckModel,
    OutBeat,
    VideoCheckModel,
    lines_to_beats,
)

RESET = None  # an event in the beat list: rst for a few clocks (the source idle)
Event = Beat | None | int  # an int: the source idle (tvalid low) for that many clocks


class Bench:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.w, self.h = env_int("ORB_WIDTH"), env_int("ORB_HEIGHT")
        self.timeout = env_int("ORB_IDLE_TIMEOUT", 0)
        self.edge = 0
        self.out: list[tuple[int, OutBeat]] = []  # (edge, beat)
        self.ends: list[tuple[int, int, int]] = []  # (edge, bad, faults)
        self.taken: list[tuple[bool, Beat | None]] = []  # per edge: rst, the input pixel taken
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
            beat = None
            if dut.s_axis_video_tvalid.value == 1 and dut.s_axis_video_tready.value == 1:
                data, user = int(dut.s_axis_video_tdata.value), int(dut.s_axis_video_tuser.value)
                beat = Beat(data, user, int(dut.s_axis_video_tlast.value))
            self.taken.append((dut.rst.value == 1, beat))
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
        """Send the beats (with random idle clocks before some), RESET events as rst pulses, int
        events as that many idle clocks."""
        dut = self.dut
        rng = np.random.default_rng(seed)
        idles = np.where(rng.random(len(events)) < idle_prob, rng.integers(1, 4, len(events)), 0).tolist()
        for ev, idle in zip(events, idles, strict=True):
            if isinstance(ev, int):
                dut.s_axis_video_tvalid.value = 0
                await ClockCycles(dut.clk, ev)
                continue
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
        await ClockCycles(dut.clk, self.timeout + self.w * self.h + 8)  # any padding under way ends

    def check(
        self, events: list[Event], what: str, good_images: list[np.ndarray] | None = None
    ) -> VideoCheckModel | LiveVideoCheckModel:
        model: VideoCheckModel | LiveVideoCheckModel
        if self.timeout:
            model = LiveVideoCheckModel(self.w, self.h, self.timeout)
            for rst, beat in self.taken:
                model.edge(beat, rst)
            # a pixel emitted at edge k is read after edge k + 1 (values read after an edge are those it
            # sampled; the monitor's first edge is model edge 0)
            got_edges = [e - 2 for e, _ in self.out]
            if got_edges != model.edges[: len(got_edges)]:
                i = next((i for i, (a, b) in enumerate(zip(got_edges, model.edges, strict=False)) if a != b), 0)
                raise AssertionError(f"{what}: output beat {i} at edge {got_edges[i]}, model {model.edges[i]}")
            assert self.ready_low_edges == 0, f"{what}: tready low at {self.ready_low_edges} edges (a live source)"
        else:
            model = VideoCheckModel(self.w, self.h)
            for ev in events:
                if ev is RESET:
                    model.reset()
                elif not isinstance(ev, int):
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
# a live source (IDLE_TIMEOUT_g > 0)

TUSER_FAULTS = {"too few lines": FEW_LINES, "one line only": FEW_LINES, "tuser in mid-line": EARLY_SOF}
LINE_FAULTS = {
    "short line": SHORT_LINE,
    "short line at the first pixel": SHORT_LINE,
    "short last line": SHORT_LINE,
    "long line": LONG_LINE,
    "long last line": LONG_LINE,
    "no tlast on the last pixel": LONG_LINE,
}


def blanked(events: list[Event], h_blank: int) -> list[Event]:
    """The events with h_blank idle clocks after each line's last pixel (a live source's blanking)."""
    out: list[Event] = []
    for ev in events:
        out.append(ev)
        if isinstance(ev, Beat) and ev.last and h_blank:
            out.append(h_blank)
    return out


def live_bench(dut) -> Bench:
    b = Bench(dut)
    assert b.timeout > 0, "the live tests run with IDLE_TIMEOUT_g > 0"
    return b


def faults_of(model: VideoCheckModel | LiveVideoCheckModel) -> list[int]:
    return [e.faults for e in model.ends]


@cocotb.test()
async def live_idle_timeout(dut) -> None:
    """The idle timeout at its boundary and wherever a cut falls, and the source coming back while the
    cut frame is padded."""
    b = live_bench(dut)
    await b.start()
    t, w, h, n = b.timeout, b.w, b.h, b.w * b.h
    out = t + n + 4  # the cable out longer than the timeout and any padding
    imgs = [image(w, h, k) for k in range(12)]
    beats = [lines_to_beats(rows(img)) for img in imgs]
    mid = n // 2 + w // 3  # in mid-line
    assert mid % w != 0
    events: list[Event] = [
        # A: idle IDLE_TIMEOUT_g - 1 clocks in mid-line: no timeout, A good
        *beats[0][:mid], t - 1, *beats[0][mid:], 8,
        # B: idle IDLE_TIMEOUT_g clocks in mid-line: padded at once; the rest of B is discarded; C good
        *beats[1][:mid], t, *beats[1][mid:], 8, *beats[2], 8,
        # D: the start-of-frame pixel only, then the cable out; E good
        beats[3][0], out, *beats[4], 8,
        # F: cut at a line start (after two lines); G good
        *beats[5][: 2 * w], out, *beats[6], 8,
        # H: cut before its last pixel (one pixel padded); I good
        *beats[7][: n - 1], out, *beats[8], 8,
        # J: cut after one line, back after IDLE_TIMEOUT_g + 2 clocks, while J is padded: K's start of
        # frame is discarded with K; L good
        *beats[9][:w], t + 2, *beats[10], 8, *beats[11], 8,
    ]  # fmt: skip
    goods = [imgs[k] for k in (0, 2, 4, 6, 8, 11)]
    await b.drive(events, seed=21, idle_prob=0)
    model = b.check(events, "live: idle timeout", goods)
    want = [0, IDLE, 0, IDLE, 0, IDLE, 0, IDLE, 0, IDLE, 0]
    assert faults_of(model) == want, f"model: frame faults {faults_of(model)}, the scenario says {want}"


@cocotb.test()
async def live_faults(dut) -> None:
    """Every fault kind on a live source with line blanking, each followed by two good frames: after a
    gap shorter than the timeout a start of frame in the open frame ends it (that next frame lost, the
    one after it unchanged); after a longer gap the timeout closes it first (the next frame
    unchanged); a line fault's padding ends within the rest of its frame (the next frame unchanged)."""
    b = live_bench(dut)
    await b.start()
    t, w, h, n = b.timeout, b.w, b.h, b.w * b.h
    h_blank = w // 2 + 2  # below the timeout; a line fault's padding ends before the next frame
    assert h_blank < t
    rng = np.random.default_rng(12)
    events: list[Event] = []
    want: list[int] = []
    goods: list[np.ndarray] = []
    for k, (name, (make, result)) in enumerate(fault_frames(w, h, rng).items()):
        for gap in (2, t + n + 4):
            img, g1, g2 = image(w, h, k), image(w, h, k + 1)[::-1], image(w, h, k + 2)[:, ::-1]
            events += [*blanked(make(img), h_blank), gap, *blanked(lines_to_beats(rows(g1)), h_blank), t + n + 4]
            events += [*blanked(lines_to_beats(rows(g2)), h_blank), 8]
            if name in TUSER_FAULTS and gap < t:
                want += [TUSER_FAULTS[name], 0]
                goods += [g2]
                continue
            if name in TUSER_FAULTS:
                want.append(IDLE)
            elif name in LINE_FAULTS:
                want.append(LINE_FAULTS[name])
            elif result == "good":
                want.append(0)
                goods.append(img)
            want += [0, 0]
            goods += [g1, g2]
    await b.drive(events, seed=22, idle_prob=0)
    model = b.check(events, "live: every fault", goods)
    assert faults_of(model) == want, f"model: frame faults {faults_of(model)}, the scenarios say {want}"


@cocotb.test()
async def live_mix(dut) -> None:
    """A seeded random mix on a live source: faults, good frames with blanking, gaps around the
    timeout between and inside frames, resets."""
    b = live_bench(dut)
    await b.start()
    t, w, h, n = b.timeout, b.w, b.h, b.w * b.h
    rng = np.random.default_rng(env_int("ORB_SEED", 5) + 100)
    faults = fault_frames(w, h, rng)
    names = list(faults)
    events: list[Event] = []
    for k in range(30):
        img = image(w, h, k)
        pick = int(rng.integers(0, len(names) + 4))
        beats: list[Event]
        if pick < len(names):
            beats = list(faults[names[pick]][0](img))
        elif pick == len(names) and events:
            beats = [*lines_to_beats(rows(img))[: int(rng.integers(1, 2 * w))], RESET]
        else:
            beats = list(lines_to_beats(rows(img)))
            if pick == len(names) + 1:  # a gap inside the frame, around the timeout
                at = int(rng.integers(1, n))
                beats[at:at] = [int(rng.choice([t - 1, t, t + 3]))]
        events += blanked(beats, int(rng.integers(0, 4)))
        events.append(int(rng.choice([1, t - 1, t, t + n // 2, t + n + 4])))
    await b.drive(events, seed=23, idle_prob=0.1)
    model = b.check(events, "live: random mix")
    assert any(f & IDLE for f in faults_of(model)), "the mix has no idle timeout: pick another seed"


# ------------------------------------------------------------------------------------------------
# pytest runners


HOLD_TESTS = ["each_fault_then_good", "good_frames_with_gaps", "reset_mid_frame", "random_mix", "non_stallable_source"]
LIVE_TESTS = ["live_idle_timeout", "live_faults", "live_mix", "good_frames_with_gaps", "reset_mid_frame"]


def test_video_check_16x6() -> None:
    run("orb_video_check", "test_orb_video_check", {"WIDTH_g": 16, "HEIGHT_g": 6}, env=SIM_ENV, testcase=HOLD_TESTS)


def test_video_check_33x5() -> None:
    generics = {"WIDTH_g": 33, "HEIGHT_g": 5}
    run("orb_video_check", "test_orb_video_check", generics, env={**SIM_ENV, "ORB_SEED": "9"}, testcase=HOLD_TESTS)


def test_video_check_live_16x6() -> None:
    generics = {"WIDTH_g": 16, "HEIGHT_g": 6, "IDLE_TIMEOUT_g": 24}
    run("orb_video_check", "test_orb_video_check", generics, env=SIM_ENV, testcase=LIVE_TESTS)


def test_video_check_live_33x5() -> None:
    generics = {"WIDTH_g": 33, "HEIGHT_g": 5, "IDLE_TIMEOUT_g": 50}
    run("orb_video_check", "test_orb_video_check", generics, env={**SIM_ENV, "ORB_SEED": "9"}, testcase=LIVE_TESTS)


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
