# SPDX-License-Identifier: MIT
"""Learn an rBRIEF pattern by the greedy decorrelation of Rublee et al., ORB (ICCV 2011), section 4.3.

Training set: FAST keypoints (golden_model.pipeline.detect, orb border rule) of scikit-image's
bundled photographs that are not in the evaluation set (astronaut, camera, coffee, chelsea) nor in
golden_model.images.sample_photographs (which also holds rocket). Each keypoint is steered by its
continuous orientation theta = atan2(m01, m10) of the model's moments on the smoothed image: every
point of the radius-15 disc is rotated by theta (the model's convention, y downwards), rounded half
away from zero and read from the smoothed image. A test's bit on a keypoint is then
steered(p1) < steered(p2), exactly what the accelerator computes up to the sector quantisation.

Candidates: a seeded sample of distinct unordered pairs of integer points of the disc
(x^2 + y^2 <= 225) at least ``min_dist`` apart, each randomly ordered. The paper's candidates are
pairs of non-overlapping 5x5 sub-windows of the 31x31 patch; ours are point tests on the 7x7
binomial-smoothed image, the minimum distance playing the part of the non-overlap.

Greedy: candidates sorted by |mean - 0.5| (stable); walk the list and keep a test when its absolute
Pearson correlation with every kept test is below the threshold; with fewer than 256 kept, raise
the threshold by ``corr_step`` and start again.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from golden_model.images import to_luma
from golden_model.orientation import moments, quantise
from golden_model.pattern import TIE_MARGIN, rotate_points, round_half_away
from golden_model.pipeline import detect, in_desc_border
from golden_model.smooth import smooth

RADIUS = 15
TESTS = 256
EVALUATION_IMAGES = ("astronaut", "camera", "coffee", "chelsea")
# retina (14 keypoints at threshold 20) and cell (0) add nothing; horse is a binary silhouette;
# rocket is left out because golden_model.images.sample_photographs uses it.
TRAINING_IMAGES = (
    "brick",
    "grass",
    "gravel",
    "coins",
    "moon",
    "hubble_deep_field",
    "motorcycle_left",
    "motorcycle_right",
)
ALL_SECTORS = 64  # 4N for N = 16; the sectors of N = 4 and 8 are a subset


@dataclass(frozen=True)
class GreedyParams:
    seed: int = 1
    fast_threshold: int = 20
    keypoints: int = 20000
    per_image: int = 4000
    candidates: int = 40000
    min_dist: float = 2.0
    corr_start: float = 0.10
    corr_step: float = 0.01
    block: int = 2048


@dataclass(frozen=True)
class TrainingSet:
    values: np.ndarray  # (K, P) uint8: steered smoothed values at the disc points
    counts: dict[str, int]  # keypoints used per image


def load_image(name: str) -> np.ndarray:
    """A bundled scikit-image picture as 8-bit luma (motorcycle_* are read from the data folder)."""
    import skimage.data
    import skimage.io

    if name.startswith("motorcycle_"):
        img = skimage.io.imread(Path(skimage.data.__file__).parent / f"{name}.png")
    else:
        img = getattr(skimage.data, name)()
    return to_luma(np.ascontiguousarray(img))


def disc_points(radius: int = RADIUS) -> np.ndarray:
    """(P, 2) int64 (x, y) of the integer points with x^2 + y^2 <= radius^2, in raster order."""
    r = np.arange(-radius, radius + 1)
    xs, ys = np.meshgrid(r, r)
    inside = xs * xs + ys * ys <= radius * radius
    return np.stack([xs[inside], ys[inside]], axis=1).astype(np.int64)


def keypoints(img: np.ndarray, fast_threshold: int) -> tuple[np.ndarray, np.ndarray]:
    xs, ys, _, _ = detect(img, fast_threshold)
    keep = in_desc_border(xs, ys, img.shape[1], img.shape[0])
    return xs[keep], ys[keep]


def orientations(smoothed: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """Continuous keypoint angles in radians, atan2(m01, m10) with y downwards."""
    m10, m01 = moments(smoothed, xs, ys)
    return np.arctan2(m01.astype(np.float64), m10.astype(np.float64))


def steered_values(
    smoothed: np.ndarray, xs: np.ndarray, ys: np.ndarray, theta: np.ndarray, points: np.ndarray
) -> np.ndarray:
    """(K, P) smoothed values at ``points`` rotated by each keypoint's theta."""
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    px, py = points[None, :, 0], points[None, :, 1]
    rx = round_half_away(px * c - py * s).astype(np.int64)
    ry = round_half_away(px * s + py * c).astype(np.int64)
    return smoothed[ys[:, None] + ry, xs[:, None] + rx]


