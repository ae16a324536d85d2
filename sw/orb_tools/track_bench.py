# SPDX-License-Identifier: MIT
"""`orb-accel track-bench`: frame-to-frame tracking with the fabric's grid selection against OpenCV ORB.

Clips. An INPUT that is a video (a file cv2.VideoCapture reads, by suffix: .avi, .mp4, ...) gives its
first --frames frames; one that is a photograph gives a synthetic clip of a hand-held camera over it
(`camera_clip`): per frame t, with s = t / 29 (the motion's time base is a 30-frame cycle whatever
--frames is) and six phases p0..p5 drawn uniformly from [0, 2 pi) by a generator seeded with
(--seed, CRC-32 of the input's name):

    zoom  = 1 + 0.25 sin(2 pi 0.7 s + p0)                    roll = 8 deg sin(2 pi 0.5 s + p1)
    pan x = 0.18 W_photo sin(2 pi 0.6 s + p2)                pan y = 0.15 H_photo sin(2 pi 0.8 s + p3)
    keystone (h20, h21) = 2e-4 (sin(2 pi s + p4), cos(2 pi s + p5))

about the photograph's centre, at a view of 0.55 min(W_photo / W, H_photo / H) / zoom photograph pixels
per frame pixel (cv2.warpPerspective, bilinear, reflected border), plus Gaussian sensor noise of
sigma 2 grey levels, rounded and clipped to 0..255. A photograph so large that the widest view
(zoom 0.75) would sample it coarser than 1:1 is first reduced with cv2.INTER_AREA until it does not
(the camera integrates; no aliasing). Every frame is 8-bit luma by the accelerator's formula
(golden_model.images.to_luma), a video's frames fitted to --size as `orb_tools.eval_photos.fit` does
(centre crop to the aspect ratio, INTER_AREA shrinking, INTER_CUBIC enlarging).

Extractors, per frame: `ours`, the golden model with the fabric's grid selection (golden_model.pipeline.
extract, selection "grid": --budget features, default golden_model.config.recommended_budget of the
size; a grid of --cells COLSxROWS over the frame, default 8x6; --threshold 20 and --threshold-lo 7; --scales
levels of --step, --sectors; a level must be at least 37x37 pixels, else the command refuses); `opencv`,
cv2.ORB_create(nfeatures = our feature count on that frame), OpenCV's defaults otherwise (none when
ours has none).

Measured, for each pair of frames (i, i + g) of a clip and each gap g of --gaps, per extractor:
cross-checked brute-force Hamming matches (cv2.BFMatcher(NORM_HAMMING, crossCheck=True)); the inliers
of cv2.findFundamentalMat(FM_RANSAC, 1.0 px, confidence 0.999, 2000 iterations) on them, with
cv2.setRNGSeed(--seed) before each estimate (0 with fewer than 8 matches); inliers per feature
(inliers / features of frame i); coverage, the share of an 8x6 grid over frame i holding at least
one inlier; and whether the pair failed (fewer than 30 inliers). Summary per extractor and gap: the
means of features, inliers, inliers per feature and coverage over the pairs, the share of failed pairs,
and `failed_alone`: the pairs where this extractor failed and the other did not.

Writes track_bench.csv (one row per clip x gap x pair x extractor), track_bench_summary.json
(settings, the summary, the same per clip) and track_bench.png.
"""

from __future__ import annotations

import contextlib
import csv
import json
import math
import os
import zlib
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TypeVar

import cv2
import numpy as np

from golden_model.config import (
    RECOMMENDED_COLS,
    RECOMMENDED_ROWS,
    RECOMMENDED_SCALES,
    RECOMMENDED_SECTORS,
    RECOMMENDED_STEP,
    RECOMMENDED_THRESHOLD_LO,
    Config,
    ConfigError,
    level_size,
    recommended_budget,
)
from golden_model.images import ImageError, to_luma
from golden_model.pipeline import extract

from .eval_photos import fit
from .images import VIDEO_SUFFIXES, load_rgb_or_grey
from .scale_bench import MIN_LEVEL, Extractor, Points, extract_opencv_orb, max_levels

