# SPDX-License-Identifier: MIT
"""The simulation bench of orb_accel_top (and its wrappers): clock and reset, the CPU side through
the shipped driver (orb_accel.OrbAccel on orb_sim.cocotb_bus.CocotbBus over AXI4-Lite), the
colour video source and an overlay-output capture. Used by the top-level tests and the jobs.
Generics come from the environment (ORB_WIDTH, ORB_HEIGHT,
ORB_SCALES, ORB_SECTORS, ORB_MEM_DEPTH, ORB_INPUT; ORB_STEP_NUM, ORB_STEP_DEN default 2:1;
ORB_MEM_KIND, default BRAM).

A DDR build (MEM_KIND_g "DDR", docs/feature-dma.md) gets its DDR: orb_sim.ddr_ram.RegionRam on
m_axi_feat, an emulated reserved region (`ddr_region`, default ORB_DDR_BASE / ORB_DDR_SIZE or
orb_sim.ddr_ram's DDR_BASE, DDR_SIZE), with random stalls on AW, W and B (start's `ddr_pause`), and
the driver reads its frames from there (OrbAccel(memory=ram.memory()), a ring of ORB_RING_COUNT
buffers, default as many as the region holds).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TypeVar

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.task import bridge
from cocotb.triggers import ClockCycles, ReadOnly, RisingEdge
from cocotbext.axi import AxiLiteBus, AxiLiteMaster

from golden_model import regs
from golden_model.featmem import EndOfFrame
from golden_model.features import Features
from golden_model.luma import rgb_to_luma
from orb_accel.bus import BusError
from orb_accel.driver import IRQ_SOURCES, HwConfig, OrbAccel

from .cocotb_bus import OKAY, PERIOD_NS, SLVERR, CocotbBus, set_axil_pauses
from .core_inputs import selection_text
from .ddr_ram import RegionRam, mem_kind, region_from_env
from .video import Gaps, VideoSource

__all__ = ["OKAY", "SLVERR", "AccelBench"]

T = TypeVar("T")
BLANKING = Gaps("blanking")


class AccelBench:
    """The bench of orb_accel_top, or of a wrapper with other clock, reset and AXI4-Lite names
    (orb_accel_zynq: `AccelBench(dut, "aclk", "aresetn", reset_active_low=True, axil_prefix=
    "s_axi_ctrl")`)."""

    def __init__(self, dut, clk: str = "clk", reset: str = "rst", reset_active_low: bool = False,
                 axil_prefix: str = "s_axil", ddr_region: tuple[int, int] | None = None) -> None:  # fmt: skip
        self.dut = dut
        self.clk = getattr(dut, clk)
        self.reset = getattr(dut, reset)
        self.reset_active = 0 if reset_active_low else 1
        self.axil_prefix = axil_prefix
        self.width = int(os.environ["ORB_WIDTH"])
        self.height = int(os.environ["ORB_HEIGHT"])
        self.scales = int(os.environ["ORB_SCALES"])
        self.sectors = int(os.environ["ORB_SECTORS"])  # in all (16, 32 or 64), as SECTORS_g
        self.step = (int(os.environ.get("ORB_STEP_NUM", "2")), int(os.environ.get("ORB_STEP_DEN", "1")))  # pyramid
        self.depth = int(os.environ["ORB_MEM_DEPTH"])
        self.block_log2 = int(os.environ.get("ORB_BLOCK_LOG2", "3"))  # the overlay's (orb_accel_top's default 3)
        self.input = os.environ.get("ORB_INPUT", "RGB")
        self.ddr = mem_kind() == "DDR"  # the features go to the DDR ring through m_axi_feat
        self.ddr_region = region_from_env() if ddr_region is None else ddr_region
        self.ram: RegionRam | None = None
        self.video = VideoSource(dut, self.clk)
        self.captured: list[np.ndarray] = []
        self._capturing = False
        self.frame_timeout_clocks = 40 * self.width * self.height  # a frame plus any legal back-pressure

    async def start(self, pause_prob: float = 0.0, seed: int = 1, ddr_pause: float | None = None) -> None:
        """Clock, reset, the AXI4-Lite master with random pauses (`pause_prob` on its five
        channels), a DDR build's RAM (stalls `ddr_pause` on AW, W, B; default pause_prob), the driver."""
        dut = self.dut
        self.reset.value = self.reset_active
        self.video.idle()
        dut.m_axis_video_tready.value = 1
        cocotb.start_soon(Clock(self.clk, PERIOD_NS, unit="ns").start(start_high=False))
        # the bus model only once reset is asserted and the clock starts low
        bus = AxiLiteBus.from_prefix(dut, self.axil_prefix)
        self.axil = AxiLiteMaster(bus, self.clk, self.reset, reset_active_level=bool(self.reset_active))
        set_axil_pauses(self.axil, pause_prob, seed)
        if self.ddr:
            self.ram = RegionRam(dut, self.clk, self.reset, bool(self.reset_active), *self.ddr_region)
            self.ram.set_pauses(pause_prob if ddr_pause is None else ddr_pause, seed)
        self.bus = CocotbBus(self.axil, self.clk, dut.irq, ram=self.ram)
        await ClockCycles(self.clk, 4)
        self.reset.value = 1 - self.reset_active
        await RisingEdge(self.clk)
        # checks the ID, reads the configuration; reads only the used words of a slot (each read costs clocks)
        ring_count = int(os.environ["ORB_RING_COUNT"]) if os.environ.get("ORB_RING_COUNT") else None
        memory = self.ram.memory() if self.ram is not None else None
        self.accel = await self.cpu(OrbAccel, self.bus, True, "slot", memory=memory, ring_count=ring_count)
        assert self.accel.hw == HwConfig(self.width, self.height, self.scales, self.sectors, self.depth, *self.step), (
            f"configuration read back {self.accel.hw}"
        )

    def start_capture(self) -> None:
        """Capture every m_axis_video frame into `captured` from now on (Python every clock)."""
        if not self._capturing:
            self._capturing = True
            cocotb.start_soon(self._capture())

    # ---- CPU side: the shipped driver (orb_accel.OrbAccel) over CocotbBus ------------------------
    async def cpu(self, fn: Callable[..., T], *args, **kwargs) -> T:
        """Run blocking driver code `fn(*args, **kwargs)` against the simulation."""
        return await bridge(fn)(*args, **kwargs)

    def clocks_to_s(self, clocks: int) -> float:
        return clocks * PERIOD_NS * 1e-9

    async def read(self, addr: int) -> tuple[int, int]:
        """(response, value) of one 32-bit read: OKAY or the error response, never an exception."""
        try:
            return OKAY, await self.cpu(self.bus.read32, addr)
        except BusError as exc:
            return exc.resp, 0

    async def write(self, addr: int, value: int) -> int:
        """The response to one 32-bit write."""
        try:
            await self.cpu(self.bus.write32, addr, value)
        except BusError as exc:
            return exc.resp
        return OKAY

    async def read_reg(self, reg: regs.Register) -> int:
        return await self.cpu(self.accel.read, reg)

    async def write_reg(self, reg: regs.Register, value: int) -> None:
        await self.cpu(self.accel.write, reg, value)

    async def configure(self, threshold: int, mode: str = "orb", irq: int = 1, enable: int = 1,
                        selection: str = "all", budget: int | None = None,
                        cells: tuple[int, int] | None = None,
                        threshold_lo: int | None = None) -> None:  # fmt: skip
        """The driver's configure (selection "all" unless told: the tests of the memory and the
        overlay count every feature; the driver's own default is "grid")."""
        sources = tuple(s for i, s in enumerate(IRQ_SOURCES) if irq >> i & 1)
        await self.cpu(self.accel.configure, threshold, mode, bool(enable), sources, selection, budget, cells,
                       threshold_lo)  # fmt: skip

    @property
    def selection(self) -> str:
        """The selection last configured, as orbtb's scoreboard spells it ("all" or
        "grid:BUDGET:COLSxROWS:LOW")."""
        sel = self.accel.selection
        return selection_text(sel.mode, sel.budget, sel.cells, sel.threshold_lo)

    async def wait_irq(self, timeout_clocks: int) -> None:
        """Wait for the interrupt line (not acknowledged)."""
        if not await self.cpu(self.bus.wait_irq, self.clocks_to_s(timeout_clocks)):
            raise AssertionError(f"no interrupt within {timeout_clocks} clocks")

    async def read_bank(self, bank: int) -> tuple[Features, EndOfFrame]:
        """The bank's features (canonical order, in the mode of the last configure) and its
        end-of-frame record, read by the driver."""
        frame = await self.cpu(self.accel.read_bank, bank)
        return frame.features, frame.record

    async def release(self, bank: int) -> None:
        await self.cpu(self.accel.release, bank)

    async def open_ring(self, count: int | None = None) -> list[int]:
        """A DDR build: lay the ring out again in the RAM (`count` buffers, default as many as it
        holds) and soft-reset (after a hard reset cleared RING_*, or to test another ring)."""
        assert self.ram is not None, "open_ring on a BRAM build"
        return await self.cpu(self.accel.open_ring, self.ram.memory(), count)

    async def read_newest(self) -> tuple[Features, EndOfFrame]:
        """The next frame through the driver: wait for its interrupt, acknowledge it, read the
        newest bank and release it."""
        frame = await self.cpu(self.accel.next_frame, self.clocks_to_s(self.frame_timeout_clocks))
        return frame.features, frame.record

    # ---- video ---------------------------------------------------------------------------------
    def pack(self, rgb: np.ndarray) -> np.ndarray:
        """tdata words of an (H, W, 3) RGB frame in this configuration's packing (for LUMA also an
        (H, W) grey frame, sent as it is)."""
        c = rgb.astype(np.int64)
        if self.input == "LUMA":
            return c if rgb.ndim == 2 else rgb_to_luma(rgb).astype(np.int64)
        if self.input == "RBG":
            return (c[..., 0] << 16) | (c[..., 2] << 8) | c[..., 1]
        return (c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2]

    def shown(self, rgb: np.ndarray) -> np.ndarray:
        """The (H, W, 3) RGB video the overlay passes for an input frame (grey for LUMA)."""
        if self.input == "LUMA":
            return np.repeat(rgb_to_luma(rgb)[..., None], 3, axis=2)
        return rgb

    async def send(self, rgb: np.ndarray, gaps: Gaps = BLANKING) -> None:
        await self.video.send_frame(self.pack(rgb), gaps)

    def unpack_out(self, words: np.ndarray) -> np.ndarray:
        """(H, W, 3) RGB of captured m_axis_video words (the input's packing; grey for LUMA)."""
        w = words.astype(np.int64)
        a, b, c = (w >> 16) & 255, (w >> 8) & 255, w & 255
        rgb = np.stack((a, c, b) if self.input == "RBG" else (a, b, c), axis=-1)
        return rgb.astype(np.uint8)

    async def _capture(self) -> None:
        """Collects m_axis_video frames of W x H beats; a frame cut by a reset is dropped."""
        dut = self.dut
        frame: list[int] = []
        while True:
            await RisingEdge(self.clk)
            await ReadOnly()
            if self.reset.value == self.reset_active:
                frame = []
            elif dut.m_axis_video_tvalid.value == 1 and dut.m_axis_video_tready.value == 1:
                assert (dut.m_axis_video_tuser.value == 1) == (not frame), "m_axis_video tuser not on a first beat"
                frame.append(int(dut.m_axis_video_tdata.value))
                if len(frame) == self.width * self.height:
                    words = np.array(frame, dtype=np.int64)
                    self.captured.append(self.unpack_out(words).reshape(self.height, self.width, 3))
                    frame = []
