# SPDX-License-Identifier: MIT
"""OrbAccel.settle() against a scripted accelerator: the frame-end races around its acknowledgement.

The bus here is a small register-level model of the feature memory's bank protocol
(docs/feature-memory.md): a finished frame goes to the next bank unless that bank is still READY,
in which case it is skipped (an overrun) and the next frame tries the same bank again; a finished
frame sets IRQ_STATUS.frame_done and STATUS.last_bank. Frames finish when the driver waits for the
interrupt, or at a chosen read. Each frame is empty (its record alone), which is all settle() and
next_frame() need to read.

- A frame that finished before settle() acknowledged the interrupts must have its bank released,
  or every later frame is skipped and the driver waits for an interrupt that never comes.
- A frame that finishes between the acknowledgement and that release raises the interrupt with a
  bank that is gone: settle() waits on for the next frame instead of failing.
"""

from __future__ import annotations

import numpy as np
import pytest

from golden_model import regs
from golden_model.featcodec import encode_eof, record_slot
from golden_model.featword import SLOT_BYTES
from orb_accel import OrbAccel

W, H, SCALES, SECTORS, DEPTH = 128, 96, 2, 32, 16


class ScriptedAccel:
    """Bus (read32, write32, read_block, wait_irq) of a model accelerator with two banks."""

    def __init__(self) -> None:
        self.ready = [0, 0]
        self.next_bank = 0
        self.last_bank = 0
        self.irq_status = 0
        self.irq_enable = 0
        self.frames = 0
        self.overruns = 0
        self.ctrl = 0
        self.threshold = 20
        self.finish_on_status_read: int | None = None  # finish a frame at the n-th STATUS read
        self.status_reads = 0
        self.mem: dict[int, int] = {}

    def finish_frame(self) -> None:
        b = self.next_bank
        self.frames += 1
        if self.ready[b]:
            self.overruns += 1
            return
        self.ready[b], self.last_bank, self.next_bank = 1, b, b ^ 1
        self.irq_status |= regs.IRQ_STATUS.field("frame_done").put(1)
        base = regs.MEM_BASE + b * DEPTH * SLOT_BYTES
        for i, w in enumerate(record_slot(encode_eof(self.frames & 0xFFFF), 0, 0)):
            self.mem[base + 4 * i] = w

    # ---- bus ----------------------------------------------------------------------------------
    def read32(self, addr: int) -> int:
        if addr >= regs.MEM_BASE:
            return self.mem.get(addr, 0)
        if addr == regs.STATUS.offset:
            self.status_reads += 1
            if self.status_reads == self.finish_on_status_read:
                self.finish_frame()
            word = regs.STATUS.field("bank_ready").put(self.ready[0] | self.ready[1] << 1)
            return regs.STATUS.field("last_bank").put(self.last_bank, word)
        values = {
            regs.ID.offset: regs.ORB_ID,
            regs.VERSION.offset: regs.VERSION.field("major").put(regs.VERSION_MAJOR),
            regs.CFG_SIZE.offset: regs.CFG_SIZE.field("height").put(H, regs.CFG_SIZE.field("width").put(W)),
            regs.CFG_ORB.offset: regs.CFG_ORB.field("step_den").put(
                1,
                regs.CFG_ORB.field("step_num").put(
                    2, regs.CFG_ORB.field("sectors").put(SECTORS, regs.CFG_ORB.field("scales").put(SCALES))
                ),
            ),
            regs.CFG_MEM.offset: regs.CFG_MEM.field("depth").put(DEPTH),
            regs.CTRL.offset: self.ctrl,
            regs.THRESHOLD.offset: self.threshold,
            regs.IRQ_STATUS.offset: self.irq_status,
            regs.IRQ_ENABLE.offset: self.irq_enable,
            regs.BANK0_INFO.offset: 0,
            regs.BANK1_INFO.offset: 0,
        }
        return values.get(addr, 0)

    def write32(self, addr: int, value: int) -> None:
        if addr == regs.IRQ_STATUS.offset:
            self.irq_status &= ~value
        elif addr == regs.IRQ_ENABLE.offset:
            self.irq_enable = value
        elif addr == regs.BANK_RELEASE.offset:
            self.ready[regs.BANK_RELEASE.field("bank").get(value)] = 0
        elif addr == regs.CTRL.offset:
            self.ctrl = value
        elif addr == regs.THRESHOLD.offset:
            self.threshold = value

    def read_block(self, addr: int, count: int) -> np.ndarray:
        return np.array([self.read32(addr + 4 * i) for i in range(count)], dtype=np.uint32)

    def wait_irq(self, timeout_s: float) -> bool:
        # time passes: frames finish until the interrupt is up (a bounded number of them)
        for _ in range(8):
            if self.irq_status & self.irq_enable:
                return True
            self.finish_frame()
        return bool(self.irq_status & self.irq_enable)


def started() -> tuple[ScriptedAccel, OrbAccel]:
    bus = ScriptedAccel()
    accel = OrbAccel(bus)
    accel.configure(threshold=20, mode="orb")
    return bus, accel


def test_a_frame_finished_before_settle_has_its_bank_released() -> None:
    bus, accel = started()
    bus.finish_frame()  # bank 0 READY, its interrupt pending
    accel.configure(threshold=30, mode="fast")
    accel.settle(0.01)
    assert bus.ready == [0, 0], f"banks still held after settle: {bus.ready}"
    for _ in range(3):  # and frames keep coming
        accel.next_frame(0.01)
    assert bus.overruns == 0


def test_a_frame_finished_between_acknowledgement_and_release_is_waited_past() -> None:
    bus, accel = started()
    bus.finish_frame()  # bank 0
    # the next frame (bank 1) finishes just as settle() reads STATUS to release what is ready
    bus.finish_on_status_read = bus.status_reads + 1
    frames_before = bus.frames
    frame = accel.settle(0.01)
    assert bus.frames >= frames_before + 2, "settle returned a frame that finished before it"
    assert frame.bank == bus.last_bank and bus.ready == [0, 0]
    accel.next_frame(0.01)


def test_next_frame_without_settle_still_needs_the_release() -> None:
    """The scripted model is strict: a bank never released stops the frames (the failure the
    first test guards against)."""
    bus, accel = started()
    bus.finish_frame()
    accel.write(regs.IRQ_STATUS, 0xFFFFFFFF)  # acknowledged, bank 0 left READY
    accel.next_frame(0.01)  # bank 1
    with pytest.raises(TimeoutError, match="no interrupt"):
        accel.next_frame(0.01)
