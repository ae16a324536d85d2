# SPDX-License-Identifier: MIT
"""Pixel formats of the model's input: 8-bit luma from grey or RGB(A) arrays (file loading is
orb_tools.images)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .luma import rgb_to_luma

DEFAULT_IMAGE = Path(__file__).resolve().parent / "data" / "default_640x480.png"


class ImageError(ValueError):
    """An image file that is missing, unreadable or unusable."""


def to_luma(img: np.ndarray) -> np.ndarray:
    """Greyscale stays as it is (16-bit is scaled to 8); RGB(A) goes through the RTL's luma formula."""
    if img.dtype == np.uint16:
        img = (img >> 8).astype(np.uint8)
    if img.dtype != np.uint8:
        raise ImageError(f"unsupported pixel type {img.dtype}")
    if img.ndim == 2:
        return img
    if img.ndim == 3 and img.shape[2] in (3, 4):
        return rgb_to_luma(np.ascontiguousarray(img[..., :3]))
    raise ImageError(f"unsupported image shape {img.shape}")
