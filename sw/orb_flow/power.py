# SPDX-License-Identifier: MIT
"""`make power`: an estimate of the accelerator's power and energy per frame without Vivado
(docs/power.md): the synthesised resources of each entity (yosys, orb_flow.synth) times the
switching activity of GHDL's netlist in Verilator on real photographs (orb_sim.fast.activity)
times per-resource 7-series coefficients derived from published Vivado reports
(sw/orb_flow/power_coefficients.json, with their sources).

Per configuration (the board's three of vivado/board.json and the thesis's device):
  1. the synthesis record of orb_accel_zynq with the configuration's generics (build/synth/...:
     reused when its cache key matches hdl/, else `python -m orb_flow.synth` runs: 15-30 min);
  2. the activity build of orb_accel_top (Verilator with toggle coverage; minutes) plays FRAMES
     photographs as the board's HDMI input does (the configuration's pixel clock within the core
     clock, CEA-861 blanking, the 4,096-pixel input FIFO), with the shipped driver reading every
     frame, and counts every net's toggles and every RAM port's enabled clocks over the last
     WINDOW frame periods (the first frames fill the pipeline);
  3. per instance: its activity (toggles per net bit per clock), its module's own cells; per
     resource, coefficient x clock MHz x activity / Vivado's default activity (12.5% toggle; BRAM
     enable 0.5 + write 0.5), so that the vectorless figure (every activity at the default, what
     Vivado's report_power assumes without simulation) is the same sum with the defaults;
  4. the band: the same sums with every coefficient at its low and its high value.

Energy per frame = power / 60 frames a second. Static power is the device's (a constant of the
part at a junction temperature), stated beside the dynamic power, not inside it.

What it does not see (docs/power.md, "Limits"): glitches (a zero-delay simulation counts each net
once a clock; real combinational nets toggle more), routing (a fixed per-net coefficient instead
of each net's capacitance), the HDMI IP and the PS (their published figures are quoted, not
estimated), and everything Vivado would place differently from yosys's mapping.

    python -m orb_flow.power [--configs board-vga ...] [--frames 3] [--window 2] [--out build/power]
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from collections import defaultdict
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from golden_model.config import named
from orb_accel.driver import OrbAccel
from orb_sim.fast.activity import Instance, by_module, parse_coverage
from orb_sim.fast.build import build_fast
from orb_sim.fast.jobs import pack
from orb_sim.fast.sim import FastBus, FastMemory, FastSim, frame_program
from orb_sim.hdl import sources

from . import synth
from .board.recovery import BOARD_TIMEOUT, CEA, FIFO_DEPTH  # the board's input: CEA-861 timing, its FIFO

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "build" / "power"
COEFFICIENTS = Path(__file__).with_name("power_coefficients.json")
BOARD = ROOT / "vivado" / "board.json"
FPS = 60
# The thesis's device (its Table 5.3: 640x480, 2 scales, 32 sectors, 100 MHz, 60 frames a second)
THESIS = {"config": "thesis-vga", "pixel_mhz": 25.175, "core_mhz": 100}
THESIS_TABLE = {  # Table 5.3 of the thesis: (scales, sectors) -> (mW, mJ a frame), Vivado 2020.2
    (1, 16): (149, 2.48), (1, 32): (159, 2.65), (1, 64): (167, 2.78),
    (2, 16): (290, 4.8), (2, 32): (312, 5.2), (2, 64): (328, 5.5),
}  # fmt: skip
PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "camera")  # scikit-image's real photographs
BANDS = ("typ", "low", "high")
SIM_TOP = "orb_accel_top"  # the activity build's top (orb_sim.fast); the synthesis's is orb_accel_zynq


class PowerError(RuntimeError):
    """A step could not run (its message says which and why)."""


def log(msg: str) -> None:
    print(f"power: {msg}", flush=True)


# ---- inputs ----------------------------------------------------------------------------------------
def load_coefficients(path: Path = COEFFICIENTS) -> dict[str, Any]:
    data = json.loads(path.read_text())
    for k in ("lut", "carry4", "ff", "signal", "clock_ff", "clock_tree", "bram36", "dsp"):
        c = data["coefficients"].get(k)
        if c is None or not c["low"] <= c["typ"] <= c["high"]:
            raise PowerError(f"{path}: coefficient {k!r} missing or outside its band")
    return data


def configurations() -> dict[str, dict[str, Any]]:
    """Name -> the configuration's pixel and core clocks (vivado/board.json's, and the thesis's)."""
    board = json.loads(BOARD.read_text())
    out = {c["config"]: {"config": c["config"], "pixel_mhz": c["pixel_mhz"], "core_mhz": c["core_mhz"]}
           for c in board["configs"].values()}  # fmt: skip
    out[THESIS["config"]] = dict(THESIS)
    return out


