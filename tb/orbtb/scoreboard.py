# SPDX-License-Identifier: MIT
"""Compare RTL frames with the golden model, reporting the first mismatch with its coordinates."""

from __future__ import annotations

import numpy as np

from golden_model import Config, extract, first_difference
from golden_model.config import parse_cells
from golden_model.features import Features
from golden_model.pipeline import streamed


def model_config(img: np.ndarray, scales: int, threshold: int, mode: str = "fast", sectors: int = 32,
                 step: tuple[int, int] = (2, 1), selection: str = "all") -> Config:  # fmt: skip
    """The model's configuration; `selection` is `all` or `grid:BUDGET:COLSxROWS:LOW` (docs/spec.md
    section 14)."""
    h, w = img.shape
    kind, *arg = selection.split(":")
    sel = {}
    if kind == "grid":
        cols, rows = parse_cells(arg[1])
        sel = {"selection": "grid", "budget": int(arg[0]), "cols": cols, "rows": rows, "threshold_lo": int(arg[2])}
    return Config(w, h, scales=scales, sectors=sectors, threshold=threshold, mode=mode, step_num=step[0],
                  step_den=step[1], **sel)  # fmt: skip


def expected_features(img: np.ndarray, scales: int, threshold: int, mode: str = "fast", sectors: int = 32,
                      step: tuple[int, int] = (2, 1), selection: str = "all") -> Features:  # fmt: skip
    """The model's features of a frame (what its bank holds)."""
    return extract(img, model_config(img, scales, threshold, mode, sectors, step, selection))


def expected_streamed(img: np.ndarray, scales: int, threshold: int, mode: str = "fast", sectors: int = 32,
                      step: tuple[int, int] = (2, 1), selection: str = "all") -> Features:  # fmt: skip
    """The features the feature stream carries (what the overlay marks): the bank's in `all`
    selection, in `grid` also those a later candidate replaced (golden_model.pipeline.streamed)."""
    return streamed(img, model_config(img, scales, threshold, mode, sectors, step, selection))


def check_frame(got: Features, expected: Features, what: str) -> None:
    diff = first_difference(got, expected)
    if diff is not None:
        raise AssertionError(f"{what}: RTL (first) and model (second) differ: {diff}")
