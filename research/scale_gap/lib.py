"""exp14: variants of our per-level ORB extractor vs OpenCV ORB defaults at the same budget.

Everything here wraps / copies golden_model functions; the model itself is untouched.
The benchmark protocol is orb_tools.scale_bench's (homographies, pair_counts, score), reused as is.
"""

from __future__ import annotations

import json
import math
import re
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import cv2
import numpy as np

from golden_model.brief import describe
from golden_model.fast import ARC_TABLE, BORDER, CIRCLE, circle_masks
from golden_model.nms import nms3x3
from golden_model.orientation import PATCH_RADIUS, moments, quantise
from golden_model.scaler import pyramid
from golden_model.smooth import smooth as smooth_binomial7
from orb_tools import scale_bench as sb

cv2.setNumThreads(1)
HERE = Path(__file__).resolve().parent
PHOTOS = sorted((HERE.parents[1] / "build" / "eval" / "photos").glob("*.png"))  # make eval writes them

# ----------------------------------------------------------------------------------------------
# OpenCV's bit_pattern_31_ (256 tests x (x1, y1, x2, y2)), for experiment 5 only. Not in the
# repository (OpenCV's data): put the 1024 numbers of bit_pattern_31_ from OpenCV's orb.cpp into
# cv_pattern.txt here to run the pat-cv-* variants.
def cv_pattern() -> np.ndarray:
    text = (HERE / "cv_pattern.txt").read_text()
    return np.array([int(v) for v in re.findall(r"-?\d+", text)], dtype=np.int64).reshape(256, 4)


@dataclass(frozen=True)
class Opt:
    step: tuple[int, int] = (5, 4)
    levels: int = 6
    thr: int | tuple[int, ...] = 20  # global or per level
    score: str = "sad"  # sad | cv (OpenCV's FAST score: max t for which the segment test still passes)
    nms: int = 3  # 3 | 5 (window side)
    ori_kernel: tuple[int, ...] | None = None  # None: the model's 7x7 binomial
    desc_kernel: tuple[int, ...] | None = None  # None: the model's 7x7 binomial
    pattern: str = "orbit"  # orbit | cv-sector | cv-angle
    sectors: int = 32
    # selection: none | perlevel (OpenCV-style geometric budgets) | global
    select: str = "none"
    n: int = 0  # total budget N (perlevel/global)
    rank: str = "sad"  # sad | cv | raster | harris | harris2x (FAST top 2n then Harris) | shitomasi
    harris_block: int = 7
    harris_k: tuple[int, int] = (5, 7)  # k = num / 2^shift (5/128 ~ 0.039); (0, 0) -> OpenCV's float 0.04
    harris_on: str = "raw"  # raw | smooth
    budget_decay: float = 0.0  # 0: 1/f per level like OpenCV; else this ratio per level


