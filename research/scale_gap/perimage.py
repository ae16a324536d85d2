"""Per-photograph pooled scores (full benchmark) of named variants and cv-default at their budget."""
import sys
import cv2, numpy as np
from orb_tools import scale_bench as sb
from . import lib
from .variants import VARIANTS
for name in sys.argv[1:]:
    o = VARIANTS[name]
    out = []
    for p in lib.PHOTOS:
        img = cv2.imread(str(p), 0)
        ref = lib.extract(img, o); cref = lib.extract_cv_default(img, len(ref))
        t, c = np.zeros(5, np.int64), np.zeros(5, np.int64)
        for a in sb.ROTATIONS:
            for s in sb.SCALE_CHANGES:
                for pp in sb.PERSPECTIVES:
                    hm = sb.homography(img.shape, a, s, pp); w = sb.warp(img, hm)
                    t += sb.pair_counts(ref, lib.extract(w, o), hm, img.shape)
                    c += sb.pair_counts(cref, lib.extract_cv_default(w, len(ref)), hm, img.shape)
        out.append(f"{p.stem} {sb.score(t):.2f} vs {sb.score(c):.2f} (n {len(ref)}/{len(cref)})")
    print(name, " | ".join(out), flush=True)
