#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Golden-model speed benchmark: wall time per frame for a set of configurations.

Each configuration runs the whole model (orb mode) on the bundled default photograph resized to
the configuration's size; the figure is the median of --repeat runs after one warm-up run.
Writes build/bench/model.json and prints a table.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from pathlib import Path

import cv2
import numpy as np

from golden_model import Config, extract
from golden_model.images import DEFAULT_IMAGE
from orb_tools.images import load_luma

CONFIGS = (
    (640, 480, 1, 8),
    (640, 480, 2, 8),
    (640, 480, 2, 16),
    (1280, 720, 2, 8),
    (1920, 1080, 2, 8),
    (1920, 1080, 4, 16),
)


def bench(img: np.ndarray, cfg: Config, repeat: int) -> tuple[float, int]:
    feats = extract(img, cfg)  # warm-up (pattern tables, caches)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        extract(img, cfg)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), len(feats)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--threshold", type=int, default=20)
    ap.add_argument("--out", type=Path, default=Path("build/bench/model.json"))
    args = ap.parse_args()
    base = load_luma(DEFAULT_IMAGE)
    rows = []
    print(f"{'size':>10} {'scales':>6} {'sectors':>7} {'features':>8} {'median s':>9}")
    for w, h, scales, n in CONFIGS:
        img = cv2.resize(base, (w, h), interpolation=cv2.INTER_CUBIC)
        cfg = Config(w, h, scales=scales, sectors=4 * n, threshold=args.threshold)
        seconds, count = bench(img, cfg, args.repeat)
        rows.append({"width": w, "height": h, "scales": scales, "sectors": 4 * n, "threshold": args.threshold,
                     "features": count, "median_s": round(seconds, 4)})  # fmt: skip
        print(f"{w:>5}x{h:<4} {scales:>6} {4 * n:>7} {count:>8} {seconds:>9.3f}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    meta = {"python": platform.python_version(), "numpy": np.__version__, "machine": platform.machine(),
            "cpu_count": os.cpu_count()}  # fmt: skip
    args.out.write_text(json.dumps({"meta": meta, "results": rows}, indent=2) + "\n")
    print(f"-> {args.out}")


if __name__ == "__main__":
    main()
