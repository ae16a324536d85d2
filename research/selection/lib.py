"""Research prototype for issue 24: feature selection policies, measured on the scale benchmark.

Not installed, imported or linted by the project; the chosen rule lives in golden_model.select.
Candidates: per level, FAST at a main threshold t_hi and a low threshold t_lo, one 3x3 NMS on the
combined map S' = S_hi + 4096 where a pixel is a corner at t_hi, S_lo elsewhere (so the main
corners suppress exactly as NMS(S_hi) would), descriptor border, sector and descriptor as the
golden model computes them, and candidate ranking measures (SAD, Harris variants).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from golden_model.brief import describe
from golden_model.fast import fast_score
from golden_model.nms import nms3x3
from golden_model.orientation import moments, quantise
from golden_model.pipeline import DESC_BORDER
from golden_model.scaler import pyramid
from golden_model.smooth import smooth


@dataclass
class Level:
    k: int
    w: int
    h: int
    x: np.ndarray
    y: np.ndarray
    sad: np.ndarray
    hi: np.ndarray
    desc: np.ndarray
    resp: dict = field(default_factory=dict)


def harris_map(img: np.ndarray, block: int, kshift: tuple[int, int] = (1, 5), src: str = "raw",
               gshift: int = 0) -> np.ndarray:
    """Integer Harris: 3x3 Sobel on img, block x block box sums, R = a b - c^2 - (num (a+b)^2 >> shift).
    gshift: gradients >> gshift before the products (hardware precision)."""
    v = img.astype(np.int64)
    h, w = v.shape
    ix = np.zeros_like(v)
    iy = np.zeros_like(v)
    ix[1:-1, 1:-1] = 2 * (v[1:-1, 2:] - v[1:-1, :-2]) + (v[:-2, 2:] - v[:-2, :-2]) + (v[2:, 2:] - v[2:, :-2])
    iy[1:-1, 1:-1] = 2 * (v[2:, 1:-1] - v[:-2, 1:-1]) + (v[2:, :-2] - v[:-2, :-2]) + (v[2:, 2:] - v[:-2, 2:])
    if gshift:
        ix >>= gshift
        iy >>= gshift

    def box(a: np.ndarray) -> np.ndarray:
        r = block // 2
        c = np.pad(a, ((1, 0), (1, 0))).cumsum(0).cumsum(1)
        out = np.zeros_like(a)
        out[r : h - r, r : w - r] = c[block:, block:] - c[:-block, block:] - c[block:, :-block] + c[:-block, :-block]
        return out

    a, b, c = box(ix * ix), box(iy * iy), box(ix * iy)
    num, sh = kshift
    return a * b - c * c - ((num * (a + b) * (a + b)) >> sh)


def logq(r: np.ndarray, mbits: int) -> np.ndarray:
    """Quantise a positive response to a float-like code: exponent then mbits of mantissa; <= 0 -> 0."""
    r = np.asarray(r, np.int64)
    out = np.zeros(r.shape, np.int64)
    pos = r > 0
    e = np.zeros(r.shape, np.int64)
    e[pos] = np.floor(np.log2(r[pos].astype(np.float64))).astype(np.int64)
    # exact floor(log2) for ints
    for _ in range(2):
        e = np.where(pos & ((np.int64(1) << np.maximum(e, 0)) > r), e - 1, e)
        e = np.where(pos & ((np.int64(1) << np.minimum(e + 1, 62)) <= r), e + 1, e)
    mant = np.where(e >= mbits, r >> np.maximum(e - mbits, 0), r << np.maximum(mbits - e, 0)) & ((1 << mbits) - 1)
    out[pos] = 1 + (e[pos] << mbits) + mant[pos]
    return out


def level_candidates(img: np.ndarray, k: int, t_hi: int, t_lo: int, sectors: int, measures: tuple[str, ...]) -> Level:
    h, w = img.shape
    s_hi = fast_score(img, t_hi)
    s_lo = fast_score(img, t_lo) if t_lo < t_hi else s_hi
    comb = np.where(s_hi > 0, s_hi + 4096, s_lo)
    ys, xs = np.nonzero(nms3x3(comb))
    b = DESC_BORDER
    keep = (xs >= b) & (xs <= w - 1 - b) & (ys >= b) & (ys <= h - 1 - b)
    xs, ys = xs[keep].astype(np.int64), ys[keep].astype(np.int64)
    sad = s_lo[ys, xs].astype(np.int64)
    hi = s_hi[ys, xs] > 0
    sm = smooth(img)
    m10, m01 = moments(sm, xs, ys)
    n = sectors // 4
    sec = quantise(m10, m01, n)
    desc = describe(sm, xs, ys, sec, n)
    resp = {"sad": sad}
    for m in measures:
        if m == "sad":
            continue
        kind, _, arg = m.partition(":")
        if kind == "harris":  # harris:B[:src][:gshift][:qM]
            parts = arg.split(":") if arg else ["7"]
            q = None
            if parts[-1].startswith("q"):
                q = int(parts[-1][1:])
                parts = parts[:-1]
            block = int(parts[0])
            src = parts[1] if len(parts) > 1 else "raw"
            gsh = int(parts[2]) if len(parts) > 2 else 0
            base = sm if src == "sm" else img
            r = harris_map(base, block, src=src, gshift=gsh)[ys, xs]
            resp[m] = logq(r, q) if q is not None else r
        else:
            raise ValueError(m)
    return Level(k, w, h, xs, ys, sad, hi, desc, resp)


def candidates(img: np.ndarray, step=(5, 4), levels=5, t_hi=20, t_lo=20, sectors=64,
               measures=("sad",)) -> list[Level]:  # fmt: skip
    out = []
    for k, lv in enumerate(pyramid(img, levels, step)):
        h, w = lv.shape
        if w < 2 * DESC_BORDER + 1 or h < 2 * DESC_BORDER + 1:
            break
        out.append(level_candidates(lv, k, t_hi, t_lo, sectors, measures))
    return out


def level_budgets(total: int, step, levels: int) -> list[int]:
    num, den = step
    q = den / num
    per = total * (1 - q) / (1 - q**levels)
    out = []
    for _ in range(levels - 1):
        out.append(round(per))
        per *= q
    out.append(max(total - sum(out), 0))
    return out


# ---------------------------------------------------------------- policies -> indices per level
def order_desc(key: np.ndarray, lv: Level) -> np.ndarray:
    """Indices by key descending, ties raster order."""
    return np.lexsort((lv.x, lv.y, -key))


def pol_topn(lv: Level, n: int, measure: str, lo: bool = False) -> np.ndarray:
    """The host rule of spec 14: top n by measure (main-threshold corners only unless lo)."""
    idx = np.arange(len(lv.x)) if lo else np.flatnonzero(lv.hi)
    key = lv.resp[measure][idx]
    o = np.lexsort((lv.x[idx], lv.y[idx], -key))
    return idx[o[:n]]


def cell_rank(lv: Level, idx: np.ndarray, cx: np.ndarray, cy: np.ndarray, key: np.ndarray, kcell: int,
              two_thr: bool) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Per candidate (of idx) its rank within its cell by (hi, key) desc, raster ties; candidates beyond
    kcell dropped; lo candidates dropped in cells with a hi one (two_thr) or always (not two_thr).
    Returns (kept idx, their rank)."""
    hi = lv.hi[idx]
    if not two_thr:
        m = hi
        idx, cx, cy, key, hi = idx[m], cx[m], cy[m], key[m], hi[m]
    cell = cy * 100000 + cx
    o = np.lexsort((lv.x[idx], lv.y[idx], -key, ~hi, cell))
    cell_o = cell[o]
    start = np.r_[True, cell_o[1:] != cell_o[:-1]]
    grp = np.cumsum(start) - 1
    first = np.flatnonzero(start)
    rank = np.arange(len(o)) - first[grp]
    cell_has_hi = np.zeros(len(first), bool)
    np.logical_or.at(cell_has_hi, grp, hi[o])
    ok = (rank < kcell) & (hi[o] | ~cell_has_hi[grp])
    return idx[o][ok], rank[ok]


