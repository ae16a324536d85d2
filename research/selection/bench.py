"""Scale-benchmark of selection variants (issue 24 research; see README.md).

PYTHONPATH=sw:.:research/selection .venv/bin/python research/selection/bench.py --set tune VARIANT...
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
from orb_tools import scale_bench as sb

from . import lib, photos
from .variants import VARIANTS


def cv_default(img, n):
    e = sb.Extractor("cv-default", "opencv-default")
    return sb.extract_opencv_orb(img, e, n)


def to_points(p: lib.Pts) -> sb.Points:
    return sb.Points(p.x, p.y, p.desc.reshape(-1, 32))


def one_image(args):
    name, img, variants, screen = args
    groups = {}
    for vn, v in variants.items():
        groups.setdefault((v["t_lo"], v.get("step", (5, 4)), v.get("levels", 5), v.get("sectors", 64)), []).append(vn)
    measures = tuple(sorted({v["kw"].get("measure", "sad") for v in variants.values()}))
    hs = []
    for a in sb.ROTATIONS:
        for s in sb.SCALE_CHANGES:
            for pp in (sb.PERSPECTIVES[:1] if screen else sb.PERSPECTIVES):
                hs.append((a, s, pp))
    warped = [(sb.homography(img.shape, *h), None) for h in hs]
    warped = [(hm, sb.warp(img, hm)) for hm, _ in warped]
    res = {}
    cvcache = {}
    for vn, v in variants.items():
        if v["policy"] != "model":
            continue
        import golden_model.response as gr
        from dataclasses import replace as dreplace

        from golden_model.config import Config
        from golden_model.pipeline import DESC_BORDER, candidates
        from golden_model.scaler import pyramid as pyr
        from golden_model.select import select_grid

        gr.MANTISSA_BITS = v["kw"].get("mbits", 1)
        gr.GRAD_SHIFT = v["kw"].get("gshift", 2)
        gr.SUM_SHIFT = v["kw"].get("sshift", 5)

        def run_model(im, v=v):
            h, w = im.shape
            nlev = v.get("levels", 5)
            while nlev > 1:
                lw, lh = pyr(im, nlev, (5, 4))[-1].shape[::-1]
                if lw >= 2 * DESC_BORDER + 1 and lh >= 2 * DESC_BORDER + 1:
                    break
                nlev -= 1
            cfg = Config(w, h, scales=nlev, step_num=5, step_den=4, sectors=64, threshold=20,
                         threshold_lo=v["t_lo"], selection="grid", budget=v["budget"], cell=v["kw"].get("cell", 80))
            f = select_grid(candidates(im, cfg), cfg)
            x0, y0 = f.full_res()
            return lib.Pts(x0, y0, f.descriptor, f.scale)

        ref = run_model(img)
        n = len(ref)
        tot = np.zeros((len(sb.SCALE_CHANGES), 5), np.int64)
        ctot = np.zeros((len(sb.SCALE_CHANGES), 5), np.int64)
        if n not in cvcache:
            cvcache[n] = (cv_default(img, n), [cv_default(w, n) for _, w in warped])
        cref, cw = cvcache[n]
        for (hm, w), h, c2 in zip(warped, hs, cw):
            si = sb.SCALE_CHANGES.index(h[1])
            tot[si] += sb.pair_counts(to_points(ref), to_points(run_model(w)), hm, img.shape)
            ctot[si] += sb.pair_counts(cref, c2, hm, img.shape)
        res[vn] = {"ours": tot.tolist(), "cv": ctot.tolist(), "n": n, "cov": lib.coverage(ref, img.shape[1], img.shape[0])}
    variants = {k: v for k, v in variants.items() if v["policy"] != "model"}
    groups = {}
    for vn, v in variants.items():
        groups.setdefault((v["t_lo"], v.get("step", (5, 4)), v.get("levels", 5), v.get("sectors", 64)), []).append(vn)
    measures = tuple(sorted({v["kw"].get("measure", "sad") for v in variants.values()}))
    for (t_lo, step, nlev, sectors), names in groups.items():
        ref_c = lib.candidates(img, step, nlev, 20, t_lo, sectors, measures)
        war_c = [lib.candidates(w, step, nlev, 20, t_lo, sectors, measures) for _, w in warped]
        for vn in names:
            v = variants[vn]
            ref = lib.select(ref_c, v["budget"], step, nlev, v["policy"], **v["kw"])
            tot = np.zeros((len(sb.SCALE_CHANGES), 5), np.int64)
            ctot = np.zeros((len(sb.SCALE_CHANGES), 5), np.int64)
            n = len(ref)
            if n not in cvcache:
                cref = cv_default(img, n)
                cw = [cv_default(w, n) for _, w in warped]
                cvcache[n] = (cref, cw)
            cref, cw = cvcache[n]
            for (hm, _), wc, h, c2 in zip(warped, war_c, hs, cw):
                got = lib.select(wc, v["budget"], step, nlev, v["policy"], **v["kw"])
                si = sb.SCALE_CHANGES.index(h[1])
                tot[si] += sb.pair_counts(to_points(ref), to_points(got), hm, img.shape)
                ctot[si] += sb.pair_counts(cref, c2, hm, img.shape)
            res[vn] = {"ours": tot.tolist(), "cv": ctot.tolist(), "n": n,
                       "cov": lib.coverage(ref, img.shape[1], img.shape[0])}  # fmt: skip
    return name, res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--set", default="tune")
    ap.add_argument("--screen", action="store_true")
    ap.add_argument("--native", action="store_true", help="the project's eval photos at their own size")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", type=Path, default=HERE / "results.jsonl")
    ap.add_argument("names", nargs="+")
    a = ap.parse_args()
    sel = {}
    for n in a.names:
        hits = {k: v for k, v in VARIANTS.items() if k == n or (n.endswith("*") and k.startswith(n[:-1]))}
        if not hits:
            sys.exit(f"unknown variant {n}")
        sel.update(hits)
    imgs = photos.load_eval() if a.native else photos.load(a.set)
    t0 = time.time()
    tot = {vn: [np.zeros((3, 5), np.int64), np.zeros((3, 5), np.int64), [], []] for vn in sel}
    with ProcessPoolExecutor(a.jobs) as ex:
        for name, res in ex.map(one_image, [(n, im, sel, a.screen) for n, im in imgs]):
            for vn, r in res.items():
                tot[vn][0] += np.array(r["ours"])
                tot[vn][1] += np.array(r["cv"])
                tot[vn][2].append(r["n"])
                tot[vn][3].append(r["cov"])
            print(f"  {name} done {time.time() - t0:.0f}s", file=sys.stderr, flush=True)
    with open(a.out, "a") as fh:
        for vn, (o, c, ns, cov) in tot.items():
            row = {"variant": vn, "set": a.set, "screen": a.screen, "ours": round(sb.score(o), 2),
                   "cv": round(sb.score(c), 2), "diff": round(sb.score(o) - sb.score(c), 2),
                   "by_scale": [round(sb.score(o[i]), 2) for i in range(3)],
                   "cv_by_scale": [round(sb.score(c[i]), 2) for i in range(3)],
                   "n": round(float(np.mean(ns)), 1), "cov": round(float(np.mean(cov)), 3)}  # fmt: skip
            fh.write(json.dumps(row) + "\n")
            print(f"{vn:40s} ours {row['ours']:6.2f} cv {row['cv']:6.2f} diff {row['diff']:+6.2f} "
                  f"n {row['n']:7.1f} cov {row['cov']:.3f} {row['by_scale']}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
