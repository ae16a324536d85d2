"""Photo sets of the selection research: `tune` (scikit-image's bundled photographs) and `held`
(Debian packages opencv-doc and mate-backgrounds, extracted under $ORB_PHOTO_ROOT, default
build/eval/debian), every photograph centre-cropped to 4:3 and resized to 640x480 (INTER_AREA),
luma by the accelerator's formula."""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import numpy as np
import skimage.data
import skimage.io

from golden_model.images import to_luma

TUNE = ("astronaut", "camera", "coffee", "chelsea", "rocket", "motorcycle_left")
OCV = "usr/share/doc/opencv-doc/examples/data/"
MATE = "usr/share/backgrounds/mate/nature/"
HELD = tuple(OCV + f for f in (
    "aero1.jpg", "aero3.jpg", "aloeL.jpg", "baboon.jpg", "basketball1.png", "board.jpg", "box_in_scene.png",
    "building.jpg", "butterfly.jpg", "fruits.jpg", "graf1.png", "home.jpg", "leuvenA.jpg", "messi5.jpg",
    "rubberwhale1.png", "smarties.png", "squirrel_cls.jpg", "stuff.jpg", "sudoku.png", "left.jpg",
)) + tuple(MATE + f for f in (
    "Aqua.jpg", "Blinds.jpg", "Dune.jpg", "FreshFlower.jpg", "Garden.jpg", "GreenMeadow.jpg", "LadyBird.jpg",
    "RainDrops.jpg", "Storm.jpg", "TwoWings.jpg", "Wood.jpg", "YellowFlower.jpg",
))  # fmt: skip


def fit(img: np.ndarray, w: int = 640, h: int = 480) -> np.ndarray:
    ih, iw = img.shape[:2]
    if iw * h > ih * w:
        cw = ih * w // h
        img = img[:, (iw - cw) // 2 : (iw - cw) // 2 + cw]
    else:
        ch = iw * h // w
        img = img[(ih - ch) // 2 : (ih - ch) // 2 + ch]
    interp = cv2.INTER_AREA if img.shape[1] > w else cv2.INTER_LINEAR
    return cv2.resize(img, (w, h), interpolation=interp)


def load(which: str, w: int = 640, h: int = 480, native: bool = False) -> list[tuple[str, np.ndarray]]:
    out = []
    if which in ("tune", "all"):
        for n in TUNE:
            im = getattr(skimage.data, n)() if n != "motorcycle_left" else skimage.io.imread(Path(skimage.data.__file__).parent / "motorcycle_left.png")
            im = to_luma(im)
            out.append((n, im if native else fit(im, w, h)))
    if which in ("held", "all"):
        root = Path(os.environ.get("ORB_PHOTO_ROOT", "build/eval/debian"))
        for p in HELD:
            im = cv2.imread(str(root / p), cv2.IMREAD_COLOR)
            if im is None:
                raise FileNotFoundError(root / p)
            im = to_luma(cv2.cvtColor(im, cv2.COLOR_BGR2RGB))
            out.append((Path(p).stem, fit(im, w, h)))
    return out


def load_eval() -> list[tuple[str, np.ndarray]]:
    """The project's evaluation photographs (build/eval/photos, `make eval`) at their own sizes, luma
    as the CLI loads them."""
    out = []
    for n in ("astronaut", "camera", "coffee", "chelsea"):
        im = cv2.imread(f"build/eval/photos/{n}.png", cv2.IMREAD_UNCHANGED)
        if im.ndim == 3:
            im = cv2.cvtColor(im, cv2.COLOR_BGR2RGB)
        out.append((n, to_luma(im)))
    return out
