# SPDX-License-Identifier: MIT
"""RGB to luma, the integer formula of the RTL's colour-conversion block.

Y = (77 R + 150 G + 29 B + 128) >> 8, i.e. BT.601 weights (0.299, 0.587, 0.114) in 8-bit fixed
point, rounded half up. The weights sum to 256, so Y never exceeds 255.
"""

from __future__ import annotations

import numpy as np

LUMA_R = 77
LUMA_G = 150
LUMA_B = 29
LUMA_SHIFT = 8


def rgb_to_luma(rgb: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8 RGB to (H, W) uint8 luma."""
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(f"expected an (H, W, 3) RGB array, got shape {rgb.shape}")
    c = rgb.astype(np.int32)
    y = (LUMA_R * c[..., 0] + LUMA_G * c[..., 1] + LUMA_B * c[..., 2] + (1 << (LUMA_SHIFT - 1))) >> LUMA_SHIFT
    return y.astype(np.uint8)
