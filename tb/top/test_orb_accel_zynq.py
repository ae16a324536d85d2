# SPDX-License-Identifier: MIT
"""orb_accel_zynq, the flat Vivado wrapper of orb_accel_top: the same accelerator behind Xilinx-style
names (aclk, aresetn active low, s_axi_ctrl_* AXI4-Lite, s_axis_video_* / m_axis_video_*, irq).

- wrapper: the CPU model on s_axi_ctrl reads the ID, configures threshold, interrupt enable and
  CTRL.enable; two colour photographs stream through s_axis_video in the wrapper's packing (24-bit
  tdata, INPUT_g); after each frame-done interrupt the newest bank is read back (STATUS.last_bank,
  BANKn_INFO.count, slots words 0..9, the end-of-frame record) and compared with the golden model;
  m_axis_video carries frame 0 unchanged and frame 1 with frame 0's features drawn on it
  (render_marker_overlay). Then aresetn is pulled low in mid-frame: the registers return to their
  reset values, the interrupt drops, and the next good frame is published as frame 0, bit-exact.
- board_events: what the Zybo's HDMI input (v_vid_in_axi4s) does when the cable is pulled, the
  source is switched off or changes resolution, with frame_done and error interrupts enabled; the
  wrapper's video checker treats its input as live (IDLE_TIMEOUT_g, docs/video-input.md).
  (a) Cable unplugged: frame B stops in mid-line after about half its lines and the source stays
  silent for 24,000 clocks; meanwhile the CPU reads ID, STATUS, IRQ_STATUS, every counter, writes
  and reads back THRESHOLD, reads the feature memory (raw words of both banks and, through the
  driver, bank 0, which must still hold frame A), each access bounded (a hang fails with the
  access's name); nothing is published (STATUS.bank_ready 0, last_bank unchanged). IDLE_TIMEOUT_g
  clocks after B's last pixel the checker pads the rest of B and closes it bad (frame_fault bit 4):
  the error interrupt rises once, at the clock the timeout and the padding give, PROTO_ERRORS + 1,
  FRAME_COUNT + 1 (B's number used up), DISCARDED + 0, while the cable is still out. (b) Cable
  back: the next frame C finds no frame open and is published as frame 2 in bank 1, bit-exact with
  the threshold written during the silence, with no error: only the cut frame is lost. (c)
  Resolution change: a frame D with shorter and fewer lines (short line: padded, aborted, never
  published, PROTO_ERRORS + 1, DISCARDED + the rest of D), and back to back with it E, longer lines
  and more lines, whose start of frame arrives while D is padded: discarded with all of E (a start
  of frame during padding loses its frame: DISCARDED + all of E, no frame, no error), then a frame G
  of the right line length but more lines (too many lines: its first HEIGHT_g lines are a good
  frame, published as frame 4; the extra lines are discarded) and a frame F of the right format
  (frame 5), both bit-exact; FRAME_COUNT, DROPPED, OVERRUN, OVERFLOW_COUNT, DESC_LOST checked too.
  m_axis_video: every beat taken on s_axis_video leaves in order with its tuser and tlast (wrong
  sizes pass as they came), unchanged or in a marker colour, and the last frame shows the previous
  published frame's features exactly (render_marker_overlay). On the old checker (IDLE_TIMEOUT_g
  0) B would stay open through the silence and be closed by C's start of frame.
- wrapper on the DDR build (test_accel_zynq_ddr, MEM_KIND_g "DDR"): the same, the frames written
  through m_axi_feat into cocotbext-axi's AXI4 RAM (an emulated reserved region inside the
  wrapper's 1 GiB window, random stalls on AW, W and B) and read by the driver from there; CFG_DDR
  reads the window; after aresetn RING_COUNT is 0 and the driver lays the ring out again.
- reset_pulse: a one-clock aresetn pulse while a read and a write response wait: both fall at the
  edge that samples aresetn low and stay low; the registers are reset (the formal check's finding on
  the wrapper that registered aresetn only, docs/formal.md).
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, ReadOnly, RisingEdge, SimTimeoutError, with_timeout

from golden_model import regs
from golden_model.luma import rgb_to_luma
from golden_model.overlay import SCALE_COLOURS, render_marker_overlay
from orb_accel.driver import COUNTERS
from orb_sim.accel_bench import BLANKING, OKAY, AccelBench
from orb_sim.cocotb_bus import PERIOD_NS
from orb_sim.video import Gaps
from orbtb.images import colour_photo
from orbtb.runner import run
from orbtb.scoreboard import check_frame, expected_features
from orbtb.unit import SIM_ENV, env_int

warnings.filterwarnings("ignore", category=DeprecationWarning)


@cocotb.test()
async def wrapper(dut) -> None:
    b = AccelBench(dut, "aclk", "aresetn", reset_active_low=True, axil_prefix="s_axi_ctrl")
    await b.start(ddr_pause=0.3)  # a DDR build: stalls on m_axi_feat's AW, W and B
    b.start_capture()
    w, h, t = b.width, b.height, 25
    assert await b.read_reg(regs.ID) == regs.ORB_ID
    size = await b.read_reg(regs.CFG_SIZE)
    assert (regs.CFG_SIZE.field("width").get(size), regs.CFG_SIZE.field("height").get(size)) == (w, h)
    assert regs.CFG_MEM.field("depth").get(await b.read_reg(regs.CFG_MEM)) == b.depth
    ddr = await b.read_reg(regs.CFG_DDR)
    assert regs.CFG_DDR.field("ddr").get(ddr) == int(b.ddr), f"CFG_DDR = {ddr:#x}"
    if b.ddr:  # the wrapper's DDR window: the Zybo's 1 GiB at 0 (WIN_BASE_MB_g, WIN_SIZE_MB_g defaults)
        assert (regs.CFG_DDR.field("win_base").get(ddr), regs.CFG_DDR.field("win_size").get(ddr)) == (0, 1024)
    await b.configure(threshold=t)
    frames = [colour_photo("astronaut", w, h), colour_photo("coffee", w, h)]
    exps = [expected_features(rgb_to_luma(f), b.scales, t, "orb", b.sectors) for f in frames]
    assert all(len(e) > 0 for e in exps), "a test photograph has no feature to compare"

    async def video() -> None:
        for f in frames:
            await b.send(f)

    cocotb.start_soon(video())
    for k in range(len(frames)):
        feats, record = await b.read_newest()
        check_frame(feats, exps[k], f"frame {k}")
        assert (record.frame, record.dropped, record.truncated) == (k, 0, 0), record
    while len(b.captured) < len(frames):
        await RisingEdge(b.clk)
    assert not np.any(b.captured[0] != frames[0]), "frame 0 has no earlier features: it must pass unchanged"
    want = render_marker_overlay(frames[1], exps[0], scales=b.scales)
    bad = np.argwhere(np.any(b.captured[1] != want, axis=-1))
    assert len(bad) == 0, f"overlay of frame 1: first differing pixel (y, x) = {tuple(bad[0])}"
    assert await b.read_reg(regs.FRAME_COUNT) == 2

    # aresetn in mid-frame: everything (registers included) is reset
    task = cocotb.start_soon(b.send(frames[1], Gaps()))
    await ClockCycles(dut.aclk, w * (h // 2))
    task.cancel()
    b.video.idle()
    dut.aresetn.value = 0
    await ClockCycles(dut.aclk, 2)
    await ReadOnly()
    assert dut.irq.value == 0 and dut.s_axi_ctrl_bvalid.value == 0 and dut.s_axi_ctrl_rvalid.value == 0
    await RisingEdge(dut.aclk)
    dut.aresetn.value = 1
    await ClockCycles(dut.aclk, 2)
    assert await b.read_reg(regs.THRESHOLD) == regs.THRESHOLD.reset_value(), "THRESHOLD kept over aresetn"
    assert await b.read_reg(regs.CTRL) == regs.CTRL.reset_value(), "CTRL kept over aresetn"
    assert await b.read_reg(regs.FRAME_COUNT) == 0
    if b.ddr:  # the ring's registers are reset too: the driver lays the ring out again
        assert await b.read_reg(regs.RING_COUNT) == 0, "RING_COUNT kept over aresetn"
        await b.open_ring()
    await b.configure(threshold=t)
    await b.send(frames[0])
    feats, record = await b.read_newest()
    assert record.frame == 0, f"the first frame after aresetn is frame {record.frame}"
    check_frame(feats, exps[0], "frame after aresetn")
    for reg in (regs.DROPPED, regs.PROTO_ERRORS, regs.DISCARDED, regs.OVERRUN):
        assert await b.read_reg(reg) == 0, f"{reg.name} after aresetn"
    if b.ddr:
        for reg in (regs.DMA_DROPPED, regs.DMA_BUS_ERRORS):
            assert await b.read_reg(reg) == 0, f"{reg.name} after aresetn"
        assert b.ram is not None and b.ram.outside_writes == 0


async def _until(dut, signal: str, what: str, clocks: int = 200) -> None:
    """Wait (after a rising edge, in ReadOnly) until `signal` is 1, failing with `what` after `clocks` clocks."""
    for _ in range(clocks):
        await RisingEdge(dut.aclk)
        await ReadOnly()
        if getattr(dut, signal).value == 1:
            return
    raise AssertionError(f"{what}: {signal} not 1 within {clocks} clocks")


async def _read_address(dut, addr: int, what: str, clocks: int = 200) -> None:
    """Offer a read address until arready takes it (at a rising edge), then drop arvalid."""
    dut.s_axi_ctrl_araddr.value = addr
    dut.s_axi_ctrl_arvalid.value = 1
    for _ in range(clocks):
        await ReadOnly()
        taken = dut.s_axi_ctrl_arready.value == 1
        await RisingEdge(dut.aclk)
        if taken:
            dut.s_axi_ctrl_arvalid.value = 0
            return
    raise AssertionError(f"{what}: arready not 1 within {clocks} clocks")


@cocotb.test()
async def reset_pulse(dut) -> None:
    """A one-clock aresetn pulse while a read response and a write response wait (rready and bready low):
    from the edge that samples aresetn low, rvalid and bvalid are 0 and stay 0 (the master, reset at
    that edge, must see no response to a request of before the reset), and the next read is answered with
    the reset values. The wrapper that registered aresetn only (reset a clock late) showed rvalid and
    bvalid for a clock after the pulse: the formal check's counterexample (docs/formal.md)."""
    cocotb.start_soon(Clock(dut.aclk, PERIOD_NS, unit="ns").start(start_high=False))
    for name in ("awaddr", "awprot", "awvalid", "wdata", "wstrb", "wvalid", "bready", "araddr", "arprot",
                 "arvalid", "rready"):  # fmt: skip
        getattr(dut, f"s_axi_ctrl_{name}").value = 0
    for name in ("tdata", "tvalid", "tuser", "tlast"):
        getattr(dut, f"s_axis_video_{name}").value = 0
    dut.m_axis_video_tready.value = 1
    dut.aresetn.value = 0
    await ClockCycles(dut.aclk, 4)
    dut.aresetn.value = 1
    await ClockCycles(dut.aclk, 2)
    # a read of ID and a write of THRESHOLD, their responses left waiting
    await _read_address(dut, regs.ID.offset, "read address")
    await _until(dut, "s_axi_ctrl_rvalid", "read response")
    await RisingEdge(dut.aclk)
    dut.s_axi_ctrl_awaddr.value = regs.THRESHOLD.offset
    dut.s_axi_ctrl_wdata.value = 33
    dut.s_axi_ctrl_wstrb.value = 0xF
    dut.s_axi_ctrl_awvalid.value = 1
    dut.s_axi_ctrl_wvalid.value = 1
    await ReadOnly()
    aw = dut.s_axi_ctrl_awready.value == 1
    w = dut.s_axi_ctrl_wready.value == 1
    for _ in range(200):
        if aw and w:
            break
        await RisingEdge(dut.aclk)
        if aw:
            dut.s_axi_ctrl_awvalid.value = 0
        if w:
            dut.s_axi_ctrl_wvalid.value = 0
        await ReadOnly()
        aw = aw or dut.s_axi_ctrl_awready.value == 1
        w = w or dut.s_axi_ctrl_wready.value == 1
    assert aw and w, "write address and data not taken within 200 clocks"
    await RisingEdge(dut.aclk)
    dut.s_axi_ctrl_awvalid.value = 0
    dut.s_axi_ctrl_wvalid.value = 0
    await _until(dut, "s_axi_ctrl_bvalid", "write response")
    assert dut.s_axi_ctrl_rvalid.value == 1, "the read response must still wait (rready is 0)"
    # aresetn low for exactly one clock
    await RisingEdge(dut.aclk)
    dut.aresetn.value = 0
    await RisingEdge(dut.aclk)  # the one edge that samples aresetn low
    dut.aresetn.value = 1
    for k in range(8):
        await ReadOnly()
        got = {s: int(getattr(dut, s).value) for s in ("s_axi_ctrl_rvalid", "s_axi_ctrl_bvalid")}
        assert not any(got.values()), f"clock {k} after a one-clock aresetn pulse: {got} (a response from before it)"
        await RisingEdge(dut.aclk)
    # the registers are back to their reset values: a new read of THRESHOLD
    dut.s_axi_ctrl_rready.value = 1
    await _read_address(dut, regs.THRESHOLD.offset, "read address after the pulse")
    await ReadOnly()
    if dut.s_axi_ctrl_rvalid.value != 1:
        await _until(dut, "s_axi_ctrl_rvalid", "read response after the pulse")
    got, want = int(dut.s_axi_ctrl_rdata.value), regs.THRESHOLD.reset_value()
    assert got == want, f"THRESHOLD after a one-clock aresetn pulse: {got}, its reset value {want}"


