# SPDX-License-Identifier: MIT
"""`--backend rtl`: the VHDL accelerator in GHDL on one image, through the job modules of
orb_sim.jobs (never through a test).

By default the complete accelerator, orb_accel_top, as `make sim` runs it (orb_sim.jobs.
accel_job): the shipped driver writes the registers over AXI4-Lite, the frame streams in (8-bit
luma, or 24-bit RGB for a colour array), and the driver reads the features back from the
feature memory (MEM_DEPTH_g = 4096 slots per bank: a frame with more than 4,095 features is
truncated, and the report says how many). `top="core"` runs orb_core alone (orb_sim.jobs.
core_job: its feature stream monitored directly; scripts/bench/sweep_rtl.py's threshold sweep uses it). Needs
the HDL (the checkout's hdl/, or the copy an installed wheel carries: orb_sim.hdl) and GHDL;
generics come from the image size and the options.
"""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path

import numpy as np

from golden_model.config import RECOMMENDED_NAME, Config, named
from golden_model.features import Features, read_csv
from golden_model.overlay import marker_block_log2

from .core_inputs import selection_text
from .hdl import BUILD, HDL, MANIFEST
from .runner import ToolMissing, run


class RtlUnavailable(RuntimeError):
    """The RTL backend cannot run here (no HDL, no simulator, a failed simulation)."""


# feature slots per bank of the simulated orb_accel_top when not told: the recommended configuration's
ACCEL_MEM_DEPTH = named(RECOMMENDED_NAME).mem_depth
MEM_KINDS = ("bram", "ddr")  # golden_model's mem_kind: MEM_KIND_g "BRAM" (the tops' default), "DDR"


def _simulate(toplevel: str, module: str, generics: dict, env: dict[str, str], log: Path) -> None:
    """Run a job module of orb_sim.jobs on an RTL top; RtlUnavailable when it cannot."""
    if not MANIFEST.is_file():
        raise RtlUnavailable(f"the RTL backend needs the HDL ({HDL} with its manifest)")
    log.parent.mkdir(parents=True, exist_ok=True)
    try:
        run(toplevel, module, generics, env=env, log_file=log)
    except ToolMissing as exc:
        raise RtlUnavailable(str(exc)) from None
    except (SystemExit, RuntimeError) as exc:
        raise RtlUnavailable(f"the simulation failed ({exc}); see {log}") from None


def run_accel_job(img: np.ndarray, cfg: Config, job: Path, log: Path, overlay: bool,
                  mem_depth: int = ACCEL_MEM_DEPTH, block_log2: int | None = None,
                  mem_kind: str = "bram") -> dict:  # fmt: skip
    """orb_accel_top driven as a CPU drives it (orb_sim.jobs.accel_job): the frame (H, W) luma or
    (H, W, 3) RGB streams in, the features are read back into job/features.csv; with `overlay`, a
    second pass captures job/overlay.npy. Returns job.json (frame_cycles, pixels, cycles_per_pixel,
    latency_cycles, dropped_merge, truncated, desc_lost, proto_errors, frame_sim_wall_s, features).
    The overlay's block is 2^block_log2 pixels (default: golden_model.overlay.marker_block_log2).
    mem_kind "ddr": the DDR build (MEM_KIND_g "DDR"), the frame written through m_axi_feat into the
    bench's emulated DDR and read by the driver from there (job.json's `mem_kind`, `ddr`)."""
    if mem_kind not in MEM_KINDS:
        raise ValueError(f"mem_kind {mem_kind!r} not one of {MEM_KINDS}")
    job.mkdir(parents=True, exist_ok=True)
    block = marker_block_log2(cfg.scales) if block_log2 is None else block_log2
    np.save(job / "input.npy", np.ascontiguousarray(img, dtype=np.uint8))
    generics = {"WIDTH_g": cfg.width, "HEIGHT_g": cfg.height, "SCALES_g": cfg.scales,
                "STEP_NUM_g": cfg.step_num, "STEP_DEN_g": cfg.step_den,
                "SECTORS_g": cfg.sectors, "MEM_DEPTH_g": mem_depth, "BLOCK_LOG2_g": block,
                "INPUT_g": "LUMA" if img.ndim == 2 else "RGB"}  # fmt: skip
    if mem_kind == "ddr":  # left out for "bram": the BRAM build keeps its build directory
        generics["MEM_KIND_g"] = "DDR"
    env = {"ORB_JOB_DIR": str(job), "ORB_JOB_THRESHOLD": str(cfg.threshold), "ORB_JOB_MODE": cfg.mode,
           "ORB_JOB_OVERLAY": "1" if overlay else "0", "ORB_JOB_SELECTION": cfg.selection,
           "ORB_JOB_BUDGET": str(cfg.budget), "ORB_JOB_CELLS": f"{cfg.cols}x{cfg.rows}",
           "ORB_JOB_THRESHOLD_LO": str(cfg.threshold_lo)}  # fmt: skip
    _simulate("orb_accel_top", "orb_sim.jobs.accel_job", generics, env, log)
    if not (job / "job.json").exists():
        raise RtlUnavailable(f"the simulation wrote no result; see {log}")
    return json.loads((job / "job.json").read_text())


