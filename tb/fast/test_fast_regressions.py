# SPDX-License-Identifier: MIT
"""Long regressions on the fast path (docs/fast-sim.md), out of reach in GHDL; marked slow (`make
test-all`). Each prints its figures.

- video: the bundled photograph as a 100-frame sequence with motion (shifted, rotated and
  brightness-changed versions), back to back with blanking, the driver reading and releasing the
  banks as on the board: every frame published, consecutive, bit-exact;
- 1920x1080 frames with 1, 2 and 4 scales: bit-exact, nothing dropped or truncated;
- fault campaigns (orbtb.campaign): 3 x 250 events with recorded seeds (one from a random initial
  state): no lock-up, no mismatch. Replay one: `pytest tb/fast/test_fast_regressions.py -k "11-0"`;
- the long campaign: 10,000 events (seed 2026) on the named configuration test-tiny, more than
  10,000 frames: no lock-up, no mismatch; about half an hour here. Its figures go to
  build/campaign/long-2026.json (progress in long-2026.progress), recorded in
  docs/results/campaign.json (`python -m orb_flow.record campaign`, docs/fast-sim.md);
- DDR fault campaigns (orbtb.campaign on the "DDR" build of test-tiny, a 32-slot burst FIFO, a ring
  of 3 buffers): 2 x 250 events with the interconnect's stalls, slowness and error responses besides
  every other event: no lock-up, no mismatch, every frame the DDR path dropped reconciled with what
  was injected. Figures in build/campaign/ddr-fault-SEED.json.
"""

from __future__ import annotations

import json
import time

import cv2
import numpy as np
import pytest

from golden_model import Config, extract
from golden_model.config import named
from golden_model.features import first_difference
from golden_model.images import DEFAULT_IMAGE
from golden_model.luma import rgb_to_luma
from orb_accel.driver import Frame
from orb_sim.fast.jobs import ACCEL_MEM_DEPTH, generics_for, run_video_fast
from orb_sim.hdl import BUILD
from orb_tools.images import load_rgb_or_grey
from orbtb.campaign import CHANGES, DDR_KINDS, FAULTS, CampaignResult, Event, run_campaign
from orbtb.images import colour_photo

pytestmark = pytest.mark.slow


