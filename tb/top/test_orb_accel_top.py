# SPDX-License-Identifier: MIT
"""orb_accel_top end to end: colour video in, a CPU model on AXI4-Lite reading the feature memory
bank by bank, the overlay video out; everything compared with the golden model.

- photo_stream: consecutive colour photographs (blanking between frames) while the CPU reads
  frame k from one bank as frame k+1 is written into the other, with random pauses on all five
  AXI4-Lite channels; every published frame bit-exact (features, scores, sectors, descriptors),
  frame numbers consecutive, the end-of-frame record consistent; the overlay output of frame k+1
  equals golden_model.overlay.render_marker_overlay(frame k+1, features of frame k).
- faults: short line, long line, too few lines, missing start of frame, start of frame in mid-line,
  too many lines, a soft reset and rst in mid-frame, each followed by a good frame: faulty frames
  are never published, counted in PROTO_ERRORS / DISCARDED and raise the error interrupt; every
  good frame is bit-exact.
- overflow_overrun (small MEM_DEPTH): a frame with more features than a bank holds is truncated
  to the first DEPTH - 1 in arrival order, flagged in its record and counted; frames arriving
  while the CPU holds both banks are skipped (OVERRUN) and the frame numbers show the gap.
- registers: identification, configuration read-back, SLVERR on an unknown address, fast mode
  through CTRL.mode, the threshold applied from the next frame, disabled frames ignored.
- config_readback: the first part of `registers` alone (no frame), for the large configurations.
- soft_reset_holds_video: CTRL.soft_reset while the sink stalls m_axis_video with a beat waiting:
  the beat stays, unchanged, until taken (AXI4-Stream; the violation the formal check found,
  docs/formal.md), and the next frame is bit-exact.
- ddr_ring (a DDR build, MEM_KIND_g "DDR": the features go through m_axi_feat into cocotbext-axi's
  AXI4 RAM, an emulated reserved region, with random stalls on AW, W and B; docs/feature-dma.md):
  CFG_DDR; a ring of 2 buffers opened by the driver, three frames (all selection) read by the
  driver from the memory, bit-exact, in buffers 0, 1, 0 with consecutive numbers; DMA_BEATS 8 per
  slot written (record and features), DMA_DROPPED and DMA_BUS_ERRORS 0, RING_INFO the last frame's
  header, nothing written outside the ring (the rest of the region stays zero). Then a ring the
  driver places beyond the region (inside the fabric's window): every burst is answered SLVERR, the
  frame is dropped (DMA_DROPPED 1, DMA_BUS_ERRORS one per slot, the error interrupt, no buffer
  READY), and after the ring is laid in the region again the next frame is published, bit-exact.
  photo_stream, the tests of the driver's frame path, also run on the DDR build (read from memory).
"""

from __future__ import annotations

import os
import warnings

import cocotb
import numpy as np
import pytest
from cocotb.triggers import ClockCycles, RisingEdge

from golden_model import regs
from golden_model.config import RECOMMENDED_THRESHOLD_LO, named, recommended_budget, tops_default
from golden_model.features import Features
from golden_model.luma import rgb_to_luma
from golden_model.overlay import render_marker_overlay
from orb_accel.bus import BusError
from orb_accel.ddr import ArrayMemory
from orb_sim.accel_bench import OKAY, SLVERR, AccelBench
from orb_sim.video import Gaps
from orbtb.images import colour_photo
from orbtb.runner import run
from orbtb.scoreboard import check_frame, expected_features, expected_streamed
from orbtb.unit import SIM_ENV

warnings.filterwarnings("ignore", category=DeprecationWarning)

PHOTOS = ("astronaut", "coffee", "chelsea", "rocket")
UNMAPPED = 0x3C  # an offset below MEM_BASE that names no register (0x5C is RING_STRIDE since map 3.2)


def expected(b: AccelBench, rgb: np.ndarray, threshold: int, mode: str = "orb") -> Features:
    """The model's features of a frame in the selection last configured (b.selection)."""
    return expected_features(rgb_to_luma(rgb), b.scales, threshold, mode, b.sectors, b.step, b.selection)


