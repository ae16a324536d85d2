# SPDX-License-Identifier: MIT
"""The CLI's PNG feature overlay (`render_overlay`, `draw_overlay`): circles centred on the
full-resolution feature position with radius 4 * 2^scale; the tick points along the sector's
centre angle (clockwise on screen from +x, as the sectors are defined). Fast-mode features (no
sector) get a circle only. OpenCV's anti-aliasing is not hardware-friendly: this one is for files
only; the HDMI overlay's exact rules are golden_model.overlay.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from golden_model.features import Features
from golden_model.overlay import SCALE_COLOURS


def render_overlay(image: np.ndarray, features: Features) -> np.ndarray:
    """RGB uint8 image with the features drawn on it (grey input is expanded to RGB)."""
    canvas = np.repeat(image[..., None], 3, axis=2) if image.ndim == 2 else image[..., :3].copy()
    canvas = np.ascontiguousarray(canvas)
    x0, y0 = features.full_res()
    angles = np.radians(features.angle_deg())
    radius = 4.0 * features.level_factor()  # 4 full-resolution pixels at scale 0, r^s times that above
    for i in range(len(features)):
        s = int(features.scale[i])
        colour = SCALE_COLOURS[s % len(SCALE_COLOURS)]
        r = round(float(radius[i]))
        cx, cy = round(float(x0[i])), round(float(y0[i]))
        cv2.circle(canvas, (cx, cy), r, colour, 1, cv2.LINE_AA)
        if not np.isnan(angles[i]):
            tip = (round(cx + r * np.cos(angles[i])), round(cy + r * np.sin(angles[i])))
            cv2.line(canvas, (cx, cy), tip, colour, 1, cv2.LINE_AA)
    return canvas


def draw_overlay(image: np.ndarray, features: Features, path: Path) -> None:
    rgb = render_overlay(image, features)
    if not cv2.imwrite(str(path), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)):
        raise OSError(f"{path}: could not write the overlay image")
