# SPDX-License-Identifier: MIT
"""`--backend rtl`: run the VHDL accelerator in GHDL (through the cocotb testbench) on one image.

By default the complete accelerator, orb_accel_top, as `make sim` runs it: the CPU model writes
the registers over AXI4-Lite, the frame streams in (8-bit luma, or 24-bit RGB for a colour
array), and the features are read back from the feature memory (MEM_DEPTH_g = 4096 slots per
bank: a frame with more than 4,095 features is truncated, and the report says how many).
`top="detect"` runs orb_detect_top alone (its feature stream monitored directly; the simulation
speed benchmark uses it). Needs a source checkout (hdl/ and tb/ next to this package) and GHDL;
generics come from the image size and the options. Both modes run: orb and fast.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .config import Config
from .features import Features, read_csv

ROOT = Path(__file__).resolve().parents[1]


class RtlUnavailable(RuntimeError):
    """The RTL backend cannot run here (no source checkout, no simulator, unsupported mode)."""


ACCEL_MEM_DEPTH = 4096  # feature slots per bank of the simulated orb_accel_top (4,095 features)


def _simulate(toplevel: str, module: str, generics: dict, env: dict[str, str], log: Path,
              testcase: str | None = None) -> None:  # fmt: skip
    """Run a cocotb test module on an RTL top (tb/orbtb/runner.py); RtlUnavailable when it cannot."""
    if not (ROOT / "hdl").is_dir() or not (ROOT / "tb" / "orbtb").is_dir():
        raise RtlUnavailable(f"the RTL backend needs the source checkout (hdl/, tb/) next to {ROOT / 'golden_model'}")
    sys.path.insert(0, str(ROOT / "tb"))
    from orbtb.runner import ToolMissing, run

    log.parent.mkdir(parents=True, exist_ok=True)
    try:
        run(toplevel, module, generics, env={"COCOTB_REWRITE_ASSERTION_FILES": "test_*.py", **env}, testcase=testcase,
            log_file=log)  # fmt: skip
    except ToolMissing as exc:
        raise RtlUnavailable(str(exc)) from None
    except (SystemExit, RuntimeError) as exc:
        raise RtlUnavailable(f"the simulation failed ({exc}); see {log}") from None


def run_accel_job(img: np.ndarray, cfg: Config, job: Path, log: Path, overlay: bool) -> dict:
    """orb_accel_top driven as a CPU drives it (the `job` test of tb/test_orb_accel_top.py): the
    frame (H, W) luma or (H, W, 3) RGB streams in, the features are read back over AXI4-Lite into
    job/features.csv; with `overlay`, a second pass captures job/overlay.npy. Returns job.json
    (frame_cycles, pixels, cycles_per_pixel, latency_cycles, dropped_merge, truncated, desc_lost,
    proto_errors, frame_sim_wall_s, features)."""
    job.mkdir(parents=True, exist_ok=True)
    np.save(job / "input.npy", np.ascontiguousarray(img, dtype=np.uint8))
    generics = {"WIDTH_g": cfg.width, "HEIGHT_g": cfg.height, "SCALES_g": cfg.scales,
                "SECTORS_g": cfg.sectors_per_quadrant, "MEM_DEPTH_g": ACCEL_MEM_DEPTH,
                "INPUT_g": "LUMA" if img.ndim == 2 else "RGB"}  # fmt: skip
    env = {"ORB_JOB_DIR": str(job), "ORB_JOB_THRESHOLD": str(cfg.threshold), "ORB_JOB_MODE": cfg.mode,
           "ORB_JOB_OVERLAY": "1" if overlay else "0"}  # fmt: skip
    _simulate("orb_accel_top", "test_orb_accel_top", generics, env, log, testcase="job")
    if not (job / "job.json").exists():
        raise RtlUnavailable(f"the simulation wrote no result; see {log}")
    return json.loads((job / "job.json").read_text())


def extract_rtl(img: np.ndarray, cfg: Config, log_dir: Path | None = None, top: str = "accel") -> tuple[Features, dict]:
    """Features of one frame from the RTL, and the simulation report (cycles, pixels,
    latency_cycles, sim_wall_s, dropped, desc_lost). `img` is (H, W) luma, or (H, W, 3) RGB for
    the accelerator top."""
    if top not in ("accel", "detect"):
        raise ValueError(f"unknown RTL top {top!r}")
    log = (log_dir or ROOT / "build" / "rtl") / "sim.log"
    what = f"{cfg.width}x{cfg.height}, {cfg.scales} scale(s), {cfg.mode} mode"
    toplevel = "orb_accel_top" if top == "accel" else "orb_detect_top"
    print(f"simulating {toplevel} {what} in GHDL (log: {log}) ...", flush=True)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        if top == "accel":
            r = run_accel_job(img, cfg, Path(tmp), log, overlay=False)
            feats = read_csv(Path(tmp) / "features.csv", sectors_total=cfg.sectors)
            report = {"cycles": r["frame_cycles"], "pixels": r["pixels"], "latency_cycles": r["latency_cycles"],
                      "sim_wall_s": r["frame_sim_wall_s"], "dropped": r["dropped_merge"] + r["truncated"],
                      "desc_lost": r["desc_lost"], "truncated": r["truncated"]}  # fmt: skip
        else:
            frame_file, out = Path(tmp) / "frame.npy", Path(tmp) / "features.csv"
            np.save(frame_file, img)
            env = {"ORB_IMAGE_FILE": str(frame_file), "ORB_THRESHOLDS": str(cfg.threshold), "ORB_OUT": str(out),
                   "ORB_MODES": cfg.mode}  # fmt: skip
            generics = {"WIDTH_g": cfg.width, "HEIGHT_g": cfg.height, "SCALES_g": cfg.scales,
                        "SECTORS_g": cfg.sectors_per_quadrant}  # fmt: skip
            _simulate("orb_detect_top", "test_orb_detect_top", generics, env, log)
            if not out.exists():
                raise RtlUnavailable(f"the simulation wrote no features; see {log}")
            feats = read_csv(out, sectors_total=cfg.sectors)
            report = json.loads(out.with_suffix(".json").read_text())
    report["total_wall_s"] = round(time.perf_counter() - t0, 2)
    return feats, report
