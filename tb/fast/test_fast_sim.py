# SPDX-License-Identifier: MIT
"""The fast path (docs/fast-sim.md): GHDL's synthesised netlist of orb_accel_top in Verilator with
the C++ harness, driven by the shipped driver. One small configuration (128x96, 2 scales, 512
slots, RGB) is built here (about 20 s, cached by netlist hash); the long regressions are in
test_fast_regressions.py (slow).

- photo_stream: four colour photographs back to back with blanking and back-pressure on the
  overlay output, the driver reading frame k while k+1 is written; every frame bit-exact with the
  golden model, frame numbers consecutive, the overlay of frame k+1 showing frame k's features;
- against GHDL: the same frame through the RTL in GHDL (orb_sim.jobs.accel_job) and the netlist
  gives the same features, overlay, counters and record; the latency agrees within GHDL's own
  +-1 clock of coroutine order;
- a live source (a pixel clock of 3/4, a FIFO that drops on overflow) into the checker that holds
  its input: good frames pass bit-exact without a drop; after a frame with lines missing the FIFO
  drops pixels, the next frame is lost too, the frames after it published bit-exact;
- 2-state: three initial states (zeros and two random seeds) give the same features and the same
  overlay from the third frame on (the first two overlay frames show the uncleared bitmap RAMs:
  docs/overlay.md, docs/fast-sim.md);
- a 60-event fault campaign (orbtb.campaign, seed 3): no lock-up, no mismatch, every kind of event;
  and the campaign's checks failing on two planted faults (banks never released: the watchdog's
  lock-up; a wrong threshold: mismatches);
- `make sim FAST=1`'s script and `orb-accel extract --backend rtl-fast` (luma input: a second build).
"""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import cv2
import numpy as np
import pytest

from golden_model.config import (
    RECOMMENDED_COLS,
    RECOMMENDED_ROWS,
    RECOMMENDED_SCALES,
    RECOMMENDED_SECTORS,
    RECOMMENDED_STEP,
    RECOMMENDED_THRESHOLD_LO,
    Config,
    named,
    recommended_budget,
)
from golden_model.features import first_difference, read_csv
from golden_model.luma import rgb_to_luma
from golden_model.overlay import render_marker_overlay
from orb_accel.driver import HwConfig, OrbAccel
from orb_sim.fast.jobs import FastAccel, generics_for, pack, run_accel_fast
from orb_sim.rtl_backend import run_accel_job
from orbtb.campaign import KINDS, Campaign, Setting, run_campaign
from orbtb.images import colour_photo
from orbtb.scoreboard import expected_features, expected_streamed

TINY = named("test-tiny")  # docs/configurations.md
W, H, SCALES, SECTORS, DEPTH = TINY.width, TINY.height, TINY.scales, TINY.sectors, TINY.mem_depth
assert (TINY.step_num, TINY.step_den) == (2, 1), "the model calls below assume the 2:1 pyramid"
PHOTOS = ("astronaut", "coffee", "chelsea", "rocket")
ROOT = Path(__file__).resolve().parents[2]
# the driver's default selection on this accelerator (the grid, the recommended budget), and a
# tighter one that makes the netlist replace and evict
HW = HwConfig(W, H, SCALES, SECTORS, DEPTH)
DEFAULT = f"grid:{HW.default_budget()}:{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}"
TIGHT = (60, (15, 12), 5)
TIGHT_TEXT = f"grid:{TIGHT[0]}:{TIGHT[1][0]}x{TIGHT[1][1]}:{TIGHT[2]}"
CFG = Config(W, H, scales=SCALES, sectors=SECTORS, threshold=20, mode="orb", selection="grid", budget=TIGHT[0],
             cols=TIGHT[1][0], rows=TIGHT[1][1], threshold_lo=TIGHT[2])  # fmt: skip
GENERICS = generics_for(CFG, colour=True, mem_depth=DEPTH)


@pytest.fixture(scope="module")
def photos() -> list[np.ndarray]:
    return [colour_photo(name, W, H) for name in PHOTOS]


