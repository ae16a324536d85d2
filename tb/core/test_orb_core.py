# SPDX-License-Identifier: MIT
"""orb_core (the accelerator's streaming core) against the golden model, bit for bit.

The cocotb test streams one or more frames back to back (each with its own image, threshold, mode
and selection) through s_axis_video, collects m_axis_feat, resolves each frame's selection
(golden_model.featcodec.resolve_selection: what the feature memory keeps) and compares every
frame with the model's features: scale, x, y, score, response and low flag in fast mode, plus
sector and descriptor in orb mode. The pytest runners below pick widths, heights, scales,
sectors, modes, selections (`all`, or `grid:BUDGET:COLSxROWS:LOW`), images, thresholds and input gaps.
A selection that changes waits SELECT_SETTLE idle clocks before its frame (the budget's split is
formed from the inputs, orb_core's header). Every end-of-frame beat must carry the parameters its
frame was started with (docs/feature-word.md); with ORB_EARLY_WRITE the next frame's parameters (the
last frame: a set that differs in every field) are written half-way through each frame, so the
inputs hold other values when the frame's end-of-frame beat leaves.
"""

from __future__ import annotations

import os

import cocotb
import pytest
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge

from golden_model.config import RECOMMENDED_SCALES, RECOMMENDED_SECTORS, RECOMMENDED_STEP, parse_step
from golden_model.frameparams import FrameParams
from orb_sim.core_inputs import SELECT_SETTLE, drive_params, selection_params
from orb_sim.feature_stream import FeatureMonitor
from orb_sim.video import Gaps, VideoSource
from orbtb import images
from orbtb.runner import run
from orbtb.scoreboard import check_frame, expected_features

EOF_TIMEOUT_CYCLES = 5000


def _env_list(name: str, default: str) -> list[str]:
    return [v for v in os.environ.get(name, default).split(",") if v]


def other_params(p: FrameParams) -> FrameParams:
    """Legal parameters that differ from `p` in every field."""
    return FrameParams(threshold=p.threshold ^ 0x55, threshold_lo=p.threshold_lo ^ 0x3C,
                       mode="fast" if p.mode == "orb" else "orb", selection="all" if p.selection == "grid" else "grid",
                       budget=p.budget ^ 0x2A5, cols=p.cols % 15 + 1, rows=p.rows % 15 + 1)  # fmt: skip


async def write_mid_frame(dut, clk, clocks: int, params: FrameParams) -> None:
    """Drive `params` on orb_core's inputs `clocks` clocks from now (inside the frame being sent)."""
    await ClockCycles(clk, clocks)
    drive_params(dut, params)


