# SPDX-License-Identifier: MIT
"""orb_accel_zynq, the flat Vivado wrapper of orb_accel_top: the same accelerator behind Xilinx-style
names (aclk, aresetn active low, s_axi_ctrl_* AXI4-Lite, s_axis_video_* / m_axis_video_*, irq).

- wrapper: the CPU model on s_axi_ctrl reads the ID, configures threshold, interrupt enable and
  CTRL.enable; two colour photographs stream through s_axis_video in the wrapper's packing (24-bit
  tdata, INPUT_g); after each frame-done interrupt the newest bank is read back (STATUS.last_bank,
  BANKn_INFO.count, slots words 0..9, the end-of-frame record) and compared with the golden model;
  m_axis_video carries frame 0 unchanged and frame 1 with frame 0's features drawn on it
  (render_marker_overlay). Then aresetn is pulled low in mid-frame: the registers return to their
  reset values, the interrupt drops, and the next good frame is published as frame 0, bit-exact.
"""

from __future__ import annotations

import warnings

import cocotb
import numpy as np
from cocotb.triggers import ClockCycles, ReadOnly, RisingEdge

from golden_model import regs
from golden_model.luma import rgb_to_luma
from golden_model.overlay import render_marker_overlay
from orb_sim.accel_bench import AccelBench
from orb_sim.video import Gaps
from orbtb.images import colour_photo
from orbtb.runner import run
from orbtb.scoreboard import check_frame, expected_features
from orbtb.unit import SIM_ENV

warnings.filterwarnings("ignore", category=DeprecationWarning)


@cocotb.test()
async def wrapper(dut) -> None:
    b = AccelBench(dut, "aclk", "aresetn", reset_active_low=True, axil_prefix="s_axi_ctrl")
    await b.start()
    b.start_capture()
    w, h, t = b.width, b.height, 25
    assert await b.read_reg(regs.ID) == regs.ORB_ID
    size = await b.read_reg(regs.CFG_SIZE)
    assert (regs.CFG_SIZE.field("width").get(size), regs.CFG_SIZE.field("height").get(size)) == (w, h)
    assert regs.CFG_MEM.field("depth").get(await b.read_reg(regs.CFG_MEM)) == b.depth
    await b.configure(threshold=t)
    frames = [colour_photo("astronaut", w, h), colour_photo("coffee", w, h)]
    exps = [expected_features(rgb_to_luma(f), b.scales, t, "orb", b.sectors) for f in frames]
    assert all(len(e) > 0 for e in exps), "a test photograph has no feature to compare"

    async def video() -> None:
        for f in frames:
            await b.send(f)

    cocotb.start_soon(video())
    for k in range(len(frames)):
        feats, record = await b.read_newest()
        check_frame(feats, exps[k], f"frame {k}")
        assert (record.frame, record.dropped, record.truncated) == (k, 0, 0), record
    while len(b.captured) < len(frames):
        await RisingEdge(b.clk)
    assert not np.any(b.captured[0] != frames[0]), "frame 0 has no earlier features: it must pass unchanged"
    want = render_marker_overlay(frames[1], exps[0], scales=b.scales)
    bad = np.argwhere(np.any(b.captured[1] != want, axis=-1))
    assert len(bad) == 0, f"overlay of frame 1: first differing pixel (y, x) = {tuple(bad[0])}"
    assert await b.read_reg(regs.FRAME_COUNT) == 2

    # aresetn in mid-frame: everything (registers included) is reset
    task = cocotb.start_soon(b.send(frames[1], Gaps()))
    await ClockCycles(dut.aclk, w * (h // 2))
    task.cancel()
    b.video.idle()
    dut.aresetn.value = 0
    await ClockCycles(dut.aclk, 2)
    await ReadOnly()
    assert dut.irq.value == 0 and dut.s_axi_ctrl_bvalid.value == 0 and dut.s_axi_ctrl_rvalid.value == 0
    await RisingEdge(dut.aclk)
    dut.aresetn.value = 1
    await ClockCycles(dut.aclk, 2)
    assert await b.read_reg(regs.THRESHOLD) == regs.THRESHOLD.reset_value(), "THRESHOLD kept over aresetn"
    assert await b.read_reg(regs.CTRL) == regs.CTRL.reset_value(), "CTRL kept over aresetn"
    assert await b.read_reg(regs.FRAME_COUNT) == 0
    await b.configure(threshold=t)
    await b.send(frames[0])
    feats, record = await b.read_newest()
    assert record.frame == 0, f"the first frame after aresetn is frame {record.frame}"
    check_frame(feats, exps[0], "frame after aresetn")
    for reg in (regs.DROPPED, regs.PROTO_ERRORS, regs.DISCARDED, regs.OVERRUN):
        assert await b.read_reg(reg) == 0, f"{reg.name} after aresetn"


def test_accel_zynq() -> None:
    generics = {"WIDTH_g": 128, "HEIGHT_g": 96, "SCALES_g": 2, "SECTORS_g": 32, "MEM_DEPTH_g": 256, "INPUT_g": "RBG"}
    run("orb_accel_zynq", "test_orb_accel_zynq", generics, env=SIM_ENV)
