#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Hamming distance of true correspondences (scratch experiment): evaluation photos rotated by
17, 45, 100, 163, 200, 289 degrees (cv2, as the rotation bench); an original feature and the rotated
feature nearest its mapped position (<= 1.5 px) form a matching pair whatever their descriptors."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from golden_model import pattern
from golden_model.evaluate import extract_orb_multi, rotate, rotation_matrix
from golden_model.images import load_luma

KINDS = ("rbrief", "orbit", "orbit-dprime", "orbit-random")
ANGLES = (17.0, 45.0, 100.0, 163.0, 200.0, 289.0)


def ham(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.unpackbits(a ^ b, axis=1).sum(axis=1)


def main() -> None:
    imgs = [load_luma(Path(p)) for p in sys.argv[1:]]
    print("kind          sectors  pairs  match mean  match p50  match p90")
    for kind in KINDS:
        pattern.PATTERN_KIND = kind
        pattern.rotated_patterns.cache_clear()
        d = {n: [] for n in (4, 8, 16)}
        for img in imgs:
            orig = extract_orb_multi(img, 20, 1, (4, 8, 16))
            for angle in ANGLES:
                mat = rotation_matrix(img.shape, angle)
                rot = extract_orb_multi(rotate(img, mat), 20, 1, (4, 8, 16))
                for n in d:
                    o, r = orig[n], rot[n]
                    x0, y0 = o.full_res()
                    mx = mat[0, 0] * x0 + mat[0, 1] * y0 + mat[0, 2]
                    my = mat[1, 0] * x0 + mat[1, 1] * y0 + mat[1, 2]
                    xr, yr = r.full_res()
                    dist = np.hypot(xr[None, :] - mx[:, None], yr[None, :] - my[:, None])
                    j = dist.argmin(axis=1)
                    ok = dist[np.arange(len(j)), j] <= 1.5
                    d[n].append(ham(o.descriptor[ok], r.descriptor[j[ok]]))
        for n, parts in d.items():
            v = np.concatenate(parts)
            print(
                f"{kind:13s} {4 * n:7d} {len(v):6d} {v.mean():11.2f} {np.median(v):10.1f} {np.percentile(v, 90):10.1f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
