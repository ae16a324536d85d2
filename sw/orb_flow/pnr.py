#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Post-route timing of the board top without Vivado: GHDL -> Verilog -> yosys -> nextpnr-xilinx.

For one named configuration (docs/configurations.md; default board-vga) of the board top
orb_accel_zynq, in build/pnr/<config>/:
  1. GHDL -> top.v, exactly as `python -m orb_flow.synth --top orb_accel_zynq --named <config>`
     (synth.named_job, synth.ghdl_synth: the same generics and the same repaired netlist);
  2. wrap.v: a generated wrapper orb_pnr_wrap (see "Ports" below) around the top;
  3. yosys `synth_xilinx -family xc7 -abc9 -flatten` (split before map_luts like synth.py's timing
     pass, for the same yosys 0.23 work-around) -> top.json, stat.txt;
  4. nextpnr-xilinx --chipdb <xc7z020clg400-1 chip database> --xdc pnr.xdc --json top.json
     (--freq 150 and one create_clock -period 6.667 on the clock port) -> nextpnr.log;
  5. the post-route report of nextpnr.log (the last "Max frequency for clock" line and the last
     "Critical path report" of each clock) -> record.json and summary.md.
Stages are printed as they start ("pnr: synthesising board-vga", "pnr: packing", "pnr: placing",
"pnr: routing", ...), with a line every 10 minutes while nextpnr runs. The synthesis of step 3 is
reused when its cache key (synth.cache_key: the HDL sources, the generics, the tool versions, this
script's yosys script and wrapper) matches.

Ports: orb_accel_zynq has 321 port bits besides its clock (122 in, 199 out: two AXI4 interfaces, two
video streams); the XC7Z020 in its CLG400 package has 125 user I/O, and nextpnr-xilinx must put
every top-level port on a pad (it stops with "IO placer ran out of available IOs"). In Vivado these
ports go to the PS7 and the HDMI IP, not to pins. The wrapper therefore feeds every input from one
shift register (pin si, one flip-flop per input bit) and loads every output into another (pin so,
load enable ld), so that all the top's logic stays live and every port path becomes a
register-to-register path in the same clock domain. Cost: 321 flip-flops and about 200 LUTs (the
load multiplexers) more than the top, and the register placement is nextpnr's choice, where Vivado
sees the PS7's fixed AXI pins. Only the clock pin is placed (K17, the Zybo Z7's 125 MHz oscillator
pin, here only a clock-capable pin); si, ld and so get nextpnr's automatic IO placement; all are
LVCMOS33.

Limits: the figures are nextpnr-xilinx's timing model (prjxray-db's timing data, not AMD's speed
files), not signed off by AMD and not comparable one-to-one with Vivado's report (docs/pnr.md).
The flow writes no bitstream (no --fasm). It needs nextpnr-xilinx and a chip database for
xc7z020clg400-1 (NEXTPNR_XILINX, NEXTPNR_XILINX_CHIPDB, or the places in TOOL_DIRS/CHIPDB_DIRS);
without them it prints one line saying what to install and exits 2.

--synth-only stops after step 3 (top.json and the cell counts in record.json) and needs no nextpnr.

Usage: python3 -m orb_flow.pnr [--named NAME] [--timeout S] [--seed N] [--write-routed] [--synth-only] [--out D]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

from orb_flow import synth
from orb_flow.device import DEVICE
from orb_sim.hdl import sources

ROOT = synth.ROOT
OUT = ROOT / "build" / "pnr"

PART = "xc7z020clg400-1"
TOP = "orb_accel_zynq"  # the board top; its clock port is CLOCK_PORT
CLOCK_PORT = "aclk"
WRAP_TOP = "orb_pnr_wrap"
CLOCK_PIN = "K17"
PERIOD_NS = 6.667  # 150 MHz, the core-clock goal (docs/synthesis.md, "Timing")
DEFAULT_CONFIG = "board-vga"
DEFAULT_TIMEOUT_S = 4 * 3600.0  # per tool run; nextpnr-xilinx on the 42k-LUT board top is the long one
HEARTBEAT_S = 600.0

