#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Synthesis estimate of the accelerator top without Vivado: GHDL -> Verilog -> yosys synth_xilinx.

For each configuration (WIDTH_g x HEIGHT_g x SCALES_g of orb_core):
  1. `ghdl synth --std=08 -gWIDTH_g=.. -gHEIGHT_g=.. -gSCALES_g=.. --out=verilog <hdl sources in
     dependency order> -e orb_core` -> build/synth/<cfg>/top.v (GHDL's inferred-RAM notes are
     kept in ghdl.log and in the report);
  2. yosys `synth_xilinx -family xc7 -top orb_core; stat` -> resource counts (stat.txt);
  3. yosys `synth_xilinx -family xc7 -abc9 -flatten ...; sta` -> longest pre-route arrival time
     (sta.txt), the logic-delay estimate: cell delays from yosys's xc7 models, no routing.
Results: build/synth/report.json (one record per configuration; records of other configurations
already there are kept), build/synth/report.md (table) and the same table on stdout.

Counting: lut = LUT1..LUT6 + SRL16E/SRLC32E + LUT-RAM cells in LUTs (as Vivado's "Slice LUTs");
ff = FDRE + FDSE + FDCE + FDPE; bram36 = RAMB36E1 + RAMB18E1 / 2; dsp = DSP48E1.
These are yosys estimates, not Vivado results (see docs/synthesis.md).

Work-arounds for tool bugs, each recorded in the record's "workarounds" list:
  - GHDL 2.0's Verilog writer prints `abs` as VHDL (`x <= std_logic_vector(abs $signed(y));`);
    such lines are rewritten to the equivalent Verilog `assign x = ($signed(y) < 0) ? -y : y;`
    (top.ghdl.v is GHDL's raw output, top.v the file yosys reads).
  - GHDL 2.0 synth crashes (netlists-builders assertion) on orb_feat_merge with SCALES_g = 1, where
    the scale index `pop` (integer range -1 to 0) is 0 bits wide. Only if it crashes, a copy with
    the rewrites in MERGE_S1_PATCHES (no change in behaviour for SCALES_g = 1) is synthesised.
  - GHDL 2.0's Verilog writer prints zero-width nets as `""` / `0'b...`; they are dropped.
  - yosys 0.23's -abc9 flow aborts in abc9_ops (std::out_of_range) when a RAMB36E1/RAMB18E1 cell
    still has the oversized DI/DO ports its BRAM mapper creates; the timing pass runs synth_xilinx
    in two halves with `hierarchy -check` (which resizes those ports) before map_luts.
  - yosys 0.23's sta finds no timing arcs for CARRY4 (and MUXF7/F8) after synth_xilinx and skips
    every carry chain; the cell models are read again with their specify blocks before `sta`.
    LUT-RAM cells stay untimed (listed in the record's sta.untimed_cell_types).

Usage: scripts/flow/synth.py [--config WxHxS ...] [--jobs N] [--no-sta] [--timeout S]
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from orb_sim.hdl import HDL, sources  # the one list of hdl files (hdl/manifest.txt)

ROOT = Path(__file__).resolve().parents[2]

TOP = "orb_core"
OUT = ROOT / "build" / "synth"
# (WIDTH_g, HEIGHT_g, SCALES_g); documented in docs/synthesis.md
DEFAULT_CONFIGS = (
    (640, 480, 1),
    (640, 480, 2),
    (1280, 720, 2),
    (1920, 1080, 1),
    (1920, 1080, 2),
    (1920, 1080, 4),
)
# XC7Z020 (Zybo Z7-20) capacity
DEVICE = {"name": "XC7Z020", "lut": 53200, "ff": 106400, "bram36": 140, "dsp": 220}

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

ABS_RE = re.compile(r"^(\s*)(\w+) <= std_logic_vector\(abs \$signed\((\w+)\)\);", re.M)
RAM_NOTE_RE = re.compile(r"^(\S+?):(\d+):\d+:note: found (RAM|ROM) \"(\w+)\", width: (\d+) bits, depth: (\d+)", re.M)
# orb_feat_merge rewrites for SCALES_g = 1 only, where they change nothing: the scale index `pop`
# (range -1 to 0) is only used to index under `pop >= 0`, i.e. it is 0 there, and rr is always 0.
MERGE_S1_PATCHES = (
    (re.compile(r"\brr\s*<=\s*\(pop \+ 1\) mod SCALES_g;"), "rr <= 0;", "'rr <= (pop + 1) mod SCALES_g' -> 'rr <= 0'"),
    (re.compile(r"\(pop\)"), "(0)", "index '(pop)' -> '(0)'"),
)
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
read_verilog -lib -specify -overwrite +/xilinx/cells_sim.v
tee -o sta.txt sta
"""


class ToolError(RuntimeError):
    pass


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
    if not (64 <= w <= 1920 and 48 <= h <= 1080 and 1 <= s <= 4):
        raise argparse.ArgumentTypeError(f"{text}: orb_core allows W 64..1920, H 48..1080, scales 1..4")
    return Config(w, h, s)


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


def ghdl_synth(ghdl: str, cfg: Config, cdir: Path, rec: dict) -> None:
    """GHDL -> top.ghdl.v (raw) and top.v (Verilog-writer fix applied). Fills RAM notes etc."""
    files = sources()

    def run(srcs: list[Path]) -> subprocess.CompletedProcess:
        cmd = [ghdl, "synth", "--std=08"]
        cmd += [f"-g{k}={v}" for k, v in cfg.generics.items()]
        cmd += ["--out=verilog", *map(str, srcs), "-e", TOP]
        rec["ghdl_cmd"] = " ".join(cmd).replace(str(ROOT) + "/", "")
        return subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=cdir)

    t0 = time.monotonic()
    proc = run(files)
    if proc.returncode != 0 and "GHDL Bug occurred" in proc.stderr and cfg.scales == 1:
        merge = HDL / "core" / "orb_feat_merge.vhd"
        text, applied = merge.read_text(), []
        for pattern, repl, what in MERGE_S1_PATCHES:
            text, n = pattern.subn(repl, text)
            if n:
                applied.append(f"{what} ({n}x)")
        if applied:
            patched_dir = cdir / "patched"
            patched_dir.mkdir(exist_ok=True)
            patched = patched_dir / merge.name
            patched.write_text(text)
            proc = run([patched if s == merge else s for s in files])
            rec["workarounds"].append(
                "GHDL 2.0 synth crashes on orb_feat_merge with SCALES_g=1 (0-bit scale index); synthesised "
                f"build/synth/{cfg.name}/patched/orb_feat_merge.vhd instead, equivalent for SCALES_g=1: "
                + "; ".join(applied)
            )
    rec["wall_s"]["ghdl"] = round(time.monotonic() - t0, 1)
    (cdir / "ghdl.log").write_text(proc.stderr)
    (cdir / "top.ghdl.v").write_text(proc.stdout)
    if proc.returncode != 0:
        last = [ln for ln in proc.stderr.splitlines() if ln.strip()][-3:]
        raise ToolError(f"ghdl synth failed (exit {proc.returncode}): " + " | ".join(last))
    rec["ghdl_rams"] = [
        {"file": Path(m[0]).name, "line": int(m[1]), "kind": m[2], "name": m[3], "width": int(m[4]), "depth": int(m[5])}
        for m in RAM_NOTE_RE.findall(proc.stderr)
    ]
    rec["ghdl_warnings"] = [ln for ln in proc.stderr.splitlines() if ":warning:" in ln]
    verilog, n_abs = ABS_RE.subn(
        r"\1assign \2 = ($signed(\3) < 0) ? -\3 : \3;  // synth.py: was VHDL 'abs'", proc.stdout
    )
    if n_abs:
        rec["workarounds"].append(f"GHDL 2.0 Verilog writer emitted VHDL 'abs' in {n_abs} lines; rewritten as Verilog")
    verilog, n_zero = drop_zero_width(verilog)
    if n_zero:
        rec["workarounds"].append(
            f'GHDL 2.0 Verilog writer printed {n_zero} zero-width nets as invalid Verilog ("", 0\'b); removed them'
        )
    leftover = [ln for ln in verilog.splitlines() if "std_logic" in ln and not ln.lstrip().startswith(("/*", "//"))]
    if leftover:
        raise ToolError(f"GHDL's Verilog still has VHDL in it (unhandled writer bug): {leftover[0].strip()}")
    (cdir / "top.v").write_text(verilog)


def drop_zero_width(verilog: str) -> tuple[str, int]:
    """Remove the zero-width nets GHDL 2.0 writes as `assign n = "";` / `assign m = 0'b - n;`.

    A zero-width value contributes nothing, so it is dropped from the concatenations that use it;
    any other use is an error (the Verilog could not be repaired safely)."""
    zero: set[str] = set()
    for m in re.finditer(r"^\s*assign (\w+) = (.*);", verilog, re.M):
        if m[2].strip() == '""' or re.search(r"(?<![\w'])0'[bdh]", m[2]):
            zero.add(m[1])
    if not zero:
        return verilog, 0
    name_re = re.compile(r"\b(" + "|".join(sorted(zero)) + r")\b")
    out = []
    for line in verilog.splitlines():
        m = re.match(r"^\s*(?:wire|assign)\s+(\w+)\s*[;=]", line)
        if m and m[1] in zero:
            continue
        if name_re.search(line) and not line.lstrip().startswith(("/*", "//")):

            def strip_concat(c: re.Match) -> str:
                parts = [p for p in c[1].split(",") if p.strip() not in zero]
                return "{" + ",".join(parts).strip() + "}"

            line = re.sub(r"\{([^{}]*)\}", strip_concat, line)
            if name_re.search(line.split("//")[0]):
                raise ToolError(f"GHDL's Verilog uses a zero-width net outside a concatenation: {line.strip()}")
        out.append(line)
    return "\n".join(out) + "\n", len(zero)


RUNNING: set[subprocess.Popen] = set()


def run_yosys(yosys: str, cdir: Path, script: str, log: str, timeout: float) -> tuple[float, float]:
    """Run one yosys script in cdir; returns (wall s, CPU s of yosys and its abc children)."""
    (cdir / f"{log}.ys").write_text(script.format(top=TOP))
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


def parse_stat(text: str) -> dict[str, int]:
    """Cell counts of the whole design from `stat` output (the 'design hierarchy' totals if any)."""
    sections = re.split(r"^=== (.+?) ===$", text, flags=re.M)
    blocks = dict(zip(sections[1::2], sections[2::2], strict=True))
    body = blocks.get("design hierarchy") or blocks.get(TOP) or (sections[-1] if len(sections) > 1 else "")
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


def summarise(cells: dict[str, int]) -> dict:
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


def parse_sta(text: str) -> dict:
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


def synth_stat(yosys: str, cdir: Path, rec: dict, timeout: float) -> None:
    wall, cpu = run_yosys(yosys, cdir, STAT_SCRIPT, "yosys_stat", timeout)
    rec["wall_s"]["yosys_stat"], rec["cpu_s"]["yosys_stat"] = round(wall, 1), round(cpu, 1)
    rec.update(summarise(parse_stat((cdir / "stat.txt").read_text())))


def synth_sta(yosys: str, cdir: Path, rec: dict, timeout: float) -> None:
    try:
        wall, cpu = run_yosys(yosys, cdir, STA_SCRIPT, "yosys_sta", timeout)
        rec["wall_s"]["yosys_sta"], rec["cpu_s"]["yosys_sta"] = round(wall, 1), round(cpu, 1)
        sta = parse_sta((cdir / "sta.txt").read_text())
    except ToolError as exc:
        rec["errors"].append(f"timing pass: {exc}")
        return
    rec["logic_delay_ns"] = round(sta["arrival_ps"] / 1000, 3)
    rec["sta"] = {k: v for k, v in sta.items() if k != "path"}
    log = (cdir / "yosys_sta.log").read_text()
    rec["sta"]["untimed_cell_types"] = sorted(set(re.findall(r"Module '(\w+)' has no timing arcs", log)))
    flat = summarise(parse_stat((cdir / "sta_stat.txt").read_text()))
    rec["abc9_flat"] = {k: flat[k] for k in ("lut", "lut_logic", "srl", "lutram", "ff", "ramb36", "ramb18", "dsp")}


def new_record(cfg: Config) -> dict:
    return {
        "top": TOP,
        "width": cfg.width,
        "height": cfg.height,
        "scales": cfg.scales,
        "sectors": 32,  # orb_core defaults: SECTORS_g = 8 per quadrant, DESC_g = true
        "lut": None,
        "ff": None,
        "bram36": None,
        "dsp": None,
        "logic_delay_ns": None,
        "srl": None,
        "ramb18": None,
        "ramb36": None,
        "workarounds": [],
        "errors": [],
        "wall_s": {},
        "cpu_s": {},
    }


def util(rec: dict) -> dict:
    return {
        k: (round(100 * rec[k] / DEVICE[k], 1) if rec.get(k) is not None else None)
        for k in ("lut", "ff", "bram36", "dsp")
    }


def fmt(v, pct=None) -> str:
    if v is None:
        return "—"
    s = f"{v:,}" if isinstance(v, int) else f"{v:g}"
    return f"{s} ({pct:.1f}%)" if pct is not None else s


def table(records: list[dict]) -> str:
    head = (
        "| config (W x H, scales) | LUT | FF | BRAM36 | DSP | SRL | LUT-RAM | LUT, FF (abc9 flat) "
        "| logic delay ns | yosys CPU s | RAMs found by GHDL | notes |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n"
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
        notes += ["ERROR: " + e for e in r.get("errors", [])]
        rows.append(
            f"| {r['width']}x{r['height']}, {r['scales']} | {fmt(r['lut'], u['lut'])} | {fmt(r['ff'], u['ff'])} "
            f"| {fmt(r['bram36'], u['bram36'])} | {fmt(r['dsp'], u['dsp'])} | {fmt(r['srl'])} "
            f"| {fmt(r.get('lutram'))} | {flat} | {fmt(r['logic_delay_ns'])} | {cpu} | {rams} | {'; '.join(notes)} |"
        )
    return head + "\n".join(rows) + "\n"


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--config", type=parse_config, action="append", help="WxHxS, e.g. 1920x1080x2 (repeatable)")
    ap.add_argument("--jobs", type=int, default=2, help="yosys processes at once (default 2)")
    ap.add_argument("--no-sta", action="store_true", help="skip the -abc9 timing pass")
    ap.add_argument("--timeout", type=float, default=3600, help="seconds per yosys run (default 3600)")
    ap.add_argument("--out", type=Path, default=OUT, help=f"output directory (default {OUT.relative_to(ROOT)})")
    ap.add_argument("--top", choices=("orb_core", "orb_accel_top"), default="orb_core",
                    help="entity to synthesise (orb_accel_top: the complete accelerator with its defaults "
                    "MEM_DEPTH_g 1024, INPUT_g RGB)")  # fmt: skip
    args = ap.parse_args(argv)
    global TOP
    TOP = args.top

    ghdl, yosys = find_tools()
    configs = args.config or [Config(*c) for c in DEFAULT_CONFIGS]
    tools = {"ghdl": tool_version([ghdl, "--version"]), "yosys": tool_version([yosys, "-V"])}
    hdl_rev = hdl_revision()
    started = datetime.datetime.now().astimezone()
    t_start = time.monotonic()
    print(f"{len(configs)} configuration(s), {args.jobs} job(s); {tools['ghdl']}; {tools['yosys']}", flush=True)

    results = {}
    for cfg in configs:
        cdir = args.out / cfg.name
        cdir.mkdir(parents=True, exist_ok=True)
        rec = new_record(cfg)
        results[cfg] = rec
        try:
            ghdl_synth(ghdl, cfg, cdir, rec)
        except ToolError as exc:
            rec["errors"].append(str(exc))

    def task(cfg: Config, which: str) -> None:
        rec, cdir = results[cfg], args.out / cfg.name
        try:
            (synth_stat if which == "stat" else synth_sta)(yosys, cdir, rec, args.timeout)
        except ToolError as exc:
            rec["errors"].append(f"{which} pass: {exc}")
        print(f"  {cfg.name:<12} {which:<4} done after {time.monotonic() - t_start:6.0f} s", flush=True)

    passes = ["stat"] + ([] if args.no_sta else ["sta"])
    # longest first (yosys time grows with the number of scales, hardly with the width)
    order = sorted(configs, key=lambda c: (-c.scales, -c.width * c.height))
    jobs = [(c, p) for c in order for p in reversed(passes) if not results[c]["errors"]]
    signal.signal(signal.SIGTERM, _interrupt)  # `kill` stops the yosys runs too
    pool = ThreadPoolExecutor(max_workers=max(1, args.jobs))
    try:
        for f in [pool.submit(task, c, p) for c, p in jobs]:
            f.result()
    except KeyboardInterrupt:
        pool.shutdown(wait=False, cancel_futures=True)
        for proc in list(RUNNING):
            proc.kill()
        raise
    pool.shutdown()
    wall = time.monotonic() - t_start

    for rec in results.values():
        rec["util_pct"] = util(rec)
        rec["tools"] = tools
        rec["date"] = started.strftime("%Y-%m-%d")
        rec["hdl_revision"] = hdl_rev

    report = args.out / "report.json"
    old = json.loads(report.read_text()) if report.exists() else []
    keep = [
        r
        for r in old
        if (r.get("top"), r.get("width"), r.get("height"), r.get("scales"))
        not in {(TOP, c.width, c.height, c.scales) for c in configs}
    ]
    records = sorted(keep + list(results.values()), key=lambda r: (r["top"], r["width"], r["height"], r["scales"]))
    report.write_text(json.dumps(records, indent=2) + "\n")

    cmd = "scripts/flow/synth.py " + " ".join(argv if argv is not None else sys.argv[1:])
    md = (
        f"# Synthesis estimate: {TOP} on {DEVICE['name']}\n\n"
        f"Measured {started:%Y-%m-%d %H:%M %Z} with `{cmd.strip()}` on hdl/ at {hdl_rev} "
        f"({tools['ghdl']}; {tools['yosys']}); "
        f"this run: {len(configs)} configuration(s), {wall:.0f} s wall with {args.jobs} job(s).\n"
        f"Percentages of the {DEVICE['name']}: {DEVICE['lut']:,} LUT, {DEVICE['ff']:,} FF, "
        f"{DEVICE['bram36']} RAMB36, {DEVICE['dsp']} DSP48E1. LUT includes SRLs and LUT-RAM; "
        "logic delay = yosys `sta` longest pre-route arrival (no routing), ns. "
        "LUT/FF/SRL/BRAM/DSP from `synth_xilinx` (hierarchical); LUT, FF (abc9 flat) from the timing pass.\n\n"
        + table(records)
    )
    (args.out / "report.md").write_text(md)
    print()
    print(md)
    for r in results.values():
        for e in r["errors"]:
            print(f"error: {r['width']}x{r['height']}x{r['scales']}: {e}", file=sys.stderr)
    print(
        f"wrote {report.relative_to(ROOT) if report.is_relative_to(ROOT) else report} and report.md; "
        f"total wall time {wall:.0f} s"
    )
    return 1 if any(r["errors"] for r in results.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
