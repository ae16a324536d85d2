# SPDX-License-Identifier: MIT
"""A scripted DDR build for the driver's unit tests (tb/driver/test_ddr_ring.py): the registers of
register map 3.2 with CFG_DDR.ddr = 1 and a register-level model of orb_feat_dma's ring
(docs/feature-dma.md), writing its frames into the device side of an in-process memory
(orb_accel.ddr.ArrayMemory.array), with a count of every bus access.

The model follows the documented rules, written here independently of the driver:

- RING_STATUS.error from RING_BASE, RING_STRIDE, RING_COUNT and the window (bit 0 unaligned, bit 1
  overlap, bit 2 outside, bit 3 off);
- frames go to buffers 0, 1, .., RING_COUNT - 1, 0, ..: a frame whose buffer is READY is skipped
  (OVERRUN; the position does not move), one that starts while the ring is in error is dropped
  (DMA_DROPPED); a written frame's features go to slots 1 .. count, its record to slot 0, then it is
  published (ring_ready bit, ring_last, RING_INFO, IRQ_STATUS.frame_done);
- RING_RELEASE clears a READY bit; CTRL.soft_reset frees every buffer, moves the position to 0
  and clears the counters.

Frames finish when the driver waits for the interrupt (while `video`), or with publish(). What a
frame holds: `features` (a golden_model Features; encoded with the one slot codec) or nothing.
`fail(op, reg)` makes the next access of that kind answer SLVERR, undone; `lose_irq()` clears
frame_done behind the driver's back. `cache=True` gives the memory a model of the CPU's cache:
view() reads a copy that only invalidate() refreshes, line by line, so a driver that reads without
invalidating reads stale bytes.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

from golden_model import regs
from golden_model.config import MODES, SELECTIONS
from golden_model.featcodec import encode_eof, encode_feature, feature_slot, record_slot
from golden_model.features import Features
from golden_model.featword import SLOT_BYTES
from golden_model.frameparams import FrameParams
from orb_accel import BusError
from orb_accel.ddr import CACHE_LINE, ArrayMemory, check_range

W, H, SCALES, SECTORS = 640, 480, 2, 32
MIB = 1 << 20


class CachedMemory(ArrayMemory):
    """ArrayMemory with a model of the CPU's cache: `array` is DDR (what the device writes), view()
    reads `cpu`, a copy that invalidate() refreshes for whole lines of the range only."""

    def __init__(self, size: int, phys_addr: int = 0) -> None:
        super().__init__(size, phys_addr)
        self.cpu = np.zeros(size, dtype=np.uint8)
        self.calls: list[tuple[int, int]] = []

    def invalidate(self, offset: int, length: int) -> None:
        super().invalidate(offset, length)
        self.calls.append((offset, length))
        start = offset - offset % CACHE_LINE
        end = -(-(offset + length) // CACHE_LINE) * CACHE_LINE
        self.cpu[start:end] = self.array[start:end]

    def view(self, offset: int, length: int) -> np.ndarray:
        offset, length = check_range(offset, length, self.size)
        v = self.cpu[offset : offset + length].view()
        v.flags.writeable = False
        return v


def feature_words(f: Features, s: int) -> list[int]:
    """The slot words of feature s of `f`."""
    beat = encode_feature(scale=int(f.scale[s]), x=int(f.x[s]), y=int(f.y[s]), score=int(f.score[s]),
                          sector=int(f.sector[s]), descriptor=bytes(f.descriptor[s]), response=int(f.response[s]),
                          low=int(f.low[s]))  # fmt: skip
    return feature_slot(beat)


def random_features(n: int, seed: int = 1, width: int = W, height: int = H) -> Features:
    """n random features (orb mode), as a frame of them would hold."""
    rng = np.random.default_rng(seed)
    scale = rng.integers(0, SCALES, n)
    x = np.array([rng.integers(3, (width >> s) - 3) for s in scale], dtype=np.int64)
    y = np.array([rng.integers(3, (height >> s) - 3) for s in scale], dtype=np.int64)
    return Features(scale.astype(np.int64), x, y, rng.integers(1, 4000, n), rng.integers(0, SECTORS, n),
                    rng.integers(0, 256, (n, 32), dtype=np.uint8), SECTORS, (2, 1), rng.integers(0, 64, n),
                    rng.integers(0, 2, n).astype(bool))  # fmt: skip


class ScriptedRing:
    """Bus (read32, write32, read_block, wait_irq) of a DDR build writing into `memory`."""

    def __init__(self, memory: ArrayMemory, depth: int = 64, win_base_mb: int = 0, win_size_mb: int = 4096,
                 minor: int = regs.VERSION_MINOR, ddr: bool = True) -> None:  # fmt: skip
        self.memory = memory
        self.depth = depth
        self.minor = minor
        self.cfg_ddr = (regs.CFG_DDR.field("ddr").put(int(ddr)) | regs.CFG_DDR.field("win_base").put(win_base_mb)
                        | regs.CFG_DDR.field("win_size").put(win_size_mb))  # fmt: skip
        self.win = (win_base_mb * MIB, (win_base_mb + win_size_mb) * MIB)
        self.base = self.stride = self.count = 0
        self.ctrl = self.threshold = self.select = self.irq_enable = self.irq_status = 0
        self.ready = 0
        self.last = 0
        self.position = 0
        self.info = 0
        self.frames = 0  # frame numbers (every frame that ends, written or not)
        self.overruns = self.dropped = 0
        self.published: list[tuple[int, int]] = []  # (buffer, frame number) of every published frame
        self.features: Features | None = None
        self.video = True
        self.accesses: Counter[str] = Counter()  # "read REG", "write REG", "block": every bus access
        self.failures: dict[tuple[str, int], int] = {}
        self.extra_error = 0  # error bits the device shows whatever the registers say (a device that disagrees)
        self.soft_resets = 0

    # ---- the model ----------------------------------------------------------------------------
    def error(self) -> int:
        e = self.extra_error
        if self.base % 64 or self.stride % 64:
            e |= 1
        if self.count > 1 and self.stride < self.depth * SLOT_BYTES:
            e |= 2
        end = self.base + max(self.count - 1, 0) * self.stride + self.depth * SLOT_BYTES
        if self.base < self.win[0] or end > self.win[1]:
            e |= 4
        if self.count == 0:
            e |= 8
        return e

    def status(self) -> int:
        s = regs.RING_STATUS.field("ready").put(self.ready) | regs.RING_STATUS.field("last").put(self.last)
        return s | regs.RING_STATUS.field("error").put(self.error())

    def params(self) -> FrameParams:
        thr, sel = self.threshold, self.select
        return FrameParams(
            threshold=regs.THRESHOLD.field("threshold").get(thr), threshold_lo=regs.THRESHOLD.field("low").get(thr),
            mode=MODES[regs.CTRL.field("mode").get(self.ctrl)],
            selection=SELECTIONS[regs.SELECT.field("mode").get(sel)], budget=regs.SELECT.field("budget").get(sel),
            cols=regs.SELECT.field("cols").get(sel), rows=regs.SELECT.field("rows").get(sel),
        )  # fmt: skip

    def publish(self, features: Features | None = None) -> int | None:
        """A frame ends now: written and published (its buffer returned), skipped or dropped (None)."""
        f = self.features if features is None else features
        n = 0 if f is None else len(f)
        if n >= self.depth:
            raise ValueError(f"{n} features: a buffer holds {self.depth - 1} and the record")
        number = self.frames & 0xFFFF
        self.frames += 1
        if self.error():
            self.dropped += 1
            return None
        w = self.position
        if self.ready >> w & 1:
            self.overruns += 1
            return None
        at = self.base + w * self.stride - self.memory.phys_addr
        words = [wd for s in range(n) for wd in feature_words(f, s)] if n else []
        data = np.array(words, dtype="<u4").view(np.uint8)
        self.memory.array[at + SLOT_BYTES : at + SLOT_BYTES + len(data)] = data
        rec = np.zeros(SLOT_BYTES // 4, dtype="<u4")
        r = record_slot(encode_eof(number, 0, self.params()), n, 0)
        rec[: len(r)] = r
        self.memory.array[at : at + SLOT_BYTES] = rec.view(np.uint8)
        self.ready |= 1 << w
        self.last = w
        self.info = regs.RING_INFO.field("frame").put(number, n)
        self.irq_status |= regs.IRQ_STATUS.field("frame_done").put(1)
        self.position = (w + 1) % self.count
        self.published.append((w, number))
        return w

    def lose_irq(self) -> None:
        self.irq_status &= ~regs.IRQ_STATUS.field("frame_done").put(1)

    def fail(self, op: str, reg: regs.Register, nth: int = 1) -> None:
        """The nth next `op` ("read", "write") of `reg` answers SLVERR (not done)."""
        self.failures[(op, reg.offset)] = nth

    def _check(self, op: str, addr: int, value: int | None = None) -> None:
        key = (op, addr)
        if key in self.failures:
            self.failures[key] -= 1
            if self.failures[key] == 0:
                del self.failures[key]
                raise BusError(op, addr, 2, value)

    def _name(self, addr: int) -> str:
        reg = regs.BY_OFFSET.get(addr)
        return reg.name if reg is not None else f"{addr:#x}"

    def total(self) -> int:
        return sum(self.accesses.values())

    # ---- bus ----------------------------------------------------------------------------------
    def read32(self, addr: int) -> int:
        self.accesses[f"read {self._name(addr)}"] += 1
        self._check("read", addr)
        if addr == regs.CFG_DDR.offset and self.minor < 2:
            raise BusError("read", addr, 2)  # no such register before map 3.2
        values = {
            regs.ID.offset: regs.ORB_ID,
            regs.VERSION.offset: regs.VERSION.field("minor").put(self.minor, regs.VERSION.field("major").put(3)),
            regs.CFG_SIZE.offset: regs.CFG_SIZE.field("height").put(H, regs.CFG_SIZE.field("width").put(W)),
            regs.CFG_ORB.offset: regs.CFG_ORB.field("step_den").put(1, regs.CFG_ORB.field("step_num").put(
                2, regs.CFG_ORB.field("sectors").put(SECTORS, regs.CFG_ORB.field("scales").put(SCALES)))),
            regs.CFG_MEM.offset: regs.CFG_MEM.field("depth").put(self.depth),
            regs.CFG_DDR.offset: self.cfg_ddr,
            regs.CTRL.offset: self.ctrl,
            regs.THRESHOLD.offset: self.threshold,
            regs.SELECT.offset: self.select,
            regs.IRQ_STATUS.offset: self.irq_status,
            regs.IRQ_ENABLE.offset: self.irq_enable,
            regs.RING_BASE.offset: self.base,
            regs.RING_STRIDE.offset: self.stride,
            regs.RING_COUNT.offset: self.count,
            regs.RING_STATUS.offset: self.status(),
            regs.RING_INFO.offset: self.info,
            regs.OVERRUN.offset: self.overruns,
            regs.DMA_DROPPED.offset: self.dropped,
        }  # fmt: skip
        return values.get(addr, 0)

    def write32(self, addr: int, value: int) -> None:
        self.accesses[f"write {self._name(addr)}"] += 1
        self._check("write", addr, value)
        if addr == regs.IRQ_STATUS.offset:
            self.irq_status &= ~value
        elif addr == regs.IRQ_ENABLE.offset:
            self.irq_enable = value
        elif addr == regs.CTRL.offset:
            if regs.CTRL.field("soft_reset").get(value):
                self.soft_resets += 1
                self.ready = self.position = self.last = self.info = 0
                self.overruns = self.dropped = self.frames = 0
            self.ctrl = regs.CTRL.field("soft_reset").put(0, value)
        elif addr == regs.THRESHOLD.offset:
            self.threshold = value
        elif addr == regs.SELECT.offset:
            self.select = value
        elif addr == regs.RING_BASE.offset:
            self.base = value
        elif addr == regs.RING_STRIDE.offset:
            self.stride = value
        elif addr == regs.RING_COUNT.offset:
            self.count = value
        elif addr == regs.RING_RELEASE.offset:
            self.ready &= ~(1 << regs.RING_RELEASE.field("index").get(value))
        elif addr == regs.BANK_RELEASE.offset:
            raise AssertionError("BANK_RELEASE written on a DDR build")

    def read_block(self, addr: int, count: int) -> np.ndarray:
        self.accesses["block"] += count
        raise AssertionError(f"a block read of {count} words at {addr:#x} on a DDR build")

    def wait_irq(self, timeout_s: float) -> bool:
        # not a 32-bit access: the UIO file's protocol (a write and a read of the device file)
        for _ in range(4):
            if self.irq_status & self.irq_enable:
                return True
            if self.video:
                self.publish()
        return bool(self.irq_status & self.irq_enable)