GRID = (8, 6)  # columns, rows of the coverage grid
FAIL_INLIERS = 30
RANSAC_PX = 1.0
RANSAC_CONFIDENCE = 0.999
RANSAC_ITERATIONS = 2000
MAX_WORKERS = 2
EXTRACTORS = ("ours", "opencv")
# the camera (module docstring)
CYCLE_FRAMES = 30
VIEW = 0.55
ZOOM = 0.25
ROLL_DEG = 8.0
PAN = (0.18, 0.15)
KEYSTONE = 2e-4
NOISE_SIGMA = 2.0
T = TypeVar("T")
CSV_COLUMNS = ("clip", "kind", "gap", "frame", "extractor", "features", "matches", "inliers", "inliers_per_feature",
               "coverage", "failed")  # fmt: skip


@dataclass(frozen=True)
class Settings:
    """The model's configuration of the benches (track-bench and density-bench); None: recommended."""

    budget: int | None = None
    cells: tuple[int, int] | None = None
    threshold: int = 20
    threshold_lo: int = RECOMMENDED_THRESHOLD_LO
    scales: int = RECOMMENDED_SCALES
    step: tuple[int, int] = RECOMMENDED_STEP
    sectors: int = RECOMMENDED_SECTORS

    def config(self, width: int, height: int) -> Config:
        """The grid-selection Config for a frame size (ConfigError when a level is too small to hold features)."""
        check_levels(width, height, self.scales, self.step)
        budget = recommended_budget(width, height) if self.budget is None else self.budget
        cols, rows = (RECOMMENDED_COLS, RECOMMENDED_ROWS) if self.cells is None else self.cells
        return Config(width, height, scales=self.scales, sectors=self.sectors, threshold=self.threshold,
                      step_num=self.step[0], step_den=self.step[1], threshold_lo=self.threshold_lo,
                      selection="grid", budget=budget, cols=cols, rows=rows)  # fmt: skip


def check_levels(width: int, height: int, scales: int, step: tuple[int, int]) -> None:
    w, h = level_size(width, height, scales - 1, step)
    if min(w, h) < MIN_LEVEL:
        most = max_levels(width, height, step)
        raise ConfigError(f"{scales} levels of {step[0]}:{step[1]} leave a {w}x{h} smallest level at {width}x{height}; "
                          f"a level needs at least {MIN_LEVEL}x{MIN_LEVEL} pixels to hold features "
                          f"(use --scales {most} or fewer, or a larger size)")  # fmt: skip


def extract_ours(img: np.ndarray, cfg: Config) -> Points:
    """The model's grid selection, at full-resolution positions."""
    feats = extract(img, cfg)
    x0, y0 = feats.full_res()
    return Points(x0, y0, feats.descriptor.reshape(-1, 32))


def extract_opencv(img: np.ndarray, nfeatures: int) -> Points:
    """OpenCV ORB's defaults with `nfeatures` (nothing when it is 0)."""
    if nfeatures <= 0:
        return Points(np.zeros(0), np.zeros(0), np.zeros((0, 32), np.uint8))
    return extract_opencv_orb(img, Extractor("cv-default", "opencv-default"), nfeatures)


def occupancy(x: np.ndarray, y: np.ndarray, width: int, height: int, grid: tuple[int, int] = GRID) -> np.ndarray:
    """(rows, columns) booleans: which cells of a grid over the frame hold at least one of the points."""
    gx, gy = grid
    occ = np.zeros((gy, gx), dtype=bool)
    if len(x):
        cx = np.clip(np.floor(np.asarray(x, np.float64) * gx / width).astype(np.int64), 0, gx - 1)
        cy = np.clip(np.floor(np.asarray(y, np.float64) * gy / height).astype(np.int64), 0, gy - 1)
        occ[cy, cx] = True
    return occ


def coverage(x: np.ndarray, y: np.ndarray, width: int, height: int) -> float:
    """The share of the 8x6 grid's cells that hold at least one of the points."""
    return float(occupancy(x, y, width, height).mean())


