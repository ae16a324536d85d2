# SPDX-License-Identifier: MIT
"""AXI4-Stream video source driving whole frames from numpy arrays, one pixel per clock.

Gap patterns: `none` (back to back), `blanking` (fixed idle cycles after each line and frame, as
video timing has) and `random` (seeded idle cycles between any two pixels). Kept lean: the frame
is flattened once, and per clock only the signals that change are written.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from cocotb.triggers import RisingEdge


@dataclass(frozen=True)
class Gaps:
    kind: str = "none"  # none | blanking | random
    h_blank: int = 16
    v_blank: int = 64
    idle_prob: float = 0.3
    seed: int = 1

    @staticmethod
    def parse(text: str) -> Gaps:
        if text in ("", "none"):
            return Gaps()
        if text == "blanking":
            return Gaps("blanking")
        if text.startswith("random"):
            seed = int(text.split(":")[1]) if ":" in text else 1
            return Gaps("random", seed=seed)
        raise ValueError(f"unknown gap pattern {text!r}")


class VideoSource:
    def __init__(self, dut, clk, prefix: str = "s_axis_video") -> None:
        self.clk = clk
        self.tdata = getattr(dut, f"{prefix}_tdata")
        self.tvalid = getattr(dut, f"{prefix}_tvalid")
        self.tuser = getattr(dut, f"{prefix}_tuser")
        self.tlast = getattr(dut, f"{prefix}_tlast")
        self.tready = getattr(dut, f"{prefix}_tready")
        self.cycles = 0

    def idle(self) -> None:
        self.tvalid.value = 0
        self.tuser.value = 0
        self.tlast.value = 0
        self.tdata.value = 0

    async def send_frame(self, frame: np.ndarray, gaps: Gaps = Gaps()) -> None:
        """Send one frame; returns after its last pixel has been accepted."""
        w = frame.shape[1]
        pixels = frame.astype(np.int64).ravel().tolist()
        rng = np.random.default_rng(gaps.seed) if gaps.kind == "random" else None
        idle = (rng.random(len(pixels)) < gaps.idle_prob).tolist() if rng is not None else None
        clk, tdata, tvalid, tuser, tlast = self.clk, self.tdata, self.tvalid, self.tuser, self.tlast
        valid_now = False
        for i, px in enumerate(pixels):
            if idle is not None and idle[i]:
                tvalid.value = 0
                valid_now = False
                await RisingEdge(clk)
                self.cycles += 1
            x = i % w
            tdata.value = px
            if not valid_now:
                tvalid.value = 1
                valid_now = True
            if i == 0:
                tuser.value = 1
            elif i == 1:
                tuser.value = 0
            if x == w - 1:
                tlast.value = 1
            elif x == 0:
                tlast.value = 0
            await RisingEdge(clk)
            self.cycles += 1
            while not self.tready.value:
                await RisingEdge(clk)
                self.cycles += 1
            if gaps.kind == "blanking" and x == w - 1:
                tvalid.value = 0
                valid_now = False
                blank = gaps.h_blank + (gaps.v_blank if i == len(pixels) - 1 else 0)
                for _ in range(blank):
                    await RisingEdge(clk)
                self.cycles += blank
        tvalid.value = 0
        tuser.value = 0
        tlast.value = 0
