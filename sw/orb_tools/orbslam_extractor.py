# SPDX-License-Identifier: MIT
"""An ORB-SLAM-style extractor (ORB-SLAM2's ORBextractor, from its published description and
source: docs/evaluation.md, "Trajectory"), for the trajectory bench's third column.

- a pyramid of `levels` (8) levels, each the previous one resized by 1 / `factor` (1.2), bilinear;
- per level a quota of the budget: n (1 - f) / (1 - f^levels), times f = 1 / factor per level,
  rounded, the last level the remainder;
- FAST-9 with non-maximum suppression per 30 x 30 cell of the level (each cell window 6 pixels
  wider and higher, so that they overlap), at `ini_threshold` (20) and, in a cell that gives
  nothing, again at `min_threshold` (7), inside a border of 16 pixels;
- the quadtree distribution: nodes split in four until there are as many as the level's quota (or
  none can split), the largest nodes split first at the end, and the keypoint of highest FAST score
  kept per node;
- the orientation by the intensity centroid of the radius-15 disc, and the rBRIEF descriptor with
  OpenCV's learned pattern (the one ORB-SLAM uses) on the level blurred by a 7 x 7 Gaussian of
  sigma 2: OpenCV's ORB.compute with the keypoints' octaves and angles given.

It is not ORB-SLAM's code (none is copied; ORB-SLAM is GPLv3), and it differs where stated: the
levels are resized from the previous level without ORB-SLAM's padded borders.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from golden_model.orientation import PATCH_RADIUS, UMAX

CELL = 30
BORDER = 16  # ORB-SLAM's EDGE_THRESHOLD - 3
HALF_PATCH = PATCH_RADIUS  # 15


@dataclass(frozen=True)
class OrbSlamParams:
    budget: int = 1000
    levels: int = 8
    factor: float = 1.2
    ini_threshold: int = 20
    min_threshold: int = 7


def level_quotas(budget: int, levels: int, factor: float) -> list[int]:
    """Features wanted per level (ORB-SLAM's nFeaturesPerLevel)."""
    f = 1.0 / factor
    per = budget * (1 - f) / (1 - f**levels)
    out, total = [], 0
    for _ in range(levels - 1):
        n = round(per)
        out.append(n)
        total += n
        per *= f
    out.append(max(budget - total, 0))
    return out


def _fast(img: np.ndarray, threshold: int) -> list[cv2.KeyPoint]:
    return list(cv2.FastFeatureDetector_create(threshold, True).detect(img, None))


def cell_keypoints(level: np.ndarray, ini: int, low: int) -> np.ndarray:
    """(N x 3) x, y, score of the level's FAST corners by cell, in level pixels."""
    h, w = level.shape
    min_x, min_y, max_x, max_y = BORDER, BORDER, w - BORDER, h - BORDER
    width, height = max_x - min_x, max_y - min_y
    n_cols, n_rows = max(int(width / CELL), 1), max(int(height / CELL), 1)
    w_cell, h_cell = math.ceil(width / n_cols), math.ceil(height / n_rows)
    pts = []
    for i in range(n_rows):
        y0 = min_y + i * h_cell
        y1 = min(y0 + h_cell + 6, max_y)
        if y0 >= max_y - 3:
            continue
        for j in range(n_cols):
            x0 = min_x + j * w_cell
            x1 = min(x0 + w_cell + 6, max_x)
            if x0 >= max_x - 6:
                continue
            # FAST needs its 3-pixel ring: the window is read 3 pixels wider on each side
            win = level[y0 - 3 : y1 + 3, x0 - 3 : x1 + 3]
            kps = _fast(win, ini) or _fast(win, low)
            for k in kps:
                x, y = k.pt[0] + x0 - 3, k.pt[1] + y0 - 3
                if x0 <= x < x1 and y0 <= y < y1:
                    pts.append((x, y, k.response))
    if not pts:
        return np.zeros((0, 3))
    arr = np.unique(np.array(pts), axis=0)  # the overlaps find a corner twice
    return arr


def distribute(pts: np.ndarray, quota: int, bounds: tuple[float, float, float, float]) -> np.ndarray:
    """ORB-SLAM's quadtree: indices into pts (N x 3: x, y, score) of at most `quota` keypoints."""
    if len(pts) == 0 or quota <= 0:
        return np.zeros(0, dtype=np.int64)
    min_x, max_x, min_y, max_y = bounds
    n_ini = max(round((max_x - min_x) / (max_y - min_y)), 1)
    hx = (max_x - min_x) / n_ini
    # a node: (x0, x1, y0, y1, indices)
    nodes = []
    for i in range(n_ini):
        x0, x1 = min_x + i * hx, min_x + (i + 1) * hx
        sel = np.nonzero((pts[:, 0] >= x0) & ((pts[:, 0] < x1) | (i == n_ini - 1)))[0]
        if len(sel):
            nodes.append((x0, x1, min_y, max_y, sel))

    def split(node: tuple) -> list[tuple]:
        x0, x1, y0, y1, idx = node
        xm, ym = x0 + math.ceil((x1 - x0) / 2), y0 + math.ceil((y1 - y0) / 2)
        out = []
        for a0, a1, b0, b1 in ((x0, xm, y0, ym), (xm, x1, y0, ym), (x0, xm, ym, y1), (xm, x1, ym, y1)):
            px, py = pts[idx, 0], pts[idx, 1]
            sel = idx[(px >= a0) & (px < a1) & (py >= b0) & (py < b1)]
            if len(sel):
                out.append((a0, a1, b0, b1, sel))
        return out

    while True:
        before = len(nodes)
        new_nodes: list[tuple] = []
        expandable = 0
        for node in nodes:
            if len(node[4]) == 1 or (node[1] - node[0]) < 2 or (node[3] - node[2]) < 2:
                new_nodes.append(node)
                continue
            kids = split(node)
            expandable += sum(1 for k in kids if len(k[4]) > 1)
            new_nodes.extend(kids)
        nodes = new_nodes
        if len(nodes) >= quota or len(nodes) == before:
            break
        if len(nodes) + expandable * 3 > quota:
            # the last round: split the most populated nodes first until the quota is reached
            while len(nodes) < quota:
                order = sorted(range(len(nodes)), key=lambda i: len(nodes[i][4]), reverse=True)
                changed = False
                for i in order:
                    node = nodes[i]
                    if len(node[4]) <= 1 or (node[1] - node[0]) < 2 or (node[3] - node[2]) < 2:
                        continue
                    kids = split(node)
                    nodes = nodes[:i] + kids + nodes[i + 1 :]
                    changed = True
                    break
                if not changed:
                    break
            break
    best = [node[4][np.argmax(pts[node[4], 2])] for node in nodes]
    best = np.array(best, dtype=np.int64)
    if len(best) > quota:  # the last split may overshoot by up to three: keep the strongest
        best = best[np.argsort(-pts[best, 2], kind="stable")[:quota]]
    return best


_DISC = None


def _disc() -> tuple[np.ndarray, np.ndarray]:
    global _DISC
    if _DISC is None:
        um = UMAX  # the radius-15 disc's half widths by row, as OpenCV's and ORB-SLAM's
        dy, dx = [], []
        for v in range(-HALF_PATCH, HALF_PATCH + 1):
            for u in range(-int(um[abs(v)]), int(um[abs(v)]) + 1):
                dy.append(v)
                dx.append(u)
        _DISC = (np.array(dx), np.array(dy))
    return _DISC


def ic_angles(level: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Degrees in [0, 360): atan2(m01, m10) of the radius-15 disc about each (rounded) keypoint."""
    dx, dy = _disc()
    pad = np.pad(level.astype(np.float64), HALF_PATCH, mode="edge")
    xi = np.rint(x).astype(np.int64) + HALF_PATCH
    yi = np.rint(y).astype(np.int64) + HALF_PATCH
    vals = pad[yi[:, None] + dy[None, :], xi[:, None] + dx[None, :]]
    m10 = (vals * dx[None, :]).sum(axis=1)
    m01 = (vals * dy[None, :]).sum(axis=1)
    return np.degrees(np.arctan2(m01, m10)) % 360.0


def extract(img: np.ndarray, p: OrbSlamParams = OrbSlamParams()) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, y) at full resolution and descriptors (N x 32 uint8) of about p.budget keypoints."""
    quotas = level_quotas(p.budget, p.levels, p.factor)
    kps: list[cv2.KeyPoint] = []
    level = img
    for k in range(p.levels):
        if k:
            h, w = img.shape
            size = (round(w / p.factor**k), round(h / p.factor**k))
            level = cv2.resize(level, size, interpolation=cv2.INTER_LINEAR)
        lh, lw = level.shape
        if min(lh, lw) < 2 * BORDER + 8:
            break
        pts = cell_keypoints(level, p.ini_threshold, p.min_threshold)
        keep = distribute(pts, quotas[k], (BORDER, lw - BORDER, BORDER, lh - BORDER))
        if not len(keep):
            continue
        sel = pts[keep]
        ang = ic_angles(level, sel[:, 0], sel[:, 1])
        s = p.factor**k
        for (x, y, r), a in zip(sel, ang, strict=True):
            kps.append(cv2.KeyPoint(float(x * s), float(y * s), 31.0 * s, float(a), float(r), k))
    if not kps:
        return np.zeros(0), np.zeros(0), np.zeros((0, 32), np.uint8)
    orb = cv2.ORB_create(nfeatures=max(p.budget, 1), scaleFactor=p.factor, nlevels=p.levels, edgeThreshold=BORDER,
                         patchSize=31)  # fmt: skip
    kept, desc = orb.compute(img, kps)
    if desc is None:
        return np.zeros(0), np.zeros(0), np.zeros((0, 32), np.uint8)
    xy = np.array([k.pt for k in kept], dtype=np.float64).reshape(-1, 2)
    return xy[:, 0], xy[:, 1], desc