FLOW_VERSION = 1  # bump when the wrapper or the yosys script changes what is measured (cache key)

ENV_TOOL = "NEXTPNR_XILINX"
ENV_CHIPDB = "NEXTPNR_XILINX_CHIPDB"
# Where a nextpnr-xilinx build or install is looked for after $NEXTPNR_XILINX and PATH.
TOOL_DIRS = (
    Path.home() / ".local" / "share" / "openxc7" / "bin",
    Path("/snap/openxc7/current/opt/nextpnr-xilinx"),
)
# Where the chip database is looked for after $NEXTPNR_XILINX_CHIPDB (a file, or a folder holding one
# of CHIPDB_NAMES), and beside the tool (a build tree keeps it in ../xilinx/).
CHIPDB_DIRS = (Path.home() / ".local" / "share" / "openxc7" / "chipdb",)
CHIPDB_NAMES = (f"{PART}.bin", "xc7z020.bin")  # openXC7's Makefiles name it after the part

MISSING_TOOL = (
    "nextpnr-xilinx is not installed: see docs/pnr.md (openXC7's toolchain-installer) "
    f"or set {ENV_TOOL} and {ENV_CHIPDB}"
)
MISSING_CHIPDB = (
    f"the nextpnr-xilinx chip database for {PART} is not installed: see docs/pnr.md "
    f"(bbaexport.py + bbasm) or set {ENV_CHIPDB}"
)

YOSYS_SCRIPT = """read_verilog top.v
read_verilog wrap.v
synth_xilinx -family xc7 -abc9 -flatten -top {top} -run begin:map_luts
hierarchy -check
synth_xilinx -family xc7 -abc9 -flatten -top {top} -run map_luts:
tee -o stat.txt stat
write_json top.json
"""

# nextpnr's stage messages (common/ and xilinx/ of nextpnr-xilinx), in order: the first line that
# matches a stage's pattern starts it.
STAGES = (
    ("packing", re.compile(r"^Info: Packing ")),
    ("placing", re.compile(r"^Info: (Running (main analytical|simulated annealing) placer|Placed \d+ cells)")),
    ("routing", re.compile(r"^Info: (Routing global clocks|Routing\.\.|Running router2)")),
    ("reporting", re.compile(r"^Info: (Routing complete\.|Router2 time)")),
)
ROUTED_RE = re.compile(r"^Info: (Routing complete\.|Router2 time)", re.M)

# The timing report (nextpnr-xilinx common/timing.cc); the prefix is Info/Warning/ERROR by outcome.
FMAX_RE = re.compile(
    r"^(?:Info|Warning|ERROR): Max frequency for clock\s+'([^']+)': ([\d.]+) MHz \((PASS|FAIL) at ([\d.]+) MHz\)",
    re.M,
)
CRIT_HEAD_RE = re.compile(r"^Info: Critical path report for clock '([^']+)' \((\w+) -> (\w+)\):")
CRIT_STEP_RE = re.compile(r"^Info:\s*(-?[\d.]+)\s+(-?[\d.]+)\s+(Source|Net|Setup)\s+(\S+)")
CRIT_SINK_RE = re.compile(r"^Info:\s+Sink (\S+)")
CRIT_SUM_RE = re.compile(r"^Info: (-?[\d.]+) ns logic, (-?[\d.]+) ns routing")
ERROR_RE = re.compile(r"^ERROR: (.*)$", re.M)
PORT_RE = re.compile(r"\b(input|output|inout)\s+(?:wire\s+|reg\s+)?(?:\[(\d+):(\d+)\]\s*)?(\w+)")


class PnrError(RuntimeError):
    """A step of the flow failed; the message says which and why."""


class SynthOnly(Exception):
    """--synth-only: the flow stops after yosys."""


@dataclass(frozen=True)
class Tools:
    nextpnr: str
    chipdb: Path


@dataclass(frozen=True)
class Port:
    direction: str
    name: str
    width: int


# ---------------------------------------------------------------------------------------------- tools


def _executable(p: Path) -> bool:
    return p.is_file() and os.access(p, os.X_OK)


