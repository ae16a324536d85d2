# SPDX-License-Identifier: MIT
"""Accelerator configuration, validated exactly like the hardware generics and registers.

The legal values come from golden_model.limits (generated from golden_model/data/limits.json, the
one definition the HDL's orb_limits_pkg and docs/limits.md are generated from too).
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

from . import limits

MODES = ("orb", "fast")

# The Config fields checked against golden_model.limits, in the order they are checked.
_LIMITED = tuple(lim for lim in limits.LIMITS if lim.config)


class ConfigError(ValueError):
    """An illegal configuration value (the hardware would refuse it too)."""


@dataclass(frozen=True)
class Config:
    """One accelerator configuration.

    ``sectors`` is the total number of orientation sectors (16, 32 or 64; generic SECTORS_g);
    the thesis's N, the sectors per quadrant, is the derived ``sectors_per_quadrant``.
    ``threshold`` is the run-time FAST threshold; ``mode`` is ``orb`` (detect and describe) or
    ``fast`` (detection only, the thesis's isolated-FAST mode).
    """

    width: int
    height: int
    scales: int = 1
    sectors: int = 32
    threshold: int = 20
    mode: str = "orb"

    def __post_init__(self) -> None:
        for lim in _LIMITED:
            value = getattr(self, lim.name)
            if isinstance(value, bool) or not isinstance(value, numbers.Integral):
                raise ConfigError(f"{lim.name} must be an integer ({lim.text}), got {value!r}")
            object.__setattr__(self, lim.name, int(value))  # numpy integers become plain ints
        for lim in _LIMITED:
            value = getattr(self, lim.name)
            if not lim.legal(value):
                raise ConfigError(f"{lim.name} must be {lim.text}, got {value}")
        if self.mode not in MODES:
            raise ConfigError(f"mode {self.mode!r} not one of {MODES}")

    @property
    def sectors_per_quadrant(self) -> int:
        """N = sectors / 4, the sectors per quadrant of the orientation and pattern rules (spec §9, §10)."""
        return self.sectors // 4

    def scale_size(self, scale: int) -> tuple[int, int]:
        """(width, height) of scale ``scale``: each scale halves the previous one, rounding down."""
        return self.width >> scale, self.height >> scale


def sectors_to_per_quadrant(sectors: int) -> int:
    """Total sectors (16, 32 or 64) to the per-quadrant N (4, 8 or 16)."""
    if isinstance(sectors, bool) or not isinstance(sectors, numbers.Integral) or not limits.SECTORS.legal(int(sectors)):
        raise ConfigError(f"sectors must be {limits.SECTORS.text}, got {sectors!r}")
    return int(sectors) // 4
