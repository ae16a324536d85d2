# SPDX-License-Identifier: MIT
"""`--backend rtl`: run the VHDL accelerator in GHDL (through the cocotb testbench) on one image.

Needs a source checkout (hdl/ and tb/ next to this package) and GHDL; generics come from the
image size and the options. Both modes run: orb (sectors and descriptors) and fast.
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


def extract_rtl(img: np.ndarray, cfg: Config, log_dir: Path | None = None) -> tuple[Features, dict]:
    """Features of one frame from the RTL, and the simulation report (cycles, latency, wall time)."""
    if not (ROOT / "hdl").is_dir() or not (ROOT / "tb" / "orbtb").is_dir():
        raise RtlUnavailable(f"the RTL backend needs the source checkout (hdl/, tb/) next to {ROOT / 'golden_model'}")
    sys.path.insert(0, str(ROOT / "tb"))
    from orbtb.runner import ToolMissing, run

    log_dir = log_dir or ROOT / "build" / "rtl"
    log_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        frame_file, out = Path(tmp) / "frame.npy", Path(tmp) / "features.csv"
        np.save(frame_file, img)
        env = {"ORB_IMAGE_FILE": str(frame_file), "ORB_THRESHOLDS": str(cfg.threshold), "ORB_OUT": str(out),
               "ORB_MODES": cfg.mode}  # fmt: skip
        generics = {"WIDTH_g": cfg.width, "HEIGHT_g": cfg.height, "SCALES_g": cfg.scales,
                    "SECTORS_g": cfg.sectors_per_quadrant}  # fmt: skip
        log = log_dir / "sim.log"
        what = f"{cfg.width}x{cfg.height}, {cfg.scales} scale(s), {cfg.mode} mode"
        print(f"simulating {what} in GHDL (log: {log}) ...", flush=True)
        t0 = time.perf_counter()
        try:
            run("orb_detect_top", "test_orb_detect_top", generics, env=env, log_file=log)
        except ToolMissing as exc:
            raise RtlUnavailable(str(exc)) from None
        except (SystemExit, RuntimeError) as exc:
            raise RtlUnavailable(f"the simulation failed ({exc}); see {log}") from None
        if not out.exists():
            raise RtlUnavailable(f"the simulation wrote no features; see {log}")
        feats = read_csv(out, sectors_total=cfg.sectors)
        report = json.loads(out.with_suffix(".json").read_text())
        report["total_wall_s"] = round(time.perf_counter() - t0, 2)
    return feats, report
