# SPDX-License-Identifier: MIT
"""3x3 non-maximum suppression with a raster-order tie rule.

A corner (score > 0) survives when its score is strictly greater than each of its 8 neighbours
that come earlier in raster order (the row above, and the left neighbour) and greater than or
equal to each neighbour that comes later (the right neighbour and the row below). Of two equal
adjacent corners the earlier one in raster order survives, so a plateau of equal scores keeps a
corner instead of losing all of them (the thesis's strict '>' loses both). Two survivors are never
8-adjacent. Neighbours outside the image count as score 0. The rule is applied once to the score
map (not iterated): a corner suppressed by a neighbour still suppresses its own weaker neighbours.
"""

from __future__ import annotations

import numpy as np

# (dy, dx) of neighbours earlier in raster order: compared with '>'.
EARLIER = ((-1, -1), (-1, 0), (-1, 1), (0, -1))
# later in raster order: compared with '>='.
LATER = ((0, 1), (1, -1), (1, 0), (1, 1))


def nms3x3(score: np.ndarray) -> np.ndarray:
    """Boolean map of the corners that survive suppression."""
    h, w = score.shape
    padded = np.pad(score, 1)
    keep = score > 0
    for offsets, strict in ((EARLIER, True), (LATER, False)):
        for dy, dx in offsets:
            n = padded[1 + dy : 1 + dy + h, 1 + dx : 1 + dx + w]
            keep &= (score > n) if strict else (score >= n)
    return keep
