#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Learn rotation-closed ("orbit") rBRIEF seeds, one set per sector count (docs/pattern.md).

Writes the seed data golden_model/data/orbit_seeds.json, from which sw/orb_flow/gen/pattern.py
(``make pattern``) generates golden_model/pattern_data.py. Research code: nothing in the model, the
tools or the tests imports it. Same code path and defaults as the experiment of 2026-11-22
(research/pattern/, README.md there), with the matching twins taken from viewpoint changes since
issue 39 (``--twins viewpoint --views 6``, the defaults: the adopted ``orbit-dprime-viewpoint``
seeds); ``--twins rotation --views 3`` learns with rotated twins as the earlier ``orbit-dprime``
seeds were (it does not give those seeds again: docs/pattern.md). Run from the repository with the project's venv (golden_model installed):

    .venv/bin/python -m research.pattern.orbit_learn                  # orbit-dprime-viewpoint, about 2 min
    .venv/bin/python -m research.pattern.orbit_learn --twins rotation --views 3 --out /tmp/s.json  # rotated twins
    .venv/bin/python -m research.pattern.orbit_learn --method orbit-random --out /tmp/seeds.json
    make pattern                                                     # or python -m orb_flow.gen.pattern --seeds ...

A pattern for 4N sectors is M = 256 / 4N orbits; orbit j has a real-valued seed test q_j = (p1, p2)
and member k of orbit j in sector s is round(R(((k + s) mod 4N) * 360 / 4N) q_j) (both points
rotated, y downwards, rounded half away from zero: golden_model.pattern.orbit_patterns). The
hardware evaluates the 256 sector-0 tests and rotates the bits of each orbit by s.

Training keypoints: exactly those of pattern_learn.py (this directory) (same images, same seeded sampling,
20,000 keypoints). Each keypoint's bits are what the accelerator computes: the model's sector s of
the keypoint (quantise(m10, m01, N)) selects the member tables, i.e. the sector-0 bits of member
(k + s) mod 4N. With ``twins`` > 0 every keypoint also has a rotated twin: the same keypoint in a
copy of its image rotated by one of ``twins`` random angles per image (a matching pair).

Score: D = Hamming distance between the descriptors of two independent training keypoints (a
non-matching pair). With p_i the fraction of ones of test i and p_ab the joint frequencies of tests
i, j, E[D] = sum 2 p_i (1 - p_i) and Var[D] = sum_ij 2 (p11 p00 + p10 p01) - E[d_i] E[d_j].
n_eff = E[D]^2 / Var[D] equals the number of tests for independent balanced tests and falls with
imbalance and with correlation. With twins the objective is d' = (E[D] - F) / sd[D], F the expected
number of bits that flip between a keypoint and its rotated twin. Greedy: candidates are ranked by
their own orbit's score, the best ``pool`` are kept, and orbits are added one at a time, each time
the one that maximises the score of the selection so far.

Candidates: seed tests with both points uniform in the disc of radius 15, on a 1/16-pixel grid, at
least 2 pixels apart, and no rounding tie (1e-6) at any of the 64 sector angles (so none at 16 or
32 either). ``integer`` uses integer seeds instead (pattern_learn.sample_candidates). The random
baseline takes the first M candidates of another seeded draw from the same distribution.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .pattern_learn import (
    TRAINING_IMAGES,
    GreedyParams,
    disc_points,
    keypoints,
    load_image,
    sample_candidates,
)

from golden_model.orientation import moments, quantise
from golden_model.pattern import TESTS, member_tables, orbit_patterns
from golden_model.smooth import smooth

R = 15
W = 2 * R + 1
GRID = 16
ALL_SECTORS = 64
SECTOR_COUNTS = (16, 32, 64)
ROOT = Path(__file__).resolve().parents[2]
SEEDS_JSON = ROOT / "golden_model" / "data" / "orbit_seeds.json"


