# SPDX-License-Identifier: MIT
"""Test images: crops of real photographs and synthetic corner cases, all deterministic."""

from __future__ import annotations

from functools import cache

import cv2
import numpy as np

from orb_tools.images import sample_photographs


@cache
def _photos() -> dict[str, np.ndarray]:
    return sample_photographs()


def photo(name: str, width: int, height: int) -> np.ndarray:
    """A real photograph fitted to width x height: cropped when it is larger, resized otherwise."""
    img = _photos()[name]
    h, w = img.shape
    if w >= width and h >= height:
        y0, x0 = (h - height) // 2, (w - width) // 2
        return np.ascontiguousarray(img[y0 : y0 + height, x0 : x0 + width])
    scale = max(width / w, height / h)
    big = cv2.resize(img, (max(width, round(w * scale)), max(height, round(h * scale))), interpolation=cv2.INTER_CUBIC)
    bh, bw = big.shape
    y0, x0 = (bh - height) // 2, (bw - width) // 2
    return np.ascontiguousarray(big[y0 : y0 + height, x0 : x0 + width])


def colour_photo(name: str, width: int, height: int) -> np.ndarray:
    """A scikit-image photograph (grey ones as R = G = B) resized to (height, width, 3) RGB."""
    import skimage.data

    img = getattr(skimage.data, name)()
    if img.ndim == 2:
        img = np.repeat(img[..., None], 3, axis=2)
    return cv2.resize(img[..., :3], (width, height), interpolation=cv2.INTER_AREA)


def flat(width: int, height: int, value: int = 128) -> np.ndarray:
    return np.full((height, width), value, dtype=np.uint8)


def dots(width: int, height: int, pitch: int = 2) -> np.ndarray:
    """Isolated bright dots every `pitch` pixels: with pitch 2, the densest pattern NMS allows."""
    img = np.zeros((height, width), dtype=np.uint8)
    img[::pitch, ::pitch] = 255
    return img


def checker(width: int, height: int, block: int = 1) -> np.ndarray:
    yy, xx = np.mgrid[0:height, 0:width]
    return (((yy // block + xx // block) % 2) * 255).astype(np.uint8)


def border_corners(width: int, height: int) -> np.ndarray:
    """Bright dots along all four borders (distances 0 to 5), plus noise in the middle."""
    rng = np.random.default_rng(7)
    img = (rng.integers(0, 40, (height, width))).astype(np.uint8)
    for d in range(6):
        img[d, d::5] = 255
        img[height - 1 - d, d::5] = 255
        img[d::5, d] = 255
        img[d::5, width - 1 - d] = 255
    return img


def noise(width: int, height: int, seed: int = 3) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (height, width)).astype(np.uint8)


def rotated(name: str, degrees: float, width: int, height: int) -> np.ndarray:
    """A photograph turned by `degrees` (clockwise on screen) about the frame centre, cut to
    width x height from a larger crop so that no corner of the frame is empty."""
    side = int(np.ceil(np.hypot(width, height))) + 2
    big = photo(name, side, side)
    rot = cv2.getRotationMatrix2D((side / 2, side / 2), -degrees, 1.0)
    turned = cv2.warpAffine(big, rot, (side, side), flags=cv2.INTER_LINEAR)
    y0, x0 = (side - height) // 2, (side - width) // 2
    return np.ascontiguousarray(turned[y0 : y0 + height, x0 : x0 + width])


def make(kind: str, width: int, height: int) -> np.ndarray:
    """`photo:<name>`, `rotated:<name>:<degrees>`, `flat`, `dots`, `dots4`, `checker`, `checker4`,
    `border`, `noise`."""
    if kind.startswith("photo:"):
        return photo(kind.split(":", 1)[1], width, height)
    if kind.startswith("rotated:"):
        _, name, degrees = kind.split(":")
        return rotated(name, float(degrees), width, height)
    table = {
        "flat": lambda: flat(width, height),
        "dots": lambda: dots(width, height),
        "dots4": lambda: dots(width, height, 4),  # pitch 2 gives no FAST corner; 4 is the densest that does
        "checker": lambda: checker(width, height),
        "checker4": lambda: checker(width, height, 4),
        "border": lambda: border_corners(width, height),
        "noise": lambda: noise(width, height),
    }
    if kind not in table:
        raise ValueError(f"unknown image kind {kind!r}")
    return table[kind]()
