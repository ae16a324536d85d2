# SPDX-License-Identifier: MIT
"""The visual odometry of `orb-accel trajectory-bench`: one frame-to-frame tracker, the same for
every extractor (docs/evaluation.md, "Trajectory").

Per frame: the extractor's features on the left image; their 3D points in the left camera from a
rectified stereo pair (each left feature's best descriptor match among the right image's features
on the same row, within `ROW_PX`, at a disparity of `MIN_DISPARITY` pixels or more, Hamming
distance at most `MAX_HAMMING`, the disparity refined to sub-pixel by block matching as ORB-SLAM
does: depth = f b / disparity) or from a depth image (RGB-D). Each frame
is tracked against the last keyframe: its features matched to the keyframe's features that have a
3D point (brute-force Hamming, cross-checked, at most `MAX_HAMMING`), and the motion from those
3D-2D pairs by RANSAC PnP (OpenCV EPnP, `PNP_PX` pixels, fixed seed) refined on its inliers. A
frame becomes the keyframe when its inliers fall below `KEY_RATIO` of the keyframe's first match's.
A frame with fewer than `MIN_INLIERS` inliers is lost: counted, the motion of the frame before is
assumed (a constant velocity) so that the trajectory goes on and its error shows in the ATE, and
it becomes the keyframe.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import cv2
import numpy as np

ROW_PX = 2.0
MIN_DISPARITY = 1.0
MAX_HAMMING = 64
PNP_PX = 2.0
MIN_INLIERS = 20
KEY_RATIO = 0.5  # a new keyframe below this share of the keyframe's first inlier count
SAD_HALF = 5  # the stereo refinement's 11 x 11 patch
SAD_RANGE = 5  # ... searched 5 pixels either side

# an extractor: greyscale image -> (x, y, descriptors N x 32 uint8)
Extract = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]


@dataclass
class Frame:
    left: np.ndarray
    right: np.ndarray | None = None  # rectified stereo partner, or
    depth: np.ndarray | None = None  # metres, 0 or non-finite where unknown


@dataclass
class Track:
    poses: list[np.ndarray] = field(default_factory=list)  # camera-to-world, 4 x 4
    lost: list[int] = field(default_factory=list)  # frame indices
    inliers: list[int] = field(default_factory=list)  # per frame after the first
    features: list[int] = field(default_factory=list)
    points: list[int] = field(default_factory=list)  # features with a 3D point


def hamming(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(len(a) x len(b)) Hamming distances of 32-byte descriptors."""
    if len(a) == 0 or len(b) == 0:
        return np.zeros((len(a), len(b)), dtype=np.int64)
    x = np.bitwise_xor(a[:, None, :], b[None, :, :])
    return np.unpackbits(x, axis=2).sum(axis=2, dtype=np.int64)


