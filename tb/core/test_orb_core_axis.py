# SPDX-License-Identifier: MIT
"""orb_core through independent AXI4-Stream bus models (cocotbext-axi), bit-exact with the model.

The video goes in through an AxiStreamSource (one AXI frame per video line: tlast ends the line,
tuser marks the frame's first pixel) with an idle pattern on tvalid; the features come out through
an AxiStreamSink with a backpressure pattern on tready (one AXI frame per video frame: the
features, then the end-of-frame beat). Each frame must equal golden_model's fast-mode features.

Malformed input: a line longer than WIDTH_g and lines beyond HEIGHT_g must be ignored and counted
in bad_pixels (exact count), the frame itself still detected on its WIDTH_g x HEIGHT_g pixels, and
the next good frame bit-exact.
"""

from __future__ import annotations

import dataclasses
import warnings

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, Event, with_timeout

from golden_model.featcodec import decode_eof, is_eof
from golden_model.featword import FEAT_BITS
from golden_model.frameparams import FrameParams
from orb_sim.core_inputs import drive_params, selection_params
from orb_sim.feature_stream import Frame
from orbtb import images
from orbtb.runner import run
from orbtb.scoreboard import check_frame, expected_features
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int, pause_pattern

warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotbext\..*")
warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotb_bus\..*")

from cocotbext.axi import AxiStreamBus, AxiStreamFrame, AxiStreamSink, AxiStreamSource  # noqa: E402

FEATURE_BYTE_SIZE = FEAT_BITS  # one 320-bit word per beat (no tkeep on m_axis_feat)
LOW = 7  # the low threshold input, held (all selection ignores it; the end-of-frame beat reports it)


def params_at(threshold: int) -> FrameParams:
    """The run-time inputs of a frame sent with `threshold` (fast mode, all selection), as its
    end-of-frame beat must report them (only the threshold port changes here)."""
    return dataclasses.replace(selection_params("all", threshold, "fast"), threshold_lo=LOW)


class Bench:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.width, self.height = env_int("ORB_WIDTH"), env_int("ORB_HEIGHT")
        self.scales = env_int("ORB_SCALES")
        self.frames_seen = 0

    async def start(self, idle_prob: float, stall_prob: float) -> None:
        dut = self.dut
        dut.rst.value = 1
        drive_params(dut, params_at(0))
        dut.s_axis_video_tvalid.value = 0
        dut.s_axis_video_tuser.value = 0
        dut.s_axis_video_tlast.value = 0
        dut.s_axis_video_tdata.value = 0
        dut.m_axis_feat_tready.value = 0
        cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
        # bus models only once reset is asserted and the clock starts low
        self.source = AxiStreamSource(AxiStreamBus.from_prefix(dut, "s_axis_video"), dut.clk, dut.rst)
        self.sink = AxiStreamSink(
            AxiStreamBus.from_prefix(dut, "m_axis_feat"), dut.clk, dut.rst, byte_size=FEATURE_BYTE_SIZE
        )
        if idle_prob > 0:
            self.source.set_pause_generator(pause_pattern(1, idle_prob))
        if stall_prob > 0:
            self.sink.set_pause_generator(pause_pattern(2, stall_prob))
        await ClockCycles(dut.clk, 4)
        dut.rst.value = 0
        await ClockCycles(dut.clk, 2)

    async def send_frame(self, lines: list[np.ndarray], threshold: int, change_after_first_line: bool = False) -> None:
        """Queue one video frame (any list of lines, each one AXI frame) with its threshold. With
        change_after_first_line the threshold port changes once the first line has gone (the
        frame must still use the value present with its first pixel)."""
        first_gone = Event()
        self.dut.threshold.value = threshold
        for i, line in enumerate(lines):
            tuser = [1] + [0] * (len(line) - 1) if i == 0 else 0
            frame = AxiStreamFrame(
                bytes(line.astype(np.uint8)), tuser=tuser, tx_complete=first_gone if i == 0 else None
            )
            await self.source.send(frame)
        if change_after_first_line:
            await first_gone.wait()
            self.dut.threshold.value = (threshold + 101) % 256
        await self.source.wait()

    async def check_next(self, img: np.ndarray, threshold: int, what: str) -> None:
        """Receive the next feature frame and compare it with the model."""
        rx = await with_timeout(self.sink.recv(), 20 * self.width * self.height * PERIOD_NS, "ns")
        words = list(rx.tdata)
        assert words, f"{what}: empty AXI frame"
        eof = words[-1]
        assert is_eof(eof), f"{what}: the tlast beat {eof:#x} is not an end-of-frame beat"
        e = decode_eof(eof)
        frame = Frame(beats=words[:-1], number=e.frame, drops=e.drops)
        assert not [w for w in frame.beats if is_eof(w)], f"{what}: end-of-frame flag without tlast"
        assert frame.number == self.frames_seen, f"{what}: end-of-frame beat numbered {frame.number}"
        assert frame.drops == 0, f"{what}: {frame.drops} features dropped"
        assert e.params == params_at(threshold), f"{what}: the end-of-frame beat says {e.params}"
        check_frame(frame.features(), expected_features(img, self.scales, threshold), f"{what} (threshold {threshold})")
        self.dut._log.info("%s: %d features bit-exact", what, len(frame.beats))
        self.frames_seen += 1


