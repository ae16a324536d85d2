# SPDX-License-Identifier: MIT
"""The fast path's DDR model (docs/fast-sim.md, "The DDR model"): the "DDR" build of orb_accel_top
(MEM_KIND_g, orb_feat_dma: docs/feature-dma.md) writes its frames through m_axi_feat into the
harness's memory, and the shipped driver reads them from there (OrbAccel(memory=FastMemory(sim)),
the CPU's data cache modelled: what the driver does not invalidate it reads stale). test-tiny's
size (128x96, 2 scales, 512 slots) with a burst FIFO of 32 slots (DMA_FIFO_g), one build (a minute
or two when the cache is cold).

- frames: six photographs one after the other through a slow interconnect (random AWREADY and
  WREADY, delayed write responses), the third with the interconnect stopped for a frame period (the
  burst FIFO fills: dropped, its ring position not used), the fifth with its record answered SLVERR
  (dropped, its position used); the others bit-exact in the buffers the ring rules give, the
  counters (DMA_DROPPED, DMA_BUS_ERRORS) and the harness's log reconciled with what was injected,
  no AXI rule broken, nothing written outside the ring; a reader that does not invalidate sees
  stale bytes;
- a ring outside the memory: every burst answered DECERR and not stored, the frame dropped;
- the simulation server's interconnect faults as text (orb_sim.faults: axistall, axierr, axislow)
  set on the model: the bursts they name answered with errors, the frames they hit dropped;
- an error response to a burst of a frame the checker rejects costs no later frame (an earlier
  orb_feat_dma kept the error flag of a frame without a record until its 2-bit tag came round: the
  fourth frame written after it was dropped; found by the DDR campaign);
- a 40-event DDR fault campaign (orbtb.campaign, seed 4): every DDR event, frames dropped at the
  full FIFO and at error responses, all reconciled; no lock-up, no mismatch.
"""

from __future__ import annotations

import numpy as np
import pytest

from golden_model import regs
from golden_model.config import Config, named
from golden_model.featmem import SLOT_RECORD_WORDS, decode_record
from golden_model.features import first_difference
from golden_model.luma import rgb_to_luma
from golden_model.pipeline import extract
from orb_accel.bus import BusError
from orb_sim.fast.jobs import FastAccel, generics_for, pack
from orb_sim.fast.sim import FLAG_LAST, frame_program
from orb_sim.faults import AxiError, AxiSlow, AxiStall, apply_axi_faults, parse
from orbtb.campaign import DDR_KINDS, run_campaign
from orbtb.images import colour_photo

TINY = named("test-tiny")
W, H = TINY.width, TINY.height
PHOTOS = ("astronaut", "coffee", "chelsea", "rocket")
DDR_GENERICS = {**generics_for(TINY.config(), colour=True, mem_depth=TINY.mem_depth, mem_kind="ddr"), "DMA_FIFO_g": 32}
FRAME_CLOCKS = (W + 16) * H + 64
CANARY = 0x5A


@pytest.fixture(scope="module")
def photos() -> list[np.ndarray]:
    return [colour_photo(name, W, H) for name in PHOTOS]


def settle(fa: FastAccel, limit: int = 20 * FRAME_CLOCKS) -> int:
    """Run until the video is sent, no interrupt comes for 2,000 clocks and the DMA is idle; the
    interrupts acknowledged. Returns RING_STATUS."""
    sim, accel = fa.sim, fa.accel
    assert sim.run_video(limit), "the video source could not send its frame"
    start = sim.cycle
    while sim.cycle - start < limit:
        if sim.wait_irq(2000):
            accel.write(regs.IRQ_STATUS, 0xFFFFFFFF)
            continue
        status = accel.read(regs.RING_STATUS)
        if not regs.RING_STATUS.field("busy").get(status):
            return status
    raise AssertionError(f"the DMA still busy after {limit} clocks: {accel.status_text()}")


def model_config(fa: FastAccel) -> Config:
    p = fa.accel.written()
    return Config(W, H, scales=TINY.scales, sectors=TINY.sectors, threshold=p.threshold, mode=p.mode,
                  step_num=TINY.step_num, step_den=TINY.step_den, selection=p.selection, budget=p.budget,
                  cols=p.cols, rows=p.rows, threshold_lo=p.threshold_lo)  # fmt: skip


