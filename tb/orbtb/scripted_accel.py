# SPDX-License-Identifier: MIT
"""A scripted accelerator for the driver's unit tests (tb/driver/test_driver_settle.py,
test_driver_faults.py): a small register-level model of the feature memory's bank protocol
(docs/feature-memory.md) behind the driver's Bus, with faults on demand.

A finished frame goes to the next bank unless that bank is still READY, in which case it is
skipped (an overrun) and the next frame tries the same bank again; a published frame sets
IRQ_STATUS.frame_done and STATUS.last_bank. Frames finish when the driver waits for the interrupt
(while the video plays), or at a chosen STATUS read. Each frame is empty (its record alone), which
is all the driver's frame handling needs, unless `features` is set: then every frame holds those
features (encoded with the one slot codec, golden_model.featcodec; at most a bank's DEPTH - 1) and
BANKn_INFO shows their count (the PYNQ checks read them back, tb/pynq). Its record carries the
parameters it was processed with (docs/feature-memory.md): those of the registers when the frame
finishes (a write between the driver's waits landed in the blanking before the frame started), or
with `late_writes` those of the registers when the frame before it finished (every write after an
interrupt missed the blanking: the frame in flight had started). Faults: `video = False` (a cable cut: no frame
finishes, wait_irq times out), `fail(op, addr, nth)` (the nth next access of that kind answers
SLVERR, the access not done, as the register bank answers one), `lose_irq()` (a published frame's
interrupt cleared behind the driver's back).
"""

from __future__ import annotations

import numpy as np

from golden_model import regs
from golden_model.config import MODES, SELECTIONS
from golden_model.featcodec import encode_eof, encode_feature, feature_slot, record_slot
from golden_model.features import Features
from golden_model.featword import SLOT_BYTES
from golden_model.frameparams import FrameParams
from orb_accel import BusError

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
        self.select = 0
        self.late_writes = False
        self.started = self.params()  # the parameters of the frame in flight, with late_writes
        self.finish_on_status_read: int | None = None  # finish a frame at the n-th STATUS read
        self.status_reads = 0
        self.mem: dict[int, int] = {}
        self.video = True  # False: a cable cut, no frame finishes
        self.failures: dict[tuple[str, int | None], int] = {}  # (op, addr or None for the memory) -> countdown
        self.injected = 0
        self.features: Features | None = None  # what every frame holds (None: nothing, the record alone)
        self.info = [0, 0]  # BANKn_INFO of each bank

    def params(self) -> FrameParams:
        """The parameters the registers hold now."""
        thr, sel = self.threshold, self.select
        return FrameParams(
            threshold=regs.THRESHOLD.field("threshold").get(thr), threshold_lo=regs.THRESHOLD.field("low").get(thr),
            mode=MODES[regs.CTRL.field("mode").get(self.ctrl)],
            selection=SELECTIONS[regs.SELECT.field("mode").get(sel)], budget=regs.SELECT.field("budget").get(sel),
            cols=regs.SELECT.field("cols").get(sel), rows=regs.SELECT.field("rows").get(sel),
        )  # fmt: skip

    def finish_frame(self) -> None:
        b = self.next_bank
        self.frames += 1
        made_with = self.started if self.late_writes else self.params()
        self.started = self.params()  # the next frame starts now
        if self.ready[b]:
            self.overruns += 1
            return
        self.ready[b], self.last_bank, self.next_bank = 1, b, b ^ 1
        self.irq_status |= regs.IRQ_STATUS.field("frame_done").put(1)
        base = regs.MEM_BASE + b * DEPTH * SLOT_BYTES
        words = [w for s in range(self.count()) for w in self.slot(s)]
        words += record_slot(encode_eof(self.frames & 0xFFFF, 0, made_with), self.count(), 0)
        for i, w in enumerate(words):
            self.mem[base + 4 * i] = w
        self.info[b] = regs.BANK0_INFO.field("frame").put(self.frames & 0xFFFF, self.count())

    def count(self) -> int:
        """Features per frame."""
        if self.features is None:
            return 0
        if len(self.features) >= DEPTH:
            raise ValueError(f"{len(self.features)} features: a bank holds {DEPTH - 1} and the record")
        return len(self.features)

    def slot(self, s: int) -> list[int]:
        """The words of feature s's slot."""
        f = self.features
        assert f is not None
        beat = encode_feature(scale=int(f.scale[s]), x=int(f.x[s]), y=int(f.y[s]), score=int(f.score[s]),
                              sector=int(f.sector[s]), descriptor=bytes(f.descriptor[s]),
                              response=int(f.response[s]), low=int(f.low[s]))  # fmt: skip
        return feature_slot(beat)

    def lose_irq(self) -> None:
        self.irq_status &= ~regs.IRQ_STATUS.field("frame_done").put(1)

    # ---- faults -------------------------------------------------------------------------------
    def fail(self, op: str, reg: regs.Register | None, nth: int = 1) -> None:
        """The nth next `op` ("read", "write", "block") of `reg` (None: the feature memory) answers SLVERR."""
        self.failures[(op, None if reg is None else reg.offset)] = nth

    def _check(self, op: str, addr: int, value: int | None = None) -> None:
        key = (op, None if addr >= regs.MEM_BASE else addr)
        if key in self.failures:
            self.failures[key] -= 1
            if self.failures[key] == 0:
                del self.failures[key]
                self.injected += 1
                raise BusError(op if op != "block" else "read", addr, 2, value)

    # ---- bus ----------------------------------------------------------------------------------
    def read32(self, addr: int) -> int:
        self._check("read", addr)
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
            regs.VERSION.offset: regs.VERSION.field("minor").put(
                regs.VERSION_MINOR, regs.VERSION.field("major").put(regs.VERSION_MAJOR)
            ),
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
            regs.SELECT.offset: self.select,
            regs.IRQ_STATUS.offset: self.irq_status,
            regs.IRQ_ENABLE.offset: self.irq_enable,
            regs.BANK0_INFO.offset: self.info[0],
            regs.BANK1_INFO.offset: self.info[1],
            regs.OVERRUN.offset: self.overruns,
        }
        return values.get(addr, 0)

    def write32(self, addr: int, value: int) -> None:
        self._check("write", addr, value)
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
        elif addr == regs.SELECT.offset:
            self.select = value

    def read_block(self, addr: int, count: int) -> np.ndarray:
        self._check("block", addr)
        return np.array([self.mem.get(addr + 4 * i, 0) for i in range(count)], dtype=np.uint32)

    def wait_irq(self, timeout_s: float) -> bool:
        # time passes: frames finish until the interrupt is up (a bounded number of them)
        for _ in range(8):
            if self.irq_status & self.irq_enable:
                return True
            if self.video:
                self.finish_frame()
        return bool(self.irq_status & self.irq_enable)
