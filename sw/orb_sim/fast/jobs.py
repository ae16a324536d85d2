# SPDX-License-Identifier: MIT
"""The fast path's jobs (docs/fast-sim.md): what orb_sim.jobs.accel_job does in GHDL, on the
Verilated netlist, with the same outputs, so `make sim FAST=1` and `orb-accel extract --backend
rtl-fast` report the same fields.

The shipped driver (orb_accel.OrbAccel over orb_sim.fast.sim.FastBus) configures the accelerator,
the frame streams in (24-bit RGB, or 8-bit luma), the driver waits for the frame-done interrupt,
reads the newest bank and releases it; the frame is then streamed again with the accelerator
disabled while the overlay output is captured. A "DDR" build (mem_kind "ddr": orb_feat_dma,
docs/feature-dma.md) writes its frames into the harness's memory through m_axi_feat and the
driver reads them from there (OrbAccel(memory=FastMemory(sim)): a ring of buffers in it).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from golden_model.config import Config
from golden_model.features import Features, write_csv
from golden_model.latency import AXIL_IRQ_LAT
from golden_model.overlay import marker_block_log2
from orb_accel.driver import Frame, OrbAccel

from ..rtl_backend import ACCEL_MEM_DEPTH  # the GHDL job's: the same simulated accelerator
from .build import build_fast
from .sim import FastBus, FastMemory, FastSim, FastSimError

# From orb_feat_mem's frame_done pulse to the irq output, AXIL_IRQ_LAT clocks: IRQ_STATUS is set at
# the edge that samples the pulse and the registered irq one edge later (docs/registers.md,
# Interrupts; docs/latency.md), so the edge that raises irq is AXIL_IRQ_LAT after the one that
# raised the pulse. The GHDL job measures the pulse itself (an internal signal, which a netlist
# does not have): latency = irq - AXIL_IRQ_LAT.
H_BLANK, V_BLANK = 16, 64  # as orb_sim.video.Gaps("blanking")
MEM_KINDS = ("bram", "ddr")  # golden_model's mem_kind: orb_accel_top's MEM_KIND_g "BRAM", "DDR"


def generics_for(cfg: Config, colour: bool, mem_depth: int = ACCEL_MEM_DEPTH, block_log2: int | None = None,
                 mem_kind: str = "bram") -> dict[str, int | str]:  # fmt: skip
    """orb_accel_top's generics for cfg (the overlay's block: marker_block_log2 unless given; the
    feature memory: MEM_KIND_g "DDR" for mem_kind "ddr", left at its default "BRAM" otherwise)."""
    if mem_kind not in MEM_KINDS:
        raise ValueError(f"mem_kind {mem_kind!r} not one of {MEM_KINDS}")
    block = marker_block_log2(cfg.scales) if block_log2 is None else block_log2
    generics: dict[str, int | str] = {
        "WIDTH_g": cfg.width, "HEIGHT_g": cfg.height, "SCALES_g": cfg.scales, "STEP_NUM_g": cfg.step_num,
        "STEP_DEN_g": cfg.step_den, "SECTORS_g": cfg.sectors, "BLOCK_LOG2_g": block,
        "MEM_DEPTH_g": mem_depth, "INPUT_g": "RGB" if colour else "LUMA",
    }  # fmt: skip
    if mem_kind == "ddr":
        generics["MEM_KIND_g"] = "DDR"
    return generics


def is_ddr(generics: Mapping[str, int | str]) -> bool:
    """Whether orb_accel_top with these generics writes its features to DDR (MEM_KIND_g "DDR")."""
    return str(generics.get("MEM_KIND_g", "BRAM")).upper() == "DDR"


def pack(img: np.ndarray) -> np.ndarray:
    """tdata words of an (H, W, 3) RGB frame (RGB packing) or an (H, W) luma frame."""
    c = img.astype(np.uint32)
    if img.ndim == 2:
        return c
    return (c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2]


def unpack(words: np.ndarray, colour: bool) -> np.ndarray:
    w = words.astype(np.uint32)
    if not colour:
        g = (w & 255).astype(np.uint8)
        return np.stack((g, g, g), axis=-1)
    return np.stack(((w >> 16) & 255, (w >> 8) & 255, w & 255), axis=-1).astype(np.uint8)


@dataclass
class FastAccel:
    """A FastSim of orb_accel_top with the shipped driver on it."""

    sim: FastSim
    bus: FastBus
    accel: OrbAccel
    colour: bool
    width: int
    height: int
    memory: FastMemory | None = None  # a DDR build's: the harness's memory, as the driver sees it

    @classmethod
    def start(cls, generics: Mapping[str, int | str], seed: int = 0, ring_count: int | None = None,
              coherent: bool = False) -> FastAccel:  # fmt: skip
        """The netlist with these generics, reset, and the driver on it; a DDR build's driver with
        the harness's memory (FastMemory; `coherent` False: the CPU's cache modelled, so the
        driver must invalidate what it reads) and a ring of `ring_count` buffers (default: as many
        as the memory holds, at most 16)."""
        sim = FastSim(build_fast(generics), seed=seed)
        sim.reset()
        bus = FastBus(sim)
        memory = FastMemory(sim, coherent=coherent) if is_ddr(generics) else None
        accel = OrbAccel(bus, bank_read="slot", memory=memory, ring_count=ring_count)
        return cls(sim, bus, accel, generics["INPUT_g"] != "LUMA", int(generics["WIDTH_g"]), int(generics["HEIGHT_g"]),
                   memory)  # fmt: skip

    def ddr_report(self) -> dict[str, int]:
        """A DDR build's figures: the DMA counters (DMA_DROPPED, DMA_BUS_ERRORS, DMA_BEATS) and the
        memory model's (bursts, responses by kind, the master's AXI rule violations, stalls)."""
        if self.memory is None:
            return {}
        axi = self.sim.axi_stats()
        keep = ("bursts", "beats", "okay", "slverr", "decerr", "protocol_errors", "aw_stall_clocks", "w_stall_clocks",
                "max_outstanding", "max_w_ahead")  # fmt: skip
        return {**self.accel.dma_counters(), **{f"axi_{k}": axi[k] for k in keep},
                "invalidations": self.memory.invalidations}  # fmt: skip

    @property
    def frame_clocks(self) -> int:
        return (self.width + H_BLANK) * self.height + V_BLANK

    def s(self, clocks: int) -> float:
        """Simulated seconds of `clocks` clocks (the driver's timeouts)."""
        return clocks * 10e-9

    def capture_overlay(self, img: np.ndarray) -> np.ndarray:
        """Stream `img` once with capture on and return the overlay frame it produced."""
        sim = self.sim
        sim.capture(True)
        sim.push_frame(pack(img), H_BLANK, V_BLANK)
        n = self.width * self.height
        if not sim.run_video(40 * self.frame_clocks):
            raise FastSimError("the overlay frame was not taken within 40 frame times")
        for _ in range(1000):
            data, flags = sim.captured()
            if len(data) >= n:
                break
            sim.run(64)
        sim.capture(False)
        if len(data) < n:
            raise FastSimError(f"the overlay output gave {len(data)} of {n} beats")
        if not flags[0] & 1:
            raise FastSimError("the overlay output's first beat has no tuser")
        return unpack(data[:n], self.colour).reshape(self.height, self.width, 3)


def run_accel_fast(img: np.ndarray, cfg: Config, job: Path, overlay: bool, seed: int = 0,
                   mem_depth: int = ACCEL_MEM_DEPTH, block_log2: int | None = None,
                   mem_kind: str = "bram") -> dict:  # fmt: skip
    """orb_accel_top's netlist in Verilator on one image, as orb_sim.rtl_backend.run_accel_job
    runs it in GHDL: writes job/features.csv (and job/overlay.npy) and returns the same report
    fields (frame_cycles, pixels, cycles_per_pixel, latency_cycles, dropped_merge, truncated,
    desc_lost, proto_errors, frame_sim_wall_s, features, bus_reads, bus_writes), plus build_s,
    mem_kind and, for "ddr", `ddr` (FastAccel.ddr_report)."""
    job.mkdir(parents=True, exist_ok=True)
    t_build = time.perf_counter()
    fa = FastAccel.start(generics_for(cfg, img.ndim == 3, mem_depth, block_log2, mem_kind), seed)
    build_s = time.perf_counter() - t_build
    accel, sim = fa.accel, fa.sim
    accel.configure_as(cfg)
    wall = time.perf_counter()
    sim.push_frame(pack(img), 0, 0)  # as the GHDL job: one pixel per clock, no blanking
    bank = accel.wait_frame(fa.s(40 * fa.frame_clocks))
    st = sim.stats()
    frame_s = time.perf_counter() - wall
    start_cycle = sim.frame_starts()[-1][1]
    ovl = None
    if overlay:
        accel.configure_as(cfg, enable=False)
    frame = accel.read_bank(bank)
    accel.release(bank)
    write_csv(frame.features, job / "features.csv")
    if overlay:
        ovl = fa.capture_overlay(img)
        np.save(job / "overlay.npy", ovl)
    counters = accel.counters()
    pixels = cfg.width * cfg.height
    frame_cycles = st["last_beat_cycle"] - start_cycle + 1
    return {
        "features": len(frame.features), "frame_cycles": frame_cycles, "pixels": pixels,
        "cycles_per_pixel": round(frame_cycles / pixels, 4),
        "latency_cycles": st["irq_rise_cycle"] - st["last_beat_cycle"] - AXIL_IRQ_LAT,
        "dropped_merge": counters["dropped"], "truncated": frame.record.truncated,
        "desc_lost": counters["desc_lost"], "proto_errors": counters["proto_errors"],
        "frame_sim_wall_s": round(frame_s, 3), "bus_reads": fa.bus.reads, "bus_writes": fa.bus.writes,
        "build_s": round(build_s, 1), "mem_kind": mem_kind, **({"ddr": fa.ddr_report()} if fa.memory else {}),
    }  # fmt: skip


def extract_fast(img: np.ndarray, cfg: Config, seed: int = 0) -> tuple[Features, dict]:
    """Features of one frame from the netlist in Verilator (no files), and the report."""
    import tempfile

    from golden_model.features import read_csv

    with tempfile.TemporaryDirectory() as tmp:
        r = run_accel_fast(img, cfg, Path(tmp), overlay=False, seed=seed)
        return read_csv(Path(tmp) / "features.csv", sectors_total=cfg.sectors, step=cfg.step), r


def run_video_fast(frames: np.ndarray, cfg: Config, seed: int = 0, mem_depth: int = ACCEL_MEM_DEPTH,
                   on_frame: Callable[[int, Frame], None] | None = None,
                   block_log2: int | None = None, mem_kind: str = "bram") -> tuple[list[Frame], dict]:  # fmt: skip
    """Frames ((N, H, W, 3) RGB or (N, H, W) luma) back to back with blanking through the netlist
    while the shipped driver reads frame k from one bank (ring buffer) as frame k+1 is written
    into the other, and releases each, as on the board. Returns every published frame (in order)
    and a report (frames sent and published, clocks, wall time, overrun, the longest input stall;
    for "ddr" the DMA and memory figures, `ddr`)."""
    colour = frames.ndim == 4
    fa = FastAccel.start(generics_for(cfg, colour, mem_depth, block_log2, mem_kind), seed)
    accel, sim = fa.accel, fa.sim
    accel.configure_as(cfg)
    t0, c0 = time.perf_counter(), sim.cycle
    for img in frames:
        sim.push_frame(pack(img), H_BLANK, V_BLANK)
    got: list[Frame] = []
    timeout = fa.s(40 * fa.frame_clocks)
    for _ in range(len(frames)):
        frame = accel.next_frame(timeout)
        got.append(frame)
        if on_frame is not None:
            on_frame(len(got) - 1, frame)
    wall = time.perf_counter() - t0
    st = sim.stats()
    counters = accel.counters()
    report = {"frames_sent": st["frames_started"], "frames_published": len(got), "clocks": sim.cycle - c0,
              "wall_s": round(wall, 2), "clocks_per_s": round((sim.cycle - c0) / wall) if wall else 0,
              "overrun": counters["overrun"], "longest_input_stall": st["longest_stall"], **counters,
              **({"ddr": fa.ddr_report()} if fa.memory else {})}  # fmt: skip
    sim.close()
    return got, report
