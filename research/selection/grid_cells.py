# SPDX-License-Identifier: MIT
"""The selection's cell grid (2026-11-26): for each grid of GRIDS, the golden model's grid selection
(golden_model.select.select_grid with that cols x rows) on the 32 held-out photographs at 640x480,
1280x720 and 1920x1080, contrast 1 and 0.25, as `orb-accel density-bench` fits and scales them:
mean features, the frames with fewer features than OpenCV's defaults (cv2.ORB_create()), and the
8x6 corner cells left empty (research/selection/README.md, "The cell grid"). Run from the project root:
PYTHONPATH=sw:. .venv/bin/python research/selection/grid_cells.py (about 4 minutes on 2 cores)."""
import sys, json, collections, dataclasses
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
import numpy as np, cv2
from golden_model.images import to_luma
from golden_model.pipeline import candidates
from golden_model.select import select_grid
from orb_tools.eval_photos import fit
from orb_tools.images import load_rgb_or_grey
from orb_tools.density_bench import apply_contrast
from orb_tools.track_bench import Settings, occupancy
GRIDS = [(4, 3), (6, 4), (8, 6)]
def job(args):
    path, w, h = args
    img = to_luma(fit(load_rgb_or_grey(Path(path)), w, h))
    out = []
    for c in (1.0, 0.25):
        im = apply_contrast(img, c)
        cfg = Settings().config(w, h)
        cands = candidates(im, cfg)
        corner = occupancy(*cands.full_res(), w, h)
        ncv = len(cv2.ORB_create(nfeatures=500).detect(im, None))
        for g in GRIDS:
            ours = select_grid(cands, dataclasses.replace(cfg, cols=g[0], rows=g[1]))
            occ = occupancy(*ours.full_res(), w, h)
            out.append(dict(size=f"{w}x{h}", contrast=c, grid=f"{g[0]}x{g[1]}", features=len(ours), cv=ncv,
                            empty=int((corner & ~occ).sum()), corner=int(corner.sum())))
    return out
if __name__ == "__main__":
    photos = sorted(Path("build/eval/held/native").glob("*.png"))
    jobs = [(str(p), w, h) for w, h in [(640, 480), (1280, 720), (1920, 1080)] for p in photos]
    rows = []
    with ProcessPoolExecutor(2) as ex:
        for r in ex.map(job, jobs):
            rows += r
    agg = collections.defaultdict(list)
    for r in rows:
        agg[(r["grid"], r["size"], r["contrast"])].append(r)
    for k in sorted(agg):
        rs = agg[k]
        print(k, "feat %.0f" % np.mean([r["features"] for r in rs]), "fewer-than-cv", sum(r["features"] < r["cv"] for r in rs),
              "empty", sum(r["empty"] for r in rs), "/", sum(r["corner"] for r in rs))
