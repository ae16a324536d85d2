# SPDX-License-Identifier: MIT
"""`orb-accel density-bench`: where the fabric's grid selection puts its features, dense and sparse scenes.

Frames: each PHOTO (colour or grey) fitted to each --sizes entry as `orb_tools.eval_photos.fit` does
(centre crop to the aspect ratio, INTER_AREA shrinking, INTER_CUBIC enlarging), to 8-bit luma by the
accelerator's formula, then for each --contrast c: luma' = rint(128 + (luma - 128) c) clipped to
0..255 (np.rint: halves to even; c = 0 is a flat grey frame).

Extractors per frame:
- `ours`: the golden model with the grid selection (golden_model.pipeline: candidates, then
  golden_model.select.select_grid, which is what extract does): budget
  golden_model.config.recommended_budget of the size and a grid of 8 x 6 cells unless --budget /
  --cells, threshold 20 and low threshold 14, RECOMMENDED_SCALES levels of 5:4 unless --scales / --step,
  64 sectors; a level must be at least 37x37 pixels, else the command refuses;
- `cv-500`: cv2.ORB_create() with its defaults (nfeatures 500);
- `cv-ours`: cv2.ORB_create(nfeatures = our count on that frame) (nothing when ours is empty).

Per frame and extractor: the features and the budget (ours: the configured budget; cv-500: 500;
cv-ours: our count); features per level (OpenCV: per octave) and, for ours, how many levels hold
fewer than their share of the budget (golden_model.select.level_budgets); coverage, the share of an
8x6 grid over the frame whose cells hold at least one feature (full-resolution positions); the share
of the grid's 6 rows (bands of a sixth of the height) with at least one feature; the *corner cells*,
the 8x6 cells that hold at least one candidate of the model (every NMS survivor inside the
descriptor border at threshold 20 or at the low threshold, any level, at its full-resolution
position: golden_model.pipeline.candidates with the same configuration), and how many of those hold
no feature of the extractor (the goal for ours is 0); and whether the frame is empty although the
model has candidates (the goal: never).

Writes density_bench.csv (one row per photo x size x contrast x extractor) and
density_bench_summary.json (settings; per extractor x size x contrast: means over the photographs,
the corner cells left empty in all, the frames with any, the empty frames; and per photograph the
candidate count at each size and contrast).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import cv2
import numpy as np

from golden_model.features import Features
from golden_model.images import to_luma
from golden_model.pipeline import candidates
from golden_model.select import level_budgets, select_grid

from .eval_photos import fit
from .images import load_rgb_or_grey
from .track_bench import MAX_WORKERS, Settings, occupancy, pool_rows, write_csv

EXTRACTORS = ("ours", "cv-500", "cv-ours")
OPENCV_DEFAULT_FEATURES = 500
SIZES = ((640, 480), (1280, 720), (1920, 1080))
CONTRASTS = (1.0, 0.25)
CSV_COLUMNS = ("photo", "size", "contrast", "extractor", "budget", "features", "per_level", "unfilled_levels",
               "coverage", "row_share", "candidates", "corner_cells", "corner_cells_empty",
               "empty_with_candidates")  # fmt: skip


def apply_contrast(luma: np.ndarray, c: float) -> np.ndarray:
    """rint(128 + (luma - 128) c) clipped to 0..255."""
    out = np.rint(128.0 + (luma.astype(np.float64) - 128.0) * c)
    return np.clip(out, 0, 255).astype(np.uint8)


@dataclass(frozen=True)
class Found:
    """One extractor's features on a frame: full-resolution positions and levels."""

    x: np.ndarray
    y: np.ndarray
    level: np.ndarray
    budget: int
    levels: int
    level_budget: tuple[int, ...] = ()

    def __len__(self) -> int:
        return len(self.x)


def _from_features(f: Features, budget: int, levels: int, level_budget: Sequence[int]) -> Found:
    x0, y0 = f.full_res()
    return Found(x0, y0, f.scale.astype(np.int64), budget, levels, tuple(level_budget))


def _opencv(img: np.ndarray, nfeatures: int) -> Found:
    if nfeatures <= 0:
        return Found(np.zeros(0), np.zeros(0), np.zeros(0, np.int64), 0, 8)
    orb = cv2.ORB_create(nfeatures=nfeatures)
    kps = orb.detect(img, None)
    pts = np.array([kp.pt for kp in kps], dtype=np.float64).reshape(-1, 2)
    level = np.array([kp.octave for kp in kps], dtype=np.int64)
    return Found(pts[:, 0], pts[:, 1], level, nfeatures, orb.getNLevels())