@cocotb.test()
async def detect_frames(dut) -> None:
    w, h = int(os.environ["ORB_WIDTH"]), int(os.environ["ORB_HEIGHT"])
    scales = int(os.environ["ORB_SCALES"])
    thresholds = [int(t) for t in _env_list("ORB_THRESHOLDS", "20")]
    kinds = _env_list("ORB_IMAGES", "photo:camera")
    names = [kinds[i % len(kinds)] for i in range(len(thresholds))]
    frames = [images.make(k, w, h) for k in names]
    gaps = Gaps.parse(os.environ.get("ORB_GAPS", "none"))
    modes = _env_list("ORB_MODES", "fast")
    modes = [modes[i % len(modes)] for i in range(len(frames))]
    sectors = int(os.environ.get("ORB_SECTORS", "32"))
    step = parse_step(os.environ.get("ORB_STEP", "2:1"))
    selections = _env_list("ORB_SELECT", "all")
    selections = [selections[i % len(selections)] for i in range(len(frames))]
    params = [selection_params(sel, t, m) for sel, t, m in zip(selections, thresholds, modes, strict=True)]
    early = os.environ.get("ORB_EARLY_WRITE", "0") == "1"
    # what is written half-way through each frame (early): the next frame's parameters
    later = [*params[1:], other_params(params[-1])]
    if early:
        for i, (p, q) in enumerate(zip(params, later, strict=True)):
            assert p != q, f"frame {i}: the mid-frame write repeats its parameters, the test would prove nothing"

    clk = dut.clk
    dut.rst.value = 1
    drive_params(dut, params[0])
    dut.m_axis_feat_tready.value = 1
    source = VideoSource(dut, clk)
    source.idle()
    cocotb.start_soon(Clock(clk, 10, unit="ns").start(start_high=False))
    await ClockCycles(clk, 4)
    dut.rst.value = 0
    await RisingEdge(clk)
    monitor = FeatureMonitor(dut, clk)
    cocotb.start_soon(monitor.run())

    await ClockCycles(clk, SELECT_SETTLE)
    previous = selections[0]
    for i, (frame, sel) in enumerate(zip(frames, selections, strict=True)):
        drive_params(dut, params[i])
        if sel != previous:
            await ClockCycles(clk, SELECT_SETTLE)
            previous = sel
        if early:
            cocotb.start_soon(write_mid_frame(dut, clk, w * h // 2, later[i]))
        await source.send_frame(frame, gaps)
    latency = 0
    while len(monitor.frames) < len(frames):
        await RisingEdge(clk)
        latency += 1
        if latency > EOF_TIMEOUT_CYCLES:
            raise AssertionError(f"only {len(monitor.frames)} of {len(frames)} end-of-frame beats arrived")
    for i, (frame, t, mode, sel, got) in enumerate(zip(frames, thresholds, modes, selections, monitor.frames,
                                                       strict=True)):  # fmt: skip
        assert got.number == i, f"frame {i}: end-of-frame beat numbered {got.number}"
        assert got.drops == 0, f"frame {i}: {got.drops} features dropped"
        assert got.params == params[i], f"frame {i}: end-of-frame beat says {got.params}, it was made with {params[i]}"
        orb = mode == "orb"
        exp = expected_features(frame, scales, t, mode, sectors, step, sel)
        check_frame(got.features(sectors, descriptors=orb), exp, f"frame {i} ({mode}, threshold {t}, {sel})")
        if sel.startswith("grid"):
            budget = int(sel.split(":")[1])
            assert len(exp) <= budget, f"frame {i}: the model kept {len(exp)} of a budget of {budget}"
        if orb and not sel.startswith("grid:0:"):  # budget 0 keeps nothing: the check above saw none arrive
            assert len(exp) > 0 or names[i] == "flat", f"frame {i} ({names[i]}): no feature to compare"
    assert int(dut.bad_pixels.value) == 0, "pixels outside the frame were counted"
    assert int(dut.dropped.value) == 0
    assert int(dut.desc_lost.value) == 0, "the descriptor path lost features on legal frames"


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_detect(width: int, height: int, scales: int, images_: str, thresholds: str, gaps: str = "none",
               modes: str = "fast", sectors: int = 32, step: tuple[int, int] = (2, 1),
               selections: str = "all", early_write: bool = False) -> None:  # fmt: skip
    generics = {"WIDTH_g": width, "HEIGHT_g": height, "SCALES_g": scales, "SECTORS_g": sectors}
    if step != (2, 1):
        generics |= {"STEP_NUM_g": step[0], "STEP_DEN_g": step[1]}
    run(
        "orb_core",
        "test_orb_core",
        generics,
        env={
            "ORB_IMAGES": images_,
            "ORB_THRESHOLDS": thresholds,
            "ORB_GAPS": gaps,
            "ORB_MODES": modes,
            "ORB_STEP": f"{step[0]}:{step[1]}",
            "ORB_SELECT": selections,
            "ORB_EARLY_WRITE": str(int(early_write)),
        },
    )


# The grid selection (issue 24): photographs with low corners, budgets below and above the
# candidates, grids from 1 x 1 to 15 x 15, back to back with the selection changing, both modes, every
# level of the finer pyramid; the densest legal patterns (at most the budget, nothing dropped).
@pytest.mark.parametrize(
    ("width", "height", "scales", "step", "images_", "thresholds", "gaps", "modes", "selections"),
    [
        (160, 96, 3, (5, 4), "photo:astronaut,photo:coffee,photo:camera", "20,20,25", "random:3", "orb,orb,fast",
         "grid:60:8x6:7,grid:25:15x15:5,grid:1000:1x1:10"),
        (128, 96, 2, (2, 1), "photo:chelsea,photo:chelsea", "20,20", "none", "orb,orb", "all,grid:40:5x4:7"),
        (128, 96, 5, (5, 4), "dots4,checker,photo:coffee", "20,0,30", "none", "orb,fast,orb",
         "grid:90:6x5:7,grid:200:13x9:0,grid:0:8x6:7"),
    ],
)  # fmt: skip
def test_grid_selection(width: int, height: int, scales: int, step: tuple[int, int], images_: str, thresholds: str,
                        gaps: str, modes: str, selections: str) -> None:  # fmt: skip
    run_detect(width, height, scales, images_, thresholds, gaps, modes, 32, step, selections)


# Every frame says how it was made (issue 26, part 5): each frame's parameters are overwritten half-way
# through it (back to back, so its end-of-frame beat also leaves after the next frame's start); every
# end-of-frame beat must carry the parameters the frame was started with, and its features match them.
def test_frame_params_written_mid_frame() -> None:
    run_detect(96, 64, 2, "photo:astronaut,photo:coffee,photo:camera", "15,30,20", "none", "orb,fast,orb", 32, (2, 1),
               "grid:40:5x4:7,all,grid:25:3x2:9", early_write=True)  # fmt: skip


@pytest.mark.parametrize(
    ("width", "height", "scales", "images_", "thresholds", "gaps"),
    [
        (64, 48, 1, "photo:camera", "20", "none"),  # smallest legal frame
        (64, 48, 4, "photo:astronaut", "10", "random:2"),
        (160, 64, 2, "photo:coffee,photo:chelsea,photo:astronaut", "0,20,255", "none"),  # back to back
        (160, 64, 2, "photo:camera", "15,40", "blanking"),
        (128, 64, 3, "photo:coffee", "25", "random:5"),
        (96, 64, 1, "flat", "0", "none"),
        (96, 64, 2, "dots4,checker,checker4", "20,20,0", "none"),  # maximum corner density
        (96, 64, 1, "border,noise", "20,30", "none"),  # corners at every border distance
    ],
)
def test_detect_small(width: int, height: int, scales: int, images_: str, thresholds: str, gaps: str) -> None:
    run_detect(width, height, scales, images_, thresholds, gaps)


@pytest.mark.parametrize(
    ("width", "height", "scales", "sectors", "images_", "thresholds", "gaps", "modes"),
    [
        (96, 64, 1, 32, "photo:astronaut,photo:coffee", "10,15", "none", "orb"),
        # 16 sectors with input gaps (make test-all; make test: 16 sectors in the rotated row below, gaps elsewhere)
        pytest.param(160, 96, 2, 16, "photo:camera,photo:chelsea", "12,20", "random:3", "orb", marks=pytest.mark.slow),
        (160, 96, 2, 64, "photo:coffee", "10", "blanking", "orb"),
        # orb -> fast -> orb back to back (make test-all; make test: test_grid_selection's 5-level row)
        pytest.param(128, 80, 3, 32, "photo:astronaut,photo:astronaut,photo:camera", "15,15,20", "none", "orb,fast,orb",
                     marks=pytest.mark.slow),
        (96, 64, 1, 32, "dots4,noise,flat", "20,20,20", "none", "orb"),  # densest FAST dots, noise; flat
        (64, 48, 1, 32, "photo:camera", "5", "none", "orb"),  # smallest legal frame
        # rotated photographs, 0 to 360 degrees, at 16, 32 and 64 sectors
        (96, 64, 1, 16, "rotated:astronaut:0,rotated:astronaut:75,rotated:astronaut:150", "10,10,10", "none", "orb"),
        (96, 64, 1, 32, "rotated:astronaut:45,rotated:chelsea:135,rotated:astronaut:250", "10,10,10", "random:4",
         "orb"),
        (96, 64, 1, 64, "rotated:chelsea:200,rotated:chelsea:290,rotated:chelsea:345", "10,10,10", "none", "orb"),
    ],
)  # fmt: skip
def test_orb_small(width: int, height: int, scales: int, sectors: int, images_: str, thresholds: str, gaps: str,
                   modes: str) -> None:  # fmt: skip
    run_detect(width, height, scales, images_, thresholds, gaps, modes, sectors)


# The finer pyramids (issue 14): every level of 5:4, 3:2 and 9:8 bit for bit, on photographs, the
# densest legal input (zero drops) and input gaps; 5:4 x 8 is the deepest legal pyramid shape.
@pytest.mark.parametrize(
    ("width", "height", "scales", "step", "images_", "thresholds", "gaps", "modes"),
    [
        # 6 levels (make test-all; make test: 8 levels below, and test_orb_accel_top's 6-level top)
        pytest.param(160, 120, 6, (5, 4), "photo:astronaut,photo:coffee", "10,15", "none", "orb,orb",
                     marks=pytest.mark.slow),
        (128, 96, 8, (5, 4), "photo:chelsea", "8", "random:3", "orb"),
        # densest corners in fast mode (make test-all; make test: the same 5 levels of 5:4 on dots4 and
        # checker in test_recommended_configuration_densest_input and test_grid_selection)
        pytest.param(128, 96, 5, (5, 4), "dots4,checker,checker4", "20,20,0", "none", "fast,fast,fast",
                     marks=pytest.mark.slow),
        (96, 96, 4, (5, 4), "dots4,noise", "20,20", "blanking", "orb"),
        (160, 96, 3, (3, 2), "photo:camera,rotated:astronaut:60", "10,10", "random:2", "orb"),
        (96, 72, 4, (9, 8), "photo:coffee", "10", "none", "orb"),
    ],
)  # fmt: skip
def test_finer_pyramid(width: int, height: int, scales: int, step: tuple[int, int], images_: str, thresholds: str,
                       gaps: str, modes: str) -> None:  # fmt: skip
    run_detect(width, height, scales, images_, thresholds, gaps, modes, 32, step)


def test_recommended_configuration_densest_input() -> None:
    """The recommended pyramid (golden_model.config.RECOMMENDED_*: 5:4 x 5, 64 sectors) in orb mode on
    the densest legal corner pattern and a photograph, with input gaps: bit for bit, zero drops."""
    run_detect(128, 96, RECOMMENDED_SCALES, "dots4,photo:coffee,checker", "20,20,20", "random:2", "orb",
               RECOMMENDED_SECTORS, RECOMMENDED_STEP)  # fmt: skip


@pytest.mark.parametrize(("width", "height", "scales"), [(640, 48, 2), (1920, 48, 1)])
def test_detect_wide_strips(width: int, height: int, scales: int) -> None:
    run_detect(width, height, scales, "photo:astronaut", "20", "none")


@pytest.mark.slow
@pytest.mark.parametrize(("width", "height", "scales"), [(640, 64, 2), (1920, 48, 1)])
def test_orb_wide_strips(width: int, height: int, scales: int) -> None:
    run_detect(width, height, scales, "photo:astronaut", "8", "none", "orb")


@pytest.mark.slow
def test_detect_full_vga_two_scales() -> None:
    run_detect(640, 480, 2, "photo:coffee", "20", "none")


@pytest.mark.slow
def test_orb_full_vga_two_scales() -> None:
    run_detect(640, 480, 2, "photo:coffee", "20", "none", "orb")
