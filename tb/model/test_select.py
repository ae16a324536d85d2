# SPDX-License-Identifier: MIT
"""golden_model.select: per-level budgets and the grid selection (spec section 14), hand values, the
streaming form against the declarative rule, and the rules on photographs."""

from __future__ import annotations

import numpy as np
import pytest

from golden_model import Config, extract
from golden_model.config import level_size
from golden_model.features import NO_SECTOR, Features
from golden_model.pipeline import candidates
from golden_model.select import (
    CELL_SHIFT,
    CellGrid,
    LevelSelector,
    arrival_order,
    best_per_level,
    cell_axis,
    level_budgets,
    level_slots,
    rest_key,
    select_grid,
    select_level,
    streamed_grid,
    truncation_difference,
)


@pytest.mark.parametrize(
    ("total", "step", "levels", "budgets"),
    [
        # F_k = round(2^16 * 125/369, 100/369, 80/369) = 22200, 17760, 14208:
        # (1000 F_k + 2^15) >> 16 = 339, 271, 217, rest 173
        (1000, (5, 4), 4, [339, 271, 217, 173]),
        # F_0 = round(2^16 * 2/3) = 43691: 67, rest 33
        (100, (2, 1), 2, [67, 33]),
        (7, (5, 4), 1, [7]),
        (0, (5, 4), 3, [0, 0, 0]),
        # F = 34953, 17476, 8738: 2, 1, 0 (0.9 rounds down), then min(., 3 - 3) = 0, rest 0
        (3, (2, 1), 4, [2, 1, 0, 0]),
        # 1000 in 5 levels of 5:4 (docs/spec.md section 14's example)
        (1000, (5, 4), 5, [297, 238, 190, 152, 123]),
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


@pytest.mark.parametrize("step", [(2, 1), (5, 4), (3, 2), (9, 8), (15, 8), (16, 8)])
def test_budgets_sum_to_the_total_and_follow_the_geometric_split(step: tuple[int, int]) -> None:
    num, den = step
    for levels in range(1, 9):
        for total in [*list(range(0, 40)), 999, 1000, 2047, 4095]:
            got = level_budgets(total, step, levels)
            assert sum(got) == total and min(got) >= 0, (total, step, levels, got)
            q = den / num
            exact = [total * (1 - q) / (1 - q**levels) * q**k for k in range(levels)]
            # every level but the last within one of its exact share, unless the total ran out
            # (the min of the rule); the last takes the rest
            for k in range(levels - 1):
                assert got[k] <= exact[k] + 1.0, (total, step, levels, got)
                assert got[k] >= exact[k] - 1.0 or sum(got[: k + 1]) == total, (total, step, levels, got)


def _random_level(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int, CellGrid]:
    """Candidates of a level in raster order (never two at one pixel), with low flags and codes, and
    a grid: square cells, or a random frame's grid at a random level."""
    w, h = int(rng.integers(20, 200)), int(rng.integers(20, 200))
    count = int(rng.integers(0, 150))
    pos = np.sort(rng.choice(w * h, size=min(count, w * h), replace=False))
    low = rng.random(len(pos)) < rng.random()
    codes = rng.integers(0, int(rng.integers(1, 64)), len(pos))  # few codes: many ties
    if rng.random() < 0.5:
        grid = CellGrid.square(int(rng.integers(16, 90)))
    else:
        level = int(rng.integers(0, 4))
        full = (w * 5**level // 4**level + 1, h * 5**level // 4**level + 1)
        cols, rows = int(rng.integers(1, 16)), int(rng.integers(1, 16))
        grid = CellGrid(*cell_axis(cols, full[0], level, (5, 4)), *cell_axis(rows, full[1], level, (5, 4)))
    return pos % w, pos // w, low, codes, int(rng.integers(0, 40)), grid


def test_streaming_selector_keeps_exactly_the_declarative_selection() -> None:
    """LevelSelector (what the fabric does, one candidate at a time) and select_level (spec 14) agree
    on 3000 random levels: ties, low corners, more cells than places, budget 0."""
    rng = np.random.default_rng(24)
    for trial in range(3000):
        x, y, low, codes, n, grid = _random_level(rng)
        sel = LevelSelector(n, grid)
        ops = [sel.offer(int(x[i]), int(y[i]), bool(low[i]), int(codes[i])) for i in range(len(x))]
        want = select_level(x, y, low, codes, n, grid).tolist()
        assert sel.kept() == want, f"trial {trial}: n={n} {grid}: streaming {sel.kept()} != {want}"
        # slots: new ones in order 0, 1, ..., never more than n, and a replaced slot was in use
        new = [op[0] for op in ops if op is not None and op[1]]
        assert new == list(range(len(new))) and len(new) <= max(n, 0), f"trial {trial}"
        for k, op in enumerate(ops):
            if op is not None and not op[1]:
                assert op[0] in new[: sum(1 for o in ops[:k] if o is not None and o[1])], f"trial {trial}"


@pytest.mark.parametrize(("width", "height", "step", "levels"),
                         [(640, 480, (5, 4), 8), (1280, 720, (5, 4), 8), (1920, 1080, (5, 4), 8),
                          (1920, 1080, (2, 1), 8), (100, 75, (5, 4), 3), (4095, 4095, (16, 8), 8),
                          (64, 48, (3, 2), 4)])  # fmt: skip
def test_cell_map_is_the_frames_grid(width: int, height: int, step: tuple[int, int], levels: int) -> None:
    """The fixed-point cell map (spec 14) puts every level pixel in the cell of the frame's grid that
    holds its full-resolution position (v + 0.5) a / b - 0.5 (integers: floor(((2 v + 1) a - b)
    cells / (2 full b))), for every grid, but for positions within 2^-16 of a cell boundary; a cell
    row is at least a pixel row high (K < 2^24)."""
    num, den = step
    for k in range(levels):
        size = level_size(width, height, k, step)
        if min(size) < 1:
            break
        a, b = num**k, den**k
        for axis, full in enumerate((width, height)):
            v = np.arange(size[axis], dtype=np.int64)
            for cells in range(1, 16):
                kk, oo = cell_axis(cells, full, k, step)
                got = (v * kk + oo) >> CELL_SHIFT
                num_, den_ = ((2 * v + 1) * a - b) * cells, 2 * full * b
                want = num_ // den_
                if kk < (1 << CELL_SHIFT) - 1:  # (a saturated K: cells below a pixel, not the frame's)
                    # exact but within 2^-16 of a cell boundary, where the 24-bit fraction decides
                    frac = num_ % den_
                    edge = (frac << 16 < den_) | ((den_ - frac) << 16 < den_)
                    off = np.flatnonzero(got != want)
                    assert np.all(edge[off]) and np.all(np.abs(got - want) <= 1), (
                        f"{width}x{height} {step} level {k} axis {axis}, {cells} cells: {v[off][:5]}"
                    )
                assert kk < 1 << CELL_SHIFT and 0 <= oo < 1 << CELL_SHIFT and got.max() <= cells - 1
                assert np.all(np.diff(got) <= 1), "a cell row below a pixel row"


def test_selection_hand_case() -> None:
    """Cells of 10 pixels, budget 3: floors first, then the rest by code, ties by joining time."""
    #           cell (0,0) main 5, (0,0) main 9 (record: displaces 5), (1,0) low 8, (1,0) main 2,
    #           (2,0) low 1, (0,1) main 9 (not a record of a new cell: first of cell (0,1))
    x = np.array([1, 3, 12, 15, 25, 4])
    y = np.array([0, 0, 0, 0, 0, 12])
    low = np.array([False, False, True, False, True, False])
    code = np.array([5, 9, 8, 2, 1, 9])
    # 4 cells hold candidates > budget 3: the floors of the first 3 cells (by first candidate):
    # (0,0) -> index 1, (1,0) -> index 3 (main beats low), (2,0) -> index 4
    assert select_level(x, y, low, code, 3, CellGrid.square(10)).tolist() == [1, 3, 4]
    # budget 5: all 4 floors (1, 3, 4, 5), one place for the rest R = {0 (displaced at 1)}
    assert select_level(x, y, low, code, 5, CellGrid.square(10)).tolist() == [0, 1, 3, 4, 5]
    # budget 6: the low corner 2 (displaced at 3, rest key 0) fills the place the main ones leave
    assert select_level(x, y, low, code, 6, CellGrid.square(10)).tolist() == [0, 1, 2, 3, 4, 5]
    # a main candidate of code 0 shares rest key 1 with code 1 and still comes before a low corner
    x3, y3 = np.array([1, 2, 3, 4]), np.zeros(4, dtype=np.int64)
    low3, code3 = np.array([False, True, False, False]), np.array([9, 60, 1, 0])
    # codes 1 and 0 share rest key 1: the one that joined first (2) stays
    assert select_level(x3, y3, low3, code3, 2, CellGrid.square(16)).tolist() == [0, 2]
    assert select_level(x3, y3, low3, code3, 3, CellGrid.square(16)).tolist() == [0, 2, 3]
    assert select_level(x3, y3, low3, code3, 4, CellGrid.square(16)).tolist() == [0, 1, 2, 3]
    # equal codes in R: the one that joined first stays
    x2, y2 = np.array([1, 2, 3, 4]), np.zeros(4, dtype=np.int64)
    low2, code2 = np.zeros(4, dtype=bool), np.array([7, 3, 3, 3])
    assert select_level(x2, y2, low2, code2, 2, CellGrid.square(16)).tolist() == [0, 1]  # floor 0, then 1 of {1, 2, 3}


def test_grid_selection_on_photographs(photographs) -> None:
    """Per level at most its budget; every cell with a candidate keeps its best one; the rest have
    rest keys at least those of every candidate left out (a low corner only where no main one is left)."""
    checked_sparse = False
    for name, budget in (("astronaut", 300), ("coffee", 300), ("coffee", 3000)):
        img = photographs[name][:240, :320]
        cfg = Config(320, 240, scales=4, step_num=5, step_den=4, threshold=20, threshold_lo=7, selection="grid",
                     budget=budget, cols=8, rows=6)  # fmt: skip
        cand = candidates(img, cfg)
        got = extract(img, cfg)
        assert got == select_grid(cand, cfg) and got == got.sorted()
        assert cand.low.any() and not Config(320, 240, scales=4, step_num=5, step_den=4).selection == "grid"
        for k, n in enumerate(level_budgets(budget, cfg.step, cfg.scales)):
            lv, kept = cand.take(np.flatnonzero(cand.scale == k)), got.take(np.flatnonzero(got.scale == k))
            assert len(kept) <= n, f"{name} level {k}"
            gx, gy = CellGrid.of_level(cfg, k).of(lv.x, lv.y)
            cells = set(zip(gx.tolist(), gy.tolist(), strict=True))
            if len(cells) > n:
                continue
            keys = set(zip(kept.x.tolist(), kept.y.tolist(), strict=True))
            for c in cells:
                m = (gx == c[0]) & (gy == c[1])
                rank = (~lv.low[m]).astype(np.int64) * 64 + lv.response[m]
                best = np.flatnonzero(m)[np.flatnonzero(rank == rank.max())[0]]
                assert (int(lv.x[best]), int(lv.y[best])) in keys, f"{name} level {k} cell {c}"
            # the rest: non-floor candidates; none left out has a higher rest key than the lowest kept
            floor_keys = set()
            for c in cells:
                m = (gx == c[0]) & (gy == c[1])
                rank = (~lv.low[m]).astype(np.int64) * 64 + lv.response[m]
                best = np.flatnonzero(m)[np.flatnonzero(rank == rank.max())[0]]
                floor_keys.add((int(lv.x[best]), int(lv.y[best])))
            rest = [int(rest_key(lo, r)) for a, b, r, lo in zip(kept.x, kept.y, kept.response, kept.low, strict=True)
                    if (int(a), int(b)) not in floor_keys]  # fmt: skip
            left = [int(rest_key(lo, r)) for a, b, r, lo in zip(lv.x, lv.y, lv.response, lv.low, strict=True)
                    if (int(a), int(b)) not in keys]  # fmt: skip
            assert len(kept) == min(n, len(lv)), f"{name} level {k}: a free place left while candidates wait"
            if rest and left:
                assert max(left) <= min(rest), f"{name} level {k}: a rest key above the rest was left out"
            checked_sparse |= len(kept) < n and bool(kept.low.any())
    assert checked_sparse, "no level left places for low corners: the sparse case is not exercised"


def test_streamed_grid_holds_the_selection_and_what_it_replaced(photographs) -> None:
    """The stream of the grid selection (what the overlay marks): a superset of the kept features,
    within the candidates, and equal to them when the budget holds every candidate."""
    img = photographs["astronaut"][:240, :320]
    for budget in (60, 300, 4000):
        cfg = Config(320, 240, scales=3, step_num=5, step_den=4, threshold=20, threshold_lo=7, selection="grid",
                     budget=budget)  # fmt: skip
        cand = candidates(img, cfg)
        kept, streamed = extract(img, cfg), streamed_grid(cand, cfg)
        keys, every, kept_keys = (set(zip(f.scale.tolist(), f.x.tolist(), f.y.tolist(), strict=True))
                                  for f in (streamed, cand, kept))  # fmt: skip
        assert kept_keys <= keys <= every, f"budget {budget}"
        if budget == 60:
            assert len(streamed) > len(kept), "a small budget replaces some streamed features"
        if budget == 4000:  # every level's budget above its candidates: a main corner is never replaced
            assert streamed.take(np.flatnonzero(~streamed.low)) == kept.take(np.flatnonzero(~kept.low))


def test_truncation_difference_accepts_level_prefixes_only(photographs) -> None:
    img = photographs["coffee"][:200, :260]
    cfg = Config(260, 200, scales=3, step_num=5, step_den=4, threshold=15)
    every = extract(img, cfg)
    parts = []
    for k, keep in enumerate((30, 0, 7)):  # each level's first features in arrival order
        w, h = cfg.scale_size(k)
        idx = np.flatnonzero(every.scale == k)
        parts.append(idx[arrival_order(every.x[idx], every.y[idx], w, h)][:keep])
    stored = every.take(np.concatenate(parts)).sorted()
    assert truncation_difference(stored, every, 37, cfg) is None
    assert truncation_difference(stored, every, 38, cfg) is not None  # one too few for the capacity
    assert truncation_difference(every, every, len(every) + 5, cfg) is None  # nothing truncated
    last = np.flatnonzero(every.scale == 0)[-1]  # level 0's last feature: not among its first 30
    assert last not in parts[0]
    hole = every.take(np.concatenate([parts[0][:-1], parts[2], [last]])).sorted()
    assert "missing" in (truncation_difference(hole, every, 37, cfg) or ""), "a feature out of arrival order"


def test_all_selection_reports_the_main_corners_only(photographs) -> None:
    img = photographs["camera"][:200, :260]
    a = extract(img, Config(260, 200, scales=2, threshold=25))
    b = extract(img, Config(260, 200, scales=2, threshold=25, threshold_lo=5))  # ignored in `all`
    assert a == b and not a.low.any()
    g = candidates(img, Config(260, 200, scales=2, threshold=25, threshold_lo=5, selection="grid", budget=100))
    main = g.take(np.flatnonzero(~g.low))
    assert main == a, "the main candidates of the combined NMS are exactly the `all` features"


@pytest.mark.parametrize(("step", "levels", "cap"), [((5, 4), 5, 1023), ((2, 1), 2, 2047), ((5, 4), 8, 4095),
                                                     ((9, 8), 8, 1023), ((16, 8), 1, 15),
                                                     ((3, 2), 4, 511)])  # fmt: skip
def test_level_slots_bound_every_budget(step: tuple[int, int], levels: int, cap: int) -> None:
    """The slots the hardware reserves per level hold every budget up to the capacity."""
    slots = level_slots(cap, step, levels)
    worst = [0] * levels
    for total in range(cap + 1):
        worst = [max(w, b) for w, b in zip(worst, level_budgets(total, step, levels), strict=True)]
    assert all(w <= s for w, s in zip(worst, slots, strict=True)), (worst, slots)
    assert sum(slots) <= cap + levels * levels, "the reservation is far above the capacity"