def pair_stats(a: Points, b: Points, width: int, height: int, seed: int) -> dict:
    """Matches, fundamental-matrix inliers, inliers per feature of `a`, inlier coverage of `a`'s frame, failed."""
    matches = inliers = 0
    cov = 0.0
    if len(a) and len(b):
        found = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(a.desc, b.desc)
        matches = len(found)
        if matches >= 8:
            q = np.array([m.queryIdx for m in found], dtype=np.int64)
            t = np.array([m.trainIdx for m in found], dtype=np.int64)
            pa = np.stack([a.x[q], a.y[q]], axis=1).astype(np.float64)
            pb = np.stack([b.x[t], b.y[t]], axis=1).astype(np.float64)
            cv2.setRNGSeed(seed)
            _, mask = cv2.findFundamentalMat(pa, pb, cv2.FM_RANSAC, RANSAC_PX, RANSAC_CONFIDENCE, RANSAC_ITERATIONS)
            if mask is not None:
                inl = mask.ravel().astype(bool)
                inliers = int(inl.sum())
                cov = coverage(pa[inl, 0], pa[inl, 1], width, height)
    return {"matches": matches, "inliers": inliers, "inliers_per_feature": inliers / len(a) if len(a) else 0.0,
            "coverage": cov, "failed": inliers < FAIL_INLIERS}  # fmt: skip


def _homography(photo_size: tuple[int, int], frame_size: tuple[int, int], base: float, s: float,
                phases: np.ndarray) -> np.ndarray:  # fmt: skip
    """Frame pixel -> photograph pixel at time s (module docstring)."""
    (iw, ih), (w, h) = photo_size, frame_size
    tau = 2 * math.pi
    zoom = 1.0 + ZOOM * math.sin(tau * 0.7 * s + phases[0])
    a = math.radians(ROLL_DEG * math.sin(tau * 0.5 * s + phases[1]))
    cx = iw / 2 + PAN[0] * iw * math.sin(tau * 0.6 * s + phases[2])
    cy = ih / 2 + PAN[1] * ih * math.sin(tau * 0.8 * s + phases[3])
    px = KEYSTONE * math.sin(tau * s + phases[4])
    py = KEYSTONE * math.cos(tau * s + phases[5])
    sc = base / zoom
    rot = np.array([[sc * math.cos(a), -sc * math.sin(a), 0], [sc * math.sin(a), sc * math.cos(a), 0], [0, 0, 1]])
    persp = np.array([[1, 0, 0], [0, 1, 0], [px, py, 1]])
    to_c = np.array([[1, 0, -w / 2], [0, 1, -h / 2], [0, 0, 1]])
    back = np.array([[1, 0, cx], [0, 1, cy], [0, 0, 1]])
    return back @ rot @ persp @ to_c


def camera_clip(photo: np.ndarray, frames: int, width: int, height: int, rng: np.random.Generator) -> list[np.ndarray]:
    """A hand-held camera over a luma photograph (module docstring)."""
    phases = rng.uniform(0, 2 * math.pi, 6)
    ih, iw = photo.shape
    shrink = (1 - ZOOM) / (min(iw / width, ih / height) * VIEW)
    if shrink < 1:
        photo = cv2.resize(
            photo, (max(1, round(iw * shrink)), max(1, round(ih * shrink))), interpolation=cv2.INTER_AREA
        )
        ih, iw = photo.shape
    base = min(iw / width, ih / height) * VIEW
    out = []
    for t in range(frames):
        hm = _homography((iw, ih), (width, height), base, t / (CYCLE_FRAMES - 1), phases)
        f = cv2.warpPerspective(photo, hm, (width, height), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                borderMode=cv2.BORDER_REFLECT)  # fmt: skip
        noisy = np.rint(f + rng.normal(0.0, NOISE_SIGMA, f.shape))
        out.append(np.clip(noisy, 0, 255).astype(np.uint8))
    return out


def is_video(path: Path) -> bool:
    return path.suffix.lower() in VIDEO_SUFFIXES


def video_frames(path: Path, frames: int, width: int, height: int) -> list[np.ndarray]:
    """The first `frames` frames of a video as luma, fitted to width x height."""
    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        raise ImageError(f"{path}: not a video OpenCV can read")
    out = []
    try:
        while len(out) < frames:
            ok, bgr = cap.read()
            if not ok:
                break
            out.append(to_luma(fit(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB), width, height)))
    finally:
        cap.release()
    return out