def photographs(width: int, height: int, count: int) -> list[np.ndarray]:
    """`count` RGB frames: scikit-image's colour photographs resized to the frame (cycled)."""
    import cv2
    import skimage.data as data

    out = []
    for k in range(count):
        img = getattr(data, PHOTOS[k % len(PHOTOS)])()
        if img.ndim == 2:
            img = np.stack([img] * 3, axis=-1)
        out.append(np.ascontiguousarray(cv2.resize(img[..., :3], (width, height), interpolation=cv2.INTER_AREA)))
    return out


# ---- synthesis: each module's own cells -------------------------------------------------------------
def module_cells(stat_text: str) -> dict[str, dict[str, Any]]:
    """yosys's hierarchical `stat` -> module -> its own cells, summarised (a module without cells of
    its own: all zero)."""
    return {m: s or synth.summarise({}) for m, s in synth.module_summaries(stat_text).items()}


def module_instances(stat_text: str) -> dict[str, int]:
    """yosys's `design hierarchy` section: module -> its number of instances in the design."""
    m = re.search(r"^=== design hierarchy ===$(.*?)^\s+Number of", stat_text, flags=re.M | re.S)
    if not m:
        raise PowerError("the synthesis's stat.txt has no design hierarchy (a flat design?)")
    return {g[1]: int(g[2]) for g in re.finditer(r"^\s+(\S+)\s+(\d+)$", m[1], flags=re.M)}


def synthesis(name: str, timeout: float) -> tuple[dict[str, Any], Path]:
    """The synthesis record of the board top with configuration `name` and its stat.txt, run now
    when build/synth holds none for today's hdl/."""
    job = synth.named_job("orb_accel_zynq", name)
    cdir = job.dir(synth.OUT)
    ghdl, yosys = synth.find_tools()
    tools = {"ghdl": synth.tool_version([ghdl, "--version"]), "yosys": synth.tool_version([yosys, "-V"])}
    key = synth.cache_key(job.top, job.generics, sources(), tools)
    rec = synth.load_cached(cdir, key)
    if rec is None:
        log(f"{name}: synthesising orb_accel_zynq (yosys, about 15-30 min; build/synth/)")
        cmd = [sys.executable, "-m", "orb_flow.synth", "--top", "orb_accel_zynq", "--named", name,
               "--timeout", str(int(timeout))]  # fmt: skip
        subprocess.run(cmd, cwd=ROOT, check=False)
        rec = synth.load_cached(cdir, key)
        if rec is None:
            raise PowerError(f"{name}: synthesis gave no record in {cdir} (see its log above)")
    return rec, cdir / "stat.txt"


# ---- activity ---------------------------------------------------------------------------------------
def board_generics(name: str) -> dict[str, int | str]:
    """orb_accel_top's generics as the board top orb_accel_zynq sets them for configuration `name`
    (dvi2rgb's RBG input, the HDMI idle timeout, the DDR window of vivado/board.json), so that the
    simulated modules are the synthesised ones, name for name."""
    ddr = json.loads(BOARD.read_text())["feat_dma"]
    return {**named(name).generics("RBG"), "IDLE_TIMEOUT_g": BOARD_TIMEOUT, "WIN_BASE_MB_g": ddr["win_base_mb"],
            "WIN_SIZE_MB_g": ddr["win_size_mb"]}  # fmt: skip


