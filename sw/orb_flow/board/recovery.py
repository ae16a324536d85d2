# SPDX-License-Identifier: MIT
"""The board's recovery after a cut in its HDMI input (docs/board.md, "Recovery after a cut"): how
many frames are lost when the cable is pulled in mid-frame, or the source restarts its timing in
mid-frame, measured on the accelerator's netlist in Verilator (orb_sim.fast, docs/fast-sim.md)
behind a model of the board's input, for each board configuration of vivado/board.json and each
video checker (IDLE_TIMEOUT_g 0: the checker that holds its input while padding; 4096: the board's).

The input model: the frames play at the configuration's pixel clock (`pixel_mhz` of `core_mhz`,
the simulation's clock being the core clock) with the blanking of their CEA-861 timing (CEA below),
through a FIFO of 4,096 pixels in front of s_axis_video that drops what arrives while it is full,
as v_vid_in_axi4s (C_ADDR_WIDTH 12) does; the source ignores tready (harness.cpp's live source).
The overlay output is always ready. The fast path builds orb_accel_top only, not the wrapper
orb_accel_zynq: the measured top is orb_accel_top with the wrapper's IDLE_TIMEOUT_g (the wrapper
adds a registered reset and the address width, nothing on the video path).

Each run: `--before` good frames, the event frame, `--after` good frames, each a different shift of
the bundled photograph resized to the frame. The event frame stops after `--at` of its lines and a
third of a line; "cut": the source is silent for one frame period (the cable out, longer than the
timeout and any padding), then the next frame starts (the source comes back at a start of frame);
"restart": the next frame starts at once, in mid-line (a source that restarts its timing, no idle
gap). The shipped driver (orb_accel.OrbAccel) reads and releases every published frame; each is
identified by its features, bit-exact with the golden model's of one frame sent. Lost: the frames
sent from the event frame on that were never published (the event frame included; the goal is 1).

    python -m orb_flow.board.recovery [--configs 640x480 ...] [--idle-timeout 0 4096] [--events cut restart]

Writes build/recovery/recovery.json; `python -m orb_flow.record recovery` keeps it in
docs/results/recovery.json and `make views` writes docs/board.md's table.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from fractions import Fraction
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from golden_model.config import Config, named
from golden_model.features import Features, first_difference
from golden_model.images import DEFAULT_IMAGE
from golden_model.luma import rgb_to_luma
from golden_model.pipeline import extract
from orb_accel.driver import OrbAccel
from orb_flow.gen.board import load as load_board
from orb_sim.fast.build import build_fast
from orb_sim.fast.jobs import is_ddr, pack
from orb_sim.fast.sim import FastBus, FastMemory, FastSim, frame_program

ROOT = Path(__file__).resolve().parents[3]
OUT = ROOT / "build" / "recovery" / "recovery.json"
FIFO_DEPTH = 4096  # v_vid_in_axi4s with C_ADDR_WIDTH 12 (vivado/lib/bd.tcl)
BOARD_TIMEOUT = 4096  # orb_accel_zynq's IDLE_TIMEOUT_g default
# CEA-861 timings: active (width, height) -> total (pixels per line, lines per frame)
CEA = {(640, 480): (800, 525), (1280, 720): (1650, 750), (1920, 1080): (2200, 1125)}
EVENTS = ("cut", "restart")
SHIFT = 16  # frame k is the photograph shifted k * SHIFT pixels to the right (its features differ)


def timing(cfg: dict[str, Any]) -> tuple[int, int]:
    """The CEA-861 totals of a board configuration, checked against its pixel clock (60 or 59.94 Hz)."""
    key = (cfg["width"], cfg["height"])
    if key not in CEA:
        raise SystemExit(f"error: no CEA-861 timing for {key[0]}x{key[1]} in orb_flow.board.recovery.CEA")
    h_total, v_total = CEA[key]
    hz = cfg["pixel_mhz"] * 1e6 / (h_total * v_total)
    if not 59.9 < hz < 60.1:
        raise SystemExit(f"error: {key[0]}x{key[1]}: {h_total}x{v_total} at {cfg['pixel_mhz']} MHz is {hz:.2f} Hz")
    return h_total, v_total


def frames(width: int, height: int, count: int) -> list[np.ndarray]:
    """`count` RGB frames: the bundled photograph resized, shifted by SHIFT pixels per frame."""
    bgr = cv2.imread(str(DEFAULT_IMAGE), cv2.IMREAD_COLOR)
    base = cv2.cvtColor(cv2.resize(bgr, (width, height), interpolation=cv2.INTER_AREA), cv2.COLOR_BGR2RGB)
    return [np.ascontiguousarray(np.roll(base, k * SHIFT, axis=1)) for k in range(count)]


def programs(rgb: list[np.ndarray], event: int, kind: str, at: float, h_total: int, v_total: int,
             out: int) -> list[tuple[np.ndarray, ...]]:  # fmt: skip
    """The beat programs of the frames (gaps in pixel clocks: the CEA blanking), frame `event` cut
    after `at` of its lines and a third of a line, then silent `out` pixel clocks (cut) or none
    (restart)."""
    progs = []
    for k, img in enumerate(rgb):
        h, w = img.shape[:2]
        data, flags, gaps = frame_program(pack(img), h_total - w, (v_total - h) * h_total)
        if k == event:
            keep = round(at * h) * w + w // 3
            data, flags, gaps = data[:keep].copy(), flags[:keep].copy(), gaps[:keep].copy()
            gaps[-1] = out if kind == "cut" else 0
        progs.append((data, flags, gaps))
    return progs


def run_one(name: str, bcfg: dict[str, Any], timeout: int, kind: str, at: float, before: int, after: int,
            rgb: list[np.ndarray], expected: list[Features]) -> dict[str, Any]:  # fmt: skip
    """One event on one configuration and checker: which frames were published."""
    nc = named(bcfg["config"])
    cfg: Config = nc.config()
    h_total, v_total = timing(bcfg)
    pixel_clock = Fraction(str(bcfg["pixel_mhz"])) / bcfg["core_mhz"]
    frame_clocks = int(h_total * v_total / pixel_clock)
    out = h_total * v_total  # the cable out for one frame period
    generics = {**nc.generics("RGB"), "IDLE_TIMEOUT_g": timeout}
    t0 = time.perf_counter()
    sim = FastSim(build_fast(generics))
    build_s = time.perf_counter() - t0
    sim.reset()
    # a DDR build (the board's) is read through the harness's memory, as on the board through u-dma-buf
    accel = OrbAccel(FastBus(sim), bank_read="slot", memory=FastMemory(sim) if is_ddr(generics) else None)
    accel.configure_as(cfg)
    sim.set_live(pixel_clock, FIFO_DEPTH)
    progs = programs(rgb, before, kind, at, h_total, v_total, out if kind == "cut" else 0)
    for prog in progs:
        sim.push(*prog)
    slots = sum(int(gaps.sum()) + len(gaps) for _, _, gaps in progs)
    end = sim.cycle + int(slots / pixel_clock) + 2 * frame_clocks  # every frame is out, and its features
    t0 = time.perf_counter()
    published: list[int | None] = []  # the frame sent, per frame published (None: none matches)
    numbers: list[int] = []
    while sim.cycle < end:
        try:
            frame = accel.next_frame(frame_clocks * 10e-9)  # FastBus: 10 ns per clock
        except TimeoutError:
            continue
        match = [k for k, e in enumerate(expected) if first_difference(frame.features, e) is None]
        published.append(match[0] if match else None)
        numbers.append(frame.number)
    wall = time.perf_counter() - t0
    st, counters = sim.stats(), accel.counters()
    sim.close()
    sent = list(range(before, len(rgb)))  # the event frame and the frames after it
    lost = [k for k in sent if k not in published]
    result = {
        "config": name, "named": nc.name, "idle_timeout": timeout, "event": kind, "at": at,
        "cut_after_pixels": len(progs[before][0]), "pixels": bcfg["width"] * bcfg["height"],
        "cable_out_pixel_clocks": out if kind == "cut" else 0, "timing": [h_total, v_total],
        "pixel_mhz": bcfg["pixel_mhz"], "core_mhz": bcfg["core_mhz"], "fifo_depth": FIFO_DEPTH,
        "frames_before": before, "frames_after": after, "published": published, "frame_numbers": numbers,
        "lost": len(lost), "lost_frames": lost, "wrong": sum(p is None for p in published),
        "before_published": all(k in published for k in range(before)),
        "recovered": (len(rgb) - 1) in published,
        "fifo_dropped": st["fifo_dropped"], "fifo_max": st["fifo_max"],
        "proto_errors": counters["proto_errors"], "discarded": counters["discarded"],
        "clocks": st["cycle"], "sim_wall_s": round(wall, 1), "build_s": round(build_s, 1),
    }  # fmt: skip
    return result


def main(argv: list[str] | None = None) -> int:
    board = load_board(ROOT / "vivado" / "board.json")
    by_name = {c["config"]: k for k, c in board["configs"].items()}
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--configs", nargs="+", default=list(board["configs"]),
                    help=f"board configurations (default: all): {', '.join(board['configs'])} or "
                         f"{', '.join(by_name)}")  # fmt: skip
    ap.add_argument("--idle-timeout", nargs="+", type=int, default=[0, BOARD_TIMEOUT],
                    help="the checkers' IDLE_TIMEOUT_g (default: 0, the old checker, and the board's)")  # fmt: skip
    ap.add_argument("--events", nargs="+", choices=EVENTS, default=list(EVENTS))
    ap.add_argument("--at", type=float, default=0.5, help="where the event frame stops, in frame heights (0.5)")
    ap.add_argument("--before", type=int, default=1, help="good frames before the event (1)")
    ap.add_argument("--after", type=int, default=4, help="good frames after the event (4)")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    if not 0 <= args.at < 1 or args.before < 1 or args.after < 2:
        ap.error("--at must be in [0, 1), --before at least 1, --after at least 2")
    names = []
    for c in args.configs:
        if c not in board["configs"] and c not in by_name:
            ap.error(f"no board configuration {c!r}: {', '.join(board['configs'])} or {', '.join(by_name)}")
        names.append(by_name.get(c, c))
    runs = []
    for name in names:
        bcfg = board["configs"][name]
        cfg = named(bcfg["config"]).config()
        rgb = frames(bcfg["width"], bcfg["height"], args.before + 1 + args.after)
        expected = [extract(rgb_to_luma(img), cfg) for img in rgb]
        for timeout in args.idle_timeout:
            for kind in args.events:
                r = run_one(name, bcfg, timeout, kind, args.at, args.before, args.after, rgb, expected)
                print(f"{name} IDLE_TIMEOUT_g={timeout} {kind}: lost {r['lost']} ({r['lost_frames']}), published "
                      f"{r['published']}, FIFO dropped {r['fifo_dropped']:,}, PROTO_ERRORS {r['proto_errors']}, "
                      f"{r['clocks']:,} clocks in {r['sim_wall_s']} s", flush=True)  # fmt: skip
                runs.append(r)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    command = "python -m orb_flow.board.recovery " + " ".join(sys.argv[1:] if argv is None else argv)
    args.out.write_text(json.dumps({"command": command.strip(), "runs": runs}, indent=1) + "\n")
    print(f"wrote {args.out}")
    bad = [r for r in runs if r["wrong"] or not r["before_published"] or not r["recovered"]]
    for r in bad:
        print(f"error: {r['config']} IDLE_TIMEOUT_g={r['idle_timeout']} {r['event']}: {r['wrong']} frames published "
              f"that match no frame sent; before published {r['before_published']}; recovered {r['recovered']}",
              file=sys.stderr)  # fmt: skip
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