# ---- board events: cable unplugged, cable back, resolution change ------------------------------
ACCESS_CLOCKS = 2000  # bound of one CPU access (below CocotbBus's own OP_TIMEOUT_CLOCKS of 5000)
GAP_CLOCKS = 24_000  # the source is silent this long after the cut (about two 128x96 frames)
SETTLE_CLOCKS = 2000  # after the last pixel of a wrong frame: its end-of-frame beat has long left


async def bounded(coro, what: str, clocks: int = ACCESS_CLOCKS):
    """Await a CPU access (or a series of them), failing with `what` instead of hanging."""
    try:
        return await with_timeout(coro, clocks * PERIOD_NS, "ns")
    except SimTimeoutError:
        raise AssertionError(f"{what}: no AXI4-Lite response within {clocks} clocks (the bus hung)") from None


Beat = tuple[int, int, int]  # (tdata, tuser, tlast)


class StreamLog:
    """Every beat taken on s_axis_video and on m_axis_video, and the clocks at which irq rose
    (one Python step per clock)."""

    def __init__(self, dut) -> None:
        self.dut = dut
        self.taken_in: list[Beat] = []
        self.taken_out: list[Beat] = []
        self.irq_rises: list[int] = []
        self.clock = 0

    async def run(self) -> None:
        d = self.dut
        ports = [
            (log, *(getattr(d, f"{prefix}_{n}") for n in ("tdata", "tvalid", "tready", "tuser", "tlast")))
            for log, prefix in ((self.taken_in, "s_axis_video"), (self.taken_out, "m_axis_video"))
        ]
        irq_was = 0
        while True:
            await RisingEdge(d.aclk)
            await ReadOnly()
            self.clock += 1
            for log, data, valid, ready, user, last in ports:
                if valid.value == 1 and ready.value == 1:
                    log.append((int(data.value), int(user.value), int(last.value)))
            irq = int(d.irq.value)
            if irq and not irq_was:
                self.irq_rises.append(self.clock)
            irq_was = irq