def clip_seed(seed: int, name: str) -> np.random.Generator:
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


def load_clip(path: Path, frames: int, width: int, height: int, seed: int) -> tuple[str, list[np.ndarray]]:
    """(kind, luma frames) of an INPUT: a video's first frames, or a camera clip over a photograph."""
    if not path.exists():
        raise ImageError(f"{path}: no such file")
    if is_video(path):
        got = video_frames(path, frames, width, height)
        kind = "video"
    else:
        got = camera_clip(to_luma(load_rgb_or_grey(path)), frames, width, height, clip_seed(seed, path.stem))
        kind = "photo"
    if len(got) < 2:
        raise ImageError(f"{path}: {len(got)} frame(s); a clip needs at least 2")
    return kind, got


@dataclass(frozen=True)
class Job:
    """One clip's work (what a worker process receives)."""

    name: str
    path: Path
    frames: int
    gaps: tuple[int, ...]
    size: tuple[int, int]
    seed: int
    settings: Settings = field(default_factory=Settings)


def clip_rows(name: str, kind: str, frames: Sequence[np.ndarray], gaps: Sequence[int], cfg: Config,
              seed: int) -> list[dict]:  # fmt: skip
    """The CSV rows of one clip's frames."""
    ours = [extract_ours(f, cfg) for f in frames]
    points = {"ours": ours, "opencv": [extract_opencv(f, len(p)) for f, p in zip(frames, ours, strict=True)]}
    rows = []
    for g in gaps:
        for i in range(len(frames) - g):
            for ext in EXTRACTORS:
                a, b = points[ext][i], points[ext][i + g]
                rows.append({"clip": name, "kind": kind, "gap": g, "frame": i, "extractor": ext, "features": len(a),
                             **pair_stats(a, b, cfg.width, cfg.height, seed)})  # fmt: skip
    return rows


def run_job(job: Job) -> list[dict]:
    w, h = job.size
    kind, frames = load_clip(job.path, job.frames, w, h, job.seed)
    return clip_rows(job.name, kind, frames, job.gaps, job.settings.config(w, h), job.seed)


def pool_rows(work: Callable[[T], list[dict]], jobs: Sequence[T], names: Sequence[str], workers: int = MAX_WORKERS,
              progress: Callable[[str], None] | None = None) -> list[dict]:  # fmt: skip
    """The rows of every job in the order of `jobs`, computed by at most MAX_WORKERS processes (`work` a
    module-level function); `progress` hears each job's name as it completes in order."""
    workers = max(1, min(workers, MAX_WORKERS, len(jobs), os.cpu_count() or 1))
    rows: list[dict] = []
    with contextlib.ExitStack() as stack:
        mapped = map(work, jobs) if workers == 1 else stack.enter_context(ProcessPoolExecutor(workers)).map(work, jobs)
        for name, got in zip(names, mapped, strict=True):
            rows += got
            if progress:
                progress(f"{name}: done")
    return rows


def run(jobs: Sequence[Job], workers: int = MAX_WORKERS, progress: Callable[[str], None] | None = None) -> list[dict]:
    """Every clip's rows, in the order of `jobs` (a pool of at most MAX_WORKERS processes over clips)."""
    return pool_rows(run_job, jobs, [j.name for j in jobs], workers, progress)


def summarise(rows: Sequence[dict]) -> list[dict]:
    """One row per extractor and gap (module docstring)."""
    out = []
    for g in sorted({r["gap"] for r in rows}):
        sel = {e: [r for r in rows if r["gap"] == g and r["extractor"] == e] for e in EXTRACTORS}
        failed = {e: np.array([r["failed"] for r in sel[e]], dtype=bool) for e in EXTRACTORS}
        for e in EXTRACTORS:
            other = EXTRACTORS[1 - EXTRACTORS.index(e)]
            col = {k: np.array([r[k] for r in sel[e]], dtype=np.float64)
                   for k in ("features", "inliers", "inliers_per_feature", "coverage")}  # fmt: skip
            n = len(sel[e])
            out.append({"extractor": e, "gap": g, "pairs": n,
                        **{k: round(float(v.mean()), 4) if n else math.nan for k, v in col.items()},
                        "failed_share": round(float(failed[e].mean()), 4) if n else math.nan,
                        "failed_alone": int((failed[e] & ~failed[other]).sum())})  # fmt: skip
    return out