@dataclass
class Activity:
    instances: dict[str, Instance]
    clocks: int
    frames_published: int
    features: list[int]
    build_s: float
    sim_s: float
    fifo_dropped: int | None = None  # pixels the input FIFO dropped (the core fell behind); None: not counted


def run_activity(name: str, pixel_mhz: float, core_mhz: float, frames: int, window: int, cov: Path) -> Activity:
    """The activity build of `name` plays `frames` photographs at the board's input timing; the
    toggle counters cover the last `window` frame periods. Cached: `cov` and its .json beside it
    are reused while the library (its hash covers the netlist) and the run's settings are the same."""
    nc = named(name)
    cfg = nc.config()
    generics = board_generics(name)
    h_total, v_total = CEA[(cfg.width, cfg.height)]
    pixel_clock = Fraction(str(pixel_mhz)) / Fraction(str(core_mhz))
    frame_clocks = int(h_total * v_total / pixel_clock)
    log(f"{name}: building the activity model (Verilator with toggle coverage; cached in build/fastsim)")
    t0 = time.perf_counter()
    lib = build_fast(generics, toggle_coverage=True)
    build_s = time.perf_counter() - t0
    key = {"library": lib.parent.name, "frames": frames, "window": window, "pixel_mhz": pixel_mhz,
           "core_mhz": core_mhz, "photos": PHOTOS, "fifo": FIFO_DEPTH}  # fmt: skip
    meta = cov.with_suffix(".json")
    if cov.exists() and meta.exists():
        old = json.loads(meta.read_text())
        if old.get("key") == json.loads(json.dumps(key)):
            log(f"{name}: activity of {old['clocks']:,} clocks reused ({cov})")
            return Activity(parse_coverage(cov), old["clocks"], old["frames_published"], old["features"],
                            old["build_s"], old["sim_s"], old.get("fifo_dropped"))  # fmt: skip
    sim = FastSim(lib)
    sim.reset()
    ddr = generics.get("MEM_KIND_g") == "DDR"
    accel = OrbAccel(FastBus(sim), bank_read="slot", memory=FastMemory(sim) if ddr else None)
    accel.configure_as(cfg)
    sim.set_live(pixel_clock, FIFO_DEPTH)
    for img in photographs(cfg.width, cfg.height, frames):  # dvi2rgb's order (INPUT_g "RBG"): R, B, G
        sim.push(*frame_program(pack(img[..., [0, 2, 1]]), h_total - cfg.width, (v_total - cfg.height) * h_total))
    log(f"{name}: playing {frames} frames at {pixel_mhz} MHz pixels in a {core_mhz} MHz core "
        f"({frame_clocks:,} clocks a frame; toggles over the last {window})")  # fmt: skip
    t0 = time.perf_counter()
    start = sim.cycle + (frames - window) * frame_clocks
    end = start + window * frame_clocks
    features: list[int] = []
    zeroed = False
    while sim.cycle < end:
        if not zeroed and sim.cycle >= start:
            sim.coverage_zero()
            zeroed, start = True, sim.cycle
        limit = (start if not zeroed else end) - sim.cycle
        try:
            frame = accel.next_frame(max(limit, 1) * 10e-9)  # FastBus: 10 ns a clock
            features.append(len(frame.features))
        except TimeoutError:
            continue
    if not zeroed:
        raise PowerError(f"{name}: the window never started")
    sim.coverage_write(cov)
    clocks = sim.cycle - start
    sim_s = round(time.perf_counter() - t0, 1)
    dropped = sim.stats()["fifo_dropped"]
    sim.close()
    if dropped:
        raise PowerError(f"{name}: the input FIFO dropped {dropped:,} pixels: the core did not keep up with the "
                         f"stream at {core_mhz} MHz, so this is not the board's activity")  # fmt: skip
    act = Activity(parse_coverage(cov), clocks, len(features), features, round(build_s, 1), sim_s, dropped)
    meta.write_text(json.dumps({"key": key, "clocks": clocks, "frames_published": len(features),
                                "features": features, "build_s": act.build_s, "sim_s": sim_s,
                                "fifo_dropped": dropped}, indent=1) + "\n")  # fmt: skip
    return act