def run_core_job(frames: list[np.ndarray], cfg: Config, thresholds: list[int], modes: list[str], job: Path,
                 log: Path) -> tuple[list[Features], dict]:  # fmt: skip
    """Frames (each (H, W) luma) back to back through orb_core (orb_sim.jobs.core_job) with one
    threshold and mode per frame and cfg's selection; returns each frame's features (a grid
    frame's stream resolved as the feature memory keeps it) and the job's report."""
    job.mkdir(parents=True, exist_ok=True)
    np.save(job / "frames.npy", np.stack([np.ascontiguousarray(f, dtype=np.uint8) for f in frames]))
    generics = {"WIDTH_g": cfg.width, "HEIGHT_g": cfg.height, "SCALES_g": cfg.scales,
                "STEP_NUM_g": cfg.step_num, "STEP_DEN_g": cfg.step_den, "SECTORS_g": cfg.sectors}  # fmt: skip
    selection = selection_text(cfg.selection, cfg.budget, (cfg.cols, cfg.rows), cfg.threshold_lo)
    env = {"ORB_JOB_DIR": str(job), "ORB_JOB_THRESHOLDS": ",".join(map(str, thresholds)),
           "ORB_JOB_MODES": ",".join(modes), "ORB_JOB_SELECTION": selection}  # fmt: skip
    _simulate("orb_core", "orb_sim.jobs.core_job", generics, env, log)
    if not (job / "report.json").exists():
        raise RtlUnavailable(f"the simulation wrote no result; see {log}")
    report = json.loads((job / "report.json").read_text())
    feats = [
        read_csv(job / f"features_{i}.csv", sectors_total=cfg.sectors, step=cfg.step)
        for i in range(report["frames_out"])
    ]
    return feats, report


def extract_rtl(img: np.ndarray, cfg: Config, log_dir: Path | None = None, top: str = "accel") -> tuple[Features, dict]:
    """Features of one frame from the RTL, and the simulation report (cycles, pixels,
    latency_cycles, sim_wall_s, dropped, desc_lost). `img` is (H, W) luma, or (H, W, 3) RGB for
    the accelerator top. `top`: "accel" (orb_accel_top) or "core" (orb_core)."""
    if top not in ("accel", "core"):
        raise ValueError(f"unknown RTL top {top!r} (accel or core)")
    log = (log_dir or BUILD / "rtl") / "sim.log"
    what = f"{cfg.width}x{cfg.height}, {cfg.scales} scale(s), {cfg.mode} mode"
    toplevel = "orb_accel_top" if top == "accel" else "orb_core"
    print(f"simulating {toplevel} {what} in GHDL (log: {log}) ...", flush=True)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        if top == "accel":
            r = run_accel_job(img, cfg, Path(tmp), log, overlay=False)
            feats = read_csv(Path(tmp) / "features.csv", sectors_total=cfg.sectors, step=cfg.step)
            report = {"cycles": r["frame_cycles"], "pixels": r["pixels"], "latency_cycles": r["latency_cycles"],
                      "sim_wall_s": r["frame_sim_wall_s"], "dropped": r["dropped_merge"] + r["truncated"],
                      "desc_lost": r["desc_lost"], "truncated": r["truncated"]}  # fmt: skip
        else:
            all_feats, r = run_core_job([img], cfg, [cfg.threshold], [cfg.mode], Path(tmp), log)
            if r["frames_out"] != 1:
                raise RtlUnavailable(f"orb_core published {r['frames_out']} frames for one; see {log}")
            feats = all_feats[0]
            report = {"cycles": r["cycles"], "pixels": r["pixels"], "latency_cycles": r["latency_cycles"],
                      "sim_wall_s": r["sim_wall_s"], "dropped": r["dropped"], "desc_lost": r["desc_lost"],
                      "bad_pixels": r["bad_pixels"]}  # fmt: skip
    report["total_wall_s"] = round(time.perf_counter() - t0, 2)
    return feats, report