def find_nextpnr(env: dict[str, str] | None = None) -> str | None:
    """$NEXTPNR_XILINX, else nextpnr-xilinx on PATH, else one in TOOL_DIRS."""
    env = dict(os.environ) if env is None else env
    if env.get(ENV_TOOL):
        p = Path(env[ENV_TOOL]).expanduser()
        return str(p) if _executable(p) else None
    found = shutil.which("nextpnr-xilinx", path=env.get("PATH"))
    if found:
        return found
    return next((str(d / "nextpnr-xilinx") for d in TOOL_DIRS if _executable(d / "nextpnr-xilinx")), None)


def find_chipdb(nextpnr: str | None, env: dict[str, str] | None = None) -> Path | None:
    """$NEXTPNR_XILINX_CHIPDB (a file, or a folder holding one of CHIPDB_NAMES), else CHIPDB_DIRS and
    the tool's own tree (../xilinx/ and ../chipdb/ of the binary's folder)."""
    env = dict(os.environ) if env is None else env

    def in_dir(d: Path) -> Path | None:
        return next((d / n for n in CHIPDB_NAMES if (d / n).is_file()), None)

    if env.get(ENV_CHIPDB):
        p = Path(env[ENV_CHIPDB]).expanduser()
        return p if p.is_file() else in_dir(p) if p.is_dir() else None
    dirs = list(CHIPDB_DIRS)
    if nextpnr:
        base = Path(nextpnr).resolve().parent
        dirs += [base.parent / "xilinx", base.parent / "chipdb", base / "chipdb"]
    return next((db for db in map(in_dir, dirs) if db), None)


def find_tools(env: dict[str, str] | None = None) -> Tools | str:
    """The tool and its chip database, or the one line that says what is missing."""
    nextpnr = find_nextpnr(env)
    if nextpnr is None:
        return MISSING_TOOL
    chipdb = find_chipdb(nextpnr, env)
    if chipdb is None:
        return MISSING_CHIPDB
    return Tools(nextpnr, chipdb)


