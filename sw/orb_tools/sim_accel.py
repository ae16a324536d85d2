# SPDX-License-Identifier: MIT
"""`make sim` (`orb-accel sim`): the complete accelerator (orb_accel_top) in GHDL on one image, driven as the CPU
drives it: registers written and the features read back over AXI4-Lite from the feature memory.
`--fast` (`make sim FAST=1`): the same on GHDL's synthesised netlist in Verilator
(orb_sim.fast, docs/fast-sim.md), with the same outputs. `--video FILE` (`make sim VIDEO=...`):
every frame of a video (at most --max-frames) back to back through the netlist, the driver reading
and releasing the banks as on the board; each frame checked against the model (report.json).
A configuration whose mem_kind is "ddr" (the board builds; `--mem-kind` to choose) writes its
frames through the AXI4 master into a DDR model, and the driver reads them from that memory
(docs/feature-dma.md): in GHDL cocotbext-axi's AXI4 RAM (orb_sim.ddr_ram), with `--fast` the
harness's (docs/fast-sim.md); report.json says which (`mem_kind`) and has its figures (`ddr`).

The image (default: the bundled 640x480 photograph) streams in as 24-bit RGB at one pixel per
clock; the CPU model reads the frame's bank; the image is streamed a second time with the
accelerator disabled to capture the HDMI overlay of the first frame's features. Writes to the
output directory (default build/sim): features.csv (the CLI's format), overlay.png (the
overlay block's output) and report.json (features, bit_exact against the golden model, dropped,
truncated, latency_cycles, cycles_per_pixel, sim_wall_s and details), and prints a short summary.

The device is a named configuration (docs/configurations.md; `--config`, `make sim CONFIG=`):
its generics and the selection the driver starts it with, the image resized to its frame size
(`--size native` keeps the image's own; `--size WxH`). Without `--config`: recommended-vga's values at
the image's own size. The other options replace single values. In `grid` the frame must equal the
model's selection with nothing lost.
`--selection all` stores every feature: a frame with more than a bank holds is truncated, and the
stored features are checked to be what the memory keeps (golden_model.select.truncation_difference:
each level's first features in arrival order); the truncation is reported, not an error.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np

from golden_model import Config, extract, first_difference, limits
from golden_model.config import (
    NAMES,
    RECOMMENDED_NAME,
    SELECTIONS,
    ConfigError,
    NamedConfig,
    named,
    parse_cells,
    parse_step,
    recommended_budget,
)
from golden_model.features import Features, read_csv
from golden_model.images import DEFAULT_IMAGE, ImageError
from golden_model.luma import rgb_to_luma
from golden_model.overlay import marker_block_log2, render_marker_overlay
from golden_model.pipeline import streamed
from golden_model.select import truncation_difference
from orb_accel.driver import Frame
from orb_sim.fast.sim import FastSimError
from orb_sim.rtl_backend import RtlUnavailable, run_accel_job
from orb_sim.runner import ToolMissing
from orb_tools.images import load_rgb_or_grey


def progress_loop(path: Path, stop: threading.Event) -> None:
    last = ""
    while not stop.wait(2.0):
        if path.exists():
            parts = path.read_text().split()
            if len(parts) == 4:
                phase, done, total = parts[0], int(parts[1]), int(parts[2])
                if phase == "frame":
                    line = f"  {100 * done / total:5.1f} % of the frame's pixels in, {float(parts[3]):.0f} s"
                else:
                    line = f"  frame done in {float(parts[3]):.0f} s; reading the features back over AXI4-Lite "
                    line += "while the overlay frame streams"
                if line != last:
                    print(line, flush=True)
                    last = line


def make_config(args: argparse.Namespace, nc: NamedConfig, w: int, h: int) -> tuple[Config, int, int]:
    """The model configuration of the run (the driver configures the accelerator from it), the
    simulated bank's slots and the overlay's block (log2): the named configuration at the frame's
    size, with the options given (other scales: the smallest block that fits them)."""
    mem_depth = nc.mem_depth if args.mem_depth is None else args.mem_depth
    if not limits.MEM_DEPTH.legal(mem_depth):
        raise ConfigError(f"mem_depth must be {limits.MEM_DEPTH.text}, got {mem_depth}")
    capacity = mem_depth - 1
    same = (w, h) == (nc.width, nc.height) and mem_depth == nc.mem_depth
    budget = args.budget
    if budget is None:
        budget = nc.budget if same and nc.selection == "grid" else min(capacity, recommended_budget(w, h))
    selection = nc.selection if args.selection is None else args.selection
    if selection == "grid" and not 0 <= budget <= capacity:
        raise ConfigError(f"budget {budget}: a bank of the simulated accelerator holds 0..{capacity} features")
    cols, rows = (nc.cols, nc.rows) if args.cells is None else parse_cells(args.cells)
    num, den = (nc.step_num, nc.step_den) if args.step is None else parse_step(args.step)
    pick = lambda given, default: default if given is None else given  # noqa: E731
    cfg = nc.config(width=w, height=h, scales=pick(args.scales, nc.scales), sectors=pick(args.sectors, nc.sectors),
                    threshold=pick(args.threshold, nc.threshold), mode="orb", step_num=num, step_den=den,
                    selection=selection, budget=budget, cols=cols, rows=rows,
                    threshold_lo=pick(args.threshold_lo, nc.threshold_lo))  # fmt: skip
    block_log2 = nc.block_log2 if args.scales is None else marker_block_log2(cfg.scales)
    return cfg, mem_depth, block_log2


def parse_size(text: str | None, nc: NamedConfig | None) -> tuple[int, int] | None:
    """--size: (W, H); None for native; not given: the named configuration's size when one was
    named (--config), else native."""
    if text is None:
        return None if nc is None else (nc.width, nc.height)
    if text == "native":
        return None
    w, sep, h = text.lower().partition("x")
    if not sep or not w.isdigit() or not h.isdigit():
        raise ValueError(f"size {text!r}: expected WxH or native")
    return int(w), int(h)


def describe_selection(cfg: Config) -> str:
    if cfg.selection == "all":
        return "every feature (selection all)"
    return f"grid selection: budget {cfg.budget}, {cfg.cols} x {cfg.rows} cells, low threshold {cfg.threshold_lo}"


def compare(got: Features, img: np.ndarray, cfg: Config, truncated: int, capacity: int) -> str | None:
    """None when the frame is what the accelerator must deliver: the model's selection, or in `all`
    selection with a full bank what the memory keeps of every feature."""
    expected = extract(img, cfg)
    if cfg.selection == "all" and truncated:
        return truncation_difference(got, expected, capacity, cfg)
    return first_difference(got, expected)


def build_parser() -> argparse.ArgumentParser:
    """The options of `orb-accel sim` (`make sim`)."""
    ap = argparse.ArgumentParser(prog="orb-accel sim", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)  # fmt: skip
    ap.add_argument("--image", type=Path, help="image file (default: the bundled 640x480 photograph)")
    ap.add_argument("--config", choices=NAMES,
                    help=f"a named configuration (docs/configurations.md), the image resized to its size; default: "
                         f"{RECOMMENDED_NAME} at the image's size; the options below replace its values")  # fmt: skip
    ap.add_argument("--size", help="WxH: resize the image to this (default: the named configuration's size, else "
                    "the image's; native: the image's)")  # fmt: skip
    ap.add_argument("--scales", type=int, help="scales, pyramid levels")
    ap.add_argument("--step", help="pyramid step NUM:DEN")
    ap.add_argument("--sectors", type=int, help="16, 32 or 64")
    ap.add_argument("--threshold", type=int)
    ap.add_argument("--selection", choices=SELECTIONS, help="grid or all")
    ap.add_argument("--budget", type=int, help="grid: features per frame (default: the configuration's at its size, "
                    "else the recommended one of the size within a bank)")  # fmt: skip
    ap.add_argument("--cells", help="grid: COLSxROWS cells over the frame")
    ap.add_argument("--mem-depth", type=int, help="slots per bank of the simulated accelerator")
    ap.add_argument("--threshold-lo", type=int, help="grid: low FAST threshold")
    ap.add_argument("--out-dir", type=Path, default=Path("build") / "sim")
    ap.add_argument("--fast", action="store_true", help="the netlist in Verilator instead of the RTL in GHDL")
    ap.add_argument("--seed", type=int, default=0, help="--fast: random initial state from this seed (0: zeros)")
    ap.add_argument("--mem-kind", choices=("bram", "ddr"),
                    help="the feature memory, block-RAM banks or the DDR ring (default: the named "
                         "configuration's mem_kind)")  # fmt: skip
    ap.add_argument("--video", type=Path, help="a video file: all its frames through the netlist (implies --fast)")
    ap.add_argument("--max-frames", type=int, default=300, help="--video: at most this many frames (300)")
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.video is not None:
        return main_video(args)
    path = args.image or DEFAULT_IMAGE
    try:
        original = load_rgb_or_grey(path)
        if original.dtype == np.uint16:  # 16-bit files: the top 8 bits (spec section 2)
            original = (original >> 8).astype(np.uint8)
        rgb = original if original.ndim == 3 else np.repeat(original[..., None], 3, axis=2)
        rgb = np.ascontiguousarray(rgb[..., :3], dtype=np.uint8)
        nc = named(args.config or RECOMMENDED_NAME)
        size = parse_size(args.size, nc if args.config else None)
        if size is not None and size != (rgb.shape[1], rgb.shape[0]):
            rgb = cv2.resize(rgb, size, interpolation=cv2.INTER_AREA)
        h, w = rgb.shape[:2]
        cfg, mem_depth, block_log2 = make_config(args, nc, w, h)
    except (ImageError, ConfigError, ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    out = args.out_dir.resolve()
    job = out / "job"
    shutil.rmtree(job, ignore_errors=True)
    job.mkdir(parents=True)
    log = out / "sim.log"
    mem_kind = args.mem_kind or nc.mem_kind
    engine = "its netlist in Verilator" if args.fast else f"GHDL (log: {log})"
    if mem_kind == "ddr":
        engine += ", the features written to its DDR model"
    print(f"make sim: {path.name} {w}x{h}, {nc.name}: {cfg.scales} scale(s) of {cfg.step_num}:{cfg.step_den}, "
          f"{cfg.sectors} sectors, "
          f"threshold {cfg.threshold}, {describe_selection(cfg)}: orb_accel_top in {engine}", flush=True)  # fmt: skip
    stop = threading.Event()
    watcher = threading.Thread(target=progress_loop, args=(job / "progress.txt", stop), daemon=True)
    watcher.start()
    t0 = time.perf_counter()
    try:
        if args.fast:
            from orb_sim.fast.jobs import run_accel_fast

            result = run_accel_fast(
                rgb, cfg, job, overlay=True, seed=args.seed, mem_depth=mem_depth, block_log2=block_log2,
                mem_kind=mem_kind,
            )  # fmt: skip
        else:
            result = run_accel_job(rgb, cfg, job, log, overlay=True, mem_depth=mem_depth, block_log2=block_log2,
                                   mem_kind=mem_kind)  # fmt: skip
    except (RtlUnavailable, ToolMissing, FastSimError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    finally:
        stop.set()
    sim_wall = time.perf_counter() - t0
    feats = read_csv(job / "features.csv", sectors_total=cfg.sectors, step=cfg.step)
    shutil.copyfile(job / "features.csv", out / "features.csv")
    luma = rgb_to_luma(rgb)
    diff = compare(feats, luma, cfg, result["truncated"], mem_depth - 1)
    # the overlay marks what the feature stream carried: every feature in `all` (the bank may have
    # truncated them), in `grid` the selection and the features it replaced
    overlay = np.load(job / "overlay.npy")
    overlay_expected = render_marker_overlay(rgb, streamed(luma, cfg), scales=cfg.scales,
                                             block_log2=block_log2)  # fmt: skip
    overlay_exact = bool(np.array_equal(overlay, overlay_expected))
    cv2.imwrite(str(out / "overlay.png"), cv2.cvtColor(overlay, cv2.COLOR_RGB2BGR))
    # lost: dropped in the core, or truncated by a full bank in the grid selection (which must never
    # happen); the `all` selection's truncation is reported on its own
    truncated = result["truncated"]
    dropped = result["dropped_merge"] + result["desc_lost"] + (truncated if cfg.selection == "grid" else 0)
    report = {
        "image": str(path), "width": w, "height": h, "scales": cfg.scales, "step": f"{cfg.step_num}:{cfg.step_den}",
        "sectors": cfg.sectors, "selection": cfg.selection, "budget": cfg.budget, "cells": [cfg.cols, cfg.rows],
        "threshold_lo": cfg.threshold_lo, "truncated": truncated, "mem_depth": mem_depth, "block_log2": block_log2,
        "config": nc.name,
        "threshold": cfg.threshold, "features": result["features"], "bit_exact": diff is None,
        "first_difference": diff, "overlay_bit_exact": overlay_exact, "dropped": dropped,
        "dropped_detail": {"merge": result["dropped_merge"], "feature_memory_truncated": result["truncated"],
                           "descriptor_lost": result["desc_lost"]},
        "latency_cycles": result["latency_cycles"], "cycles_per_pixel": result["cycles_per_pixel"],
        "frame_cycles": result["frame_cycles"], "sim_wall_s": round(sim_wall, 1),
        "frame_sim_wall_s": result["frame_sim_wall_s"], "proto_errors": result["proto_errors"],
        "engine": "verilator-netlist" if args.fast else "ghdl-rtl",
        "mem_kind": mem_kind,  # the feature memory: "bram" (the banks, over AXI4-Lite) or "ddr" (the ring)
    }  # fmt: skip
    if args.fast:
        report["build_s"] = result["build_s"]
        report["seed"] = args.seed
    if "ddr" in result:
        report["ddr"] = result["ddr"]
    (out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    ok = report["bit_exact"] and overlay_exact and dropped == 0
    trunc = f"; {truncated} truncated by the full bank (selection all)" if truncated and cfg.selection == "all" else ""
    print(f"{result['features']} features, bit-exact with the model: {'yes' if diff is None else 'NO: ' + diff}; "
          f"overlay bit-exact: {'yes' if overlay_exact else 'NO'}; lost {dropped}{trunc}; "
          f"{result['cycles_per_pixel']} clocks per pixel; last pixel to end-of-frame record "
          f"{result['latency_cycles']} clocks; simulation {sim_wall:.0f} s "
          f"(first frame {result['frame_sim_wall_s']} s)")  # fmt: skip
    print(f"wrote {out / 'features.csv'}, {out / 'overlay.png'}, {out / 'report.json'}")
    return 0 if ok else 1


def main_video(args: argparse.Namespace) -> int:
    from orb_sim.fast.jobs import run_video_fast
    from orb_tools.images import load_frames

    try:
        nc = named(args.config or RECOMMENDED_NAME)
        frames = load_frames(
            [args.video], parse_size(args.size, nc if args.config else None), max_frames=args.max_frames
        )
        n, h, w = frames.shape[:3]
        cfg, mem_depth, block_log2 = make_config(args, nc, w, h)
    except (ImageError, ConfigError, ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    out = args.out_dir.resolve()
    out.mkdir(parents=True, exist_ok=True)
    print(f"make sim: {args.video.name}, {n} frames of {w}x{h}, {nc.name}: {cfg.scales} scale(s) of "
          f"{cfg.step_num}:{cfg.step_den}, {cfg.sectors} sectors, threshold {cfg.threshold}, "
          f"{describe_selection(cfg)}: orb_accel_top's netlist in Verilator", flush=True)  # fmt: skip
    results: list[dict] = []

    def check(i: int, frame: Frame) -> None:
        luma = rgb_to_luma(frames[i]) if frames.ndim == 4 else frames[i]
        diff = compare(frame.features, luma, cfg, frame.truncated, mem_depth - 1)
        lost = frame.dropped + (frame.truncated if cfg.selection == "grid" else 0)
        if lost and diff is None:
            diff = f"{lost} features lost"
        results.append({"frame": i, "number": frame.number, "features": len(frame), "bit_exact": diff is None,
                        "first_difference": diff, "dropped": frame.dropped, "truncated": frame.truncated})  # fmt: skip
        if i % 10 == 0 or diff is not None:
            verdict = "yes" if diff is None else "NO: " + diff
            print(f"  frame {i}: {len(frame)} features, bit-exact: {verdict}", flush=True)

    try:
        _, run = run_video_fast(frames, cfg, seed=args.seed, mem_depth=mem_depth, on_frame=check, block_log2=block_log2,
                                mem_kind=args.mem_kind or nc.mem_kind)  # fmt: skip
    except (ToolMissing, FastSimError, TimeoutError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    exact = sum(r["bit_exact"] for r in results)
    report = {"video": str(args.video), "config": nc.name, "mem_depth": mem_depth, "width": w, "height": h,
              "scales": cfg.scales,
              "step": f"{cfg.step_num}:{cfg.step_den}", "sectors": cfg.sectors,
              "threshold": cfg.threshold, "selection": cfg.selection, "budget": cfg.budget,
              "cells": [cfg.cols, cfg.rows], "threshold_lo": cfg.threshold_lo, "frames": n,
              "frames_published": len(results),
              "bit_exact_frames": exact,
              "features": sum(r["features"] for r in results), "run": run, "per_frame": results,
              "engine": "verilator-netlist", "mem_kind": args.mem_kind or nc.mem_kind}  # fmt: skip
    (out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    print(f"{len(results)} of {n} frames published, {exact} bit-exact with the model, {report['features']} features; "
          f"{run['wall_s']} s ({run['clocks_per_s']:,} clocks/s) -> {out / 'report.json'}")  # fmt: skip
    return 0 if exact == n == len(results) else 1
