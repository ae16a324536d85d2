# SPDX-License-Identifier: MIT
"""The `orb-accel extract` command with the model backend: outputs and one-line errors on bad input."""

from __future__ import annotations

import csv
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from golden_model import Config, extract, read_csv
from golden_model.config import (
    RECOMMENDED_BUDGET,
    RECOMMENDED_SCALES,
    RECOMMENDED_SECTORS,
    RECOMMENDED_STEP,
    RECOMMENDED_THRESHOLD_LO,
)
from golden_model.images import DEFAULT_IMAGE
from orb_tools.cli import main
from orb_tools.images import load_luma


def _photo_png(tmp_path: Path) -> Path:
    import skimage.data

    path = tmp_path / "chelsea.png"
    cv2.imwrite(str(path), cv2.cvtColor(skimage.data.chelsea(), cv2.COLOR_RGB2BGR))
    return path


@pytest.mark.parametrize(("extra", "mode"), [([], "orb"), (["--fast-only"], "fast")])
def test_extract_model_writes_csv_and_overlay(tmp_path: Path, extra: list[str], mode: str) -> None:
    png = _photo_png(tmp_path)
    out, overlay = tmp_path / "f.csv", tmp_path / "o.png"
    rc = main(["extract", str(png), "--backend", "model", "--threshold", "25", "--scales", "2", "--step", "2:1",
               "--sectors", "64", "--budget", "0", "--out", str(out), "--overlay", str(overlay), *extra])  # fmt: skip
    assert rc == 0
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows, "no features written"
    assert list(rows[0])[:6] == ["scale", "x", "y", "score", "sector", "descriptor"]
    img = load_luma(png)
    cfg = Config(img.shape[1], img.shape[0], scales=2, sectors=64, threshold=25, mode=mode)
    expected = extract(img, cfg)
    got = read_csv(out, sectors_total=64)
    assert got == expected
    if mode == "orb":
        assert all(len(r["descriptor"]) == 64 and r["descriptor"] == r["descriptor"].lower() for r in rows)
        assert all(0 <= int(r["sector"]) < 64 for r in rows)
    else:
        assert all(r["sector"] == "" and r["descriptor"] == "" for r in rows)
    drawn = cv2.imread(str(overlay))
    assert drawn is not None and drawn.shape[:2] == img.shape
    assert not np.array_equal(cv2.cvtColor(drawn, cv2.COLOR_BGR2GRAY), img), "overlay draws nothing"


def test_extract_defaults_are_the_recommended_configuration(tmp_path: Path) -> None:
    out = tmp_path / "f.csv"
    assert main(["extract", "--default-image", "--out", str(out)]) == 0
    img = load_luma(DEFAULT_IMAGE)
    cfg = Config(img.shape[1], img.shape[0], scales=RECOMMENDED_SCALES, sectors=RECOMMENDED_SECTORS, threshold=20,
                 step_num=RECOMMENDED_STEP[0], step_den=RECOMMENDED_STEP[1])  # fmt: skip
    got = read_csv(out, sectors_total=cfg.sectors, step=cfg.step)
    full = extract(img, cfg)
    # the accelerator's grid selection at the recommended budget, cell and low threshold
    grid = extract(img, replace(cfg, selection="grid", budget=RECOMMENDED_BUDGET,
                                threshold_lo=RECOMMENDED_THRESHOLD_LO))  # fmt: skip
    assert got == grid and len(got) == RECOMMENDED_BUDGET < len(full)
    assert int(got.scale.max()) == RECOMMENDED_SCALES - 1, "every level of the recommended pyramid has features"
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    x0, _ = got.sorted().full_res()
    assert [float(r["x0"]) for r in rows] == pytest.approx(x0.tolist(), abs=1e-4), "x0 is (x + 0.5) r^s - 0.5"


@pytest.mark.parametrize(("step", "message"), [("5:2", "need step_den < step_num <= 2 step_den"),
                                               ("5:3", "step_den must be"), ("54", "expected NUM:DEN")])  # fmt: skip
def test_extract_refuses_an_illegal_step(tmp_path: Path, step: str, message: str) -> None:
    proc = _run_cli("extract", "--default-image", "--step", step, "--out", str(tmp_path / "out.csv"))
    assert proc.returncode == 2 and message in proc.stderr and "Traceback" not in proc.stderr, proc.stderr


def test_default_image_is_640x480() -> None:
    assert load_luma(DEFAULT_IMAGE).shape == (480, 640)


def _run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    cmd = [sys.executable, "-m", "orb_tools.cli", *args]
    return subprocess.run(cmd, capture_output=True, text=True, check=False)


@pytest.mark.parametrize(
    ("make_args", "message"),
    [
        (lambda d: [str(d / "missing.png")], "no such file"),
        (lambda d: [str(d)], "is a directory"),
        (lambda d: [str(d / "junk.png")], "not an image"),
        (lambda d: [str(d / "tiny.png")], "smaller than the minimum 64x48"),
        (lambda d: [str(d / "ok.png"), "--threshold", "256"], "threshold must be 0..255"),
        (lambda d: [str(d / "ok.png"), "--threshold", "abc"], "threshold must be an integer"),
        (lambda d: [str(d / "ok.png"), "--scales", "9"], "scales must be 1..8"),
        (lambda d: [str(d / "ok.png"), "--sectors", "24"], "sectors must be 16, 32 or 64"),
        (lambda d: [str(d / "ok.png"), "--backend", "fpga"], "invalid choice"),
        (lambda d: [str(d / "ok.png"), "--budget", "5000"], "budget must be 0..4095"),
        (lambda d: [str(d / "ok.png"), "--cells", "16x6"], "cols must be 1..15"),
        (lambda d: [str(d / "ok.png"), "--cells", "8by6"], "expected COLSxROWS"),
        (lambda d: [str(d / "ok.png"), "--threshold-lo", "300"], "threshold_lo must be 0..255"),
    ],
)
def test_extract_bad_input_is_one_line_error(tmp_path: Path, make_args, message: str) -> None:
    (tmp_path / "junk.png").write_bytes(b"this is not a png")
    cv2.imwrite(str(tmp_path / "tiny.png"), np.zeros((47, 80), np.uint8))
    cv2.imwrite(str(tmp_path / "ok.png"), np.zeros((48, 64), np.uint8))
    proc = _run_cli("extract", *make_args(tmp_path), "--out", str(tmp_path / "out.csv"))
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert message in lines[0], lines[0]
    assert not (tmp_path / "out.csv").exists()


def test_extract_unwritable_output_is_one_line_error(tmp_path: Path) -> None:
    cv2.imwrite(str(tmp_path / "ok.png"), np.zeros((48, 64), np.uint8))
    (tmp_path / "file").write_text("x")
    proc = _run_cli("extract", str(tmp_path / "ok.png"), "--out", str(tmp_path / "file" / "out.csv"))
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
