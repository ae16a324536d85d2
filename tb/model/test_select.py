# SPDX-License-Identifier: MIT
"""golden_model.select: per-level budgets (spec section 14), hand values and the rules on photographs."""

from __future__ import annotations

import numpy as np
import pytest

from golden_model import Config, extract
from golden_model.features import NO_SECTOR, Features
from golden_model.select import best_per_level, level_budgets


@pytest.mark.parametrize(
    ("total", "step", "levels", "budgets"),
    [
        # q = 0.8: 1000 * 0.2 / (1 - 0.8^4) = 338.75 -> 339, 271.00 -> 271, 216.80 -> 217, rest 173
        (1000, (5, 4), 4, [339, 271, 217, 173]),
        # q = 0.5: 100 * 0.5 / (1 - 0.5^2) = 66.67 -> 67, rest 33
        (100, (2, 1), 2, [67, 33]),
        (7, (5, 4), 1, [7]),
        (0, (5, 4), 3, [0, 0, 0]),
        (3, (2, 1), 4, [2, 1, 0, 0]),  # 1.6 -> 2, 0.8 -> 1, 0.4 -> 0, rest max(3 - 3, 0)
    ],
)
def test_budgets_hand_values(total: int, step: tuple[int, int], levels: int, budgets: list[int]) -> None:
    assert level_budgets(total, step, levels) == budgets


@pytest.mark.parametrize(
    ("total", "step", "levels"), [(-1, (5, 4), 2), (10, (4, 4), 2), (10, (5, 4), 0), (1.5, (2, 1), 2)]
)
def test_budgets_refuse_bad_input(total, step, levels) -> None:
    with pytest.raises(ValueError):
        level_budgets(total, step, levels)


def _features(scale, x, y, score, step=(5, 4)) -> Features:
    n = len(x)
    arr = [np.array(v, dtype=np.int64) for v in (scale, x, y, score)]
    return Features(*arr, np.full(n, NO_SECTOR, dtype=np.int64), np.zeros((n, 0), dtype=np.uint8), 32, step)


def test_selection_keeps_the_highest_scores_and_breaks_ties_in_raster_order() -> None:
    # level 0 budget 2 of 3 (total 3 over 2 levels of 2:1: [2, 1]); level 1 budget 1
    f = _features([0, 0, 0, 0, 1, 1], [5, 9, 2, 7, 3, 1], [4, 4, 6, 1, 2, 2], [50, 80, 80, 10, 30, 30], step=(2, 1))
    got = best_per_level(f, 3, 2)
    # level 0: score 80 twice (y=4, x=9 before y=6, x=2), then 50 is cut; level 1: tie 30, x=1 first
    assert list(zip(got.scale.tolist(), got.x.tolist(), got.y.tolist(), strict=True)) == [
        (0, 9, 4),
        (0, 2, 6),
        (1, 1, 2),
    ]
    assert got.step == (2, 1)


def test_selection_on_a_photograph(photographs) -> None:
    img = photographs["astronaut"][:240, :320]
    cfg = Config(320, 240, scales=4, step_num=5, step_den=4, threshold=20)
    feats = extract(img, cfg)
    got = best_per_level(feats, 600, cfg.scales)
    budgets = level_budgets(600, cfg.step, cfg.scales)
    assert got == got.sorted()
    for k, n in enumerate(budgets):
        lvl, kept = feats.score[feats.scale == k], got.score[got.scale == k]
        assert len(kept) == min(n, len(lvl)), f"level {k}"
        if len(kept) < len(lvl):  # everything kept scores at least as high as everything cut
            assert kept.min() >= np.sort(lvl)[::-1][len(kept)], f"level {k}"
    assert best_per_level(feats, 10**6, cfg.scales) == feats  # a budget above the count keeps all
    with pytest.raises(ValueError, match="scale 3"):
        best_per_level(feats, 600, 3)
