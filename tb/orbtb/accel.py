# SPDX-License-Identifier: MIT
"""Testbench support for orb_accel_top: clock and reset, a CPU model on AXI4-Lite (registers and
feature-memory banks read as docs/feature-memory.md lays them out), the colour video source and
an overlay-output capture. Generics come from the environment (ORB_WIDTH, ORB_HEIGHT,
ORB_SCALES, ORB_SECTORS, ORB_MEM_DEPTH, ORB_INPUT).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, ReadOnly, RisingEdge, with_timeout
from cocotbext.axi import AxiLiteBus, AxiLiteMaster

from golden_model import regs
from golden_model.featmem import SLOT_BYTES, SLOT_WORDS_USED, EndOfFrame, decode_features, decode_record
from golden_model.features import Features
from golden_model.luma import rgb_to_luma

from .unit import PERIOD_NS, set_axil_pauses
from .video import Gaps, VideoSource

BLANKING = Gaps("blanking")
OKAY, SLVERR = 0, 2
OP_TIMEOUT_NS = 5000 * PERIOD_NS  # no AXI4-Lite transaction may take longer: nothing hangs


class AccelBench:
    """The bench of orb_accel_top, or of a wrapper with other clock, reset and AXI4-Lite names
    (orb_accel_zynq: `AccelBench(dut, "aclk", "aresetn", reset_active_low=True, axil_prefix=
    "s_axi_ctrl")`)."""

    def __init__(self, dut, clk: str = "clk", reset: str = "rst", reset_active_low: bool = False,
                 axil_prefix: str = "s_axil") -> None:  # fmt: skip
        self.dut = dut
        self.clk = getattr(dut, clk)
        self.reset = getattr(dut, reset)
        self.reset_active = 0 if reset_active_low else 1
        self.axil_prefix = axil_prefix
        self.width = int(os.environ["ORB_WIDTH"])
        self.height = int(os.environ["ORB_HEIGHT"])
        self.scales = int(os.environ["ORB_SCALES"])
        self.n = int(os.environ["ORB_SECTORS"])
        self.depth = int(os.environ["ORB_MEM_DEPTH"])
        self.input = os.environ.get("ORB_INPUT", "RGB")
        self.video = VideoSource(dut, self.clk)
        self.captured: list[np.ndarray] = []
        self._capturing = False

    async def start(self, pause_prob: float = 0.0, seed: int = 1) -> None:
        dut = self.dut
        self.reset.value = self.reset_active
        self.video.idle()
        dut.m_axis_video_tready.value = 1
        cocotb.start_soon(Clock(self.clk, PERIOD_NS, unit="ns").start(start_high=False))
        # the bus model only once reset is asserted and the clock starts low (toolchain.md)
        bus = AxiLiteBus.from_prefix(dut, self.axil_prefix)
        self.axil = AxiLiteMaster(bus, self.clk, self.reset, reset_active_level=bool(self.reset_active))
        set_axil_pauses(self.axil, pause_prob, seed)
        await ClockCycles(self.clk, 4)
        self.reset.value = 1 - self.reset_active
        await RisingEdge(self.clk)

    def start_capture(self) -> None:
        """Capture every m_axis_video frame into `captured` from now on (Python every clock)."""
        if not self._capturing:
            self._capturing = True
            cocotb.start_soon(self._capture())

    # ---- CPU side ------------------------------------------------------------------------------
    async def read(self, addr: int) -> tuple[int, int]:
        resp = await with_timeout(self.axil.read(addr, 4), OP_TIMEOUT_NS, "ns")
        return int(resp.resp), int.from_bytes(resp.data, "little")

    async def read_reg(self, reg: regs.Register) -> int:
        resp, value = await self.read(reg.offset)
        assert resp == OKAY, f"read {reg.name}: resp {resp}"
        return value

    async def write(self, addr: int, value: int) -> int:
        resp = await with_timeout(self.axil.write(addr, value.to_bytes(4, "little")), OP_TIMEOUT_NS, "ns")
        return int(resp.resp)

    async def write_reg(self, reg: regs.Register, value: int) -> None:
        resp = await self.write(reg.offset, value)
        assert resp == OKAY, f"write {reg.name} = {value:#x}: resp {resp}"

    async def configure(self, threshold: int, mode: str = "orb", irq: int = 1, enable: int = 1) -> None:
        await self.write_reg(regs.THRESHOLD, threshold)
        await self.write_reg(regs.IRQ_ENABLE, irq)
        ctrl = regs.CTRL.field("enable").put(enable, regs.CTRL.field("mode").put(0 if mode == "orb" else 1))
        await self.write_reg(regs.CTRL, ctrl)

    async def wait_irq(self, timeout_clocks: int) -> None:
        for _ in range(timeout_clocks):
            if self.dut.irq.value == 1:
                return
            await RisingEdge(self.clk)
        raise AssertionError(f"no interrupt within {timeout_clocks} clocks")

    async def read_words(self, addr: int, count: int) -> list[int]:
        resp = await with_timeout(self.axil.read(addr, 4 * count), OP_TIMEOUT_NS * count, "ns")
        assert int(resp.resp) == OKAY, f"feature-memory read at {addr:#x}: resp {resp.resp}"
        return np.frombuffer(resp.data, dtype="<u4").tolist()

    async def read_bank(self, bank: int, mode: str = "orb") -> tuple[Features, EndOfFrame]:
        """The bank's features (canonical order) and its end-of-frame record, read as a CPU does:
        the count from BANKn_INFO, then every feature slot's words 0..9 and the record."""
        info = await self.read_reg(regs.BANK0_INFO if bank == 0 else regs.BANK1_INFO)
        count = regs.BANK0_INFO.field("count").get(info)
        base = regs.MEM_BASE + bank * self.depth * SLOT_BYTES
        words: list[int] = []
        for s in range(count):
            words += await self.read_words(base + s * SLOT_BYTES, SLOT_WORDS_USED)
        record = decode_record(await self.read_words(base + count * SLOT_BYTES, 5))
        assert record.count == count, f"bank {bank}: record count {record.count}, BANK{bank}_INFO count {count}"
        feats = decode_features(np.array(words, dtype=np.uint32), 4 * self.n, descriptors=mode == "orb")
        return feats, record

    async def release(self, bank: int) -> None:
        await self.write_reg(regs.BANK_RELEASE, bank)

    async def read_newest(self, mode: str = "orb") -> tuple[Features, EndOfFrame]:
        """After a frame-done interrupt: clear it, read the newest bank, release it."""
        await self.wait_irq(40 * self.width * self.height)
        await self.write_reg(regs.IRQ_STATUS, 1)
        status = await self.read_reg(regs.STATUS)
        bank = regs.STATUS.field("last_bank").get(status)
        assert regs.STATUS.field("bank_ready").get(status) >> bank & 1, f"bank {bank} not ready: {status:#x}"
        feats, record = await self.read_bank(bank, mode)
        await self.release(bank)
        return feats, record

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
