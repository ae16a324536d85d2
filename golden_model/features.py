# SPDX-License-Identifier: MIT
"""The feature list every backend produces, its canonical order and its CSV form."""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

CSV_COLUMNS = ("scale", "x", "y", "score", "sector", "descriptor", "x0", "y0", "angle_deg", "response", "low")
NO_SECTOR = -1
# the canonical order, most significant first: scale, then row, then column (Features.sorted)
CANONICAL_ORDER = ("scale", "y", "x")


def _empty_int() -> np.ndarray:
    return np.zeros(0, dtype=np.int64)


@dataclass
class Features:
    """Columns of one frame's features. ``sector`` is -1 and ``descriptor`` is (K, 0) in fast mode.

    ``sectors_total`` (4N of the configuration, in either mode) converts sectors to angles;
    ``step`` (the pyramid step num, den of the configuration) converts level coordinates to
    full-resolution ones. ``response`` is the corner response code (docs/spec.md section 15) and
    ``low`` marks a corner at the low threshold only (section 14); both default to 0 / False.
    """

    scale: np.ndarray = field(default_factory=_empty_int)
    x: np.ndarray = field(default_factory=_empty_int)
    y: np.ndarray = field(default_factory=_empty_int)
    score: np.ndarray = field(default_factory=_empty_int)
    sector: np.ndarray = field(default_factory=_empty_int)
    descriptor: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), dtype=np.uint8))
    sectors_total: int = 0
    step: tuple[int, int] = (2, 1)
    response: np.ndarray | None = None
    low: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = int(self.x.shape[0])
        if self.response is None:
            self.response = np.zeros(n, dtype=np.int64)
        if self.low is None:
            self.low = np.zeros(n, dtype=bool)

    def __len__(self) -> int:
        return int(self.x.shape[0])

    @property
    def has_descriptors(self) -> bool:
        return self.descriptor.shape[1] > 0

    def sorted(self) -> Features:
        """Canonical order: scale, then y, then x (the order a raster scan meets them per scale)."""
        order = np.lexsort(tuple(getattr(self, name) for name in reversed(CANONICAL_ORDER)))
        return self.take(order)

    def take(self, index: np.ndarray) -> Features:
        return Features(
            self.scale[index], self.x[index], self.y[index], self.score[index], self.sector[index],
            self.descriptor[index], self.sectors_total, self.step, self.response[index], self.low[index],
        )  # fmt: skip

    def level_factor(self) -> np.ndarray:
        """Per feature, r^scale with r = num / den: the size of a level pixel in full-resolution pixels."""
        num, den = self.step
        return (float(num) / float(den)) ** self.scale.astype(np.float64)

    def full_res(self) -> tuple[np.ndarray, np.ndarray]:
        """Feature centres in full-resolution pixel coordinates: (x + 0.5) r^scale - 0.5, r = num / den
        (docs/spec.md section 3: the exact centre of a level pixel, which the resampler's taps keep)."""
        f = self.level_factor()
        return (self.x + 0.5) * f - 0.5, (self.y + 0.5) * f - 0.5

    def size(self) -> np.ndarray:
        """Per feature, the patch diameter in full-resolution pixels: 31 r^scale (cv2.KeyPoint.size)."""
        return 31.0 * self.level_factor()

    def angle_deg(self) -> np.ndarray:
        if self.sectors_total == 0:
            return np.full(len(self), np.nan)
        return np.where(self.sector >= 0, self.sector * (360.0 / self.sectors_total), np.nan)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Features):
            return NotImplemented
        return first_difference(self, other) is None

    @staticmethod
    def concat(parts: list[Features], sectors_total: int, descriptor_bytes: int,
               step: tuple[int, int] = (2, 1)) -> Features:  # fmt: skip
        if not parts:
            return Features(descriptor=np.zeros((0, descriptor_bytes), dtype=np.uint8), sectors_total=sectors_total,
                            step=step)  # fmt: skip
        return Features(
            *(np.concatenate([getattr(p, name) for p in parts]) for name in ("scale", "x", "y", "score", "sector")),
            np.concatenate([p.descriptor for p in parts]),
            sectors_total,
            step,
            np.concatenate([p.response for p in parts]),
            np.concatenate([p.low for p in parts]),
        )


