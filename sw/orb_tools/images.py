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


VIDEO_SUFFIXES = (".mp4", ".avi", ".mkv", ".mov", ".webm", ".m4v", ".mpg", ".mpeg")


def _video_frames(path: Path, max_frames: int) -> list[np.ndarray]:
    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        raise ImageError(f"{path}: not a video OpenCV can read")
    frames = []
    try:
        while len(frames) < max_frames:
            ok, bgr = cap.read()
            if not ok:
                break
            frames.append(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB))
    finally:
        cap.release()
    if not frames:
        raise ImageError(f"{path}: a video without frames")
    return frames


def load_frames(paths: list[Path], size: tuple[int, int] | None = None, max_frames: int = 50) -> np.ndarray:
    """(N, H, W, 3) uint8 RGB frames of images and videos (at most `max_frames` of each video),
    resized to `size` (W, H) when given; without it every frame must have the first one's size."""
    if max_frames < 1:
        raise ImageError(f"at most {max_frames} frames per video: must be 1 or more")
    frames: list[np.ndarray] = []
    for path in paths:
        if not path.exists():
            raise ImageError(f"{path}: no such file")
        if path.suffix.lower() in VIDEO_SUFFIXES:
            got = _video_frames(path, max_frames)
        else:
            img = load_rgb_or_grey(path)
            got = [np.repeat(img[..., None], 3, axis=2) if img.ndim == 2 else img[..., :3]]
        for img in got:
            if size is not None:
                img = cv2.resize(img, size, interpolation=cv2.INTER_AREA)
            elif frames and img.shape != frames[0].shape:
                h, w = frames[0].shape[:2]
                raise ImageError(
                    f"{path}: {img.shape[1]}x{img.shape[0]}, not {w}x{h} as the first frame (use a size option)"
                )
            frames.append(np.ascontiguousarray(img, dtype=np.uint8))
    return np.stack(frames)
