# SPDX-License-Identifier: MIT
"""Per-level feature budgets: keep each pyramid level's strongest features (docs/spec.md section 14).

The accelerator reports every feature it finds; a host that wants a fixed number per frame, as
OpenCV's ORB gives one, keeps the best of each level with this rule (the driver's `Frame.best`, the
ROS node's `~budget`, `orb-accel extract --budget`). It costs no hardware: the score is in every
feature word. On the scale benchmark it is worth 6 points (docs/evaluation.md): a flat threshold
keeps too many weak corners at the fine levels.

Budgets: a total N split over L levels as OpenCV's ORB splits `nfeatures`, geometrically with the
ratio q = den / num per level:

    n_k = round(N (1 - q) / (1 - q^L) q^k)   for k < L - 1   (round half to even, Python's round)
    n_{L-1} = max(N - sum of the others, 0)

Selection: within level k the n_k features of highest score; equal scores are taken in raster
order (smaller y first, then smaller x). A level with fewer features keeps all of them; its unused
budget is not passed on. The result is in canonical order (scale, y, x).
"""

from __future__ import annotations

import numpy as np

from .features import Features


def level_budgets(total: int, step: tuple[int, int], levels: int) -> list[int]:
    """The budgets n_0 .. n_{levels-1} of a total (module docstring)."""
    if isinstance(total, bool) or not isinstance(total, (int, np.integer)) or total < 0:
        raise ValueError(f"a feature budget must be a non-negative integer, got {total!r}")
    num, den = step
    if not (levels >= 1 and num > den >= 1):
        raise ValueError(f"need levels >= 1 and a step num > den >= 1, got {levels} levels of {num}:{den}")
    q = den / num
    per = total * (1 - q) / (1 - q**levels)
    out: list[int] = []
    for _ in range(levels - 1):
        out.append(round(per))
        per *= q
    out.append(max(int(total) - sum(out), 0))
    return out


def best_per_level(features: Features, total: int, levels: int) -> Features:
    """The features the budget keeps (module docstring), in canonical order; `levels` is the
    configuration's number of scales (features.step gives the step)."""
    budgets = level_budgets(total, features.step, levels)
    if len(features) and int(features.scale.max()) >= levels:
        raise ValueError(f"a feature of scale {int(features.scale.max())} in a {levels}-level configuration")
    keep: list[np.ndarray] = []
    for k, n in enumerate(budgets):
        idx = np.flatnonzero(features.scale == k)
        order = np.lexsort((features.x[idx], features.y[idx], -features.score[idx]))
        keep.append(idx[order[:n]])
    return features.take(np.concatenate(keep)).sorted()