def test_ddr_frames(photos: list[np.ndarray]) -> None:
    fa = FastAccel.start(DDR_GENERICS, ring_count=3)
    sim, accel, mem = fa.sim, fa.accel, fa.memory
    ring = accel.ring
    assert mem is not None and ring is not None and ring.count == 3 and ring.base == sim.memory_region[0]
    accel.configure(threshold=20, irq=("frame_done", "error"))
    cfg = model_config(fa)
    base, size = sim.memory_region
    end = ring.offset + ring.extent
    sim.write_mem(base + end, bytes([CANARY]) * (size - end))
    sim.set_axi_timing(aw_ready=0.6, w_ready=0.7, b_delay=30, b_jitter=40, outstanding=4, w_ahead=8, seed=9)
    sim.axi_log(True)
    published = []
    for k in range(6):
        rgb = photos[k % len(photos)]
        if k == 2:  # the interconnect stopped for a frame period: the burst FIFO fills, the frame is dropped
            sim.axi_stall(FRAME_CLOCKS, aw=True, w=True)
        if k == 4:  # frame 4 goes to buffer 0 (frame 2 did not use its position): its record answered SLVERR
            sim.axi_error_at(ring.base, "slverr")
        sim.push_frame(pack(rgb), 16, 64)
        status = settle(fa)
        ready = regs.RING_STATUS.field("ready").get(status)
        if k == 0:  # the driver invalidated the ring at open: without another invalidation the CPU sees it empty
            assert ready == 1
            assert not mem.view(ring.buffer_offset(0), 64).any()
            record = decode_record(np.frombuffer(sim.read_mem(ring.base, 64), "<u4")[:SLOT_RECORD_WORDS])
            assert record.frame == 0 and record.count > 0
        for b in range(ring.count):
            if ready >> b & 1:
                frame = accel.read_bank(b)
                accel.release(b)
                published.append((frame.number, frame.bank))
                diff = first_difference(frame.features, extract(rgb_to_luma(rgb), cfg))
                assert diff is None, f"frame {k} (number {frame.number}): netlist and model differ: {diff}"
                assert frame.dropped == 0 and frame.truncated == 0
    # frame 2 dropped at the full FIFO (its position not used: frame 3 in buffer 2), frame 4 at its
    # record's error response (its position used: frame 5 in buffer 1)
    assert published == [(0, 0), (1, 1), (3, 2), (5, 1)], published
    dma, axi = accel.dma_counters(), sim.axi_stats()
    assert dma["dma_dropped"] == 2 and dma["dma_bus_errors"] == 1, dma
    assert axi["slverr"] == 1 and axi["injected"] == 1 and axi["decerr"] == 0 and axi["refused"] == 0, axi
    assert axi["protocol_errors"] == 0 and axi["aw_stall_clocks"] > 0 and axi["max_outstanding"] > 1, axi
    assert dma["dma_beats"] == axi["beats"] == 8 * axi["bursts"]
    info = accel.read(regs.RING_INFO)
    assert regs.RING_INFO.field("frame").get(info) == 5
    # the log: frame 4's record written and answered SLVERR, frame 2's never written
    log = sim.axi_log_take()
    assert len(log) == axi["bursts"]
    records = {}
    for e in log:
        if (int(e["addr"]) - ring.base) % ring.stride == 0:
            records[decode_record(np.asarray(e["data"], "<u8").view("<u4")[:SLOT_RECORD_WORDS]).frame] = int(e["resp"])
    assert records == {0: 0, 1: 0, 3: 0, 4: 2, 5: 0}, records
    assert not np.any(np.frombuffer(sim.read_mem(base + end, size - end), np.uint8) != CANARY), "written outside"
    assert mem.invalidations >= 2 * len(published)
    sim.close()


def test_ddr_outside_memory(photos: list[np.ndarray]) -> None:
    """A ring beyond the harness's memory (inside the fabric's window, so RING_STATUS.error is 0):
    every burst is answered DECERR and nothing is stored; the frame is dropped and counted."""
    fa = FastAccel.start(DDR_GENERICS, ring_count=2)
    sim, accel = fa.sim, fa.accel
    base, size = fa.bus.memory_region
    assert (base, size) == sim.memory_region
    before = sim.read_mem(base, size)
    ctrl = accel.read(regs.CTRL)
    stopped = regs.CTRL.field("enable").put(0, ctrl)
    accel.write(regs.CTRL, stopped)
    accel.write(regs.RING_BASE, base + size)
    accel.write(regs.CTRL, regs.CTRL.field("soft_reset").put(1, stopped))
    accel.write(regs.CTRL, ctrl)
    accel.configure(threshold=20, irq=("frame_done", "error"))
    sim.push_frame(pack(photos[0]), 16, 64)
    status = settle(fa)
    assert regs.RING_STATUS.field("ready").get(status) == 0 and regs.RING_STATUS.field("error").get(status) == 0
    axi, dma = sim.axi_stats(), accel.dma_counters()
    assert axi["bursts"] > 1 and axi["refused"] == axi["decerr"] == axi["bursts"] and axi["bytes"] == 0, axi
    assert axi["refused_beats"] == axi["beats"] and axi["injected"] == 0
    assert dma["dma_dropped"] == 1 and dma["dma_bus_errors"] == axi["bursts"], dma
    assert sim.read_mem(base, size) == before
    with pytest.raises(BusError):
        fa.bus.read_mem(base + size - 2, 4)
    assert fa.bus.read_mem(base + size - 4, 4) == before[-4:]
    sim.close()


