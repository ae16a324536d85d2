# SPDX-License-Identifier: MIT
"""The accelerator's driver: configure, wait for a frame, read its bank, release it.

Plain blocking Python against a `Bus` (orb_accel.bus), so the same code runs on the board (UIO,
/dev/mem), against the simulator in another process (orb_accel.socket_bus) and inside a cocotb
test (every top-level test drives the accelerator through it). The register map is
golden_model.regs, the feature-memory layout golden_model.featmem (both generated or defined
once; docs/registers.md, docs/feature-memory.md). numpy only. docs/driver.md has the API.

    accel = OrbAccel(bus)
    accel.configure(threshold=20, mode="orb")   # grid selection, the recommended budget
    with accel.frame(timeout_s=0.1) as frame:   # the bank is released on leaving the block
        print(frame.number, len(frame), frame.x, frame.descriptors.shape)

Faults (docs/driver.md, "Faults and recovery"): a wait without a frame raises TimeoutError, an
error response BusError; the driver stays usable after either, counts them in `accel.faults`, and
releases the banks nobody holds (a killed predecessor's at open, one it lost track of after a
timeout or a bus error) so that the accelerator, which skips every frame whose bank is held,
publishes again.

DDR builds (CFG_DDR.ddr = 1, register map 3.2; docs/feature-dma.md, docs/driver.md "Features from
DDR") write every frame into a ring of buffers in DDR instead of the two banks: OrbAccel(bus,
memory=...) lays the ring out in that memory (orb_accel.ddr: u-dma-buf, pynq.allocate, an array),
checks it (orb_accel.ring.plan_ring), writes RING_BASE, RING_STRIDE and RING_COUNT while the
accelerator is stopped and soft-resets it; frames are then read from memory (two cache
invalidations, one numpy decoding) with a handful of register accesses per frame. The API is the
same: wait_frame() gives a ring buffer's index where it gave a bank, read_bank() and release()
take it, Frame.bank is it.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import Protocol, TypeVar

import numpy as np

from golden_model import regs
from golden_model.config import (
    MODES,
    RECOMMENDED_COLS,
    RECOMMENDED_ROWS,
    RECOMMENDED_THRESHOLD_LO,
    SELECTIONS,
    Config,
    recommended_budget,
)
from golden_model.featmem import (
    SLOT_BYTES,
    SLOT_RECORD_WORDS,
    SLOT_WORDS_USED,
    EndOfFrame,
    decode_features,
    decode_record,
)
from golden_model.features import Features
from golden_model.frameparams import FrameParams
from golden_model.select import best_per_level

from .bus import Bus, BusError
from .ddr import FrameMemory, MemoryFactory
from .ring import MAX_BUFFERS, DdrWindow, RingLayout, plan_ring, read_record, ring_error_text, slot_view

COUNTERS = ("FRAME_COUNT", "DROPPED", "PROTO_ERRORS", "OVERRUN", "OVERFLOW_COUNT", "DESC_LOST", "DISCARDED")
IRQ_SOURCES = ("frame_done", "error")
SLOT_WORDS = SLOT_BYTES // 4  # 32-bit words per slot (SLOT_WORDS_USED of them hold data)
PATCH_DIAMETER = 31  # a keypoint's size at octave 0 (OpenCV ORB's patchSize): 31 * r^octave
NO_ANGLE = -1.0  # cv2.KeyPoint's angle when there is no orientation (fast mode)
# the register map version (major, minor) from which the end-of-frame record carries the parameters
# its frame was processed with (docs/feature-memory.md); an older map's records read 0 there
PARAMS_VERSION = (3, 1)
# the register map version from which CFG_DDR says where the features go (the banks or the DDR ring;
# docs/feature-dma.md); an older map has neither CFG_DDR nor the ring (a read there answers SLVERR)
DDR_VERSION = (3, 2)
DMA_COUNTERS = ("DMA_DROPPED", "DMA_BUS_ERRORS", "DMA_BEATS")
# looked up once: counters() and the frame path read these every frame
_COUNTER_REGS = tuple((name.lower(), getattr(regs, name)) for name in COUNTERS)
_FRAME_DONE = regs.IRQ_STATUS.field("frame_done")
_RING_READY = regs.RING_STATUS.field("ready")
_T = TypeVar("_T")


class AccelError(RuntimeError):
    """The device is not an ORB accelerator, or it answered inconsistently."""


@dataclass
class FaultCounts:
    """What the driver met and recovered from since it was opened (docs/driver.md, "Faults and
    recovery"). Timeouts and bus errors are also raised to the caller (TimeoutError, BusError); the
    frames of the banks a recovery releases are lost, and counted here: nothing goes silently."""

    timeouts: int = 0  # waits for an interrupt that ended without one (TimeoutError): no video, no interrupt
    bus_errors: int = 0  # bus operations answered with an error response (BusError raised to the caller)
    stale_banks: int = 0  # READY banks nobody held, released unread (a killed predecessor's, or lost track of)
    stray_irqs: int = 0  # frame-done interrupts whose bank a recovery had already released (waited past)


@dataclass(frozen=True)
class HwConfig:
    """The configuration the bitstream was built with (read back from CFG_*)."""

    width: int
    height: int
    scales: int
    sectors: int  # orientation sectors in all (16, 32 or 64)
    mem_depth: int  # slots per bank (a bank holds mem_depth - 1 features and the record)
    step_num: int = 2  # pyramid step step_num:step_den (each scale r = num / den times smaller)
    step_den: int = 1

    @property
    def step(self) -> tuple[int, int]:
        return self.step_num, self.step_den

    @property
    def capacity(self) -> int:
        """Features a bank holds: the largest grid-selection budget (SELECT.budget)."""
        return self.mem_depth - 1

    def default_budget(self) -> int:
        """The grid selection's budget configure() sets unless told: the recommended one for the
        frame size (golden_model.config.recommended_budget), at most what a bank holds."""
        return min(recommended_budget(self.width, self.height), self.capacity)


@dataclass(frozen=True)
class Selection:
    """The selection in effect (SELECT and THRESHOLD.low; docs/selection.md): `mode` "grid" (each
    level keeps its share of `budget` features, the best corner of every cell of a `cells` =
    (columns, rows) grid over the frame first, a corner at `threshold_lo` where a cell has none at
    the threshold, then the strongest of the rest, corners at `threshold_lo` last) or "all" (every
    feature at the threshold; the others are ignored)."""

    mode: str
    budget: int
    cells: tuple[int, int]
    threshold_lo: int


@dataclass(frozen=True)
class Frame:
    """One published frame: its bank (on the DDR ring: its ring buffer's index), features
    (canonical order: scale, row, column), end-of-frame record, the mode it was decoded in, the
    configuration, the counters read with it (the
    cumulative registers of COUNTERS, lower-case names; empty when not read) and `params`, the
    parameters the frame was processed with as its record says (threshold, threshold_lo, mode,
    selection, budget, cols, rows: sampled by the accelerator at the frame's first pixel, whatever
    was written since; None from an accelerator whose register map predates PARAMS_VERSION)."""

    bank: int
    features: Features
    record: EndOfFrame
    mode: str = "orb"
    hw: HwConfig | None = None
    counters: dict[str, int] = field(default_factory=dict)
    params: FrameParams | None = None

    def __len__(self) -> int:
        return len(self.features)

    @property
    def number(self) -> int:
        """The accelerator's frame number (16 bits, wraps)."""
        return self.record.frame

    @property
    def dropped(self) -> int:
        """Features of this frame lost before the feature memory (its record)."""
        return self.record.dropped

    @property
    def truncated(self) -> int:
        """Features of this frame not stored because its bank was full (its record)."""
        return self.record.truncated

    @property
    def scale(self) -> np.ndarray:
        return self.features.scale

    @property
    def scale_x(self) -> np.ndarray:
        """Column in the pixels of the feature's own scale."""
        return self.features.x

    @property
    def scale_y(self) -> np.ndarray:
        return self.features.y

    @property
    def x(self) -> np.ndarray:
        """Feature centre in full-resolution pixels: (scale_x + 0.5) r^scale - 0.5, r = num / den the
        pyramid step (docs/spec.md section 3)."""
        return self.features.full_res()[0]

    @property
    def y(self) -> np.ndarray:
        return self.features.full_res()[1]

    @property
    def score(self) -> np.ndarray:
        return self.features.score

    @property
    def response(self) -> np.ndarray:
        """The 6-bit corner response code the grid selection ranks by (docs/spec.md section 15)."""
        return self.features.response

    @property
    def low(self) -> np.ndarray:
        """True for a corner at the low threshold only (a cell's best where it has no corner at
        the threshold; grid selection)."""
        return self.features.low

    @property
    def angle(self) -> np.ndarray:
        """Orientation in degrees (sector * 360 / sectors); NaN in fast mode."""
        return self.features.angle_deg()

    def keypoint_arrays(self) -> dict[str, np.ndarray]:
        """cv2.KeyPoint's fields for every feature, as arrays: x, y (full resolution), size =
        PATCH_DIAMETER * r^octave, angle in degrees (-1: none, fast mode), response = score,
        octave = scale. orb_accel.opencv and the ROS message are built from these."""
        octave = self.scale.astype(np.int32)
        angle = self.angle
        return {
            "x": self.x, "y": self.y, "size": PATCH_DIAMETER * self.features.level_factor(),
            "angle": np.where(np.isnan(angle), NO_ANGLE, angle), "response": self.score.astype(np.float64),
            "octave": octave,
        }  # fmt: skip

    @property
    def descriptors(self) -> np.ndarray:
        """(N, 32) uint8 in OpenCV's ORB byte and bit order; (N, 0) in fast mode."""
        return self.features.descriptor

    def best(self, total: int) -> Frame:
        """This frame with only the features a budget of `total` keeps: each pyramid level's
        strongest, split over the levels as OpenCV's ORB splits nfeatures (docs/spec.md section 14;
        golden_model.select). Record and counters are this frame's, unchanged."""
        if self.hw is None:
            raise ValueError("a frame without its configuration (hw) has no level count for the budget")
        return replace(self, features=best_per_level(self.features, total, self.hw.scales))


BANK_READS = ("bank", "slot")


class OrbAccel:
    """bank_read: how read_bank loads a bank: "bank" (default) in one block of whole 64-byte slots
    (16 words per feature: 60 % more bus reads than needed, one call: the fastest on the board and
    over a socket; docs/ros.md, benchmark), "slot" one block of the 10 used words per slot (fewest
    bus reads: the simulation benches use it, where each read costs clocks).

    release_stale (default True): at open, release the banks the accelerator shows READY whose
    frame-done interrupt was already taken: a previous process died holding them (recover(); the
    banks are in `released_at_open`, counted in faults.stale_banks). False for a program that only
    looks (`orb-accel board info`) while another one may be reading frames.

    memory, ring_count (DDR builds only, CFG_DDR.ddr = 1; ignored otherwise): the FrameMemory the
    ring lies in (orb_accel.ddr), or a callable that opens one given the bytes a ring of
    `ring_count` buffers (default 16) takes, called only for a DDR build; `ring_count` buffers,
    default as many as the memory holds, at most 16. At open the ring is checked (ValueError
    naming the broken rule: orb_accel.ring.plan_ring), written while the accelerator is stopped,
    and the accelerator soft-reset (its frame numbers and counters restart; the buffers a dead
    predecessor held are freed, in `released_at_open`); AccelError if RING_STATUS.error is then
    not 0. A DDR build opened without memory can only be looked at (release_stale False), not
    read: ValueError otherwise."""

    def __init__(self, bus: Bus, check_id: bool = True, bank_read: str = "bank", release_stale: bool = True,
                 memory: FrameMemory | MemoryFactory | None = None, ring_count: int | None = None) -> None:  # fmt: skip
        if bank_read not in BANK_READS:
            raise ValueError(f"bank_read {bank_read!r} not one of {BANK_READS}")
        self.bus = bus
        self.bank_read = bank_read
        self.faults = FaultCounts()
        self._held: set[int] = set()  # banks wait_frame handed out and release has not given back
        self._suspect = False  # a bus error cut an operation: the bank state is checked before the next wait
        self._stray_ok = False  # a recovery released a bank whose interrupt may still come
        # the DDR ring (docs/feature-dma.md): CFG_DDR, the memory and the layout (None: the banks)
        self.window: DdrWindow | None = None
        self.memory: FrameMemory | None = None
        self.ring: RingLayout | None = None
        self._pending = 0  # ring buffers READY that wait_frame has not handed out yet (a bit each)
        self._last = 0  # the ring buffer handed out last: the next is looked for from the one after it
        self._unreleased: set[int] = set()  # ring buffers whose release was cut by a bus error
        version = (regs.VERSION_MAJOR, regs.VERSION_MINOR)
        if check_id:
            ident = self.read(regs.ID)
            if ident != regs.ORB_ID:
                raise AccelError(f"ID reads {ident:#010x}, not {regs.ORB_ID:#010x} ('ORB1'): not an ORB accelerator")
            major, minor = version = self.version()
            if major != regs.VERSION_MAJOR:
                raise AccelError(f"register map version {major}.{minor}: this driver reads version "
                                 f"{regs.VERSION_MAJOR}.x (docs/registers.md)")  # fmt: skip
            self.records_params = (major, minor) >= PARAMS_VERSION
        else:
            self.records_params = True  # unchecked: taken to be this driver's map
        self.hw = self.read_config()
        if version >= DDR_VERSION:
            self.window = DdrWindow.from_register(self.read(regs.CFG_DDR))
        # the mode frames are decoded in: CTRL's (another program may have configured the device),
        # then whatever configure() sets; a frame keeps the mode that was set when it started
        ctrl = self.read(regs.CTRL)
        self.mode = MODES[regs.CTRL.field("mode").get(ctrl)]
        self.enabled = bool(regs.CTRL.field("enable").get(ctrl))
        self._mode_before = self.mode
        thr, sel = self.read(regs.THRESHOLD), self.read(regs.SELECT)
        self.threshold = regs.THRESHOLD.field("threshold").get(thr)
        self.selection = Selection(
            mode=SELECTIONS[regs.SELECT.field("mode").get(sel)],  # 0 all, 1 grid (2, 3 are refused)
            budget=regs.SELECT.field("budget").get(sel),
            cells=(regs.SELECT.field("cols").get(sel), regs.SELECT.field("rows").get(sel)),
            threshold_lo=regs.THRESHOLD.field("low").get(thr),
        )
        self.released_at_open: list[int] = []
        if self.ddr:
            if memory is not None:
                self.released_at_open = self.open_ring(memory, ring_count)
            elif release_stale:
                raise ValueError("this accelerator writes its features to a DDR ring (CFG_DDR.ddr = 1): open it "
                                 "with memory= (orb_accel.ddr: UDmaBuf, PynqMemory, ArrayMemory; the command "
                                 "line's --ddr-memory), docs/driver.md, Features from DDR")  # fmt: skip
        elif release_stale:
            self.released_at_open = self.recover()

    # ---- the DDR ring --------------------------------------------------------------------------
    @property
    def ddr(self) -> bool:
        """Whether the accelerator writes its features to the DDR ring (CFG_DDR.ddr)."""
        return self.window is not None and self.window.ddr

    def open_ring(self, memory: FrameMemory | MemoryFactory, count: int | None = None, offset: int | None = None,
                  stride: int | None = None) -> list[int]:  # fmt: skip
        """Lay the ring out in `memory` (or in what the callable opens for the bytes `count`
        buffers take, default 16), check it (orb_accel.ring.plan_ring: ValueError naming the
        broken rule, before anything is written), stop the accelerator, drop the CPU's cache lines
        of the ring, write RING_BASE, RING_STRIDE and RING_COUNT, soft-reset, check RING_STATUS.error
        (AccelError with its bits decoded) and restore CTRL.enable. Returns the buffers that were
        READY before the reset (a dead predecessor's, freed by it; counted in faults.stale_banks)."""
        if self.window is None or not self.window.ddr:
            raise AccelError("this accelerator keeps its features in block-RAM banks (no DDR ring: CFG_DDR.ddr 0 "
                             "or a register map before 3.2)")  # fmt: skip
        depth = self.hw.mem_depth
        if not isinstance(memory, FrameMemory):
            memory = memory((count or MAX_BUFFERS) * depth * SLOT_BYTES + 64)
        layout = plan_ring(memory, depth, self.window, count, offset, stride)
        ctrl = self.read(regs.CTRL)
        stopped = regs.CTRL.field("enable").put(0, ctrl)
        self.write(regs.CTRL, stopped)
        ready = regs.RING_STATUS.field("ready").get(self.read(regs.RING_STATUS))
        # no line of the ring may be dirty in the CPU's caches once the device writes it (the CPU
        # never writes it; this drops whatever an earlier user of the memory left)
        memory.invalidate(layout.offset, layout.extent)
        self.write(regs.RING_BASE, layout.base)
        self.write(regs.RING_STRIDE, layout.stride)
        self.write(regs.RING_COUNT, layout.count)
        self.write(regs.CTRL, regs.CTRL.field("soft_reset").put(1, stopped))
        status = self.read(regs.RING_STATUS)
        error = regs.RING_STATUS.field("error").get(status)
        if error:
            raise AccelError(f"RING_STATUS.error = {error:#x} after writing RING_BASE {layout.base:#x}, RING_STRIDE "
                             f"{layout.stride:#x}, RING_COUNT {layout.count} (the accelerator stays stopped): "
                             f"{ring_error_text(error)}")  # fmt: skip
        self.write(regs.CTRL, ctrl)
        self.memory, self.ring = memory, layout
        self._held.clear()
        self._unreleased.clear()
        self._ring_restarted()
        stale = [i for i in range(MAX_BUFFERS) if ready >> i & 1]
        self.faults.stale_banks += len(stale)
        return stale

    def _ring_restarted(self) -> None:
        """After a soft reset: every buffer free, the next frame goes to buffer 0."""
        self._pending = 0
        self._last = self.ring.count - 1 if self.ring is not None else 0

    def _ring_layout(self) -> RingLayout:
        if self.ring is None:
            raise AccelError("this accelerator writes its features to a DDR ring, and this driver was opened "
                             "without memory (OrbAccel(bus, memory=...)): it can look, not read frames")  # fmt: skip
        return self.ring

    def _adopt(self, status: int) -> None:
        """Take RING_STATUS's READY buffers that are neither handed out nor being recovered as
        pending frames."""
        ring = self._ring_layout()
        ready = _RING_READY.get(status) & ((1 << ring.count) - 1)
        for i in self._held:
            ready &= ~(1 << i)
        for i in self._unreleased:
            ready &= ~(1 << i)
        self._pending = ready

    def _next_pending(self) -> int | None:
        """The pending buffer that comes first in ring order after the one handed out last."""
        n = self._ring_layout().count
        for k in range(1, n + 1):
            i = (self._last + k) % n
            if self._pending >> i & 1:
                self._pending &= ~(1 << i)
                self._last = i
                return i
        return None

    def dma_counters(self) -> dict[str, int]:
        """The DDR path's counters (DMA_COUNTERS, lower-case names): frames dropped, write error
        responses, W beats written."""
        return {name.lower(): self.read(getattr(regs, name)) for name in DMA_COUNTERS}

    def close(self) -> None:
        """Close the ring's memory if it has a close() (an UDmaBuf's mapping); the bus stays the
        caller's. The driver reads no frame after it."""
        memory, self.memory, self.ring = self.memory, None, None
        if memory is not None and hasattr(memory, "close"):
            memory.close()

    # ---- the bus, bus errors counted -----------------------------------------------------------
    def _call(self, op: Callable[..., _T], *args: object) -> _T:
        try:
            return op(*args)
        except BusError:
            self.faults.bus_errors += 1
            self._suspect = True
            raise

    # ---- registers -----------------------------------------------------------------------------
    def read(self, reg: regs.Register) -> int:
        if reg.access == "wo":
            raise ValueError(f"{reg.name} is write-only")
        try:  # _call, inline: every frame reads registers
            return self.bus.read32(reg.offset)
        except BusError:
            self.faults.bus_errors += 1
            self._suspect = True
            raise

    def write(self, reg: regs.Register, value: int) -> None:
        """Write a register; a write the register bank would refuse (SLVERR: a read-only register,
        a reserved bit, a field above its maximum) raises ValueError before it reaches the bus (on
        the board an error response to a CPU store is a SIGBUS, not an exception: docs/uio.md)."""
        if reg.access == "ro":
            raise ValueError(f"{reg.name} is read-only")
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value <= 0xFFFFFFFF:
            raise ValueError(f"{reg.name}: {value!r} is not a 32-bit value")
        if reg.access != "w1c":
            generics = {"MEM_DEPTH_g": self.hw.mem_depth} if hasattr(self, "hw") else None
            if not reg.legal(int(value), generics):
                allowed = ", ".join(f"{f.name} {f.min or 0}..{self._field_max(f)}" for f in reg.fields)
                raise ValueError(
                    f"{reg.name}: {int(value):#x} sets a reserved bit or a field above its maximum ({allowed})"
                )
        try:  # _call, inline
            self.bus.write32(reg.offset, int(value))
        except BusError:
            self.faults.bus_errors += 1
            self._suspect = True
            raise

    def _field_max(self, f: regs.Field) -> int:
        top = (1 << f.width) - 1 if f.max is None else f.max
        if f.max_generic == "MEM_DEPTH_g" and hasattr(self, "hw"):
            top = min(top, self.hw.mem_depth - 1)
        return top

    def read_config(self) -> HwConfig:
        size, orb, mem = self.read(regs.CFG_SIZE), self.read(regs.CFG_ORB), self.read(regs.CFG_MEM)
        return HwConfig(
            width=regs.CFG_SIZE.field("width").get(size),
            height=regs.CFG_SIZE.field("height").get(size),
            scales=regs.CFG_ORB.field("scales").get(orb),
            sectors=regs.CFG_ORB.field("sectors").get(orb),
            mem_depth=regs.CFG_MEM.field("depth").get(mem),
            step_num=regs.CFG_ORB.field("step_num").get(orb),
            step_den=regs.CFG_ORB.field("step_den").get(orb),
        )

    def version(self) -> tuple[int, int]:
        v = self.read(regs.VERSION)
        return regs.VERSION.field("major").get(v), regs.VERSION.field("minor").get(v)

    def configure(self, threshold: int, mode: str = "orb", enable: bool = True,
                  irq: tuple[str, ...] = ("frame_done",), selection: str = "grid", budget: int | None = None,
                  cells: tuple[int, int] | None = None, threshold_lo: int | None = None) -> None:  # fmt: skip
        """FAST threshold (0..255), mode ("orb" or "fast"), enable, the interrupt sources to
        enable (of IRQ_SOURCES) and the selection (docs/selection.md): "grid" keeps at most
        `budget` features a frame (default HwConfig.default_budget(): the recommended one, at most
        a bank's capacity), the best of every cell of a `cells` = (columns, rows) grid over the frame
        first, at each level (default 8 x 6), with corners at `threshold_lo` (default
        RECOMMENDED_THRESHOLD_LO; at or above the threshold: none) where a cell has none at the
        threshold; "all" reports every feature at
        the threshold (a dense frame fills its bank and loses the rest: Frame.truncated). Applied
        from the next frame on. Raises ValueError on a bad value, before anything is written."""
        fields = {"threshold": threshold}
        if threshold_lo is not None:
            fields["threshold_lo"] = threshold_lo
        for name, value in fields.items():
            hi = (1 << regs.THRESHOLD.field("threshold").width) - 1
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value <= hi:
                raise ValueError(f"{name} {value!r} outside 0..{hi}")
        if selection not in SELECTIONS:
            raise ValueError(f"selection {selection!r} not one of {SELECTIONS}")
        budget = self.hw.default_budget() if budget is None else budget
        cols, rows = (RECOMMENDED_COLS, RECOMMENDED_ROWS) if cells is None else cells
        threshold_lo = RECOMMENDED_THRESHOLD_LO if threshold_lo is None else threshold_lo
        for name, value, f in (
            ("budget", budget, regs.SELECT.field("budget")),
            ("cell columns", cols, regs.SELECT.field("cols")),
            ("cell rows", rows, regs.SELECT.field("rows")),
        ):
            lo, hi = f.min or 0, self._field_max(f)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
                why = f" (a bank holds {self.hw.capacity} features)" if name == "budget" else ""
                raise ValueError(f"{name} {value!r} outside {lo}..{hi}{why}")
        if mode not in MODES:
            raise ValueError(f"mode {mode!r} not one of {MODES}")
        bad = [s for s in irq if s not in IRQ_SOURCES]
        if bad:
            raise ValueError(f"interrupt sources {bad} not among {IRQ_SOURCES}")
        irq_word = 0
        for s in irq:
            irq_word = regs.IRQ_ENABLE.field(s).put(1, irq_word)
        sel = regs.SELECT.field("mode").put(SELECTIONS.index(selection))
        sel = regs.SELECT.field("cols").put(int(cols), sel)
        sel = regs.SELECT.field("rows").put(int(rows), sel)
        self.write(regs.SELECT, regs.SELECT.field("budget").put(int(budget), sel))
        thr = regs.THRESHOLD.field("low").put(int(threshold_lo))
        self.write(regs.THRESHOLD, regs.THRESHOLD.field("threshold").put(int(threshold), thr))
        self.write(regs.IRQ_ENABLE, irq_word)
        ctrl = regs.CTRL.field("mode").put(MODES.index(mode))
        self.write(regs.CTRL, regs.CTRL.field("enable").put(int(enable), ctrl))
        self._mode_before = self.mode  # the frame in flight keeps it (settle)
        self.mode, self.enabled, self.threshold = mode, bool(enable), int(threshold)
        self.selection = Selection(selection, int(budget), (int(cols), int(rows)), int(threshold_lo))

    def written(self) -> FrameParams:
        """The parameters this driver last wrote (read back at open): those of every frame that
        starts after the write. A frame's own, as the accelerator sampled them, are Frame.params."""
        s = self.selection
        return FrameParams(self.threshold, s.threshold_lo, self.mode, s.mode, s.budget, *s.cells)

    def configure_as(self, cfg: Config, enable: bool = True, irq: tuple[str, ...] = ("frame_done",)) -> None:
        """configure() with a model configuration's threshold, mode and selection (budget, cells
        and low threshold in `grid`), so that a frame compares with golden_model.extract(img, cfg)."""
        grid = cfg.selection == "grid"
        self.configure(cfg.threshold, cfg.mode, enable, irq, cfg.selection, cfg.budget if grid else None,
                       (cfg.cols, cfg.rows) if grid else None, cfg.threshold_lo if grid else None)  # fmt: skip

    def settle(self, timeout_s: float) -> Frame:
        """Let the frame in flight pass after configure(): the accelerator samples thresholds,
        selection and mode at a frame's first pixel, so the first frame to finish after a change may have
        started before it. Acknowledges pending interrupts and releases the banks of frames that
        finished before (discarded), then reads and releases the next frame (returned, in the mode
        of its start); every later frame uses the new values."""
        old_mode = self._mode_before
        if self.ddr:
            return self._settle_ring(timeout_s, old_mode)
        # A frame that finished before this call is discarded with its interrupt: its bank must be
        # released too, or the accelerator, whose next frame waits for that bank, stops publishing
        # (the frames are skipped as overruns) while this waits for an interrupt that never comes.
        self.write(regs.IRQ_STATUS, 0xFFFFFFFF)
        ready = regs.STATUS.field("bank_ready").get(self.read(regs.STATUS))
        for b in range(regs.BANKS):
            if ready >> b & 1:
                self.release(b)
        while True:
            # a frame that finished between the acknowledgement and its release raised the
            # interrupt, but its bank is gone: wait on for the next one
            if not regs.IRQ_STATUS.field("frame_done").get(self.wait_irq(timeout_s)):
                continue
            status = self.read(regs.STATUS)
            bank = regs.STATUS.field("last_bank").get(status)
            if regs.STATUS.field("bank_ready").get(status) >> bank & 1:
                break
        with self.holding(bank) as bank:
            # decoded in its own mode (its record's), or without one in the mode of its start
            frame = self.read_bank(bank, mode=None if self.records_params else old_mode)
        self._mode_before = self.mode
        return frame

    def _settle_ring(self, timeout_s: float, old_mode: str) -> Frame:
        """settle() on the DDR ring: the frames already published are released unread."""
        ring = self._ring_layout()
        self.write(regs.IRQ_STATUS, 0xFFFFFFFF)
        status = self.read(regs.RING_STATUS)
        ready = regs.RING_STATUS.field("ready").get(status) & ((1 << ring.count) - 1)
        for i in range(ring.count):
            if ready >> i & 1 and i not in self._held:
                self.release(i)
        self._pending = 0
        if ready:  # the newest of them: the next frame goes to the buffer after it
            self._last = regs.RING_STATUS.field("last").get(status)
        with self.holding(self.wait_frame(timeout_s)) as index:
            frame = self.read_bank(index, mode=None if self.records_params else old_mode)
        self._mode_before = self.mode
        return frame

    def soft_reset(self) -> None:
        """Restart the data path and the counters (the registers keep their values; on the DDR
        ring every buffer is freed and the next frame goes to buffer 0)."""
        ctrl = self.read(regs.CTRL)
        self.write(regs.CTRL, regs.CTRL.field("soft_reset").put(1, ctrl))
        if self.ddr:
            self._ring_restarted()

    def counters(self) -> dict[str, int]:
        return {name: self.read(reg) for name, reg in _COUNTER_REGS}

    def status_text(self) -> str:
        """The status registers as one line (for error messages)."""
        names = ("RING_STATUS", "IRQ_STATUS", "CTRL") if self.ddr else ("STATUS", "IRQ_STATUS", "CTRL")
        parts = [f"{name} = {self.read(getattr(regs, name)):#x}" for name in names]
        counters = self.counters() | (self.dma_counters() if self.ddr else {})
        return ", ".join(parts + [f"{k} = {v}" for k, v in counters.items()])

    # ---- frames --------------------------------------------------------------------------------
    def wait_irq(self, timeout_s: float) -> int:
        """Wait for the interrupt, acknowledge it and return the IRQ_STATUS bits that were set.
        Raises TimeoutError (with the status registers) when none comes within timeout_s."""
        if not self._call(self.bus.wait_irq, timeout_s):
            self.faults.timeouts += 1
            raise TimeoutError(f"no interrupt within {timeout_s:g} s: {self.status_text()}")
        status = self.read(regs.IRQ_STATUS)
        self.write(regs.IRQ_STATUS, status)
        return status

    def wait_frame(self, timeout_s: float) -> int:
        """Wait for a frame-done interrupt (error interrupts are acknowledged and waited past) and
        return the bank of the newest complete frame. The caller must release it.

        Recovery (docs/driver.md, "Faults and recovery"): after a bus error cut an operation, the
        banks are checked first (recover()); on a timeout the banks nobody holds are released
        before TimeoutError is raised (a bank left READY stops the accelerator for good: it skips
        every frame whose bank is held), so that frames flow again when the video comes back.

        On the DDR ring: the index of the next READY buffer in ring order (after the one handed
        out last), with no bus access while buffers found READY by an earlier RING_STATUS read are
        left; else the wait for the interrupt, its acknowledgement and one RING_STATUS read."""
        if self.ddr:
            return self._wait_ring(timeout_s)
        if self._suspect:
            self.recover()
        while True:
            try:
                irq = self.wait_irq(timeout_s)
            except TimeoutError as exc:
                released = self.recover()
                if not released:
                    raise
                raise TimeoutError(f"{exc}; released bank(s) {released} that nobody held") from None
            if not regs.IRQ_STATUS.field("frame_done").get(irq):
                continue
            status = self.read(regs.STATUS)
            bank = regs.STATUS.field("last_bank").get(status)
            if regs.STATUS.field("bank_ready").get(status) >> bank & 1:
                break
            if not self._stray_ok:
                raise AccelError(f"frame-done interrupt but bank {bank} is not ready: STATUS = {status:#x}")
            self.faults.stray_irqs += 1  # its bank went in a recovery: wait on for the next frame
        self._stray_ok = False
        self._held.add(bank)
        return bank

    def _wait_ring(self, timeout_s: float) -> int:
        self._ring_layout()
        if self._suspect:
            self.recover()
        while True:
            index = self._next_pending()
            if index is not None:
                break
            try:
                irq = self.wait_irq(timeout_s)
            except TimeoutError as exc:
                released = self.recover()  # also takes READY buffers whose interrupt was lost
                if self._pending:
                    continue  # frames after all: a lost interrupt cost its wait, not the frames
                if not released:
                    raise
                raise TimeoutError(f"{exc}; released ring buffer(s) {released} whose release had failed") from None
            if _FRAME_DONE.get(irq):
                # a frame published between the last acknowledgement and the last RING_STATUS read
                # was taken then; its interrupt finds nothing new: wait on
                self._adopt(self.read(regs.RING_STATUS))
        self._held.add(index)
        return index

    def recover(self) -> list[int]:
        """Release the banks the accelerator shows READY that this driver does not hold, except the
        newest one while its frame-done interrupt is pending (a frame still to be taken): a killed
        predecessor's (at open), or one this driver lost track of (a bus error between the
        interrupt and the release; an interrupt lost). Their frames are lost and counted in
        faults.stale_banks. Returns the banks released (usually none).

        On the DDR ring, whose frames carry their own numbers: release the buffers whose release a
        bus error cut (counted in faults.stale_banks) and take every other READY buffer nobody
        holds as a frame to read (none is lost to a lost interrupt). Returns those released."""
        if self.ddr:
            return self._recover_ring()
        pending = regs.IRQ_STATUS.field("frame_done").get(self.read(regs.IRQ_STATUS))
        status = self.read(regs.STATUS)
        ready = regs.STATUS.field("bank_ready").get(status)
        newest = regs.STATUS.field("last_bank").get(status)
        stale = [b for b in range(regs.BANKS)
                 if ready >> b & 1 and b not in self._held and not (pending and b == newest)]  # fmt: skip
        for b in stale:
            self.release(b)
            self.faults.stale_banks += 1
            self._stray_ok = True  # a frame that finished after the reads above may have lost its bank
        self._suspect = False
        return stale

    def _recover_ring(self) -> list[int]:
        self._ring_layout()
        status = self.read(regs.RING_STATUS)
        ready = regs.RING_STATUS.field("ready").get(status)
        stale = sorted(i for i in self._unreleased if ready >> i & 1)
        for i in stale:
            self.release(i)
            self.faults.stale_banks += 1
        self._unreleased.clear()  # those no longer READY were released after all
        for i in stale:
            status &= ~(1 << i)
        self._adopt(status)
        self._suspect = False
        return stale

    def _read_ring(self, index: int, mode: str | None, counters: bool) -> Frame:
        """read_bank() on the DDR ring: buffer `index` from memory, no bus access but the counters."""
        ring = self._ring_layout()
        assert self.memory is not None
        if index not in range(ring.count):
            raise ValueError(f"ring buffer {index} outside 0..{ring.count - 1}")
        try:
            record = read_record(self.memory, ring, index)
        except ValueError as exc:
            raise AccelError(f"ring buffer {index}: slot 0 is {exc}") from None
        if record.count > self.hw.capacity:
            raise AccelError(f"ring buffer {index}: record count {record.count} above a buffer's {self.hw.capacity}")
        # decoded in place from the memory (new arrays: the buffer may be written again once released)
        return self._frame(index, slot_view(self.memory, ring, index, record.count), record, mode, counters)

    def _frame(self, bank: int, words: np.ndarray, record: EndOfFrame, mode: str | None, counters: bool) -> Frame:
        params = record.params if self.records_params else None
        if mode is None:
            mode = params.mode if params is not None else self.mode
        feats = decode_features(words, self.hw.sectors, descriptors=mode == "orb")
        feats.step = self.hw.step
        return Frame(bank, feats, record, mode, self.hw, self.counters() if counters else {}, params)

    def read_bank(self, bank: int, mode: str | None = None, counters: bool = True) -> Frame:
        """A ready bank's features and record (the bank stays held: see release), decoded in `mode`
        (default: the frame's own mode, from its record; from an accelerator whose records carry no
        parameters, the mode last configured), with the counters when `counters` (len(COUNTERS)
        more reads). On the DDR ring `bank` is a ring buffer's index (wait_frame's)."""
        if mode is not None and mode not in MODES:
            raise ValueError(f"mode {mode!r} not one of {MODES}")
        if self.ddr:
            return self._read_ring(bank, mode, counters)
        if bank not in range(regs.BANKS):
            raise ValueError(f"bank {bank} outside 0..{regs.BANKS - 1}")
        info = self.read(regs.BANK0_INFO if bank == 0 else regs.BANK1_INFO)
        count = regs.BANK0_INFO.field("count").get(info)
        base = regs.MEM_BASE + bank * self.hw.mem_depth * SLOT_BYTES
        if self.bank_read == "bank":
            block = self._call(self.bus.read_block, base, (count + 1) * SLOT_WORDS).reshape(count + 1, SLOT_WORDS)
            words = block[:count]  # whole slots: the decoder reads the words it needs
            record = decode_record(block[count, :SLOT_RECORD_WORDS])
        else:
            words = np.empty((count, SLOT_WORDS_USED), dtype=np.uint32)
            for s in range(count):
                words[s] = self._call(self.bus.read_block, base + s * SLOT_BYTES, SLOT_WORDS_USED)
            record = decode_record(self._call(self.bus.read_block, base + count * SLOT_BYTES, SLOT_RECORD_WORDS))
        if record.count != count:
            raise AccelError(f"bank {bank}: record count {record.count}, BANK{bank}_INFO count {count}")
        return self._frame(bank, words, record, mode, counters)

    def release(self, bank: int) -> None:
        """Give a bank back to the accelerator (after reading it); on the DDR ring a ring buffer
        (RING_RELEASE)."""
        if self.ddr:
            ring = self._ring_layout()
            if bank not in range(ring.count):
                raise ValueError(f"ring buffer {bank} outside 0..{ring.count - 1}")
            self._held.discard(bank)
            self._unreleased.add(bank)  # until the write is answered: a recovery then releases it
            self.write(regs.RING_RELEASE, bank)
            self._unreleased.discard(bank)
            return
        if bank not in range(regs.BANKS):
            raise ValueError(f"bank {bank} outside 0..{regs.BANKS - 1}")
        self._held.discard(bank)  # given back even if the write fails: a recovery then finds it READY
        self.write(regs.BANK_RELEASE, bank)

    @contextmanager
    def holding(self, bank: int) -> Iterator[int]:
        """Hold `bank` for the block; it is released on leaving, also when the block raises (then
        the block's exception propagates, with a note if the release failed too)."""
        try:
            yield bank
        except BaseException as exc:
            self._release_after(bank, exc)
            raise
        self.release(bank)

    def _release_after(self, bank: int, exc: BaseException) -> None:
        """Release `bank` after `exc` cut the work on it (a failed release is noted on `exc`)."""
        try:
            self.release(bank)
        except Exception as release_exc:  # e.g. the connection went with the block's error
            if hasattr(exc, "add_note"):  # Python 3.11+
                exc.add_note(f"bank {bank} could not be released: {release_exc}")

    @contextmanager
    def frame(self, timeout_s: float) -> Iterator[Frame]:
        """The next published frame, its bank held for the block and released on leaving."""
        with self.holding(self.wait_frame(timeout_s)) as bank:
            yield self.read_bank(bank)

    def next_frame(self, timeout_s: float) -> Frame:
        """The next published frame, read and released."""
        # `with self.frame(timeout_s) as f: return f`, without its two generators (every frame)
        bank = self.wait_frame(timeout_s)
        try:
            frame = self.read_bank(bank)
        except BaseException as exc:
            self._release_after(bank, exc)
            raise
        self.release(bank)
        return frame

    def frames(self, count: int | None, timeout_s: float) -> Iterator[Frame]:
        """`count` frames (None: forever), each read and released before it is yielded."""
        n = 0
        while count is None or n < count:
            yield self.next_frame(timeout_s)
            n += 1


class FrameSource(Protocol):
    """What gives the driver's frames, whatever carries them: OrbAccel (the accelerator on a bus) and
    orb_accel.remote.RemoteAccel (an `orb-accel serve` stream from another machine; docs/stream.md).
    A consumer written against it (`orb-accel board stream`, a ROS node) takes either: `hw` the
    accelerator's configuration, next_frame() one frame (TimeoutError when none comes within
    timeout_s: the bus's seconds for OrbAccel, wall seconds for RemoteAccel), frames() `count` of
    them (None: on and on), each one a Frame the consumer owns (its bank already released)."""

    hw: HwConfig

    def next_frame(self, timeout_s: float) -> Frame: ...

    def frames(self, count: int | None, timeout_s: float) -> Iterator[Frame]: ...
