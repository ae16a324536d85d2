# SPDX-License-Identifier: MIT
"""A directory of per-frame feature CSVs: the output of `orb-accel board stream --csv DIR` and of
`orb-accel bag csv` (docs/ros-bags.md). numpy and the standard library only (it runs on the board).

    DIR/index.csv            one row per frame, in the order written (INDEX_COLUMNS: with the parameters
                             the frame was processed with, as its end-of-frame record says)
    DIR/frame_000000.csv     that frame's features, golden_model.features.write_csv's columns
    DIR/frame_000001.csv     ...

The directory must be new or empty: a run never appends to or mixes with an earlier one. Each
frame's CSV is written before its index row, and the index is flushed row by row, so a stream cut
short leaves a readable directory.
"""

from __future__ import annotations

import csv
from pathlib import Path
from types import TracebackType

import numpy as np

from golden_model.brief import DESCRIPTOR_BYTES
from golden_model.config import MODES
from golden_model.features import Features, read_csv, write_csv
from golden_model.frameparams import FrameParams

INDEX = "index.csv"
INDEX_COLUMNS = (
    "index", "file", "frame", "stamp", "threshold", "mode", "sectors", "width", "height", "features", "dropped",
    "truncated", "threshold_lo", "selection", "budget", "cols", "rows",
)  # fmt: skip
_TEXT = ("file", "mode", "selection")
_FLOAT = ("stamp",)


class CsvDir:
    """Writer of a CSV directory; ``out`` is created, or must be an empty directory."""

    def __init__(self, out: Path) -> None:
        self.out = Path(out)
        if self.out.exists() and (not self.out.is_dir() or any(self.out.iterdir())):
            raise FileExistsError(f"{self.out}: exists and is not an empty directory (not overwriting)")
        self.out.mkdir(parents=True, exist_ok=True)
        self._fh = open(self.out / INDEX, "w", newline="")
        self._index = csv.writer(self._fh)
        self._index.writerow(INDEX_COLUMNS)
        self._fh.flush()
        self.count = 0

    def write(
        self, features: Features, *, frame: int, stamp: float, params: FrameParams, width: int, height: int,
        dropped: int, truncated: int,
    ) -> Path:  # fmt: skip
        """Write one frame's CSV and its index row; returns the CSV's path. ``stamp`` is in seconds,
        ``params`` the parameters the frame was processed with (Frame.params, the message's)."""
        if params.mode not in MODES:
            raise ValueError(f"mode {params.mode!r} not one of {MODES}")
        name = f"frame_{self.count:06d}.csv"
        path = self.out / name
        write_csv(features, path)
        self._index.writerow([
            self.count, name, int(frame), repr(float(stamp)), int(params.threshold), params.mode,
            int(features.sectors_total), int(width), int(height), len(features), int(dropped), int(truncated),
            int(params.threshold_lo), params.selection, int(params.budget), int(params.cols), int(params.rows),
        ])  # fmt: skip
        self._fh.flush()
        self.count += 1
        return path

    def close(self) -> None:
        self._fh.close()

    def __enter__(self) -> CsvDir:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()


def read_csv_dir(path: Path) -> list[tuple[dict, Features]]:
    """Read a CSV directory back: (index row, features) per frame, in index order.

    Row values are ints, except ``file``, ``mode`` and ``selection`` (str) and ``stamp`` (float seconds).
    """
    path = Path(path)
    index = path / INDEX
    if not index.is_file():
        raise FileNotFoundError(f"{path}: no {INDEX} (not a CSV directory)")
    with open(index, newline="") as fh:
        reader = csv.DictReader(fh)
        if tuple(reader.fieldnames or ()) != INDEX_COLUMNS:
            raise ValueError(f"{index}: columns {reader.fieldnames}, expected {list(INDEX_COLUMNS)}")
        raw = list(reader)
    out = []
    for r in raw:
        row = {k: (v if k in _TEXT else float(v) if k in _FLOAT else int(v)) for k, v in r.items()}
        feats = read_csv(path / row["file"], sectors_total=row["sectors"])
        if len(feats) != row["features"]:
            raise ValueError(f"{path / row['file']}: {len(feats)} features, {INDEX} says {row['features']}")
        if row["mode"] == "orb" and len(feats) == 0:  # an empty CSV cannot tell the descriptor width
            feats.descriptor = np.zeros((0, DESCRIPTOR_BYTES), dtype=np.uint8)
        out.append((row, feats))
    return out
