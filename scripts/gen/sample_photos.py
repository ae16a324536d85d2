#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write scikit-image's bundled evaluation photographs as PNG files (no download needed).

astronaut (NASA, public domain), camera (CC0), coffee (CC0, Rachel Michetti), chelsea (CC0,
Stefan van der Walt): the set every evaluation in docs/evaluation.md uses. Colour images are
written in colour; the CLI converts them to luma with the accelerator's formula.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import skimage.data

EVALUATION_PHOTOS = ("astronaut", "camera", "coffee", "chelsea")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("out_dir", type=Path)
    args = ap.parse_args()
    args.out_dir.mkdir(parents=True, exist_ok=True)
    for name in EVALUATION_PHOTOS:
        img = getattr(skimage.data, name)()
        if img.ndim == 3:
            img = cv2.cvtColor(img, cv2.COLOR_RGB2BGR)
        path = args.out_dir / f"{name}.png"
        cv2.imwrite(str(path), img)
        print(path)


if __name__ == "__main__":
    main()
