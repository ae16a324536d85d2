#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Worst paths of a synthesised xc7 netlist, by endpoint and by block: the readable side of the
logic-delay estimate (docs/synthesis.md, "Timing").

Input: net.json, the flattened netlist synth.py's timing pass writes after `synth_xilinx -abc9
-flatten` (yosys `write_json`), and yosys's own cell models (share/yosys/xilinx/cells_sim.v).

The delay model is yosys `sta`'s, read from the same specify blocks: per cell type the
combinational arcs (`(I0 => O) = 642`), the clock-to-output arrivals (`(posedge C => (Q : D)) =
303`, the largest where several are given, whatever their condition) and the setup times
(`$setup(CE, posedge C, 109)`); the DSP48E1's parameter-dependent figures are the ones its
specify functions compute. No routing, no clock skew: a pre-route logic-delay estimate. Unlike
yosys 0.23's `sta`, the LUT-RAM cells (RAM32M, RAM64X1D, ...) are timed too, from the same file.

A path starts at a primary input (time 0) or at a sequential cell's output (its arrival) and ends
at a sequential cell's input with a setup time (arrival + setup) or at a primary output. For
every endpoint bit the tool keeps the latest path and walks it back: the start, the cells passed
(LUTs = logic levels, CARRY4 = carry-chain length, MUXF7/F8), and the delay.

Reports (as JSON and Markdown): the ten worst paths with distinct endpoint registers (the bits of
one vector count as one endpoint), the worst path per block (hierarchy prefix of the endpoint,
e.g. `u_core.g_level[1].u_path`), the number of endpoint bits over a limit, and a histogram.

Usage: python3 -m orb_flow.timing NET_JSON [--top T] [--limit-ns 3.5] [--paths 10] [--json F] [--md F]
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

CELLS_SIM_CANDIDATES = (
    Path("/usr/share/yosys/xilinx/cells_sim.v"),
    Path("/usr/local/share/yosys/xilinx/cells_sim.v"),
)

COMB_RE = re.compile(r"\(\s*(\w+)\s*(?:\[(\d+)\])?\s*([*=])>\s*(\w+)\s*(?:\[(\d+)\])?\s*\)\s*=\s*(\d+)\s*;")
EDGE_RE = re.compile(r"\(\s*(?:pos|neg)edge\s+(\w+)\s*=>\s*\(\s*(\w+)\s*(?:\[(\d+)\])?\s*:[^)]*\)\s*\)\s*=\s*(\d+)\s*;")
SETUP_RE = re.compile(r"\$setup\(\s*(\w+)\s*(?:\[(\d+)\])?\s*,[^,]*,\s*(?:/\*[^*]*\*/\s*)?(\d+)\s*\)")
MODULE_RE = re.compile(r"^module\s+(\\?\S+?)\s*[(#]", re.M)

GHDL_NAME_RE = re.compile(r"(^|\.)n\d+_[a-z]+$")
LUT_TYPES = {f"LUT{n}" for n in range(1, 7)}
MUX_TYPES = {"MUXF7", "MUXF8"}


@dataclass
class CellModel:
    """A cell type's arcs: (src port, src bit or None, full, dst port, dst bit or None, ps)."""

    comb: list[tuple[str, int | None, bool, str, int | None, int]] = field(default_factory=list)
    arrival: dict[tuple[str, int | None], tuple[str, int]] = field(default_factory=dict)  # -> (clock, ps)
    required: dict[tuple[str, int | None], int] = field(default_factory=dict)


def find_cells_sim() -> Path:
    for p in CELLS_SIM_CANDIDATES:
        if p.exists():
            return p
    raise FileNotFoundError("yosys's xilinx/cells_sim.v not found (install yosys: apt-get install yosys)")


def read_models(path: Path) -> dict[str, CellModel]:
    """The specify blocks of cells_sim.v, per module (DSP48E1 is computed by dsp_model)."""
    text = path.read_text()
    models: dict[str, CellModel] = {}
    starts = [(m.start(), m[1]) for m in MODULE_RE.finditer(text)]
    for i, (pos, name) in enumerate(starts):
        end = starts[i + 1][0] if i + 1 < len(starts) else len(text)
        body = text[pos:end]
        if name == "DSP48E1" or "specify" not in body:
            continue
        m = CellModel()
        for blk in re.findall(r"specify(.*?)endspecify", body, re.S):
            blk = re.sub(r"//[^\n]*", "", blk)
            for a in COMB_RE.finditer(blk):
                sb = int(a[2]) if a[2] is not None else None
                db = int(a[5]) if a[5] is not None else None
                m.comb.append((a[1], sb, a[3] == "*", a[4], db, int(a[6])))
            for a in EDGE_RE.finditer(blk):
                key = (a[2], int(a[3]) if a[3] is not None else None)
                m.arrival[key] = (a[1], max(m.arrival.get(key, ("", 0))[1], int(a[4])))
            for a in SETUP_RE.finditer(blk):
                if int(a[3]) <= 0:
                    continue  # as yosys: zero and negative setups are ignored
                key = (a[1], int(a[2]) if a[2] is not None else None)
                m.required[key] = max(m.required.get(key, 0), int(a[3]))
        models[name] = m
    return models


def _param(p: dict[str, Any], name: str, default: Any) -> Any:
    v = p.get(name, default)
    if isinstance(v, str) and re.fullmatch(r"[01xz]+", v) and name not in ("USE_MULT", "USE_DPORT"):
        return int(v.replace("x", "0").replace("z", "0"), 2)
    return v.strip() if isinstance(v, str) else v


def dsp_model(params: dict[str, Any]) -> CellModel:
    """DSP48E1 figures as its specify functions in cells_sim.v compute them from the parameters."""
    g = {
        k: _param(params, k, d)
        for k, d in (
            ("AREG", 1),
            ("BREG", 1),
            ("CREG", 1),
            ("DREG", 1),
            ("ADREG", 1),
            ("MREG", 1),
            ("PREG", 1),
            ("USE_MULT", "MULTIPLY"),
            ("USE_DPORT", "FALSE"),
            ("USE_PATTERN_DETECT", "NO_PATDET"),
        )
    }
    mult, dport, pat = g["USE_MULT"], g["USE_DPORT"], g["USE_PATTERN_DETECT"] != "NO_PATDET"
    md, mt, nd = (
        mult == "MULTIPLY" and dport == "FALSE",
        mult == "MULTIPLY" and dport == "TRUE",
        mult == "NONE" and dport == "FALSE",
    )
    regs = ("AREG", "BREG", "CREG", "DREG", "ADREG", "MREG", "PREG")
    areg, breg, creg, dreg, adreg, mreg, preg = (g[k] != 0 for k in regs)

    def a_req() -> int:
        if areg:
            return 254
        if md:
            return 1416 if mreg else (3030 if pat else 2739) if preg else 0
        if mt:
            return 2400 if mreg else 1283 if adreg else (4014 if pat else 3723) if preg else 0
        if nd and preg:
            return 1730 if pat else 1441
        return 0

    def b_req() -> int:
        if breg:
            return 324
        if mreg:
            return 1285
        if (md or mt) and preg:
            return 2898 if pat else 2608
        if nd and preg:
            return 1718 if pat else 1428
        return 0

    def c_req() -> int:
        return 168 if creg else (1534 if pat else 1244) if preg else 0

    def d_req() -> int:
        if not mt:
            return 0
        return 248 if dreg else 1195 if adreg else 2310 if mreg else (3925 if pat else 3635) if preg else 0

    def arrival(pc: bool) -> int:
        x = 106 if pc else 0  # PCOUT is that much later than P in every case but the last
        if preg:
            return 329 + x
        if creg:
            return 1687 + (148 if pc else 0)
        if md:
            if mreg:
                return 1671 + (148 if pc else 0)
            if areg:
                return 2952 + (146 if pc else 0)
            return (2813 + (147 if pc else 0)) if breg else 0
        if mt:
            if mreg:
                return 1671 + (148 if pc else 0)
            if areg:
                return 4083 if pc else 3935
            if dreg:
                return 4056 if pc else 3908
            if pc:
                return 2960 if breg else 2859 if adreg else 0
            return 2958 if adreg else 2813 if breg else 0
        if nd:
            return (1780 if pc else 1632) if areg else (1765 if pc else 1616) if breg else 0
        return 0

    m = CellModel()
    if not (preg or mreg or areg or adreg):
        m.comb += [
            ("A", None, True, "P", None, 2823 if md else 3806 if mt else 1523 if nd else 0),
            ("A", None, True, "PCOUT", None, 2970 if md else 3954 if mt else 1671 if nd else 0),
        ]
    elif a_req() > 0:
        m.required[("A", None)] = a_req()
    if not (preg or mreg or breg):
        m.comb += [
            ("B", None, True, "P", None, 2690 if (md or mt) else 1509 if nd else 0),
            ("B", None, True, "PCOUT", None, 2838 if (md or mt) else 1658 if nd else 0),
        ]
    elif b_req() > 0:
        m.required[("B", None)] = b_req()
    if not (preg or creg):
        m.comb += [("C", None, True, "P", None, 1325), ("C", None, True, "PCOUT", None, 1474)]
    elif c_req() > 0:
        m.required[("C", None)] = c_req()
    if not (preg or mreg or adreg or dreg):
        if mt:
            m.comb += [("D", None, True, "P", None, 3717), ("D", None, True, "PCOUT", None, 3700)]
    elif d_req() > 0:
        m.required[("D", None)] = d_req()
    if not preg:
        m.comb += [("PCIN", None, True, "P", None, 1107), ("PCIN", None, True, "PCOUT", None, 1255)]
    else:
        m.required[("PCIN", None)] = 1315 if pat else 1025
    if preg or areg or adreg or breg or creg or dreg or mreg:
        m.arrival[("P", None)] = ("CLK", arrival(False))
        m.arrival[("PCOUT", None)] = ("CLK", arrival(True))
    m.comb = [c for c in m.comb if c[5] > 0]
    return m


@dataclass
class Arc:
    src: int  # net bit
    dst: int
    ps: int
    cell: str
    ctype: str
    launch: bool = False  # a clock-to-output arc: the path starts at this cell


@dataclass
class Path_:
    endpoint: str  # name of the endpoint's net (the register's D input, or a port)
    end_reg: str  # the endpoint register's vector (its output net), else the net
    end_cell: str
    end_port: str
    arrival_ps: int  # arrival + setup
    setup_ps: int
    start: str
    start_type: str
    luts: int
    carry4: int
    muxf: int
    cells: list[tuple[str, str, int]]  # (cell type, output net name, arrival ps), start first

    def as_dict(self) -> dict[str, Any]:
        return {
            "endpoint": self.end_reg,
            "endpoint_bit": self.endpoint,
            "endpoint_cell": f"{self.end_cell}.{self.end_port}",
            "start": self.start,
            "start_type": self.start_type,
            "delay_ns": round(self.arrival_ps / 1000, 3),
            "setup_ns": round(self.setup_ps / 1000, 3),
            "lut_levels": self.luts,
            "carry4": self.carry4,
            "muxf": self.muxf,
            "block": block_of(self.end_reg),
            "cells": [{"type": t, "net": n, "at_ns": round(a / 1000, 3)} for t, n, a in self.cells],
        }


def block_of(name: str) -> str:
    """The hierarchy prefix of a net name: everything before the last dot, else '(top)'."""
    name = name.lstrip("\\")
    depth = 0
    cut = -1
    for i, ch in enumerate(name):
        if ch == "[":
            depth += 1
        elif ch == "]":
            depth -= 1
        elif ch == "." and depth == 0:
            cut = i
    return name[:cut] if cut > 0 else "(top)"


def path_block(p: Path_) -> str:
    """The block of a path: that of its endpoint register, else of the last net on the path with
    a name from the design (yosys's own names start with '$'), else '(top)'."""
    for name in [p.end_reg, *(n for _, n, _ in reversed(p.cells))]:
        if not name.lstrip("\\").startswith("$") and not name.startswith("<"):
            return block_of(name.split(" (")[0])
    return "(top)"


def vector_of(name: str) -> str:
    return re.sub(r"\[\d+\]$", "", name)


class Netlist:
    def __init__(self, net: dict[str, Any], top: str | None, models: dict[str, CellModel]) -> None:
        mods = net["modules"]
        if top is None:
            marked = (1, "1", "00000000000000000000000000000001")
            tops = [n for n, m in mods.items() if m.get("attributes", {}).get("top") in marked]
            top = tops[0] if tops else max(mods, key=lambda n: len(mods[n].get("cells", {})))
        self.top = top
        mod = mods[top]
        self.names: dict[int, str] = {}
        self._rank: dict[int, tuple[bool, bool, int]] = {}
        self._q: dict[str, int] = {}  # FD cell -> its Q bit
        for name, nn in mod.get("netnames", {}).items():
            hidden = nn.get("hide_name", 0) or name.startswith("$")
            for i, b in enumerate(nn["bits"]):
                if not isinstance(b, int):
                    continue
                full = name if len(nn["bits"]) == 1 else f"{name}[{i + nn.get('offset', 0)}]"
                old = self.names.get(b)
                # GHDL's own names (n254_q, n12_o) only where the design's signal name is gone
                generated = bool(GHDL_NAME_RE.search(name))
                rank = (hidden, generated, len(full))
                if old is None or rank < self._rank[b]:
                    self.names[b] = full
                    self._rank[b] = rank
        self.arcs: dict[int, list[Arc]] = defaultdict(list)  # by source bit
        self.start: dict[int, tuple[int, str, str]] = {}  # bit -> (arrival, cell, type)
        self.ends: dict[int, tuple[int, str, str, str]] = {}  # bit -> (setup, cell, type, port)
        self.untimed: dict[str, int] = defaultdict(int)
        for port in mod.get("ports", {}).values():
            for b in port["bits"]:
                if isinstance(b, int):
                    if port["direction"] == "input":
                        self.start[b] = (0, "<input>", "port")
                    else:
                        self.ends.setdefault(b, (0, "<output>", "port", ""))
        for cname, cell in mod.get("cells", {}).items():
            ctype = cell["type"]
            model = dsp_model(cell.get("parameters", {})) if ctype == "DSP48E1" else models.get(ctype)
            if model is None:
                self.untimed[ctype] += 1
                continue
            conns = cell["connections"]
            if ctype.startswith("FD"):
                q = [b for b in conns.get("Q", []) if isinstance(b, int)]
                if q:
                    self._q[cname] = q[0]
            dirs = cell.get("port_directions", {})

            def bits(port: str, idx: int | None, conns: dict[str, list[Any]] = conns) -> list[int]:
                bs = conns.get(port, [])
                sel = bs if idx is None else (bs[idx : idx + 1] if idx < len(bs) else [])
                return [b for b in sel if isinstance(b, int)]

            required = dict(model.required)
            if ctype.startswith("FD"):
                required.setdefault(("D", None), 0)  # a zero setup, which the specify block leaves out
            for (port, idx), ps in required.items():
                if dirs.get(port, "input") != "input":
                    continue
                for b in bits(port, idx):
                    old = self.ends.get(b)
                    if old is None or old[0] < ps:
                        self.ends[b] = (ps, cname, ctype, port)
            for (port, idx), (clock, ps) in model.arrival.items():
                # as yosys: the clock's own arrival (input buffer, BUFG) comes first
                for c in bits(clock, None)[:1]:
                    for b in bits(port, idx):
                        self.arcs[c].append(Arc(c, b, ps, cname, ctype, launch=True))
            for sp, si, full, dp, di, ps in model.comb:
                sb, db = bits(sp, si), bits(dp, di)
                if full or si is not None or di is not None:
                    pairs = [(s, d) for s in sb for d in db]
                else:
                    pairs = list(zip(sb, db, strict=False))
                for s, d in pairs:
                    self.arcs[s].append(Arc(s, d, ps, cname, ctype))

    def name(self, b: int) -> str:
        return self.names.get(b, f"<net {b}>")

    def analyse(self) -> tuple[dict[int, int], dict[int, Arc | None]]:
        """Latest arrival at every net bit (longest path through a DAG of combinational arcs)."""
        indeg: dict[int, int] = defaultdict(int)
        for arcs in self.arcs.values():
            for a in arcs:
                indeg[a.dst] += 1
        arrival: dict[int, int] = {}
        pred: dict[int, Arc | None] = {}
        for b, (ps, _c, _t) in self.start.items():
            arrival[b] = ps
            pred[b] = None
        ready = [b for b in set(self.arcs) | set(self.start) if indeg.get(b, 0) == 0]
        seen = 0
        while ready:
            b = ready.pop()
            seen += 1
            t = arrival.get(b)
            for a in self.arcs.get(b, ()):
                if t is not None and (a.dst not in arrival or arrival[a.dst] < t + a.ps):
                    arrival[a.dst] = t + a.ps
                    pred[a.dst] = a
                indeg[a.dst] -= 1
                if indeg[a.dst] == 0:
                    ready.append(a.dst)
        loops = [b for b, n in indeg.items() if n > 0]
        if loops:
            print(f"warning: {len(loops)} net bits on combinational loops are not timed", file=sys.stderr)
        return arrival, pred

    def path(self, end: int, arrival: dict[int, int], pred: dict[int, Arc | None]) -> Path_:
        setup, ecell, etype, eport = self.ends[end]
        cells: list[tuple[str, str, int]] = []
        b = end
        luts = carry = muxf = 0
        start_type = "port"
        while pred.get(b) is not None:
            a = pred[b]
            assert a is not None
            if a.launch:
                start_type = a.ctype
                break
            cells.append((a.ctype, self.name(b), arrival[b]))
            if a.ctype in LUT_TYPES:
                luts += 1
            elif a.ctype == "CARRY4":
                carry += 1
            elif a.ctype in MUX_TYPES:
                muxf += 1
            b = a.src
        cells.append((start_type, self.name(b), arrival.get(b, 0)))
        cells.reverse()
        end_name = self.name(end)
        if etype.startswith("FD"):
            reg = self._reg_name(ecell)
        else:
            reg = f"{end_name} ({etype}.{eport})" if etype != "port" else vector_of(end_name)
        return Path_(
            end_name,
            reg,
            ecell,
            eport,
            arrival.get(end, 0) + setup,
            setup,
            self.name(b),
            start_type,
            luts,
            carry,
            muxf,
            cells,
        )

    def _reg_name(self, cell: str) -> str:
        q = self._q.get(cell)
        return vector_of(self.name(q)) if q is not None else cell


def load(net_json: Path, top: str | None, cells_sim: Path | None = None) -> Netlist:
    models = read_models(cells_sim or find_cells_sim())
    return Netlist(json.loads(net_json.read_text()), top, models)


def report(nl: Netlist, limit_ns: float, n_paths: int) -> dict[str, Any]:
    arrival, pred = nl.analyse()
    per_bit = []
    for b, (setup, _c, _t, _p) in nl.ends.items():
        if b in arrival:
            per_bit.append((arrival[b] + setup, b))
    per_bit.sort(reverse=True)
    limit_ps = round(limit_ns * 1000)
    worst: list[Path_] = []
    seen_reg: set[str] = set()
    by_block: dict[str, Path_] = {}
    by_block_seen: set[int] = set()
    over = 0
    for t, b in per_bit:
        if t > limit_ps:
            over += 1
        p = None
        if len(worst) < n_paths:
            p = nl.path(b, arrival, pred)
            if p.end_reg not in seen_reg:
                seen_reg.add(p.end_reg)
                worst.append(p)
        if b in by_block_seen:
            continue
        p = p or nl.path(b, arrival, pred)
        blk = path_block(p)
        by_block_seen.add(b)
        if blk not in by_block:
            by_block[blk] = p
    hist: dict[str, int] = defaultdict(int)  # endpoint bits per half nanosecond
    for t, _ in per_bit:
        lo = min(t // 500, 19) * 500
        hist[f"[{lo / 1000:.1f}, {(lo + 500) / 1000:.1f}) ns" if lo < 9500 else "[9.5, ...) ns"] += 1
    return {
        "top": nl.top,
        "limit_ns": limit_ns,
        "logic_delay_ns": round(per_bit[0][0] / 1000, 3) if per_bit else None,
        "endpoints": len(per_bit),
        "endpoints_over_limit": over,
        "worst_paths": [p.as_dict() for p in worst],
        "worst_by_block": {k: v.as_dict() for k, v in sorted(by_block.items(), key=lambda kv: -kv[1].arrival_ps)},
        "histogram": dict(sorted(hist.items(), key=lambda kv: float(kv[0][1:].split(",")[0]))),
        "untimed_cells": dict(sorted(nl.untimed.items())),
    }


def markdown(rep: dict[str, Any], title: str) -> str:
    out = [
        f"### {title}",
        "",
        f"Longest path {rep['logic_delay_ns']} ns (pre-route logic delay, yosys cell models); "
        f"{rep['endpoints_over_limit']:,} of {rep['endpoints']:,} endpoint bits over {rep['limit_ns']} ns.",
        "",
        "| # | delay ns | LUT levels | CARRY4 | MUXF | start | end |",
        "|---|---|---|---|---|---|---|",
    ]
    for i, p in enumerate(rep["worst_paths"], 1):
        out.append(
            f"| {i} | {p['delay_ns']:.3f} | {p['lut_levels']} | {p['carry4']} | {p['muxf']} "
            f"| `{p['start']}` ({p['start_type']}) | `{p['endpoint']}` |"
        )
    out += [
        "",
        "Worst path per block:",
        "",
        "| block | delay ns | LUT levels | CARRY4 | start | end |",
        "|---|---|---|---|---|---|",
    ]
    for blk, p in rep["worst_by_block"].items():
        out.append(
            f"| `{blk}` | {p['delay_ns']:.3f} | {p['lut_levels']} | {p['carry4']} | `{p['start']}` "
            f"| `{p['endpoint']}` |"
        )
    if rep["untimed_cells"]:
        out += ["", "Untimed cells: " + ", ".join(f"{k} x{v}" for k, v in rep["untimed_cells"].items())]
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("net", type=Path)
    ap.add_argument("--top")
    ap.add_argument("--limit-ns", type=float, default=3.5)
    ap.add_argument("--paths", type=int, default=10)
    ap.add_argument("--json", type=Path)
    ap.add_argument("--md", type=Path)
    ap.add_argument("--cells-sim", type=Path)
    a = ap.parse_args(argv)
    rep = report(load(a.net, a.top, a.cells_sim), a.limit_ns, a.paths)
    md = markdown(rep, f"{rep['top']} ({a.net})")
    if a.json:
        a.json.write_text(json.dumps(rep, indent=1) + "\n")
    if a.md:
        a.md.write_text(md)
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
