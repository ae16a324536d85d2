# SPDX-License-Identifier: MIT
"""The orb_core job (orb_sim.jobs.core_job, used by scripts/bench/sweep_rtl.py)
through orb_sim.rtl_backend: back-to-back frames with one threshold and mode each come back as the
model's features, frame numbers in order, nothing dropped."""

from __future__ import annotations

from pathlib import Path

from golden_model import Config, extract, first_difference
from orb_sim.rtl_backend import extract_rtl, run_core_job
from orbtb import images


def test_core_job_frames_equal_the_model(tmp_path: Path) -> None:
    cfg = Config(128, 80, scales=2, sectors=32, mode="orb")
    frames = [images.photo("astronaut", 128, 80), images.photo("coffee", 128, 80)]
    thresholds, modes = [12, 20], ["orb", "fast"]
    got, report = run_core_job(frames, cfg, thresholds, modes, tmp_path / "job", tmp_path / "sim.log")
    assert report["frame_numbers"] == [0, 1] and report["drops"] == [0, 0], report
    assert report["dropped"] == 0 and report["desc_lost"] == 0 and report["bad_pixels"] == 0, report
    for i, (img, t, mode) in enumerate(zip(frames, thresholds, modes, strict=True)):
        want = extract(img, Config(128, 80, scales=2, sectors=32, threshold=t, mode=mode))
        assert len(want) > 10, f"frame {i}: too few features for a meaningful comparison"
        diff = first_difference(got[i], want)
        assert diff is None, f"frame {i} ({mode}, threshold {t}): {diff}"


def test_extract_rtl_on_the_core(tmp_path: Path) -> None:
    img = images.photo("chelsea", 96, 64)
    cfg = Config(96, 64, scales=1, sectors=64, threshold=10, mode="orb")
    feats, report = extract_rtl(img, cfg, log_dir=tmp_path, top="core")
    assert first_difference(feats, extract(img, cfg)) is None
    assert report["dropped"] == 0 and report["pixels"] == 96 * 64, report