def moving_sequence(rgb: np.ndarray, n: int) -> np.ndarray:
    """n frames of `rgb` moving: a shift of up to 24 pixels, a turn of up to 6 degrees and a
    brightness change of up to 25 %, each varying smoothly from frame to frame."""
    h, w = rgb.shape[:2]
    out = []
    for i in range(n):
        a = 2 * np.pi * i / n
        m = cv2.getRotationMatrix2D((w / 2, h / 2), 6.0 * np.sin(a), 1.0)
        m[0, 2] += 24 * np.sin(2 * a)
        m[1, 2] += 16 * np.cos(a)
        moved = cv2.warpAffine(rgb, m, (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
        gain = 1.0 + 0.25 * np.sin(3 * a)
        out.append(np.clip(moved.astype(np.float32) * gain, 0, 255).astype(np.uint8))
    return np.stack(out)


def test_video_100_frames() -> None:
    rgb = load_rgb_or_grey(DEFAULT_IMAGE)
    frames = moving_sequence(rgb, 100)
    h, w = rgb.shape[:2]
    cfg = Config(w, h, scales=2, sectors=32, threshold=20, mode="orb")
    mismatches: list[str] = []
    counts: list[int] = []

    def check(i: int, frame: Frame) -> None:
        want = extract(rgb_to_luma(frames[i]), cfg)
        counts.append(len(frame))
        diff = first_difference(frame.features, want)
        if diff is not None or frame.dropped or frame.truncated:
            mismatches.append(f"frame {i}: {diff}, dropped {frame.dropped}, truncated {frame.truncated}")

    got, report = run_video_fast(frames, cfg, on_frame=check)
    print(f"video: {len(got)} frames of {w}x{h}, {sum(counts)} features ({min(counts)}..{max(counts)} per frame), "
          f"mismatches {len(mismatches)}; {report}")  # fmt: skip
    assert not mismatches, mismatches[:5]
    assert len(got) == 100 and report["frames_sent"] == 100 and report["overrun"] == 0
    numbers = [f.number for f in got]
    assert numbers == list(range(100)), numbers


@pytest.mark.parametrize("scales", [1, 2, 4])
def test_1080p(scales: int) -> None:
    rgb = cv2.resize(load_rgb_or_grey(DEFAULT_IMAGE), (1920, 1080), interpolation=cv2.INTER_CUBIC)
    cfg = Config(1920, 1080, scales=scales, sectors=32, threshold=25, mode="orb")
    want = extract(rgb_to_luma(rgb), cfg)
    assert len(want) < ACCEL_MEM_DEPTH, "the frame must fit one bank for an exact comparison"
    got, report = run_video_fast(rgb[None], cfg)
    print(f"1920x1080, {scales} scale(s): {len(got[0])} features, model {len(want)}; {report}")
    assert len(got) == 1 and got[0].dropped == 0 and got[0].truncated == 0
    diff = first_difference(got[0].features, want)
    assert diff is None, f"netlist (first) and model (second) differ: {diff}"


CAMPAIGN_PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "camera")
CAMPAIGN_OUT = BUILD / "campaign"


def write_report(name: str, result: CampaignResult) -> None:
    CAMPAIGN_OUT.mkdir(parents=True, exist_ok=True)
    (CAMPAIGN_OUT / f"{name}.json").write_text(json.dumps(result.report(), indent=1) + "\n")


@pytest.mark.parametrize(("seed", "init_seed"), [(11, 0), (23, 7), (41, 0)], ids=["11-0", "23-7", "41-0"])
def test_fault_campaign(seed: int, init_seed: int) -> None:
    photos = [colour_photo(name, 128, 96) for name in CAMPAIGN_PHOTOS]
    generics = {"WIDTH_g": 128, "HEIGHT_g": 96, "SCALES_g": 2, "SECTORS_g": 32, "MEM_DEPTH_g": 512, "INPUT_g": "RGB"}
    result = run_campaign(photos, 250, seed=seed, generics=generics, init_seed=init_seed)
    write_report(f"fault-{seed}-{init_seed}", result)
    print(f"fault campaign: {result.summary()}")
    assert not result.lockups, result.lockups
    assert not result.mismatches, result.mismatches[:5]
    # 9 of the 21 weights are faults (orbtb.campaign.WEIGHTS): about 107 of 250 events, 80 is 3.5
    # standard deviations below
    assert len(result.events) == 250 and result.faults >= 80


LONG_SEED, LONG_EVENTS = 2026, 10_000


def test_long_campaign() -> None:
    """Issue 26's campaign: 10,000 events, at least one frame each (a cable cut sends three), on
    test-tiny (128x96, 2 scales, 512 slots), with every fault, parameter change (the selection's
    too), back-pressure, the CPU holding banks and resets; no lock-up, every good frame bit-exact."""
    tiny = named("test-tiny")
    generics = generics_for(tiny.config(), colour=True, mem_depth=tiny.mem_depth)
    photos = [colour_photo(name, tiny.width, tiny.height) for name in CAMPAIGN_PHOTOS]
    CAMPAIGN_OUT.mkdir(parents=True, exist_ok=True)
    progress = CAMPAIGN_OUT / f"long-{LONG_SEED}.progress"
    progress.write_text("")
    t0 = time.monotonic()
    counts = {"published": 0, "skipped": 0}

    def note(ev: Event) -> None:
        counts["published"] += ev.published
        counts["skipped"] += ev.skipped
        if (ev.step + 1) % 250 == 0:
            with progress.open("a") as f:
                f.write(f"{ev.step + 1} events, {counts['published']} published, {counts['skipped']} skipped, "
                        f"{time.monotonic() - t0:.0f} s\n")  # fmt: skip

    result = run_campaign(photos, LONG_EVENTS, seed=LONG_SEED, generics=generics, on_event=note)
    write_report(f"long-{LONG_SEED}", result)
    print(f"long campaign: {result.summary()}")
    assert not result.lockups, result.lockups
    assert not result.mismatches, result.mismatches[:5]
    assert len(result.events) == LONG_EVENTS and result.frames_sent >= 10_000
    # each kind of fault and change hundreds of times (a weight of 1 in 21: about 476 expected)
    rare = {k: n for k, n in result.by_kind((*FAULTS, *CHANGES)).items() if n < 300}
    assert not rare, rare
    assert result.frames_skipped >= 100 and result.frames_published >= 5_000


@pytest.mark.parametrize(("seed", "init_seed"), [(11, 0), (23, 7)], ids=["ddr-11-0", "ddr-23-7"])
def test_ddr_fault_campaign(seed: int, init_seed: int) -> None:
    """The fault campaign on the DDR build (docs/fast-sim.md, "The DDR model"): test-tiny's size with
    a burst FIFO of 32 slots, so that the stalls fill it; every event of the BRAM campaign and the DDR
    ones; each frame the DDR path dropped explained by a stall or an error response and counted."""
    tiny = named("test-tiny")
    generics = {**generics_for(tiny.config(), colour=True, mem_depth=tiny.mem_depth, mem_kind="ddr"),
                "DMA_FIFO_g": 32}  # fmt: skip
    photos = [colour_photo(name, tiny.width, tiny.height) for name in CAMPAIGN_PHOTOS]
    result = run_campaign(photos, 250, seed=seed, generics=generics, init_seed=init_seed)
    write_report(f"ddr-fault-{seed}-{init_seed}", result)
    print(f"DDR fault campaign: {result.summary()}")
    assert not result.lockups, result.lockups
    assert not result.mismatches, result.mismatches[:5]
    ddr = result.by_kind(DDR_KINDS)
    assert len(result.events) == 250 and all(n >= 5 for n in ddr.values()), ddr
    assert result.frames_dropped_fifo >= 1 and result.frames_dropped_error >= 1, result.report()["ddr"]
    assert result.axi["protocol_errors"] == 0 and result.axi["refused"] == 0, result.axi