def first_difference(a: Features, b: Features) -> str | None:
    """None when equal; else a sentence naming the first differing feature (canonical order)."""
    a, b = a.sorted(), b.sorted()
    for i in range(min(len(a), len(b))):
        ka = (int(a.scale[i]), int(a.y[i]), int(a.x[i]))
        kb = (int(b.scale[i]), int(b.y[i]), int(b.x[i]))
        if ka != kb:
            first, other = (ka, "second") if ka < kb else (kb, "first")
            return f"feature {i}: scale {first[0]} (x={first[2]}, y={first[1]}) missing from the {other} list"
        for name in ("score", "response", "low", "sector"):
            va, vb = int(getattr(a, name)[i]), int(getattr(b, name)[i])
            if va != vb:
                return f"feature {i} at scale {ka[0]} (x={ka[2]}, y={ka[1]}): {name} {va} != {vb}"
        if a.descriptor.shape[1] != b.descriptor.shape[1] or not np.array_equal(a.descriptor[i], b.descriptor[i]):
            da, db = a.descriptor[i].tobytes().hex(), b.descriptor[i].tobytes().hex()
            return f"feature {i} at scale {ka[0]} (x={ka[2]}, y={ka[1]}): descriptor {da} != {db}"
    if len(a) != len(b):
        longer, which = (a, "first") if len(a) > len(b) else (b, "second")
        i = min(len(a), len(b))
        where = f"scale {int(longer.scale[i])} (x={int(longer.x[i])}, y={int(longer.y[i])})"
        return f"the {which} list has {abs(len(a) - len(b))} more features, the first at {where}"
    return None


def write_csv(features: Features, path: Path) -> None:
    f = features.sorted()
    x0, y0 = f.full_res()
    angle = f.angle_deg()
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_COLUMNS)
        for i in range(len(f)):
            has_sector = int(f.sector[i]) != NO_SECTOR
            w.writerow([
                int(f.scale[i]), int(f.x[i]), int(f.y[i]), int(f.score[i]),
                int(f.sector[i]) if has_sector else "",
                f.descriptor[i].tobytes().hex() if f.has_descriptors else "",
                f"{x0[i]:.10g}", f"{y0[i]:.10g}",
                f"{angle[i]:g}" if has_sector else "",
                int(f.response[i]), int(f.low[i]),
            ])  # fmt: skip


def read_csv(path: Path, sectors_total: int = 0, step: tuple[int, int] = (2, 1)) -> Features:
    """Read a features CSV written by any backend (extra columns ignored)."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    missing = [c for c in ("scale", "x", "y", "score", "sector", "descriptor") if rows and c not in rows[0]]
    if missing:
        raise ValueError(f"{path}: missing CSV columns {missing}")
    ints = {name: np.array([int(r[name]) for r in rows], dtype=np.int64) for name in ("scale", "x", "y", "score")}
    sector = np.array([int(r["sector"]) if r["sector"] else NO_SECTOR for r in rows], dtype=np.int64)
    has_desc = bool(rows) and bool(rows[0]["descriptor"])
    desc = (
        np.array([np.frombuffer(bytes.fromhex(r["descriptor"]), dtype=np.uint8) for r in rows]).reshape(len(rows), 32)
        if has_desc
        else np.zeros((len(rows), 0), dtype=np.uint8)
    )
    # response and low: columns added with the selection (0 when a file predates them)
    extra = {name: np.array([int(r.get(name) or 0) for r in rows], dtype=np.int64) for name in ("response", "low")}
    return Features(ints["scale"], ints["x"], ints["y"], ints["score"], sector, desc, sectors_total, step,
                    extra["response"], extra["low"].astype(bool))  # fmt: skip
