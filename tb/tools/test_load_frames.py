# SPDX-License-Identifier: MIT
"""orb_tools.images.load_frames: the frames `--sim` and `orb-accel sim-server` stream (images and
videos, one size or resized), and its errors."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from golden_model.images import ImageError
from orb_tools.images import load_frames
from orbtb.images import colour_photo


def _video(path: Path, frames: list[np.ndarray]) -> None:
    h, w = frames[0].shape[:2]
    out = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 10, (w, h))
    assert out.isOpened(), "OpenCV cannot write MJPG here"
    for rgb in frames:
        out.write(cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    out.release()


def test_images_and_video(tmp_path: Path) -> None:
    photos = [colour_photo(name, 96, 64) for name in ("astronaut", "coffee", "chelsea")]
    cv2.imwrite(str(tmp_path / "a.png"), cv2.cvtColor(photos[0], cv2.COLOR_RGB2BGR))
    cv2.imwrite(str(tmp_path / "grey.png"), cv2.cvtColor(photos[1], cv2.COLOR_RGB2GRAY))
    _video(tmp_path / "v.avi", photos)
    frames = load_frames([tmp_path / "a.png", tmp_path / "grey.png", tmp_path / "v.avi"])
    assert frames.shape == (5, 64, 96, 3) and frames.dtype == np.uint8
    assert np.array_equal(frames[0], photos[0])  # PNG is lossless; colour order RGB
    assert np.array_equal(frames[1][..., 0], frames[1][..., 2]), "a grey image becomes R = G = B"
    for k in range(3):  # MJPG is lossy: each video frame is close to its photograph, not equal
        assert np.abs(frames[2 + k].astype(int) - photos[k]).mean() < 12, f"video frame {k}"
    assert len(load_frames([tmp_path / "v.avi"], max_frames=2)) == 2
    small = load_frames([tmp_path / "a.png", tmp_path / "v.avi"], size=(48, 32))
    assert small.shape == (4, 32, 48, 3)


def test_errors(tmp_path: Path) -> None:
    cv2.imwrite(str(tmp_path / "a.png"), colour_photo("astronaut", 96, 64))
    cv2.imwrite(str(tmp_path / "b.png"), colour_photo("coffee", 64, 48))
    with pytest.raises(ImageError, match="not 96x64 as the first frame"):
        load_frames([tmp_path / "a.png", tmp_path / "b.png"])
    with pytest.raises(ImageError, match="no such file"):
        load_frames([tmp_path / "missing.png"])
    (tmp_path / "bad.avi").write_bytes(b"not a video")
    with pytest.raises(ImageError, match=r"bad\.avi"):
        load_frames([tmp_path / "bad.avi"])
    with pytest.raises(ImageError, match="1 or more"):
        load_frames([tmp_path / "a.png"], max_frames=0)
