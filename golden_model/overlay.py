# SPDX-License-Identifier: MIT
"""The HDMI feature overlay (`render_marker_overlay`, `marker_schedule`): the exact rules of
docs/spec.md section 13, which hdl/output/orb_overlay.vhd implements bit for bit: a per-block,
per-scale marker bitmap drawn as nested one-pixel square outlines, and which feature frame each
video frame shows. (The CLI's anti-aliased PNG drawing is orb_tools.drawing.)
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from .features import Features

# RGB colours per scale: green, cyan, magenta, yellow, orange, blue, red, white (the HDMI markers
# and the CLI's PNG).
SCALE_COLOURS = ((0, 255, 0), (0, 220, 255), (255, 0, 255), (255, 220, 0), (255, 128, 0), (64, 128, 255),
                 (255, 48, 48), (255, 255, 255))  # fmt: skip

# ------------------------------------------------------------------------------------------------
# Marker overlay of the HDMI output (docs/spec.md section 13; RTL: hdl/output/orb_overlay.vhd)

MARKER_BLOCK_LOG2 = 3  # default block size 8 x 8
MARKER_BLOCK_LOG2_RANGE = (2, 5)
MARKER_MAX_SCALES = 8


def marker_block_log2(scales: int) -> int:
    """The block size the simulations and board builds use for ``scales`` scales: 8x8 (the default)
    when its rings fit, else the smallest block with one ring per scale (16x16 for 5 to 8 scales)."""
    b = MARKER_BLOCK_LOG2
    while (1 << b) < 2 * scales:
        b += 1
    return b


def check_marker_config(scales: int, block_log2: int) -> None:
    """Refuse the block sizes and scale counts the RTL's generics refuse (spec 13.1)."""
    lo, hi = MARKER_BLOCK_LOG2_RANGE
    if not lo <= block_log2 <= hi:
        raise ValueError(f"block_log2 {block_log2} outside {lo}..{hi}")
    if not 1 <= scales <= MARKER_MAX_SCALES:
        raise ValueError(f"scales {scales} outside 1..{MARKER_MAX_SCALES}")
    if (1 << block_log2) < 2 * scales:
        raise ValueError(f"block size {1 << block_log2} too small for {scales} nested scale rings (needs 2 * scales)")


def marker_bitmap(features: Features, width: int, height: int, scales: int = 4,
                  block_log2: int = MARKER_BLOCK_LOG2) -> np.ndarray:  # fmt: skip
    """(blocks_y, blocks_x, scales) bool: block (bx, by) holds a feature of scale s (spec 13.1).

    A feature of scale s at (x, y) marks, at its scale, the block that holds its exact
    full-resolution centre (x + 0.5) r^s - 0.5, r = num / den the features' pyramid step
    (``features.step``): in integers, bx = ((2x + 1) num^s - den^s) >> (1 + s log2(den) + b), likewise
    by, b = block_log2. For the 2:1 pyramid this is (x >> (b - s), y >> (b - s)), the block holding
    the pixel's whole footprint. Features with s >= scales, or whose block lies outside the
    ceil(W / B) x ceil(H / B) grid, are ignored. The bitmap is an OR over the features, so their
    order and repetitions do not matter.
    """
    check_marker_config(scales, block_log2)
    blocks_x, blocks_y = -(-width >> block_log2), -(-height >> block_log2)
    s = features.scale.astype(np.int64)
    keep = (s >= 0) & (s < scales) & (features.x >= 0) & (features.y >= 0)
    s = s[keep]
    num, den = features.step
    den_log2 = den.bit_length() - 1
    if den != 1 << den_log2:
        raise ValueError(f"pyramid step {num}:{den}: the denominator must be a power of two")
    num_pow = np.array([num**k for k in range(scales)], dtype=np.int64)[s]
    shift = 1 + s * den_log2 + block_log2
    bx = ((2 * features.x[keep].astype(np.int64) + 1) * num_pow - (1 << (s * den_log2))) >> shift
    by = ((2 * features.y[keep].astype(np.int64) + 1) * num_pow - (1 << (s * den_log2))) >> shift
    inside = (bx < blocks_x) & (by < blocks_y)
    marks = np.zeros((blocks_y, blocks_x, scales), dtype=bool)
    marks[by[inside], bx[inside], s[inside]] = True
    return marks


def marker_rings(width: int, height: int, block_log2: int = MARKER_BLOCK_LOG2) -> np.ndarray:
    """(height, width) ring index of every pixel in its block: the distance to the nearest block
    edge, min(u, B-1-u, v, B-1-v) with u = x mod B, v = y mod B (spec 13.2)."""
    last = (1 << block_log2) - 1
    u = np.arange(width) & last
    v = np.arange(height) & last
    ru = np.minimum(u, last - u)
    rv = np.minimum(v, last - v)
    return np.minimum(rv[:, None], ru[None, :])


def render_marker_overlay(rgb: np.ndarray, features: Features, scales: int = 4,
                          block_log2: int = MARKER_BLOCK_LOG2) -> np.ndarray:  # fmt: skip
    """The HDMI overlay (spec 13.2): an (H, W, 3) uint8 RGB frame with the features' block markers.

    Scale s of a marked block is drawn as the one-pixel outline of the square inset s pixels from
    the block's edge (ring s) in SCALE_COLOURS[s]; rings are disjoint, so every scale of a block
    shows and the result does not depend on the order of the features. All other pixels pass
    unchanged. Blocks cut by the right or bottom frame edge keep their nominal B x B rings.
    """
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.dtype != np.uint8:
        raise ValueError(f"expected an (H, W, 3) uint8 RGB frame, got {rgb.dtype} with shape {rgb.shape}")
    height, width = rgb.shape[:2]
    marks = marker_bitmap(features, width, height, scales, block_log2)
    ring = marker_rings(width, height, block_log2)
    by = (np.arange(height) >> block_log2)[:, None]
    bx = (np.arange(width) >> block_log2)[None, :]
    on_ring = ring < scales
    hit = on_ring & marks[by, bx, np.minimum(ring, scales - 1)]
    colours = np.array(SCALE_COLOURS[:scales], dtype=np.uint8)
    out = rgb.copy()
    out[hit] = colours[ring[hit]]
    return out


def marker_schedule(events: Iterable[str]) -> list[int | None]:
    """Which feature frame each video frame shows (spec 13.3).

    `events` lists, in the order the overlay accepts them, "sof" (a video start-of-frame beat),
    "feature" (a feature beat) and "eof" (a feature end-of-frame beat); on one clock edge a "sof"
    comes before the feature stream's beat. Feature frames are numbered from 0 in the order of
    their end-of-frame beats (discarded ones included). The result has one entry per "sof": the
    number of the feature frame that video frame shows, or None (markers of none).
    """
    waiting: int | None = None  # a complete feature frame held in the fill bank
    dropping = False  # the feature frame in progress began while one was waiting: discarded whole
    frame = 0  # number of the feature frame in progress
    shown: list[int | None] = []
    for event in events:
        if event == "sof":
            shown.append(waiting)
            waiting = None
        elif event == "feature":
            if waiting is not None:
                dropping = True
        elif event == "eof":
            if waiting is None and not dropping:
                waiting = frame
            dropping = False
            frame += 1
        else:
            raise ValueError(f"unknown overlay event {event!r}")
    return shown
