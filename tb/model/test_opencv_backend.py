# SPDX-License-Identifier: MIT
"""The OpenCV backend: same settings as the accelerator configuration, same Features form."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from golden_model.config import Config
from golden_model.fast import fast_score
from golden_model.pipeline import detect
from golden_model.scaler import pyramid
from orb_tools.images import sample_photographs
from orb_tools.opencv_backend import angle_to_sector, extract_opencv, fast_keypoints, orb_detector, sad_score_at


@pytest.fixture(scope="module")
def photos() -> dict[str, np.ndarray]:
    return sample_photographs()


def _cfg(img: np.ndarray, **kw: object) -> Config:
    h, w = img.shape
    return Config(width=w, height=h, **kw)  # type: ignore[arg-type]


def test_sad_score_matches_fast_score_at_corners(photos: dict[str, np.ndarray]) -> None:
    img = photos["camera"]
    score = fast_score(img, 20)
    ys, xs = np.nonzero(score)
    assert len(xs) > 1000
    np.testing.assert_array_equal(sad_score_at(img, xs, ys), score[ys, xs])


def test_sad_score_is_zero_near_the_border() -> None:
    img = np.full((64, 64), 100, dtype=np.uint8)
    img[::2] = 200
    assert sad_score_at(img, np.array([2, 3, 60, 61]), np.array([10, 10, 10, 10])).tolist()[::3] == [0, 0]
    assert sad_score_at(img, np.array([3]), np.array([3]))[0] > 0


def test_angle_to_sector_rounds_to_centred_sectors() -> None:
    angles = np.array([0.0, 5.62, 5.63, 354.38, 354.37, 359.99, 90.0, 185.0])
    assert angle_to_sector(angles, 32).tolist() == [0, 0, 1, 0, 31, 0, 8, 16]
    assert angle_to_sector(np.array([11.2, 11.3, 348.8]), 16).tolist() == [0, 1, 0]


def test_fast_mode_is_opencv_fast_on_our_pyramid(photos: dict[str, np.ndarray]) -> None:
    img = photos["astronaut"]
    cfg = _cfg(img, scales=2, threshold=25, mode="fast")
    feats = extract_opencv(img, cfg)
    assert feats.descriptor.shape == (len(feats), 0)
    assert (feats.sector == -1).all() and feats.sectors_total == cfg.sectors
    assert feats == feats.sorted()
    for s, level in enumerate(pyramid(img, 2)):
        xs, ys = fast_keypoints(level, 25, nonmax=True)
        at = feats.scale == s
        assert sorted(zip(feats.y[at].tolist(), feats.x[at].tolist(), strict=True)) == sorted(
            zip(ys.tolist(), xs.tolist(), strict=True)
        )
        np.testing.assert_array_equal(feats.score[at], sad_score_at(level, feats.x[at], feats.y[at]))


def test_fast_mode_is_close_to_the_model(photos: dict[str, np.ndarray]) -> None:
    """Same segment test; only the NMS differs (ours compares SAD scores, OpenCV its own)."""
    img = photos["coffee"]
    ours = detect(img, 20)[0]
    theirs = extract_opencv(img, _cfg(img, threshold=20, mode="fast"))
    assert 0.9 < len(theirs) / len(ours) < 1.1


def test_orb_mode_reports_opencv_orb(photos: dict[str, np.ndarray]) -> None:
    img = photos["astronaut"]
    cfg = _cfg(img, scales=3, sectors=32, threshold=20)
    feats = extract_opencv(img, cfg)
    kps, desc = orb_detector(cfg).detectAndCompute(img, None)
    assert len(feats) == len(kps) > 1000
    assert feats.descriptor.shape == (len(feats), 32) and feats.descriptor.dtype == np.uint8
    assert set(np.unique(feats.scale).tolist()) == {0, 1, 2}
    assert feats.sectors_total == 32 and ((feats.sector >= 0) & (feats.sector < 32)).all()
    # Each keypoint is found again: level position * 2^octave == OpenCV's pt, and its descriptor.
    full = zip((feats.x << feats.scale).tolist(), (feats.y << feats.scale).tolist(), strict=True)
    by_pos = {(int(s), x, y): i for i, (s, (x, y)) in enumerate(zip(feats.scale, full, strict=True))}
    for k, kp in enumerate(kps):
        i = by_pos[(kp.octave, int(kp.pt[0]), int(kp.pt[1]))]
        assert kp.pt == (float(int(kp.pt[0])), float(int(kp.pt[1])))
        assert feats.sector[i] == angle_to_sector(np.array([kp.angle]), 32)[0]
        np.testing.assert_array_equal(feats.descriptor[i], desc[k])
    levels = pyramid(img, 3)
    for s in range(3):
        at = feats.scale == s
        h, w = levels[s].shape
        assert (feats.x[at] >= 31).all() and (feats.x[at] < w - 31).all() and (feats.y[at] < h - 31).all()


def test_orb_descriptors_match_across_a_rotation(photos: dict[str, np.ndarray]) -> None:
    img = np.ascontiguousarray(photos["camera"])
    cfg = _cfg(img, threshold=20)
    a = extract_opencv(img, cfg)
    b = extract_opencv(np.ascontiguousarray(np.rot90(img)), cfg)
    matches = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(a.descriptor, b.descriptor)
    assert len(matches) > 0.9 * len(a)


def test_empty_image_gives_no_features() -> None:
    img = np.zeros((64, 64), dtype=np.uint8)
    for mode in ("orb", "fast"):
        feats = extract_opencv(img, _cfg(img, mode=mode))
        assert len(feats) == 0
        assert feats.descriptor.shape == (0, 32 if mode == "orb" else 0)
