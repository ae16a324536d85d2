# SPDX-License-Identifier: MIT
"""orb_feat_merge: directed and random tests of the multi-scale feature merger.

Every feature pushed carries a unique tag (x = per-scale sequence number, y = frame number,
random score) and a random sector and descriptor, so the output shows exactly which features
arrived, in which order per scale and in which frame (the beats between two end-of-frame beats),
and that each one's payload arrived intact with it (DESC_g = true) or was left out, its output
bits 0 (DESC_g = false: the payload inputs are driven with random values all the same).
Expected drops are never modelled from the RTL: they come from stimuli whose count is obvious.
While the output is stalled (tready = 0) with a feature already in the output register, no FIFO
can drain, so a scale that receives N features keeps exactly its first FIFO_DEPTH and drops
N - FIFO_DEPTH; a frame that pushes at most FIFO_DEPTH features per scale into empty FIFOs drops
none, whatever tready does.

Checked everywhere: per-frame content (payload included) and per-scale order, the end-of-frame
beat's frame number and drop count, the `dropped` total, AXI4-Stream rules (tdata/tlast held
while stalled), the feature/end-of-frame flag bits and reserved (0) bits, and that an
end-of-frame beat comes only after every scale's frame_done.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cocotb
import numpy as np
import pytest
from cocotb.triggers import ClockCycles, RisingEdge

from golden_model.featcodec import decode_eof, decode_feature, eof_error, feature_error, is_eof
from golden_model.featword import EOF_BEAT, FEATURE_BEAT
from orbtb.runner import run
from orbtb.unit import SIM_ENV, env_int, env_str, reset

# per-scale input widths: those of the stream fields (tb/common/test_orb_feat_pkg.py checks that they
# equal orb_util_pkg's COORD_BITS_c and SCORE_BITS_c)
COORD, SCORE = FEATURE_BEAT.field("x").width, FEATURE_BEAT.field("score").width
SECTOR_BITS, DESC_BITS = FEATURE_BEAT.field("sector").width, FEATURE_BEAT.field("descriptor").width
CODE, SLOT = FEATURE_BEAT.field("response").width, FEATURE_BEAT.field("sel_slot").width
DROPS_MAX = (1 << EOF_BEAT.field("drops").width) - 1  # the end-of-frame beat's count saturates here
# (x, y, score, sector, descriptor, low, code, sel_slot, sel_replace) as pushed into one scale
Feat = tuple[int, int, int, int, int, int, int, int, int]


@dataclass
class FrameOut:
    beats: list[tuple[int, Feat]] = field(default_factory=list)  # (scale, feature)
    number: int = -1
    drops: int = -1
    eof_edge: int = -1


class MergeBench:
    """Drives orb_feat_merge one clock at a time and records every accepted beat."""

    def __init__(self, dut) -> None:
        self.dut = dut
        self.scales = env_int("ORB_SCALES")
        self.depth = env_int("ORB_FIFO_DEPTH")
        self.desc = env_str("ORB_DESC").lower() == "true"
        self.rng = np.random.default_rng(self.scales * 1000 + self.depth + 7 * self.desc)
        self.edge = 0
        self.frames: list[FrameOut] = []
        self.current = FrameOut()
        # per end-of-frame beat: the edge at which each scale's oldest frame_done not yet matched
        # with a beat was sampled (a scale's frame ends are matched with beats in order)
        self.done_edges: list[list[int]] = []
        self._pending_done: list[list[int]] = [[] for _ in range(self.scales)]
        self.seq = [0] * self.scales
        # expectation, filled by the scenarios
        self.expected: list[dict[int, list[Feat]]] = [{s: [] for s in range(self.scales)}]
        self.expected_drops: list[int] = [0]
        self._ready = 0
        self._stalled: tuple[int, int] | None = None  # (tdata, tlast) offered but not taken
        self._driven = (0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0)

    async def start(self) -> None:
        await reset(
            self.dut,
            dict.fromkeys(
                (
                    "in_valid",
                    "in_x",
                    "in_y",
                    "in_score",
                    "in_sector",
                    "in_desc",
                    "in_done",
                    "in_low",
                    "in_code",
                    "in_slot",
                    "in_replace",
                ),
                0,
            )
            | {"m_axis_feat_tready": 0},
        )

    def feature(self, scale: int, frame: int) -> Feat:
        """A new feature of `scale` in `frame`, with a random score, sector and descriptor."""
        x = self.seq[scale] % (1 << COORD)
        self.seq[scale] += 1
        score = int(self.rng.integers(0, 1 << SCORE))
        sector = int(self.rng.integers(0, 1 << SECTOR_BITS))
        desc = int.from_bytes(self.rng.bytes(DESC_BITS // 8), "little")
        low, code = int(self.rng.integers(0, 2)), int(self.rng.integers(0, 1 << CODE))
        slot, repl = int(self.rng.integers(0, 1 << SLOT)), int(self.rng.integers(0, 2))
        return (x, frame % (1 << COORD), score, sector, desc, low, code, slot, repl)

    async def cycle(self, feats: dict[int, Feat] | None = None, done: tuple[int, ...] = (), ready: int = 1) -> None:
        """One clock: push `feats` (scale -> feature), pulse in_done for `done`, drive tready."""
        dut = self.dut
        valid = xs = ys = scs = sec = dsc = dn = lows = codes = slots = repls = 0
        for s, (x, y, sc, sector, desc, low, code, slot, repl) in (feats or {}).items():
            valid |= 1 << s
            xs |= x << (s * COORD)
            ys |= y << (s * COORD)
            scs |= sc << (s * SCORE)
            sec |= sector << (s * SECTOR_BITS)
            dsc |= desc << (s * DESC_BITS)
            lows |= low << s
            codes |= code << (s * CODE)
            slots |= slot << (s * SLOT)
            repls |= repl << s
        for s in done:
            dn |= 1 << s
        driven = (valid, xs, ys, scs, sec, dsc, dn, lows, codes, slots, repls)
        if driven != self._driven:
            dut.in_valid.value = valid
            if valid:
                dut.in_x.value = xs
                dut.in_y.value = ys
                dut.in_score.value = scs
                dut.in_sector.value = sec
                dut.in_desc.value = dsc
                dut.in_low.value = lows
                dut.in_code.value = codes
                dut.in_slot.value = slots
                dut.in_replace.value = repls
            dut.in_done.value = dn
            self._driven = driven
        if ready != self._ready:
            dut.m_axis_feat_tready.value = ready
            self._ready = ready
        await RisingEdge(dut.clk)
        self.edge += 1
        if done:
            for s in done:
                self._pending_done[s].append(self.edge)
        self._sample(ready)

    def _sample(self, ready: int) -> None:
        dut = self.dut
        if dut.m_axis_feat_tvalid.value != 1:
            assert self._stalled is None, f"edge {self.edge}: tvalid dropped while a beat was stalled"
            return
        data, last = int(dut.m_axis_feat_tdata.value), int(dut.m_axis_feat_tlast.value)
        if self._stalled is not None:
            assert (data, last) == self._stalled, (
                f"edge {self.edge}: beat changed while stalled: {self._stalled[0]:#x} -> {data:#x}"
            )
        if not ready:
            self._stalled = (data, last)
            return
        self._stalled = None
        eof = int(is_eof(data))
        assert eof == last, f"edge {self.edge}: tlast {last} with end-of-frame flag {eof} ({data:#x})"
        if last:
            assert eof_error(data) is None, f"edge {self.edge}: {eof_error(data)}"
            e = decode_eof(data)
            self.current.number = e.frame
            self.current.drops = e.drops
            self.current.eof_edge = self.edge
            self.frames.append(self.current)
            self.done_edges.append([q.pop(0) for q in self._pending_done if q])
            self.current = FrameOut()
        else:
            assert feature_error(data) is None, f"edge {self.edge}: {feature_error(data)}"
            f = decode_feature(data)
            self.current.beats.append(
                (f.scale, (f.x, f.y, f.score, f.sector, f.descriptor, f.low, f.response, f.sel_slot, f.sel_replace))
            )

    # ---- scenario helpers ----------------------------------------------------------------------
    async def plug_output(self) -> None:
        """Stall the output with one frame-0 feature of scale 0 in the output register, so no FIFO
        can drain until tready rises again."""
        plug = self.feature(0, 0)
        self.expect(0, plug, 0)
        await self.cycle({0: plug}, ready=0)
        for _ in range(3):
            await self.cycle(ready=0)

    def expect(self, scale: int, feat: Feat, frame: int) -> None:
        """`feat` of `scale` must arrive in `frame` (without its payload when DESC_g is false)."""
        while len(self.expected) <= frame:
            self.expected.append({s: [] for s in range(self.scales)})
            self.expected_drops.append(0)
        self.expected[frame][scale].append(feat if self.desc else (*feat[:3], 0, 0, *feat[5:]))

    def expect_drops(self, frame: int, n: int) -> None:
        self.expect_frame(frame)
        self.expected_drops[frame] += n

    def expect_frame(self, frame: int) -> None:
        while len(self.expected) <= frame:
            self.expected.append({s: [] for s in range(self.scales)})
            self.expected_drops.append(0)

    async def drain(self, frames: int, ready_prob: float = 1.0, limit: int = 20000) -> None:
        """Clock (no input) until `frames` end-of-frame beats have been accepted in total."""
        for _ in range(limit):
            if len(self.frames) >= frames:
                return
            await self.cycle(ready=int(self.rng.random() < ready_prob))
        raise AssertionError(f"only {len(self.frames)} of {frames} end-of-frame beats after {limit} clocks")

    def check(self, total_dropped: int | None = None) -> None:
        """Compare everything with the expectation; `dropped` must equal total_dropped (default:
        the sum of the per-frame counts, which holds while none of them saturates)."""
        assert len(self.frames) == len(self.expected), (
            f"{len(self.frames)} end-of-frame beats, expected {len(self.expected)}"
        )
        for f, (out, exp) in enumerate(zip(self.frames, self.expected, strict=True)):
            assert out.number == f, f"frame {f}: end-of-frame beat numbered {out.number}"
            for s in range(self.scales):
                got = [feat for scale, feat in out.beats if scale == s]
                for i, (g, e) in enumerate(zip(got, exp[s], strict=False)):
                    assert g == e, (
                        f"frame {f}, scale {s}, feature {i}: got (x={g[0]}, y={g[1]}) score {g[2]} sector {g[3]} "
                        f"descriptor {g[4]:#066x}, expected (x={e[0]}, y={e[1]}) score {e[2]} sector {e[3]} "
                        f"descriptor {e[4]:#066x}"
                    )
                if len(got) != len(exp[s]):
                    more = got[len(exp[s])] if len(got) > len(exp[s]) else exp[s][len(got)]
                    raise AssertionError(
                        f"frame {f}, scale {s}: {len(got)} features, expected {len(exp[s])} "
                        f"(first unmatched: x={more[0]}, y={more[1]})"
                    )
            assert not [b for b in out.beats if b[0] >= self.scales], f"frame {f}: beat of a scale that does not exist"
            assert out.drops == self.expected_drops[f], (
                f"frame {f}: {out.drops} drops reported, expected {self.expected_drops[f]}"
            )
            dones = self.done_edges[f]
            assert len(dones) == self.scales and out.eof_edge > max(dones), (
                f"frame {f}: end-of-frame beat at edge {out.eof_edge} before every scale's frame_done ({dones})"
            )
        total = int(self.dut.dropped.value)
        want = sum(self.expected_drops) if total_dropped is None else total_dropped
        assert total == want, f"dropped = {total}, expected {want}"
        self.dut._log.info(
            "%d frames, %d features, %d drops checked",
            len(self.frames),
            sum(len(fr.beats) for fr in self.frames),
            sum(self.expected_drops),
        )


# ------------------------------------------------------------------------------------------------
# cocotb tests


@cocotb.test()
async def simultaneous(dut) -> None:
    """Every scale pushes a feature in the same clocks (up to FIFO_DEPTH each: no drops), with a
    random tready; the last feature of scale 0 arrives in the same clock as its frame_done."""
    b = MergeBench(dut)
    await b.start()
    for f in range(4):
        counts = [max(1, b.depth - ((s + f) % 3)) for s in range(b.scales)]
        b.expect_frame(f)
        for c in range(max(counts)):
            feats = {s: b.feature(s, f) for s in range(b.scales) if c < counts[s]}
            for s, feat in feats.items():
                b.expect(s, feat, f)
            done = (0,) if c == counts[0] - 1 else ()
            await b.cycle(feats, done=done, ready=int(b.rng.random() < 0.6))
        for s in range(1, b.scales):
            await b.cycle(done=(s,), ready=int(b.rng.random() < 0.6))
        await b.drain(f + 1, ready_prob=0.5)
    await ClockCycles(dut.clk, 2)
    b.check()


@cocotb.test()
async def eof_waits_for_every_scale(dut) -> None:
    """Scales finish at very different times; scale 0 already pushes features of the next frame
    while the last scale is still busy: they must follow the end-of-frame beat."""
    b = MergeBench(dut)
    await b.start()
    n = min(3, b.depth - 1)
    for f in range(3):
        b.expect_frame(f)
        for s in range(b.scales):
            for _ in range(n):
                feat = b.feature(s, f)
                b.expect(s, feat, f)
                await b.cycle({s: feat})
            await b.cycle(done=(s,))
            for _ in range(10 * s):
                await b.cycle()
            if s == 0 and b.scales > 1:  # next frame's features of scale 0, before the others finish
                for _ in range(n):
                    feat = b.feature(0, f + 1)
                    b.expect(0, feat, f + 1)
                    await b.cycle({0: feat})
        await b.drain(f + 1)
    b.expect_frame(3)
    for s in range(b.scales):  # close the last frame
        await b.cycle(done=(s,))
    await b.drain(4)
    b.check()


@cocotb.test()
async def overflow_drops(dut) -> None:
    """Stalled output with a plug in the output register: each scale keeps exactly its first
    FIFO_DEPTH features; frame markers arriving while the FIFOs are full are kept."""
    b = MergeBench(dut)
    await b.start()
    d = b.depth
    plan = [  # (scale holding the plug, features per scale)
        (0, [d + 3, d, d + 1, 2 * d][: b.scales]),
        (b.scales - 1, [2 * d + 1, d - 1, d + 5, 1][: b.scales]),
    ]
    frame = 0
    for plug_scale, counts in plan:
        b.expect_frame(frame)
        plug = b.feature(plug_scale, frame)
        b.expect(plug_scale, plug, frame)
        await b.cycle({plug_scale: plug}, ready=0)
        for _ in range(3):  # the plug moves into the output register; nothing can leave after it
            await b.cycle(ready=0)
        for c in range(max(counts)):
            feats = {s: b.feature(s, frame) for s in range(b.scales) if c < counts[s]}
            for s, feat in feats.items():
                if c < d:
                    b.expect(s, feat, frame)
            await b.cycle(feats, ready=0)
        b.expect_drops(frame, sum(max(0, n - d) for n in counts))
        await b.cycle(done=tuple(range(b.scales)), ready=0)  # markers meet full FIFOs
        for _ in range(5):
            await b.cycle(ready=0)
        await b.drain(frame + 1, ready_prob=0.5)
        frame += 1
        # a normal frame in between: the per-frame drop count starts again from 0
        b.expect_frame(frame)
        for c in range(d):
            feats = {s: b.feature(s, frame) for s in range(b.scales) if (c + s) % 2 == 0}
            for s, feat in feats.items():
                b.expect(s, feat, frame)
            await b.cycle(feats, ready=int(b.rng.random() < 0.3))
        await b.cycle(done=tuple(range(b.scales)))
        await b.drain(frame + 1, ready_prob=0.3)
        frame += 1
    b.check()


@cocotb.test()
async def random_traffic(dut) -> None:
    """Random features, frame ends and tready. Run only with FIFOs deeper than the whole test's
    traffic per scale, so nothing can be dropped."""
    b = MergeBench(dut)
    await b.start()
    frames = 6
    for f in range(frames):
        b.expect_frame(f)
        active = list(range(b.scales))
        length = int(b.rng.integers(20, 80))
        for c in range(length):
            feats = {}
            for s in active:
                if b.rng.random() < 0.35:
                    feats[s] = b.feature(s, f)
                    b.expect(s, feats[s], f)
            # each scale ends its frame at a random clock after the frame's middle
            done = tuple(s for s in active if c >= length // 2 and (b.rng.random() < 0.1 or c == length - 1))
            await b.cycle(feats, done=done, ready=int(b.rng.random() < 0.5))
            active = [s for s in active if s not in done]
        await b.drain(f + 1, ready_prob=0.5)
    per_scale_total = max(b.seq)
    assert per_scale_total <= b.depth, "the stimulus could overflow a FIFO: use a deeper FIFO_DEPTH_g"
    b.check()


@cocotb.test()
async def marker_not_bypassed(dut) -> None:
    """A frame marker waiting for room in a full FIFO must stay ahead of the next frame's
    features: a feature pushed in the clock that frees the room belongs to the next frame."""
    b = MergeBench(dut)
    await b.start()
    d = b.depth
    b.expect_frame(0)
    await b.plug_output()
    for _ in range(d):
        feat = b.feature(0, 0)
        b.expect(0, feat, 0)
        await b.cycle({0: feat}, ready=0)
    await b.cycle(done=tuple(range(b.scales)), ready=0)  # the marker of scale 0 must wait
    await b.cycle(ready=0)
    nxt = b.feature(0, 1)  # next frame's first feature, in the clock the output takes the plug
    b.expect(0, nxt, 1)
    await b.cycle({0: nxt}, ready=1)
    await b.drain(1)
    await b.cycle(done=tuple(range(b.scales)))
    await b.drain(2)
    b.check()


@cocotb.test()
async def drops_counted_in_their_frame(dut) -> None:
    """Features of the next frame that are lost while the previous frame's markers still wait in
    full FIFOs are that next frame's losses, not the previous frame's."""
    b = MergeBench(dut)
    await b.start()
    d = b.depth
    b.expect_frame(1)
    await b.plug_output()
    for c in range(d + 2):  # every FIFO full; scale 0 loses two features of frame 0
        feats = {s: b.feature(s, 0) for s in range(b.scales) if c < d or s == 0}
        for s, feat in feats.items():
            if c < d:
                b.expect(s, feat, 0)
        await b.cycle(feats, ready=0)
    b.expect_drops(0, 2)
    await b.cycle(done=tuple(range(b.scales)), ready=0)
    await b.cycle(ready=0)
    for _ in range(3):  # frame 1 starts on scale 0 while the output is still stalled: lost
        await b.cycle({0: b.feature(0, 1)}, ready=0)
    b.expect_drops(1, 3)
    await b.cycle(ready=0)
    await b.drain(1)
    await b.cycle(done=tuple(range(b.scales)))
    await b.drain(2)
    b.check()


@cocotb.test()
async def frames_waiting(dut) -> None:
    """The output stalls for more than a whole frame: two frame ends per scale wait for their
    beats with features of both frames in the FIFOs (the second frame's entries counted apart), and
    a third frame end merges into the newest waiting one, so its features and the newest frame's
    share one end-of-frame beat. Nothing is lost (at most FIFO_DEPTH features per scale)."""
    b = MergeBench(dut)
    await b.start()
    d = b.depth
    sizes = [1, 1, d - 2]  # features per scale of input frames 0, 1, 2 while the output is stalled
    b.expect_frame(1)
    await b.plug_output()
    for f, n in enumerate(sizes):
        for _ in range(n):
            feats = {s: b.feature(s, f) for s in range(b.scales)}
            for s, feat in feats.items():
                b.expect(s, feat, min(f, 1))  # input frame 2 merges into output frame 1
            await b.cycle(feats, ready=0)
        await b.cycle(done=tuple(range(b.scales)), ready=0)
    await b.cycle(ready=0)
    await b.drain(2, ready_prob=0.5)
    # the next input frame is output frame 2, and the merge counts from there as before
    b.expect_frame(2)
    for _ in range(2):
        feats = {s: b.feature(s, 3) for s in range(b.scales)}
        for s, feat in feats.items():
            b.expect(s, feat, 2)
        await b.cycle(feats)
    await b.cycle(done=tuple(range(b.scales)))
    await b.drain(3)
    b.check()


@cocotb.test()
async def losses_around_eof(dut) -> None:
    """Losses of the next frame in the clocks just before and in the clock of the previous frame's
    end-of-frame beat: the loss counts are pipelined over three clocks, and a beat going out in
    between must move them to the next frame's count, not lose them or give them to its own."""
    b = MergeBench(dut)
    await b.start()
    d = b.depth
    s = b.scales - 1  # the scale whose FIFO overflows
    b.expect_frame(1)
    await b.plug_output()
    await b.cycle(done=tuple(range(b.scales)), ready=0)  # frame 0 ends: only the plug, stalled
    lost = 0
    for c in range(d + 2):  # frame 1 on one scale: its FIFO fills, then two are lost, output stalled
        feat = b.feature(s, 1)
        if c < d:
            b.expect(s, feat, 1)
        else:
            lost += 1
        await b.cycle({s: feat}, ready=0)
    # tready rises: the plug leaves and frame 0's end-of-frame beat goes out in this clock, while
    # the FIFO, holding only frame 1, is still full: this feature is lost too
    await b.cycle({s: b.feature(s, 1)}, ready=1)
    lost += 1
    beat_edge = b.edge + 1  # the beat entered the output register at this edge, taken at the next
    for _ in range(3):  # from now on a feature leaves every clock: these are kept
        feat = b.feature(s, 1)
        b.expect(s, feat, 1)
        await b.cycle({s: feat})
    b.expect_drops(1, lost)
    await b.cycle(done=tuple(range(b.scales)))
    await b.drain(2)
    # the premise: the losses above fell in the two clocks before the beat and in its clock
    assert b.frames[0].eof_edge == beat_edge, (
        f"frame 0's end-of-frame beat taken at edge {b.frames[0].eof_edge}, expected {beat_edge}: "
        "the scenario no longer puts losses around it"
    )
    b.check()


@cocotb.test()
async def drop_count_saturates(dut) -> None:
    """More than 2^16 drops in one frame: the per-frame count saturates at 65535, the 32-bit
    total counts them all. Every scale overflows in every clock."""
    b = MergeBench(dut)
    await b.start()
    d = b.depth
    b.expect_frame(0)
    await b.plug_output()
    clocks = (DROPS_MAX + 1) // b.scales + 50
    feats = {s: b.feature(s, 0) for s in range(b.scales)}  # the same feature over and over
    for s, feat in feats.items():
        for _ in range(d):
            b.expect(s, feat, 0)
    await b.cycle(feats, ready=0)
    await ClockCycles(dut.clk, clocks - 1)  # no Python per clock: inputs held
    b.edge += clocks - 1
    await b.cycle(ready=0)
    total = clocks * b.scales - d * b.scales
    b.expected_drops[0] = min(total, DROPS_MAX)
    await b.cycle(done=tuple(range(b.scales)), ready=0)
    await b.drain(1)
    b.check(total_dropped=total)


# ------------------------------------------------------------------------------------------------
# pytest runners

DIRECTED = "simultaneous,eof_waits_for_every_scale,overflow_drops"
# orbtb.runner builds once per (pytest-xdist worker, module, generic set), so runners executing
# at the same time (pytest -n) never share a build. Every runner runs with DESC_g true (sector and
# descriptor carried through the FIFOs) and false (FIFOs of x, y and score only).
DESC = pytest.mark.parametrize("desc", [True, False], ids=["desc", "fast"])


def run_merge(scales: int, depth: int, desc: bool, tests: str) -> None:
    run(
        "orb_feat_merge",
        "test_orb_feat_merge",
        {"SCALES_g": scales, "FIFO_DEPTH_g": depth, "DESC_g": desc},
        env=SIM_ENV,
        testcase=tests,
    )


@DESC
@pytest.mark.parametrize(("scales", "depth"), [(4, 4), (3, 8), (1, 2), (2, 2)])
def test_merge_directed(scales: int, depth: int, desc: bool) -> None:
    run_merge(scales, depth, desc, DIRECTED)


@DESC
@pytest.mark.parametrize("scales", [1, 4])
def test_merge_random(scales: int, desc: bool) -> None:
    run_merge(scales, 512, desc, "random_traffic")


@DESC
def test_merge_drop_count_saturates_one_scale(desc: bool) -> None:
    run_merge(1, 4, desc, "drop_count_saturates")


@DESC
def test_merge_drop_count_saturates_four_scales(desc: bool) -> None:
    run_merge(4, 8, desc, "drop_count_saturates")


@DESC
def test_merge_marker_not_bypassed(desc: bool) -> None:
    run_merge(2, 4, desc, "marker_not_bypassed")


@DESC
def test_merge_drops_counted_in_their_frame(desc: bool) -> None:
    run_merge(3, 4, desc, "drops_counted_in_their_frame")


@DESC
@pytest.mark.parametrize(("scales", "depth"), [(2, 4), (1, 2)])
def test_merge_losses_around_eof(scales: int, depth: int, desc: bool) -> None:
    run_merge(scales, depth, desc, "losses_around_eof")


@DESC
@pytest.mark.parametrize(("scales", "depth"), [(3, 4), (1, 2)])
def test_merge_frames_waiting(scales: int, depth: int, desc: bool) -> None:
    run_merge(scales, depth, desc, "frames_waiting")
