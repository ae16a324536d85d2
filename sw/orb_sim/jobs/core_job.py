# SPDX-License-Identifier: MIT
"""Job (not a test): frames through orb_core, the streaming core alone, its feature stream
monitored directly. For `orb-accel extract --backend rtl --top core` and the threshold sweep
(scripts/bench/sweep_rtl.py) (orb_sim.rtl_backend.run_core_job starts it).

ORB_JOB_DIR holds frames.npy ((F, H, W) uint8) and job.json's input fields; the job writes
features_<i>.csv per frame and report.json (cycles, pixels, latency, wall time, per-frame drops,
the core's counters). ORB_JOB_THRESHOLDS and ORB_JOB_MODES are comma lists, one per frame;
ORB_JOB_SELECTION the selection of every frame (orb_sim.core_inputs: "all" or
"grid:BUDGET:COLSxROWS:LOW"). The stream of a grid frame is resolved as the feature memory does
(golden_model.featcodec.resolve_selection). It checks nothing against the model: its caller does.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge

from golden_model import write_csv
from orb_sim.cocotb_bus import PERIOD_NS
from orb_sim.core_inputs import SELECT_SETTLE, drive_selection
from orb_sim.feature_stream import FeatureMonitor
from orb_sim.video import Gaps, VideoSource

EOF_TIMEOUT_CYCLES = 5000


@cocotb.test()
async def core_job(dut) -> None:
    out = Path(os.environ["ORB_JOB_DIR"])
    frames = np.load(out / "frames.npy")
    thresholds = [int(v) for v in os.environ["ORB_JOB_THRESHOLDS"].split(",")]
    modes = os.environ["ORB_JOB_MODES"].split(",")
    selection = os.environ.get("ORB_JOB_SELECTION", "all")
    sectors_total = int(os.environ["ORB_SECTORS"])
    clk = dut.clk
    dut.rst.value = 1
    dut.threshold.value = thresholds[0]
    dut.mode_orb.value = int(modes[0] == "orb")
    drive_selection(dut, selection, thresholds[0])
    dut.m_axis_feat_tready.value = 1
    source = VideoSource(dut, clk)
    source.idle()
    cocotb.start_soon(Clock(clk, PERIOD_NS, unit="ns").start(start_high=False))
    await ClockCycles(clk, 4)
    dut.rst.value = 0
    await ClockCycles(clk, SELECT_SETTLE)
    monitor = FeatureMonitor(dut, clk)
    cocotb.start_soon(monitor.run())
    wall = time.perf_counter()
    for frame, t, mode in zip(frames, thresholds, modes, strict=True):
        dut.threshold.value = t
        dut.mode_orb.value = int(mode == "orb")
        drive_selection(dut, selection, t)
        await source.send_frame(frame, Gaps())
    latency = 0
    while len(monitor.frames) < len(frames) and latency <= EOF_TIMEOUT_CYCLES:
        await RisingEdge(clk)
        latency += 1
    wall = time.perf_counter() - wall
    for i, (got, mode) in enumerate(zip(monitor.frames, modes, strict=False)):
        write_csv(got.features(sectors_total, descriptors=mode == "orb"), out / f"features_{i}.csv")
    report = {
        "frames": len(frames), "frames_out": len(monitor.frames), "cycles": source.cycles,
        "pixels": int(frames[0].size) * len(frames), "latency_cycles": latency, "sim_wall_s": round(wall, 2),
        "frame_numbers": [f.number for f in monitor.frames], "drops": [f.drops for f in monitor.frames],
        "bad_pixels": int(dut.bad_pixels.value), "dropped": int(dut.dropped.value),
        "desc_lost": int(dut.desc_lost.value),
    }  # fmt: skip
    (out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
