# SPDX-License-Identifier: MIT
"""orb_smooth against golden_model.smooth.smooth, window by window.

The flat 49 x 8-bit window is driven directly, tagged with the position (x, y) of its newest
pixel, so the smoothed centre is (x - 3, y - 3); the expected value is the model's smoothed image
of the frame the window was cut from at that centre, and 0 whenever x < 6 or y < 6. Every output
must leave exactly 3 clocks after its input and keep its tag. Stimulus: every window position of
photograph crops, flat windows of every extreme value, single impulses at each of the 49
positions (each kernel weight alone, rounding included), rounding ties (sum = 2048 mod 4096),
and random windows.
"""

from __future__ import annotations

import cocotb
import numpy as np

from golden_model.smooth import smooth
from orbtb import images
from orbtb.runner import run
from orbtb.unit import SIM_ENV, Stream, random_gaps, reset, to_int, window_word

LATENCY = 3
Item = tuple[int, int, int]  # (x, y, window word)


def model_value(win: np.ndarray, x: int, y: int) -> int:
    if x < 6 or y < 6:
        return 0
    return int(smooth(np.ascontiguousarray(win, dtype=np.uint8))[3, 3])


async def check(dut, items: list[Item], expected: list[int], labels: list[str], seed: int) -> None:
    await reset(dut, {"in_valid": 0, "in_x": 0, "in_y": 0, "in_win": 0})
    stream = Stream(dut.clk, dut.in_valid, [dut.in_x, dut.in_y, dut.in_win], [dut.out_x, dut.out_y, dut.out_data],
                    [dut.out_valid])  # fmt: skip
    await stream.run(items, random_gaps(len(items), seed=seed, prob=0.2, long_every=400), tail=6)
    out_edges = [e for e, _ in stream.samples]
    assert out_edges == [e + LATENCY for e in stream.in_edges], (
        f"outputs are not the inputs delayed by {LATENCY} clocks ({len(out_edges)} outputs, {len(items)} inputs)"
    )
    for (x, y, _), exp, label, (_, (xv, yv, dv)) in zip(items, expected, labels, stream.samples, strict=True):
        assert (to_int(xv), to_int(yv)) == (x, y), f"{label}: tag (x={x}, y={y}) came out as {(to_int(xv), to_int(yv))}"
        got = to_int(dv)
        assert got == exp, f"{label}, centre (x={x - 3}, y={y - 3}): smoothed {got}, model {exp}"


@cocotb.test()
async def photo_windows(dut) -> None:
    items: list[Item] = []
    expected: list[int] = []
    labels: list[str] = []
    for name in ("camera", "astronaut", "coffee"):
        img = images.photo(name, 36, 24)
        ref = smooth(img)
        for y in range(img.shape[0]):
            for x in range(img.shape[1]):
                win = img[y - 6 : y + 1, x - 6 : x + 1] if x >= 6 and y >= 6 else img[:7, :7]
                items.append((x, y, window_word(win)))
                expected.append(int(ref[y - 3, x - 3]) if x >= 6 and y >= 6 else 0)
                labels.append(f"photo {name}")
    assert sum(e > 0 for e in expected) > 1000
    await check(dut, items, expected, labels, seed=1)


@cocotb.test()
async def synthetic(dut) -> None:
    rng = np.random.default_rng(9)
    items: list[Item] = []
    expected: list[int] = []
    labels: list[str] = []

    def add(win: np.ndarray, label: str, x: int = 50, y: int = 40) -> None:
        items.append((x, y, window_word(win)))
        expected.append(model_value(win, x, y))
        labels.append(label)

    for v in (0, 1, 127, 128, 254, 255):
        add(np.full((7, 7), v), f"flat {v}")
    for r in range(7):
        for c in range(7):
            for v in (1, 255, 137):
                win = np.zeros((7, 7), dtype=np.int64)
                win[r, c] = v
                add(win, f"impulse {v} at ({r}, {c})")
    # rounding ties: a flat window of 0 plus weight-1 corners giving sums with remainder 2048
    kernel = np.outer((5, 8, 12, 14, 12, 8, 5), (5, 8, 12, 14, 12, 8, 5))
    inv25 = pow(25, -1, 4096)  # the corner weight is 25, odd: a corner change of d moves the sum by 25 d
    ties = 0
    while ties < 40:
        win = rng.integers(0, 256, (7, 7))
        rem = int((kernel * win).sum()) % 4096
        d = ((2048 - rem) * inv25) % 4096
        for delta in (d, d - 4096):
            if 0 <= int(win[0, 0]) + delta <= 255:  # an exact .5 tie when the corner can take it
                win[0, 0] += delta
                assert int((kernel * win).sum()) % 4096 == 2048
                ties += 1
                add(win, "a rounding tie")
                break
    for _ in range(600):
        add(rng.integers(0, 256, (7, 7)), "random window")
    for x, y in ((5, 40), (40, 5), (6, 6), (5, 5), (0, 0), (4095, 4095)):
        add(np.full((7, 7), 200), "border rule", x, y)
    assert any(int((kernel * win_bytes(item[2])).sum()) % 4096 == 2048 for item in items), "no rounding tie"
    await check(dut, items, expected, labels, seed=2)


def win_bytes(word: int) -> np.ndarray:
    return np.frombuffer(word.to_bytes(49, "little"), dtype=np.uint8).reshape(7, 7).astype(np.int64)


def test_smooth() -> None:
    run("orb_smooth", "test_orb_smooth", {}, env=SIM_ENV)
