#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Threshold sweep of the RTL in orb mode on real photographs: bit-exactness and losses.

For each photograph and each number of scales, one GHDL simulation of orb_core streams
the photograph back to back once per threshold; the testbench compares every frame with the
golden model (features, scores, sectors, descriptors) and fails on any difference, and the
report records per frame the feature count and the features dropped by the merge, plus the
descriptor path's lost count. Photographs: the bundled 640x480 default at thresholds 10..40 in
steps of 5, and scikit-image's four evaluation photographs at native size at 10, 25 and 40.
Results go to build/bench/sweep.json and a markdown table on stdout.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import skimage.data

from golden_model.images import DEFAULT_IMAGE, to_luma
from orb_tools.images import load_luma

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tb"))

from orbtb.runner import run  # noqa: E402

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
    for name, img, thresholds in photos(args.quick):
        h, w = img.shape
        for scales in args.scales:
            with tempfile.TemporaryDirectory() as tmp:
                frame_file, report_file = Path(tmp) / "frame.npy", Path(tmp) / "report.json"
                np.save(frame_file, img)
                env = {"ORB_IMAGE_FILE": str(frame_file), "ORB_THRESHOLDS": ",".join(map(str, thresholds)),
                       "ORB_MODES": "orb", "ORB_REPORT": str(report_file)}  # fmt: skip
                generics = {"WIDTH_g": w, "HEIGHT_g": h, "SCALES_g": scales, "SECTORS_g": args.sectors // 4}
                print(f"{name} {w}x{h}, {scales} scale(s), thresholds {thresholds} ...", flush=True)
                t0 = time.perf_counter()
                run("orb_core", "test_orb_core", generics, env=env,
                    log_file=ROOT / "build" / "rtl" / "sweep.log")  # fmt: skip
                if not report_file.exists():
                    print(f"FAILED: see {ROOT / 'build' / 'rtl' / 'sweep.log'}")
                    return 1
                report = json.loads(report_file.read_text())
            for f in report["per_frame"]:
                rows.append({"photo": name, "size": f"{w}x{h}", "scales": scales, "threshold": f["threshold"],
                             "features": f["features"], "dropped": f["dropped"],
                             "bit_exact": f["bit_exact"]})  # fmt: skip
            rows[-1]["desc_lost_total"] = report["desc_lost"]
            print(f"  bit-exact, dropped {sum(f['dropped'] for f in report['per_frame'])}, descriptors lost "
                  f"{report['desc_lost']}, {time.perf_counter() - t0:.0f} s", flush=True)  # fmt: skip
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rows, indent=2) + "\n")
    print("\n| photo | size | scales | threshold | features | dropped | bit-exact |\n|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['photo']} | {r['size']} | {r['scales']} | {r['threshold']} | {r['features']} | {r['dropped']} "
              f"| {'yes' if r['bit_exact'] else 'NO'} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