# ---------------------------------------------------------------------------------------------
# training keypoints: pattern_learn's sampling, kept as the 31x31 window of every keypoint
# ---------------------------------------------------------------------------------------------


def _windows(sm: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    off = np.arange(-R, R + 1)
    m10, m01 = moments(sm, xs, ys)
    win = sm[ys[:, None, None] + off[None, :, None], xs[:, None, None] + off[None, None, :]]
    return win.reshape(len(xs), W * W), m10, m01


def rotated_twins(img: np.ndarray, xs: np.ndarray, ys: np.ndarray, rng: np.random.Generator, angles: int):
    """Windows and moments of the same keypoints in a rotated copy of ``img`` (a matching pair).

    The image is rotated (cv2.warpAffine, bilinear, as the rotation bench) by one of ``angles``
    random angles per keypoint into a canvas large enough to hold all of it; each keypoint is read at
    its rotated position rounded to the nearest pixel, with the sector computed there.
    """
    import cv2

    h, w = img.shape
    side = int(np.ceil(np.hypot(h, w))) + 2 * (R + 8)
    wins = np.empty((len(xs), W * W), dtype=np.uint8)
    m10 = np.empty(len(xs), dtype=np.int64)
    m01 = np.empty(len(xs), dtype=np.int64)
    which = rng.integers(0, angles, len(xs))
    for a, angle in enumerate(rng.uniform(0.0, 360.0, angles)):
        mat = cv2.getRotationMatrix2D(((w - 1) / 2.0, (h - 1) / 2.0), float(angle), 1.0)
        mat[:, 2] += (side - 1) / 2.0 - np.array([(w - 1) / 2.0, (h - 1) / 2.0])
        rot = cv2.warpAffine(img, mat, (side, side), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
        sel = which == a
        rx = np.floor(mat[0, 0] * xs[sel] + mat[0, 1] * ys[sel] + mat[0, 2] + 0.5).astype(np.int64)
        ry = np.floor(mat[1, 0] * xs[sel] + mat[1, 1] * ys[sel] + mat[1, 2] + 0.5).astype(np.int64)
        wins[sel], m10[sel], m01[sel] = _windows(smooth(rot), rx, ry)
    return wins, m10, m01


def viewpoint_twins(img: np.ndarray, xs: np.ndarray, ys: np.ndarray, rng: np.random.Generator, views: int,
                    max_tilt: float = 50.0):  # fmt: skip
    """Windows and moments of the same keypoints in a copy of ``img`` seen from another viewpoint.

    As ``rotated_twins``, but each of the ``views`` random views per image is the viewpoint bench's
    exact homography (orb_tools.viewpoint_bench.tilt_homography): a tilt uniform in 0..``max_tilt``
    degrees about a random in-plane axis, then an in-plane rotation uniform in 0..360 degrees, scale
    1; the view is translated into a canvas that holds all of it with a margin (R + 8)."""
    import cv2

    from orb_tools.viewpoint_bench import tilt_homography

    h, w = img.shape
    wins = np.empty((len(xs), W * W), dtype=np.uint8)
    m10 = np.empty(len(xs), dtype=np.int64)
    m01 = np.empty(len(xs), dtype=np.int64)
    which = rng.integers(0, views, len(xs))
    corners = np.array([[0, w - 1, w - 1, 0], [0, 0, h - 1, h - 1], [1, 1, 1, 1]], dtype=np.float64)
    cx, cy = (w - 1) / 2.0, (h - 1) / 2.0
    to_c = np.array([[1, 0, -cx], [0, 1, -cy], [0, 0, 1]])
    back = np.array([[1, 0, cx], [0, 1, cy], [0, 0, 1]])

    def rz(deg: float) -> np.ndarray:
        c, s_ = np.cos(np.radians(deg)), np.sin(np.radians(deg))
        return np.array([[c, s_, 0], [-s_, c, 0], [0, 0, 1]])

    for a in range(views):
        tilt, axis_angle, rot = rng.uniform(0.0, max_tilt), rng.uniform(0.0, 180.0), rng.uniform(0.0, 360.0)
        # a tilt about an axis at axis_angle: rotate the axis onto x, tilt about x, rotate back, then rotate
        hm = back @ rz(-axis_angle) @ to_c @ tilt_homography(img.shape, tilt, "x", axis_angle + rot)
        pc = hm @ corners
        px, py = pc[0] / pc[2], pc[1] / pc[2]
        shift = np.array([[1, 0, R + 8 - px.min()], [0, 1, R + 8 - py.min()], [0, 0, 1]])
        hm = shift @ hm
        size = (int(np.ceil(px.max() - px.min())) + 2 * (R + 8), int(np.ceil(py.max() - py.min())) + 2 * (R + 8))
        view = cv2.warpPerspective(img, hm, size, flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
        sel = which == a
        q = hm @ np.vstack([xs[sel], ys[sel], np.ones(int(sel.sum()))])
        rx = np.floor(q[0] / q[2] + 0.5).astype(np.int64)
        ry = np.floor(q[1] / q[2] + 0.5).astype(np.int64)
        wins[sel], m10[sel], m01[sel] = _windows(smooth(view), rx, ry)
    return wins, m10, m01


def training_windows(params: GreedyParams, twins: int = 0, twin_kind: str = "rotation", max_tilt: float = 50.0):
    """(961, K) uint8 window values (row (dy+15)*31 + dx+15), m10 and m01 of pattern_learn's keypoints.

    With ``twins`` > 0 also the same for a twin of every keypoint: rotated (``rotated_twins``) or, with
    ``twin_kind`` "viewpoint", seen from another viewpoint tilted up to ``max_tilt`` (``viewpoint_twins``).
    """
    rng = np.random.default_rng([params.seed, 0])
    rng_twin = np.random.default_rng([params.seed, 7])
    parts, tparts = [], []
    for name in TRAINING_IMAGES:
        img = load_image(name)
        xs, ys = keypoints(img, params.fast_threshold)
        if len(xs) > params.per_image:
            pick = np.sort(rng.choice(len(xs), params.per_image, replace=False))
            xs, ys = xs[pick], ys[pick]
        parts.append(_windows(smooth(img), xs, ys))
        if twins:
            if twin_kind == "rotation":
                tparts.append(rotated_twins(img, xs, ys, rng_twin, twins))
            else:
                tparts.append(viewpoint_twins(img, xs, ys, rng_twin, twins, max_tilt))
    win, m10, m01 = (np.concatenate([p[i] for p in parts]) for i in range(3))
    pick = np.arange(len(win))
    if len(win) > params.keypoints:
        pick = np.sort(rng.choice(len(win), params.keypoints, replace=False))
    out = [np.ascontiguousarray(win[pick].T), m10[pick], m01[pick]]
    if twins:
        twin, t10, t01 = (np.concatenate([p[i] for p in tparts]) for i in range(3))
        out += [np.ascontiguousarray(twin[pick].T), t10[pick], t01[pick]]
    return tuple(out)


# ---------------------------------------------------------------------------------------------
# candidates
# ---------------------------------------------------------------------------------------------


def tie_free(seeds: np.ndarray) -> np.ndarray:
    ok = np.ones(len(seeds), dtype=bool)
    for i, q in enumerate(seeds):
        try:
            member_tables(q[None, :], ALL_SECTORS)
        except ValueError:
            ok[i] = False
    return ok


def real_candidates(count: int, min_dist: float, seed: int) -> np.ndarray:
    """(count, 4) float64 seed tests: points uniform in the radius-15 disc on a 1/16 grid."""
    rng = np.random.default_rng(seed)
    out = np.empty((0, 4))
    while len(out) < count:
        m = 4 * count
        r = R * np.sqrt(rng.random((m, 2)))
        phi = 2 * np.pi * rng.random((m, 2))
        x = np.round(r * np.cos(phi) * GRID) / GRID
        y = np.round(r * np.sin(phi) * GRID) / GRID
        q = np.stack([x[:, 0], y[:, 0], x[:, 1], y[:, 1]], axis=1)
        ok = (q[:, 0] ** 2 + q[:, 1] ** 2 <= R * R) & (q[:, 2] ** 2 + q[:, 3] ** 2 <= R * R)
        ok &= np.hypot(q[:, 0] - q[:, 2], q[:, 1] - q[:, 3]) >= min_dist
        q = q[ok]
        q = q[tie_free(q)]
        out = np.concatenate([out, q])
    return out[:count]


def integer_candidates(count: int, min_dist: float, seed: int) -> np.ndarray:
    points = disc_points()
    pairs = sample_candidates(points, 2 * count, min_dist, seed)
    q = np.concatenate([points[pairs[:, 0]], points[pairs[:, 1]]], axis=1).astype(np.float64)
    return q[tie_free(q)][:count]


# ---------------------------------------------------------------------------------------------
# bits and statistics
# ---------------------------------------------------------------------------------------------


class Steered:
    """Training windows sorted by the keypoints' sector for one sector count."""

    def __init__(self, win: np.ndarray, m10: np.ndarray, m01: np.ndarray, n: int) -> None:
        self.sectors = 4 * n
        sec = quantise(m10, m01, n)
        order = np.argsort(sec, kind="stable")
        self.win = np.ascontiguousarray(win[:, order])
        self.inverse = np.argsort(order)
        sec = sec[order]
        self.blocks = [(s, np.searchsorted(sec, s), np.searchsorted(sec, s, side="right")) for s in range(self.sectors)]
        self.k = win.shape[1]

    def bits(self, seeds: np.ndarray) -> np.ndarray:
        """(C, 4N, K) bool: member k of each orbit on every keypoint (sector-steered)."""
        tab = np.stack([member_tables(q[None, :], self.sectors)[:, 0] for q in seeds])  # (C, 4N, 4)
        a = (tab[..., 1] + R) * W + tab[..., 0] + R
        b = (tab[..., 3] + R) * W + tab[..., 2] + R
        b0 = self.win[a] < self.win[b]  # (C, 4N, K) sector-0 member bits
        out = np.empty_like(b0)
        for s, lo, hi in self.blocks:
            out[:, :, lo:hi] = np.roll(b0[:, :, lo:hi], -s, axis=1)
        return out[:, :, self.inverse]

    def pattern_bits(self, tables: np.ndarray) -> np.ndarray:
        """(256, K) bool bits of any per-sector table set (4N, 256, 4), e.g. the rBRIEF pattern."""
        out = np.empty((TESTS, self.k), dtype=bool)
        for s, lo, hi in self.blocks:
            t = tables[s].astype(np.int64)
            a = (t[:, 1] + R) * W + t[:, 0] + R
            b = (t[:, 3] + R) * W + t[:, 2] + R
            out[:, lo:hi] = self.win[a, lo:hi] < self.win[b, lo:hi]
        return out[:, self.inverse]


def dcov(pi: np.ndarray, pj: np.ndarray, p11: np.ndarray) -> np.ndarray:
    """Cov(d_i, d_j) of the XOR bits of two independent keypoints, from the joint frequencies."""
    p10, p01 = pi - p11, pj - p11
    p00 = 1.0 - pi - pj + p11
    return 2.0 * (p11 * p00 + p10 * p01) - 4.0 * pi * (1.0 - pi) * pj * (1.0 - pj)


def gram(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Joint frequency of ones, exact counts in float32 (K < 2^24)."""
    return (a.astype(np.float32) @ b.astype(np.float32).swapaxes(-1, -2)).astype(np.float64) / a.shape[-1]


def set_stats(bits: np.ndarray) -> dict:
    """n_eff, E[D], sd[D], mean |mean - 0.5|, mean and max |corr| of a (T, K) bit matrix."""
    p = bits.mean(axis=1)
    g = gram(bits, bits)
    e = float((2 * p * (1 - p)).sum())
    v = float(dcov(p[:, None], p[None, :], g).sum())
    sd = np.sqrt(p * (1 - p))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = np.abs(g - np.outer(p, p)) / np.outer(sd, sd)
    off = corr[~np.eye(len(p), dtype=bool)]
    # tests with identical (or complementary) bits on every keypoint, counted as tests beyond the first
    canon = np.where(bits[:, :1], ~bits, bits)
    dup = len(bits) - len(np.unique(np.packbits(canon, axis=1), axis=0))
    return {
        "n_eff": e * e / v,
        "E_D": e,
        "sd_D": float(np.sqrt(v)),
        "mean_dev": float(np.abs(p - 0.5).mean()),
        "mean_corr": float(np.nanmean(off)),
        "max_corr": float(np.nanmax(off)),
        "duplicate_tests": dup,
    }


def intrinsic(st: Steered, seeds: np.ndarray, batch: int, twin: Steered | None = None):
    """E_c, V_cc and F_c (expected flips between a keypoint and its rotated twin) of every orbit."""
    e = np.empty(len(seeds))
    v = np.empty(len(seeds))
    f = np.zeros(len(seeds))
    for lo in range(0, len(seeds), batch):
        bits = st.bits(seeds[lo : lo + batch])
        if twin is not None:
            f[lo : lo + batch] = (bits != twin.bits(seeds[lo : lo + batch])).mean(axis=2).sum(axis=1)
        p = bits.mean(axis=2)
        g = gram(bits, bits)
        e[lo : lo + batch] = (2 * p * (1 - p)).sum(axis=1)
        v[lo : lo + batch] = dcov(p[:, :, None], p[:, None, :], g).sum(axis=(1, 2))
    return e, v, f


def greedy(st: Steered, cands: np.ndarray, pool: int, batch: int, log, twin: Steered | None = None) -> np.ndarray:
    """n_eff = E^2 / V, or with ``twin`` d' = (E - F) / sqrt(V) (non-match mean minus match mean over sd)."""
    m = TESTS // st.sectors
    t0 = time.perf_counter()
    e, v, f = intrinsic(st, cands, batch, twin)

    def objective(e_, v_, f_):
        return (e_ - f_) / np.sqrt(v_) if twin is not None else e_ * e_ / v_

    score = objective(e, v, f)
    top = np.argsort(-score, kind="stable")[:pool]
    log(
        f"  intrinsic score of {len(cands)} orbits: best {score[top[0]]:.2f}, pool-th {score[top[-1]]:.2f}, "
        f"median {np.median(score):.2f} ({time.perf_counter() - t0:.0f} s)"
    )
    seeds, e, v, f = cands[top], e[top], v[top], f[top]
    bits = st.bits(seeds)  # (P, 4N, K)
    p = bits.mean(axis=2)
    cross = np.zeros(len(seeds))
    chosen: list[int] = []
    e_s = v_s = f_s = 0.0
    # the pattern's integer tests must be distinct (tb/model/test_pattern.py): a candidate whose members
    # round onto each other or onto a test already chosen is not taken
    tables = member_tables(seeds, st.sectors)  # (4N, P, 4)
    tests_of = [set(map(tuple, tables[:, i].tolist())) for i in range(len(seeds))]
    taken: set[tuple[int, ...]] = set()
    for step in range(m):
        total = objective(e_s + e, v_s + v + 2 * cross, f_s + f)
        total[chosen] = -np.inf
        total[[i for i, t in enumerate(tests_of) if len(t) < st.sectors or t & taken]] = -np.inf
        c = int(np.argmax(total))
        chosen.append(c)
        taken |= tests_of[c]
        e_s += e[c]
        f_s += f[c]
        v_s += v[c] + 2 * cross[c]
        new = bits[c].astype(np.float32)  # (4N, K)
        for lo in range(0, len(seeds), batch):
            g = gram(bits[lo : lo + batch], new[None])  # (B, 4N, 4N)
            cross[lo : lo + batch] += dcov(p[lo : lo + batch, :, None], p[c][None, None, :], g).sum(axis=(1, 2))
        log(
            f"  orbit {step}: candidate {c} (own n_eff {e[c] ** 2 / v[c]:.2f}, flips {f[c]:.2f}/{st.sectors}) "
            f"seed {seeds[c].tolist()}; selection n_eff {e_s**2 / v_s:.2f} of {(step + 1) * st.sectors}, "
            f"E[D] {e_s:.1f}, flips {f_s:.1f}, sd {np.sqrt(v_s):.2f}, d' {(e_s - f_s) / np.sqrt(v_s):.2f}"
        )
    return seeds[chosen]


@dataclass(frozen=True)
class OrbitParams:
    candidates: int = 2000
    pool: int = 300
    batch: int = 64
    twins: int = 3  # > 0: objective d' with rotated twins (this many angles per image); 0: n_eff
    integer: bool = False  # integer seed candidates instead of the 1/16 grid
    random_seed: int = 1001  # seed of the random baseline's candidates
    twin_kind: str = "rotation"  # rotation: rotated twins; viewpoint: tilted and rotated (viewpoint_twins)
    max_tilt: float = 50.0  # viewpoint twins: the largest tilt (degrees)


def log(s: str) -> None:
    print(s, flush=True)


def learn(op: OrbitParams, sector_counts: tuple[int, ...]) -> tuple[dict[int, np.ndarray], str]:
    """Learned seeds per sector count and their description (the experiment's ORBIT_SOURCE)."""
    params = GreedyParams()
    t0 = time.perf_counter()
    win, m10, m01, *tw = training_windows(params, op.twins, op.twin_kind, op.max_tilt)
    log(f"training keypoints {win.shape[1]} ({time.perf_counter() - t0:.0f} s)")
    if op.integer:
        cands = integer_candidates(op.candidates, params.min_dist, params.seed)
    else:
        cands = real_candidates(op.candidates, params.min_dist, params.seed)
    log(f"{len(cands)} candidates ({time.perf_counter() - t0:.0f} s)")
    learned: dict[int, np.ndarray] = {}
    for sectors in sector_counts:
        n = sectors // 4
        st = Steered(win, m10, m01, n)
        twin = Steered(*tw, n) if tw else None
        log(f"{sectors} sectors: {TESTS // sectors} orbits of {sectors}")
        learned[sectors] = greedy(st, cands, op.pool, op.batch, log, twin)
        bits = st.pattern_bits(orbit_patterns(learned[sectors], sectors))
        s = set_stats(bits)
        if twin is not None:
            s["twin_flips"] = float(
                (bits != twin.pattern_bits(orbit_patterns(learned[sectors], sectors))).mean(axis=1).sum()
            )
            s["dprime"] = (s["E_D"] - s["twin_flips"]) / s["sd_D"]
        log("  training, learned: " + ", ".join(f"{k} {v:.4g}" for k, v in s.items()))
        log(f"  ({time.perf_counter() - t0:.0f} s)")
    kind = "integer" if op.integer else f"real (1/{GRID} grid)"
    if op.twin_kind == "rotation":  # the adopted seeds' text, byte for byte
        objective = f"d' with rotated twins ({op.twins} angles per image)" if op.twins else "n_eff"
    else:
        objective = f"d' with tilted (0..{op.max_tilt:g} degrees) and rotated twins ({op.twins} views per image)"
    source = (
        f"orbit greedy {objective}, {kind} seeds, candidates={op.candidates} pool={op.pool}, "
        f"pattern_learn training keypoints (seed {params.seed}, {win.shape[1]}), sector-steered"
    )
    return learned, source


def random_seeds(sector_counts: tuple[int, ...], seed: int = 1001) -> tuple[dict[int, np.ndarray], str]:
    """Baseline: the first 256 / 4N random candidates (the experiment's orbit-random)."""
    rnd = real_candidates(TESTS // 16, GreedyParams().min_dist, seed)  # as the experiment: 16 drawn
    return {s: rnd[: TESTS // s] for s in sector_counts}, f"first 256/4N of real_candidates(seed {seed})"


# ---------------------------------------------------------------------------------------------
# the seed data file (read by sw/orb_flow/gen/pattern.py)
# ---------------------------------------------------------------------------------------------


def seeds_json(method: str, source: str, seeds: dict[int, np.ndarray]) -> str:
    """golden_model/data/orbit_seeds.json's text: one seed test (x1, y1, x2, y2) per line."""

    def num(v: float) -> str:
        if v * GRID != round(v * GRID):
            raise ValueError(f"seed coordinate {v!r} is not on the 1/{GRID} grid")
        return json.dumps(float(v))

    lines = [
        "{",
        f'  "description": {json.dumps(DESCRIPTION)},',
        f'  "method": {json.dumps(method)},',
        f'  "source": {json.dumps(source)},',
        '  "seeds": {',
    ]
    for i, sectors in enumerate(sorted(seeds)):
        rows = np.asarray(seeds[sectors], dtype=np.float64).tolist()
        lines.append(f'    "{sectors}": [')
        lines += [
            f"      [{', '.join(num(v) for v in t)}]" + ("," if j < len(rows) - 1 else "") for j, t in enumerate(rows)
        ]
        lines.append("    ]" + ("," if i < len(seeds) - 1 else ""))
    lines += ["  }", "}", ""]
    return "\n".join(lines)


DESCRIPTION = (
    "rBRIEF orbit seeds (docs/pattern.md, spec section 10): seeds[4N] holds the 256 / 4N seed tests "
    "[x1, y1, x2, y2] (multiples of 1/16, both points inside radius 15) for 4N = 16, 32, 64 sectors. "
    "Written by research/pattern/orbit_learn.py; sw/orb_flow/gen/pattern.py (make pattern) generates "
    "golden_model/pattern_data.py from it."
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--method", choices=["orbit-dprime", "orbit-random"], default="orbit-dprime")
    ap.add_argument("--twins", choices=["rotation", "viewpoint"], default="viewpoint",
                    help="orbit-dprime's matching twins: viewpoint changes (the adopted seeds) or rotated copies")
    ap.add_argument("--views", type=int, default=6, help="twin views (angles) per training image (adopted: 6)")
    ap.add_argument("--candidates", type=int, default=OrbitParams.candidates, help="seed candidates drawn")
    ap.add_argument("--pool", type=int, default=OrbitParams.pool, help="candidates kept for the greedy selection")
    ap.add_argument("--max-tilt", type=float, default=OrbitParams.max_tilt, help="the viewpoint twins' largest tilt")
    ap.add_argument("--out", type=Path, default=SEEDS_JSON, help=f"seed data to write (default: {SEEDS_JSON})")
    args = ap.parse_args()
    if args.method == "orbit-dprime":
        seeds, source = learn(OrbitParams(candidates=args.candidates, pool=args.pool, twins=args.views,
                                     twin_kind=args.twins, max_tilt=args.max_tilt), SECTOR_COUNTS)
    else:
        seeds, source = random_seeds(SECTOR_COUNTS)
    method = args.method + ("-viewpoint" if args.method == "orbit-dprime" and args.twins == "viewpoint" else "")
    args.out.write_text(seeds_json(method, source, seeds))
    print(f"wrote {args.out}; now run `make pattern` (or sw/orb_flow/gen/pattern.py --seeds {args.out} --out ...)")


if __name__ == "__main__":
    main()
