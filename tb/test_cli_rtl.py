# SPDX-License-Identifier: MIT
"""`orb-accel extract --backend rtl --fast-only` writes the same CSV as the model backend."""

from __future__ import annotations

from pathlib import Path

import cv2
import pytest

from golden_model.cli import main
from orbtb import images


@pytest.mark.parametrize(("name", "threshold", "scales"), [("coffee", 12, 2), ("camera", 40, 1)])
def test_rtl_csv_equals_model_csv(tmp_path: Path, name: str, threshold: int, scales: int) -> None:
    png = tmp_path / f"{name}.png"
    cv2.imwrite(str(png), images.photo(name, 160, 96))
    outs = {}
    for backend in ("rtl", "model"):
        outs[backend] = tmp_path / f"{backend}.csv"
        args = ["extract", str(png), "--backend", backend, "--fast-only", "--threshold", str(threshold),
                "--scales", str(scales), "--out", str(outs[backend])]  # fmt: skip
        assert main(args) == 0
    rtl, model = outs["rtl"].read_text(), outs["model"].read_text()
    assert model.count("\n") > 10, "too few features for a meaningful comparison"
    assert rtl == model, "RTL CSV differs from the model CSV"


def test_rtl_backend_orb_mode_is_a_clear_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    png = tmp_path / "p.png"
    cv2.imwrite(str(png), images.photo("camera", 64, 48))
    assert main(["extract", str(png), "--backend", "rtl", "--out", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--fast-only" in err[0], err
