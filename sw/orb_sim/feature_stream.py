# SPDX-License-Identifier: MIT
"""Feature-stream monitor and decoder for m_axis_feat (layout: docs/feature-word.md).

The monitor wakes only while tvalid is high, so an idle stream costs no Python per clock.
Beats decode into frames: the features between two end-of-frame beats, plus that beat's frame
number, drop count and the parameters the frame was processed with. Every word is checked and
decoded by golden_model.featcodec, the one codec of the layout (a feature word holds score, x, y
and scale, and, when the merge carries descriptors, the orientation sector and the 256-bit
descriptor).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from cocotb.triggers import ReadOnly, RisingEdge

from golden_model.featcodec import (
    FeatureBeat,
    decode_eof,
    decode_feature,
    decode_stream_features,
    eof_error,
    feature_error,
)
from golden_model.features import Features
from golden_model.frameparams import FrameParams

__all__ = ["FeatureBeat", "FeatureMonitor", "Frame", "decode_feature"]


@dataclass
class Frame:
    beats: list[int] = field(default_factory=list)  # feature beats of this frame
    number: int = -1
    drops: int = 0
    params: FrameParams | None = None  # the parameters its end-of-frame beat says it was processed with
    eof_cycle: int = -1  # clock count when the end-of-frame beat was accepted

    def decoded(self) -> list[FeatureBeat]:
        """The frame's feature beats decoded, in arrival order."""
        return [decode_feature(w) for w in self.beats]

    def features(self, sectors_total: int = 0, descriptors: bool = False) -> Features:
        """The frame's features in canonical order; fast mode (no sector, no descriptor) unless
        `descriptors`, which decodes the sector and the descriptor of every feature. Raises
        golden_model.featcodec.LayoutError at a beat that is not a well-formed feature word."""
        return decode_stream_features(self.beats, sectors_total, descriptors)


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
            if err := eof_error(word):
                raise AssertionError(f"tlast beat: {err}")
            eof = decode_eof(word)
            self.current.number, self.current.drops, self.current.params = eof.frame, eof.drops, eof.params
            self.frames.append(self.current)
            self.current = Frame()
        else:
            if err := feature_error(word):
                raise AssertionError(f"beat without tlast: {err}")
            self.current.beats.append(word)