def pol_grid_quota(lv: Level, n: int, measure: str, kcell: int, two_thr: bool, aspect_fit: bool = True) -> np.ndarray:
    """Grid sized so that cells * kcell <= n (cells about square); each cell's best kcell."""
    if n <= 0:
        return np.zeros(0, np.int64)
    w, h = lv.w - 2 * DESC_BORDER, lv.h - 2 * DESC_BORDER
    cells = max(n // kcell, 1)
    gx = max(1, int(math.floor(math.sqrt(cells * w / h))))
    gy = max(1, cells // gx)
    while gx * gy > cells:
        gy -= 1
    gy = max(gy, 1)
    idx = np.arange(len(lv.x))
    cx = ((lv.x - DESC_BORDER) * gx) // w
    cy = ((lv.y - DESC_BORDER) * gy) // h
    key = lv.resp[measure]
    kept, _ = cell_rank(lv, idx, cx, cy, key, kcell, two_thr)
    return kept


def pol_grid_band(lv: Level, n: int, measure: str, cell: int, kcell: int, two_thr: bool, carry: bool = True,
                  slack: float = 1.0, rank_major="all", band_rows: int = 0) -> np.ndarray:  # fmt: skip
    """Fixed cells of `cell` pixels (from the level's origin); each keeps kcell; band b (a row of
    cells) may emit up to floor(n (b+1) / R * slack) - emitted so far (carry) or n / R; within a band
    rank-major (all cells' best first), then key, then raster."""
    idx = np.arange(len(lv.x))
    cx = lv.x // cell
    cy = lv.y // cell
    key = lv.resp[measure]
    kept, rank = cell_rank(lv, idx, cx, cy, key, kcell, two_thr)
    rows = -(-lv.h // cell)
    bcells = band_rows or 1  # cell rows per band
    nb = -(-rows // bcells)
    out = []
    used = 0
    for b in range(nb):
        m = (cy[kept] // bcells) == b
        ki, kr = kept[m], rank[m]
        if carry:
            allot = min(n, int(math.floor(n * (b + 1) / nb * slack))) - used
        else:
            allot = n // nb
        allot = max(allot, 0)
        if rank_major == "all":
            o = np.lexsort((lv.x[ki], lv.y[ki], -key[ki], ~lv.hi[ki], kr))
        elif rank_major == "first":
            o = np.lexsort((lv.x[ki], lv.y[ki], -key[ki], ~lv.hi[ki], kr > 0))
        else:
            o = np.lexsort((lv.x[ki], lv.y[ki], -key[ki], ~lv.hi[ki]))
        take = ki[o[:allot]]
        used += len(take)
        out.append(take)
    return np.concatenate(out) if out else np.zeros(0, np.int64)


def pol_quadtree(lv: Level, n: int, measure: str, two_thr: bool) -> np.ndarray:
    """ORB-SLAM's DistributeOctTree (simplified): split nodes with >1 point until >= n nodes or no
    split possible; keep the best-key point per node (host reference, not hardware)."""
    idx = np.arange(len(lv.x)) if two_thr else np.flatnonzero(lv.hi)
    if n <= 0 or len(idx) == 0:
        return np.zeros(0, np.int64)
    key = lv.resp[measure]
    x0, x1, y0, y1 = DESC_BORDER, lv.w - DESC_BORDER, DESC_BORDER, lv.h - DESC_BORDER
    nini = max(1, round((x1 - x0) / (y1 - y0)))
    hx = (x1 - x0) / nini
    nodes = []
    for i in range(nini):
        a = x0 + i * hx
        sel = idx[(lv.x[idx] >= a) & (lv.x[idx] < a + hx)] if i < nini - 1 else idx[lv.x[idx] >= a]
        if len(sel):
            nodes.append((a, a + hx, y0, y1, sel))
    while True:
        if len(nodes) >= n:
            break
        new = []
        split_any = False
        for (a, b2, c, d, sel) in nodes:
            if len(sel) == 1 or (b2 - a) < 1:
                new.append((a, b2, c, d, sel))
                continue
            split_any = True
            mx, my = (a + b2) / 2, (c + d) / 2
            for (p, q, r, s) in ((a, mx, c, my), (mx, b2, c, my), (a, mx, my, d), (mx, b2, my, d)):
                m = (lv.x[sel] >= p) & (lv.x[sel] < q) & (lv.y[sel] >= r) & (lv.y[sel] < s)
                if m.any():
                    new.append((p, q, r, s, sel[m]))
        nodes = new
        if not split_any:
            break
    out = []
    for (*_, sel) in nodes:
        hs = sel[lv.hi[sel]] if lv.hi[sel].any() else sel
        out.append(hs[np.argmax(key[hs])])
    out = np.array(out, np.int64)
    if len(out) > n:  # ORB-SLAM keeps all nodes of the last split; cap by key here
        out = out[np.argsort(-key[out], kind="stable")[:n]]
    return out


@dataclass
class Pts:
    x: np.ndarray
    y: np.ndarray
    desc: np.ndarray
    level: np.ndarray

    def __len__(self) -> int:
        return len(self.x)


def select(levels: list[Level], total: int, step, nlev: int, policy: str, **kw) -> Pts:
    budgets = level_budgets(total, step, nlev)
    xs, ys, ds, ls = [], [], [], []
    r = step[0] / step[1]
    for lv, n in zip(levels, budgets):
        if policy == "all":
            i = np.flatnonzero(lv.hi)
        elif policy == "topn":
            i = pol_topn(lv, n, **kw)
        elif policy == "quota":
            i = pol_grid_quota(lv, n, **kw)
        elif policy == "band":
            i = pol_grid_band(lv, n, **kw)
        elif policy == "floor":
            i = pol_floor(lv, n, **kw)
        elif policy == "quadtree":
            i = pol_quadtree(lv, n, **kw)
        else:
            raise ValueError(policy)
        f = r**lv.k
        xs.append((lv.x[i] + 0.5) * f - 0.5)
        ys.append((lv.y[i] + 0.5) * f - 0.5)
        ds.append(lv.desc[i])
        ls.append(np.full(len(i), lv.k))
    if not xs:
        return Pts(np.zeros(0), np.zeros(0), np.zeros((0, 32), np.uint8), np.zeros(0, np.int64))
    return Pts(np.concatenate(xs), np.concatenate(ys), np.concatenate(ds), np.concatenate(ls))


def coverage(p: Pts, w: int, h: int, gx: int = 8, gy: int = 6) -> float:
    if len(p) == 0:
        return 0.0
    cx = np.clip((p.x * gx / w).astype(int), 0, gx - 1)
    cy = np.clip((p.y * gy / h).astype(int), 0, gy - 1)
    return len(set(zip(cx.tolist(), cy.tolist()))) / (gx * gy)


def pol_floor(lv: Level, n: int, measure: str, grid: tuple[int, int] = (8, 6), cell: int = 0, two_thr: bool = True,
              kcell: int = 1, lo_topn: bool = False, reserve: bool = True) -> np.ndarray:  # fmt: skip
    """Coverage floor + best-first: each cell's best kcell by (hi, key) (lo only in cells without a
    main corner), then the best of the remaining main-threshold corners up to n in all (reserve: the
    top-n part is n - cells, so the total never exceeds n; else up to n regardless)."""
    if n <= 0 or len(lv.x) == 0:
        return np.zeros(0, np.int64)
    if cell:
        cx, cy = lv.x // cell, lv.y // cell
        ncells = (-(-lv.w // cell)) * (-(-lv.h // cell))
    else:
        gx, gy = grid
        cx, cy = lv.x * gx // lv.w, lv.y * gy // lv.h
        ncells = gx * gy
    key = lv.resp[measure]
    idx = np.arange(len(lv.x))
    kept, _ = cell_rank(lv, idx, cx, cy, key, kcell, two_thr)
    if len(kept) > n:
        o = np.lexsort((lv.x[kept], lv.y[kept], -key[kept], ~lv.hi[kept]))
        kept = kept[o[:n]]
    room = (n - ncells * kcell) if reserve else (n - len(kept))
    rest = np.setdiff1d(np.flatnonzero(lv.hi | lo_topn), kept)
    o = np.lexsort((lv.x[rest], lv.y[rest], -key[rest]))
    return np.concatenate([kept, rest[o[: max(room, 0)]]])
