# SPDX-License-Identifier: MIT
"""orb_overlay (HDMI feature overlay) against the golden model, pixel for pixel (docs/spec.md 13).

The cocotb test runs one scenario: RGB video frames through s_axis_video and feature frames through
s_axis_feat, timed against the video as the scenario says (spread over a video frame, end-of-frame
beat before, at or one edge before the next start of frame, a frame starting early, ...). A
monitor records the clock edge of every accepted beat on the three streams. Afterwards the
accepted starts of frame and feature beats, in edge order (a feature beat OVERLAY_FEAT_LAT edges after
its acceptance, where the overlay takes it: spec 13.3), go through the model's
`marker_schedule` (which feature frame each video frame shows); each scenario also states the
schedule it means to produce, so a test cannot pass by showing nothing. Every output pixel must
equal `render_marker_overlay(video frame, shown feature frame)` (or the input pixel when none is
shown), with tuser/tlast passed through, the AXI4-Stream output held while stalled, and, without
back-pressure, the fixed latency of 3 clocks. The RTL's own assertion (a mark and a clear never in
one bank on one clock) is live in every run.

Scenarios: `photos` (features of real photographs at 1 to 8 scales of the 2:1 or a finer pyramid
step (ORB_STEP), interleaved scale order),
`borders` (features at every border and corner of every scale, plus out-of-range ones),
`sequence` (a feature in every block at every scale, then an empty feature frame, a photograph's
features and no feature frame: clearing proven), `timing` (end-of-frame at the same edge as / one
edge before a start of frame, a frame starting early, a feature beat on the start-of-frame edge).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cocotb
import cv2
import numpy as np
import pytest
from cocotb.triggers import RisingEdge

from golden_model import Config, extract
from golden_model.config import level_size, parse_step
from golden_model.featcodec import decode_stream_features, encode_eof, encode_feature
from golden_model.features import NO_SECTOR, Features
from golden_model.featword import EOF_FLAG, FEAT_BITS, FEATURE_BEAT
from golden_model.images import to_luma
from golden_model.latency import OVERLAY_FEAT_LAT, OVERLAY_VIDEO_LAT
from golden_model.overlay import marker_bitmap, marker_schedule, render_marker_overlay
from orbtb.runner import run
from orbtb.unit import env_int, env_str, reset

RGB_PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "camera")
# feature words carry random bits from above the end-of-frame flag on (sector, reserved bits,
# descriptor): the overlay reads only x, y and scale
JUNK_LO = EOF_FLAG.lsb + 1
JUNK_BYTES = (FEAT_BITS - JUNK_LO) // 8


# ------------------------------------------------------------------------------------------------
# stimuli


def rgb_photo(name: str, width: int, height: int) -> np.ndarray:
    """A scikit-image photograph as (height, width, 3) uint8 RGB (grey ones repeated), resized so
    that it covers the frame, then cropped at the centre."""
    import skimage.data as data

    img = getattr(data, name)()
    if img.ndim == 2:
        img = np.repeat(img[..., None], 3, axis=2)
    img = img[..., :3]
    h, w = img.shape[:2]
    scale = max(width / w, height / h)
    if scale > 1 or min(w, h) > 3 * max(width, height):
        size = (max(width, round(w * scale)), max(height, round(h * scale)))
        img = cv2.resize(img, size, interpolation=cv2.INTER_AREA)
    h, w = img.shape[:2]
    y0, x0 = (h - height) // 2, (w - width) // 2
    return np.ascontiguousarray(img[y0 : y0 + height, x0 : x0 + width])


def photo_features(rgb: np.ndarray, scales: int, step: tuple[int, int] = (2, 1), threshold: int = 20) -> Features:
    h, w = rgb.shape[:2]
    return extract(to_luma(rgb), Config(w, h, scales=scales, threshold=threshold, mode="fast", step_num=step[0],
                                        step_den=step[1]))  # fmt: skip


def level_coord(full: float, s: int, step: tuple[int, int]) -> int:
    """A level-s coordinate whose centre lies near full-resolution coordinate `full` (stimulus only;
    the model's marker_bitmap decides which block it marks)."""
    return max(0, int(np.floor((full + 0.5) / (step[0] / step[1]) ** s - 0.5)))


def make_features(scale: list[int], x: list[int], y: list[int]) -> Features:
    n = len(x)
    ints = [np.array(v, dtype=np.int64) for v in (scale, x, y)]
    return Features(*ints, np.zeros(n, dtype=np.int64), np.full(n, NO_SECTOR, dtype=np.int64),
                    np.zeros((n, 0), dtype=np.uint8))  # fmt: skip


def interleaved_words(f: Features, rng: np.random.Generator) -> list[int]:
    """Feature words in an interleaved scale order: each scale's features in raster order, the next
    scale picked at random per beat (as a merge of per-scale streams delivers them). Unused fields
    (score, sector, descriptor) carry random bits: the overlay must ignore them."""
    per_scale = {}
    for s in sorted(set(f.scale.tolist())):
        idx = np.flatnonzero(f.scale == s)
        idx = idx[np.lexsort((f.x[idx], f.y[idx]))]
        per_scale[s] = list(idx)
    words = []
    while per_scale:
        s = list(per_scale)[int(rng.integers(len(per_scale)))]
        i = per_scale[s].pop(0)
        if not per_scale[s]:
            del per_scale[s]
        junk = int.from_bytes(rng.bytes(JUNK_BYTES), "little") << JUNK_LO
        score = int(rng.integers(1 << FEATURE_BEAT.field("score").width))
        words.append(junk | encode_feature(scale=int(f.scale[i]), x=int(f.x[i]), y=int(f.y[i]), score=score))
    return words


def shuffled_words(f: Features, rng: np.random.Generator) -> list[int]:
    return [interleaved_words(f.take(np.array([i])), rng)[0] for i in rng.permutation(len(f))]


def eof_word(number: int) -> int:
    return encode_eof(number)


def decode(words: list[int], step: tuple[int, int]) -> Features:
    """The features of a frame's words (fast mode; the random bits above the flag, the selection's
    fields among them, are not checked: the overlay marks every word)."""
    f = decode_stream_features(words, check=False, resolve=False)
    f.step = step
    return f


def pack_rgb(rgb: np.ndarray) -> list[int]:
    p = rgb.astype(np.int64)
    return ((p[..., 0] << 16) | (p[..., 1] << 8) | p[..., 2]).ravel().tolist()


# ------------------------------------------------------------------------------------------------
# bench


@dataclass
class Bench:
    dut: object
    width: int = 0
    height: int = 0
    scales: int = 0
    block_log2: int = 0
    backpressure: float = 0.0
    video_idle: float = 0.0
    blank: int = 8
    edge: int = 0
    rng: np.random.Generator = field(default_factory=lambda: np.random.default_rng(1))
    frames: list[np.ndarray] = field(default_factory=list)  # video frames sent
    events: list[tuple[int, int, str]] = field(default_factory=list)  # (edge, order, kind)
    feat_words: list[int] = field(default_factory=list)  # accepted feature-stream words, EOFs included
    in_beats: list[tuple[int, int, int, int]] = field(default_factory=list)  # (edge, data, user, last)
    out_beats: list[tuple[int, int, int, int]] = field(default_factory=list)
    feat_busy: bool = False

    def __post_init__(self) -> None:
        self.width, self.height = env_int("ORB_WIDTH"), env_int("ORB_HEIGHT")
        self.scales, self.block_log2 = env_int("ORB_SCALES"), env_int("ORB_BLOCK_LOG2")
        self.step = parse_step(env_str("ORB_STEP", "2:1"))
        self.backpressure = float(env_str("ORB_BACKPRESSURE", "0"))
        self.video_idle = float(env_str("ORB_VIDEO_IDLE", "0"))
        self.rng = np.random.default_rng(env_int("ORB_SEED", 1))

    async def start(self) -> None:
        names = ("s_axis_video_tdata", "s_axis_video_tvalid", "s_axis_video_tuser", "s_axis_video_tlast",
                 "s_axis_feat_tdata", "s_axis_feat_tvalid", "s_axis_feat_tlast")  # fmt: skip
        await reset(self.dut, dict.fromkeys(names, 0) | {"m_axis_video_tready": 1})
        cocotb.start_soon(self.monitor())

    async def monitor(self) -> None:
        dut = self.dut
        sv_valid, sv_ready, sv_data = dut.s_axis_video_tvalid, dut.s_axis_video_tready, dut.s_axis_video_tdata
        sv_user, sv_last = dut.s_axis_video_tuser, dut.s_axis_video_tlast
        sf_valid, sf_ready, sf_data, sf_last = (dut.s_axis_feat_tvalid, dut.s_axis_feat_tready, dut.s_axis_feat_tdata,
                                                dut.s_axis_feat_tlast)  # fmt: skip
        mv_valid, mv_ready, mv_data = dut.m_axis_video_tvalid, dut.m_axis_video_tready, dut.m_axis_video_tdata
        mv_user, mv_last = dut.m_axis_video_tuser, dut.m_axis_video_tlast
        stalled: tuple[int, int, int] | None = None
        ready = 1
        while True:
            await RisingEdge(dut.clk)
            self.edge += 1
            e = self.edge
            if sv_valid.value == 1 and sv_ready.value == 1:
                user = int(sv_user.value)
                self.in_beats.append((e, int(sv_data.value), user, int(sv_last.value)))
                if user:
                    self.events.append((e, 0, "sof"))
            assert sf_ready.value == 1, f"edge {e}: s_axis_feat_tready low"
            if sf_valid.value == 1:
                last = int(sf_last.value)
                self.feat_words.append(int(sf_data.value) | (last << FEAT_BITS))
                # counted where the overlay takes it, OVERLAY_FEAT_LAT edges after the port (spec 13.3)
                self.events.append((e + OVERLAY_FEAT_LAT, 1, "eof" if last else "feature"))
            if mv_valid.value == 1:
                beat = (int(mv_data.value), int(mv_user.value), int(mv_last.value))
                if stalled is not None:
                    assert beat == stalled, f"edge {e}: output changed while stalled: {stalled} -> {beat}"
                if ready:
                    self.out_beats.append((e, *beat))
                    stalled = None
                else:
                    stalled = beat
            else:
                assert stalled is None, f"edge {e}: tvalid dropped while the output was stalled"
            new_ready = int(self.rng.random() >= self.backpressure) if self.backpressure > 0 else 1
            if new_ready != ready:
                mv_ready.value = new_ready
                ready = new_ready

    # ---- drivers ----------------------------------------------------------------------------------
    async def video_frame(self, rgb: np.ndarray, with_first: int | None = None) -> None:
        """Send one frame; returns once its last pixel is accepted. `with_first`: a feature-stream
        end-of-frame word driven together with the first pixel (both taken on one edge, since
        s_axis_feat never stalls: the test checks the recorded edges)."""
        dut = self.dut
        self.frames.append(rgb)
        w = rgb.shape[1]
        tdata, tvalid, tuser, tlast, tready = (dut.s_axis_video_tdata, dut.s_axis_video_tvalid, dut.s_axis_video_tuser,
                                               dut.s_axis_video_tlast, dut.s_axis_video_tready)  # fmt: skip
        pixels = pack_rgb(rgb)
        idle = (self.rng.random(len(pixels)) < self.video_idle).tolist()
        valid_on = False
        for i, px in enumerate(pixels):
            if idle[i] and i > 0:
                tvalid.value = 0
                valid_on = False
                await RisingEdge(dut.clk)
            tdata.value = px
            if not valid_on:
                tvalid.value = 1
                valid_on = True
            x = i % w
            if i <= 1:
                tuser.value = int(i == 0)
            if x == w - 1 or x == 0:
                tlast.value = int(x == w - 1)
            if i == 0 and with_first is not None:
                assert not self.feat_busy
                dut.s_axis_feat_tdata.value = with_first
                dut.s_axis_feat_tlast.value = 1
                dut.s_axis_feat_tvalid.value = 1
            await RisingEdge(dut.clk)
            if i == 0 and with_first is not None:
                dut.s_axis_feat_tvalid.value = 0
                dut.s_axis_feat_tlast.value = 0
            while tready.value != 1:
                await RisingEdge(dut.clk)
        tvalid.value = 0
        tuser.value = 0
        tlast.value = 0

    async def idle(self, clocks: int) -> None:
        for _ in range(clocks):
            await RisingEdge(self.dut.clk)

    async def feature_beat(self, word: int, last: int = 0) -> None:
        dut = self.dut
        dut.s_axis_feat_tdata.value = word
        dut.s_axis_feat_tlast.value = last
        dut.s_axis_feat_tvalid.value = 1
        await RisingEdge(dut.clk)
        dut.s_axis_feat_tvalid.value = 0
        dut.s_axis_feat_tlast.value = 0

    async def features(self, words: list[int], span: int, eof: int | None = None) -> None:
        """Send `words` spread over about `span` clocks (random gaps), then the end-of-frame word."""
        self.feat_busy = True
        mean_gap = max(0, span // (len(words) + 1) - 1)
        gaps = self.rng.integers(0, 2 * mean_gap + 1, len(words) + 1).tolist()
        for word, gap in zip([*words, None], gaps, strict=True):
            await self.idle(gap)
            if word is not None:
                await self.feature_beat(word)
        if eof is not None:
            await self.feature_beat(eof, 1)
        self.feat_busy = False

    def frame_clocks(self) -> int:
        return int(self.width * self.height * (1 + self.video_idle) * (1 + self.backpressure))

    async def frame_with_features(self, rgb: np.ndarray, words: list[int] | None, number: int) -> None:
        """One video frame with a feature frame spread over it (its end-of-frame beat may come after
        the last pixel); returns after both, plus a short blanking."""
        task = None
        if words is not None:
            task = cocotb.start_soon(self.features(words, self.frame_clocks(), eof_word(number)))
        await self.video_frame(rgb)
        if task is not None:
            await task
        await self.idle(self.blank)

    # ---- checks -----------------------------------------------------------------------------------
    def feature_frames(self) -> list[Features]:
        frames, current = [], []
        for w in self.feat_words:
            if w >> FEAT_BITS:
                frames.append(decode(current, self.step))
                current = []
            else:
                current.append(w)
        return frames

    def schedule(self) -> list[int | None]:
        return marker_schedule(kind for _, _, kind in sorted(self.events))

    async def check(self, expect_shown: list[int | None]) -> None:
        self.backpressure = 0.0  # the monitor raises tready for good
        n_pix = self.width * self.height
        for _ in range(100):
            if len(self.out_beats) >= len(self.in_beats):
                break
            await self.idle(10)
        await self.idle(10)
        assert len(self.in_beats) == n_pix * len(self.frames), "input beats and frames sent differ"
        assert len(self.out_beats) == len(self.in_beats), f"{len(self.out_beats)} beats out, {len(self.in_beats)} in"
        shown = self.schedule()
        assert shown == expect_shown, f"schedule of the accepted events {shown}, scenario meant {expect_shown}"
        feats = self.feature_frames()
        marked_total = 0
        for n, rgb in enumerate(self.frames):
            beats_in = self.in_beats[n * n_pix : (n + 1) * n_pix]
            beats_out = self.out_beats[n * n_pix : (n + 1) * n_pix]
            assert [b[1] for b in beats_in] == pack_rgb(rgb), f"frame {n}: input beats differ from the frame sent"
            exp = rgb if shown[n] is None else render_marker_overlay(rgb, feats[shown[n]], self.scales, self.block_log2)
            marked_total += int(np.count_nonzero(np.any(exp != rgb, axis=2)))
            exp_words = pack_rgb(exp)
            for i, (bi, bo) in enumerate(zip(beats_in, beats_out, strict=True)):
                if bo[1:] != (exp_words[i], bi[2], bi[3]):
                    y, x = divmod(i, self.width)
                    raise AssertionError(
                        f"video frame {n} (shows feature frame {shown[n]}) pixel x={x} y={y}: got "
                        f"{bo[1]:06x} user {bo[2]} last {bo[3]}, expected {exp_words[i]:06x} user {bi[2]} "
                        f"last {bi[3]} (input {bi[1]:06x})"
                    )
                if self.backpressure_free and bo[0] - bi[0] != OVERLAY_VIDEO_LAT:
                    raise AssertionError(
                        f"frame {n} pixel {i}: latency {bo[0] - bi[0]} clocks, not {OVERLAY_VIDEO_LAT}"
                    )
        if any(s is not None and len(feats[s]) > 0 for s in shown):
            assert marked_total > 0, "no marker pixel expected anywhere: the test would prove nothing"
        self.dut._log.info("frames %d, shown %s, feature frames %s, marked pixels %d", len(self.frames), shown,
                           [len(f) for f in feats], marked_total)  # fmt: skip

    @property
    def backpressure_free(self) -> bool:
        return float(env_str("ORB_BACKPRESSURE", "0")) == 0


# ------------------------------------------------------------------------------------------------
# scenarios


async def scenario_photos(b: Bench) -> None:
    """Video frame k+1 shows the features of photograph k, fed in interleaved scale order during k."""
    names = env_str("ORB_PHOTOS", "astronaut,coffee,chelsea").split(",")
    feat_scales = env_int("ORB_FEAT_SCALES", b.scales)
    frames = [rgb_photo(n, b.width, b.height) for n in names]
    for k, rgb in enumerate(frames):
        f = photo_features(rgb, feat_scales, b.step)
        assert len(f) > 0, f"{names[k]}: no features"
        words = interleaved_words(f, b.rng) if k < len(frames) - 1 else None
        await b.frame_with_features(rgb, words, k)
    await b.check([None, *range(len(frames) - 1)])


def border_features(width: int, height: int, block_log2: int, scales: int = 4,
                    step: tuple[int, int] = (2, 1)) -> Features:  # fmt: skip
    """Features at the four borders and corners of every scale (0..scales-1, whatever SCALES_g),
    plus ones in the last block column/row and just beyond the block grid (to be ignored)."""
    sc, xs, ys = [], [], []
    for s in range(scales):
        ws, hs = level_size(width, height, s, step)
        for x in (0, 1, 2, ws // 2, ws - 3, ws - 2, ws - 1):
            for y in (0, 1, 2, hs // 2, hs - 3, hs - 2, hs - 1):
                if x in (0, 1, 2, ws - 3, ws - 2, ws - 1) or y in (0, 1, 2, hs - 3, hs - 2, hs - 1):
                    sc.append(s)
                    xs.append(x)
                    ys.append(y)
        extra = [(ws, 0), (0, hs), (4095, 4095), (4095, 0), (0, 4095)]
        if step == (2, 1) and s <= block_log2:
            gx, gy = -(-width >> block_log2) << (block_log2 - s), -(-height >> block_log2) << (block_log2 - s)
            extra += [(gx - 1, 5), (gx, 5), (7, gy - 1), (7, gy), (gx - 1, gy - 1), (gx, gy)]
        elif step != (2, 1):  # around the first level coordinate past the block grid
            gx = level_coord(-(-width >> block_log2) << block_log2, s, step)
            gy = level_coord(-(-height >> block_log2) << block_log2, s, step)
            extra += [(gx + d, 5) for d in (-1, 0, 1)] + [(7, gy + d) for d in (-1, 0, 1)] + [(gx, gy)]
        for x, y in extra:
            sc.append(s)
            xs.append(x)
            ys.append(y)
    return make_features(sc, xs, ys)


async def scenario_borders(b: Bench) -> None:
    frames = [rgb_photo(n, b.width, b.height) for n in ("coffee", "astronaut")]
    f = border_features(b.width, b.height, b.block_log2, max(4, b.scales), b.step)
    await b.frame_with_features(frames[0], shuffled_words(f, b.rng), 0)
    await b.frame_with_features(frames[1], None, 1)
    await b.check([None, 0])


def dense_features(width: int, height: int, block_log2: int, rng: np.random.Generator, scales: int = 4,
                   step: tuple[int, int] = (2, 1)) -> Features:  # fmt: skip
    """At every scale 0..scales-1 a feature in every block it can reach, some twice."""
    sc, xs, ys = [], [], []
    half = 1 << (block_log2 - 1)
    for s in range(scales):
        for by in range(-(-height >> block_log2)):
            for bx in range(-(-width >> block_log2)):
                x = level_coord(min((bx << block_log2) + half, width - 1), s, step)
                y = level_coord(min((by << block_log2) + half, height - 1), s, step)
                for _ in range(1 + int(rng.random() < 0.2)):
                    sc.append(s)
                    xs.append(x)
                    ys.append(y)
    return make_features(sc, xs, ys)


async def scenario_sequence(b: Bench) -> None:
    """Dense, empty, a photograph's features, then no feature frame at all: clearing proven (marks of
    frame k never reach frame k + 2, and a bank shown once is empty the next time)."""
    names = ("chelsea", "rocket", "astronaut", "coffee", "camera")
    frames = [rgb_photo(n, b.width, b.height) for n in names]
    dense = dense_features(b.width, b.height, b.block_log2, b.rng, max(4, b.scales), b.step)
    dense.step = b.step
    marks = marker_bitmap(dense, b.width, b.height, b.scales, b.block_log2)
    if b.block_log2 == 3 and b.width % 8 == 0 and b.height % 8 == 0 and b.step == (2, 1):
        assert marks.all(), "the dense frame must mark every block at every scale"
    await b.frame_with_features(frames[0], shuffled_words(dense, b.rng), 0)
    await b.frame_with_features(frames[1], [], 1)  # empty feature frame
    await b.frame_with_features(frames[2], interleaved_words(photo_features(frames[2], b.scales, b.step), b.rng), 2)
    await b.frame_with_features(frames[3], None, 3)  # no feature frame completes before frame 4
    await b.frame_with_features(frames[4], None, 3)
    await b.check([None, 0, 1, 2, None])


async def scenario_timing(b: Bench) -> None:
    """End-of-frame beats against starts of frame, clock-exact (spec 13.3): a feature beat counts
    OVERLAY_FEAT_LAT edges after the port, so the beats meant for an edge go that much earlier."""
    frames = [rgb_photo(RGB_PHOTOS[i % len(RGB_PHOTOS)], b.width, b.height) for i in range(7)]
    words = [interleaved_words(photo_features(rgb, b.scales, b.step), b.rng) for rgb in frames]
    span = b.frame_clocks()
    # V0 with F0, whose end-of-frame beat comes on the same edge as V1's start: V1 shows none.
    task = cocotb.start_soon(b.features(words[0], span))
    await b.video_frame(frames[0])
    await task
    await b.idle(b.blank)
    # V1 with F1: it begins while F0 waits, so it is discarded whole.
    v1 = cocotb.start_soon(b.video_frame(frames[1], with_first=eof_word(0)))
    await RisingEdge(b.dut.clk)  # the edge taking V1's first pixel and F0's end-of-frame beat
    await b.features(words[1], span, eof_word(1))
    await v1
    await b.idle(b.blank)
    # V2 shows F0; F2's end-of-frame beat one edge before V3's start: V3 shows F2.
    task = cocotb.start_soon(b.features(words[2], span))
    await b.video_frame(frames[2])
    await task
    await b.idle(b.blank)
    await b.feature_beat(eof_word(2), 1)
    await b.idle(OVERLAY_FEAT_LAT)
    # V3 with F3, then F4's first beat counting on the edge of V4's start (after the swap: kept).
    task = cocotb.start_soon(b.features(words[3], span, eof_word(3)))
    await b.video_frame(frames[3])
    await task
    await b.idle(b.blank)
    b.feat_busy = True
    await b.feature_beat(words[4][0])
    await b.idle(OVERLAY_FEAT_LAT - 1)
    v4 = cocotb.start_soon(b.video_frame(frames[4]))
    await b.features(words[4][1:], span, eof_word(4))
    await v4
    await b.idle(b.blank)
    # F5 begins before V5's start (F4 waiting): discarded whole although most of it comes later.
    await b.feature_beat(words[5][0])
    await b.idle(OVERLAY_FEAT_LAT)
    task = cocotb.start_soon(b.features(words[5][1:], span, eof_word(5)))
    await b.video_frame(frames[5])
    await task
    await b.idle(b.blank)
    await b.frame_with_features(frames[6], None, 6)
    await b.check([None, None, 0, 2, 3, 4, None])


SCENARIOS = {"photos": scenario_photos, "borders": scenario_borders, "sequence": scenario_sequence,
             "timing": scenario_timing}  # fmt: skip


@cocotb.test()
async def overlay(dut) -> None:
    bench = Bench(dut)
    await bench.start()
    await SCENARIOS[env_str("ORB_SCENARIO")](bench)


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_overlay(width: int, height: int, scales: int, block_log2: int, scenario: str, **env: str) -> None:
    generics = {"WIDTH_g": width, "HEIGHT_g": height, "SCALES_g": scales, "BLOCK_LOG2_g": block_log2}
    if "step" in env:
        num, den = parse_step(env["step"])
        generics |= {"STEP_NUM_g": num, "STEP_DEN_g": den}
    run(
        "orb_overlay",
        "test_orb_overlay",
        generics,
        env={"ORB_SCENARIO": scenario, **{f"ORB_{k.upper()}": v for k, v in env.items()}},
    )


@pytest.mark.parametrize(
    ("width", "height", "scales", "block_log2", "env"),
    [
        (64, 48, 1, 3, {"photos": "camera,astronaut"}),
        (64, 48, 4, 3, {"photos": "astronaut,coffee,chelsea", "backpressure": "0.3", "video_idle": "0.2"}),
        (160, 120, 2, 3, {"photos": "coffee,rocket", "seed": "2"}),
        (160, 120, 3, 4, {"photos": "chelsea,astronaut", "backpressure": "0.2", "seed": "3"}),  # 16x16 blocks
        # 4x4 blocks; features of scales 2 and 3 arrive and are ignored
        (100, 52, 2, 2, {"photos": "rocket,camera", "feat_scales": "4", "video_idle": "0.3"}),
        # finer pyramids (issue 14): 6 and 8 levels of 5:4 in 16x16 blocks, 3:2 with its scales past SCALES_g
        (160, 120, 6, 4, {"photos": "astronaut,coffee", "step": "5:4", "backpressure": "0.2"}),
        (128, 96, 8, 4, {"photos": "chelsea,rocket", "step": "5:4", "video_idle": "0.2", "seed": "6"}),
        (100, 52, 3, 3, {"photos": "coffee,camera", "step": "3:2", "feat_scales": "5"}),
    ],
)
def test_overlay_photos(width: int, height: int, scales: int, block_log2: int, env: dict[str, str]) -> None:
    run_overlay(width, height, scales, block_log2, "photos", **env)


@pytest.mark.parametrize(
    ("width", "height", "scales", "block_log2", "scenario", "env"),
    [
        (64, 48, 4, 3, "borders", {}),
        (100, 52, 3, 3, "borders", {"backpressure": "0.25"}),  # blocks cut by the right and bottom edges
        (101, 53, 2, 2, "borders", {}),
        (64, 48, 4, 3, "sequence", {}),
        (100, 52, 4, 3, "sequence", {"backpressure": "0.3", "video_idle": "0.3", "seed": "5"}),
        (64, 48, 2, 3, "timing", {}),
        (64, 48, 4, 5, "timing", {"seed": "4"}),  # 32x32 blocks
        (100, 52, 6, 4, "borders", {"step": "5:4"}),
        (96, 64, 8, 4, "sequence", {"step": "9:8", "backpressure": "0.2"}),
    ],
)
def test_overlay_directed(width: int, height: int, scales: int, block_log2: int, scenario: str,
                          env: dict[str, str]) -> None:  # fmt: skip
    run_overlay(width, height, scales, block_log2, scenario, **env)


@pytest.mark.slow
def test_overlay_vga() -> None:
    run_overlay(640, 480, 4, 3, "photos", photos="astronaut,coffee", backpressure="0.1")


# ------------------------------------------------------------------------------------------------
# the model's rules on their own (no simulator)


def test_model_rings_and_order() -> None:
    rgb = np.zeros((48, 64, 3), dtype=np.uint8)
    f = make_features([0, 1, 3, 3, 0], [9, 4, 0, 1, 63], [9, 0, 0, 0, 47])
    out = render_marker_overlay(rgb, f)
    green = np.all(out == (0, 255, 0), axis=2)
    # scale 0 at (9, 9): outline of block (1, 1), pixels 8..15
    assert green[8, 8:16].all() and green[15, 8:16].all() and green[8:16, 8].all() and green[8:16, 15].all()
    assert not green[9:15, 9:15].any() and green.sum() == 56  # and block (7, 5) of (63, 47)
    cyan = np.all(out == (0, 220, 255), axis=2)  # scale 1 at x=4: anchor 9, block (1, 0), ring 1
    assert cyan[1, 9:15].all() and cyan[1:7, 9].all() and cyan.sum() == 20
    yellow = np.all(out == (255, 220, 0), axis=2)  # scale 3 at x=0 and x=1: anchors 4 and 12
    assert yellow[3, 3:5].all() and yellow[3, 11:13].all() and yellow.sum() == 8
    for seed in range(3):
        perm = np.random.default_rng(seed).permutation(len(f))
        assert np.array_equal(render_marker_overlay(rgb, f.take(perm)), out)
    assert np.array_equal(render_marker_overlay(rgb, f, scales=2), np.where(yellow[..., None], 0, out))


def test_model_schedule() -> None:
    s, f, e = "sof", "feature", "eof"
    assert marker_schedule([s, f, e, s, s]) == [None, 0, None]
    assert marker_schedule([s, f, s, e, f, s, e, s]) == [None, None, 0, None]  # frame 1 began while 0 waited
    assert marker_schedule([s, e, s, e, e, s]) == [None, 0, 1]  # empty frames; frame 2 dropped
    assert marker_schedule([f, e, s, f, e, s]) == [0, 1]