# ---- the estimate -----------------------------------------------------------------------------------
ENTITY_RE = re.compile(r"^(orb_[a-z0-9]+(?:_[a-z]+)*?)(?:_\d\w*|_[0-9a-f]{40})?$")


def entity_of(module: str) -> str:
    """GHDL's module name -> the entity's (orb_line_buffer_640_2_19_1 -> orb_line_buffer)."""
    m = ENTITY_RE.match(module)
    return m[1] if m else module


def estimate(act: Activity, cells: dict[str, dict[str, Any]], instances: dict[str, int], core_mhz: float,
             coef: dict[str, Any], band: str = "typ", vectorless: bool = False) -> dict[str, Any]:  # fmt: skip
    """Dynamic power in mW per entity and per resource class from each module's own cells x its
    instances (yosys) and its activity (the coverage). `vectorless`: every activity at Vivado's
    default (toggle 12.5%, BRAM enable 0.5 and write 0.5)."""
    c = {k: v[band] for k, v in coef["coefficients"].items()}
    d = coef["defaults"]
    by_entity: dict[str, dict[str, float]] = defaultdict(lambda: defaultdict(float))
    activity: dict[str, list[float]] = defaultdict(lambda: [0.0, 0.0])  # entity -> [toggles, bit-clocks]
    bram_en: dict[str, list[float]] = defaultdict(lambda: [0.0, 0.0, 0.0])  # entity -> [rd, wr, tiles] weighted
    unprobed = [0.0, 0.0]  # block RAM at the default enables (no probe): uW, tiles
    modules = by_module(act.instances)
    # the simulated top is GHDL's `orb_accel_top`; in the board top's synthesis it carries its generics
    tops = [m for m in cells if entity_of(m) == SIM_TOP]
    if SIM_TOP in modules and SIM_TOP not in cells and len(tops) == 1:
        modules[tops[0]] = modules.pop(SIM_TOP)
    missing = sorted(m for m in modules if m not in cells)
    for mod, k in cells.items():
        n = instances.get(mod, 1)
        ent = entity_of(mod)
        cov = modules.get(mod)
        if cov is None:
            if not any(k[x] for x in ("lut", "ff", "dsp", "bram36")):
                continue
            ent += " (not simulated)"  # the board wrapper: at the default activity
        alpha = cov.toggles / (cov.bits * n * act.clocks) if cov and cov.bits else 0.0
        if cov and cov.bits:
            activity[ent][0] += cov.toggles
            activity[ent][1] += cov.bits * n * act.clocks
        r = 1.0 if vectorless or cov is None else alpha / d["toggle"]
        if vectorless or cov is None or cov.rd_clocks is None:
            en_rd, en_wr = d["bram_enable"], d["bram_write"]
        else:
            en_rd, en_wr = cov.rd_clocks / (n * act.clocks), (cov.wr_clocks or 0) / (n * act.clocks)
        tiles = n * (k["ramb36"] + k["ramb18"] / 2)
        luts = n * (k["lut_logic"] + k["srl"] + k["lutram"])
        ffs, carry, dsp = n * k["ff"], n * k["carry4"], n * k["dsp"]
        p = by_entity[ent]
        p["lut"] += luts * c["lut"] * core_mhz * r
        p["carry4"] += carry * c["carry4"] * core_mhz * r
        p["ff"] += ffs * c["ff"] * core_mhz * r
        p["signal"] += (luts + ffs + carry) * c["signal"] * core_mhz * r
        p["dsp"] += dsp * c["dsp"] * core_mhz * r
        # a tile's coefficient is at enable 0.5 + write 0.5: there its ports' enables sum to 1
        bram = tiles * c["bram36"] * core_mhz * (en_rd + en_wr) / (d["bram_enable"] + d["bram_write"])
        p["bram"] += bram
        if tiles and (cov is None or cov.rd_clocks is None):  # no probe: a memory outside orb_sdp_ram
            unprobed[0] += bram
            unprobed[1] += tiles
        p["clock"] += (ffs + n * (k["srl"] + k["lutram"])) * c["clock_ff"] * core_mhz
        if tiles:
            b = bram_en[ent]
            b[0] += en_rd * tiles
            b[1] += en_wr * tiles
            b[2] += tiles
    by_entity["clock tree"]["clock"] += c["clock_tree"] * core_mhz
    entities = {e: {k: round(v / 1000, 3) for k, v in p.items()} for e, p in by_entity.items()}  # uW -> mW
    for e, p in entities.items():
        p["total"] = round(sum(p.values()), 3)
        if activity[e][1]:
            p["activity"] = round(activity[e][0] / activity[e][1], 5)
        if bram_en[e][2]:
            p["bram_read_enable"] = round(bram_en[e][0] / bram_en[e][2], 4)
            p["bram_write_enable"] = round(bram_en[e][1] / bram_en[e][2], 4)
    classes = ("lut", "carry4", "ff", "signal", "dsp", "bram", "clock")
    by_class = {k: round(sum(p.get(k, 0.0) for p in entities.values()), 2) for k in classes}
    tog = sum(a[0] for a in activity.values())
    bit_clocks = sum(a[1] for a in activity.values())
    return {
        "dynamic_mw": round(sum(by_class.values()), 1),
        "by_class_mw": by_class,
        "by_entity_mw": dict(sorted(entities.items(), key=lambda kv: -kv[1]["total"])),
        "mean_activity": round(tog / bit_clocks, 5) if bit_clocks else 0.0,
        "bram_unprobed": {"mw": round(unprobed[0] / 1000, 2), "tiles": unprobed[1]},
        "unmatched_modules": missing,
        "unsimulated_modules": sorted(
            e.removesuffix(" (not simulated)") for e in entities if e.endswith("(not simulated)")
        ),
    }


