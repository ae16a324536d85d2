"""Where the viewpoint bench's score is lost: the detector or the descriptor (README.md here).

Per tilt, pooled over the set's photographs and the viewpoint bench's views, for each extractor:
repeatability (reference features inside the view with a feature of the view within 3 pixels of
their exact image, over those inside), the matching score (orb_tools.viewpoint_bench's) and the
descriptor's share (correct matches over repeatable features): a low repeatability is the
detector's or the selection's loss, a low share the descriptor's or the orientation's.

    .venv/bin/python -m research.viewpoint.diagnose --set tune [--seeds FILE] EXTRACTOR...
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from orb_tools import scale_bench as sb
from orb_tools import viewpoint_bench as vpb

from .bench import images, use_seeds


def repeatable(ref: sb.Points, got: sb.Points, hmat: np.ndarray, shape: tuple[int, ...]) -> tuple[int, int]:
    """(inside, repeatable) of the reference features under hmat."""
    h, w = shape[:2]
    ph = hmat @ np.vstack([ref.x, ref.y, np.ones(len(ref))])
    mx, my = ph[0] / ph[2], ph[1] / ph[2]
    b = sb.DESC_BORDER
    ins = (mx >= b) & (mx <= w - 1 - b) & (my >= b) & (my <= h - 1 - b)
    if not ins.any() or not len(got):
        return int(ins.sum()), 0
    d, _ = cKDTree(np.column_stack([got.x, got.y])).query(np.column_stack([mx[ins], my[ins]]))
    return int(ins.sum()), int((d <= sb.MATCH_RADIUS).sum())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("extractors", nargs="+")
    ap.add_argument("--set", choices=["tune", "held"], default="tune")
    ap.add_argument("--seeds", type=Path)
    args = ap.parse_args()
    if args.seeds:
        use_seeds(args.seeds)
    exts = [sb.parse_extractor(t) for t in args.extractors]
    sb.check_budgets(exts)
    tot: dict[tuple[str, float], np.ndarray] = {}
    for _name, img in images(args.set):
        refs, budgets = sb.references(img, exts)
        for tilt, axis, rot, sc in vpb.views():
            hmat = vpb.tilt_homography(img.shape, tilt, axis if axis != "-" else "x", rot, sc)
            warped = sb.warp(img, hmat)
            for e in exts:
                got = sb._extract(warped, e, budgets)
                inside, rep = repeatable(refs[e.name], got, hmat, img.shape)
                c = vpb.pair_counts(refs[e.name], got, hmat, img.shape)
                tot.setdefault((e.name, tilt), np.zeros(3, np.int64))[:] += (inside, rep, c[4])
    print(f"set {args.set}, seeds {args.seeds or 'model'}")
    print("| extractor | tilt | repeatability | matching score | correct / repeatable |")
    print("|---|---|---|---|---|")
    for (name, tilt), (inside, rep, correct) in tot.items():
        print(f"| {name} | {tilt:g} | {100 * rep / max(inside, 1):.2f} | {100 * correct / max(inside, 1):.2f} | "
              f"{100 * correct / max(rep, 1):.2f} |")


if __name__ == "__main__":
    main()