def summary_by_clip(rows: Sequence[dict]) -> dict[str, list[dict]]:
    clips = list(dict.fromkeys(r["clip"] for r in rows))
    return {c: summarise([r for r in rows if r["clip"] == c]) for c in clips}


def write_csv(path: Path, rows: Sequence[dict], columns: Sequence[str]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(columns), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def write_outputs(out_dir: Path, rows: Sequence[dict], settings: dict) -> list[dict]:
    """track_bench.csv, track_bench_summary.json, track_bench.png; the summary."""
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(out_dir / "track_bench.csv", rows, CSV_COLUMNS)
    summary = summarise(rows)
    by_clip = summary_by_clip(rows)
    doc = {"settings": settings, "summary": summary, "by_clip": by_clip}
    (out_dir / "track_bench_summary.json").write_text(json.dumps(doc, indent=1) + "\n")
    plot(summary, by_clip, out_dir / "track_bench.png")
    return summary


def settings_record(settings: Settings, size: tuple[int, int], frames: int, gaps: Sequence[int], seed: int) -> dict:
    cfg = settings.config(*size)
    return {**asdict(settings), "size": f"{size[0]}x{size[1]}", "budget_used": cfg.budget,
            "cells_used": f"{cfg.cols}x{cfg.rows}", "frames": frames, "gaps": list(gaps), "seed": seed}  # fmt: skip


def table(summary: Sequence[dict]) -> str:
    keys = ("pairs", "features", "inliers", "inliers_per_feature", "coverage", "failed_share", "failed_alone")
    lines = ["| extractor | gap | " + " | ".join(keys) + " |", "|---|---|" + "---|" * len(keys)]
    for r in summary:
        lines.append(f"| {r['extractor']} | {r['gap']} | " + " | ".join(str(r[k]) for k in keys) + " |")
    return "\n".join(lines)


def plot(summary: Sequence[dict], by_clip: dict[str, list[dict]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    gaps = sorted({r["gap"] for r in summary})
    clips = list(by_clip)
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw={"width_ratios": [max(len(clips), 2), 3]})
    series = [(e, g) for g in gaps for e in EXTRACTORS]
    width = 0.8 / len(series)
    for i, (e, g) in enumerate(series):
        vals = [next(r["inliers"] for r in by_clip[c] if r["extractor"] == e and r["gap"] == g) for c in clips]
        ax0.bar(np.arange(len(clips)) + i * width, vals, width, label=f"{e}, gap {g}")
    ax0.set_xticks(np.arange(len(clips)) + 0.4 - width / 2, clips, rotation=30, ha="right", fontsize=8)
    ax0.set_ylabel("mean F-RANSAC inliers per pair")
    ax0.legend(fontsize=8)
    ax0.grid(axis="y", alpha=0.3)
    metrics = ("inliers_per_feature", "coverage", "failed_share")
    for i, (e, g) in enumerate(series):
        r = next(r for r in summary if r["extractor"] == e and r["gap"] == g)
        ax1.bar(np.arange(len(metrics)) + i * width, [r[m] for m in metrics], width, label=f"{e}, gap {g}")
    ax1.set_xticks(
        np.arange(len(metrics)) + 0.4 - width / 2,
        ["inliers\nper feature", "inlier coverage\n(8x6 grid)", "failed pairs\n(< 30 inliers)"],
        fontsize=8,
    )
    ax1.grid(axis="y", alpha=0.3)
    fig.suptitle("Tracking: grid selection (ours) vs OpenCV ORB at the same count (orb-accel track-bench)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def make_jobs(paths: Sequence[Path], frames: int, gaps: Sequence[int], size: tuple[int, int], seed: int,
              settings: Settings) -> list[Job]:  # fmt: skip
    """One job per INPUT, named after its file (a repeated name gets its position appended)."""
    stems = [p.stem for p in paths]
    names = [s if stems.count(s) == 1 else f"{s}-{i}" for i, s in enumerate(stems)]
    return [Job(n, p, frames, tuple(gaps), size, seed, settings) for n, p in zip(names, paths, strict=True)]