def power_record(name: str, conf: dict[str, Any], synth_rec: dict[str, Any], stat_text: str, act: Activity,
                 coef: dict[str, Any]) -> dict[str, Any]:  # fmt: skip
    core = conf["core_mhz"]
    cells, inst = module_cells(stat_text), module_instances(stat_text)
    runs = {band: estimate(act, cells, inst, core, coef, band) for band in BANDS}
    vec = {band: estimate(act, cells, inst, core, coef, band, vectorless=True) for band in BANDS}
    static = coef["static"]
    nc = named(name)
    cfg = nc.config()
    rec = {
        "config": name, "width": cfg.width, "height": cfg.height, "scales": cfg.scales, "sectors": cfg.sectors,
        "pixel_mhz": conf["pixel_mhz"], "core_mhz": core, "fps": FPS,
        "resources": {k: synth_rec.get(k) for k in ("lut", "ff", "bram36", "dsp")},
        "synth_measured": {"date": synth_rec.get("date"), "hdl_revision": synth_rec.get("hdl_revision")},
        "activity_clocks": act.clocks, "frames_published": act.frames_published, "features": act.features,
        "fifo_dropped": act.fifo_dropped,
        "mean_activity": runs["typ"]["mean_activity"],
        "dynamic_mw": {b: runs[b]["dynamic_mw"] for b in BANDS},
        "dynamic_vectorless_mw": {b: vec[b]["dynamic_mw"] for b in BANDS},
        "energy_mj": {b: round(runs[b]["dynamic_mw"] / FPS, 2) for b in BANDS},
        "energy_vectorless_mj": {b: round(vec[b]["dynamic_mw"] / FPS, 2) for b in BANDS},
        "static_device_w": static["device_w"], "static_pl_w": static["pl_w"], "static_tj_c": static["tj_c"],
        "by_class_mw": runs["typ"]["by_class_mw"], "by_class_vectorless_mw": vec["typ"]["by_class_mw"],
        "by_entity_mw": runs["typ"]["by_entity_mw"],
        "bram_unprobed": runs["typ"]["bram_unprobed"],
        "unmatched_modules": runs["typ"]["unmatched_modules"],
        "unsimulated_modules": runs["typ"]["unsimulated_modules"],
        "build_s": act.build_s, "sim_s": act.sim_s,
    }  # fmt: skip
    if (cfg.scales, cfg.sectors) in THESIS_TABLE and name == THESIS["config"]:
        rec["thesis_mw"], rec["thesis_mj"] = THESIS_TABLE[(cfg.scales, cfg.sectors)]
    return rec


