# SPDX-License-Identifier: MIT
"""orb_frame_gate against a reference model of its rule (docs/frame-gate.md).

The rule: `enable` is sampled with each start of frame, at the first clock edge that sees the
frame's tuser beat on the input (the edge that takes it, unless a passing one waits on a stalled
output: it keeps passing, AXI4-Stream's rule); a frame sampled with enable 1 passes whole, in order,
however enable changes later; a
frame sampled with enable 0 is taken whole (s_axis_video_tready 1 at every one of its beats, no
stall whatever the output does) and never appears on the output; out of reset the gate is open
(the rest of a frame cut by a reset passes). Latency 0: a passed beat is on the output in the
same clock as on the input, and tready comes back from the output.

`GateModel` implements that rule one clock edge at a time. A monitor reads the ports at every edge,
steps the model and checks: an input beat the model passes is on m_axis_video at that edge with the
same data, tuser and tlast, and s_axis_video_tready equals m_axis_video_tready; a beat the model
drops is taken at once (tready 1) and m_axis_video_tvalid is 0; and, whatever the model says, a beat on
m_axis_video that is not taken is there at the next edge with the same data, tuser and tlast
(AXI4-Stream's source rule, which the formal check proves: docs/formal.md). At the end: every input beat was
taken once, in order; the output beats (seen by the monitor and, in the random runs, received by
cocotbext-axi's AxiStreamSink) are exactly the model's passed beats; the directed scenarios also
compare the output with the frames they name by hand.

Directed: the gate open out of reset (beats without a start of frame pass while enable is 0);
enable falling during a passed frame (it still passes whole) and rising during a dropped frame (it
stays blocked); enable changing in the same clock as the tuser beat (the new value decides), in the
clock after it (the old value decides) and while the tuser beat is stalled by the output (the
value of its first clock decides: enable falling while it waits does not drop it, the regression
test of the violation the formal check found); back-to-back frames; reset in mid-frame reopens the gate;
one beat per clock without gaps or back-pressure. Random (seed ORB_SEED): frames of random sizes,
random input gaps, AxiStreamSink back-pressure from a pause generator, enable toggling at random
clocks plus on and right after start-of-frame beats, resets at random points; the run must have hit
each of these situations (counted by the monitor).
"""

from __future__ import annotations

import warnings
from collections import Counter
from dataclasses import dataclass

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge

from golden_model.latency import FRAME_GATE_LAT
from orbtb.runner import run
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int, pause_pattern

warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotbext\..*")
warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotb_bus\..*")

from cocotbext.axi import AxiStreamBus, AxiStreamSink  # noqa: E402

FLIP = "flip"  # an enable value for Send/Idle: the opposite of the current one


@dataclass(frozen=True)
class Beat:
    data: int
    user: int = 0
    last: int = 0


@dataclass
class Send:
    """One input beat, after `gap` idle clocks. `enable` (0, 1, FLIP) is written in the same clock
    the beat is put on the input. Benches that drive m_axis_video_tready themselves hold it low for
    `stall` clocks with this beat on the input, then raise it and write `enable_late`."""

    beat: Beat
    gap: int = 0
    enable: int | str | None = None
    stall: int = 0
    enable_late: int | None = None


@dataclass
class Idle:
    cycles: int
    enable: int | str | None = None  # written at the start of the idle clocks


@dataclass
class Reset:
    cycles: int = 2  # rst high for this many clock edges, the input idle


Step = Send | Idle | Reset


class GateModel:
    """The frame gate's rule, one clock edge at a time.

    A frame passes or is dropped as a whole; which is decided by `enable` at the first clock edge
    that sees its start-of-frame (tuser) beat on the input: a dropped one is taken there, a passing
    one that the output stalls keeps passing until taken (`sof_hold`). Beats after a reset and
    before the next start of frame pass (the gate is open out of reset)."""

    def __init__(self) -> None:
        self.frame_passes = True
        self.sof_hold = False  # a passing tuser beat was not taken at the last edge

    def passes(self, user: int, enable: int) -> bool:
        """Whether the beat on the input at this edge is one of a passed frame (were it taken now)."""
        if user:
            return enable == 1 or self.sof_hold
        return self.frame_passes

    def step(self, user: int, passes: bool, taken: bool) -> None:
        """The input beat (user, passes) is taken at this edge, or waits (not taken)."""
        if user and taken:
            self.frame_passes = passes
        self.sof_hold = bool(user and passes and not taken)

    def idle(self) -> None:
        """No beat on the input at this edge."""
        self.sof_hold = False

    def reset(self) -> None:
        self.frame_passes = True
        self.sof_hold = False