def image_values(name: str, params: GreedyParams, rng: np.random.Generator, points: np.ndarray) -> np.ndarray:
    """Steered values of at most ``per_image`` random keypoints of one image."""
    img = load_image(name)
    xs, ys = keypoints(img, params.fast_threshold)
    if len(xs) > params.per_image:
        pick = np.sort(rng.choice(len(xs), params.per_image, replace=False))
        xs, ys = xs[pick], ys[pick]
    smoothed = smooth(img)
    return steered_values(smoothed, xs, ys, orientations(smoothed, xs, ys), points)


def training_set(params: GreedyParams, points: np.ndarray) -> TrainingSet:
    rng = np.random.default_rng([params.seed, 0])
    parts = [image_values(name, params, rng, points) for name in TRAINING_IMAGES]
    owner = np.concatenate([np.full(len(p), i) for i, p in enumerate(parts)])
    values = np.concatenate(parts)
    if len(values) > params.keypoints:
        pick = np.sort(rng.choice(len(values), params.keypoints, replace=False))
        values, owner = values[pick], owner[pick]
    counts = {name: int((owner == i).sum()) for i, name in enumerate(TRAINING_IMAGES)}
    return TrainingSet(values, counts)


def sample_candidates(points: np.ndarray, count: int, min_dist: float, seed: int) -> np.ndarray:
    """(C, 2) point-index pairs: distinct unordered pairs at least ``min_dist`` apart, random order."""
    rng = np.random.default_rng([seed, 1])
    i, j = np.triu_indices(len(points), k=1)
    d2 = ((points[i] - points[j]) ** 2).sum(axis=1)
    eligible = np.flatnonzero(d2 >= min_dist * min_dist)
    if count > len(eligible):
        raise ValueError(f"only {len(eligible)} eligible pairs, {count} candidates asked for")
    pick = np.sort(rng.choice(eligible, count, replace=False))
    pairs = np.stack([i[pick], j[pick]], axis=1)
    swap = rng.random(count) < 0.5
    pairs[swap] = pairs[swap][:, ::-1]
    return pairs