# ----------------------------------------------------------------------------------------------
def smooth_kernel(img: np.ndarray, kernel: tuple[int, ...] | None) -> np.ndarray:
    """Separable integer smoothing, rounded half up once; 0 on the border of the kernel's radius."""
    if kernel is None:
        return smooth_binomial7(img)
    k = np.array(kernel, dtype=np.int64)
    r = len(k) // 2
    s2 = int(k.sum()) ** 2
    h, w = img.shape
    out = np.zeros((h, w), dtype=np.uint8)
    v = img.astype(np.int64)
    rows = sum(int(kk) * v[:, i : w - 2 * r + i] for i, kk in enumerate(k))
    full = sum(int(kk) * rows[j : h - 2 * r + j, :] for j, kk in enumerate(k))
    out[r : h - r, r : w - r] = np.clip((full + s2 // 2) // s2, 0, 255)
    return out


def kernel_radius(kernel: tuple[int, ...] | None) -> int:
    return 3 if kernel is None else len(kernel) // 2


def cv_fast_score_map(img: np.ndarray, thr: int) -> np.ndarray:
    """(H, W) int32: OpenCV-style FAST score (max over 9-arcs and polarity of the arc's min |d|, minus 1)
    where the segment test passes at `thr`, 0 elsewhere."""
    h, w = img.shape
    v = img.astype(np.int16)
    c = v[BORDER : h - BORDER, BORDER : w - BORDER]
    d = np.stack([v[BORDER + dy : h - BORDER + dy, BORDER + dx : w - BORDER + dx] - c for dx, dy in CIRCLE])
    d2 = np.concatenate([d, d[:8]])
    best = np.full(c.shape, -10_000, dtype=np.int16)
    for s in range(16):
        arc = d2[s : s + 9]
        best = np.maximum(best, arc.min(axis=0))  # brighter: min of (p - c)
        best = np.maximum(best, (-arc).min(axis=0))  # darker: min of (c - p)
    bright, dark, _ = circle_masks(img, thr)
    corner = ARC_TABLE[bright] | ARC_TABLE[dark]
    out = np.zeros((h, w), dtype=np.int32)
    out[BORDER : h - BORDER, BORDER : w - BORDER] = np.where(corner, best.astype(np.int32) - 1, 0)
    return out


def sad_score_map(img: np.ndarray, thr: int) -> np.ndarray:
    from golden_model.fast import fast_score

    return fast_score(img, thr)


def nms_window(score: np.ndarray, side: int) -> np.ndarray:
    """Raster tie rule as nms3x3: strictly greater than earlier neighbours, >= later ones."""
    if side == 3:
        return nms3x3(score)
    r = side // 2
    h, w = score.shape
    padded = np.pad(score, r)
    keep = score > 0
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            if dy == 0 and dx == 0:
                continue
            n = padded[r + dy : r + dy + h, r + dx : r + dx + w]
            earlier = dy < 0 or (dy == 0 and dx < 0)
            keep &= (score > n) if earlier else (score >= n)
    return keep


def harris_map(img: np.ndarray, block: int, k: tuple[int, int], kind: str = "harris") -> np.ndarray:
    """Integer Harris (3x3 Sobel, block x block box window), OpenCV's ORB HarrisResponses layout.
    k = (num, shift): R = a b - c^2 - (num (a + b)^2 >> shift); (0, 0): float k = 0.04.
    kind shitomasi: min eigenvalue ~ (a + b) - sqrt((a - b)^2 + 4 c^2) (float)."""
    v = img.astype(np.int64)
    h, w = v.shape
    ix = np.zeros_like(v)
    iy = np.zeros_like(v)
    ix[1:-1, 1:-1] = (2 * (v[1:-1, 2:] - v[1:-1, :-2]) + (v[:-2, 2:] - v[:-2, :-2]) + (v[2:, 2:] - v[2:, :-2]))
    iy[1:-1, 1:-1] = (2 * (v[2:, 1:-1] - v[:-2, 1:-1]) + (v[2:, :-2] - v[:-2, :-2]) + (v[2:, 2:] - v[:-2, 2:]))

    def box(a: np.ndarray) -> np.ndarray:
        r = block // 2
        c = np.pad(a, ((1, 0), (1, 0))).cumsum(0).cumsum(1)
        out = np.zeros_like(a)
        out[r : h - r, r : w - r] = (c[block:, block:] - c[:-block, block:] - c[block:, :-block] + c[:-block, :-block])
        return out

    a, b, c = box(ix * ix), box(iy * iy), box(ix * iy)
    if kind == "shitomasi":
        return (a + b) - np.sqrt(((a - b).astype(np.float64)) ** 2 + 4.0 * c.astype(np.float64) ** 2)
    if k == (0, 0):
        return a.astype(np.float64) * b - c.astype(np.float64) ** 2 - 0.04 * (a + b).astype(np.float64) ** 2
    return a * b - c * c - ((k[0] * (a + b) * (a + b)) >> k[1])


def level_budgets(n: int, factor: float, levels: int, decay: float = 0.0) -> list[int]:
    """OpenCV's ORB split: n (1 - 1/f) / (1 - (1/f)^L) (1/f)^k, rounded, last level the remainder."""
    q = decay if decay else 1.0 / factor
    per = n * (1 - q) / (1 - q**levels)
    out, total = [], 0
    for _ in range(levels - 1):
        b = int(round(per))
        out.append(b)
        total += b
        per *= q
    out.append(max(n - total, 0))
    return out


def cv_rot_pattern(angle_deg: np.ndarray) -> np.ndarray:
    """(K, 256, 4) int64: OpenCV's pattern rotated by each angle (cvRound of x cos - y sin, x sin + y cos)."""
    a = np.radians(angle_deg)[:, None]
    ca, sa = np.cos(a), np.sin(a)
    p = cv_pattern()[None].astype(np.float64)
    out = np.empty((len(angle_deg), 256, 4), dtype=np.int64)
    for i in (0, 2):
        x, y = p[..., i], p[..., i + 1]
        out[..., i] = np.rint(x * ca - y * sa)
        out[..., i + 1] = np.rint(x * sa + y * ca)
    return out


def describe_cv(smoothed: np.ndarray, xs: np.ndarray, ys: np.ndarray, angle_deg: np.ndarray) -> np.ndarray:
    pats = cv_rot_pattern(angle_deg)
    p1 = smoothed[ys[:, None] + pats[..., 1], xs[:, None] + pats[..., 0]]
    p2 = smoothed[ys[:, None] + pats[..., 3], xs[:, None] + pats[..., 2]]
    bits = (p1 < p2).reshape(len(xs), 32, 8)
    return np.packbits(bits, axis=2, bitorder="little").reshape(len(xs), 32)


# ----------------------------------------------------------------------------------------------
@dataclass
class Pts(sb.Points):
    lvl: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))


