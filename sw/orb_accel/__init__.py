# SPDX-License-Identifier: MIT
"""The host side of the ORB accelerator: its driver (numpy only; runs on the board's ARM CPU)."""

from .bus import Bus, BusError
from .driver import AccelError, Frame, HwConfig, OrbAccel

__all__ = ["AccelError", "Bus", "BusError", "Frame", "HwConfig", "OrbAccel"]
