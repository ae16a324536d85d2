# SPDX-License-Identifier: MIT
"""The DDR ring as the driver sees it (docs/feature-dma.md; docs/driver.md, "Features from DDR"):
where its buffers lie in a FrameMemory (orb_accel.ddr), the checks the driver makes before it
writes RING_BASE, RING_STRIDE and RING_COUNT, the decoding of RING_STATUS.error, and the reading
of one published buffer from memory.

Buffer i (0 .. count - 1) starts at bus address base + i * stride and holds `depth` 64-byte
slots: slot 0 the frame's end-of-frame record, slots 1 .. count its features. A buffer is read
with two cache invalidations and no bus access: the record's 64 bytes, then count * 64 bytes of
features, decoded in place in one numpy pass (golden_model.featmem.decode_features, the bank
path's decoder, on a view of the memory: slot_view). numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from golden_model import regs
from golden_model.featmem import SLOT_BYTES, SLOT_RECORD_WORDS, SLOT_WORDS_USED, EndOfFrame, decode_record

from .ddr import FrameMemory

MAX_BUFFERS = regs.RING_COUNT.field("count").max or 16  # RING_COUNT.count: 1 .. 16 (0: off)
ALIGN = 64  # RING_BASE and RING_STRIDE: multiples of 64 (one slot, one 8-beat burst)
MIB = 1 << 20
# RING_STATUS.error's bits (docs/feature-dma.md, "The ring configuration and its checks")
RING_ERRORS = (
    ("unaligned", "RING_BASE or RING_STRIDE is not a multiple of 64"),
    ("overlap", "RING_COUNT > 1 and RING_STRIDE < depth * 64: the buffers overlap"),
    ("outside", "the ring leaves the fabric's DDR window (CFG_DDR win_base, win_size)"),
    ("off", "RING_COUNT is 0"),
)
SLOT_WORDS = SLOT_BYTES // 4


def ring_error_text(bits: int) -> str:
    """RING_STATUS.error decoded: 'bit 1 overlap (...), bit 2 outside (...)'; 'none' for 0."""
    names = [f"bit {k} {name} ({why})" for k, (name, why) in enumerate(RING_ERRORS) if bits >> k & 1]
    return ", ".join(names) if names else "none"


@dataclass(frozen=True)
class DdrWindow:
    """CFG_DDR: whether the features go to the DDR ring, and the window [base, base + size) MiB of
    bus addresses the fabric may write (WIN_BASE_MB_g, WIN_SIZE_MB_g)."""

    ddr: bool
    win_base_mb: int
    win_size_mb: int

    @classmethod
    def from_register(cls, word: int) -> DdrWindow:
        f = regs.CFG_DDR.field
        return cls(bool(f("ddr").get(word)), f("win_base").get(word), f("win_size").get(word))

    @property
    def start(self) -> int:
        return self.win_base_mb * MIB

    @property
    def end(self) -> int:
        return (self.win_base_mb + self.win_size_mb) * MIB

    def text(self) -> str:
        return f"[{self.start:#x}, {self.end:#x}) ({self.win_size_mb} MiB from {self.win_base_mb} MiB)"


@dataclass(frozen=True)
class RingLayout:
    """The ring in a FrameMemory: buffer i at byte `offset + i * stride` of the memory, bus address
    `base + i * stride`, `depth` slots of 64 bytes each."""

    offset: int  # byte offset of buffer 0 in the memory
    stride: int
    count: int
    depth: int
    phys_addr: int  # the memory's bus address

    @property
    def base(self) -> int:
        """RING_BASE: the bus address of buffer 0."""
        return self.phys_addr + self.offset

    @property
    def buffer_bytes(self) -> int:
        return self.depth * SLOT_BYTES

    @property
    def extent(self) -> int:
        """Bytes from buffer 0's start to the last buffer's end."""
        return (self.count - 1) * self.stride + self.buffer_bytes

    def buffer_offset(self, index: int) -> int:
        return self.offset + index * self.stride


def plan_ring(memory: FrameMemory, depth: int, window: DdrWindow, count: int | None = None, offset: int | None = None,
              stride: int | None = None) -> RingLayout:  # fmt: skip
    """The ring in `memory` for buffers of `depth` slots, checked against the memory and the
    fabric's window: `offset` of buffer 0 in the memory (default: the first 64-byte aligned bus
    address), `stride` (default depth * 64, buffers back to back), `count` buffers (default: as
    many as the memory holds, at most 16). Raises ValueError naming the rule a value breaks:
    count not in 1..16; a buffer address not 64-byte aligned; buffers overlapping (stride <
    depth * 64); the ring outside the memory; the ring outside the fabric's window."""
    phys, size = int(memory.phys_addr), int(memory.size)
    buffer_bytes = depth * SLOT_BYTES
    if offset is None:
        offset = -phys % ALIGN
    if stride is None:
        stride = buffer_bytes
    if count is None:
        room = size - offset
        count = min(MAX_BUFFERS, 1 + (room - buffer_bytes) // stride) if room >= buffer_bytes and stride > 0 else 0
        if count < 1:
            raise ValueError(f"DDR ring: count must be 1..{MAX_BUFFERS}, but the memory of {size:#x} bytes holds no "
                             f"buffer of {depth} slots ({buffer_bytes:#x} bytes) from offset {offset:#x}")  # fmt: skip
    for name, value in (("count", count), ("offset", offset), ("stride", stride)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise ValueError(f"DDR ring: {name} {value!r} is not an integer")
    count, offset, stride = int(count), int(offset), int(stride)
    if not 1 <= count <= MAX_BUFFERS:
        raise ValueError(f"DDR ring: count {count} not in 1..{MAX_BUFFERS} (RING_COUNT; 0 is off)")
    if offset < 0 or stride < 0:
        raise ValueError(f"DDR ring: offset {offset} and stride {stride} must not be negative")
    base = phys + offset
    if base % ALIGN or stride % ALIGN:
        raise ValueError(f"DDR ring: buffer addresses must be {ALIGN}-byte aligned (RING_BASE and RING_STRIDE "
                         f"multiples of {ALIGN}); base {base:#x}, stride {stride:#x}")  # fmt: skip
    if count > 1 and stride < buffer_bytes:
        raise ValueError(f"DDR ring: buffers overlap: stride {stride:#x} < depth {depth} x {SLOT_BYTES} = "
                         f"{buffer_bytes:#x} bytes")  # fmt: skip
    layout = RingLayout(offset, stride, count, depth, phys)
    if offset + layout.extent > size:
        raise ValueError(f"DDR ring: {count} buffer(s) of {buffer_bytes:#x} bytes at stride {stride:#x} from offset "
                         f"{offset:#x} end at byte {offset + layout.extent:#x}, outside the mapped memory of "
                         f"{size:#x} bytes")  # fmt: skip
    if base < window.start or base + layout.extent > window.end:
        raise ValueError(f"DDR ring: bus addresses [{base:#x}, {base + layout.extent:#x}) outside the fabric's DDR "
                         f"window {window.text()} (CFG_DDR win_base, win_size)")  # fmt: skip
    return layout


def read_record(memory: FrameMemory, layout: RingLayout, index: int) -> EndOfFrame:
    """Buffer `index`'s end-of-frame record (slot 0), after invalidating its 64 bytes. Raises
    ValueError if slot 0 is not a record."""
    at = layout.buffer_offset(index)
    memory.invalidate(at, SLOT_BYTES)
    words = np.frombuffer(memory.view(at, SLOT_BYTES), dtype="<u4")
    return decode_record(words[:SLOT_RECORD_WORDS])


def slot_view(memory: FrameMemory, layout: RingLayout, index: int, count: int) -> np.ndarray:
    """Buffer `index`'s `count` feature slots (slots 1 .. count), whole, as a read-only (count,
    SLOT_WORDS) uint32 view of the memory (no copy), after invalidating their count * 64 bytes. The
    view is the buffer's memory: decode it before the buffer is released (the device may then write
    it again); golden_model.featmem.decode_features reads it in place into new arrays."""
    at = layout.buffer_offset(index) + SLOT_BYTES
    n = count * SLOT_BYTES
    if n:
        memory.invalidate(at, n)
    return np.frombuffer(memory.view(at, n), dtype="<u4").reshape(count, SLOT_WORDS)


def read_slots(memory: FrameMemory, layout: RingLayout, index: int, count: int) -> np.ndarray:
    """Buffer `index`'s `count` feature slots (slots 1 .. count) as an (count, SLOT_WORDS_USED)
    uint32 array (a copy: the buffer may be written again once it is released), after invalidating
    their count * 64 bytes."""
    return np.array(slot_view(memory, layout, index, count)[:, :SLOT_WORDS_USED], dtype=np.uint32)
