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

import golden_model.pattern as gp
from orb_tools import scale_bench as sb
from orb_tools.images import load_luma
from orb_tools import viewpoint_bench as vpb


def use_seeds(path: Path) -> None:
    """Make the model's descriptor use the seed file's orbits (every sector count in it)."""
    data = json.loads(path.read_text())["seeds"]
    for sectors, rows in data.items():
        gp.ORBIT_SEEDS[int(sectors)] = tuple(tuple(float(v) for v in r) for r in rows)
    gp.rotated_patterns.cache_clear()


def use_steered(path: Path = Path(__file__).with_name("rbrief_base.json")) -> None:
    """Make the model's descriptor use a steered pattern: the project's earlier learned rBRIEF base
    pattern (256 integer tests, rbrief_base.json) rotated to each sector's angle and rounded half
    away from zero, as the earlier design did (not rotation-closed: a sector-dependent multiplexer
    per test point in hardware, docs/descriptor-design.md)."""
    import numpy as np

    base = np.array(json.loads(path.read_text())["pattern"], dtype=np.float64)

    def steered(n: int) -> np.ndarray:
        out = np.empty((4 * n, len(base), 4), dtype=np.int8)
        for s in range(4 * n):
            _, rounded = gp.rotate_points(base, s * 360.0 / (4 * n))
            out[s] = np.clip(rounded, -gp.PATTERN_RADIUS, gp.PATTERN_RADIUS)
        out.setflags(write=False)
        return out

    import golden_model.brief as gb

    gb.rotated_patterns = steered


def images(which: str) -> list:
    if which == "tune":
        from research.selection.photos import load

        return load("tune")
    out = [(p.stem, load_luma(p)) for p in sorted(Path("build/eval/held/640x480").glob("*.png"))]
    if not out:
        raise SystemExit("no photographs under build/eval/held/640x480: run orb-accel eval-photos build/eval/held")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("extractors", nargs="+")
    ap.add_argument("--set", choices=["tune", "held"], default="tune")
    ap.add_argument("--seeds", type=Path, help="orbit seed file (default: the model's)")
    ap.add_argument("--steered", action="store_true", help="the steered learned rBRIEF pattern instead (use_steered)")
    ap.add_argument("--tilts", type=float, nargs="+", default=list(vpb.TILTS))
    args = ap.parse_args()
    if args.seeds:
        use_seeds(args.seeds)
    if args.steered:
        use_steered()
    exts = [sb.parse_extractor(t) for t in args.extractors]
    _, summary = vpb.run(images(args.set), exts, tilts=args.tilts)
    print(f"set {args.set}, seeds {args.seeds or 'model'}{', steered rBRIEF' if args.steered else ''}")
    print("| extractor | tilt | score | inliers | h ok |")
    for r in summary:
        print(f"| {r['extractor']} | {r['tilt']} | {r['score_pct']} | {r['inlier_pct']} | {r['h_ok_pct']} |")


if __name__ == "__main__":
    main()
