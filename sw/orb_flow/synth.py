#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Synthesis estimate of the accelerator without Vivado: GHDL -> Verilog -> yosys synth_xilinx.

A job is a top (orb_core, orb_accel_top or orb_accel_zynq) with a configuration WIDTH_g x HEIGHT_g
x SCALES_g (plus the top's extra generics in TOPS). For each job, in build/synth/<top>/<W>x<H>x<S>/:
  1. `ghdl synth --std=08 -gWIDTH_g=.. -gHEIGHT_g=.. -gSCALES_g=.. [-gMEM_DEPTH_g=.. -gINPUT_g=..]
     --out=verilog <hdl sources in manifest order> -e <top>` -> top.v (GHDL's inferred-RAM notes
     are kept in ghdl.log and in the record);
  2. yosys `synth_xilinx -family xc7 -top <top>; stat` -> resource counts (stat.txt);
  3. only with --sta (make synth STA=1; slow: 4.5-7.5 min per job measured): yosys `synth_xilinx
     -family xc7 -abc9 -flatten ...; sta` -> longest pre-route arrival time (sta.txt), the
     logic-delay estimate: cell delays from yosys's xc7 models, no routing. Without it
     logic_delay_ns is null.

Default set (make synth): orb_core 640x480x1 and 1920x1080x2, resources only (3.5-7 min wall
measured with 2 jobs on a shared 2-core machine). At the end the script prints how long the other
known jobs (OTHER_JOBS) and the sta pass would take, from the last measured wall times
(build/synth/times.json, else the wall_s in synth_expected.json), or "unknown".

Cache: each job's record is kept in its directory (record.json) with a cache key, a SHA-256 of the
HDL sources (orb_sim.hdl.sources(), the manifest's files in order, by name and content), the top,
the generics, FLOW_VERSION, the yosys scripts and the GHDL/yosys versions. A job whose key matches
and which has the requested passes is not run again; a second `make synth` takes seconds.

Results: build/synth/report.json (one record per top and configuration; records of other jobs
already there are kept) and build/synth/report.md (table), both rewritten as soon as a pass of a
job finishes, not at the end.

Expected values: sw/orb_flow/synth_expected.json holds, per "<top> <W>x<H>x<S>", the lut, ff,
bram36, dsp (and optionally logic_delay_ns) measured at a given commit, and a tolerance in percent.
Every record produced or reused is compared against them; a figure outside the tolerance (higher:
a regression; lower: an improvement, or logic optimised away; either way the expectation is out of
date) is reported with expected, got and tolerance and makes the exit status 1. A job without an
entry is reported as "no expectation".

Counting: lut = LUT1..LUT6 + SRL16E/SRLC32E + LUT-RAM cells in LUTs (as Vivado's "Slice LUTs");
ff = FDRE + FDSE + FDCE + FDPE; bram36 = RAMB36E1 + RAMB18E1 / 2; dsp = DSP48E1.
These are yosys estimates, not Vivado results (see docs/synthesis.md).

Work-arounds for tool bugs, each recorded in the record's "workarounds" list:
  - GHDL 2.0's Verilog writer: `abs` printed as VHDL, zero-width nets, nets declared twice, and the
    orb_feat_merge crash at SCALES_g = 1: repaired by orb_sim.verilog_netlist (shared with the fast
    simulation in Verilator; its docstring lists each repair); top.ghdl.v is GHDL's raw output,
    top.v the file yosys reads.
  - yosys 0.23's -abc9 flow aborts in abc9_ops (std::out_of_range) when a RAMB36E1/RAMB18E1 cell
    still has the oversized DI/DO ports its BRAM mapper creates; the timing pass runs synth_xilinx
    in two halves with `hierarchy -check` (which resizes those ports) before map_luts.
  - yosys 0.23's sta finds no timing arcs for CARRY4 (and MUXF7/F8) after synth_xilinx and skips
    every carry chain; the cell models are read again with their specify blocks before `sta`.
    LUT-RAM cells stay untimed (listed in the record's sta.untimed_cell_types).

Usage: python3 -m orb_flow.synth [--top T] [--config WxHxS ...] [--sta] [--jobs N] [--timeout S] [--out D]
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Collection, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from orb_flow import (
    digest,
    timing,
)  # the hdl/ digest of a record (orb_flow.digest); the worst-paths report of the timing pass's netlist
from orb_flow.device import DEVICE  # the XC7Z020, once
from orb_sim.hdl import sources  # the one list of hdl files: hdl/manifest.txt
from orb_sim.verilog_netlist import VerilogError, ghdl_verilog  # GHDL's Verilog, repaired

ROOT = Path(__file__).resolve().parents[2]

OUT = ROOT / "build" / "synth"
EXPECTED = Path(__file__).resolve().with_name("synth_expected.json")

# Bump when a change to this script changes the figures or the record's meaning: it is part of the
# cache key, so every cached record is measured again.
FLOW_VERSION = 4  # 4: the timing pass keeps its netlist (net.json) for the worst-paths report

# The tops the script knows and the generics each gets besides WIDTH_g, HEIGHT_g, SCALES_g
# (their defaults, given explicitly so that they are in the record and the cache key).
TOPS: dict[str, dict[str, int | str]] = {
    "orb_core": {},
    "orb_accel_top": {"MEM_DEPTH_g": 1024, "INPUT_g": "RGB", "MEM_KIND_g": "BRAM"},
    "orb_accel_zynq": {"MEM_DEPTH_g": 1024, "INPUT_g": "RBG", "MEM_KIND_g": "BRAM"},
}
DEFAULT_TOP = "orb_core"
# make synth: (top, "WxHxS"), resources only; documented in docs/synthesis.md
DEFAULT_JOBS = (
    ("orb_core", "640x480x1"),
    ("orb_core", "1920x1080x2"),
)
# Known but not run by default; the end of a default run prints their estimated times.
OTHER_JOBS = (
    ("orb_core", "640x480x2"),
    ("orb_core", "1280x720x2"),
    ("orb_core", "1920x1080x1"),
    ("orb_core", "1920x1080x4"),
    ("orb_accel_top", "640x480x2"),
    ("orb_accel_top", "1920x1080x2"),
    ("orb_accel_zynq", "640x480x1"),
    ("orb_accel_zynq", "1920x1080x2"),
)
# The pre-route logic-delay goal of a register-to-register path (docs/synthesis.md, "Timing"): at
# most 3.5 ns leaves about half of the 6.67 ns period of a 150 MHz core clock to routing.
TIMING_GOAL_NS = 3.5
# the figures synth_expected.json may give and the check compares
CHECKED = ("lut", "ff", "bram36", "dsp", "logic_delay_ns")
BLOCK_FIGURES = ("lut", "ff", "bram36", "dsp")
WORST_KEPT = 5  # worst paths (distinct endpoint registers) an expected-values entry keeps
# XC7Z020 (Zybo Z7-20) capacity

LUT_CELLS = ("LUT1", "LUT2", "LUT3", "LUT4", "LUT5", "LUT6")
SRL_CELLS = ("SRL16E", "SRLC16E", "SRLC32E")
FF_CELLS = ("FDRE", "FDSE", "FDCE", "FDPE")
# distributed-RAM primitives and the LUTs each occupies
LUTRAM_CELLS = {
    "RAM16X1S": 1,
    "RAM32X1S": 1,
    "RAM64X1S": 1,
    "RAM16X1D": 2,
    "RAM32X1D": 2,
    "RAM64X1D": 2,
    "RAM128X1S": 2,
    "RAM128X1D": 4,
    "RAM256X1S": 4,
    "RAM32M": 4,
    "RAM64M": 4,
    "RAM32M16": 8,
    "RAM64M8": 8,
}

ARRIVAL_RE = re.compile(r"Latest arrival time in '(\S+)' is (\d+):")

STAT_SCRIPT = """read_verilog top.v
synth_xilinx -family xc7 -top {top}
tee -o stat.txt stat
"""
# -abc9 -flatten as one synth_xilinx, split before map_luts so that `hierarchy -check` can resize
# the BRAM cells' ports first (yosys 0.23 abc9_ops aborts on them otherwise). The cell models are
# read again with their specify blocks before `sta`: without that, yosys 0.23's sta has no timing
# arcs for CARRY4 ("Module 'CARRY4' has no timing arcs!") and silently skips every carry chain.
STA_SCRIPT = """read_verilog top.v
synth_xilinx -family xc7 -abc9 -flatten -top {top} -run begin:map_luts
hierarchy -check
synth_xilinx -family xc7 -abc9 -flatten -top {top} -run map_luts:
tee -o sta_stat.txt stat
write_json -compat-int net.json
read_verilog -lib -specify -overwrite +/xilinx/cells_sim.v
tee -o sta.txt sta
"""
PASSES = {"stat": ("yosys_stat", STAT_SCRIPT), "sta": ("yosys_sta", STA_SCRIPT)}


class ToolError(VerilogError):
    """A tool failed (GHDL's errors come as VerilogError, this class's base)."""


@dataclass(frozen=True)
class Config:
    width: int
    height: int
    scales: int

    @property
    def name(self) -> str:
        return f"{self.width}x{self.height}x{self.scales}"

    @property
    def generics(self) -> dict[str, int]:
        return {"WIDTH_g": self.width, "HEIGHT_g": self.height, "SCALES_g": self.scales}


def parse_config(text: str) -> Config:
    m = re.fullmatch(r"(\d+)x(\d+)x(\d+)", text.strip().lower())
    if not m:
        raise argparse.ArgumentTypeError(f"config must look like 1920x1080x2 (W x H x scales), got {text!r}")
    w, h, s = (int(g) for g in m.groups())
    if not (64 <= w <= 1920 and 48 <= h <= 1080 and 1 <= s <= 8):
        raise argparse.ArgumentTypeError(f"{text}: the tops allow W 64..1920, H 48..1080, scales 1..8")
    return Config(w, h, s)


@dataclass(frozen=True)
class Job:
    top: str
    cfg: Config
    extra: tuple[tuple[str, str], ...] = ()  # --generic overrides (NAME, VALUE), e.g. the board's

    @property
    def name(self) -> str:
        """The job's name, also its key in synth_expected.json and times.json: '<top> <W>x<H>x<S>',
        followed by ' NAME=VALUE' for each --generic override."""
        return " ".join([self.top, self.cfg.name, *(f"{k}={v}" for k, v in self.extra)])

    @property
    def generics(self) -> dict[str, int | str]:
        return {**self.cfg.generics, **TOPS[self.top], **dict(self.extra)}

    def dir(self, out: Path) -> Path:
        return out / self.top / "_".join([self.cfg.name, *(f"{k}{v}" for k, v in self.extra)])


def parse_generic(text: str) -> tuple[str, str]:
    """'MEM_DEPTH_g=2048' -> ('MEM_DEPTH_g', '2048'); only the generics a top already has can be set."""
    name, sep, value = text.partition("=")
    known = (
        {"WIDTH_g", "HEIGHT_g", "SCALES_g"}
        | {k for g in TOPS.values() for k in g}
        | {"SECTORS_g", "STEP_NUM_g", "STEP_DEN_g", "BLOCK_LOG2_g"}
    )
    if not sep or not value or name not in known:
        raise argparse.ArgumentTypeError(f"--generic takes NAME=VALUE with NAME one of {sorted(known)}, got {text!r}")
    return name, value


def job(top: str, config: str) -> Job:
    if top not in TOPS:
        raise ValueError(f"unknown top {top!r}; known: {', '.join(TOPS)}")
    return Job(top, parse_config(config))


def parse_job_name(name: str) -> Job:
    """'orb_core 640x480x1' or 'orb_accel_zynq 640x480x4 MEM_DEPTH_g=1024 ...' -> Job
    (ValueError/ArgumentTypeError if the top, the config or a generic is unknown)."""
    top, _, rest = name.partition(" ")
    config, *generics = rest.split()
    j = job(top, config)
    return Job(j.top, j.cfg, tuple(parse_generic(g) for g in generics))


def generics_job(top: str, c: dict[str, Any]) -> Job:
    """A configuration's job (a board configuration of vivado/board.json or a named configuration of
    golden_model/data/configs.json): WxHxS and MEM_DEPTH_g, and the generics that differ from the
    tops' defaults (so that the names and the cache keys are sw/orb_flow/board/estimate.py's)."""
    extra = [("MEM_DEPTH_g", str(c["mem_depth"]))]
    if c["sectors"] != 32:
        extra.append(("SECTORS_g", str(c["sectors"])))
    if (c["step_num"], c["step_den"]) != (2, 1):
        extra += [("STEP_NUM_g", str(c["step_num"])), ("STEP_DEN_g", str(c["step_den"]))]
    if c["block_log2"] != 3:
        extra.append(("BLOCK_LOG2_g", str(c["block_log2"])))
    if c.get("mem_kind", "bram") != "bram":  # the tops' default MEM_KIND_g "BRAM"
        extra.append(("MEM_KIND_g", c["mem_kind"].upper()))
    return Job(top, parse_config(f"{c['width']}x{c['height']}x{c['scales']}"), tuple(extra))


def board_jobs() -> list[Job]:
    """The board's configurations (vivado/board.json) as sw/orb_flow/board/estimate.py runs them: the
    whole accelerator orb_accel_zynq with each configuration's generics."""
    board = json.loads((ROOT / "vivado" / "board.json").read_text())
    return [generics_job(board["accel"]["entity"], c) for c in board["configs"].values()]


def named_job(top: str, name: str) -> Job:
    """`--named NAME`: the named configuration's generics (docs/configurations.md) on `top`."""
    configs = json.loads((ROOT / "golden_model" / "data" / "configs.json").read_text())["configs"]
    if name not in configs:
        raise ValueError(f"no configuration named {name!r}; known: {', '.join(configs)}")
    return generics_job(top, configs[name])


def cache_key(top: str, generics: dict[str, int | str], files: Sequence[Path], tools: dict[str, str]) -> str:
    """SHA-256 over what a job's figures depend on: every HDL source (name and content, in compile
    order), the top, its generics, FLOW_VERSION, the yosys scripts and the tool versions."""
    h = hashlib.sha256()
    meta = {
        "flow": FLOW_VERSION,
        "top": top,
        "generics": {k: generics[k] for k in sorted(generics)},
        "scripts": [STAT_SCRIPT, STA_SCRIPT],
        "tools": {k: tools[k] for k in sorted(tools)},
    }
    h.update(json.dumps(meta, sort_keys=True).encode())
    for f in files:
        h.update(b"\0" + f.name.encode() + b"\0" + hashlib.sha256(f.read_bytes()).digest())
    return h.hexdigest()


def load_expected(path: Path = EXPECTED) -> dict[str, Any]:
    """synth_expected.json, checked for shape: {"tolerance_pct": x, "jobs": {"<top> <cfg>": {...}}}."""
    data = json.loads(path.read_text())
    if not isinstance(data.get("tolerance_pct"), (int, float)) or data["tolerance_pct"] < 0:
        raise ValueError(f"{path}: 'tolerance_pct' must be a non-negative number")
    jobs = data.get("jobs")
    if not isinstance(jobs, dict):
        raise ValueError(f"{path}: 'jobs' must be an object keyed by '<top> <W>x<H>x<S>'")
    for name, entry in jobs.items():
        try:
            parse_job_name(name)
        except (ValueError, argparse.ArgumentTypeError) as exc:
            raise ValueError(f"{path}: {name!r}: {exc}") from None
        if not any(k in entry for k in CHECKED):
            raise ValueError(f"{path}: {name} has none of {', '.join(CHECKED)}")
        for k in CHECKED:
            if k in entry and not isinstance(entry[k], (int, float)):
                raise ValueError(f"{path}: {name}.{k} must be a number")
    return data


def num(x: float) -> str:
    return f"{x:,.0f}" if abs(x) >= 1000 else f"{x:.4g}"


@dataclass(frozen=True)
class Check:
    status: str  # "ok", "fail" or "no expectation"
    messages: tuple[str, ...]  # one per figure outside the tolerance, and notes

    def as_dict(self) -> dict[str, Any]:
        return {"status": self.status, "messages": list(self.messages)}


def check_record(rec: dict[str, Any], expected: dict[str, Any]) -> Check:
    """Compare a record's figures with its expectation (load_expected's data)."""
    name = rec.get("job") or f"{rec['top']} {rec['width']}x{rec['height']}x{rec['scales']}"
    entry = expected["jobs"].get(name)
    if entry is None:
        return Check("no expectation", ())
    tol = float(entry.get("tolerance_pct", expected["tolerance_pct"]))
    fails: list[str] = []
    notes: list[str] = []
    for k in CHECKED:
        if k not in entry:
            continue
        exp, got = entry[k], rec.get(k)
        if got is None:
            why = "sta not run (STA=1)" if k == "logic_delay_ns" else "no figure (the run failed)"
            (notes if k == "logic_delay_ns" else fails).append(f"{name}: {k} expected {exp:,}, not checked: {why}")
            continue
        dev = abs(got - exp)
        if dev <= abs(exp) * tol / 100 + 1e-9:
            continue
        rel = f"{100 * (got - exp) / exp:+.1f} %" if exp else f"{got - exp:+g}"
        kind = "higher: a regression" if got > exp else "lower: better, or logic optimised away; check, then update"
        fails.append(
            f"{name}: {k} expected {exp:,} ± {tol:g} % ({num(exp * (1 - tol / 100))}..{num(exp * (1 + tol / 100))}), "
            f"got {got:,} ({rel}, {kind})"
        )
    return Check("fail" if fails else "ok", tuple(fails + notes))


def find_tools() -> tuple[str, str]:
    """Paths of ghdl (any back end) and yosys, or exit 1 with the install commands."""
    ghdl = next((p for p in (shutil.which(n) for n in ("ghdl", "ghdl-llvm", "ghdl-mcode")) if p), None)
    yosys = shutil.which("yosys")
    missing = []
    if ghdl is None:
        missing.append(("GHDL", "apt-get install ghdl-llvm"))
    if yosys is None:
        missing.append(("yosys", "apt-get install yosys"))
    for tool, cmd in missing:
        print(f"error: {tool} is not installed; install it with: {cmd}", file=sys.stderr)
    if missing:
        sys.exit(1)
    return ghdl, yosys


def tool_version(cmd: list[str]) -> str:
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, check=False).stdout
    except OSError:
        return "?"
    return out.splitlines()[0].strip() if out else "?"


def hdl_revision() -> str:
    """Last commit touching hdl/, with '+local changes' when the work tree differs from it."""
    try:
        rev = subprocess.run(
            ["git", "log", "-1", "--format=%h", "--", "hdl"], capture_output=True, text=True, check=True, cwd=ROOT
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "hdl"], capture_output=True, text=True, check=True, cwd=ROOT
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown revision"
    return f"commit {rev}" + (" + local changes" if dirty else "")


def ghdl_synth(ghdl: str, job: Job, files: Sequence[Path], cdir: Path, rec: dict[str, Any]) -> None:
    """GHDL -> top.ghdl.v (raw) and top.v (repaired): orb_sim.verilog_netlist, shared with the fast
    simulation."""
    ghdl_verilog(ghdl, job.top, job.generics, files, cdir, rec)


RUNNING: set[subprocess.Popen[bytes]] = set()


def run_yosys(yosys: str, top: str, cdir: Path, script: str, log: str, timeout: float) -> tuple[float, float]:
    """Run one yosys script in cdir; returns (wall s, CPU s of yosys and its abc children)."""
    (cdir / f"{log}.ys").write_text(script.format(top=top))
    t0 = time.monotonic()
    with open(cdir / f"{log}.stderr", "w") as err:
        proc = subprocess.Popen(
            [yosys, "-q", "-l", f"{log}.log", "-s", f"{log}.ys"], cwd=cdir, stdout=subprocess.DEVNULL, stderr=err
        )
        RUNNING.add(proc)
        timer = threading.Timer(timeout, proc.kill)
        timer.start()
        try:
            _, status, usage = os.wait4(proc.pid, 0)  # rusage includes the abc processes yosys waited for
        finally:
            timer.cancel()
            RUNNING.discard(proc)
        proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - t0
    cpu = usage.ru_utime + usage.ru_stime
    if proc.returncode != 0:
        if wall >= timeout:
            raise ToolError(f"yosys ({log}) did not finish within {timeout:.0f} s")
        msg = (cdir / f"{log}.stderr").read_text().strip().splitlines() or ["(no message)"]
        raise ToolError(f"yosys ({log}) failed (exit {proc.returncode}) after {wall:.0f} s: {msg[-1]}")
    return wall, cpu


def parse_stat(text: str, top: str) -> dict[str, int]:
    """Cell counts of the whole design from `stat` output (the 'design hierarchy' totals if any)."""
    sections = re.split(r"^=== (.+?) ===$", text, flags=re.M)
    blocks = dict(zip(sections[1::2], sections[2::2], strict=True))
    body = blocks.get("design hierarchy") or blocks.get(top) or (sections[-1] if len(sections) > 1 else "")
    cells: dict[str, int] = {}
    in_cells = False
    for line in body.splitlines():
        if "Number of cells:" in line:
            in_cells = True
            continue
        if in_cells:
            m = re.match(r"^\s+(\S+)\s+(\d+)$", line)
            if not m:
                if cells:
                    break
                continue
            cells[m[1]] = int(m[2])
    if not cells:
        raise ToolError("could not find cell counts in yosys stat output")
    return cells


def summarise(cells: dict[str, int]) -> dict[str, Any]:
    lut_logic = sum(cells.get(c, 0) for c in LUT_CELLS)
    srl = sum(cells.get(c, 0) for c in SRL_CELLS)
    lutram = sum(n * LUTRAM_CELLS[c] for c, n in cells.items() if c in LUTRAM_CELLS)
    ramb18, ramb36 = cells.get("RAMB18E1", 0), cells.get("RAMB36E1", 0)
    known = {*LUT_CELLS, *SRL_CELLS, *FF_CELLS, *LUTRAM_CELLS, "RAMB18E1", "RAMB36E1", "DSP48E1"}
    known |= {"CARRY4", "MUXF7", "MUXF8", "BUFG", "IBUF", "OBUF", "INV"}
    return {
        "lut": lut_logic + srl + lutram,
        "lut_logic": lut_logic,
        "srl": srl,
        "lutram": lutram,
        "ff": sum(cells.get(c, 0) for c in FF_CELLS),
        "ramb36": ramb36,
        "ramb18": ramb18,
        "bram36": ramb36 + ramb18 / 2,
        "dsp": cells.get("DSP48E1", 0),
        "carry4": cells.get("CARRY4", 0),
        "muxf7": cells.get("MUXF7", 0),
        "muxf8": cells.get("MUXF8", 0),
        "other_cells": {c: n for c, n in sorted(cells.items()) if c not in known},
    }


GENERIC_SUFFIX_RE = re.compile(r"^(.+?)(?:_\d\w*)?$")


def module_summaries(text: str) -> dict[str, dict[str, Any] | None]:
    """Each module's own cells (its sub-modules' not included) from a hierarchical `stat`,
    summarised; None for a module with no cells of its own."""
    sections = re.split(r"^=== (.+?) ===$", text, flags=re.M)
    out: dict[str, dict[str, Any] | None] = {}
    for module, body in zip(sections[1::2], sections[2::2], strict=True):
        if module == "design hierarchy":
            continue
        try:
            out[module] = summarise(parse_stat(f"=== {module} ===\n{body}", module))
        except ToolError:  # a module with no cells of its own
            out[module] = None
    return out


def parse_blocks(text: str) -> dict[str, dict[str, Any]]:
    """Each entity's own cells (its sub-blocks' not included) from a hierarchical `stat`: keyed by
    the entity's name without GHDL's generic suffix (orb_line_buffer_640_2_19_1 -> orb_line_buffer),
    the number of variants and, per figure, the smallest and largest over them."""
    figures: dict[str, list[dict[str, Any]]] = {}
    for module, s in module_summaries(text).items():
        if s is None:
            continue
        m = GENERIC_SUFFIX_RE.match(module)
        figures.setdefault(m[1] if m else module, []).append(s)
    return {
        name: {"variants": len(fs), **{k: [min(f[k] for f in fs), max(f[k] for f in fs)] for k in BLOCK_FIGURES}}
        for name, fs in sorted(figures.items())
    }


def parse_sta(text: str) -> dict[str, Any]:
    m = ARRIVAL_RE.search(text)
    if not m:
        raise ToolError("yosys sta printed no 'Latest arrival time' line")
    path = []
    for line in text[m.end() :].splitlines()[1:]:
        if not line.strip():
            break
        path.append(line.rstrip())
    cells = [ln.strip() for ln in path if re.match(r"^\s*\d+ ", ln)]
    through = sorted({n.split(".")[0] for n in re.findall(r"\\([A-Za-z_][\w\[\]]*\.[\w.\[\]]+)", "\n".join(path))})
    return {
        "arrival_ps": int(m[2]),
        # False when yosys warns "Critical-path does not terminate in a recognised endpoint"
        "endpoint_recognised": not (cells and "(<unknown>)" in cells[0]),
        "endpoint": cells[0] if cells else "",
        "startpoint": cells[-1] if cells else "",
        "through": through,
        "path": path,
    }


def synth_stat(yosys: str, top: str, cdir: Path, rec: dict[str, Any], timeout: float) -> None:
    wall, cpu = run_yosys(yosys, top, cdir, STAT_SCRIPT, "yosys_stat", timeout)
    rec["wall_s"]["yosys_stat"], rec["cpu_s"]["yosys_stat"] = round(wall, 1), round(cpu, 1)
    text = (cdir / "stat.txt").read_text()
    rec.update(summarise(parse_stat(text, top)))
    rec["blocks"] = parse_blocks(text)


def synth_sta(yosys: str, top: str, cdir: Path, rec: dict[str, Any], timeout: float) -> None:
    wall, cpu = run_yosys(yosys, top, cdir, STA_SCRIPT, "yosys_sta", timeout)
    rec["wall_s"]["yosys_sta"], rec["cpu_s"]["yosys_sta"] = round(wall, 1), round(cpu, 1)
    sta = parse_sta((cdir / "sta.txt").read_text())
    rec["logic_delay_ns"] = round(sta["arrival_ps"] / 1000, 3)
    rec["sta"] = {k: v for k, v in sta.items() if k != "path"}
    log = (cdir / "yosys_sta.log").read_text()
    rec["sta"]["untimed_cell_types"] = sorted(set(re.findall(r"Module '(\w+)' has no timing arcs", log)))
    flat = summarise(parse_stat((cdir / "sta_stat.txt").read_text(), top))
    rec["abc9_flat"] = {k: flat[k] for k in ("lut", "lut_logic", "srl", "lutram", "ff", "ramb36", "ramb18", "dsp")}
    timing_report(top, cdir, rec)


def timing_report(top: str, cdir: Path, rec: dict[str, Any]) -> None:
    """The worst paths of the timing pass's netlist (sw/orb_flow/timing.py): timing.json and
    timing.md in the job's directory, and in the record the ten worst paths (distinct endpoint
    registers) with their logic depth, the worst per block, and the endpoint bits over the goal."""
    rep = timing.report(timing.load(cdir / "net.json", top), TIMING_GOAL_NS, 10)
    (cdir / "timing.json").write_text(json.dumps(rep, indent=1) + "\n")
    title = f"{rec['top']} {rec['job']}"
    (cdir / "timing.md").write_text(timing.markdown(rep, title))
    brief = ("delay_ns", "lut_levels", "carry4", "muxf", "start", "start_type", "endpoint", "block")
    rec["timing"] = {
        "goal_ns": TIMING_GOAL_NS,
        "logic_delay_ns": rep["logic_delay_ns"],
        "endpoints": rep["endpoints"],
        "endpoints_over_goal": rep["endpoints_over_limit"],
        "worst_paths": [{k: p[k] for k in brief} for p in rep["worst_paths"]],
        "worst_by_block": {b: {k: p[k] for k in brief} for b, p in rep["worst_by_block"].items()},
        "untimed_cells": rep["untimed_cells"],
    }
    if rep["logic_delay_ns"] is not None and abs(rep["logic_delay_ns"] - rec["logic_delay_ns"]) > 0.0015:
        rec["warnings"].append(f"timing.py's longest path {rep['logic_delay_ns']} ns differs from yosys sta's")


def new_record(job: Job, key: str) -> dict[str, Any]:
    return {
        "top": job.top,
        "job": job.name,  # with any --generic overrides: the key of synth_expected.json
        "width": job.cfg.width,
        "height": job.cfg.height,
        "scales": job.cfg.scales,
        "generics": job.generics,
        "sectors": int(job.generics.get("SECTORS_g", 32)),  # the tops' default SECTORS_g = 32 sectors in all
        "lut": None,
        "ff": None,
        "bram36": None,
        "dsp": None,
        "logic_delay_ns": None,  # null unless the sta pass ran (--sta / STA=1)
        "srl": None,
        "ramb18": None,
        "ramb36": None,
        "passes": [],
        "cache_key": key,
        "workarounds": [],
        "warnings": [],
        "errors": [],
        "wall_s": {},
        "cpu_s": {},
    }


def load_cached(cdir: Path, key: str) -> dict[str, Any] | None:
    """The job's cached record if its cache key matches and it has no errors, else None."""
    try:
        rec = json.loads((cdir / "record.json").read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(rec, dict) or rec.get("cache_key") != key or rec.get("errors"):
        return None
    return rec


def util(rec: dict[str, Any]) -> dict[str, float | None]:
    return {
        k: (round(100 * rec[k] / DEVICE[k], 1) if rec.get(k) is not None else None)
        for k in ("lut", "ff", "bram36", "dsp")
    }


def fmt(v: float | None, pct: float | None = None) -> str:
    if v is None:
        return "—"
    s = f"{v:,}" if isinstance(v, int) else f"{v:g}"
    return f"{s} ({pct:.1f}%)" if pct is not None else s


def fmt_s(seconds: float | None) -> str:
    if seconds is None:
        return "unknown"
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.1f} min"


def rec_key(rec: dict[str, Any]) -> tuple[str, int, int, int]:
    return (rec["top"], rec["width"], rec["height"], rec["scales"])


def table(records: list[dict[str, Any]]) -> str:
    head = (
        "| top | config (W x H, scales) | LUT | FF | BRAM36 | DSP | SRL | LUT-RAM | LUT, FF (abc9 flat) "
        "| logic delay ns | yosys CPU s | check | measured | RAMs found by GHDL | notes |\n"
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|---|\n"
    )
    rows = []
    for r in records:
        u = util(r)
        cpu = fmt(round(sum(r["cpu_s"].values()))) if r.get("cpu_s") else "—"
        flat = f"{fmt(r['abc9_flat']['lut'])}, {fmt(r['abc9_flat']['ff'])}" if r.get("abc9_flat") else "—"
        rams = ", ".join(f"{x['depth']}x{x['width']}" for x in r.get("ghdl_rams", [])) or "—"
        notes = []
        if any("orb_feat_merge" in w for w in r.get("workarounds", [])):
            notes.append("merge patched for GHDL bug")
        if r.get("sta") and not r["sta"].get("endpoint_recognised", True):
            notes.append("sta path ends at no recognised endpoint")
        if r.get("sta", {}).get("untimed_cell_types"):
            notes.append("untimed in sta: " + ", ".join(r["sta"]["untimed_cell_types"]))
        notes += r.get("warnings", [])
        notes += ["ERROR: " + e for e in r.get("errors", [])]
        check = r.get("check", {}).get("status", "—")
        measured = f"{r.get('date', '?')}, {r.get('hdl_revision', '?')}"
        rows.append(
            f"| {r['top']} | {r['width']}x{r['height']}, {r['scales']} | {fmt(r['lut'], u['lut'])} "
            f"| {fmt(r['ff'], u['ff'])} | {fmt(r['bram36'], u['bram36'])} | {fmt(r['dsp'], u['dsp'])} "
            f"| {fmt(r['srl'])} | {fmt(r.get('lutram'))} | {flat} | {fmt(r['logic_delay_ns'])} | {cpu} "
            f"| {check} | {measured} | {rams} | {'; '.join(notes)} |"
        )
    return head + "\n".join(rows) + "\n"


def estimate(name: str, steps: Sequence[str], times: dict[str, Any], expected: dict[str, Any]) -> tuple[float, str]:
    """Seconds the steps (ghdl, yosys_stat, yosys_sta) of one job took when last measured: from
    times.json (this machine), else from synth_expected.json. Raises KeyError when unknown."""
    for source, where in ((times.get(name, {}), "measured here"), (expected["jobs"].get(name, {}), "expected file")):
        walls = source.get("wall_s", {})
        if all(s in walls for s in steps):
            date = source.get("date") or source.get("measured", {}).get("date", "?")
            return sum(float(walls[s]) for s in steps), f"{where}, {date}"
    raise KeyError(name)


def estimates(
    without_sta: Sequence[Job],
    others: Sequence[Job],
    times: dict[str, Any],
    expected: dict[str, Any],
    cached: Collection[str] = (),
) -> list[str]:
    """Lines saying how long what this run left out would take, one yosys process after the other:
    the timing pass of the jobs in without_sta and the resource passes of the other jobs (those
    named in cached have a valid cached record and take seconds)."""
    lines: list[str] = []

    def together(total: list[float | None]) -> str:
        known = [t for t in total if t is not None]
        if known and not any(known) and None not in total:
            return f"  {'together':<52} seconds (cached)"
        s = f"~{fmt_s(sum(known))} wall, one after the other" + (" + unknown" * (None in total)) if known else "unknown"
        return f"  {'together':<52} {s}"

    def line(label: str, name: str, steps: Sequence[str]) -> float | None:
        if name in cached:
            lines.append(f"  {label:<52} cached (seconds)")
            return 0.0
        try:
            s, src = estimate(name, steps, times, expected)
        except KeyError:
            lines.append(f"  {label:<52} unknown (never measured)")
            return None
        lines.append(f"  {label:<52} ~{fmt_s(s)} ({src})")
        return s

    if others:
        lines.append("Other known configurations (resources; make synth TOP=<top> SIZE=<WxHxS>):")
        total = [line(f"{j.name}", j.name, ("ghdl", "yosys_stat")) for j in others]
        lines.append(together(total))
    if without_sta:
        lines.append("The timing pass (STA=1), per configuration of this run:")
        total = [line(f"{j.name} sta", j.name, ("yosys_sta",)) for j in without_sta]
        lines.append(together(total))
    if lines:
        lines.insert(0, "Estimated wall times from the last measured ones (noisy: the machine may be shared):")
    return lines


class Run:
    """Shared state of one run: records, times and the report files, written under a lock."""

    def __init__(self, out: Path, expected: dict[str, Any], expected_path: Path, header: str) -> None:
        self.out = out
        self.expected = expected
        self.expected_path = expected_path
        self.header = header
        self.lock = threading.Lock()
        self.report = out / "report.json"
        self.times_file = out / "times.json"
        try:
            self.records: list[dict[str, Any]] = json.loads(self.report.read_text())
        except (OSError, ValueError):
            self.records = []
        try:
            self.times: dict[str, Any] = json.loads(self.times_file.read_text())
        except (OSError, ValueError):
            self.times = {}

    def note_time(self, job: Job, step: str, wall: float | None, date: str) -> None:
        if wall is None:
            return
        with self.lock:
            entry = self.times.setdefault(job.name, {"wall_s": {}})
            entry["wall_s"][step] = wall
            entry["date"] = date
            self.times_file.write_text(json.dumps(self.times, indent=2, sort_keys=True) + "\n")

    def publish(self, rec: dict[str, Any]) -> None:
        """Check the record, put it into report.json / report.md (replacing its old record)."""
        with self.lock:
            rec["util_pct"] = util(rec)
            rec["check"] = check_record(rec, self.expected).as_dict()
            self.records = [r for r in self.records if r.get("top") and rec_key(r) != rec_key(rec)] + [rec]
            self.records.sort(key=rec_key)
            self.out.mkdir(parents=True, exist_ok=True)
            self.report.write_text(json.dumps(self.records, indent=2) + "\n")
            (self.out / "report.md").write_text(self.markdown())

    def markdown(self) -> str:
        return (
            f"# Synthesis estimate on {DEVICE['name']}\n\n"
            f"{self.header}\n"
            f"Percentages of the {DEVICE['name']}: {DEVICE['lut']:,} LUT, {DEVICE['ff']:,} FF, "
            f"{DEVICE['bram36']} RAMB36, {DEVICE['dsp']} DSP48E1. LUT includes SRLs and LUT-RAM; "
            "logic delay = yosys `sta` longest pre-route arrival (no routing), ns, only where the timing "
            "pass ran (STA=1). LUT/FF/SRL/BRAM/DSP from `synth_xilinx` (hierarchical); LUT, FF (abc9 flat) "
            f"from the timing pass. check: against {rel(self.expected_path)}.\n\n" + table(self.records)
        )


def _interrupt(signum: int, frame: object) -> None:
    raise KeyboardInterrupt


def rel(p: Path) -> str:
    return str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p)


def expected_entry(rec: dict[str, Any], cdir: Path, command: str, old: dict[str, Any]) -> dict[str, Any]:
    """A finished record as its synth_expected.json entry: the figures, the timing pass's where it
    ran, the measurement (command, hdl/ commit, date, tools), the wall times and the blocks' own
    figures; an entry's own tolerance_pct is kept."""
    entry: dict[str, Any] = {k: rec[k] for k in ("lut", "ff", "bram36", "dsp")}
    if "sta" in rec["passes"]:
        entry["logic_delay_ns"] = rec["logic_delay_ns"]
        if rec.get("timing"):
            t = rec["timing"]
            worst = [{k: p[k] for k in ("delay_ns", "lut_levels", "start", "endpoint", "block")}
                     for p in t["worst_paths"][:WORST_KEPT]]  # fmt: skip
            entry["timing"] = {"goal_ns": t["goal_ns"], "endpoints": t["endpoints"],
                               "endpoints_over_goal": t["endpoints_over_goal"], "worst_paths": worst}  # fmt: skip
    if "tolerance_pct" in old:
        entry["tolerance_pct"] = old["tolerance_pct"]
    entry["measured"] = {
        "command": command,
        "commit": rec["hdl_revision"].removeprefix("commit "),
        "hdl_digest": digest.at_commit(rec["hdl_revision"].removeprefix("commit "), ROOT),
        "date": rec["date"],
        "tools": ", ".join(" ".join(rec["tools"][t].split()[:2]) for t in ("ghdl", "yosys")),  # GHDL 2.0.0, Yosys 0.23
    }
    entry["wall_s"] = rec["wall_s"]
    stat = cdir / "stat.txt"
    blocks = rec.get("blocks") or (parse_blocks(stat.read_text()) if stat.exists() else None)
    if blocks:
        entry["blocks"] = blocks
    return entry


def update_expected(
    path: Path, expected: dict[str, Any], done: list[tuple[dict[str, Any], Path]], command: str
) -> list[str]:
    """Write the records of this run into the expected-values file (--update-expected). A record
    with an error, or measured on hdl/ with local changes (no commit to cite), is refused."""
    refused = []
    for rec, cdir in done:
        if rec["errors"] or not rec["passes"] or "local changes" in rec.get("hdl_revision", "local changes"):
            refused.append(rec["job"])
            continue
        old = expected["jobs"].get(rec["job"], {})
        expected["jobs"][rec["job"]] = expected_entry(rec, cdir, command, old)
    path.write_text(dump_expected(expected))
    return refused


def dump_expected(expected: Mapping[str, Any]) -> str:
    """The expected-values file's text: indented JSON, a block's [smallest, largest] pairs on one line."""
    text = json.dumps(expected, indent=2, ensure_ascii=False)
    return re.sub(r"\[\s+(-?[\d.]+),\s+(-?[\d.]+)\s+\]", r"[\1, \2]", text) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    extra = "; ".join(f"{t}: " + ", ".join(f"{k} {v}" for k, v in g.items()) for t, g in TOPS.items() if g)
    ap.add_argument("--top", choices=tuple(TOPS), default=DEFAULT_TOP, help=f"entity (default {DEFAULT_TOP}; {extra})")
    default_cfgs = ", ".join(c for _, c in DEFAULT_JOBS)
    ap.add_argument("--config", type=parse_config, action="append", help=f"WxHxS, repeatable (default: {default_cfgs})")
    ap.add_argument("--named", action="append", metavar="NAME",
                    help="a named configuration (docs/configurations.md): its WxHxS and generics")  # fmt: skip
    ap.add_argument(
        "--sta",
        action=argparse.BooleanOptionalAction,
        default=False,
        help="also run the slow -abc9 timing pass for logic_delay_ns (default: no; a run ends with its estimate)",
    )
    ap.add_argument("--jobs", type=int, default=2, help="processes at once (default 2)")
    ap.add_argument("--timeout", type=float, default=3600, help="seconds per yosys run (default 3600)")
    ap.add_argument("--out", type=Path, default=OUT, help=f"output directory (default {rel(OUT)})")
    ap.add_argument("--expected", type=Path, default=EXPECTED, help=f"expected values (default {rel(EXPECTED)})")
    ap.add_argument("--no-cache", action="store_true", help="run every job even if its cached record matches")
    ap.add_argument("--update-expected", action="store_true",
                    help="write this run's figures into the expected-values file (a change of the figures that is "
                         "intended; hdl/ must be committed)")  # fmt: skip
    ap.add_argument(
        "--generic",
        type=parse_generic,
        action="append",
        default=[],
        help="NAME=VALUE, repeatable: override a generic of the top (e.g. the board's MEM_DEPTH_g=2048)",
    )
    args = ap.parse_args(argv)

    try:
        expected = load_expected(args.expected)
    except (OSError, ValueError) as exc:
        print(f"error: expected values: {exc}", file=sys.stderr)
        return 2
    default_set = not args.config and not args.named and args.top == DEFAULT_TOP
    try:
        named = [named_job(args.top, n) for n in args.named or ()]
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    named = [Job(j.top, j.cfg, tuple(dict([*j.extra, *args.generic]).items())) for j in named]
    jobs = [Job(args.top, c, tuple(args.generic)) for c in args.config or ()] + named
    if not jobs:
        jobs = [Job(args.top, job(t, c).cfg, tuple(args.generic)) for t, c in DEFAULT_JOBS]
    jobs = list(dict.fromkeys(jobs))
    ghdl, yosys = find_tools()
    tools = {"ghdl": tool_version([ghdl, "--version"]), "yosys": tool_version([yosys, "-V"])}
    files = sources()
    hdl_rev = hdl_revision()
    started = datetime.datetime.now().astimezone()
    date = started.strftime("%Y-%m-%d")
    t_start = time.monotonic()
    cmd = "python3 -m orb_flow.synth " + " ".join(argv if argv is not None else sys.argv[1:])
    wanted = ["stat", *(["sta"] if args.sta else [])]
    run = Run(
        args.out,
        expected,
        args.expected,
        f"Last run {started:%Y-%m-%d %H:%M %Z}: `{cmd.strip()}` on hdl/ at {hdl_rev} ({tools['ghdl']}; "
        f"{tools['yosys']}). Each record was measured at the date and hdl/ revision in its `measured` column "
        "(a record whose cache key matched was reused).\n",
    )
    print(f"{len(jobs)} job(s), passes {'+'.join(wanted)}, {args.jobs} process(es); {tools['ghdl']}; {tools['yosys']}")

    # what each job needs: nothing (cached), or ghdl and/or some yosys passes
    todo: dict[Job, list[str]] = {}
    recs: dict[Job, dict[str, Any]] = {}
    for j in jobs:
        cdir = j.dir(args.out)
        key = cache_key(j.top, j.generics, files, tools)
        cached = None if args.no_cache else load_cached(cdir, key)
        need = [p for p in wanted if cached is None or p not in cached.get("passes", [])]
        if cached is not None:
            cached["job"] = j.name  # records cached before the field existed
        if cached is not None and not need:
            if "sta" in cached.get("passes", []) and (cdir / "net.json").exists():
                timing_report(j.top, cdir, cached)  # seconds: the report follows timing.py's changes
            print(f"  {j.name:<28} cached (measured {cached.get('date', '?')}, hdl/ at {cached.get('hdl_revision')})")
            run.publish(cached)
            recs[j] = cached
            continue
        # a cached record missing a pass reuses its top.v; anything else starts again from GHDL
        rec = cached if cached is not None and (cdir / "top.v").exists() else new_record(j, key)
        if rec is not cached:
            rec.update(date=date, hdl_revision=hdl_rev, tools=tools)
            (cdir / "record.json").unlink(missing_ok=True)
        recs[j], todo[j] = rec, need

    signal.signal(signal.SIGTERM, _interrupt)  # `kill` stops the yosys runs too
    pool = ThreadPoolExecutor(max_workers=max(1, args.jobs))

    def ghdl_task(j: Job) -> None:
        rec, cdir = recs[j], j.dir(args.out)
        cdir.mkdir(parents=True, exist_ok=True)
        try:
            ghdl_synth(ghdl, j, files, cdir, rec)
        except ToolError as exc:
            rec["errors"].append(str(exc))
        if cache_key(j.top, j.generics, files, tools) != rec["cache_key"]:
            rec["warnings"].append("hdl/ changed while GHDL read it: this record is not cached")
            rec["cache_key"] = None
        run.note_time(j, "ghdl", rec["wall_s"].get("ghdl"), date)
        print(f"  {j.name:<28} ghdl done after {time.monotonic() - t_start:6.0f} s", flush=True)

    def pass_task(j: Job, which: str) -> None:
        rec, cdir = recs[j], j.dir(args.out)
        try:
            (synth_stat if which == "stat" else synth_sta)(yosys, j.top, cdir, rec, args.timeout)
            with run.lock:
                rec["passes"] = sorted({*rec["passes"], which}, key=list(PASSES).index)
                rec["date"], rec["hdl_revision"], rec["tools"] = date, hdl_rev, tools
        except ToolError as exc:
            rec["errors"].append(f"{which} pass: {exc}")
        run.note_time(j, PASSES[which][0], rec["wall_s"].get(PASSES[which][0]), date)
        done = all(p in rec["passes"] for p in wanted) or rec["errors"]
        if done and not rec["errors"] and rec.get("cache_key"):
            (cdir / "record.json").write_text(json.dumps(rec, indent=2) + "\n")
        run.publish(rec)
        figures = f"{fmt(rec['lut'])} LUT, {fmt(rec['ff'])} FF, {fmt(rec['bram36'])} BRAM36, {fmt(rec['dsp'])} DSP"
        if which == "sta":
            figures = f"logic delay {fmt(rec['logic_delay_ns'])} ns"
            if rec.get("timing"):
                t = rec["timing"]
                figures += (
                    f" ({t['endpoints_over_goal']:,} of {t['endpoints']:,} endpoint bits over the "
                    f"{t['goal_ns']} ns goal; worst paths: {rel(cdir / 'timing.md')})"
                )
        status = "FAILED: " + rec["errors"][-1] if rec["errors"] else figures
        print(f"  {j.name:<28} {which:<4} done after {time.monotonic() - t_start:6.0f} s: {status}", flush=True)

    def est(j: Job) -> float:
        try:
            return estimate(j.name, ("yosys_stat",), run.times, expected)[0]
        except KeyError:  # yosys time grows with the number of scales and the top, hardly with the width
            return j.cfg.scales * 100 + (200 if j.top != "orb_core" else 0) + j.cfg.width / 100

    try:
        for f in [pool.submit(ghdl_task, j) for j in todo if not recs[j]["passes"]]:
            f.result()
        # longest first; the timing pass before the resource pass of the same job
        order = sorted(todo, key=lambda j: -est(j))
        tasks = [(j, p) for j in order for p in reversed(todo[j]) if not recs[j]["errors"]]
        for f in [pool.submit(pass_task, j, p) for j, p in tasks]:
            f.result()
        for j in todo:
            if recs[j]["errors"] and not recs[j]["passes"]:
                run.publish(recs[j])  # ghdl failed: no pass ran, still report it
    except KeyboardInterrupt:
        pool.shutdown(wait=False, cancel_futures=True)
        for proc in list(RUNNING):
            proc.kill()
        raise
    pool.shutdown()
    wall = time.monotonic() - t_start

    this_run = [recs[j] for j in jobs]
    print()
    print(run.markdown())
    fails = 0
    for j, r in zip(jobs, this_run, strict=True):
        for e in r["errors"]:
            print(f"error: {j.name}: {e}", file=sys.stderr)
        c = r.get("check") or check_record(r, expected).as_dict()
        if c["status"] == "fail":
            fails += 1
            for m in c["messages"]:
                print(f"expected-values check FAILED: {m}", file=sys.stderr)
        else:
            what = f" (no entry in {rel(args.expected)})" if c["status"] == "no expectation" else ""
            print(f"expected-values check {c['status']}: {j.name}{what}" + "".join(f"; {m}" for m in c["messages"]))
    others = [job(t, c) for t, c in (*DEFAULT_JOBS, *OTHER_JOBS)] if default_set else []
    others = [o for o in others if o not in jobs]
    cached = {o.name for o in others if load_cached(o.dir(args.out), cache_key(o.top, o.generics, files, tools))}
    without_sta = [j for j in jobs if "sta" not in recs[j].get("passes", [])]
    for line in estimates(without_sta, others, run.times, expected, cached):
        print(line)
    print(f"wrote {rel(run.report)} and report.md; total wall time {wall:.0f} s")
    if args.update_expected:
        refused = update_expected(args.expected, expected, [(recs[j], j.dir(args.out)) for j in jobs], cmd.strip())
        for name in refused:
            print(
                f"error: {name}: not written to {rel(args.expected)} (failed, or hdl/ not committed)", file=sys.stderr
            )
        print(f"updated {rel(args.expected)}: {len(jobs) - len(refused)} entr(y/ies); now `make views`")
        return 1 if refused else 0
    if fails:
        print(
            f"error: {fails} configuration(s) outside the expected values of {rel(args.expected)}; if the change is "
            "intended, commit hdl/ and run the same command with --update-expected (make synth ... UPDATE=1)",
            file=sys.stderr,
        )
    return 1 if fails or any(r["errors"] for r in this_run) else 0


if __name__ == "__main__":
    sys.exit(main())
