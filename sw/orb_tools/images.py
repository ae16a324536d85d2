# SPDX-License-Identifier: MIT
"""Image files for the CLI, the tools and the tests: any file OpenCV reads, as RGB or 8-bit luma;
scikit-image's bundled photographs."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from golden_model.images import ImageError, to_luma


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
