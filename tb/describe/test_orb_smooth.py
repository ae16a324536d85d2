# SPDX-License-Identifier: MIT
"""orb_smooth against golden_model.smooth.smooth, column by column.

orb_smooth sees a sliding 7x7 window one column per beat (as orb_window slides it): each beat
drives the newest column (7 x 8 bits, top pixel in the low byte), tagged with the position (x, y)
of its bottom pixel, and the window is the last seven columns driven. The expected value of a
beat is the model's smoothing of that window at its centre (x - 3, y - 3), and 0 whenever x < 6 or
y < 6. Every output must leave exactly 5 clocks after its input and keep its tag. Stimulus: every
position of photograph crops in raster order (the line starts exercise the border rule with
columns of the previous line still in the sums), flat windows of every extreme value, single
impulses at each of the 49 positions (each kernel weight alone, rounding included), rounding ties
(sum = 2048 mod 4096) and random windows, each driven as seven columns; the beats between two
synthetic windows check the windows that mix them.
"""

from __future__ import annotations

import cocotb
import numpy as np

from golden_model.latency import SMOOTH_LAT
from golden_model.smooth import smooth
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, random_gaps, reset, to_int

KERNEL = np.outer((5, 8, 12, 14, 12, 8, 5), (5, 8, 12, 14, 12, 8, 5))


class Columns:
    """The driven beats (x, y, column) and, from the same columns, what each beat must give."""

    def __init__(self) -> None:
        self.items: list[tuple[int, int, int]] = []
        self.expected: list[int] = []
        self.labels: list[str] = []
        self.windows: list[np.ndarray] = []  # the window of each checked (inner) beat
        self._cols: list[np.ndarray] = []

    def add(self, x: int, y: int, col: np.ndarray, label: str) -> None:
        col = np.asarray(col, dtype=np.uint8).reshape(7)
        self._cols.append(col)
        self.items.append((x, y, int.from_bytes(col.tobytes(), "little")))
        self.labels.append(label)
        if x < 6 or y < 6:
            self.expected.append(0)
            return
        assert len(self._cols) >= 7, f"{label}: an inner position before seven columns were driven"
        win = np.stack(self._cols[-7:], axis=1)
        self.windows.append(win.astype(np.int64))
        self.expected.append(int(smooth(np.ascontiguousarray(win))[3, 3]))

    def window(self, win: np.ndarray, label: str, x: int = 50, y: int = 40) -> None:
        """A whole 7x7 window as seven columns; the last beat (tag (x, y)) sees exactly it."""
        for c in range(7):
            self.add(max(x - 6 + c, 0), y, np.asarray(win)[:, c], label)


async def check(dut, cols: Columns, seed: int) -> None:
    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_col": 0})
    stream = Stream(dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_col], [dut.out_x, dut.out_y, dut.out_data],
                    [dut.out_valid])  # fmt: skip
    await stream.run(cols.items, random_gaps(len(cols.items), seed=seed, prob=0.2, long_every=400), tail=6)
    out_edges = [e for e, _ in stream.samples]
    assert out_edges == [e + SMOOTH_LAT for e in stream.in_edges], (
        f"outputs are not the inputs delayed by {SMOOTH_LAT} clocks "
        f"({len(out_edges)} outputs, {len(cols.items)} inputs)"
    )
    for i, ((x, y, _), exp, label, (_, (xv, yv, dv))) in enumerate(
        zip(cols.items, cols.expected, cols.labels, stream.samples, strict=True)
    ):
        tag = (to_int(xv), to_int(yv))
        assert tag == (x, y), f"beat {i}, {label}: tag (x={x}, y={y}) came out as {tag}"
        got = to_int(dv)
        assert got == exp, f"beat {i}, {label}, centre (x={x - 3}, y={y - 3}): smoothed {got}, model {exp}"


@cocotb.test()
async def photo_columns(dut) -> None:
    cols = Columns()
    for name in ("camera", "astronaut", "coffee"):
        img = images.photo(name, 36, 24)
        ref = smooth(img)
        for y in range(img.shape[0]):
            for x in range(img.shape[1]):
                cols.add(x, y, img[y - 6 : y + 1, x] if y >= 6 else img[:7, x], f"photo {name}")
                if x >= 6 and y >= 6:
                    assert cols.expected[-1] == int(ref[y - 3, x - 3])  # the rolling window is the image's
    assert sum(e > 0 for e in cols.expected) > 1000
    await check(dut, cols, seed=1)


@cocotb.test()
async def synthetic(dut) -> None:
    rng = np.random.default_rng(9)
    cols = Columns()
    for x in range(6):  # six border-rule beats first, so every inner beat has seven columns behind it
        cols.add(x, 40, np.full(7, 99), "fill")
    for v in (0, 1, 127, 128, 254, 255):
        cols.window(np.full((7, 7), v), f"flat {v}")
    for r in range(7):
        for c in range(7):
            for v in (1, 255, 137):
                win = np.zeros((7, 7), dtype=np.int64)
                win[r, c] = v
                cols.window(win, f"impulse {v} at ({r}, {c})")
    # rounding ties: a random window whose corner is moved until the weighted sum is 2048 mod 4096
    inv25 = pow(25, -1, 4096)  # the corner weight is 25, odd: a corner change of d moves the sum by 25 d
    ties = 0
    while ties < 40:
        win = rng.integers(0, 256, (7, 7))
        rem = int((KERNEL * win).sum()) % 4096
        d = ((2048 - rem) * inv25) % 4096
        for delta in (d, d - 4096):
            if 0 <= int(win[0, 0]) + delta <= 255:  # an exact .5 tie when the corner can take it
                win[0, 0] += delta
                assert int((KERNEL * win).sum()) % 4096 == 2048
                ties += 1
                cols.window(win, "a rounding tie")
                break
    for _ in range(600):
        cols.window(rng.integers(0, 256, (7, 7)), "random window")
    for x, y in ((5, 40), (40, 5), (6, 6), (5, 5), (0, 0), (4095, 4095)):
        cols.window(np.full((7, 7), 200), "border rule", x, y)
    assert sum(int((KERNEL * w).sum()) % 4096 == 2048 for w in cols.windows) >= 40, "rounding ties not checked"
    await check(dut, cols, seed=2)


def test_smooth() -> None:
    run("orb_smooth", "test_orb_smooth", {}, env=SIM_ENV)
