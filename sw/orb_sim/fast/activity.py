# SPDX-License-Identifier: MIT
"""Switching activity of the netlist in Verilator (docs/power.md, "Activity"): the fast simulation
built with toggle coverage (`build_fast(..., toggle_coverage=True)`), whose counters say how often
each register bit of GHDL's netlist changed, per module, over a window of clocks.

What is counted (the rest of the netlist is left out of the coverage, `/*verilator coverage_off*/`:
counting every bit of every net each clock made the 640x480 build a hundred times slower than the
plain one):
  - every register of GHDL's netlist (`reg [..] nNNN_q;`, a flip-flop's output): the source of
    all activity, as in Vivado's vectorless estimate, whose default 12.5% is the registers' and
    inputs' toggle rate; combinational nets, ports and memory words (an inferred RAM's array) are
    not counted;
  - every orb_sdp_ram (the one RAM entity every FIFO, line buffer and memory uses) gets two probe
    registers that toggle on each clock its read (`rd_en`) and write (`wr_en`) port is enabled:
    their toggle counts are the ports' enabled clocks, the block RAM's enable rates. The probes
    add registers nothing reads: the design's behaviour is unchanged.

Registers wider than 32 bits are counted through 32-bit slices (wires `nNNN_q_pwcK` = bits 32K and
up, in the coverage instead of the register): Verilator 5.48's toggle coverage of a signal wider
than one 32-bit word counts word k's toggles k + 1 times (measured: a 392-bit shift register read
6.7 times its toggles; tb/flow/test_power.py checks the slices against exact counts).

Verilator keeps one set of counters per module when a module has several instances (the hierarchy
then reads `..._n*_...`): the counts are the sum over the instances.

Verilator counts each bit's 0->1 and 1->0 changes as two points; a net's toggles are their sum.
"""

from __future__ import annotations

import re
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

PROBE_RD, PROBE_WR = "pw_probe_rd", "pw_probe_wr"
RAM_MODULE_RE = re.compile(r"^module (orb_sdp_ram_\w+)$", re.M)
FF_RE = re.compile(r"^(\s*)reg (?:\[(\d+):(\d+)\] )?(n\d+_q);$", re.M)  # GHDL's flip-flop outputs
SLICE = 32  # bits a coverage slice holds (see above)
SLICE_RE = re.compile(r"^(.*)_pwc(\d+)$")
OFF, ON = "/*verilator coverage_off*/", "/*verilator coverage_on*/"
# One coverage point of coverage.dat: \x01key\x02value pairs, then the count
POINT_RE = re.compile(r"^C '(.*)' (\d+)$")
BIT_RE = re.compile(r"^(.*?)(?:\[(\d+)\])?:(0->1|1->0)$")


