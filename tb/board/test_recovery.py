# SPDX-License-Identifier: MIT
"""orb_flow.board.recovery's input model without a simulation (the measurement itself runs the
netlists for an hour: docs/board.md, "Recovery after a cut"): each board configuration's CEA-861
timing matches its pixel clock and a wrong one is refused; the beat programs carry a frame period of
pixel clocks per frame, the event frame stopping in mid-line with the cable out for one frame period
("cut") or none ("restart"); the frames differ from each other."""

from __future__ import annotations

import numpy as np
import pytest

from orb_flow.board import recovery
from orb_flow.gen.board import DATA, load
from orb_sim.fast.sim import FLAG_LAST, FLAG_USER

BOARD = load(DATA)


@pytest.mark.parametrize("name", list(BOARD["configs"]))
def test_timing_matches_the_pixel_clock(name: str) -> None:
    cfg = BOARD["configs"][name]
    h_total, v_total = recovery.timing(cfg)
    assert h_total > cfg["width"] and v_total > cfg["height"]
    with pytest.raises(SystemExit, match="Hz"):
        recovery.timing({**cfg, "pixel_mhz": cfg["pixel_mhz"] * 1.25})


@pytest.mark.parametrize("kind", recovery.EVENTS)
def test_programs(kind: str) -> None:
    w, h, h_total, v_total = 40, 30, 50, 36
    rgb = [np.full((h, w, 3), k, dtype=np.uint8) for k in range(4)]
    out = 7 * h_total * v_total
    progs = recovery.programs(rgb, 1, kind, 0.5, h_total, v_total, out)
    for k, (data, flags, gaps) in enumerate(progs):
        assert flags[0] == FLAG_USER and np.all(data == k * 0x010101)
        if k != 1:
            assert len(data) == w * h and gaps.sum() + len(gaps) == h_total * v_total
            assert np.array_equal(np.flatnonzero(flags & FLAG_LAST), np.arange(w - 1, w * h, w))
    data, flags, gaps = progs[1]
    assert len(data) == 15 * w + w // 3 and not flags[-1] & FLAG_LAST, "the event frame stops in mid-line"
    assert gaps[-1] == (out if kind == "cut" else 0)


def test_frames_differ() -> None:
    frames = recovery.frames(64, 48, 3)
    assert all(f.shape == (48, 64, 3) and f.dtype == np.uint8 for f in frames)
    assert not np.array_equal(frames[0], frames[1]) and not np.array_equal(frames[1], frames[2])
