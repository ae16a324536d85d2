"""Viewpoint bench of candidate descriptor patterns (issue 39; README.md here).

The viewpoint bench (orb_tools.viewpoint_bench, its default views) on the tune set (scikit-image's
photographs fitted to 640x480, research.selection.photos) or on the held-out photographs
(build/eval/held/640x480, `make eval`), with the model's orbit seeds replaced by a seed file's
(research.pattern.orbit_learn --out FILE) for the extractors of ours. Prints the summary by tilt.

    .venv/bin/python -m research.viewpoint.bench --set tune [--seeds FILE] EXTRACTOR...
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import cv2

import golden_model.pattern as gp
from golden_model.images import to_luma
from orb_tools import scale_bench as sb
from orb_tools import viewpoint_bench as vpb


def use_seeds(path: Path) -> None:
    """Make the model's descriptor use the seed file's orbits (every sector count in it)."""
    data = json.loads(path.read_text())["seeds"]
    for sectors, rows in data.items():
        gp.ORBIT_SEEDS[int(sectors)] = tuple(tuple(float(v) for v in r) for r in rows)
    gp.rotated_patterns.cache_clear()


def images(which: str) -> list:
    if which == "tune":
        from research.selection.photos import load

        return load("tune")
    out = []
    for p in sorted(Path("build/eval/held/640x480").glob("*.png")):
        im = cv2.imread(str(p), cv2.IMREAD_COLOR)
        out.append((p.stem, to_luma(cv2.cvtColor(im, cv2.COLOR_BGR2RGB))))
    if not out:
        raise SystemExit("no photographs under build/eval/held/640x480: run orb-accel eval-photos build/eval/held")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("extractors", nargs="+")
    ap.add_argument("--set", choices=["tune", "held"], default="tune")
    ap.add_argument("--seeds", type=Path, help="orbit seed file (default: the model's)")
    ap.add_argument("--tilts", type=float, nargs="+", default=list(vpb.TILTS))
    args = ap.parse_args()
    if args.seeds:
        use_seeds(args.seeds)
    exts = [sb.parse_extractor(t) for t in args.extractors]
    _, summary = vpb.run(images(args.set), exts, tilts=args.tilts)
    print(f"set {args.set}, seeds {args.seeds or 'model'}")
    print("| extractor | tilt | score | inliers | h ok |")
    for r in summary:
        print(f"| {r['extractor']} | {r['tilt']} | {r['score_pct']} | {r['inlier_pct']} | {r['h_ok_pct']} |")


if __name__ == "__main__":
    main()