def extract(img: np.ndarray, o: Opt) -> Pts:
    r = o.step[0] / o.step[1]
    n_quad = o.sectors // 4
    border = PATCH_RADIUS + max(3, kernel_radius(o.ori_kernel), kernel_radius(o.desc_kernel))
    budgets = level_budgets(o.n, r, o.levels, o.budget_decay) if o.select == "perlevel" else None
    xs_all, ys_all, ds_all, ls_all, rk_all = [], [], [], [], []
    for k, level in enumerate(pyramid(img, o.levels, o.step)):
        h, w = level.shape
        if w < 2 * border + 1 or h < 2 * border + 1:
            break
        thr = o.thr[k] if isinstance(o.thr, tuple) else o.thr
        score = (cv_fast_score_map if o.score == "cv" else sad_score_map)(level, thr)
        ys, xs = np.nonzero(nms_window(score, o.nms))
        keep = (xs >= border) & (xs <= w - 1 - border) & (ys >= border) & (ys <= h - 1 - border)
        xs, ys = xs[keep].astype(np.int64), ys[keep].astype(np.int64)
        if o.select != "none":
            rank = rank_values(level, xs, ys, score, o)
            if budgets is not None:
                nk = budgets[k]
                order = _select(rank, xs, ys, score, nk, o)
                xs, ys = xs[order], ys[order]
                rank = rank[order]
            rk_all.append(rank)
        sm_ori = smooth_kernel(level, o.ori_kernel)
        sm_desc = sm_ori if o.desc_kernel == o.ori_kernel else smooth_kernel(level, o.desc_kernel)
        m10, m01 = moments(sm_ori, xs, ys)
        if o.pattern == "orbit":
            sector = quantise(m10, m01, n_quad)
            desc = describe(sm_desc, xs, ys, sector, n_quad)
        elif o.pattern == "cv-sector":
            sector = quantise(m10, m01, n_quad)
            desc = describe_cv(sm_desc, xs, ys, sector * (360.0 / o.sectors))
        elif o.pattern == "cv-angle":
            ang = np.degrees(np.arctan2(m01.astype(np.float64), m10.astype(np.float64)))
            desc = describe_cv(sm_desc, xs, ys, ang)
        else:
            raise ValueError(o.pattern)
        xs_all.append((xs + 0.5) * r**k - 0.5)
        ys_all.append((ys + 0.5) * r**k - 0.5)
        ds_all.append(desc.reshape(-1, 32))
        ls_all.append(np.full(len(xs), k, np.int64))
    x, y = np.concatenate(xs_all), np.concatenate(ys_all)
    d, lv = np.concatenate(ds_all), np.concatenate(ls_all)
    if o.select == "global":
        rank = np.concatenate(rk_all)
        order = np.argsort(-rank, kind="stable")[: o.n]
        x, y, d, lv = x[order], y[order], d[order], lv[order]
    return Pts(x, y, d, lv)


def rank_values(level: np.ndarray, xs: np.ndarray, ys: np.ndarray, score: np.ndarray, o: Opt) -> np.ndarray:
    if o.rank in ("sad", "cv"):
        return score[ys, xs].astype(np.float64)
    if o.rank == "raster":
        return -(ys * level.shape[1] + xs).astype(np.float64)
    src = level if o.harris_on == "raw" else smooth_binomial7(level)
    if o.rank in ("harris", "harris2x"):
        return harris_map(src, o.harris_block, o.harris_k)[ys, xs].astype(np.float64)
    if o.rank == "shitomasi":
        return harris_map(src, o.harris_block, o.harris_k, "shitomasi")[ys, xs].astype(np.float64)
    raise ValueError(o.rank)


def _select(rank: np.ndarray, xs, ys, score, nk: int, o: Opt) -> np.ndarray:
    """Indices kept on one level, in raster order."""
    if o.rank == "harris2x":  # OpenCV: retain the best 2n by FAST score, then the best n by Harris
        pre = np.argsort(-score[ys, xs], kind="stable")[: 2 * nk]
        sub = pre[np.argsort(-rank[pre], kind="stable")[:nk]]
        return np.sort(sub)
    return np.sort(np.argsort(-rank, kind="stable")[:nk])


