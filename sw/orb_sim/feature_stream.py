# SPDX-License-Identifier: MIT
"""Feature-stream monitor and decoder for m_axis_feat (layout: hdl/common/orb_feat_pkg.vhd).

The monitor wakes only while tvalid is high, so an idle stream costs no Python per clock.
Beats decode into frames: the features between two end-of-frame beats, plus that beat's frame
number and drop count. A feature word (320 bits) holds score, x, y and scale, and, when the
merge carries descriptors, the orientation sector and the 256-bit descriptor (bit 64 + i = test
i, i.e. the descriptor's bytes little-endian from bit 64, as golden_model.brief packs them).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from cocotb.triggers import ReadOnly, RisingEdge

from golden_model.features import NO_SECTOR, Features

FEAT_BITS = 320
COORD_MASK = (1 << 12) - 1
SCORE_MASK = (1 << 12) - 1
EOF_BIT = 39
SECTOR_LO, SECTOR_BITS = 40, 6
DESC_LO, DESC_BITS = 64, 256
DESC_BYTES = DESC_BITS // 8
SECTOR_MASK = (1 << SECTOR_BITS) - 1
DESC_MASK = (1 << DESC_BITS) - 1
LOW_MASK = (1 << 40) - 1  # score, x, y, scale and the flags
# bits that are 0 in every feature beat: [39:38] and [63:46]
FEATURE_ZERO_MASK = (3 << 38) | (((1 << DESC_LO) - 1) & ~((1 << (SECTOR_LO + SECTOR_BITS)) - 1))
# bits that are 0 in every end-of-frame beat: all but [31:0] and [39]
EOF_ZERO_MASK = ((1 << FEAT_BITS) - 1) & ~((1 << 32) - 1) & ~(1 << EOF_BIT)


@dataclass(frozen=True)
class FeatureBeat:
    """One decoded feature word. ``sector`` and ``descriptor`` are 0 when the merge carries no
    descriptors; ``descriptor`` is the 256 bits as an int (bit i = test i); ``descriptor_bytes``
    gives golden_model's byte form."""

    scale: int
    x: int
    y: int
    score: int
    sector: int
    descriptor: int

    @property
    def descriptor_bytes(self) -> bytes:
        return self.descriptor.to_bytes(DESC_BYTES, "little")


def decode_feature(word: int) -> FeatureBeat:
    """Decode a feature beat (tlast = 0) of m_axis_feat."""
    return FeatureBeat(
        scale=(word >> 36) & 3, x=(word >> 12) & COORD_MASK, y=(word >> 24) & COORD_MASK, score=word & SCORE_MASK,
        sector=(word >> SECTOR_LO) & SECTOR_MASK, descriptor=(word >> DESC_LO) & DESC_MASK,
    )  # fmt: skip


@dataclass
class Frame:
    beats: list[int] = field(default_factory=list)  # feature beats of this frame
    number: int = -1
    drops: int = 0
    eof_cycle: int = -1  # clock count when the end-of-frame beat was accepted

    def decoded(self) -> list[FeatureBeat]:
        """The frame's feature beats decoded, in arrival order."""
        return [decode_feature(w) for w in self.beats]

    def features(self, sectors_total: int = 0, descriptors: bool = False) -> Features:
        """The frame's features in canonical order; fast mode (no sector, no descriptor) unless
        `descriptors`, which decodes the sector and the descriptor of every feature."""
        n = len(self.beats)
        d = np.array([w & LOW_MASK for w in self.beats], dtype=np.int64).reshape(n)
        if descriptors:
            beats = self.decoded()
            sector = np.array([b.sector for b in beats], dtype=np.int64).reshape(n)
            desc = np.frombuffer(b"".join(b.descriptor_bytes for b in beats), dtype=np.uint8).reshape(n, DESC_BYTES)
        else:
            sector, desc = np.full(n, NO_SECTOR, dtype=np.int64), np.zeros((n, 0), dtype=np.uint8)
        return Features(
            scale=(d >> 36) & 3, x=(d >> 12) & COORD_MASK, y=(d >> 24) & COORD_MASK, score=d & SCORE_MASK,
            sector=sector, descriptor=desc.copy(), sectors_total=sectors_total,
        ).sorted()  # fmt: skip


class FeatureMonitor:
    """Collects accepted beats of an AXI4-Stream into Frames."""

    def __init__(self, dut, clk, prefix: str = "m_axis_feat") -> None:
        self.clk = clk
        self.tdata = getattr(dut, f"{prefix}_tdata")
        self.tvalid = getattr(dut, f"{prefix}_tvalid")
        self.tready = getattr(dut, f"{prefix}_tready")
        self.tlast = getattr(dut, f"{prefix}_tlast")
        self.frames: list[Frame] = []
        self.current = Frame()
        self.cycle = 0  # clocks seen while active; an absolute count is kept by the test if needed

    async def run(self) -> None:
        clk, tvalid, tready = self.clk, self.tvalid, self.tready
        while True:
            await ReadOnly()
            if not tvalid.value:
                await RisingEdge(tvalid)
            await RisingEdge(clk)
            if tvalid.value and tready.value:
                self._accept(int(self.tdata.value), bool(self.tlast.value))

    def _accept(self, word: int, last: bool) -> None:
        if last:
            if not (word >> EOF_BIT) & 1:
                raise AssertionError(f"tlast beat without the end-of-frame flag: {word:#x}")
            if word & EOF_ZERO_MASK:
                raise AssertionError(f"end-of-frame beat with reserved bits set: {word:#x}")
            self.current.number = word & 0xFFFF
            self.current.drops = (word >> 16) & 0xFFFF
            self.frames.append(self.current)
            self.current = Frame()
        else:
            if (word >> EOF_BIT) & 1:
                raise AssertionError(f"end-of-frame flag without tlast: {word:#x}")
            if word & FEATURE_ZERO_MASK:
                raise AssertionError(f"feature beat with reserved bits set: {word:#x}")
            self.current.beats.append(word)
