"""Tracking benchmark of selection variants on synthetic camera-motion clips (issue 24 research).

.venv/bin/python -m research.selection.track VARIANT...   (from the repository root)
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import cv2
import numpy as np

HERE = Path(__file__).resolve().parent
from orb_tools import scale_bench as sb

from . import lib, photos
from .variants import VARIANTS


def clip(img: np.ndarray, frames: int, seed: int, w: int = 640, h: int = 480) -> list[np.ndarray]:
    """A hand-held-like camera over a photograph: smooth pan, zoom, roll and mild perspective, noise."""
    rng = np.random.default_rng(seed)
    ih, iw = img.shape
    out = []
    ph = rng.uniform(0, 2 * math.pi, 6)
    for t in range(frames):
        s = t / max(frames - 1, 1)
        zoom = 1.0 + 0.25 * math.sin(2 * math.pi * s * 0.7 + ph[0])
        ang = 8.0 * math.sin(2 * math.pi * s * 0.5 + ph[1])
        cx = iw / 2 + 0.18 * iw * math.sin(2 * math.pi * s * 0.6 + ph[2])
        cy = ih / 2 + 0.15 * ih * math.sin(2 * math.pi * s * 0.8 + ph[3])
        px = 2e-4 * math.sin(2 * math.pi * s + ph[4])
        py = 2e-4 * math.cos(2 * math.pi * s + ph[5])
        base = min(iw / w, ih / h) * 0.55
        sc = base / zoom  # source pixels per output pixel
        a = math.radians(ang)
        # output (u, v) -> source: centre + R * sc * (u - w/2, v - h/2)
        m = np.array([[sc * math.cos(a), -sc * math.sin(a), 0], [sc * math.sin(a), sc * math.cos(a), 0], [0, 0, 1]])
        p = np.array([[1, 0, 0], [0, 1, 0], [px, py, 1]])
        to_c = np.array([[1, 0, -w / 2], [0, 1, -h / 2], [0, 0, 1]])
        back = np.array([[1, 0, cx], [0, 1, cy], [0, 0, 1]])
        hm = back @ m @ p @ to_c
        f = cv2.warpPerspective(img, hm, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                borderMode=cv2.BORDER_REFLECT)  # fmt: skip
        noise = rng.normal(0, 2.0, f.shape)
        out.append(np.clip(f + noise, 0, 255).astype(np.uint8))
    return out


def pair_stats(a: sb.Points, b: sb.Points, w: int, h: int) -> tuple[int, int, float]:
    """(matches, F-RANSAC inliers, inlier coverage of an 8x6 grid of frame a)."""
    if len(a) < 8 or len(b) < 8:
        return 0, 0, 0.0
    ms = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(a.desc, b.desc)
    if len(ms) < 8:
        return len(ms), 0, 0.0
    q = np.array([m.queryIdx for m in ms])
    t = np.array([m.trainIdx for m in ms])
    pa = np.stack([a.x[q], a.y[q]], 1).astype(np.float64)
    pb = np.stack([b.x[t], b.y[t]], 1).astype(np.float64)
    f, mask = cv2.findFundamentalMat(pa, pb, cv2.FM_RANSAC, 1.0, 0.999, 2000)
    if mask is None:
        return len(ms), 0, 0.0
    inl = mask.ravel().astype(bool)
    cx = np.clip((pa[inl, 0] * 8 / w).astype(int), 0, 7)
    cy = np.clip((pa[inl, 1] * 6 / h).astype(int), 0, 5)
    return len(ms), int(inl.sum()), len(set(zip(cx.tolist(), cy.tolist()))) / 48


def run_clip(args):
    name, img, variants, frames, gaps, seed = args
    cv2.setRNGSeed(seed)
    fr = clip(img, frames, seed)
    h, w = fr[0].shape
    res = {}
    cands = {}
    for vn, v in variants.items():
        key = (v["t_lo"],)
        if key not in cands:
            measures = tuple(sorted({vv["kw"].get("measure", "sad") for vv in variants.values()}))
            cands[key] = [lib.candidates(f, (5, 4), 5, 20, v["t_lo"], 64, measures) for f in fr]
        pts = [lib.select(c, v["budget"], (5, 4), 5, v["policy"], **v["kw"]) for c in cands[key]]
        ours = [sb.Points(p.x, p.y, p.desc) for p in pts]
        cvp = [sb.extract_opencv_orb(f, sb.Extractor("cv", "opencv-default"), max(len(p), 1)) for f, p in zip(fr, pts)]
        st = {"ours": [], "cv": []}
        for g in gaps:
            for i in range(frames - g):
                for tag, P in (("ours", ours), ("cv", cvp)):
                    m, inl, cov = pair_stats(P[i], P[i + g], w, h)
                    st[tag].append((g, len(P[i]), m, inl, cov))
        res[vn] = st
    return name, res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--set", default="held")
    ap.add_argument("--frames", type=int, default=30)
    ap.add_argument("--gaps", type=int, nargs="+", default=[1, 5])
    ap.add_argument("--clips", type=int, default=8)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("names", nargs="+")
    a = ap.parse_args()
    sel = {n: VARIANTS[n] for n in a.names}
    imgs = photos.load(a.set, native=True) if a.set == "tune" else load_native(a.set)
    imgs = imgs[: a.clips]
    t0 = time.time()
    agg = {vn: {"ours": [], "cv": []} for vn in sel}
    with ProcessPoolExecutor(a.jobs) as ex:
        jobs = [(n, im, sel, a.frames, a.gaps, i + 1) for i, (n, im) in enumerate(imgs)]
        for name, res in ex.map(run_clip, jobs):
            for vn, st in res.items():
                for tag in ("ours", "cv"):
                    agg[vn][tag] += st[tag]
            print(f"  {name} {time.time() - t0:.0f}s", file=sys.stderr, flush=True)
    for vn, st in agg.items():
        for g in a.gaps:
            row = []
            for tag in ("ours", "cv"):
                r = np.array([x[1:] for x in st[tag] if x[0] == g], np.float64)
                n, m, inl, cov = r.mean(0)
                fail = (r[:, 2] < 30).mean() * 100
                ipf = (r[:, 2] / np.maximum(r[:, 0], 1)).mean()
                row.append(f"{tag} n {n:6.0f} inl {inl:6.1f} inl/f {ipf:.3f} cov {cov:.3f} fail {fail:4.1f}%")
            print(f"{vn:32s} gap {g}: " + " | ".join(row), flush=True)


def load_native(which):
    import os

    root = Path(os.environ.get("ORB_PHOTO_ROOT", "build/eval/debian"))
    from golden_model.images import to_luma

    out = []
    for p in photos.HELD:
        im = cv2.imread(str(root / p), cv2.IMREAD_COLOR)
        im = to_luma(cv2.cvtColor(im, cv2.COLOR_BGR2RGB))
        if min(im.shape) < 600:
            im = cv2.resize(im, None, fx=1.6, fy=1.6, interpolation=cv2.INTER_CUBIC)
        out.append((Path(p).stem, im))
    # the large ones (the mate photographs) first: most room for camera motion
    out.sort(key=lambda t: -t[1].size)
    return out


if __name__ == "__main__":
    main()