def summary(rec: dict[str, Any]) -> str:
    d, v, e = rec["dynamic_mw"], rec["dynamic_vectorless_mw"], rec["energy_mj"]
    top = list(rec["by_entity_mw"].items())[:4]
    lines = [
        f"{rec['config']}: dynamic {d['typ']:.0f} mW (band {d['low']:.0f}-{d['high']:.0f}) at "
        f"{rec['core_mhz']} MHz, {e['typ']} mJ a frame at {FPS} fps; vectorless {v['typ']:.0f} mW; "
        f"mean activity {100 * rec['mean_activity']:.2f}% (Vivado's default 12.5%); device static "
        f"{rec['static_device_w'] * 1000:.0f} mW",
        "  largest: " + ", ".join(f"{k} {p['total']:.1f} mW" for k, p in top),
    ]
    if "thesis_mw" in rec:
        lines.append(f"  the thesis's Table 5.3 for this device: {rec['thesis_mw']} mW, {rec['thesis_mj']} mJ a frame")
    if rec["unmatched_modules"]:
        lines.append(f"  warning: modules simulated but not in the synthesis: {', '.join(rec['unmatched_modules'])}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    confs = configurations()
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--configs", nargs="+", default=list(confs), help=f"configurations (default all: {', '.join(confs)})"
    )
    ap.add_argument("--frames", type=int, default=3, help="photographs played (default 3)")
    ap.add_argument("--window", type=int, default=2, help="frame periods the toggles cover: the last ones (default 2)")
    ap.add_argument("--core-mhz", type=float, help="the core clock instead of the configuration's (a what-if)")
    ap.add_argument("--timeout", type=float, default=9000, help="seconds for a synthesis run (default 9000)")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    bad = [c for c in args.configs if c not in confs]
    if bad:
        ap.error(f"unknown configuration(s) {', '.join(bad)}: known {', '.join(confs)}")
    if not 1 <= args.window < args.frames:
        ap.error("--window must be at least 1 and below --frames (the first frame fills the pipeline)")
    coef = load_coefficients()
    args.out.mkdir(parents=True, exist_ok=True)
    recs = []
    command = "python -m orb_flow.power " + " ".join(sys.argv[1:] if argv is None else argv)
    try:
        for name in args.configs:
            core = args.core_mhz
            conf = {**confs[name], **({"core_mhz": int(core) if core.is_integer() else core} if core else {})}
            if conf["core_mhz"] < conf["pixel_mhz"]:
                raise PowerError(f"{name}: a core clock of {conf['core_mhz']} MHz is below the pixel clock")
            srec, stat = synthesis(name, args.timeout)
            act = run_activity(name, conf["pixel_mhz"], conf["core_mhz"], args.frames, args.window,
                               args.out / f"{name}.coverage.dat")  # fmt: skip
            rec = power_record(name, conf, srec, stat.read_text(), act, coef)
            (args.out / f"{name}.json").write_text(json.dumps(rec, indent=1) + "\n")
            print(summary(rec), flush=True)
            recs.append(rec)
    except PowerError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    (args.out / "power.json").write_text(json.dumps({"command": command.strip(), "runs": recs}, indent=1) + "\n")
    log(f"wrote {args.out / 'power.json'}; record it with `python -m orb_flow.record power`, then `make views`")
    return 1 if any(r["unmatched_modules"] for r in recs) else 0


if __name__ == "__main__":
    sys.exit(main())