def tool_version(cmd: Sequence[str]) -> str:
    """First line a tool prints for --version (nextpnr prints it on stderr)."""
    try:
        p = subprocess.run(list(cmd), capture_output=True, text=True, check=False, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return "?"
    lines = (p.stdout + p.stderr).strip().splitlines()
    return lines[0].strip() if lines else "?"


# -------------------------------------------------------------------------------------------- wrapper


def parse_ports(verilog: str, module: str) -> list[Port]:
    """The ports of `module` in a netlist in GHDL's Verilog style (ANSI header, one port a line)."""
    m = re.search(rf"^module\s+{re.escape(module)}\b(.*?)\);", verilog, re.M | re.S)
    if not m:
        raise PnrError(f"module {module} not found in the netlist")
    ports = [Port(d, name, abs(int(hi) - int(lo)) + 1 if hi else 1) for d, hi, lo, name in PORT_RE.findall(m.group(1))]
    if not ports:
        raise PnrError(f"module {module}: no ports found in its header")
    return ports


def _shift(reg: str, width: int, fill: str) -> str:
    return fill if width == 1 else f"{{{reg}[{width - 2}:0], {fill}}}"


def wrapper(module: str, ports: Sequence[Port], clock: str = CLOCK_PORT) -> str:
    """Verilog of WRAP_TOP: `module`'s inputs from a shift register fed by pin si, its outputs loaded
    (ld = 1) into a shift register read out on pin so, its clock on pin clk."""
    if any(p.direction == "inout" for p in ports):
        raise PnrError(f"{module} has inout ports; the wrapper handles inputs and outputs only")
    if not any(p.name == clock and p.direction == "input" for p in ports):
        raise PnrError(f"{module} has no input port {clock}")
    ins = [p for p in ports if p.direction == "input" and p.name != clock]
    outs = [p for p in ports if p.direction == "output"]
    n_in = max(1, sum(p.width for p in ins))
    n_out = max(1, sum(p.width for p in outs))
    conns = [f"    .{clock}(clk)"]
    for group, reg in ((ins, "isr"), (outs, "o")):
        lsb = 0
        for p in group:
            conns.append(f"    .{p.name}({reg}[{lsb + p.width - 1}:{lsb}])")
            lsb += p.width
    body = ",\n".join(conns)
    shift_in, shift_out = _shift("isr", n_in, "si"), _shift("osr", n_out, "1'b0")
    return (
        f"// generated by sw/orb_flow/pnr.py: every port of {module} but its clock on a register\n"
        f"module {WRAP_TOP} (input clk, input si, input ld, output so);\n"
        f"  reg [{n_in - 1}:0] isr = 0;\n"
        f"  reg [{n_out - 1}:0] osr = 0;\n"
        f"  wire [{n_out - 1}:0] o;\n"
        f"  always @(posedge clk) isr <= {shift_in};\n"
        f"  always @(posedge clk) osr <= ld ? o : {shift_out};\n"
        f"  assign so = osr[{n_out - 1}];\n"
        f"  {module} dut (\n{body}\n  );\n"
        "endmodule\n"
    )


def xdc(period_ns: float = PERIOD_NS) -> str:
    """Constraints: the clock pin and its period; IOSTANDARD on every pin (nextpnr-xilinx requires it);
    si, ld and so are placed by nextpnr."""
    lines = [f"set_property PACKAGE_PIN {CLOCK_PIN} [get_ports clk]"]
    lines += [f"set_property IOSTANDARD LVCMOS33 [get_ports {p}]" for p in ("clk", "si", "ld", "so")]
    lines.append(f"create_clock -period {period_ns} -name clk [get_ports clk]")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------------------------ log parser


def parse_critical_paths(text: str) -> dict[str, dict[str, Any]]:
    """The last critical-path report of each clock in a nextpnr log: start (the first Source), end
    (the last Sink), delay (the running total, setup included), logic and routing parts, and the
    number of nets on the path."""
    paths: dict[str, dict[str, Any]] = {}
    cur: dict[str, Any] | None = None
    for line in text.splitlines():
        head = CRIT_HEAD_RE.match(line)
        if head:
            cur = {"clock": head[1], "edges": f"{head[2]} -> {head[3]}", "from": None, "to": None,
                   "delay_ns": None, "logic_ns": None, "routing_ns": None, "nets": 0}  # fmt: skip
            continue
        if cur is None:
            continue
        step = CRIT_STEP_RE.match(line)
        sink = CRIT_SINK_RE.match(line)
        summary = CRIT_SUM_RE.match(line)
        if step:
            kind = step[3]
            cur["delay_ns"] = float(step[2])
            if kind == "Source" and cur["from"] is None:
                cur["from"] = step[4]
            cur["nets"] += kind == "Net"
        elif sink:
            cur["to"] = sink[1]
        elif summary:
            cur["logic_ns"], cur["routing_ns"] = float(summary[1]), float(summary[2])
            paths[cur["clock"]] = cur
            cur = None
    return paths


def parse_log(text: str) -> dict[str, Any]:
    """What record.json keeps of a nextpnr-xilinx log: per clock the last Fmax line and the last
    critical path, `post_route` (whether that last report comes after the router's end), and the
    errors."""
    clocks: dict[str, dict[str, Any]] = {}
    for name, fmax, verdict, target in FMAX_RE.findall(text):
        clocks[name] = {"fmax_mhz": float(fmax), "target_mhz": float(target), "pass": verdict == "PASS"}
    for name, path in parse_critical_paths(text).items():
        clocks.setdefault(name, {"fmax_mhz": None, "target_mhz": None, "pass": None})["critical_path"] = path
    routed = [m.end() for m in ROUTED_RE.finditer(text)]
    reported = [m.start() for m in FMAX_RE.finditer(text)]
    return {
        "post_route": bool(routed and reported and reported[-1] > routed[-1]),  # the last report follows routing
        "clocks": clocks,
        "errors": [e.strip() for e in ERROR_RE.findall(text) if not e.startswith("Max frequency")],
    }


def main_clock(parsed: dict[str, Any]) -> tuple[str, dict[str, Any]] | None:
    """The clock the figures are about: the one with the lowest Fmax (here the only one, clk)."""
    timed = [(k, v) for k, v in parsed["clocks"].items() if v.get("fmax_mhz") is not None]
    return min(timed, key=lambda kv: kv[1]["fmax_mhz"]) if timed else None


# ------------------------------------------------------------------------------------------- the flow


def say(msg: str) -> None:
    print(f"pnr: {msg}", flush=True)


def cache_key(job: synth.Job, files: Sequence[Path], tools: dict[str, str]) -> str:
    base = synth.cache_key(job.top, job.generics, files, tools)
    meta = json.dumps({"pnr_flow": FLOW_VERSION, "script": YOSYS_SCRIPT, "period": PERIOD_NS}, sort_keys=True)
    return hashlib.sha256((base + meta).encode()).hexdigest()


def synthesise(job: synth.Job, cdir: Path, rec: dict[str, Any], timeout: float) -> None:
    """GHDL (synth.ghdl_synth) and yosys -> cdir/top.json; reused when the key in cdir/synth.json
    matches, with the wall times it measured."""
    ghdl, yosys = synth.find_tools()
    files = sources()
    tools = {"ghdl": synth.tool_version([ghdl, "--version"]), "yosys": synth.tool_version([yosys, "-V"])}
    rec["tools"].update(tools)
    key = cache_key(job, files, tools)
    stamp = cdir / "synth.json"
    try:
        done = json.loads(stamp.read_text())
    except (OSError, ValueError):
        done = {}
    if (cdir / "top.json").is_file() and done.get("key") == key:
        say(f"synthesis of {rec['config']} is up to date (build/pnr/{cdir.name}/top.json)")
        rec["wall_s"].update(done.get("wall_s", {}))
        rec["synth_reused"] = True
        return
    say(f"synthesising {rec['config']} (GHDL, {job.name})")
    stamp.unlink(missing_ok=True)
    synth.ghdl_synth(ghdl, job, files, cdir, rec)
    (cdir / "wrap.v").write_text(wrapper(job.top, parse_ports((cdir / "top.v").read_text(), job.top)))
    say("synthesising: yosys synth_xilinx -abc9 -flatten (25 min measured for board-vga on 2 cores)")
    wall, cpu = synth.run_yosys(yosys, WRAP_TOP, cdir, YOSYS_SCRIPT, "yosys_pnr", timeout)
    rec["wall_s"]["yosys"] = round(wall, 1)
    rec["cpu_s"] = {"yosys": round(cpu, 1)}
    walls = {k: rec["wall_s"][k] for k in ("ghdl", "yosys")}
    stamp.write_text(json.dumps({"key": key, "wall_s": walls, "cpu_s": rec["cpu_s"]}, indent=2) + "\n")
    rec["synth_reused"] = False


def fill_cells(cdir: Path, rec: dict[str, Any]) -> None:
    """The wrapped netlist's cell counts (synth.py's counting) and their share of the XC7Z020."""
    cells = synth.summarise(synth.parse_stat((cdir / "stat.txt").read_text(), WRAP_TOP))
    keep = ("lut", "ff", "bram36", "dsp", "carry4", "srl", "lutram")
    rec["cells"] = {k: cells[k] for k in keep}
    rec["utilisation_pct"] = {k: round(100 * cells[k] / DEVICE[k], 1) for k in ("lut", "ff", "bram36", "dsp")}


def nextpnr_cmd(tools: Tools, cdir: Path, seed: int, write_routed: bool) -> list[str]:
    cmd = [tools.nextpnr, "--chipdb", str(tools.chipdb), "--xdc", "pnr.xdc", "--json", "top.json"]
    cmd += ["--freq", f"{1000 / PERIOD_NS:.2f}", "--seed", str(seed)]
    return cmd + (["--write", "routed.json"] if write_routed else [])


def follow(lines: Iterable[str], log: TextIO, t0: float, rec: dict[str, Any]) -> None:
    """Copy nextpnr's output to the log, print each stage as it starts and a line every HEARTBEAT_S;
    stage start times (s after t0) go to rec['stage_start_s']."""
    starts: dict[str, float] = rec.setdefault("stage_start_s", {})
    nxt, last_beat, last_line = 0, t0, ""
    for line in lines:
        log.write(line)
        now = time.monotonic()
        for i in range(nxt, len(STAGES)):
            name, pat = STAGES[i]
            if pat.match(line):
                starts[name] = round(now - t0, 1)
                say(name)
                nxt = i + 1
                break
        if line.strip():
            last_line = line.strip()
        if now - last_beat >= HEARTBEAT_S:
            say(f"  ... {(now - t0) / 60:.0f} min: {last_line[:100]}")
            last_beat = now


def run_nextpnr(tools: Tools, cdir: Path, rec: dict[str, Any], timeout: float, seed: int, write: bool) -> str:
    cmd = nextpnr_cmd(tools, cdir, seed, write)
    rec["command"] = " ".join(cmd)
    t0 = time.monotonic()
    with open(cdir / "nextpnr.log", "w") as log:
        proc = subprocess.Popen(cmd, cwd=cdir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        timer = threading.Timer(timeout, proc.kill)
        timer.start()
        try:
            assert proc.stdout is not None
            follow(proc.stdout, log, t0, rec)
            proc.wait()
        finally:
            timer.cancel()
            if proc.poll() is None:
                proc.kill()
    wall = time.monotonic() - t0
    rec["wall_s"]["nextpnr"] = round(wall, 1)
    rec["nextpnr_exit"] = proc.returncode
    text = (cdir / "nextpnr.log").read_text()
    if proc.returncode != 0:
        rec["errors"].append(
            f"nextpnr-xilinx did not finish within {timeout:.0f} s"
            if wall >= timeout
            else f"nextpnr-xilinx exited {proc.returncode} after {wall:.0f} s"
        )
    return text


def fill_timing(rec: dict[str, Any], text: str) -> None:
    parsed = parse_log(text)
    rec["timing"] = parsed
    rec["errors"] += parsed["errors"]
    main = main_clock(parsed)
    if main is None:
        return
    name, c = main
    path = c.get("critical_path") or {}
    rec.update(
        clock=name,
        fmax_mhz=c["fmax_mhz"],
        target_mhz=c["target_mhz"],
        met=c["pass"],
        critical_path={k: path.get(k) for k in ("from", "to", "delay_ns", "logic_ns", "routing_ns", "nets")},
    )


def cells_line(rec: dict[str, Any]) -> str:
    c, u = rec.get("cells"), rec.get("utilisation_pct", {})
    if not c:
        return "-"
    main = ", ".join(f"{c[k]:g} {k} ({u[k]} %)" for k in ("lut", "ff", "bram36", "dsp"))
    return f"{main}; {c['carry4']} CARRY4"


def summary_md(rec: dict[str, Any]) -> str:
    cp = rec.get("critical_path") or {}
    fmax = rec.get("fmax_mhz")
    state = "post-route" if rec.get("timing", {}).get("post_route") else "NOT routed (pre-route estimate or none)"
    timing = [
        f"- timing ({state}): Fmax {fmax if fmax is not None else '-'} MHz for clock "
        f"{rec.get('clock', '-')}, target {rec.get('target_mhz', '-')} MHz, "
        f"{'met' if rec.get('met') else 'not met' if rec.get('met') is False else '-'}",
        f"- critical path: {cp.get('from', '-')} -> {cp.get('to', '-')}, {cp.get('delay_ns', '-')} ns "
        f"({cp.get('logic_ns', '-')} ns logic, {cp.get('routing_ns', '-')} ns routing, {cp.get('nets', '-')} nets)",
    ]
    if rec.get("synth_only"):
        timing = ["- timing: not measured (--synth-only: nextpnr-xilinx not run)"]
    rows = [
        f"# nextpnr-xilinx place and route: {rec['config']} ({rec['job']})",
        "",
        f"- part: {rec['part']}, chip database {rec['chipdb']}",
        f"- tools: {'; '.join(f'{k} {v}' for k, v in rec['tools'].items())}",
        f"- cells (yosys, with the wrapper): {cells_line(rec)}",
        *timing,
        f"- wall: {', '.join(f'{k} {v:.0f} s' for k, v in rec['wall_s'].items())}",
        f"- command: `{rec.get('command', '-')}` (in build/pnr/{rec['config']}/)",
        "",
        "nextpnr-xilinx's timing model, not Vivado's: see docs/pnr.md for what it measures and its limits.",
    ]
    if rec["errors"]:
        rows += ["", "Errors:", *(f"- {e}" for e in rec["errors"])]
    return "\n".join(rows) + "\n"


def new_record(config: str, job: synth.Job, tools: Tools | None) -> dict[str, Any]:
    return {
        "config": config,
        "top": job.top,
        "job": job.name,
        "generics": job.generics,
        "part": PART,
        "chipdb": str(tools.chipdb) if tools else None,
        "chipdb_bytes": tools.chipdb.stat().st_size if tools else None,
        "period_ns": PERIOD_NS,
        "tools": {"nextpnr-xilinx": tool_version([tools.nextpnr, "--version"]) if tools else "not run (--synth-only)"},
        "hdl": synth.hdl_revision(),
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "wall_s": {},
        "errors": [],
    }


def write_record(cdir: Path, rec: dict[str, Any]) -> None:
    (cdir / "record.json").write_text(json.dumps(rec, indent=2) + "\n")
    (cdir / "summary.md").write_text(summary_md(rec))


def run(config: str, tools: Tools | None, out: Path, timeout: float, seed: int, write_routed: bool) -> dict[str, Any]:
    """The flow for one configuration; tools None: synthesis only (--synth-only)."""
    job = synth.named_job(TOP, config)
    cdir = out / config
    cdir.mkdir(parents=True, exist_ok=True)
    rec = new_record(config, job, tools)
    t0 = time.monotonic()
    try:
        synthesise(job, cdir, rec, timeout)
        fill_cells(cdir, rec)
        (cdir / "pnr.xdc").write_text(xdc())
        if tools is None:
            rec["synth_only"] = True
            raise SynthOnly
        say(f"running nextpnr-xilinx ({tools.chipdb.name}, log build/pnr/{config}/nextpnr.log)")
        fill_timing(rec, run_nextpnr(tools, cdir, rec, timeout, seed, write_routed))
    except SynthOnly:
        say("--synth-only: stopping before nextpnr-xilinx")
    except (synth.ToolError, synth.VerilogError, PnrError) as e:
        rec["errors"].append(str(e))
    rec["wall_s"]["total"] = round(time.monotonic() - t0, 1)
    write_record(cdir, rec)
    return rec


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--named", default=DEFAULT_CONFIG, metavar="NAME",
                    help=f"named configuration (docs/configurations.md), default {DEFAULT_CONFIG}")  # fmt: skip
    ap.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S, metavar="S",
                    help=f"limit of each tool run in seconds (default {DEFAULT_TIMEOUT_S:.0f})")  # fmt: skip
    ap.add_argument("--seed", type=int, default=1, help="nextpnr's placer seed (default 1)")
    ap.add_argument("--write-routed", action="store_true", help="also write the routed netlist (routed.json)")
    ap.add_argument("--out", type=Path, default=OUT, help="output folder (default build/pnr)")
    ap.add_argument("--synth-only", action="store_true",
                    help="stop after yosys (top.json, cell counts); needs no nextpnr-xilinx")  # fmt: skip
    args = ap.parse_args(argv)
    found = None if args.synth_only else find_tools()
    if isinstance(found, str):
        print(found, file=sys.stderr)
        return 2
    try:
        synth.named_job(TOP, args.named)
    except ValueError as e:
        ap.error(str(e))
    rec = run(args.named, found, args.out, args.timeout, args.seed, args.write_routed)
    sys.stdout.write(summary_md(rec))
    say(f"record: {synth.rel(args.out / args.named / 'record.json')}")
    if rec["errors"]:
        return 1
    return 0 if args.synth_only or rec.get("fmax_mhz") is not None else 1


if __name__ == "__main__":
    sys.exit(main())
