# SPDX-License-Identifier: MIT
"""The host side of the ORB accelerator: its driver (numpy only; runs on the board's ARM CPU)."""

from .bus import Bus, BusError
from .devmem import DevMemBus
from .driver import AccelError, Frame, FrameSource, HwConfig, OrbAccel
from .uio import UIO_NAME, UioBus, find_uio

__all__ = [
    "UIO_NAME",
    "AccelError",
    "Bus",
    "BusError",
    "DevMemBus",
    "Frame",
    "FrameSource",
    "HwConfig",
    "OrbAccel",
    "UioBus",
    "find_uio",
]
