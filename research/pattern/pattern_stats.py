#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Statistics of rBRIEF patterns on the evaluation photographs (docs/pattern.md).

For each pattern file (default: the live golden_model/pattern_data.py): geometry checks, and over
the FAST keypoints of astronaut, camera, coffee and chelsea (threshold 20, orb border), with the
tests steered by the model's 32-sector tables: mean |mean - 0.5| of the test bits and the mean and
largest absolute pairwise correlation between tests.
"""

from __future__ import annotations

import argparse
import runpy
from pathlib import Path

import numpy as np

from golden_model.images import to_luma

from . import pattern_learn as pl

LIVE = Path(__file__).resolve().parents[2] / "golden_model" / "pattern_data.py"


def load_pattern(path: Path) -> np.ndarray:
    if path.suffix != ".py":
        raise SystemExit(f"{path}: not a Python pattern file")
    data = runpy.run_path(str(path))  # a pattern file is data written as Python
    if "PATTERN" in data:  # a plain 256-test table (older or candidate patterns)
        return np.array(data["PATTERN"], dtype=np.int64)
    if path.resolve() == LIVE.resolve():  # the live orbit pattern: its sector-0 table at 32 sectors
        from golden_model.pattern import rotated_patterns

        return rotated_patterns(8)[0].astype(np.int64)
    raise SystemExit(f"{path}: holds neither PATTERN nor the live orbit seeds")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("patterns", nargs="*", type=Path, default=[LIVE])
    args = ap.parse_args()
    import skimage.data

    images = [to_luma(getattr(skimage.data, name)()) for name in pl.EVALUATION_IMAGES]
    for path in args.patterns:
        p = load_pattern(path)
        r2 = p[:, 0::2] ** 2 + p[:, 1::2] ** 2
        distinct = len({tuple(t) for t in p.tolist()})
        bits = np.concatenate([pl.sector_steered_bits(img, p, 8, 20) for img in images])
        mean = bits.mean(axis=0)
        mean_corr, max_corr = pl.correlation_stats(bits)
        print(f"{path}: max x^2+y^2 {r2.max()}, distinct tests {distinct}; {len(bits)} keypoints: "
              f"mean |mean-0.5| {np.abs(mean - 0.5).mean():.3f}, mean |corr| {mean_corr:.3f}, "
              f"max |corr| {max_corr:.3f}")  # fmt: skip


if __name__ == "__main__":
    main()
