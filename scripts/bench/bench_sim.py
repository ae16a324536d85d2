#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""RTL simulation-speed benchmark (`make bench-sim`; docs/benchmarks.md): one full frame through
orb_accel_top, the RTL in GHDL (cocotb, orb_sim.jobs.accel_job) and GHDL's synthesised netlist in
Verilator (orb_sim.fast), side by side in one run, each checked bit-exact against the model.

For each size (default 640x480 and 1920x1080, 2 scales, 32 sectors, the bundled photograph
resized, 24-bit RGB, one pixel per clock): clocks of the frame, wall time of the frame (streaming
it and waiting for its interrupt), clocks per second; for the fast path also the Verilator build
time, measured separately into an empty cache (on unless `--no-cold-build`). Writes
build/bench/sim.json and prints a table.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import tempfile
import time
from pathlib import Path

import cv2

from golden_model import Config, extract, first_difference
from golden_model.features import read_csv
from golden_model.images import DEFAULT_IMAGE
from golden_model.luma import rgb_to_luma
from orb_sim.fast import build as fast_build
from orb_sim.fast.jobs import generics_for, run_accel_fast
from orb_sim.rtl_backend import run_accel_job
from orb_tools.images import load_rgb_or_grey

SIZES = ((640, 480, 2), (1920, 1080, 2))


def cold_build_s(cfg: Config) -> float:
    """Seconds to build the fast path of `cfg` into an empty cache (netlist + Verilator + C++)."""
    saved = fast_build.BUILD
    with tempfile.TemporaryDirectory() as tmp:
        fast_build.BUILD = Path(tmp)
        try:
            t0 = time.perf_counter()
            fast_build.build_fast(generics_for(cfg, colour=True))
            return time.perf_counter() - t0
        finally:
            fast_build.BUILD = saved


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", action="append", help="WxHxS, e.g. 1920x1080x2 (repeatable)")
    ap.add_argument("--no-ghdl", action="store_true", help="the fast path only")
    ap.add_argument("--no-cold-build", action="store_true", help="do not time a build into an empty cache")
    ap.add_argument("--out", type=Path, default=Path("build/bench/sim.json"))
    args = ap.parse_args()
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.size] if args.size else SIZES
    base = load_rgb_or_grey(DEFAULT_IMAGE)
    ghdl_backend = "llvm" if shutil.which("ghdl-llvm") and os.environ.get("ORB_GHDL_BACKEND") != "mcode" else "mcode"
    rows = []
    for w, h, scales in sizes:
        rgb = cv2.resize(base, (w, h), interpolation=cv2.INTER_CUBIC)
        cfg = Config(w, h, scales=scales, sectors=32, threshold=20, mode="orb")
        want = extract(rgb_to_luma(rgb), cfg)
        paths = ["verilator-netlist"] + ([] if args.no_ghdl else [f"ghdl-{ghdl_backend}-rtl"])
        for name in paths:
            with tempfile.TemporaryDirectory() as tmp:
                job = Path(tmp)
                t0 = time.perf_counter()
                if name == "verilator-netlist":
                    r = run_accel_fast(rgb, cfg, job, overlay=False)
                else:
                    r = run_accel_job(rgb, cfg, job, job / "sim.log", overlay=False)
                total = time.perf_counter() - t0
                feats = read_csv(job / "features.csv", sectors_total=cfg.sectors)
            lost = r["truncated"] + r["dropped_merge"]
            diff = first_difference(feats, want) if lost == 0 else f"{lost} features truncated or dropped"
            frame_s = r["frame_sim_wall_s"]
            row = {"path": name, "width": w, "height": h, "scales": scales, "features": len(feats),
                   "bit_exact": diff is None, "first_difference": diff, "frame_clocks": r["frame_cycles"],
                   "frame_wall_s": frame_s, "clocks_per_s": round(r["frame_cycles"] / frame_s) if frame_s else None,
                   "job_wall_s": round(total, 2)}  # fmt: skip
            if name == "verilator-netlist" and not args.no_cold_build:
                row["cold_build_s"] = round(cold_build_s(cfg), 1)
            rows.append(row)
            print(json.dumps(row), flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rows, indent=2) + "\n")
    print("\n| frame | path | frame wall time | clocks per second | features | bit-exact | cold build |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        build = f"{r['cold_build_s']} s" if "cold_build_s" in r else "-"
        print(f"| {r['width']}x{r['height']}x{r['scales']} | {r['path']} | {r['frame_wall_s']} s | "
              f"{r['clocks_per_s']:,} | {r['features']} | {'yes' if r['bit_exact'] else 'NO'} | {build} |")  # fmt: skip
    print(f"-> {args.out}")


if __name__ == "__main__":
    main()
