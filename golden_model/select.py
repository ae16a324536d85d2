# SPDX-License-Identifier: MIT
"""Feature budgets and the selection the accelerator makes per pyramid level (docs/spec.md section 14).

Budgets: a total N is split over L levels as OpenCV's ORB splits `nfeatures`, geometrically with the
ratio q = den / num per level, in integers (the hardware computes the same at each frame start):

    F_k = round(2^16 (num - den) den^k num^(L-1-k) / (num^L - den^L))     (round half up, k < L - 1)
    n_k = min((N F_k + 2^15) >> 16, N - (n_0 + ... + n_{k-1}))             (k < L - 1)
    n_{L-1} = N - (n_0 + ... + n_{L-2})

so the budgets never sum to more than N.

Selection (`grid` mode), per level with budget n, over the level's candidates in arrival order
(the order the NMS decides them: raster order, but for the last row of centres in fast mode,
arrival_order): every NMS survivor the level reports, each with its response code and a flag `low` (a corner
at the low threshold only). The cells are one grid over the frame, `cols` x `rows` cells, the same at
every level: a candidate's cell is the one that holds its full-resolution position (x + 0.5) r^k -
0.5, computed in fixed point (CellGrid: cell (x Kx + Ox) >> 24, with Kx, Ox of the level).

- A candidate is a *record* when its rank (main before low, then the response code) is strictly
  above that of every earlier candidate of its cell. A cell's *floor* is its last record: its best
  candidate, a low one only when the cell has no main corner.
- If the level's cells with candidates number more than n, the floors of the first n of them (in
  the order of their first candidates) are the selection.
- Otherwise every cell keeps its floor, and the rest R, every candidate that is not a floor, fills
  the remaining n - (number of floors) places best first: rest key descending (rest_key: max(code,
  1) for a main candidate, 0 for a low one, so low corners fill only places the main ones leave),
  then by the time each joined R (a candidate that was never a record: its own arrival; a record
  that a later record of its cell displaced: that record's arrival), earlier first.

This is exactly what the fabric's streaming selection keeps (docs/selection.md): floors held per
cell, the rest in a store that evicts its lowest rest key, latest first. `all` mode keeps every main
candidate (nothing is selected; the feature memory stores them in arrival order).

Host budget (`Frame.best`, `orb-accel extract --budget` on every feature): level k keeps its n_k
features of highest SAD score, equal scores in raster order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .config import Config
from .features import Features, first_difference

FIXED_BITS = 16
# the cell map's fraction bits (docs/spec.md section 14)
CELL_SHIFT = 24


def cell_axis(cells: int, full: int, level: int, step: tuple[int, int]) -> tuple[int, int]:
    """(K, O) of one axis of level `level` (docs/spec.md section 14): a level coordinate v lies in
    cell (v K + O) >> 24 of `cells` cells over the frame's `full` pixels, with a = num^k, b = den^k,
    K = min(ceil(2^24 cells a / (full b)), 2^24 - 1) and O = floor(2^23 cells (a - b) / (full b)):
    the cell of the full-resolution position (v + 0.5) a / b - 0.5 (orb_util_pkg.cell_k, cell_o)."""
    num, den = step
    a, b = num**level, den**level
    k = min(-(-(cells * a << CELL_SHIFT) // (full * b)), (1 << CELL_SHIFT) - 1)
    return k, (cells * (a - b) << (CELL_SHIFT - 1)) // (full * b)


@dataclass(frozen=True)
class CellGrid:
    """One level's cell map: the cell of (x, y) is ((x kx + ox) >> 24, (y ky + oy) >> 24)."""

    kx: int
    ox: int
    ky: int
    oy: int

    @classmethod
    def of_level(cls, cfg: Config, level: int) -> CellGrid:
        """The grid of cfg.cols x cfg.rows cells over the frame, at level `level`."""
        return cls(*cell_axis(cfg.cols, cfg.width, level, cfg.step), *cell_axis(cfg.rows, cfg.height, level, cfg.step))

    @classmethod
    def square(cls, size: int) -> CellGrid:
        """Cells of size x size level pixels (cell (x // size, y // size) for coordinates below 2^12):
        for directed tests."""
        k = -(-(1 << CELL_SHIFT) // size)
        return cls(k, 0, k, 0)

    def of(self, x: np.ndarray | int, y: np.ndarray | int) -> tuple[np.ndarray, np.ndarray]:
        """The cells (column, row) of level coordinates."""
        cx = (np.asarray(x, np.int64) * self.kx + self.ox) >> CELL_SHIFT
        cy = (np.asarray(y, np.int64) * self.ky + self.oy) >> CELL_SHIFT
        return cx, cy


def split_fractions(step: tuple[int, int], levels: int) -> list[int]:
    """F_0 .. F_{L-2} of the module docstring (fixed point, 16 fraction bits)."""
    num, den = step
    if not (levels >= 1 and num > den >= 1):
        raise ValueError(f"need levels >= 1 and a step num > den >= 1, got {levels} levels of {num}:{den}")
    d = num**levels - den**levels
    out = []
    for k in range(levels - 1):
        a = (num - den) * den**k * num ** (levels - 1 - k)
        out.append(((a << (FIXED_BITS + 1)) + d) // (2 * d))
    return out


def level_budgets(total: int, step: tuple[int, int], levels: int) -> list[int]:
    """The budgets n_0 .. n_{levels-1} of a total (module docstring)."""
    if isinstance(total, bool) or not isinstance(total, (int, np.integer)) or total < 0:
        raise ValueError(f"a feature budget must be a non-negative integer, got {total!r}")
    total = int(total)
    out: list[int] = []
    for f in split_fractions(step, levels):
        out.append(min((total * f + (1 << (FIXED_BITS - 1))) >> FIXED_BITS, total - sum(out)))
    out.append(total - sum(out))
    return out


def best_per_level(features: Features, total: int, levels: int) -> Features:
    """The host budget (module docstring), in canonical order; `levels` is the configuration's
    number of scales (features.step gives the step)."""
    budgets = level_budgets(total, features.step, levels)
    if len(features) and int(features.scale.max()) >= levels:
        raise ValueError(f"a feature of scale {int(features.scale.max())} in a {levels}-level configuration")
    keep: list[np.ndarray] = []
    for k, n in enumerate(budgets):
        idx = np.flatnonzero(features.scale == k)
        order = np.lexsort((features.x[idx], features.y[idx], -features.score[idx]))
        keep.append(idx[order[:n]])
    return features.take(np.concatenate(keep)).sorted()


def select_level(x: np.ndarray, y: np.ndarray, low: np.ndarray, response: np.ndarray, n: int,
                 grid: CellGrid) -> np.ndarray:  # fmt: skip
    """Indices of the candidates the `grid` selection keeps of one level (module docstring); the
    arrays hold the level's candidates in arrival (raster) order."""
    count = len(x)
    if n <= 0 or count == 0:
        return np.zeros(0, dtype=np.int64)
    x, y = np.asarray(x, np.int64), np.asarray(y, np.int64)
    resp = np.asarray(response, np.int64)
    main = ~np.asarray(low, bool)
    rank = (main.astype(np.int64) << 16) | resp
    cx, cy = grid.of(x, y)
    cid = (cy << 16) | cx
    # group by cell, arrival order inside a group (the arrays are in arrival order: a stable sort)
    order = np.argsort(cid, kind="stable")
    c_o, r_o = cid[order], rank[order]
    start = np.r_[True, c_o[1:] != c_o[:-1]]
    grp = np.cumsum(start) - 1
    first = np.flatnonzero(start)
    # the best rank of the earlier candidates of the same cell (-1 for a cell's first): a running
    # maximum over the groups, each lifted above every earlier group so that the maximum restarts
    lift = grp << 20
    run = np.maximum.accumulate(r_o + lift) - lift
    prev = np.r_[-1, run[:-1]]
    prev[first] = -1
    record_o = r_o > prev
    # a record's successor: the next record of its cell (-1: none, it is the floor)
    pos_o = np.arange(count)
    rec_pos = np.where(record_o, pos_o, count)
    nxt = np.minimum.accumulate(rec_pos[::-1])[::-1]  # first record at or after each position
    succ_pos = np.r_[nxt[1:], count]
    last_of_grp = np.r_[first[1:], count] - 1
    succ_pos = np.where(succ_pos > last_of_grp[grp], count, succ_pos)
    floor_o = record_o & (succ_pos == count)
    cells = len(first)
    if cells > n:
        # the first n cells by the arrival of their first candidate keep their floors
        first_arrival = order[first]
        chosen = np.argsort(first_arrival, kind="stable")[:n]
        keep_grp = np.zeros(cells, dtype=bool)
        keep_grp[chosen] = True
        return np.sort(order[floor_o & keep_grp[grp]])
    floors = order[floor_o]
    rest_o = ~floor_o
    join = np.where(record_o, order[np.minimum(succ_pos, count - 1)], order)  # arrival of the displacing record
    cand = order[rest_o]
    key_join = join[rest_o]
    room = n - len(floors)
    best = np.lexsort((key_join, -rest_key(low, resp)[cand]))[:room]
    return np.sort(np.concatenate([floors, cand[best]]))


def rest_key(low: np.ndarray, response: np.ndarray) -> np.ndarray:
    """The key the rest is ranked by (docs/spec.md section 14): max(code, 1) for a main candidate,
    0 for a low one."""
    return np.where(np.asarray(low, bool), 0, np.maximum(np.asarray(response, np.int64), 1))


def arrival_order(x: np.ndarray, y: np.ndarray, width: int, height: int) -> np.ndarray:
    """The order a level's candidates reach its selection: the order the 3x3 NMS decides them,
    by (min(y + 4, H - 1), min(x + 4, W - 1)) (docs/spec.md section 14): raster order, except that
    in fast mode the last row of centres (y = H - 4) is decided together with the row above it."""
    x, y = np.asarray(x, np.int64), np.asarray(y, np.int64)
    return np.lexsort((np.minimum(x + 4, width - 1), np.minimum(y + 4, height - 1)))


def _levels_in_arrival_order(features: Features, cfg: Config) -> list[tuple[int, CellGrid, np.ndarray]]:
    """Per level: its budget (level_budgets of cfg.budget), its cell grid and the indices of its
    features in arrival order."""
    out = []
    for k, n in enumerate(level_budgets(cfg.budget, features.step, cfg.scales)):
        w, h = cfg.scale_size(k)
        idx = np.flatnonzero(features.scale == k)
        out.append((n, CellGrid.of_level(cfg, k), idx[arrival_order(features.x[idx], features.y[idx], w, h)]))
    return out


def select_grid(features: Features, cfg: Config) -> Features:
    """The `grid` selection (cfg.budget, cfg.cols x cfg.rows cells) of a frame's candidates (all
    levels, any order), in canonical order."""
    keep = [idx[select_level(features.x[idx], features.y[idx], features.low[idx], features.response[idx], n, grid)]
            for n, grid, idx in _levels_in_arrival_order(features, cfg)]  # fmt: skip
    return features.take(np.concatenate(keep)).sorted()


def truncation_difference(stored: Features, every: Features, capacity: int, cfg: Config) -> str | None:
    """For a frame of the `all` selection that filled its bank: None when `stored` is what the
    feature memory keeps of `every` (the model's features) -- min(capacity, len(every)) of them, and
    of each level a prefix in arrival order (the levels interleave by timing, each level in its own
    order: arrival_order), bit-exact; else where they first differ."""
    want_n = min(capacity, len(every))
    if len(stored) != want_n:
        return f"{len(stored)} features stored, expected {want_n} (capacity {capacity}, {len(every)} in the frame)"
    picked: list[np.ndarray] = []
    for k in range(cfg.scales):
        w, h = cfg.scale_size(k)
        idx = np.flatnonzero(every.scale == k)
        idx = idx[arrival_order(every.x[idx], every.y[idx], w, h)]
        picked.append(idx[: int(np.count_nonzero(stored.scale == k))])
    return first_difference(stored, every.take(np.concatenate(picked)).sorted())


def streamed_grid(features: Features, cfg: Config) -> Features:
    """Every candidate the `grid` selection's stream carries (LevelSelector stores it in a slot,
    new or replacing): the kept features and those a later candidate replaced, in canonical order.
    The HDMI overlay marks these (docs/spec.md section 13)."""
    keep: list[np.ndarray] = []
    for n, grid, idx in _levels_in_arrival_order(features, cfg):
        sel = LevelSelector(n, grid)
        ops = [sel.offer(int(features.x[i]), int(features.y[i]), bool(features.low[i]), int(features.response[i]))
               for i in idx]  # fmt: skip
        keep.append(idx[np.array([op is not None for op in ops], dtype=bool)])
    return features.take(np.concatenate(keep)).sorted()


class LevelSelector:
    """The streaming form of `select_level`, one candidate at a time, as the fabric does it: a
    cell's floor is held in place, the rest in a store of buckets (one per rest key) that
    evicts the most recently added candidate of its lowest key. Each candidate gives an operation:
    None (dropped), or (slot, new) -- the candidate is stored in the level's slot `slot` (0 .. n-1),
    a slot never used before in this frame when `new`, else one whose occupant it replaces. The
    kept set after the last candidate equals `select_level`'s (a test checks it)."""

    def __init__(self, n: int, grid: CellGrid) -> None:
        self.n = n
        self.grid = grid
        self.used = 0
        self.floors: dict[tuple[int, int], tuple[int, int]] = {}  # cell -> (rank, slot)
        self.buckets: dict[int, list[int]] = {}  # rest key -> slots, most recent last
        self.occupant: dict[int, int] = {}  # slot -> the candidate index stored there
        self.count = 0  # candidates seen

    def _pop_min(self) -> int | None:
        if not self.buckets:
            return None
        low = min(self.buckets)
        slot = self.buckets[low].pop()
        if not self.buckets[low]:
            del self.buckets[low]
        return slot

    def _min_key(self) -> int | None:
        return min(self.buckets) if self.buckets else None

    def _push(self, key: int, slot: int) -> None:
        self.buckets.setdefault(key, []).append(slot)

    def _store(self, index: int, slot: int, new: bool) -> tuple[int, bool]:
        self.occupant[slot] = index
        return slot, new

    def offer(self, x: int, y: int, low: bool, response: int) -> tuple[int, bool] | None:
        index = self.count
        self.count += 1
        if self.n <= 0:
            return None
        main = not low
        rank = (int(main) << 16) | int(response)
        cx, cy = self.grid.of(x, y)
        c = (int(cx), int(cy))
        floor = self.floors.get(c)
        full = self.used >= self.n
        if floor is None:  # (a) a cell's first candidate: its floor
            if not full:
                slot, self.used = self.used, self.used + 1
                self.floors[c] = (rank, slot)
                return self._store(index, slot, True)
            slot = self._pop_min()
            if slot is None:  # the level holds nothing but floors: no place for this cell
                self.floors[c] = (-1, -1)
                return None
            self.floors[c] = (rank, slot)
            return self._store(index, slot, False)
        f_rank, f_slot = floor
        if f_slot < 0:  # a cell that found no place stays without one
            return None
        if rank > f_rank:  # (b) a record: it becomes the floor, the displaced one joins the rest now
            f_key = int(rest_key(f_rank >> 16 == 0, f_rank & 0xFFFF))
            if not full:
                slot, self.used = self.used, self.used + 1
                self._push(f_key, f_slot)
                self.floors[c] = (rank, slot)
                return self._store(index, slot, True)
            m = self._min_key()
            if m is not None and f_key > m:  # the rest's lowest goes, the old floor stays
                slot = self._pop_min()
                assert slot is not None
                self._push(f_key, f_slot)
                self.floors[c] = (rank, slot)
                return self._store(index, slot, False)
            self.floors[c] = (rank, f_slot)  # the old floor is the lowest: it goes
            return self._store(index, f_slot, False)
        key = int(rest_key(low, response))
        if not full:  # (c) a candidate for the rest (a low one only takes a free place: key 0)
            slot, self.used = self.used, self.used + 1
            self._push(key, slot)
            return self._store(index, slot, True)
        m = self._min_key()
        if m is not None and key > m:
            slot = self._pop_min()
            assert slot is not None
            self._push(key, slot)
            return self._store(index, slot, False)
        return None

    def kept(self) -> list[int]:
        """The candidate indices held now (the selection, once the level's last candidate is in)."""
        return sorted(self.occupant.values())


def level_slots(cap: int, step: tuple[int, int], levels: int) -> list[int]:
    """The most slots each level can be given by a budget of at most `cap`: min(cap, ((cap F_k) >> 16)
    + levels), F_{L-1} = 2^16 minus the others (orb_util_pkg.level_slots; tb/model/test_select.py
    checks the bound against level_budgets for every budget up to `cap`)."""
    f = split_fractions(step, levels)
    f.append((1 << FIXED_BITS) - sum(f))
    return [min(cap, ((cap * fk) >> FIXED_BITS) + levels) for fk in f]