def test_bits(values: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """(K, C) bool: the tests steered(p1) < steered(p2)."""
    return values[:, pairs[:, 0]] < values[:, pairs[:, 1]]


@dataclass(frozen=True)
class Candidates:
    """Candidate tests in greedy order (most balanced first) with their training bits."""

    pairs: np.ndarray  # (C, 2) point-index pairs
    bits: np.ndarray  # (C, K) bool, one row per candidate
    mean: np.ndarray  # (C,) float64 fraction of ones
    std: np.ndarray  # (C,) float64 sqrt(mean * (1 - mean))


def ordered_candidates(values: np.ndarray, pairs: np.ndarray, chunk: int = 4096) -> Candidates:
    """Evaluate every candidate on the training set, sort by |mean - 0.5| and drop constant tests."""
    bits = np.empty((len(pairs), len(values)), dtype=bool)
    for k in range(0, len(pairs), chunk):
        bits[k : k + chunk] = test_bits(values, pairs[k : k + chunk]).T
    mean = np.count_nonzero(bits, axis=1) / len(values)
    order = np.argsort(np.abs(mean - 0.5), kind="stable")
    order = order[(mean[order] > 0.0) & (mean[order] < 1.0)]  # a constant test has no correlation
    mean = mean[order]
    return Candidates(pairs[order], bits[order], mean, np.sqrt(mean * (1.0 - mean)))


def abs_corr(a: np.ndarray, ia: np.ndarray, b: np.ndarray, ib: np.ndarray, cands: Candidates) -> np.ndarray:
    """|Pearson correlation| between rows ``a`` (candidates ``ia``) and rows ``b`` (candidates ``ib``).

    ``a`` and ``b`` are 0/1 float32 rows; their products are integer counts below 2^24, exact in
    float32 whatever the BLAS, so the result does not depend on the machine.
    """
    k = a.shape[1]
    both = (a @ b.T).astype(np.float64) / k
    ma, mb = cands.mean[ia][:, None], cands.mean[ib][None, :]
    return np.abs(both - ma * mb) / (cands.std[ia][:, None] * cands.std[ib][None, :])


class Selection:
    """The tests kept so far in one greedy pass."""

    def __init__(self, cands: Candidates, threshold: float) -> None:
        self.cands = cands
        self.threshold = threshold
        self.index: list[int] = []
        self.rows = np.empty((TESTS, cands.bits.shape[1]), dtype=np.float32)

    def full(self) -> bool:
        return len(self.index) == TESTS

    def passing(self, rows: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Mask of the candidates whose |corr| with every kept test is below the threshold."""
        n = len(self.index)
        if n == 0:
            return np.ones(len(idx), dtype=bool)
        kept = np.array(self.index)
        return abs_corr(self.rows[:n], kept, rows, idx, self.cands).max(axis=0) < self.threshold

    def offer(self, rows: np.ndarray, idx: np.ndarray) -> None:
        """Walk the candidates in order, keeping those uncorrelated with the kept ones and each other."""
        ok = self.passing(rows, idx)
        rows, idx = rows[ok], idx[ok]
        gram = abs_corr(rows, idx, rows, idx, self.cands)
        chosen: list[int] = []
        for j in range(len(idx)):
            if len(self.index) + len(chosen) == TESTS:
                break
            if not chosen or gram[j, chosen].max() < self.threshold:
                chosen.append(j)
        n = len(self.index)
        self.rows[n : n + len(chosen)] = rows[chosen]
        self.index += idx[chosen].tolist()


def greedy_pass(cands: Candidates, threshold: float, block: int, chunk: int = 256) -> list[int]:
    """One walk over the ordered candidates; the kept candidate indices (at most 256).

    Each block is first screened against the tests kept before it (one matrix product); its
    survivors are then offered in chunks, each screened again and walked sequentially.
    """
    sel = Selection(cands, threshold)
    for start in range(0, len(cands.pairs), block):
        idx = np.arange(start, min(start + block, len(cands.pairs)))
        rows = cands.bits[idx].astype(np.float32)
        ok = sel.passing(rows, idx)
        rows, idx = rows[ok], idx[ok]
        for k in range(0, len(idx), chunk):
            sel.offer(rows[k : k + chunk], idx[k : k + chunk])
            if sel.full():
                return sel.index
    return sel.index


def correlation_stats(bits: np.ndarray) -> tuple[float, float]:
    """Mean and max absolute pairwise Pearson correlation of the columns of a (K, T) bit matrix."""
    b = bits.astype(np.float64)
    b -= b.mean(axis=0)
    norm = np.sqrt((b * b).sum(axis=0))
    corr = np.abs((b.T @ b) / np.outer(norm, norm))
    off = corr[~np.eye(len(corr), dtype=bool)]
    return float(np.nanmean(off)), float(np.nanmax(off))


def check_pattern(pattern: np.ndarray) -> None:
    """Radius, distinct points and tests, and no rounding tie at any of the 64 sector angles."""
    if pattern.shape != (TESTS, 4):
        raise ValueError(f"pattern shape {pattern.shape}")
    r2 = pattern[:, 0::2] ** 2 + pattern[:, 1::2] ** 2
    if (r2 > RADIUS * RADIUS).any():
        raise ValueError("pattern point outside radius 15")
    if (pattern[:, :2] == pattern[:, 2:]).all(axis=1).any():
        raise ValueError("test with identical points")
    if len({tuple(t) for t in pattern.tolist()}) != TESTS:
        raise ValueError("duplicate tests")
    for s in range(ALL_SECTORS):
        raw, _ = rotate_points(pattern, s * 360.0 / ALL_SECTORS)
        if (np.abs(np.abs(raw) - np.floor(np.abs(raw)) - 0.5) < TIE_MARGIN).any():
            raise ValueError(f"rounding tie at sector {s}/{ALL_SECTORS}")


def search_threshold(cands: Candidates, params: GreedyParams, t0: float) -> tuple[list[int], float]:
    """Greedy passes with the threshold raised by ``corr_step`` until 256 tests are kept."""
    threshold = params.corr_start
    while True:
        kept = greedy_pass(cands, threshold, params.block)
        print(f"  threshold {threshold:.2f}: {len(kept)} tests ({time.perf_counter() - t0:.1f} s)")
        if len(kept) == TESTS:
            return kept, threshold
        threshold = round(threshold + params.corr_step, 6)


def learn(params: GreedyParams) -> tuple[np.ndarray, str]:
    """The learned (256, 4) pattern and its PATTERN_SOURCE description."""
    t0 = time.perf_counter()
    points = disc_points()
    train = training_set(params, points)
    print(f"training keypoints: {len(train.values)} " + ", ".join(f"{n}={c}" for n, c in train.counts.items()))
    pairs = sample_candidates(points, params.candidates, params.min_dist, params.seed)
    cands = ordered_candidates(train.values, pairs)
    print(f"{len(pairs)} candidates, {len(cands.pairs)} non-constant ({time.perf_counter() - t0:.1f} s)")
    kept, threshold = search_threshold(cands, params, t0)
    sel = cands.pairs[kept]
    pattern = np.concatenate([points[sel[:, 0]], points[sel[:, 1]]], axis=1)
    check_pattern(pattern)
    mean_corr, max_corr = correlation_stats(cands.bits[kept].T)
    mean_dev = float(np.abs(cands.mean[kept] - 0.5).mean())
    print(f"final threshold {threshold:.2f}; training mean |corr| {mean_corr:.4f}, max {max_corr:.4f}, "
          f"mean |mean - 0.5| {mean_dev:.4f}; {time.perf_counter() - t0:.1f} s")  # fmt: skip
    return pattern, describe_source(params, train, threshold)


def describe_source(params: GreedyParams, train: TrainingSet, threshold: float) -> str:
    return (
        f"greedy (Rublee et al. 2011, sec. 4.3) seed={params.seed}"
        f" images={','.join(n for n, c in train.counts.items() if c)}"
        f" keypoints={len(train.values)} (FAST threshold {params.fast_threshold}, <= {params.per_image}"
        f" per image, steered by continuous theta) candidates={params.candidates} point pairs"
        f" (min distance {params.min_dist:g}) corr_threshold={threshold:.2f}"
    )


def sector_steered_bits(img: np.ndarray, pattern: np.ndarray, n: int, fast_threshold: int) -> np.ndarray:
    """(K, 256) bits of ``pattern`` on the keypoints of ``img``, steered by the model's sectors."""
    xs, ys = keypoints(img, fast_threshold)
    smoothed = smooth(img)
    m10, m01 = moments(smoothed, xs, ys)
    sectors = quantise(m10, m01, n)
    tables = np.stack([rotate_points(pattern, s * 360.0 / (4 * n))[1] for s in range(4 * n)])
    pats = tables[sectors]
    p1 = smoothed[ys[:, None] + pats[..., 1], xs[:, None] + pats[..., 0]]
    p2 = smoothed[ys[:, None] + pats[..., 3], xs[:, None] + pats[..., 2]]
    return p1 < p2


def continuous_steered_bits(img: np.ndarray, pattern: np.ndarray, fast_threshold: int) -> np.ndarray:
    """(K, 256) bits of ``pattern`` on the keypoints of ``img``, steered by continuous theta."""
    xs, ys = keypoints(img, fast_threshold)
    smoothed = smooth(img)
    points = pattern.reshape(-1, 2)
    values = steered_values(smoothed, xs, ys, orientations(smoothed, xs, ys), points)
    return values[:, 0::2] < values[:, 1::2]
