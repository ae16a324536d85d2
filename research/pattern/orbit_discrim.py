#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Discriminability of the test patterns, independent of rotation (scratch experiment).

For every pattern kind (rbrief, orbit, orbit-random) and sector count, the model's descriptors of
the evaluation photographs (threshold 20, 1 scale) and the Hamming distances between every pair of
different keypoints of the same photograph (non-matching pairs), pooled over the photographs:
mean, standard deviation, 1st percentile, fraction below 64, n_eff = mean^2 / var, and the median
over keypoints of the distance to the nearest other keypoint.

Also checks, for the orbit kinds, that the descriptor of a feature in sector s equals the sector-0
descriptor of the same feature with the bits permuted within each orbit (the hardware's scheme).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from golden_model import pattern
from golden_model.brief import describe
from golden_model.images import load_luma
from golden_model.orientation import quantise
from golden_model.pipeline import orb_level

KINDS = ("rbrief", "orbit", "orbit-dprime", "orbit-random")


def hamming_all(desc: np.ndarray) -> np.ndarray:
    bits = np.unpackbits(desc, axis=1, bitorder="little").astype(np.float32)
    ones = bits.sum(axis=1)
    return ones[:, None] + ones[None, :] - 2 * (bits @ bits.T)


def main() -> None:
    photos = [Path(p) for p in sys.argv[1:]]
    levels = [orb_level(load_luma(p), 0, 20) for p in photos]
    print(f"keypoints: {', '.join(f'{p.stem} {len(lv.xs)}' for p, lv in zip(photos, levels, strict=True))}")
    print("kind          sectors   mean     sd     p1   <64 (%)  n_eff  median nearest")
    for kind in KINDS:
        pattern.PATTERN_KIND = kind
        pattern.rotated_patterns.cache_clear()
        for n in (4, 8, 16):
            dists, nearest = [], []
            for lv in levels:
                sec = quantise(lv.m10, lv.m01, n)
                desc = describe(lv.smoothed, lv.xs, lv.ys, sec, n)
                if kind != "rbrief":
                    d0 = describe(lv.smoothed, lv.xs, lv.ys, np.zeros_like(sec), n)
                    b = np.unpackbits(desc, axis=1, bitorder="little")
                    b0 = np.unpackbits(d0, axis=1, bitorder="little")
                    for s in np.unique(sec):
                        m = sec == s
                        assert np.array_equal(b[m], b0[m][:, pattern.orbit_permutation(4 * n, int(s))])
                h = hamming_all(desc)
                iu = np.triu_indices(len(h), 1)
                dists.append(h[iu])
                np.fill_diagonal(h, np.inf)
                nearest.append(h.min(axis=1))
            d = np.concatenate(dists).astype(np.float64)
            near = np.concatenate(nearest)
            print(
                f"{kind:13s} {4 * n:7d} {d.mean():6.2f} {d.std():6.2f} {np.percentile(d, 1):6.1f} "
                f"{100 * (d < 64).mean():8.3f} {d.mean() ** 2 / d.var():6.1f} {np.median(near):8.1f}",
                flush=True,
            )
    print("permutation property verified on every orbit descriptor")


if __name__ == "__main__":
    main()
