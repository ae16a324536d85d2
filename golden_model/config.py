# SPDX-License-Identifier: MIT
"""Accelerator configuration, validated exactly like the hardware generics and registers."""

from __future__ import annotations

import numbers
from dataclasses import dataclass

MIN_WIDTH = 64
MIN_HEIGHT = 48
MAX_WIDTH = 1920
MAX_HEIGHT = 1080
MAX_SCALES = 4
SECTORS_PER_QUADRANT = (4, 8, 16)
MODES = ("orb", "fast")


_RANGES = {
    "width": f"{MIN_WIDTH}..{MAX_WIDTH}",
    "height": f"{MIN_HEIGHT}..{MAX_HEIGHT}",
    "scales": f"1..{MAX_SCALES}",
    "sectors_per_quadrant": "(4, 8, 16)",
    "threshold": "0..255",
}


class ConfigError(ValueError):
    """An illegal configuration value (the hardware would refuse it too)."""


@dataclass(frozen=True)
class Config:
    """One accelerator configuration.

    ``sectors_per_quadrant`` is the thesis's N; the accelerator has ``4 * N`` orientation sectors.
    ``threshold`` is the run-time FAST threshold; ``mode`` is ``orb`` (detect and describe) or
    ``fast`` (detection only, the thesis's isolated-FAST mode).
    """

    width: int
    height: int
    scales: int = 1
    sectors_per_quadrant: int = 8
    threshold: int = 20
    mode: str = "orb"

    def __post_init__(self) -> None:
        for name, legal in _RANGES.items():
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Integral):
                raise ConfigError(f"{name} must be an integer in {legal}, got {value!r}")
            object.__setattr__(self, name, int(value))  # numpy integers become plain ints
        if not MIN_WIDTH <= self.width <= MAX_WIDTH:
            raise ConfigError(f"width {self.width} outside {MIN_WIDTH}..{MAX_WIDTH}")
        if not MIN_HEIGHT <= self.height <= MAX_HEIGHT:
            raise ConfigError(f"height {self.height} outside {MIN_HEIGHT}..{MAX_HEIGHT}")
        if not 1 <= self.scales <= MAX_SCALES:
            raise ConfigError(f"scales {self.scales} outside 1..{MAX_SCALES}")
        if self.sectors_per_quadrant not in SECTORS_PER_QUADRANT:
            raise ConfigError(
                f"sectors per quadrant {self.sectors_per_quadrant} not one of {SECTORS_PER_QUADRANT}"
                f" (total sectors 16, 32 or 64)"
            )
        if not 0 <= self.threshold <= 255:
            raise ConfigError(f"threshold {self.threshold} outside 0..255")
        if self.mode not in MODES:
            raise ConfigError(f"mode {self.mode!r} not one of {MODES}")

    @property
    def sectors(self) -> int:
        """Total number of orientation sectors (4N)."""
        return 4 * self.sectors_per_quadrant

    def scale_size(self, scale: int) -> tuple[int, int]:
        """(width, height) of scale ``scale``: each scale halves the previous one, rounding down."""
        return self.width >> scale, self.height >> scale


def sectors_to_per_quadrant(sectors: int) -> int:
    """Total sectors (16, 32, 64) to the per-quadrant N (4, 8, 16)."""
    if isinstance(sectors, bool) or not isinstance(sectors, int) or sectors not in (16, 32, 64):
        raise ConfigError(f"sectors {sectors} not one of 16, 32, 64")
    return int(sectors) // 4