def port_beat(dut, prefix: str) -> Beat:
    """The beat on the AXI4-Stream port `prefix` (tdata, tuser, tlast)."""
    data, user, last = (int(getattr(dut, f"{prefix}_{name}").value) for name in ("tdata", "tuser", "tlast"))
    return Beat(data, user, last)


class Bench:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.bits = env_int("ORB_DATA_WIDTH", 8)
        self.model = GateModel()
        self.edge = 0
        self.enable = 0
        self.direct_ready = True
        self.sink: AxiStreamSink | None = None
        self.taken: list[tuple[int, Beat, int, bool]] = []  # (edge, beat, enable, passed)
        self.expected: list[Beat] = []  # the model's passed beats
        self.out: list[tuple[int, Beat]] = []  # (edge, beat) of every output handshake
        self.errors: list[str] = []
        self.cov: Counter[str] = Counter()

    async def start(self, enable: int = 1, sink_pause: float | None = None, seed: int = 1) -> None:
        """Reset with every input driven. sink_pause None: the bench drives m_axis_video_tready
        (Send.stall); else an AxiStreamSink takes the output, pausing with that probability."""
        dut = self.dut
        dut.rst.value = 1
        self.enable = enable
        dut.enable.value = enable
        for name in ("tvalid", "tuser", "tlast", "tdata"):
            getattr(dut, f"s_axis_video_{name}").value = 0
        self.direct_ready = sink_pause is None
        dut.m_axis_video_tready.value = 1 if self.direct_ready else 0
        cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
        if not self.direct_ready:
            self.sink = AxiStreamSink(AxiStreamBus.from_prefix(dut, "m_axis_video"), dut.clk, byte_size=self.bits)
            self.sink.log.setLevel("WARNING")
            if sink_pause > 0:
                self.sink.set_pause_generator(pause_pattern(seed, sink_pause))
        cocotb.start_soon(self._monitor())
        await ClockCycles(dut.clk, 3)
        dut.rst.value = 0

    def _error(self, msg: str) -> None:
        if len(self.errors) < 10:
            self.errors.append(f"edge {self.edge}: {msg}")

    async def _monitor(self) -> None:
        dut, model, cov = self.dut, self.model, self.cov
        prev_enable = None
        after_sof: int | None = None  # enable at the last start of frame, for the edge after it
        sof_enable: int | None = None  # enable at the start of the frame under way (None: none since rst)
        reopened = False  # the gate was closed when rst came: later beats of that frame must pass
        waiting: Beat | None = None  # a passing tuser beat the output stalled at the last edge
        m_held: Beat | None = None  # the beat on m_axis_video not taken at the last edge
        while True:
            await RisingEdge(dut.clk)
            self.edge += 1
            rst = dut.rst.value == 1
            en = int(dut.enable.value)
            m_valid = int(dut.m_axis_video_tvalid.value)
            m_ready = int(dut.m_axis_video_tready.value)
            m_beat = None
            if m_valid:
                m_beat = port_beat(dut, "m_axis_video")
                if m_ready:
                    self.out.append((self.edge, m_beat))
            if m_held is not None and m_beat != m_held:
                self._error(f"m_axis_video beat {m_held} not taken, then {m_beat} (tvalid {m_valid}): AXI4-Stream")
            m_held = m_beat if m_valid and not m_ready and not rst else None
            if after_sof is not None and en != after_sof:
                cov["enable changed in the clock after a start of frame"] += 1
            after_sof = None
            if dut.s_axis_video_tvalid.value == 1:
                beat = port_beat(dut, "s_axis_video")
                s_ready = int(dut.s_axis_video_tready.value)
                passes = model.passes(beat.user, en)
                if passes:
                    if m_beat != beat:
                        self._error(f"input beat {beat} (enable {en}) passes, output {m_beat}")
                    if s_ready != m_ready:
                        self._error(f"passing beat: s_axis_video_tready {s_ready}, m_axis_video_tready {m_ready}")
                    if not m_ready:
                        cov["passing beat stalled by the output"] += 1
                else:
                    if m_valid:
                        self._error(f"input beat {beat} (enable {en}) is dropped, output {m_beat} valid")
                    if not s_ready:
                        self._error(f"dropped beat {beat} not taken (s_axis_video_tready 0)")
                    if not m_ready:
                        cov["dropped beat taken while the output stalls"] += 1
                if beat.user and passes and en == 0 and beat == waiting:
                    cov["tuser beat kept passing after enable fell while it waited"] += 1
                waiting = beat if beat.user and passes and not s_ready else None
                if s_ready:
                    self.taken.append((self.edge, beat, en, passes))
                    if passes:
                        self.expected.append(beat)
                    if beat.user:
                        cov["frames passed" if passes else "frames dropped"] += 1
                        if prev_enable is not None and en != prev_enable:
                            cov["enable changed in the clock of a start of frame"] += 1
                        after_sof = sof_enable = en
                        reopened = False
                    elif reopened and passes:
                        cov["beats of a closed frame passed after reset"] += 1
                    elif sof_enable == 1 and en == 0 and passes:
                        cov["beats passed with enable 0 (it fell in mid-frame)"] += 1
                    elif sof_enable == 0 and en == 1 and not passes:
                        cov["beats dropped with enable 1 (it rose in mid-frame)"] += 1
                model.step(beat.user, passes, bool(s_ready))
            else:
                model.idle()
                waiting = None
                if m_valid:
                    self._error(f"output beat {m_beat} with no input beat")
            if rst:
                if not model.frame_passes:
                    reopened = True
                model.reset()
                sof_enable = None
            prev_enable = en

    def _set_enable(self, value: int | str) -> None:
        self.enable = 1 - self.enable if value == FLIP else int(value)
        self.dut.enable.value = self.enable

    async def drive(self, steps: list[Step], toggle_prob: float = 0.0, seed: int = 0) -> None:
        """Play the steps; with toggle_prob > 0, enable also flips with that probability in every
        clock where a step does not set it."""
        dut = self.dut
        rng = np.random.default_rng(seed)

        def maybe_toggle() -> None:
            if toggle_prob > 0 and rng.random() < toggle_prob:
                self._set_enable(FLIP)

        for st in steps:
            if isinstance(st, Reset):
                dut.s_axis_video_tvalid.value = 0
                dut.rst.value = 1
                await ClockCycles(dut.clk, st.cycles)
                dut.rst.value = 0
                continue
            if isinstance(st, Idle):
                dut.s_axis_video_tvalid.value = 0
                for k in range(st.cycles):
                    if k == 0 and st.enable is not None:
                        self._set_enable(st.enable)
                    else:
                        maybe_toggle()
                    await RisingEdge(dut.clk)
                continue
            for _ in range(st.gap):
                dut.s_axis_video_tvalid.value = 0
                maybe_toggle()
                await RisingEdge(dut.clk)
            dut.s_axis_video_tdata.value = st.beat.data
            dut.s_axis_video_tuser.value = st.beat.user
            dut.s_axis_video_tlast.value = st.beat.last
            dut.s_axis_video_tvalid.value = 1
            if st.enable is not None:
                self._set_enable(st.enable)
            else:
                maybe_toggle()
            if self.direct_ready:
                dut.m_axis_video_tready.value = 0 if st.stall > 0 else 1
            stalled = 0
            while True:
                await RisingEdge(dut.clk)
                if dut.s_axis_video_tready.value == 1:
                    break
                stalled += 1
                assert stalled < 10_000, "input beat never taken"
                if self.direct_ready:
                    if stalled == st.stall:
                        dut.m_axis_video_tready.value = 1
                        if st.enable_late is not None:
                            self._set_enable(st.enable_late)
                else:
                    maybe_toggle()
        dut.s_axis_video_tvalid.value = 0
        if self.direct_ready:
            dut.m_axis_video_tready.value = 1
        await ClockCycles(dut.clk, 4)

    def check(self, steps: list[Step], what: str, expect: list[Beat] | None = None) -> None:
        """The monitor's per-edge checks, every beat taken once in order, the output equal to the
        model's passed beats (and to the sink's, and to `expect` when given)."""
        assert not self.errors, f"{what}: " + "; ".join(self.errors)
        sent = [st.beat for st in steps if isinstance(st, Send)]
        taken = [b for _, b, _, _ in self.taken]
        assert taken == sent, f"{what}: {len(taken)} input beats taken, {len(sent)} sent (or out of order)"
        got = [b for _, b in self.out]
        if got != self.expected:
            i = next((i for i, (a, b) in enumerate(zip(got, self.expected, strict=False)) if a != b), None)
            i = min(len(got), len(self.expected)) if i is None else i
            raise AssertionError(
                f"{what}: output beat {i} is {got[i] if i < len(got) else None}, model "
                f"{self.expected[i] if i < len(self.expected) else None} ({len(got)} out, model {len(self.expected)})"
            )
        if self.sink is not None:
            received: list[Beat] = []
            while not self.sink.empty():
                frame = self.sink.recv_nowait(compact=False)
                n = len(frame.tdata)
                received += [Beat(int(frame.tdata[k]), int(frame.tuser[k]), int(k == n - 1)) for k in range(n)]
            assert received == self.expected, f"{what}: AxiStreamSink received {len(received)} beats, not the model's"
        if expect is not None:
            assert got == expect, f"{what}: output {len(got)} beats, not the {len(expect)} of the expected frames"
        self.dut._log.info(
            "%s: %d beats in, %d out, as the model; %s", what, len(sent), len(got), dict(sorted(self.cov.items()))
        )