def model(rgb: np.ndarray, selection: str = DEFAULT):
    return expected_features(rgb_to_luma(rgb), SCALES, 20, "orb", SECTORS, (2, 1), selection)


def marked(rgb: np.ndarray, selection: str = DEFAULT):
    """What the overlay of the next frame marks: the features the stream carried."""
    return expected_streamed(rgb_to_luma(rgb), SCALES, 20, "orb", SECTORS, (2, 1), selection)


def test_photo_stream(photos: list[np.ndarray]) -> None:
    fa = FastAccel.start(GENERICS)
    sim, accel = fa.sim, fa.accel
    tight = TIGHT_TEXT
    accel.configure(threshold=20, budget=TIGHT[0], cells=TIGHT[1], threshold_lo=TIGHT[2])
    sim.set_out_ready(0.8, seed=5)
    sim.capture(True)
    for rgb in photos:
        sim.push_frame(pack(rgb), 16, 64)
    frames = list(accel.frames(len(photos), timeout_s=fa.s(40 * fa.frame_clocks)))
    assert [f.number for f in frames] == [0, 1, 2, 3]
    for k, (f, rgb) in enumerate(zip(frames, photos, strict=True)):
        diff = first_difference(f.features, model(rgb, tight))
        assert diff is None, f"frame {k}: netlist (first) and model (second) differ: {diff}"
        assert f.dropped == 0 and f.truncated == 0
    assert sim.stats()["longest_stall"] > 0, "the overlay back-pressure never reached the input"
    sim.run_video(10 * fa.frame_clocks)
    sim.run(2000)
    data, flags = sim.captured()
    n = W * H
    assert len(data) == len(photos) * n and all(flags[k * n] & 1 for k in range(len(photos)))
    for k in range(1, len(photos)):
        shown = np.stack(((data[k * n : (k + 1) * n] >> 16) & 255, (data[k * n : (k + 1) * n] >> 8) & 255,
                          data[k * n : (k + 1) * n] & 255), axis=-1).astype(np.uint8).reshape(H, W, 3)  # fmt: skip
        want = render_marker_overlay(photos[k], marked(photos[k - 1], tight), scales=SCALES)
        bad = np.argwhere(np.any(shown != want, axis=-1))
        assert len(bad) == 0, f"overlay of frame {k}: {len(bad)} pixels differ, the first at (y, x) {bad[0]}"
    sim.close()


def test_live_source(photos: list[np.ndarray]) -> None:
    """The harness's live source (FastSim.set_live, docs/fast-sim.md): a pixel clock of 3/4 of the
    clock with blanking, through a 64-pixel FIFO that drops on overflow, into the checker that holds
    its input while padding (orb_accel_top's default IDLE_TIMEOUT_g 0). Good frames pass without a
    drop, bit-exact, the FIFO never near full; a frame with 40 lines missing makes the checker pad
    them while holding the input, so the FIFO drops pixels of the next frame (the old checker's
    cascade, docs/board.md): the short frame and the next are lost, the frames after them published
    bit-exact. Frames are matched by features."""
    fa = FastAccel.start(GENERICS)
    sim, accel = fa.sim, fa.accel
    accel.configure(threshold=20, budget=TIGHT[0], cells=TIGHT[1], threshold_lo=TIGHT[2])
    sim.set_live(Fraction(3, 4), 64)
    sent = [photos[0], photos[1], photos[2], photos[3], photos[1][::-1], photos[2][:, ::-1]]
    want = [model(rgb, TIGHT_TEXT) for rgb in sent]
    for k, rgb in enumerate(sent):
        sim.push_frame(pack(rgb[: H - 40] if k == 2 else rgb), 16, 64)
    period = (W + 16) * H + 64  # pixel clocks per frame (4/3 clocks each)
    got: list[int | None] = []
    with pytest.raises(TimeoutError):
        while True:  # every frame published, until the video has ended
            f = accel.next_frame(timeout_s=fa.s(6 * period))
            got.append(next((k for k, e in enumerate(want) if first_difference(f.features, e) is None), None))
            if len(got) == 2:
                assert sim.stats()["fifo_dropped"] == 0 and sim.stats()["fifo_max"] < 8, sim.stats()
    st = sim.stats()
    assert got == [0, 1, 4, 5], f"published {got} (by the frame sent each matches), sent 0 .. 5, 2 short"
    assert st["fifo_dropped"] > 0 and st["fifo_max"] == 64, st
    sim.close()