@cocotb.test()
async def axis_pauses(dut) -> None:
    """Photographs back to back with source idles and sink backpressure."""
    b = Bench(dut)
    await b.start(idle_prob=0.3, stall_prob=0.5)
    frames = [(images.photo("astronaut", b.width, b.height), 20), (images.photo("coffee", b.width, b.height), 8)]
    receiver = cocotb.start_soon(_receive_all(b, frames, "pauses"))
    for img, t in frames:
        await b.send_frame(list(img), t)
    await receiver
    assert int(dut.bad_pixels.value) == 0, f"bad_pixels = {int(dut.bad_pixels.value)} for well-formed frames"
    assert int(dut.dropped.value) == 0


async def _receive_all(b: Bench, frames: list[tuple[np.ndarray, int]], what: str) -> None:
    for i, (img, t) in enumerate(frames):
        await b.check_next(img, t, f"{what} frame {i}")


@cocotb.test()
async def axis_bad_pixels(dut) -> None:
    """A long line and extra lines are counted exactly and ignored; the next frame is bit-exact."""
    b = Bench(dut)
    await b.start(idle_prob=0.1, stall_prob=0.3)
    w, h = b.width, b.height
    rng = np.random.default_rng(4)
    bad_img = images.photo("chelsea", w, h)
    good_img = images.photo("camera", w, h)
    long_row, extra_px, extra_lines = 5, 3, 2
    lines = [row for row in bad_img]
    lines[long_row] = np.concatenate([lines[long_row], rng.integers(0, 256, extra_px)])
    lines += [rng.integers(0, 256, w) for _ in range(extra_lines)]
    expected_bad = extra_px + extra_lines * w

    receiver = cocotb.start_soon(_receive_all(b, [(bad_img, 25), (good_img, 15)], "bad-pixel test"))
    await b.send_frame(lines, 25)
    await ClockCycles(dut.clk, 4)
    bad = int(dut.bad_pixels.value)
    assert bad == expected_bad, (
        f"bad_pixels = {bad} after a {w + extra_px}-pixel line and {extra_lines} extra lines, expected {expected_bad}"
    )
    await b.send_frame(list(good_img), 15)
    await receiver
    await ClockCycles(dut.clk, 4)
    assert int(dut.bad_pixels.value) == expected_bad, "a well-formed frame changed bad_pixels"


@cocotb.test()
async def threshold_sampled_at_frame_start(dut) -> None:
    """The threshold port changes right after each frame's first line: every scale of the frame
    must still use the value present with the frame's first pixel (spec: a threshold written
    during a frame applies from the next frame)."""
    b = Bench(dut)
    await b.start(idle_prob=0.0, stall_prob=0.0)
    frames = [(images.photo("astronaut", b.width, b.height), 20), (images.photo("rocket", b.width, b.height), 10)]
    receiver = cocotb.start_soon(_receive_all(b, frames, "threshold test"))
    for img, t in frames:
        await b.send_frame(list(img), t, change_after_first_line=True)
    await receiver


# ------------------------------------------------------------------------------------------------
# pytest runners

# orbtb.runner builds once per (module, generic set); the generics also differ from those of
# test_orb_core (FIFO_DEPTH_g) so the two never share an elaborated design.


def test_detect_top_axis() -> None:
    generics = {"WIDTH_g": 96, "HEIGHT_g": 64, "SCALES_g": 2, "FIFO_DEPTH_g": 32}
    run("orb_core", "test_orb_core_axis", generics, env=SIM_ENV, testcase="axis_pauses,axis_bad_pixels")


def test_detect_top_threshold_sampled_at_frame_start() -> None:
    generics = {"WIDTH_g": 96, "HEIGHT_g": 64, "SCALES_g": 2, "FIFO_DEPTH_g": 16}
    run("orb_core", "test_orb_core_axis", generics, env=SIM_ENV, testcase="threshold_sampled_at_frame_start")
