# SPDX-License-Identifier: MIT
"""Job (not a test): the simulated accelerator as a server for another process's driver
(orb_sim.sim_server starts it; orb_sim.bus_server serves the bus).

The frames of ORB_JOB_DIR/frames.npy ((N, H, W, 3) RGB or (N, H, W) luma) stream into the
accelerator one after another, round and round, with horizontal and vertical blanking
(config.json: h_blank clocks per line, v_blank clocks per frame), as a camera would send them; the
CPU side is whoever connects to the socket. The job writes ORB_JOB_DIR/address ("127.0.0.1:PORT")
once it listens, and frames.log (one line per frame sent: sequence number, index in frames.npy,
clock of its first pixel). It ends when a client sends SHUTDOWN. A DDR build (MEM_KIND_g "DDR")
writes its frames into the bench's emulated DDR region (config.json's ddr: base and size;
orb_sim.ddr_ram on m_axi_feat), which the HELLO answer reports and MEM_READ reads
(orb_accel.socket_bus.SocketMemory on the client's side).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import cocotb
import numpy as np
from cocotb.task import bridge
from cocotb.triggers import RisingEdge

from orb_sim.accel_bench import AccelBench
from orb_sim.bus_server import listen, serve, server_info
from orb_sim.cocotb_bus import PERIOD_NS
from orb_sim.faults import FaultyBus, parse
from orb_sim.video import Gaps


@cocotb.test()
async def sim_server(dut) -> None:
    job = Path(os.environ["ORB_JOB_DIR"])
    cfg = json.loads((job / "config.json").read_text())
    frames = np.load(job / "frames.npy")
    ddr = cfg.get("ddr") or {}
    region = (int(ddr["base"]), int(ddr["size"])) if ddr else None
    if cfg["toplevel"] == "orb_accel_zynq":
        b = AccelBench(dut, "aclk", "aresetn", reset_active_low=True, axil_prefix="s_axi_ctrl", ddr_region=region)
    else:
        b = AccelBench(dut, ddr_region=region)
    await b.start()
    clk = b.clk
    clock = {"n": 0}

    async def count_clocks() -> None:
        while True:
            await RisingEdge(clk)
            clock["n"] += 1

    gaps = Gaps("blanking", h_blank=cfg["h_blank"], v_blank=cfg["v_blank"])
    log = open(job / "frames.log", "w", buffering=1)

    async def feed() -> None:
        seq = 0
        while True:
            k = seq % len(frames)
            log.write(f"{seq} {k} {clock['n']}\n")
            await b.send(frames[k], gaps)
            seq += 1

    cocotb.start_soon(count_clocks())
    cocotb.start_soon(feed())
    listener = listen(job, cfg["host"], cfg["port"])
    info = server_info(cfg, len(frames), PERIOD_NS, "ghdl", b.ram.region if b.ram is not None else None)
    try:
        await bridge(serve)(listener, FaultyBus(b.bus, [parse(f) for f in cfg.get("faults", [])]), info)
    finally:
        listener.close()
        log.close()