def split_frames(beats: list[Beat]) -> list[list[list[int]]]:
    """Frames (split at tuser) of lines (split after tlast) of tdata words."""
    frames: list[list[list[int]]] = []
    for data, user, last in beats:
        if user or not frames:
            frames.append([[]])
        frames[-1][-1].append(data)
        if last:
            frames[-1].append([])
    return [[line for line in f if line] for f in frames]


def place(beats: list[Beat], i: int) -> str:
    """Where beat i lies: frame (counted by tuser), line (counted by tlast) and pixel."""
    frame, line, x, after_last = -1, 0, -1, False
    for _, user, last in beats[: i + 1]:
        if user:
            frame, line, x = frame + 1, 0, 0
        elif after_last:
            line, x = line + 1, 0
        else:
            x += 1
        after_last = bool(last)
    return f"video frame {frame} of this test, line {line}, pixel {x}"


@cocotb.test()
async def board_events(dut) -> None:
    """Board events on the HDMI input (docs/video-input.md fault table, docs/feature-memory.md
    protocol): (a) the cable unplugged in mid-frame, a long silence with CPU traffic; (b) the
    cable back; (c) a resolution change; the overlay output through all of them."""
    b = AccelBench(dut, "aclk", "aresetn", reset_active_low=True, axil_prefix="s_axi_ctrl")
    await b.start()
    log = StreamLog(dut)
    cocotb.start_soon(log.run())
    w, h, t, t2 = b.width, b.height, 25, 30
    irq_both = regs.IRQ_ENABLE.field("frame_done").put(1, regs.IRQ_ENABLE.field("error").put(1))
    await b.configure(threshold=t, irq=irq_both)
    error_bit = regs.IRQ_STATUS.field("error").put(1)

    def expect(rgb: np.ndarray, threshold: int):
        return expected_features(rgb_to_luma(rgb), b.scales, threshold, "orb", b.sectors)

    frame_a = colour_photo("astronaut", w, h)  # published as frame 0
    frame_b = colour_photo("coffee", w, h)  # cut in mid-frame by the unplugged cable: frame 1, bad
    frame_c = colour_photo("chelsea", w, h)  # the cable is back: frame 2 (threshold t2)
    ws, hs = 3 * w // 4, 3 * h // 4  # a smaller format: shorter lines, fewer lines (frame 3, bad)
    frame_d = colour_photo("rocket", ws, hs)
    wl, hl = 5 * w // 4, 5 * h // 4  # a larger format: longer lines, more lines (lost while D is padded)
    frame_e = colour_photo("coffee", wl, hl)
    frame_g = colour_photo("astronaut", w, hl)  # the right line length but more lines (frame 4, good)
    frame_f = colour_photo("coffee", w, h)  # the right format again (frame 5)
    exp_a, exp_c = expect(frame_a, t), expect(frame_c, t2)
    exp_g, exp_f = expect(frame_g[:h], t2), expect(frame_f, t2)
    for name, e in (("A", exp_a), ("C", exp_c), ("G", exp_g), ("F", exp_f)):
        assert 0 < len(e) < b.depth - 1, f"frame {name} has {len(e)} features: none, or more than a bank holds"

    want = dict.fromkeys(COUNTERS, 0)  # the counters the rules give, kept up to date below

    async def check_counters(when: str) -> None:
        got = {n: await bounded(b.read_reg(getattr(regs, n)), f"{n} read {when}") for n in COUNTERS}
        bad = [f"{n} = {got[n]}, expected {want[n]}" for n in COUNTERS if got[n] != want[n]]
        assert not bad, f"{when}: " + "; ".join(bad)

    async def check_status(when: str, last_bank: int) -> None:
        """No bank READY (each published one was released) and last_bank as the rule gives."""
        status = await bounded(b.read_reg(regs.STATUS), f"STATUS read {when}")
        got = (regs.STATUS.field("bank_ready").get(status), regs.STATUS.field("last_bank").get(status))
        assert got == (0, last_bank), f"{when}: STATUS.bank_ready, last_bank = {got}, expected (0, {last_bank})"

    async def next_published(what: str):
        """The driver's steps (docs/driver.md) with every IRQ_STATUS bit recorded: wait for the
        interrupt, acknowledge it, until frame_done; then STATUS.last_bank, BANKn_INFO, the bank,
        BANK_RELEASE. Returns (bank, features, record, IRQ_STATUS bits seen)."""
        seen = 0
        while not regs.IRQ_STATUS.field("frame_done").get(seen):
            await b.wait_irq(b.frame_timeout_clocks)
            st = await bounded(b.read_reg(regs.IRQ_STATUS), f"IRQ_STATUS read, {what}")
            await bounded(b.write_reg(regs.IRQ_STATUS, st), f"IRQ_STATUS write, {what}")
            seen |= st
        status = await bounded(b.read_reg(regs.STATUS), f"STATUS read, {what}")
        bank = regs.STATUS.field("last_bank").get(status)
        assert regs.STATUS.field("bank_ready").get(status) >> bank & 1, f"{what}: STATUS {status:#x}, bank not ready"
        info_reg = regs.BANK0_INFO if bank == 0 else regs.BANK1_INFO
        info = await bounded(b.read_reg(info_reg), f"{info_reg.name} read, {what}")
        feats, record = await bounded(b.read_bank(bank), f"bank {bank} read, {what}", 200_000)
        info_got = (info_reg.field("frame").get(info), info_reg.field("count").get(info))
        assert info_got == (record.frame, record.count), f"{what}: {info_reg.name} (frame, count) {info_got}, {record}"
        await bounded(b.release(bank), f"BANK_RELEASE write, {what}")
        return bank, feats, record, seen

    async def published_as(what: str, frame: int, bank: int, exp, error: bool) -> None:
        got_bank, feats, record, seen = await next_published(what)
        assert (record.frame, got_bank) == (frame, bank), (
            f"{what}: published as frame {record.frame} in bank {got_bank}, expected frame {frame} in bank {bank}"
        )
        assert (record.dropped, record.truncated) == (0, 0), f"{what}: {record}"
        got_error = bool(regs.IRQ_STATUS.field("error").get(seen))
        assert got_error == error, f"{what}: IRQ_STATUS.error seen {got_error}, expected {error} (one per bad frame)"
        check_frame(feats, exp, what)

    # frame A: a normal frame before the events (frame 0, bank 0; the next frame goes to bank 1)
    await b.send(frame_a)
    await published_as("frame A", 0, 0, exp_a, error=False)
    want["FRAME_COUNT"] = 1
    await check_counters("after frame A")
    await check_status("after frame A", last_bank=0)

    # (a) the cable is unplugged: frame B stops in mid-line after about half its lines
    before = len(log.taken_in)
    task = cocotb.start_soon(b.send(frame_b, Gaps()))
    await ClockCycles(dut.aclk, w * (h // 2) + w // 3)
    task.cancel()
    b.video.idle()
    gap_start = log.clock
    await ClockCycles(dut.aclk, 8)
    cut = len(log.taken_in) - before
    assert w * h // 4 < cut < w * h and cut % w != 0, f"frame B was cut after {cut} pixels, not in mid-line near half"
    assert len(log.taken_out) == len(log.taken_in), (
        f"m_axis_video: {len(log.taken_out)} beats out for {len(log.taken_in)} taken in: the overlay holds pixels"
    )
    # the CPU keeps working while the source is silent; nothing is published. IDLE_TIMEOUT_g clocks
    # after B's last pixel the checker pads the rest of B (one pixel per clock) and closes it bad: the
    # error interrupt, PROTO_ERRORS + 1, and B's end-of-frame beat leaves the detector (FRAME_COUNT)
    timeout = env_int("ORB_IDLE_TIMEOUT")
    closed = gap_start + timeout + (w * h - cut)  # about when B's last padding pixel leaves the checker
    assert closed + 1000 < gap_start + GAP_CLOCKS // 2, "the silence is too short for the timeout and the padding"
    mem = [regs.MEM_BASE + off for off in (0, 4, 36, b.depth * 64, b.depth * 64 + 40, 2 * b.depth * 64 - 4)]
    thresholds = (40, 7, 255, t2)  # t2 stays: the next frame (C) is detected with it
    for k, thr in enumerate(thresholds):
        await ClockCycles(dut.aclk, GAP_CLOCKS // len(thresholds))
        when = f"{(k + 1) * GAP_CLOCKS // len(thresholds)} clocks into the silence"
        assert await bounded(b.read_reg(regs.ID), f"ID read {when}") == regs.ORB_ID, f"ID {when}"
        await check_status(when, last_bank=0)
        irq_status = await bounded(b.read_reg(regs.IRQ_STATUS), f"IRQ_STATUS read {when}")
        want_irq = error_bit if k == 1 else 0  # B closed between the first and the second look
        assert irq_status == want_irq, f"{when}: IRQ_STATUS = {irq_status:#x}, expected {want_irq:#x}"
        if irq_status:
            await bounded(b.write_reg(regs.IRQ_STATUS, irq_status), f"IRQ_STATUS write {when}")
        await bounded(b.write_reg(regs.THRESHOLD, thr), f"THRESHOLD write {when}")
        got = await bounded(b.read_reg(regs.THRESHOLD), f"THRESHOLD read-back {when}")
        assert got == thr, f"{when}: THRESHOLD wrote {thr}, read back {got}"
        if k == 0:
            await check_counters(when)  # B is still open, or being padded: no fault is known yet
        elif k == 2:
            want["PROTO_ERRORS"] += 1  # B, bad; its end-of-frame beat has left the detector by now
            want["FRAME_COUNT"] += 1
        if k >= 2:
            await check_counters(when)
        for addr in mem:
            resp, _ = await bounded(b.read(addr), f"feature-memory read at {addr:#x} {when}")
            assert resp == OKAY, f"{when}: feature-memory read at {addr:#x} answered {resp}"
        if k == 0:
            # bank 0 is not written while frame B goes to bank 1 (w changes only on publishing)
            feats, record = await bounded(b.read_bank(0), f"bank 0 read {when}", 200_000)
            assert record.frame == 0, f"{when}: bank 0 holds frame {record.frame}, not frame A (0)"
            check_frame(feats, exp_a, f"bank 0 read back {when}")
    rises = [c - gap_start for c in log.irq_rises if c >= gap_start]
    assert len(rises) == 1, f"irq rose {len(rises)} times in the silence ({rises} clocks after the cut), not once"
    assert 0 <= rises[0] - (closed - gap_start) <= 16, (
        f"irq rose {rises[0]} clocks after the cut; the timeout ({timeout}) and the padding ({w * h - cut}) give "
        f"{closed - gap_start}"
    )
    assert dut.irq.value == 0, "irq high at the end of the silence"

    # (b) the cable is back: frame C finds no frame open: frame 2 (B's number 1 used up), in bank 1
    # (the bank B was using stays free), no error: only the cut frame was lost
    await b.send(frame_c)
    await published_as("frame C (the cable back)", 2, 1, exp_c, error=False)
    want["FRAME_COUNT"] += 1
    await check_counters("after frame C")
    await check_status("after frame C", last_bank=1)

    # (c) a resolution change: D (shorter lines) and E (longer lines) back to back. D: tlast at
    # x = ws - 1 < W - 1 on line 0 (short line): that pixel is forwarded, the frame padded and
    # aborted (frame 3, never published), the rest of D (ws * (hs - 1) pixels) discarded. The padding
    # (W * H - ws clocks) outlasts the rest of D with its blanking, so E's start of frame arrives
    # while D is padded: it is discarded with all of E (no frame, no error).
    blank = BLANKING.h_blank
    assert (hs - 1) * (ws + blank) + blank + BLANKING.v_blank < w * h - ws, "E must start while D is padded"
    rises = len(log.irq_rises)
    await b.send(frame_d)
    await b.send(frame_e)
    await ClockCycles(dut.aclk, SETTLE_CLOCKS)
    want["FRAME_COUNT"] += 1
    want["PROTO_ERRORS"] += 1
    want["DISCARDED"] += ws * (hs - 1) + wl * hl
    await check_counters("after frames D and E (other formats)")
    await check_status("after frames D and E", last_bank=1)
    irq_status = await bounded(b.read_reg(regs.IRQ_STATUS), "IRQ_STATUS read after D and E")
    assert irq_status == error_bit, f"after frames D and E: IRQ_STATUS = {irq_status:#x}, expected the error bit only"
    assert len(log.irq_rises) == rises + 1, f"irq rose {len(log.irq_rises) - rises} times for D and E (D: once)"
    await bounded(b.write_reg(regs.IRQ_STATUS, irq_status), "IRQ_STATUS write after D and E")
    # G: W pixels per line but hl > H lines: lines 0..H-1 make a complete, good frame (frame 4,
    # bank 0); the extra lines are discarded (too many lines); then F, the right format (frame 5)
    await b.send(frame_g)
    await published_as("frame G (more lines)", 4, 0, exp_g, error=False)
    want["FRAME_COUNT"] += 1
    want["DISCARDED"] += (hl - h) * w
    await b.send(frame_f)
    await published_as("frame F (the right format again)", 5, 1, exp_f, error=False)
    want["FRAME_COUNT"] += 1
    await check_counters("after frame F")
    await check_status("after frame F", last_bank=1)

    # the overlay output: every beat taken on s_axis_video left m_axis_video, in order, with its
    # tuser and tlast, unchanged or a marker colour (what the overlay shows after a cut or
    # wrong-sized frame is not part of spec 13; docs/spec.md 13.3)
    await ClockCycles(dut.aclk, 8)
    ins, outs = log.taken_in, log.taken_out
    markers = {int(b.pack(np.array([[c]], dtype=np.uint8))[0, 0]) for c in SCALE_COLOURS[: b.scales]}
    for i, (beat_in, beat_out) in enumerate(zip(ins, outs, strict=False)):
        if beat_in[1:] != beat_out[1:] or (beat_out[0] != beat_in[0] and beat_out[0] not in markers):
            raise AssertionError(
                f"m_axis_video beat {i} ({place(ins, i)}): (tdata, tuser, tlast) out {beat_out}, in {beat_in}"
            )
    assert len(outs) == len(ins), f"m_axis_video: {len(outs)} beats out for {len(ins)} taken in"
    shapes = [(len(f), len(f[0]), len(f[-1])) for f in split_frames(outs)]
    sent = [frame_a, None, frame_c, frame_d, frame_e, frame_g, frame_f]
    assert len(shapes) == len(sent), f"m_axis_video: {len(shapes)} frames (by tuser), {len(sent)} sent: {shapes}"
    for k, (rgb, shape) in enumerate(zip(sent, shapes, strict=True)):
        if rgb is not None:
            full = (rgb.shape[0], rgb.shape[1], rgb.shape[1])
            assert shape == full, f"m_axis_video frame {k}: (lines, first, last line length) {shape}, sent {full}"
    # F shows G's features exactly: the banks were cleared by the complete frames E and G
    got_f = b.unpack_out(np.array(split_frames(outs)[-1], dtype=np.int64))
    bad = np.argwhere(np.any(got_f != render_marker_overlay(frame_f, exp_g, scales=b.scales), axis=-1))
    first = tuple(int(v) for v in bad[0]) if len(bad) else None
    assert first is None, f"overlay of frame F (G's features): first differing pixel (y, x) = {first}"


def test_accel_zynq() -> None:
    """The wrapper with its own IDLE_TIMEOUT_g default (read from the VHDL for the test)."""
    vhdl = (Path(__file__).resolve().parents[2] / "hdl" / "top" / "orb_accel_zynq.vhd").read_text()
    timeout = re.search(r"IDLE_TIMEOUT_g\s*:\s*integer\s*:=\s*(\d+)", vhdl)
    assert timeout, "orb_accel_zynq has no IDLE_TIMEOUT_g default"
    generics = {"WIDTH_g": 128, "HEIGHT_g": 96, "SCALES_g": 2, "SECTORS_g": 32, "MEM_DEPTH_g": 256, "INPUT_g": "RBG"}
    run("orb_accel_zynq", "test_orb_accel_zynq", generics, env={**SIM_ENV, "ORB_IDLE_TIMEOUT": timeout[1]})


def test_accel_zynq_ddr() -> None:
    """The wrapper's DDR build (MEM_KIND_g "DDR", its m_axi_feat on cocotbext-axi's AXI4 RAM with
    stalls on AW, W and B): `wrapper`, the frames read by the driver from the memory, the ring laid
    out again after aresetn. A small frame: the wrapper's frame path is the same as the BRAM build's."""
    generics = {"WIDTH_g": 96, "HEIGHT_g": 64, "SCALES_g": 1, "SECTORS_g": 32, "MEM_DEPTH_g": 128, "INPUT_g": "RBG",
                "MEM_KIND_g": "DDR"}  # fmt: skip
    run("orb_accel_zynq", "test_orb_accel_zynq", generics, env=SIM_ENV, testcase=["wrapper"])
