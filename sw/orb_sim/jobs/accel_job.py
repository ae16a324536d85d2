# SPDX-License-Identifier: MIT
"""Job (not a test): one image through orb_accel_top as a CPU drives it, for `make sim` and
`orb-accel extract --backend rtl` (orb_sim.rtl_backend.run_accel_job starts it).

The shipped driver (orb_accel.OrbAccel) configures the accelerator over AXI4-Lite; the frame
streams in; the driver waits for the frame-done interrupt, reads the newest bank and releases it.
Unless ORB_JOB_OVERLAY is 0, the image is streamed once more with the accelerator disabled to
capture the overlay of its features. Inputs and outputs are files in ORB_JOB_DIR: input.npy in;
features.csv, overlay.npy, job.json and progress.txt out. ORB_JOB_THRESHOLD, ORB_JOB_MODE (orb or
fast), ORB_JOB_SELECTION (all or grid), ORB_JOB_BUDGET, ORB_JOB_CELLS (COLSxROWS), ORB_JOB_THRESHOLD_LO. It checks
nothing against the model: its caller does. A DDR build (MEM_KIND_g "DDR") writes the frame into
the bench's emulated DDR (orb_sim.ddr_ram, through m_axi_feat) and the driver reads it from there;
job.json then has `mem_kind` "ddr" and `ddr` (the DMA counters, the region, the ring, the bytes
the RAM stored).
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import cocotb
import numpy as np
from cocotb.triggers import ClockCycles, RisingEdge

from golden_model import Config, write_csv
from golden_model.config import parse_cells
from orb_sim.accel_bench import AccelBench
from orb_sim.video import Gaps


@cocotb.test()
async def accel_job(dut) -> None:
    out = Path(os.environ["ORB_JOB_DIR"])
    progress = out / "progress.txt"
    rgb = np.load(out / "input.npy")
    with_overlay = os.environ.get("ORB_JOB_OVERLAY", "1") != "0"
    b = AccelBench(dut)
    await b.start()
    accel = b.accel
    env = os.environ
    cells = parse_cells(env.get("ORB_JOB_CELLS", "8x6"))
    cfg = Config(b.width, b.height, scales=b.scales, sectors=b.sectors, threshold=int(env["ORB_JOB_THRESHOLD"]),
                 mode=env.get("ORB_JOB_MODE", "orb"), step_num=b.step[0], step_den=b.step[1],
                 threshold_lo=int(env.get("ORB_JOB_THRESHOLD_LO", "255")),
                 selection=env.get("ORB_JOB_SELECTION", "all"), budget=int(env.get("ORB_JOB_BUDGET", "0")),
                 cols=cells[0], rows=cells[1])  # fmt: skip
    await b.cpu(accel.configure_as, cfg)
    wall = time.perf_counter()
    pixels = b.width * b.height
    edge = {"n": 0, "done": -1}

    async def clocks() -> None:
        while True:
            await RisingEdge(dut.clk)
            edge["n"] += 1
            # values read at an edge are those it samples: the pulse was set by the previous edge
            if edge["done"] < 0 and dut.mem_frame_done.value == 1:
                edge["done"] = edge["n"] - 1

    async def report_progress() -> None:
        while True:
            await ClockCycles(dut.clk, 10_000)
            done = min(b.video.cycles, pixels)
            progress.write_text(f"frame {done} {pixels} {time.perf_counter() - wall:.1f}\n")

    cocotb.start_soon(clocks())
    reporter = cocotb.start_soon(report_progress())
    first = edge["n"]
    await b.send(rgb, Gaps())
    last_pixel = edge["n"]  # the edge that accepted the frame's last pixel
    bank = await b.cpu(accel.wait_frame, b.clocks_to_s(b.frame_timeout_clocks))
    # from the edge that took the last pixel to the edge that wrote the end-of-frame record
    # (orb_feat_mem's frame_done pulse); +-1 clock for the order of coroutines at one edge
    latency = edge["done"] - last_pixel
    sim_frame_s = time.perf_counter() - wall
    reporter.cancel()
    progress.write_text(f"readback 0 {pixels} {sim_frame_s:.1f}\n")
    second = None
    if with_overlay:
        await b.cpu(accel.configure_as, cfg, False)
        b.start_capture()
        second = cocotb.start_soon(b.send(rgb))
    frame = await b.cpu(accel.read_bank, bank)
    await b.release(bank)
    write_csv(frame.features, out / "features.csv")
    if second is not None:
        await second
        while not b.captured:
            await RisingEdge(dut.clk)
        np.save(out / "overlay.npy", b.captured[0])
    counters = await b.cpu(accel.counters)
    report: dict[str, object] = {
        "features": len(frame.features),
        "frame_cycles": last_pixel - first + 1,
        "pixels": pixels,
        "cycles_per_pixel": round((last_pixel - first + 1) / pixels, 4),
        "latency_cycles": latency,
        "dropped_merge": counters["dropped"],
        "truncated": frame.record.truncated,
        "desc_lost": counters["desc_lost"],
        "proto_errors": counters["proto_errors"],
        "frame_sim_wall_s": round(sim_frame_s, 2),
        "bus_reads": b.bus.reads,
        "bus_writes": b.bus.writes,
        "mem_kind": "ddr" if b.ddr else "bram",
    }
    if b.ram is not None:
        ring = accel.ring
        assert ring is not None
        report["ddr"] = {**(await b.cpu(accel.dma_counters)), "region_base": b.ram.base, "region_size": b.ram.size,
                         "ring_base": ring.base, "ring_stride": ring.stride, "ring_count": ring.count,
                         "stored_bytes": b.ram.stored, "outside_writes": b.ram.outside_writes,
                         "invalidations": getattr(accel.memory, "invalidations", 0)}  # fmt: skip
    (out / "job.json").write_text(json.dumps(report, indent=2) + "\n")