def refine_disparity(left: np.ndarray, right: np.ndarray, lx: np.ndarray, ly: np.ndarray,
                     d0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Sub-pixel disparities (and which are kept) by the sum of absolute differences of a
    (2 SAD_HALF + 1)^2 patch along the row, SAD_RANGE pixels either side of d0, and a parabola through
    the best offset and its neighbours (as ORB-SLAM's stereo matching); a best offset at the end of
    the range, or a parabola's vertex more than a pixel off, drops the point."""
    h, w = left.shape
    r, s = SAD_HALF, SAD_RANGE
    xi, yi = np.rint(lx).astype(np.int64), np.rint(ly).astype(np.int64)
    xr = np.rint(lx - d0).astype(np.int64)
    ok = (yi - r >= 0) & (yi + r < h) & (xi - r >= 0) & (xi + r < w) & (xr - r - s >= 0) & (xr + r + s < w)
    out, keep = d0.astype(np.float64).copy(), np.zeros(len(lx), dtype=bool)
    idx = np.nonzero(ok)[0]
    if len(idx) == 0:
        return out, keep
    off = np.arange(-r, r + 1)
    lp = left[(yi[idx, None, None] + off[None, :, None]), (xi[idx, None, None] + off[None, None, :])].astype(np.int32)
    sad = np.empty((len(idx), 2 * s + 1), dtype=np.int64)
    for j, dx in enumerate(range(-s, s + 1)):
        rp = right[(yi[idx, None, None] + off[None, :, None]), (xr[idx, None, None] + dx + off[None, None, :])]
        sad[:, j] = np.abs(lp - rp.astype(np.int32)).sum(axis=(1, 2))
    best = sad.argmin(axis=1)
    inner = (best > 0) & (best < 2 * s)
    rows = np.arange(len(idx))
    b = np.clip(best, 1, 2 * s - 1)
    d1, d2, d3 = sad[rows, b - 1], sad[rows, b], sad[rows, b + 1]
    den = 2.0 * (d1 + d3 - 2 * d2)
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = np.where(den > 0, (d1 - d3) / den, 0.0)
    good = inner & (np.abs(delta) <= 1.0)
    # the right image's best x is xr + (best - s) + delta: disparity = lx - that
    out[idx] = lx[idx] - (xr[idx] + (best - s) + delta)
    keep[idx] = good
    return out, keep


def stereo_points(left: tuple, right: tuple, k: np.ndarray, baseline: float,
                  images: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """(indices of the left features with a point, their 3D points N x 3 in the left camera); with
    the images, the disparities refined to sub-pixel (refine_disparity)."""
    lx, ly, ld = left
    rx, ry, rd = right
    if len(lx) == 0 or len(rx) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
    dist = hamming(ld, rd)
    disp = lx[:, None] - rx[None, :]
    ok = (np.abs(ly[:, None] - ry[None, :]) <= ROW_PX) & (disp >= MIN_DISPARITY)
    dist = np.where(ok, dist, 1 << 20)
    best = dist.argmin(axis=1)
    good = dist[np.arange(len(lx)), best] <= MAX_HAMMING
    idx = np.nonzero(good)[0]
    d = disp[idx, best[idx]]
    if images is not None:
        d, keep = refine_disparity(images[0], images[1], lx[idx], ly[idx], d)
        idx, d = idx[keep & (d >= MIN_DISPARITY)], d[keep & (d >= MIN_DISPARITY)]
    f, cx, cy = k[0, 0], k[0, 2], k[1, 2]
    z = f * baseline / d
    pts = np.column_stack([(lx[idx] - cx) * z / f, (ly[idx] - cy) * z / f, z])
    return idx, pts


def depth_points(feat: tuple, depth: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    x, y, _ = feat
    h, w = depth.shape
    xi = np.clip(np.rint(x).astype(np.int64), 0, w - 1)
    yi = np.clip(np.rint(y).astype(np.int64), 0, h - 1)
    z = depth[yi, xi] if len(x) else np.zeros(0)
    idx = np.nonzero(np.isfinite(z) & (z > 0.1))[0]
    z = z[idx]
    f, cx, cy = k[0, 0], k[0, 2], k[1, 2]
    return idx, np.column_stack([(x[idx] - cx) * z / f, (y[idx] - cy) * z / f, z])


def cross_matches(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ia, ib) of the cross-checked best matches at most MAX_HAMMING apart."""
    if len(a) == 0 or len(b) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    found = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(a, b)
    pairs = np.array([(m.queryIdx, m.trainIdx) for m in found if m.distance <= MAX_HAMMING], dtype=np.int64)
    if len(pairs) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    return pairs[:, 0], pairs[:, 1]


def _motion(obj: np.ndarray, img: np.ndarray, k: np.ndarray) -> tuple[np.ndarray | None, int]:
    """4 x 4 transform from the previous camera to the current one, and its inlier count."""
    if len(obj) < max(MIN_INLIERS, 6):
        return None, 0
    cv2.setRNGSeed(1)
    ok, rvec, tvec, inl = cv2.solvePnPRansac(obj.astype(np.float64), img.astype(np.float64), k, None,
                                             iterationsCount=300, reprojectionError=PNP_PX, confidence=0.999,
                                             flags=cv2.SOLVEPNP_EPNP)  # fmt: skip
    if not ok or inl is None or len(inl) < MIN_INLIERS:
        return None, 0 if inl is None else len(inl)
    i = inl[:, 0]
    ok, rvec, tvec = cv2.solvePnP(obj[i].astype(np.float64), img[i].astype(np.float64), k, None, rvec, tvec,
                                  useExtrinsicGuess=True, flags=cv2.SOLVEPNP_ITERATIVE)  # fmt: skip
    m = np.eye(4)
    m[:3, :3] = cv2.Rodrigues(rvec)[0]
    m[:3, 3] = tvec[:, 0]
    return m, len(i)


def run(frames: Iterable[Frame], extract: Extract, k: np.ndarray, baseline: float = 0.0,
        start: np.ndarray | None = None) -> Track:  # fmt: skip
    """Track the frames from pose `start` (camera-to-world; identity when None), each against the
    last keyframe."""
    tr = Track()
    key = None  # the keyframe: (features, indices with a point, points, pose, inliers of its first match)
    velocity = np.eye(4)  # the last frame-to-frame motion, camera to camera
    for n, fr in enumerate(frames):
        feat = extract(fr.left)
        if fr.right is not None:
            idx, pts = stereo_points(feat, extract(fr.right), k, baseline, (fr.left, fr.right))
        elif fr.depth is not None:
            idx, pts = depth_points(feat, fr.depth, k)
        else:
            raise ValueError("a frame needs a right image or a depth image")
        tr.features.append(len(feat[0]))
        tr.points.append(len(idx))
        if key is None:
            tr.poses.append(np.eye(4) if start is None else start.copy())
            key = (feat, idx, pts, tr.poses[-1], 0)
            continue
        k_feat, k_idx, k_pts, k_pose, k_first = key
        ia, ib = cross_matches(k_feat[2][k_idx], feat[2])
        img = np.column_stack([feat[0][ib], feat[1][ib]]) if len(ib) else np.zeros((0, 2))
        m, inl = _motion(k_pts[ia], img, k)
        tr.inliers.append(inl)
        if m is None:
            tr.lost.append(n)
            pose = tr.poses[-1] @ np.linalg.inv(velocity)
        else:
            pose = k_pose @ np.linalg.inv(m)
            velocity = np.linalg.inv(pose) @ tr.poses[-1]
        tr.poses.append(pose)
        if k_first == 0 and m is not None:
            key = (k_feat, k_idx, k_pts, k_pose, inl)
        # a new keyframe when the tracking weakens (half the inliers of the keyframe's first match) or is lost
        if m is None or inl < KEY_RATIO * max(key[4], 1):
            key = (feat, idx, pts, pose, 0)
    return tr
