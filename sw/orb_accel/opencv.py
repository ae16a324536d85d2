# SPDX-License-Identifier: MIT
"""A frame as OpenCV objects, for hosts that have OpenCV (the board does not need this module):

    keypoints, descriptors = to_cv2(frame)
    matches = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(descriptors, other_descriptors)

Keypoints in the frame's order (scale, row, column): pt = the centre in full-resolution pixels,
size = 31 r^octave (r the pyramid step: 2 for 2:1, 5/4 for 5:4), angle in degrees (-1 in fast
mode), response = FAST score, octave = scale.
Descriptors: (N, 32) uint8 in OpenCV's ORB byte and bit order (None in fast mode, as OpenCV's
compute gives for no descriptors).
"""

from __future__ import annotations

import numpy as np

from .driver import Frame


def to_cv2(frame: Frame) -> tuple[list, np.ndarray | None]:
    """(list of cv2.KeyPoint, descriptors) of a frame read by orb_accel.OrbAccel."""
    import cv2  # host only: the one module of orb_accel that uses OpenCV

    k = frame.keypoint_arrays()
    keypoints = [
        cv2.KeyPoint(float(x), float(y), float(s), float(a), float(r), int(o))
        for x, y, s, a, r, o in zip(k["x"], k["y"], k["size"], k["angle"], k["response"], k["octave"], strict=True)
    ]
    descriptors = np.ascontiguousarray(frame.descriptors, dtype=np.uint8) if frame.mode == "orb" else None
    return keypoints, descriptors