def grid_budget(b: AccelBench, frames: list[np.ndarray], threshold: int) -> int:
    """A grid budget that bites: below the features of every frame in `all` selection, within a bank."""
    counts = [len(expected_features(rgb_to_luma(f), b.scales, threshold, "orb", b.sectors, b.step)) for f in frames]
    return max(1, min(b.depth - 1, min(counts) * 2 // 3))


@cocotb.test()
async def photo_stream(dut) -> None:
    b = AccelBench(dut)
    await b.start(pause_prob=0.3, seed=3)
    t = 20
    # ORB_PHOTOS: the stream's photographs; a configuration with many features per pixel streams sparser
    # ones, since the CPU must read a frame within the next frame for every frame to be published
    photos = os.environ.get("ORB_PHOTOS", ",".join(PHOTOS)).split(",")
    # ORB_FRAMES: how many (at least 2: the overlay of frame k shows frame k - 1's features)
    n_frames = int(os.environ.get("ORB_FRAMES", "4"))
    assert n_frames >= 2, f"ORB_FRAMES={n_frames}: the photo stream needs 2 frames or more"
    frames = [colour_photo(photos[i % len(photos)], b.width, b.height) for i in range(n_frames)]
    # the grid selection (the driver's default) with a budget below every frame's feature count
    await b.configure(threshold=t, selection="grid", budget=grid_budget(b, frames, t))
    budget = b.accel.selection.budget
    b.start_capture()

    async def video() -> None:
        for f in frames:
            await b.send(f)

    cocotb.start_soon(video())
    prev: Features | None = None
    for k, f in enumerate(frames):
        feats, record = await b.read_newest()
        exp = expected(b, f, t)
        check_frame(feats, exp, f"frame {k} ({b.selection})")
        assert 0 < len(exp) <= budget, f"frame {k}: {len(exp)} features for a budget of {budget}"
        assert (record.frame, record.dropped, record.truncated, record.truncated_flag) == (k, 0, 0, False), record
        # the parameters the frame was processed with, as the registers held them at its start
        assert record.params == b.accel.written(), f"frame {k}: {record.params} != {b.accel.written()}"
        if k > 0:
            # video frame k showed the features of frame k - 1 (its end-of-frame beat came in blanking)
            while len(b.captured) < k + 1:
                await RisingEdge(dut.clk)
            want = render_marker_overlay(b.shown(f), prev, scales=b.scales, block_log2=b.block_log2)
            got = b.captured[k]
            bad = np.argwhere(np.any(got != want, axis=-1))
            assert len(bad) == 0, f"overlay of frame {k}: first differing pixel (y, x) = {tuple(bad[0])}"
        # the overlay marks what the stream carried: in grid selection also the features a later
        # candidate replaced in the bank (docs/overlay.md)
        prev = expected_streamed(rgb_to_luma(f), b.scales, t, "orb", b.sectors, b.step, b.selection)
    assert not np.any(b.captured[0] != b.shown(frames[0])), "frame 0 has no earlier features: it must pass unchanged"
    counters = ((regs.FRAME_COUNT, len(frames)), (regs.DROPPED, 0), (regs.PROTO_ERRORS, 0), (regs.OVERRUN, 0),
                (regs.OVERFLOW_COUNT, 0), (regs.DESC_LOST, 0), (regs.DISCARDED, 0))  # fmt: skip
    if b.ddr:  # the DDR ring: nothing dropped, no error response, nothing written outside the region
        counters += ((regs.DMA_DROPPED, 0), (regs.DMA_BUS_ERRORS, 0))
        assert b.ram is not None and b.ram.outside_writes == 0
    for reg, value in counters:
        got = await b.read_reg(reg)
        assert got == value, f"{reg.name} = {got}, expected {value}"


@cocotb.test()
async def ddr_ring(dut) -> None:
    b = AccelBench(dut)
    assert b.ddr, "ddr_ring runs on a DDR build (MEM_KIND_g DDR)"
    await b.start(pause_prob=0.2, seed=7, ddr_pause=0.4)
    ram = b.ram
    assert ram is not None
    ddr = await b.read_reg(regs.CFG_DDR)
    assert regs.CFG_DDR.field("ddr").get(ddr) == 1, f"CFG_DDR = {ddr:#x}"
    await b.open_ring(2)
    ring = b.accel.ring
    assert ring is not None and (ring.base, ring.count, ring.depth) == (ram.base, 2, b.depth), ring
    t = 20
    await b.configure(threshold=t, irq=3, selection="all")
    w, h = b.width, b.height
    frames = [colour_photo(p, w, h) for p in ("coffee", "chelsea", "astronaut")]
    exps = [expected(b, f, t) for f in frames]
    assert all(0 < len(e) < b.depth - 1 for e in exps), [len(e) for e in exps]
    beats0 = await b.read_reg(regs.DMA_BEATS)

    async def video() -> None:
        for f in frames:
            await b.send(f)

    cocotb.start_soon(video())
    timeout = b.clocks_to_s(b.frame_timeout_clocks)
    for k, exp in enumerate(exps):
        frame = await b.cpu(b.accel.next_frame, timeout)
        check_frame(frame.features, exp, f"DDR frame {k}")
        assert (frame.bank, frame.number, frame.record.truncated) == (k % 2, k, 0), (frame.bank, frame.record)
    beats = await b.read_reg(regs.DMA_BEATS) - beats0
    assert beats == 8 * sum(len(e) + 1 for e in exps), f"DMA_BEATS + {beats}: not 8 per slot"
    for reg in (regs.DMA_DROPPED, regs.DMA_BUS_ERRORS, regs.OVERRUN):
        assert await b.read_reg(reg) == 0, f"{reg.name} after three frames"
    info = await b.read_reg(regs.RING_INFO)
    assert (regs.RING_INFO.field("count").get(info), regs.RING_INFO.field("frame").get(info)) == (len(exps[2]), 2)
    status = await b.read_reg(regs.RING_STATUS)
    assert regs.RING_STATUS.field("ready").get(status) == 0, f"RING_STATUS = {status:#x}: a buffer not released"
    mem = np.frombuffer(ram.bytes, dtype=np.uint8)
    assert ram.outside_writes == 0 and not np.any(mem[ring.extent :]), "bytes written outside the ring of 2 buffers"

    # a ring beyond the emulated region (inside the fabric's window): SLVERR to every burst
    beyond = ArrayMemory(ring.extent, ram.base + ram.size)
    await b.cpu(b.accel.open_ring, beyond, 2)
    await b.write_reg(regs.IRQ_STATUS, 0xFFFFFFFF)
    await b.send(frames[1])
    for _ in range(100):  # the frame is dropped at its record's (error) response
        if await b.read_reg(regs.DMA_DROPPED):
            break
        await ClockCycles(dut.clk, 200)
    want = len(exps[1]) + 1  # one burst a slot: the features and the record
    assert await b.read_reg(regs.DMA_DROPPED) == 1
    assert await b.read_reg(regs.DMA_BUS_ERRORS) == want
    assert ram.outside_writes == 64 * want, f"{ram.outside_writes} bytes outside, expected {64 * want}"
    irq = await b.read_reg(regs.IRQ_STATUS)
    assert regs.IRQ_STATUS.field("error").get(irq) == 1 and regs.IRQ_STATUS.field("frame_done").get(irq) == 0, (
        f"IRQ_STATUS = {irq:#x}"
    )
    assert regs.RING_STATUS.field("ready").get(await b.read_reg(regs.RING_STATUS)) == 0
    # back in the region: the next frame is published (frame 0 after the driver's soft reset)
    await b.open_ring(2)
    await b.write_reg(regs.IRQ_STATUS, 0xFFFFFFFF)
    await b.send(frames[2])
    frame = await b.cpu(b.accel.next_frame, timeout)
    check_frame(frame.features, exps[2], "DDR frame after the ring came back")
    assert (frame.bank, frame.number) == (0, 0), (frame.bank, frame.record)


@cocotb.test()
async def faults(dut) -> None:
    b = AccelBench(dut)
    await b.start(pause_prob=0.2, seed=5)
    t = 20
    await b.configure(threshold=t, irq=3)
    w, h = b.width, b.height
    good = [colour_photo(p, w, h) for p in PHOTOS]
    gaps = Gaps("blanking")
    published: list[tuple[int, Features]] = []
    errors: list[int] = []  # IRQ_STATUS.error at each interrupt

    async def cpu(count: int) -> None:
        while len(published) < count:
            await b.wait_irq(40 * w * h)
            st = await b.read_reg(regs.IRQ_STATUS)
            await b.write_reg(regs.IRQ_STATUS, st)
            errors.append(regs.IRQ_STATUS.field("error").get(st))
            if regs.IRQ_STATUS.field("frame_done").get(st):
                status = await b.read_reg(regs.STATUS)
                bank = regs.STATUS.field("last_bank").get(status)
                feats, record = await b.read_bank(bank)
                await b.release(bank)
                published.append((record.frame, feats))

    async def send_words(words: list[tuple[int, int, int]]) -> None:
        """Raw beats (tdata, tuser, tlast), one per clock."""
        src = b.video
        for data, user, last in words:
            src.tdata.value, src.tuser.value, src.tlast.value, src.tvalid.value = data, user, last, 1
            await RisingEdge(dut.clk)
            while not src.tready.value:
                await RisingEdge(dut.clk)
        src.idle()
        await ClockCycles(dut.clk, 64)

    def beats(rgb: np.ndarray, lines: int, line_len: dict[int, int] | None = None, sof: bool = True):
        packed = b.pack(rgb)
        out = []
        for y in range(lines):
            n = (line_len or {}).get(y, w)
            for x in range(n):
                out.append((int(packed[y % h, x % w]), int(sof and x == 0 and y == 0), int(x == n - 1)))
        return out

    cpu_task = cocotb.start_soon(cpu(7))
    expected_frames: list[tuple[int, np.ndarray]] = []
    await b.send(good[0], gaps)  # detector frame 0
    expected_frames.append((0, good[0]))
    await send_words(beats(good[1], h, {5: w - 3}))  # short line: frame 1 padded, not published
    await b.send(good[1], gaps)  # frame 2
    expected_frames.append((2, good[1]))
    await send_words(beats(good[2], h, {7: w + 4}))  # long line: frame 3 bad
    await b.send(good[2], gaps)  # frame 4
    expected_frames.append((4, good[2]))
    await send_words(beats(good[3], h // 2))  # too few lines: frame 5 bad when the next tuser comes
    await b.send(good[3], gaps)  # frame 6
    expected_frames.append((6, good[3]))
    await send_words(beats(good[0], 3, sof=False))  # missing start of frame: discarded
    await b.send(good[0], gaps)  # frame 7
    expected_frames.append((7, good[0]))
    # early start of frame: 3 lines and half a line, then the next frame's tuser in mid-line
    await send_words(beats(good[1], 3) + [(int(b.pack(good[1])[3, x]), 0, 0) for x in range(w // 2)])  # frame 8
    await b.send(good[1], gaps)  # frame 9
    expected_frames.append((9, good[1]))
    await send_words(beats(good[2], h + 2))  # too many lines: frame 10 is good, 2 lines discarded
    expected_frames.append((10, good[2]))
    await cpu_task
    assert [n for n, _ in published] == [n for n, _ in expected_frames], f"published frames {published}"
    for (n, feats), (_, rgb) in zip(published, expected_frames, strict=True):
        check_frame(feats, expected(b, rgb, t), f"frame {n}")
    assert await b.read_reg(regs.PROTO_ERRORS) == 4
    assert sum(errors) == 4, f"error interrupts seen: {sum(errors)}, expected one per bad frame (4)"
    # discarded: the rest of the short-line frame after line 5, the 4 excess pixels of the long
    # line and the lines after it, the 3 lines without a start of frame, the 2 extra lines
    assert await b.read_reg(regs.DISCARDED) == (h - 6) * w + 4 + (h - 8) * w + 3 * w + 2 * w
    assert await b.read_reg(regs.FRAME_COUNT) == 11
    # soft reset in mid-frame: the rest of that frame is discarded, counters restart, the next
    # frame is frame 0 again and bit-exact
    task = cocotb.start_soon(b.send(good[1], Gaps()))
    await ClockCycles(dut.clk, w * (h // 2))
    ctrl = await b.read_reg(regs.CTRL)
    await b.write_reg(regs.CTRL, regs.CTRL.field("soft_reset").put(1, ctrl))
    await task
    assert await b.read_reg(regs.FRAME_COUNT) == 0
    assert await b.read_reg(regs.DISCARDED) > 0
    await b.send(good[2], gaps)
    feats, record = await b.read_newest()
    assert record.frame == 0, record
    check_frame(feats, expected(b, good[2], t), "frame after the soft reset")
    # rst in mid-frame: everything restarts (registers too), the next frame is frame 0 and exact
    task = cocotb.start_soon(b.send(good[3], Gaps()))
    await ClockCycles(dut.clk, w * (h // 3))
    dut.rst.value = 1
    await ClockCycles(dut.clk, 3)
    dut.rst.value = 0
    await task
    assert await b.read_reg(regs.DISCARDED) > 0, "the rest of the frame cut by rst was not counted"
    await b.configure(threshold=t)
    await b.send(good[0], gaps)
    feats, record = await b.read_newest()
    assert record.frame == 0, record
    check_frame(feats, expected(b, good[0], t), "frame after rst")


@cocotb.test()
async def overflow_overrun(dut) -> None:
    b = AccelBench(dut)
    await b.start(pause_prob=0.0)
    t = 10
    await b.configure(threshold=t)
    w, h = b.width, b.height
    img = colour_photo("astronaut", w, h)
    exp = expected(b, img, t)
    cap = b.depth - 1
    assert len(exp) > cap, f"the test photo has {len(exp)} features, not more than {cap}"
    # frames 0 and 1 fill both banks; the CPU holds them, so frame 2 is skipped
    for _ in range(3):
        await b.send(img)
    await ClockCycles(dut.clk, 200)
    assert await b.read_reg(regs.OVERRUN) == 1
    status = await b.read_reg(regs.STATUS)
    assert regs.STATUS.field("bank_ready").get(status) == 3 and regs.STATUS.field("overflow").get(status) == 1
    for bank in (0, 1):
        feats, record = await b.read_bank(bank)
        got = (record.frame, record.count, record.truncated, record.truncated_flag)
        assert got == (bank, cap, len(exp) - cap, True), f"bank {bank}: record {record}"
        if b.scales == 1:  # one scale: arrival order is the canonical order
            check_frame(feats, exp.take(np.arange(cap)), f"truncated frame {bank}")
    assert await b.read_reg(regs.OVERFLOW_COUNT) == 2 * (len(exp) - cap)
    await b.release(0)
    await b.send(img)
    await ClockCycles(dut.clk, 200)
    feats, record = await b.read_bank(0)
    assert record.frame == 3, f"the frame after the skipped one is frame 3, got {record.frame}"


async def check_config_registers(b: AccelBench) -> None:
    """ID and the CFG_* registers against the generics the top was built with; SLVERR on an unknown
    register and on a write to a read-only one."""
    assert await b.read_reg(regs.ID) == regs.ORB_ID
    size = await b.read_reg(regs.CFG_SIZE)
    assert (regs.CFG_SIZE.field("width").get(size), regs.CFG_SIZE.field("height").get(size)) == (b.width, b.height)
    orb = await b.read_reg(regs.CFG_ORB)
    assert (regs.CFG_ORB.field("scales").get(orb), regs.CFG_ORB.field("sectors").get(orb)) == (b.scales, b.sectors)
    step = (regs.CFG_ORB.field("step_num").get(orb), regs.CFG_ORB.field("step_den").get(orb))
    assert step == b.step, f"pyramid step read back {step}, built with {b.step}"
    assert regs.CFG_MEM.field("depth").get(await b.read_reg(regs.CFG_MEM)) == b.depth
    assert regs.CFG_DDR.field("ddr").get(await b.read_reg(regs.CFG_DDR)) == int(b.ddr)
    resp, _ = await b.read(UNMAPPED)
    assert resp == SLVERR, "an unknown register must answer SLVERR"
    assert await b.write(regs.ID.offset, 0) == SLVERR


@cocotb.test()
async def soft_reset_holds_video(dut) -> None:
    """CTRL.soft_reset while m_axis_video holds a beat the sink does not take: the old top reset the
    overlay at once and withdrew the beat (tvalid fell without a handshake); now the beat stays on
    m_axis_video, unchanged, until taken, and the overlay is reset then. The next frame is frame 0 and
    bit-exact. A monitor checks the AXI4-Stream hold rule on m_axis_video in every clock of the test."""
    b = AccelBench(dut)
    await b.start()
    errors: list[str] = []

    async def hold_rule() -> None:
        held = None
        while True:
            await RisingEdge(dut.clk)
            valid = dut.m_axis_video_tvalid.value == 1
            beat = None
            if valid:
                beat = tuple(int(getattr(dut, f"m_axis_video_{n}").value) for n in ("tdata", "tuser", "tlast"))
            if held is not None and beat != held and len(errors) < 5:
                errors.append(f"m_axis_video beat {held} not taken, then {beat}")
            held = beat if valid and dut.m_axis_video_tready.value == 0 and dut.rst.value == 0 else None

    cocotb.start_soon(hold_rule())
    t = 20
    await b.configure(threshold=t)
    img = colour_photo("coffee", b.width, b.height)
    task = cocotb.start_soon(b.send(img, Gaps()))
    await ClockCycles(dut.clk, b.width * 3)
    while dut.m_axis_video_tvalid.value != 1:
        await RisingEdge(dut.clk)
    dut.m_axis_video_tready.value = 0  # from the next edge on the beat waits
    await ClockCycles(dut.clk, 2)
    waiting = int(dut.m_axis_video_tdata.value)
    ctrl = await b.read_reg(regs.CTRL)
    await b.write_reg(regs.CTRL, regs.CTRL.field("soft_reset").put(1, ctrl))
    await ClockCycles(dut.clk, 8)
    assert dut.m_axis_video_tvalid.value == 1, "the waiting m_axis_video beat was withdrawn by the soft reset"
    assert int(dut.m_axis_video_tdata.value) == waiting, "the waiting m_axis_video beat changed"
    dut.m_axis_video_tready.value = 1
    await task
    assert not errors, "; ".join(errors)
    assert await b.read_reg(regs.FRAME_COUNT) == 0
    await b.send(img, Gaps("blanking"))
    feats, record = await b.read_newest()
    assert record.frame == 0, record
    check_frame(feats, expected(b, img, t), "frame after the soft reset")
    assert not errors, "; ".join(errors)


@cocotb.test()
async def config_readback(dut) -> None:
    """The configuration registers alone (no frame): for the large configurations, whose frames the
    photo stream already checks."""
    b = AccelBench(dut)
    await b.start(pause_prob=0.5, seed=9)
    await check_config_registers(b)


@cocotb.test()
async def registers(dut) -> None:
    b = AccelBench(dut)
    await b.start(pause_prob=0.5, seed=9)
    await check_config_registers(b)
    img = colour_photo("coffee", b.width, b.height)
    # fast mode at threshold 30, then orb mode at 15: each frame uses the values set before it
    await b.configure(threshold=30, mode="fast")
    await b.send(img)
    assert b.accel.mode == "fast"
    feats, _ = await b.read_newest()
    check_frame(feats, expected(b, img, 30, "fast"), "fast-mode frame")
    await b.configure(threshold=15, mode="orb")
    await b.send(img)
    feats, _ = await b.read_newest()
    check_frame(feats, expected(b, img, 15), "orb-mode frame")
    # disabled: frames are taken and ignored (no interrupt), enabled again: processed
    await b.configure(threshold=15, enable=0)
    await b.send(img)
    await ClockCycles(dut.clk, 500)
    assert dut.irq.value == 0, "a disabled accelerator published a frame"
    await b.configure(threshold=15)
    await b.send(img)
    feats, _ = await b.read_newest()
    check_frame(feats, expected(b, img, 15), "frame after re-enabling")
    assert await b.write(regs.MEM_BASE - 4, 0) == SLVERR
    assert (await b.read(regs.MEM_BASE))[0] == OKAY


@cocotb.test()
async def driver_errors(dut) -> None:
    """The shipped driver's error behaviour against the RTL: bad arguments raise ValueError naming
    the range before anything is written; an error response raises BusError; a frame that never
    comes raises TimeoutError with the status registers; a bank held in a `with` block is released
    even when the block raises."""
    b = AccelBench(dut)
    await b.start()
    accel = b.accel
    await b.cpu(accel.configure, 20)  # the driver's defaults: grid selection, the recommended budget
    cap = b.depth - 1
    assert accel.selection.mode == "grid" and accel.selection.budget == min(cap, recommended_budget(b.width, b.height))
    for bad, words in (({"threshold": 300}, "0..255"), ({"threshold": -1}, "0..255"), ({"mode": "brief"}, "mode"),
                       ({"irq": ("vsync",)}, "interrupt"), ({"budget": cap + 1}, f"a bank holds {cap}"),
                       ({"cells": (0, 6)}, "cell columns 0 outside 1..15"), ({"threshold_lo": 256}, "threshold_lo"),
                       ({"selection": "best"}, "selection")):  # fmt: skip
        try:
            await b.cpu(accel.configure, **{"threshold": 20, **bad})
        except ValueError as exc:
            assert words in str(exc), f"{bad}: message {exc!s} does not name {words}"
        else:
            raise AssertionError(f"configure({bad}) did not raise ValueError")
    assert await b.read_reg(regs.THRESHOLD) == regs.THRESHOLD.field("low").put(RECOMMENDED_THRESHOLD_LO, 20), (
        "a refused configure wrote"
    )
    select = await b.read_reg(regs.SELECT)
    assert regs.SELECT.field("budget").get(select) == accel.selection.budget, "a refused configure wrote SELECT"
    for op, args in ((b.bus.read32, (UNMAPPED,)), (b.bus.write32, (regs.ID.offset, 0)),
                     (b.bus.write32, (regs.CTRL.offset, regs.CTRL.field("mode").put(3))),
                     (b.bus.write32, (regs.BANK_RELEASE.offset, 2)), (accel.release, (5,)),
                     (b.bus.write32, (regs.SELECT.offset, regs.SELECT.field("budget").put(cap + 1, 0x6801))),
                     (b.bus.write32, (regs.SELECT.offset, regs.SELECT.field("mode").put(2, 0x6800))),
                     (b.bus.write32, (regs.SELECT.offset, regs.SELECT.field("cols").put(0, 0x6801)))):  # fmt: skip
        try:
            await b.cpu(op, *args)
        except BusError as exc:
            assert exc.resp == SLVERR and "SLVERR" in str(exc), str(exc)
        except ValueError as exc:  # caught by the driver before the bus (bank 5)
            assert "bank" in str(exc), str(exc)
        else:
            raise AssertionError(f"{op.__name__}{args} raised nothing")
    try:
        await b.cpu(accel.next_frame, b.clocks_to_s(2000))  # no video: no frame
    except TimeoutError as exc:
        assert "STATUS" in str(exc) and "frame_count = 0" in str(exc), str(exc)
    else:
        raise AssertionError("next_frame without video did not time out")
    img = colour_photo("coffee", b.width, b.height)
    await b.send(img)

    def read_then_fail() -> None:
        with accel.frame(timeout_s=b.clocks_to_s(b.frame_timeout_clocks)) as frame:
            assert len(frame.features) > 0
            raise KeyError("the caller's code fails while it holds the bank")

    try:
        await b.cpu(read_then_fail)
    except KeyError:
        pass
    else:
        raise AssertionError("the caller's exception was swallowed")
    status = await b.read_reg(regs.STATUS)
    assert regs.STATUS.field("bank_ready").get(status) == 0, f"the bank was not released: STATUS = {status:#x}"
    # both banks free again: the next two frames are published, each the grid selection of at most
    # a bank's capacity (no frame is truncated)
    want = expected(b, img, 20)
    assert 0 < len(want) <= cap
    for k in (1, 2):
        await b.send(img)
        feats, record = await b.read_newest()
        assert (record.frame, record.truncated) == (k, 0), record
        check_frame(feats, want, f"frame {k} after the released bank")


# ------------------------------------------------------------------------------------------------
# pytest runners

CONFIGS = {
    # name: (W, H, scales, sectors, memory depth, input packing)
    "rgb_2scales": (128, 96, 2, 32, 256, "RGB"),
    "rbg_1scale_small_mem": (96, 64, 1, 16, 16, "RBG"),
    "luma_1scale": (96, 64, 1, 64, 256, "LUMA"),
    "rgb_4scales": (192, 160, 4, 32, 1024, "RGB"),
    # the finer pyramid (issue 14): 6 levels of 5:4, the overlay in 16x16 blocks
    "rgb_6levels_5to4": (192, 144, 6, 32, 1024, "RGB", {"STEP_NUM_g": 5, "STEP_DEN_g": 4, "BLOCK_LOG2_g": 4}),
}
# the DDR builds (MEM_KIND_g "DDR", docs/feature-dma.md): the features written to an emulated DDR
CONFIGS["ddr_rgb_1scale"] = (96, 64, 1, 32, 128, "RGB", {"MEM_KIND_g": "DDR"})
# the board's build at 640x480 (board-vga's generics, its 1,024 slots a buffer)
VGA = named("board-vga")
CONFIGS["ddr_board_vga"] = (VGA.width, VGA.height, VGA.scales, VGA.sectors, VGA.mem_depth, "RGB",
                            {"STEP_NUM_g": VGA.step_num, "STEP_DEN_g": VGA.step_den, "BLOCK_LOG2_g": VGA.block_log2,
                             "MEM_KIND_g": "DDR"})  # fmt: skip
# the board configurations' pyramid: 4 levels of 5:4, 16x16 overlay blocks (docs/configurations.md)
SMALL = named("test-small")
CONFIGS["rgb_4levels_5to4"] = (SMALL.width, SMALL.height, SMALL.scales, SMALL.sectors, SMALL.mem_depth, "RGB",
                               {"STEP_NUM_g": SMALL.step_num, "STEP_DEN_g": SMALL.step_den,
                                "BLOCK_LOG2_g": SMALL.block_log2})  # fmt: skip


def run_accel(config: str, testcase: list[str] | None = None, env: dict[str, str] | None = None) -> None:
    w, h, s, sectors, depth, packing, *extra = CONFIGS[config]
    generics = {"WIDTH_g": w, "HEIGHT_g": h, "SCALES_g": s, "SECTORS_g": sectors, "MEM_DEPTH_g": depth,
                "INPUT_g": packing, **(extra[0] if extra else {})}  # fmt: skip
    run("orb_accel_top", "test_orb_accel_top", generics, env={**SIM_ENV, **(env or {})}, testcase=testcase)


@pytest.mark.parametrize(
    ("config", "testcase"),
    [
        ("rgb_2scales", ["photo_stream", "registers"]),
        ("luma_1scale", ["photo_stream", "faults", "registers", "soft_reset_holds_video"]),
        # the same fault sequence through the RGB input and two levels: 3.5 minutes of simulation
        # for what luma_1scale checks in 70 s (make test-all)
        pytest.param("rgb_2scales", ["faults"], marks=pytest.mark.slow, id="rgb_2scales-faults"),
    ],
    ids=["rgb_2scales", "luma_1scale", "rgb_2scales-faults"],
)
def test_accel_stream_faults_registers(config: str, testcase: list[str]) -> None:
    run_accel(config, testcase=testcase)


@pytest.mark.slow
def test_accel_four_scales() -> None:
    # two frames: the overlay of the second shows the first's features (test_accel_all streams four).
    # make test-all: make test has 4 scales of 2:1 in orb_core's tests and a multi-level top in
    # test_accel_finer_pyramid
    run_accel("rgb_4scales", testcase=["photo_stream"], env={"ORB_FRAMES": "2"})


def test_accel_finer_pyramid() -> None:
    # The board's pyramid, 4 levels of 5:4: two frames and the configuration registers (the frames
    # of `registers` cost many minutes of simulation here; rgb_2scales runs them, and
    # test_accel_all every test in this configuration)
    run_accel("rgb_4levels_5to4", testcase=["photo_stream", "config_readback"],
              env={"ORB_PHOTOS": "coffee,rocket", "ORB_FRAMES": "2"})  # fmt: skip


@pytest.mark.slow
def test_accel_six_levels() -> None:
    # 6 levels carry 1.8x the features of one: astronaut's 866 take longer to read than a 192x144
    # frame lasts. make test-all; make test: the board's 4 levels above, 8 levels of 5:4 in
    # test_orb_core's test_finer_pyramid
    run_accel("rgb_6levels_5to4", testcase=["photo_stream", "config_readback"],
              env={"ORB_PHOTOS": "coffee,rocket", "ORB_FRAMES": "2"})  # fmt: skip


def test_accel_defaults() -> None:
    """The top built with no generics is the tops' default named configuration ("thesis-vga",
    orb_configs_pkg.TOPS_DEFAULT_c): its configuration registers read back that configuration."""
    d = tops_default()
    assert d.name == "thesis-vga"
    env = {"ORB_WIDTH": str(d.width), "ORB_HEIGHT": str(d.height), "ORB_SCALES": str(d.scales),
           "ORB_SECTORS": str(d.sectors), "ORB_STEP_NUM": str(d.step_num), "ORB_STEP_DEN": str(d.step_den),
           "ORB_MEM_DEPTH": str(d.mem_depth), "ORB_BLOCK_LOG2": str(d.block_log2)}  # fmt: skip
    run("orb_accel_top", "test_orb_accel_top", {}, env={**SIM_ENV, **env}, testcase=["config_readback"])


def test_accel_ddr() -> None:
    """The DDR build: the ring through the AXI4 RAM with stalls (ddr_ring) and the photo stream
    read by the driver from memory, two frames."""
    run_accel("ddr_rgb_1scale", testcase=["ddr_ring", "photo_stream"],
              env={"ORB_PHOTOS": "coffee,chelsea", "ORB_FRAMES": "2"})  # fmt: skip


@pytest.mark.slow
def test_accel_ddr_board_vga() -> None:
    """The board's 640x480 DDR build (board-vga's generics): two photographs through the ring,
    read by the driver from memory, bit-exact (make test-all; make sim CONFIG=board-vga runs one)."""
    run_accel("ddr_board_vga", testcase=["photo_stream"], env={"ORB_PHOTOS": "coffee,rocket", "ORB_FRAMES": "2"})


def test_accel_overflow_overrun() -> None:
    run_accel("rbg_1scale_small_mem", testcase=["overflow_overrun", "driver_errors"])


if os.environ.get("ORB_ACCEL_ALL"):  # every test in every configuration (slow)

    @pytest.mark.slow
    @pytest.mark.parametrize("config", list(CONFIGS))
    def test_accel_all(config: str) -> None:
        run_accel(config)
