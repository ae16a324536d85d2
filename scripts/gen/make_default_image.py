#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Make the bundled default 640x480 image from scikit-image's `coffee` photograph.

Source: skimage.data.coffee(), "courtesy of Pikolo Espresso Bar", CC0 by the photographer
(Rachel Michetti). The 600x400 photograph is centre-cropped to 4:3 (533x400) and resized to
640x480 with bicubic interpolation, then written as an RGB PNG.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import skimage.data

OUT = Path(__file__).resolve().parents[1] / "golden_model" / "data" / "default_640x480.png"


def main() -> None:
    rgb = skimage.data.coffee()
    h, w = rgb.shape[:2]
    cw = h * 4 // 3
    x0 = (w - cw) // 2
    crop = rgb[:, x0 : x0 + cw]
    img = cv2.resize(crop, (640, 480), interpolation=cv2.INTER_CUBIC)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(OUT), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
