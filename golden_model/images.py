# SPDX-License-Identifier: MIT
"""Image loading for the CLI and the tests: any file OpenCV reads, converted to 8-bit luma."""

from __future__ import annotations

from pathlib import Path

import cv2
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


def load_rgb_or_grey(path: Path) -> np.ndarray:
    """The image as OpenCV reads it, with colour in RGB order."""
    if not path.exists():
        raise ImageError(f"{path}: no such file")
    if path.is_dir():
        raise ImageError(f"{path}: is a directory, not an image")
    img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if img is None:
        raise ImageError(f"{path}: not an image OpenCV can read")
    if img.ndim == 3 and img.shape[2] == 4:
        img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGB)
    elif img.ndim == 3 and img.shape[2] == 3:
        img = cv2.cvtColor(img, cv2.COLOR_BGR2RGB)
    return img


def load_luma(path: Path) -> np.ndarray:
    return to_luma(load_rgb_or_grey(Path(path)))


def sample_photographs() -> dict[str, np.ndarray]:
    """scikit-image's bundled real photographs as luma (no download needed)."""
    import skimage.data as data

    names = ("astronaut", "camera", "coffee", "chelsea", "rocket")
    return {name: to_luma(getattr(data, name)()) for name in names}