def test_interconnect_faults_as_text(photos: list[np.ndarray]) -> None:
    specs = ["axistall:5000:1500:aww", "axierr:3:50:decerr", "axislow:0.5:40"]
    faults = [parse(t) for t in specs]
    assert faults == [AxiStall(5000, 1500, "aww"), AxiError(3, 50, 3), AxiSlow(0.5, 40)]
    assert [f.text for f in faults] == specs
    for bad in ("axistall:100:100", "axistall:100:10:x", "axierr:0", "axierr:2:1:okay", "axislow:0:5", "axislow:1.5:5",
                "axislow:fast:5"):  # fmt: skip
        with pytest.raises(ValueError, match="fault"):
            parse(bad)
    fa = FastAccel.start(DDR_GENERICS, ring_count=3)
    sim, accel = fa.sim, fa.accel
    assert apply_axi_faults(sim, [parse("cut:2:1"), *faults]) == faults
    accel.configure(threshold=20, irq=("frame_done", "error"))
    published = 0
    for k in range(2):
        sim.push_frame(pack(photos[k]), 16, 64)
        ready = regs.RING_STATUS.field("ready").get(settle(fa))
        published += bin(ready).count("1")
    axi, dma = sim.axi_stats(), accel.dma_counters()
    # bursts 3, 53, 103, .. (from 1) answered DECERR; AWREADY and WREADY low 1,500 clocks in 5,000
    assert axi["decerr"] == axi["injected"] == len(range(2, axi["bursts"], 50)) > 1, axi
    assert axi["aw_stall_clocks"] > 0 and axi["w_stall_clocks"] > 0 and axi["slverr"] == 0
    assert dma["dma_bus_errors"] == axi["decerr"] and dma["dma_dropped"] + published == 2, (dma, published)
    sim.close()


def _rejected(words: np.ndarray) -> tuple[np.ndarray, ...]:
    """A frame whose line 80 is 20 pixels short: the checker rejects it (orb_feat_dma aborts it)."""
    data, flags, gaps = frame_program(words, 16, 64)
    y, k = 80, 20
    keep = np.ones(len(data), dtype=bool)
    keep[(y + 1) * W - k : (y + 1) * W] = False
    flags, gaps = flags.copy(), gaps.copy()
    flags[(y + 1) * W - k - 1] |= FLAG_LAST
    gaps[(y + 1) * W - k - 1] = 16
    return data[keep], flags[keep], gaps[keep]


def test_ddr_error_to_a_rejected_frame(photos: list[np.ndarray]) -> None:
    """An error response to a burst of a frame the checker rejects (aborted: its queued slots are
    still written, docs/feature-dma.md) is counted and costs no other frame: the five good frames
    after it (more than the frame tags' 4) are all published (a frame is dropped only for an error
    to one of its own bursts)."""
    fa = FastAccel.start(DDR_GENERICS, ring_count=3)
    sim, accel = fa.sim, fa.accel
    accel.configure(threshold=20, irq=("frame_done", "error"))
    sim.axi_error(sim.axi_stats()["bursts"] + 2, "slverr")
    sim.push(*_rejected(pack(photos[0])))
    status = settle(fa)
    assert regs.RING_STATUS.field("ready").get(status) == 0
    assert sim.axi_stats()["slverr"] == 1 and accel.dma_counters()["dma_bus_errors"] == 1
    numbers = []
    for k in range(5):
        sim.push_frame(pack(photos[k % len(photos)]), 16, 64)
        ready = regs.RING_STATUS.field("ready").get(settle(fa))
        for b in range(3):
            if ready >> b & 1:
                numbers.append(accel.read_bank(b, counters=False).number)
                accel.release(b)
    dropped = accel.dma_counters()["dma_dropped"]
    sim.close()
    assert numbers == [1, 2, 3, 4, 5] and dropped == 0, (numbers, dropped)


def test_ddr_fault_campaign_quick(photos: list[np.ndarray]) -> None:
    result = run_campaign(photos, 40, seed=4, generics=DDR_GENERICS)
    print(result.summary())
    assert not result.lockups, result.lockups
    assert not result.mismatches, result.mismatches[:5]
    # seed 4 draws every DDR event; stalls fill the burst FIFO and error responses drop frames
    missing = [k for k, n in result.by_kind(DDR_KINDS).items() if n == 0]
    assert not missing, missing
    assert result.frames_dropped_fifo >= 1 and result.frames_dropped_error >= 1, result.report()["ddr"]
    assert result.error_responses >= result.frames_dropped_error and result.axi["protocol_errors"] == 0
    assert result.frames_published >= 15 and result.features_checked > 500