def frame(rng: np.random.Generator, width: int, height: int, bits: int, sof: bool = True) -> list[Beat]:
    """A frame of random data: tuser on the first beat (if sof), tlast at the end of each line."""
    data = rng.integers(0, 1 << bits, width * height)
    return [Beat(int(data[i]), int(sof and i == 0), int(i % width == width - 1)) for i in range(width * height)]


def sends(beats: list[Beat], **at: dict) -> list[Send]:
    """Send steps for the beats; at={"i": {field: value}} sets fields of beat i's step."""
    out = [Send(b) for b in beats]
    for i, fields in at.items():
        for k, v in fields.items():
            setattr(out[int(i.removeprefix("b"))], k, v)
    return out


# ------------------------------------------------------------------------------------------------
# directed scenarios


@cocotb.test()
async def open_out_of_reset(dut) -> None:
    """Out of reset the gate is open: beats without a start of frame pass although enable is 0; the
    next frame (enable still 0) is dropped, taken at one beat per clock although the output stalls
    all the while; enable 1 between frames lets the following one pass."""
    b = Bench(dut)
    await b.start(enable=0)
    rng = np.random.default_rng(1)
    headless = frame(rng, 5, 1, b.bits, sof=False)
    dropped, passed = frame(rng, 4, 3, b.bits), frame(rng, 3, 2, b.bits)
    stalled = [Send(bt, stall=3) for bt in dropped]  # m_axis_video_tready low: must not matter
    steps: list[Step] = [*sends(headless), *stalled, Idle(2, enable=1), *sends(passed)]
    await b.drive(steps)
    b.check(steps, "open out of reset", expect=headless + passed)
    edges = [e for e, _, _, _ in b.taken[len(headless) : len(headless) + len(dropped)]]
    assert edges == list(range(edges[0], edges[0] + len(dropped))), "dropped frame not taken at one beat per clock"


