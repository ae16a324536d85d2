# SPDX-License-Identifier: MIT
"""orb_fast_score against golden_model.fast.fast_score, window by window, at two thresholds.

The flat 49 x 8-bit window is driven directly (no window generator), tagged with the position
(x, y) of its newest (bottom-right) pixel, so the tested centre is (x - 3, y - 3). Expected score:
fast_score of the image the window was cut from at that centre at the low threshold in effect
(min(threshold_lo, threshold)), and 0 whenever x < 6 or y < 6 (the border rule); expected
out_main: a corner at the main threshold there (docs/spec.md section 5). Every output must appear
exactly 4 clocks after its input and keep its tag. Each window gets a low threshold at random:
equal to the main one, below it, above it (acts as equal) or 0.

Stimulus: windows at every position of photograph crops (border positions carry real corner
windows, which must still score 0), and synthetic windows: threshold edges (p = c + t is not
brighter, c + t + 1 is; the same for darker), arcs of 8 (no corner) and 9 (corner) at every
start including the ones wrapping from bit 15 to bit 0, full circles, t = 0 and t = 255, the
maximum score 4080, and random windows with random thresholds.
"""

from __future__ import annotations

import cocotb
import numpy as np

from golden_model.fast import CIRCLE, fast_score
from golden_model.latency import FAST_SCORE_LAT
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, random_gaps, reset, to_int, window_word

Item = tuple[int, int, int, int, int]  # (x, y, threshold, threshold_lo, window word)
_LOW = np.random.default_rng(99)


def low_for(t: int) -> int:
    """A low threshold for a window of main threshold t: equal, below, above (acts as t) or 0."""
    kind = int(_LOW.integers(0, 4))
    return (t, int(_LOW.integers(0, t + 1)), int(_LOW.integers(t, 256)), 0)[kind]


def model_score(win: np.ndarray, t: int, x: int, y: int, t_lo: int | None = None) -> tuple[int, int]:
    """The model's (score, main) of the window's centre (3, 3), and the border rule of the tag."""
    if x < 6 or y < 6:
        return 0, 0
    w = np.ascontiguousarray(win, dtype=np.uint8)
    lo = t if t_lo is None else min(t_lo, t)
    return int(fast_score(w, lo)[3, 3]), int(fast_score(w, t)[3, 3] > 0)


async def check_windows(dut, items: list[Item], expected: list[tuple[int, int]], labels: list[str], seed: int) -> None:
    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "threshold": 0, "threshold_lo": 0, "in_win": 0})
    stream = Stream(
        dut.clk,
        dut.in_valid,
        [dut.in_x, dut.in_y, dut.threshold, dut.threshold_lo, dut.in_win],
        [dut.out_x, dut.out_y, dut.out_score, dut.out_main],
        [dut.out_valid],
    )
    await stream.run(items, random_gaps(len(items), seed=seed, prob=0.2, long_every=500), tail=6)
    out_edges = [e for e, _ in stream.samples]
    expected_edges = [e + FAST_SCORE_LAT for e in stream.in_edges]
    if out_edges != expected_edges:
        i = next((i for i, (a, b) in enumerate(zip(out_edges, expected_edges, strict=False)) if a != b), -1)
        raise AssertionError(
            f"outputs are not the inputs delayed by {FAST_SCORE_LAT} clocks: {len(out_edges)} outputs for {len(items)} "
            f"inputs, first difference at output {i} ({labels[i] if 0 <= i < len(labels) else 'extra output'})"
        )
    for (x, y, t, tl, _), exp, label, (_, (x_v, y_v, s_v, m_v)) in zip(
        items, expected, labels, stream.samples, strict=True
    ):
        got_tag = (to_int(x_v), to_int(y_v))
        assert got_tag == (x, y), f"{label}: tag (x={x}, y={y}) came out as {got_tag}"
        got = (to_int(s_v), to_int(m_v))
        assert got == exp, (
            f"{label}, tag (x={x}, y={y}), centre (x={x - 3}, y={y - 3}), t={t}, t_lo={tl}: (score, main) {got}, "
            f"model {exp}"
        )
    corners = sum(e[0] > 0 for e in expected)
    low_only = sum(e[0] > 0 and not e[1] for e in expected)
    assert not items or low_only > 0, "no window is a corner at the low threshold only: the test cannot fail"
    dut._log.info("%d windows checked, %d corners", len(items), corners)


@cocotb.test()
async def photo_windows(dut) -> None:
    """Every window position of photograph crops; border positions get corner windows (score 0)."""
    w, h = 40, 30
    items: list[Item] = []
    expected: list[tuple[int, int]] = []
    labels: list[str] = []
    cases = (("camera", 8, 8), ("astronaut", 20, 7), ("coffee", 0, 9), ("rocket", 45, 12), ("chelsea", 8, 0))
    for name, t, tl in cases:
        img = images.photo(name, w, h)
        score = fast_score(img, t)
        low = fast_score(img, min(t, tl))
        corner_windows = [
            img[cy - 3 : cy + 4, cx - 3 : cx + 4] for cy, cx in zip(*np.nonzero(score), strict=True) if score[cy, cx]
        ]
        assert corner_windows, f"{name} at t={t} has no corner: the crop is useless"
        k = 0
        for y in range(h):
            for x in range(w):
                if x >= 6 and y >= 6:
                    win = img[y - 6 : y + 1, x - 6 : x + 1]
                    exp = (int(low[y - 3, x - 3]), int(score[y - 3, x - 3] > 0))
                else:
                    win = corner_windows[k % len(corner_windows)]  # a corner, masked by the border rule
                    k += 1
                    exp = (0, 0)
                items.append((x, y, t, tl, window_word(win)))
                expected.append(exp)
                labels.append(f"photo {name} {w}x{h}")
    await check_windows(dut, items, expected, labels, seed=1)