def frame_rows(photo: str, img: np.ndarray, contrast: float, settings: Settings) -> list[dict]:
    """The CSV rows of one frame (module docstring)."""
    h, w = img.shape
    cfg = settings.config(w, h)
    cands = candidates(img, cfg)
    ours = select_grid(cands, cfg)
    budgets = level_budgets(cfg.budget, cfg.step, cfg.scales)
    found = {"ours": _from_features(ours, cfg.budget, cfg.scales, budgets),
             "cv-500": _opencv(img, OPENCV_DEFAULT_FEATURES), "cv-ours": _opencv(img, len(ours))}  # fmt: skip
    cx, cy = cands.full_res()
    corner = occupancy(cx, cy, w, h)
    rows = []
    for name in EXTRACTORS:
        f = found[name]
        occ = occupancy(f.x, f.y, w, h)
        per_level = np.bincount(f.level, minlength=f.levels)[: max(f.levels, 1)]
        unfilled = int((per_level < np.array(f.level_budget)).sum()) if f.level_budget else 0
        rows.append({"photo": photo, "size": f"{w}x{h}", "contrast": contrast, "extractor": name, "budget": f.budget,
                     "features": len(f), "per_level": "/".join(str(int(n)) for n in per_level),
                     "unfilled_levels": unfilled, "coverage": round(float(occ.mean()), 4),
                     "row_share": round(float(occ.any(axis=1).mean()), 4), "candidates": len(cands),
                     "corner_cells": int(corner.sum()), "corner_cells_empty": int((corner & ~occ).sum()),
                     "empty_with_candidates": len(f) == 0 and len(cands) > 0})  # fmt: skip
    return rows


@dataclass(frozen=True)
class Job:
    """One photograph's frames (what a worker process receives)."""

    name: str
    path: Path
    sizes: tuple[tuple[int, int], ...]
    contrasts: tuple[float, ...]
    settings: Settings = field(default_factory=Settings)


def run_job(job: Job) -> list[dict]:
    original = load_rgb_or_grey(job.path)
    rows = []
    for w, h in job.sizes:
        luma = to_luma(fit(original, w, h))
        for c in job.contrasts:
            rows += frame_rows(job.name, apply_contrast(luma, c), c, job.settings)
    return rows


def make_jobs(paths: Sequence[Path], sizes: Sequence[tuple[int, int]], contrasts: Sequence[float],
              settings: Settings) -> list[Job]:  # fmt: skip
    stems = [p.stem for p in paths]
    names = [s if stems.count(s) == 1 else f"{s}-{i}" for i, s in enumerate(stems)]
    return [Job(n, p, tuple(sizes), tuple(contrasts), settings) for n, p in zip(names, paths, strict=True)]


def run(jobs: Sequence[Job], workers: int = MAX_WORKERS, progress: Callable[[str], None] | None = None) -> list[dict]:
    """Every photograph's rows, in the order of `jobs` (at most MAX_WORKERS processes over photographs)."""
    return pool_rows(run_job, jobs, [j.name for j in jobs], workers, progress)


def _mean(rows: Sequence[dict], key: str) -> float:
    return round(float(np.mean([r[key] for r in rows])), 4) if rows else math.nan


def _area(size: str) -> int:
    w, _, h = size.partition("x")
    return int(w) * int(h)


def summarise(rows: Sequence[dict]) -> list[dict]:
    """One row per extractor x size x contrast (module docstring)."""
    out = []
    keys = list(dict.fromkeys((r["extractor"], r["size"], r["contrast"]) for r in rows))
    for ext, size, c in sorted(keys, key=lambda k: (EXTRACTORS.index(k[0]), _area(k[1]), -k[2])):
        sel = [r for r in rows if (r["extractor"], r["size"], r["contrast"]) == (ext, size, c)]
        out.append({"extractor": ext, "size": size, "contrast": c, "frames": len(sel),
                    "features": _mean(sel, "features"), "min_features": min(r["features"] for r in sel),
                    "coverage": _mean(sel, "coverage"), "row_share": _mean(sel, "row_share"),
                    "corner_cells": sum(r["corner_cells"] for r in sel),
                    "corner_cells_empty": sum(r["corner_cells_empty"] for r in sel),
                    "frames_with_empty_corner_cells": sum(r["corner_cells_empty"] > 0 for r in sel),
                    "empty_with_candidates": sum(bool(r["empty_with_candidates"]) for r in sel),
                    "unfilled_levels": sum(r["unfilled_levels"] for r in sel)})  # fmt: skip
    return out


def candidates_by_photo(rows: Sequence[dict]) -> dict[str, dict[str, int]]:
    out: dict[str, dict[str, int]] = {}
    for r in rows:
        if r["extractor"] == "ours":
            out.setdefault(r["photo"], {})[f"{r['size']} c{r['contrast']:g}"] = r["candidates"]
    return out


def write_outputs(out_dir: Path, rows: Sequence[dict], settings: Settings) -> list[dict]:
    """density_bench.csv and density_bench_summary.json; the summary."""
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(out_dir / "density_bench.csv", rows, CSV_COLUMNS)
    summary = summarise(rows)
    doc = {"settings": asdict(settings), "summary": summary, "candidates": candidates_by_photo(rows)}
    (out_dir / "density_bench_summary.json").write_text(json.dumps(doc, indent=1) + "\n")
    return summary


def table(summary: Sequence[dict]) -> str:
    keys = ("frames", "features", "min_features", "coverage", "row_share", "corner_cells", "corner_cells_empty",
            "frames_with_empty_corner_cells", "empty_with_candidates", "unfilled_levels")  # fmt: skip
    lines = ["| extractor | size | contrast | " + " | ".join(keys) + " |", "|---|---|---|" + "---|" * len(keys)]
    for r in summary:
        lines.append(f"| {r['extractor']} | {r['size']} | {r['contrast']:g} | " + " | ".join(str(r[k]) for k in keys)
                     + " |")  # fmt: skip
    return "\n".join(lines)