def test_against_ghdl(photos: list[np.ndarray], tmp_path: Path) -> None:
    rgb = photos[1]
    ghdl = run_accel_job(rgb, CFG, tmp_path / "ghdl", tmp_path / "ghdl.log", overlay=True)
    fast = run_accel_fast(rgb, CFG, tmp_path / "fast", overlay=True)
    a = read_csv(tmp_path / "ghdl" / "features.csv", SECTORS)
    b = read_csv(tmp_path / "fast" / "features.csv", SECTORS)
    assert first_difference(a, b) is None, f"GHDL (first) and the netlist (second) differ: {first_difference(a, b)}"
    assert first_difference(b, model(rgb, TIGHT_TEXT)) is None
    assert np.array_equal(np.load(tmp_path / "ghdl" / "overlay.npy"), np.load(tmp_path / "fast" / "overlay.npy"))
    same = ("features", "frame_cycles", "pixels", "cycles_per_pixel", "dropped_merge", "truncated", "desc_lost",
            "proto_errors")  # fmt: skip
    assert {k: ghdl[k] for k in same} == {k: fast[k] for k in same}
    assert abs(ghdl["latency_cycles"] - fast["latency_cycles"]) <= 1, (ghdl["latency_cycles"], fast["latency_cycles"])


def _overlay_frames(data: np.ndarray) -> list[np.ndarray]:
    n = W * H
    return [np.stack(((d >> 16) & 255, (d >> 8) & 255, d & 255), axis=-1).astype(np.uint8).reshape(H, W, 3)
            for d in (data[k * n : (k + 1) * n] for k in range(len(data) // n))]  # fmt: skip


def test_initial_state(photos: list[np.ndarray]) -> None:
    """Zeros (seed 0) and two random initial states: the same features, the same overlay from the
    third frame on. The overlay's bitmap RAMs are not cleared by reset (docs/overlay.md: block RAM
    is zero after configuration, and each bank is cleared as it is shown), so with random RAM
    contents the first two overlay frames show random marks: that is where the random state
    reaches an output, which also shows the randomisation is in effect."""
    shown = {}
    for seed in (0, 5, 9):
        fa = FastAccel.start(GENERICS, seed=seed)
        fa.accel.configure(threshold=20)
        fa.sim.capture(True)
        for k in range(3):
            fa.sim.push_frame(pack(photos[k]), 16, 64)
        frames = list(fa.accel.frames(3, fa.s(40 * fa.frame_clocks)))
        for k, f in enumerate(frames):
            assert first_difference(f.features, model(photos[k])) is None, f"seed {seed}, frame {k}"
        fa.sim.run_video(10 * fa.frame_clocks)
        fa.sim.run(2000)
        shown[seed] = _overlay_frames(fa.sim.captured()[0])
        assert len(shown[seed]) == 3
        want = render_marker_overlay(photos[2], marked(photos[1]), scales=SCALES)
        assert np.array_equal(shown[seed][2], want), f"seed {seed}: overlay of frame 2"
        if seed == 0:
            assert np.array_equal(shown[0][0], photos[0]), "zero RAMs: frame 0 passes unmarked"
            want1 = render_marker_overlay(photos[1], marked(photos[0]), scales=SCALES)
            assert np.array_equal(shown[0][1], want1), "zero RAMs: frame 1 shows frame 0's features"
        fa.sim.close()
    assert not np.array_equal(shown[5][0], photos[0]) and not np.array_equal(shown[9][0], photos[0]), (
        "random RAM contents did not reach the first overlay frame: is the random initial state in effect?"
    )


def test_fault_campaign_quick(photos: list[np.ndarray]) -> None:
    result = run_campaign(photos, 60, seed=3, generics=GENERICS)
    print(result.summary())
    assert not result.lockups, result.lockups
    assert not result.mismatches, result.mismatches[:5]
    assert result.faults >= 15 and result.frames_published >= 20 and result.features_checked > 1000
    # seed 3 draws every kind of event and a hold that makes the accelerator skip a frame: the
    # short campaign of make test reaches each path of the reference (tb/orbtb/campaign.py)
    missing = [k for k, n in result.by_kind(KINDS).items() if n == 0]
    assert not missing and result.frames_skipped >= 1, (missing, result.frames_skipped)


class _NeverReleases(Campaign):
    """A CPU that keeps every bank while the campaign's reference believes them released."""

    def release(self) -> None:
        self.ref.ready.clear()


class _WrongThreshold(Campaign):
    """A CPU that writes a threshold 3 above the one the reference applies."""

    def write_setting(self, accel: OrbAccel, s: Setting) -> None:
        super().write_setting(accel, replace(s, threshold=s.threshold + 3))


def test_fault_campaign_can_fail(photos: list[np.ndarray]) -> None:
    """The campaign's checks fail on planted faults: banks never released stop the publishing, which
    the watchdog reports as a lock-up; frames made at another threshold than the reference's are
    mismatches (their features and the parameters in their records)."""
    stuck = _NeverReleases(photos, 3, GENERICS).run(20)
    assert len(stuck.lockups) == 1 and "no frame for" in stuck.lockups[0], stuck.lockups
    assert len(stuck.events) < 20
    wrong = _WrongThreshold(photos, 3, GENERICS).run(6)
    assert not wrong.lockups, wrong.lockups
    assert any("its record says" in m for m in wrong.mismatches), wrong.mismatches[:3]
    assert any(" lost: " in m for m in wrong.mismatches), wrong.mismatches[:3]  # the features differ


def test_make_sim_fast_and_cli(tmp_path: Path, photos: list[np.ndarray]) -> None:
    img = tmp_path / "photo.png"
    cv2.imwrite(str(img), cv2.cvtColor(photos[3], cv2.COLOR_RGB2BGR))
    r = subprocess.run([sys.executable, "-m", "orb_tools.cli", "sim", "--fast", "--image", str(img), "--size", "native",
                        "--out-dir", str(tmp_path / "sim")], capture_output=True, text=True, timeout=900)  # fmt: skip
    assert r.returncode == 0, r.stdout + r.stderr
    report = json.loads((tmp_path / "sim" / "report.json").read_text())
    assert report["bit_exact"] and report["overlay_bit_exact"] and report["engine"] == "verilator-netlist"
    # make sim's default is the named configuration "recommended-vga" with its grid selection, here
    # at the photograph's own size (--size native)
    rec = named("recommended-vga")
    assert report["config"] == rec.name
    luma = rgb_to_luma(photos[3])
    grid = f"grid:{recommended_budget(W, H)}:{rec.cols}x{rec.rows}:{rec.threshold_lo}"
    want = expected_features(luma, rec.scales, rec.threshold, "orb", rec.sectors, (rec.step_num, rec.step_den), grid)
    assert report["features"] == len(want) and report["dropped"] == 0
    out = tmp_path / "cli.csv"
    r = subprocess.run([sys.executable, "-m", "orb_tools.cli", "extract", str(img), "--backend", "rtl-fast", "--budget",
                        "0", "--out", str(out)], capture_output=True, text=True, timeout=900)  # fmt: skip
    assert r.returncode == 0, r.stdout + r.stderr
    luma = rgb_to_luma(cv2.cvtColor(cv2.imread(str(img)), cv2.COLOR_BGR2RGB))
    want = expected_features(luma, RECOMMENDED_SCALES, 20, "orb", RECOMMENDED_SECTORS, RECOMMENDED_STEP)
    assert first_difference(read_csv(out, 32), want) is None