@cocotb.test()
async def enable_changes_mid_frame(dut) -> None:
    """Enable falling during a passed frame: it still passes whole (the next frame is dropped);
    rising during a dropped frame: it stays blocked (the next frame passes). Also with the change
    while the output stalls the frame, and with enable toggling every clock in mid-frame."""
    b = Bench(dut)
    await b.start(enable=1)
    rng = np.random.default_rng(2)
    f = [frame(rng, 4, 3, b.bits) for _ in range(6)]
    steps: list[Step] = [
        *sends(f[0], b5={"enable": 0}),  # falls in mid-frame: f0 passes whole
        *sends(f[1], b2={"stall": 2}, b3={"enable": 1}),  # sampled 0: dropped although enable rose
        *sends(f[2], b4={"stall": 3, "enable_late": 0}),  # falls while beat 4 is stalled: passes
        *sends(f[3], b2={"enable": 1}, b3={"enable": 0}, b4={"enable": 1}),  # dropped, enable ends 1
        *sends(f[4], b1={"enable": 0}, b2={"enable": 1}, b3={"enable": 0}),  # passes, enable ends 0
        Idle(3, enable=1),
        *sends(f[5], b6={"enable": 0}),  # passes
    ]
    await b.drive(steps)
    b.check(steps, "enable changes in mid-frame", expect=f[0] + f[2] + f[4] + f[5])