def instrument(verilog: str) -> tuple[str, int, int]:
    """The netlist with only its registers in the coverage and the RAM enable probes in: (text,
    number of register declarations, number of RAM modules probed)."""

    def cover(m: re.Match[str]) -> str:
        pad, hi, lo, name = m[1], int(m[2] or 0), int(m[3] or 0), m[4]
        if lo != 0:
            raise ValueError(f"{name}: a register whose bits do not start at 0 ([{hi}:{lo}])")
        if hi < SLICE:
            return f"{ON}\n{m[0]}\n{OFF}"
        parts = [(k, min(k * SLICE + SLICE - 1, hi)) for k in range((hi + SLICE) // SLICE)]
        decl = "".join(f"{pad}wire [{top - k * SLICE}:0] {name}_pwc{k};\n" for k, top in parts)
        assign = "".join(f"{pad}assign {name}_pwc{k} = {name}[{top}:{k * SLICE}];\n" for k, top in parts)
        return f"{m[0]}\n{ON}\n{decl}{OFF}\n{assign}"

    text, registers = FF_RE.subn(cover, verilog)
    text = f"{OFF}\n{text}"
    probes = 0
    out: list[str] = []
    pos = 0
    for m in RAM_MODULE_RE.finditer(text):
        end = text.index("\nendmodule", m.end())
        body = text[pos:end]
        if "input  rd_en" not in text[m.end() : end] or "input  wr_en" not in text[m.end() : end]:
            raise ValueError(f"{m[1]}: no rd_en/wr_en port (orb_sdp_ram's ports changed?)")
        out.append(body)
        out.append(
            f"\n{ON}\n  reg {PROBE_RD} = 1'b0;\n  reg {PROBE_WR} = 1'b0;\n{OFF}"
            f"\n  always @(posedge clk) if (rd_en) {PROBE_RD} <= ~{PROBE_RD};"
            f"\n  always @(posedge clk) if (wr_en) {PROBE_WR} <= ~{PROBE_WR};"
        )
        pos = end
        probes += 1
    out.append(text[pos:])
    return "".join(out), registers, probes


@dataclass
class Instance:
    """One instance's own nets (its children's not included): toggles summed over bits, bits
    covered, and, for an orb_sdp_ram, its ports' enabled clocks."""

    module: str = ""
    toggles: int = 0
    bits: int = 0
    rd_clocks: int | None = None
    wr_clocks: int | None = None
    nets: dict[str, int] = field(default_factory=dict)  # net -> toggles (all bits)


def parse_coverage(path: Path) -> dict[str, Instance]:
    """coverage.dat -> instance path (Verilator's hierarchy, e.g. top.orb_accel_top.core) -> its
    nets' toggles. The module of each instance is the coverage page's (v_toggle/<module>)."""
    inst: dict[str, Instance] = defaultdict(Instance)
    bits: dict[str, set[tuple[str, int]]] = defaultdict(set)
    for line in path.read_text(errors="replace").splitlines():
        m = POINT_RE.match(line)
        if not m:
            continue
        fields = dict(kv.split("\x02", 1) for kv in m[1].split("\x01") if "\x02" in kv)
        if fields.get("t") != "toggle":
            continue
        b = BIT_RE.match(fields.get("o", ""))
        if not b:
            continue
        net, bit, count = b[1], int(b[2] or 0), int(m[2])
        sl = SLICE_RE.match(net)
        if sl:  # a slice of a wide register: bit 32K + bit of it
            net, bit = sl[1], int(sl[2]) * SLICE + bit
        h = fields.get("h", "")
        rec = inst[h]
        rec.module = fields.get("page", "").removeprefix("v_toggle/")
        if net == PROBE_RD:
            rec.rd_clocks = (rec.rd_clocks or 0) + count
            continue
        if net == PROBE_WR:
            rec.wr_clocks = (rec.wr_clocks or 0) + count
            continue
        rec.toggles += count
        rec.nets[net] = rec.nets.get(net, 0) + count
        bits[h].add((net, bit))
    for h, s in bits.items():
        inst[h].bits = len(s)
    return dict(inst)


@dataclass
class Module:
    """A module's counters summed over its instances: toggles, register bits of one instance, the
    RAM ports' enabled clocks (an orb_sdp_ram's), and the instance paths they came from."""

    toggles: int = 0
    bits: int = 0
    rd_clocks: int | None = None
    wr_clocks: int | None = None
    paths: list[str] = field(default_factory=list)


def by_module(instances: dict[str, Instance]) -> dict[str, Module]:
    """parse_coverage's entries summed per module (Verilator's per-module counters, or one entry per
    instance: either way the module's totals)."""
    out: dict[str, Module] = defaultdict(Module)
    for path, inst in instances.items():
        m = out[inst.module]
        m.toggles += inst.toggles
        m.bits = max(m.bits, inst.bits)
        if inst.rd_clocks is not None:
            m.rd_clocks = (m.rd_clocks or 0) + inst.rd_clocks
            m.wr_clocks = (m.wr_clocks or 0) + (inst.wr_clocks or 0)
        m.paths.append(path)
    return dict(out)
