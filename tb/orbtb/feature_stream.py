# SPDX-License-Identifier: MIT
"""Feature-stream monitor and decoder for m_axis_feat (layout: hdl/orb_feat_pkg.vhd).

The monitor wakes only while tvalid is high, so an idle stream costs no Python per clock.
Beats decode into frames: the features between two end-of-frame beats, plus that beat's frame
number and drop count.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from cocotb.triggers import ReadOnly, RisingEdge

from golden_model.features import NO_SECTOR, Features

COORD_MASK = (1 << 12) - 1
SCORE_MASK = (1 << 12) - 1
EOF_BIT = 39


@dataclass
class Frame:
    beats: list[int] = field(default_factory=list)  # feature beats of this frame
    number: int = -1
    drops: int = 0
    eof_cycle: int = -1  # clock count when the end-of-frame beat was accepted

    def features(self, sectors_total: int = 0) -> Features:
        d = np.array(self.beats, dtype=np.int64)
        n = len(d)
        return Features(
            scale=(d >> 36) & 3, x=(d >> 12) & COORD_MASK, y=(d >> 24) & COORD_MASK, score=d & SCORE_MASK,
            sector=np.full(n, NO_SECTOR, dtype=np.int64), descriptor=np.zeros((n, 0), dtype=np.uint8),
            sectors_total=sectors_total,
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
            self.current.number = word & 0xFFFF
            self.current.drops = (word >> 16) & 0xFFFF
            self.frames.append(self.current)
            self.current = Frame()
        else:
            if (word >> EOF_BIT) & 1:
                raise AssertionError(f"end-of-frame flag without tlast: {word:#x}")
            self.current.beats.append(word)