@cocotb.test()
async def enable_with_start_of_frame(dut) -> None:
    """Enable changing in the same clock as the tuser beat (the new value decides), in the clock
    after it (the old value decides), and while the tuser beat waits for a stalled output (the
    value of its first clock decides: it keeps passing); frames back to back, without gaps."""
    b = Bench(dut)
    await b.start(enable=0)
    rng = np.random.default_rng(3)
    f = [frame(rng, 3, 2, b.bits) for _ in range(9)]
    steps: list[Step] = [
        *sends(f[0], b0={"enable": 1}),  # 0 -> 1 with the tuser beat: passes
        *sends(f[1], b0={"enable": 0}),  # 1 -> 0 with the tuser beat: dropped
        *sends(f[2], b1={"enable": 1}),  # 0 -> 1 in the clock after the tuser beat: dropped
        *sends(f[3], b1={"enable": 0}),  # (enable 1 at its tuser beat) 1 -> 0 in the clock after: passes
        *sends(f[4], b0={"enable": 1, "stall": 3}),  # tuser beat stalled 3 clocks, enable 1: passes
        *sends(f[5], b0={"stall": 2, "enable_late": 0}),  # stalled, enable falls before taken: passes
        *sends(f[6], b0={"gap": 2, "enable": 1}),  # after a gap: passes
        *sends(f[7], b0={"enable": 0}, b1={"enable": 1}),  # 1 -> 0 with the tuser beat, back 1 after: dropped
        *sends(f[8]),  # passes
    ]
    await b.drive(steps)
    b.check(steps, "enable with the start of frame", expect=f[0] + f[3] + f[4] + f[5] + f[6] + f[8])
    assert b.cov["tuser beat kept passing after enable fell while it waited"] == 1


@cocotb.test()
async def sof_waiting_keeps_tvalid(dut) -> None:
    """The regression test of the violation the formal check found (docs/formal.md): enable falls
    while a passing start-of-frame beat waits on a stalled output. The old gate dropped
    m_axis_video_tvalid there without a handshake (and the beat with it); now the beat stays on
    m_axis_video with its data until taken, its frame passes whole and the next one is dropped."""
    b = Bench(dut)
    await b.start(enable=1)
    rng = np.random.default_rng(6)
    f = [frame(rng, 3, 2, b.bits) for _ in range(3)]
    for stall in (1, 4):
        dut.s_axis_video_tdata.value = f[0][0].data
        dut.s_axis_video_tuser.value = 1
        dut.s_axis_video_tlast.value = f[0][0].last
        dut.s_axis_video_tvalid.value = 1
        dut.m_axis_video_tready.value = 0
        await RisingEdge(dut.clk)  # offered with enable 1, not taken
        dut.enable.value = 0
        for _ in range(stall):
            await RisingEdge(dut.clk)
            assert dut.m_axis_video_tvalid.value == 1, f"stall {stall}: m_axis_video_tvalid fell, beat not taken"
            assert port_beat(dut, "m_axis_video") == f[0][0], f"stall {stall}: m_axis_video beat changed"
            assert dut.s_axis_video_tready.value == 0, f"stall {stall}: the waiting beat was taken"
        dut.m_axis_video_tready.value = 1
        await RisingEdge(dut.clk)
        assert dut.m_axis_video_tvalid.value == 1 and dut.s_axis_video_tready.value == 1, "beat not passed"
        dut.s_axis_video_tvalid.value = 0
        dut.enable.value = 1
        await RisingEdge(dut.clk)
    b.enable = 1
    steps: list[Step] = [
        *sends(f[0], b0={"stall": 3, "enable_late": 0}),  # enable falls while the tuser beat waits: passes
        *sends(f[1]),  # enable 0: dropped
        *sends(f[2], b0={"enable": 1}),
    ]
    await b.drive(steps)
    assert not b.errors, "; ".join(b.errors)
    got = [bt for _, bt in b.out]
    assert got[-len(f[0] + f[2]) :] == f[0] + f[2], "the frame whose tuser beat waited did not pass whole"


@cocotb.test()
async def reset_mid_frame(dut) -> None:
    """Reset in mid-frame reopens the gate: the rest of a dropped frame passes; in a passed frame
    nothing changes; a reset does not change how the next start of frame samples enable."""
    b = Bench(dut)
    await b.start(enable=0)
    rng = np.random.default_rng(4)
    f = [frame(rng, 4, 3, b.bits) for _ in range(5)]
    steps: list[Step] = [
        *sends(f[0][:5]),  # dropped ...
        Reset(2),
        *sends(f[0][5:]),  # ... the rest passes
        *sends(f[1]),  # enable 0: dropped
        Reset(1),
        *sends(f[2]),  # reset between frames, enable 0: still dropped
        *sends(f[3][:7], b0={"enable": 1}),  # passes ...
        Reset(3),
        *sends(f[3][7:]),  # ... and the rest too
        *sends(f[4], b0={"enable": 0}),  # dropped
    ]
    await b.drive(steps)
    b.check(steps, "reset in mid-frame", expect=f[0][5:] + f[3])