def synthetic_windows() -> tuple[list[Item], list[tuple[int, int]], list[str]]:
    rng = np.random.default_rng(5)
    items: list[Item] = []
    expected: list[tuple[int, int]] = []
    labels: list[str] = []

    def add(win: np.ndarray, t: int, label: str, x: int = 100, y: int = 50) -> None:
        tl = low_for(t)
        items.append((x, y, t, tl, window_word(win)))
        expected.append(model_score(win, t, x, y, tl))
        labels.append(label)

    def arc_window(c: int, p: int, start: int, length: int, rest: int | None = None) -> np.ndarray:
        win = rng.integers(0, 256, (7, 7))  # pixels off the circle are noise: they must not matter
        win[3, 3] = c
        for i, (dx, dy) in enumerate(CIRCLE):
            win[3 + dy, 3 + dx] = p if (i - start) % 16 < length else (c if rest is None else rest)
        return win

    # threshold edges, arcs of 8 and 9 at every start (starts 8..15 wrap past bit 15), both polarities
    for c, t in ((100, 20), (0, 0), (255, 0), (128, 1), (10, 200), (245, 200), (1, 254), (254, 254), (60, 60)):
        for start in range(16):
            for length in (8, 9):
                for delta in (0, 1):
                    if c + t + delta <= 255:
                        add(
                            arc_window(c, c + t + delta, start, length), t, f"bright arc {length}@{start} p=c+t+{delta}"
                        )
                    if c - t - delta >= 0:
                        add(arc_window(c, c - t - delta, start, length), t, f"dark arc {length}@{start} p=c-t-{delta}")
    # a 9-arc whose other pixels have the opposite polarity (both masks hold runs; only one has 9)
    for start in range(16):
        add(arc_window(128, 200, start, 9, rest=50), 30, f"bright 9-arc@{start} rest dark")
        add(arc_window(128, 50, start, 9, rest=200), 30, f"dark 9-arc@{start} rest bright")
        add(arc_window(128, 200, start, 8, rest=50), 30, f"bright 8-arc@{start} rest dark")
    # full circles, extreme values, t = 0 and t = 255, maximum score 4080
    for c, p in ((0, 255), (255, 0), (0, 0), (255, 255), (128, 129), (128, 127)):
        for t in (0, 1, 126, 127, 254, 255):
            add(arc_window(c, p, 0, 16), t, f"full circle c={c} p={p}")
    # border rule at the edges of the tag range
    corner = arc_window(0, 255, 3, 12)
    for x, y in ((5, 50), (50, 5), (6, 6), (5, 5), (6, 4095), (4095, 6), (4095, 4095), (0, 0), (6, 5), (5, 6)):
        add(corner, 10, "border rule", x, y)
    # random windows: plain noise, and noise around a strong random ring
    for _ in range(600):
        t = int(rng.choice([0, 1, 5, 20, 50, 128, 255]))
        add(rng.integers(0, 256, (7, 7)), t, "random window")
    for _ in range(800):
        # a ring of three classes (brighter, darker, neither) around a random arc of 6..14
        c = int(rng.integers(0, 256))
        t = int(rng.integers(0, 40))
        start, length = int(rng.integers(0, 16)), int(rng.integers(6, 15))
        bright_arc = bool(rng.integers(0, 2))
        win = rng.integers(0, 256, (7, 7))
        win[3, 3] = c
        for i, (dx, dy) in enumerate(CIRCLE):
            cls = (0 if bright_arc else 1) if (i - start) % 16 < length else int(rng.integers(0, 3))
            lo, hi = ((c + t + 1, 255), (0, c - t - 1), (max(0, c - t), min(255, c + t)))[cls]
            if lo > hi:  # the class is impossible for this c and t: fall back to "neither"
                lo, hi = max(0, c - t), min(255, c + t)
            win[3 + dy, 3 + dx] = int(rng.integers(lo, hi + 1))
        add(win, t, f"random ring, {'bright' if bright_arc else 'dark'} arc {length}@{start}")
    return items, expected, labels


@cocotb.test()
async def synthetic(dut) -> None:
    items, expected, labels = synthetic_windows()
    # sanity of the stimulus itself: it must exercise both outcomes of every edge case
    assert sum(e[0] > 0 for e in expected) > 500 and sum(e[0] == 0 for e in expected) > 500
    assert sum(e[1] for e in expected) > 300, "too few corners at the main threshold"
    assert 4080 in [e[0] for e in expected], "the maximum score is not exercised"
    await check_windows(dut, items, expected, labels, seed=2)


# ------------------------------------------------------------------------------------------------
# pytest runner


def test_fast_score() -> None:
    run("orb_fast_score", "test_orb_fast_score", {}, env=SIM_ENV)
