#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Threshold sweep of the RTL in orb mode on real photographs: bit-exactness and losses.

For each photograph and each number of scales, one GHDL simulation of orb_core (the job
orb_sim.jobs.core_job) streams the photograph back to back once per threshold; this script
compares every frame with the golden model (features, scores, sectors, descriptors) and fails on
any difference, and records per frame the feature count and the features dropped by the merge,
plus the descriptor path's lost count. Photographs: the bundled 640x480 default at thresholds 10..40 in
steps of 5, and scikit-image's four evaluation photographs at native size at 10, 25 and 40.
Results go to build/bench/sweep.json and a markdown table on stdout.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import skimage.data

from golden_model import Config, extract, first_difference
from golden_model.images import DEFAULT_IMAGE, to_luma
from orb_sim.rtl_backend import RtlUnavailable, run_core_job
from orb_tools.images import load_luma

ROOT = Path(__file__).resolve().parents[2]

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")


def photos(quick: bool) -> list[tuple[str, np.ndarray, list[int]]]:
    out = [("default_640x480", load_luma(DEFAULT_IMAGE), list(range(10, 41, 5)))]
    if not quick:
        out += [(name, to_luma(getattr(skimage.data, name)()), [10, 25, 40]) for name in PHOTOS]
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--scales", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--sectors", type=int, choices=(16, 32, 64), default=32)
    ap.add_argument("--quick", action="store_true", help="the default photograph only")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "bench" / "sweep.json")
    args = ap.parse_args()
    rows = []
    job, log = ROOT / "build" / "rtl" / "sweep", ROOT / "build" / "rtl" / "sweep.log"
    for name, img, thresholds in photos(args.quick):
        h, w = img.shape
        for scales in args.scales:
            cfg = Config(w, h, scales=scales, sectors=args.sectors, mode="orb")
            print(f"{name} {w}x{h}, {scales} scale(s), thresholds {thresholds} ...", flush=True)
            t0 = time.perf_counter()
            try:
                n = len(thresholds)
                got, report = run_core_job([img] * n, cfg, thresholds, ["orb"] * n, job, log)
            except RtlUnavailable as exc:
                print(f"FAILED: {exc}")
                return 1
            if report["frames_out"] != len(thresholds):
                print(f"FAILED: {report['frames_out']} of {len(thresholds)} frames came out; see {log}")
                return 1
            for t, feats, drops in zip(thresholds, got, report["drops"], strict=True):
                diff = first_difference(feats, extract(img, Config(w, h, scales, cfg.sectors, t)))
                if diff is not None:
                    print(f"FAILED: {name}, {scales} scale(s), threshold {t}: not bit-exact: {diff}")
                    return 1
                rows.append({"photo": name, "size": f"{w}x{h}", "scales": scales, "threshold": t,
                             "features": len(feats), "dropped": drops, "bit_exact": True})  # fmt: skip
            rows[-1]["desc_lost_total"] = report["desc_lost"]
            print(f"  bit-exact, dropped {sum(report['drops'])}, descriptors lost {report['desc_lost']}, "
                  f"{time.perf_counter() - t0:.0f} s", flush=True)  # fmt: skip
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rows, indent=2) + "\n")
    print("\n| photo | size | scales | threshold | features | dropped | bit-exact |\n|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['photo']} | {r['size']} | {r['scales']} | {r['threshold']} | {r['features']} | {r['dropped']} "
              f"| {'yes' if r['bit_exact'] else 'NO'} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