@cocotb.test()
async def full_rate(dut) -> None:
    """Without gaps or back-pressure every beat, passed or dropped, is taken in its clock: one beat
    per clock, and a passed beat leaves in the clock it arrives (latency 0)."""
    b = Bench(dut)
    await b.start(enable=1)
    rng = np.random.default_rng(5)
    f = [frame(rng, 8, 4, b.bits) for _ in range(4)]
    steps: list[Step] = [*sends(f[0]), *sends(f[1], b0={"enable": 0}), *sends(f[2]), *sends(f[3], b0={"enable": 1})]
    await b.drive(steps)
    b.check(steps, "full rate", expect=f[0] + f[3])
    in_edges = [e for e, _, _, _ in b.taken]
    assert in_edges == list(range(in_edges[0], in_edges[0] + len(in_edges))), "not one input beat per clock"
    passed_edges = [e for e, _, _, p in b.taken if p]
    assert [e + FRAME_GATE_LAT for e in passed_edges] == [e for e, _ in b.out], (
        f"a passed beat did not leave {FRAME_GATE_LAT} clocks after it arrived"
    )


# ------------------------------------------------------------------------------------------------
# random traffic


def random_steps(rng: np.random.Generator, bits: int, n_frames: int) -> list[Step]:
    """Frames of random sizes (1..12 x 1..5) with random gaps; enable flips with about a third of
    the tuser beats and some of the beats after them; a few resets at random beats; headless beats
    (no start of frame) first."""
    steps: list[Step] = []
    beats = frame(rng, int(rng.integers(1, 6)), 1, bits, sof=False)
    for _ in range(n_frames):
        beats += frame(rng, int(rng.integers(1, 13)), int(rng.integers(1, 6)), bits)
    for i, bt in enumerate(beats):
        r = rng.random()
        gap = 0 if r < 0.7 else int(rng.integers(1, 4)) if r < 0.97 else int(rng.integers(8, 30))
        enable = None
        if bt.user and rng.random() < 0.35:
            enable = FLIP
        elif i > 0 and beats[i - 1].user and rng.random() < 0.25:
            enable = FLIP
        steps.append(Send(bt, gap=gap, enable=enable))
    for pos in sorted(rng.choice(np.arange(10, len(steps)), 6, replace=False), reverse=True):
        steps.insert(int(pos), Reset(int(rng.integers(1, 4))))
    return steps


@cocotb.test()
async def random_traffic(dut) -> None:
    """Random frames, gaps, back-pressure (AxiStreamSink pause generator), enable toggles and
    resets against the model; the run must hit every situation the monitor counts."""
    seed = env_int("ORB_SEED", 7)
    rng = np.random.default_rng(seed)
    b = Bench(dut)
    await b.start(enable=int(rng.integers(0, 2)), sink_pause=0.35, seed=seed)
    steps = random_steps(rng, b.bits, 300)
    await b.drive(steps, toggle_prob=0.03, seed=seed + 1)
    b.check(steps, f"random traffic (seed {seed})")
    wanted = (
        "frames passed",
        "frames dropped",
        "enable changed in the clock of a start of frame",
        "enable changed in the clock after a start of frame",
        "beats passed with enable 0 (it fell in mid-frame)",
        "beats dropped with enable 1 (it rose in mid-frame)",
        "beats of a closed frame passed after reset",
        "passing beat stalled by the output",
        "tuser beat kept passing after enable fell while it waited",
        "dropped beat taken while the output stalls",
    )
    missing = [w for w in wanted if b.cov[w] == 0]
    assert not missing, f"random traffic (seed {seed}) never hit: {missing}"


# ------------------------------------------------------------------------------------------------
# pytest runners


def test_frame_gate_8() -> None:
    run("orb_frame_gate", "test_orb_frame_gate", {"DATA_WIDTH_g": 8}, env=SIM_ENV)


def test_frame_gate_24() -> None:
    run("orb_frame_gate", "test_orb_frame_gate", {"DATA_WIDTH_g": 24}, env={**SIM_ENV, "ORB_SEED": "11"})
