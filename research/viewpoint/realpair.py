"""A real viewpoint pair with its published homography: OpenCV's graf1.png -> graf3.png with H1to3p.xml
(the affine-covariant benchmark's Graffiti scene, about 40 degrees of viewpoint change), from Debian's
opencv-doc (`orb-accel eval-photos` fetches it into build/eval/debian-cache). The viewpoint bench's
counts (orb_tools.viewpoint_bench.pair_counts) for each extractor, our count as OpenCV's budget.

    .venv/bin/python -m research.viewpoint.realpair [--seeds FILE] EXTRACTOR...
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from golden_model.images import to_luma
from orb_tools import scale_bench as sb
from orb_tools import viewpoint_bench as vpb

from .bench import use_seeds, use_steered

DATA = Path("build/eval/debian-cache/opencv-doc/usr/share/doc/opencv-doc/examples/data")


def load(name: str) -> np.ndarray:
    im = cv2.imread(str(DATA / name), cv2.IMREAD_COLOR)
    if im is None:
        raise SystemExit(f"{DATA / name} missing: run orb-accel eval-photos build/eval/held --cache build/eval/debian-cache")
    return to_luma(cv2.cvtColor(im, cv2.COLOR_BGR2RGB))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("extractors", nargs="+")
    ap.add_argument("--seeds", type=Path)
    ap.add_argument("--steered", action="store_true")
    args = ap.parse_args()
    if args.seeds:
        use_seeds(args.seeds)
    if args.steered:
        use_steered()
    a, b = load("graf1.png"), load("graf3.png")
    fs = cv2.FileStorage(str(DATA / "H1to3p.xml"), cv2.FILE_STORAGE_READ)
    h = fs.getFirstTopLevelNode().mat()
    exts = [sb.parse_extractor(t) for t in args.extractors]
    refs, budgets = sb.references(a, exts)
    print(f"graf1 -> graf3 ({a.shape[1]}x{a.shape[0]}), seeds {args.seeds or 'model'}{', steered' if args.steered else ''}")
    print("| extractor | features | inside | correct | score | homography inliers | correct homography |")
    for e in exts:
        c = vpb.pair_counts(refs[e.name], sb._extract(b, e, budgets), h, b.shape)
        print(f"| {e.name} | {c[0]} | {c[2]} | {c[4]} | {vpb.score(c):.2f} | {vpb.inlier_ratio(c):.2f} | {c[6]} |")


if __name__ == "__main__":
    main()
