#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""RTL simulation-speed benchmark: one full frame through orb_core in GHDL.

Runs the RTL backend (the cocotb testbench, one pixel per clock, no gaps) on the bundled
photograph resized to each size, checks the result equals the model, and records simulated
clocks, wall time and clocks per second in build/bench/sim.json.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

import cv2

from golden_model import Config, extract, first_difference
from golden_model.images import DEFAULT_IMAGE
from orb_sim.rtl_backend import extract_rtl
from orb_tools.images import load_luma

SIZES = ((640, 480, 2),)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--size", action="append", help="WxHxS, e.g. 1920x1080x2 (repeatable)")
    ap.add_argument("--mode", choices=("orb", "fast"), default="orb")
    ap.add_argument("--sectors", type=int, choices=(16, 32, 64), default=32)
    ap.add_argument("--out", type=Path, default=Path("build/bench/sim.json"))
    args = ap.parse_args()
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.size] if args.size else SIZES
    base = load_luma(DEFAULT_IMAGE)
    backend = "llvm" if shutil.which("ghdl-llvm") else "mcode"
    rows = []
    for w, h, scales in sizes:
        img = cv2.resize(base, (w, h), interpolation=cv2.INTER_CUBIC)
        cfg = Config(w, h, scales=scales, sectors=args.sectors, threshold=20, mode=args.mode)
        feats, report = extract_rtl(img, cfg, top="core")
        diff = first_difference(feats, extract(img, cfg))
        row = {"width": w, "height": h, "scales": scales, "mode": args.mode, "sectors": args.sectors,
               "ghdl_backend": backend, "features": len(feats), "dropped": report["dropped"],
               "desc_lost": report["desc_lost"],
               "bit_exact": diff is None, "clocks": report["cycles"], "sim_wall_s": report["sim_wall_s"],
               "clocks_per_s": round(report["cycles"] / report["sim_wall_s"]),
               "latency_cycles": report["latency_cycles"]}  # fmt: skip
        rows.append(row)
        print(json.dumps(row))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rows, indent=2) + "\n")
    print(f"-> {args.out}")


if __name__ == "__main__":
    main()
