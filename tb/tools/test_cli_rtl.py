# SPDX-License-Identifier: MIT
"""`orb-accel extract --backend rtl` writes the same CSV as the model backend, in orb and fast mode."""

from __future__ import annotations

from pathlib import Path

import cv2
import pytest

from orb_tools.cli import main
from orbtb import images


@pytest.mark.parametrize(
    ("name", "threshold", "scales", "mode", "sectors"),
    [("coffee", 12, 2, "fast", 32), ("camera", 40, 1, "fast", 32), ("astronaut", 10, 2, "orb", 32),
     ("chelsea", 10, 1, "orb", 64)],
)  # fmt: skip
def test_rtl_csv_equals_model_csv(tmp_path: Path, name: str, threshold: int, scales: int, mode: str,
                                  sectors: int) -> None:  # fmt: skip
    png = tmp_path / f"{name}.png"
    cv2.imwrite(str(png), images.photo(name, 160, 96))
    outs = {}
    for backend in ("rtl", "model"):
        outs[backend] = tmp_path / f"{backend}.csv"
        args = ["extract", str(png), "--backend", backend, "--threshold", str(threshold), "--scales", str(scales),
                "--sectors", str(sectors), "--out", str(outs[backend])]  # fmt: skip
        args += ["--fast-only"] if mode == "fast" else []
        assert main(args) == 0
    rtl, model = outs["rtl"].read_text(), outs["model"].read_text()
    assert model.count("\n") > 10, "too few features for a meaningful comparison"
    assert rtl == model, "RTL CSV differs from the model CSV"