def extract_cv_default(img: np.ndarray, budget: int) -> Pts:
    orb = cv2.ORB_create(nfeatures=max(budget, 1))
    kps, desc = orb.detectAndCompute(img, None)
    pts = np.array([kp.pt for kp in kps], dtype=np.float64).reshape(-1, 2)
    lv = np.array([kp.octave for kp in kps], dtype=np.int64)
    return Pts(pts[:, 0], pts[:, 1], desc if desc is not None else np.zeros((0, 32), np.uint8), lv)


# ----------------------------------------------------------------------------------------------
def bench(variants: dict[str, Opt], screen: bool = False, with_cv: bool = True, out: Path | None = None,
          log=print) -> list[dict]:
    """scale_bench protocol for each variant and for cv-default at that variant's budget (per image:
    the variant's reference feature count)."""
    persps = (0.0,) if screen else sb.PERSPECTIVES
    images = [(p.stem, cv2.imread(str(p), cv2.IMREAD_GRAYSCALE)) for p in PHOTOS]
    warps = [(a, si, s, p) for a in sb.ROTATIONS for si, s in enumerate(sb.SCALE_CHANGES) for p in persps]
    cv_cache: dict[tuple[str, int, int], Pts] = {}
    results = []
    for name, o in variants.items():
        t0 = time.perf_counter()
        tot = {"ours": np.zeros((3, 5), np.int64), "cv": np.zeros((3, 5), np.int64)}
        nfeat, ncv, lvl_ours, lvl_cv = [], [], np.zeros(12, np.int64), np.zeros(12, np.int64)
        for iname, img in images:
            ref = extract(img, o)
            budget = len(ref)
            nfeat.append(budget)
            lvl_ours += np.bincount(ref.lvl, minlength=12)[:12]
            if with_cv:
                key = (iname, -1, budget)
                if key not in cv_cache:
                    cv_cache[key] = extract_cv_default(img, budget)
                cref = cv_cache[key]
                ncv.append(len(cref))
                lvl_cv += np.bincount(cref.lvl, minlength=12)[:12]
            for wi, (a, si, s, p) in enumerate(warps):
                hm = sb.homography(img.shape, a, s, p)
                wimg = sb.warp(img, hm)
                tot["ours"][si] += sb.pair_counts(ref, extract(wimg, o), hm, img.shape)
                if with_cv:
                    key = (iname, wi, budget)
                    if key not in cv_cache:
                        cv_cache[key] = extract_cv_default(wimg, budget)
                    tot["cv"][si] += sb.pair_counts(cref, cv_cache[key], hm, img.shape)
        row = {"variant": name, "screen": screen, "pooled": round(float(sb.score(tot["ours"])), 2),
               **{f"s{sc:g}": round(float(sb.score(tot["ours"][i])), 2) for i, sc in enumerate(sb.SCALE_CHANGES)},
               "feat_per_img": round(float(np.mean(nfeat)), 1), "feat": nfeat,
               "levels_ours": lvl_ours[:o.levels].tolist()}  # fmt: skip
        if with_cv:
            row.update({"cv_pooled": round(float(sb.score(tot["cv"])), 2),
                        **{f"cv_s{sc:g}": round(float(sb.score(tot["cv"][i])), 2)
                           for i, sc in enumerate(sb.SCALE_CHANGES)},
                        "cv_feat_per_img": round(float(np.mean(ncv)), 1), "levels_cv": lvl_cv[:8].tolist()})  # fmt: skip
            row["gap"] = round(row["pooled"] - row["cv_pooled"], 2)
        row["opt"] = {k: v for k, v in asdict(o).items() if v != getattr(Opt(), k)}
        row["secs"] = round(time.perf_counter() - t0, 1)
        results.append(row)
        log(fmt(row))
        if out is not None:
            with open(out, "a") as fh:
                fh.write(json.dumps(row) + "\n")
    return results


def fmt(row: dict) -> str:
    s = (f"{row['variant']:<34} {'S' if row['screen'] else 'F'} ours {row['pooled']:5.2f} "
         f"({row['s1']:5.2f}/{row['s0.8']:5.2f}/{row['s0.6']:5.2f}) n={row['feat_per_img']:7.1f}")
    if "cv_pooled" in row:
        s += (f" | cv@ {row['cv_pooled']:5.2f} ({row['cv_s1']:5.2f}/{row['cv_s0.8']:5.2f}/{row['cv_s0.6']:5.2f})"
              f" n={row['cv_feat_per_img']:7.1f} gap {row['gap']:+.2f}")
    return s + f" [{row['secs']}s] lv={row['levels_ours']}" + (f" cvlv={row.get('levels_cv')}" if "levels_cv" in row else "")
