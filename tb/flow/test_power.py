# SPDX-License-Identifier: MIT
"""The power estimate's parts (sw/orb_flow/power.py, sw/orb_sim/fast/activity.py; docs/power.md)
without the accelerator's minutes-long activity build: the netlist instrumentation and the coverage
parser on a small netlist in GHDL's style compiled by Verilator with toggle coverage (the RAM
probes must count the enabled clocks exactly, the memory's words must stay out), the estimate's
arithmetic on known activity and cells, the coefficients file and the command's refusals."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from orb_flow import power
from orb_sim.fast.activity import PROBE_RD, Instance, instrument, parse_coverage

ROOT = Path(__file__).resolve().parents[2]

# A RAM module as GHDL writes orb_sdp_ram (the name, the ports, the memory declaration) under a top
NETLIST = """\
module orb_sdp_ram_8_16_1_0123456789abcdef0123456789abcdef01234567
  (input  clk,
   input  wr_en,
   input  [3:0] wr_addr,
   input  [7:0] wr_data,
   input  rd_en,
   input  [3:0] rd_addr,
   input  out_en,
   output [7:0] rd_data);
  reg [7:0] n12_q;
  reg [7:0] gen_ram_ram_mem[15:0] ; // memory
  always @(posedge clk) begin
    if (rd_en) n12_q <= gen_ram_ram_mem[rd_addr];
    if (wr_en) gen_ram_ram_mem[wr_addr] <= wr_data;
  end
  assign rd_data = n12_q;
endmodule

module orb_power_top
  (input  clk,
   input  [7:0] din,
   output [7:0] dout);
  reg [3:0] n7_q;
  initial n7_q = 4'b0;
  wire [3:0] n8_o;
  assign n8_o = n7_q + 1;
  always @(posedge clk) n7_q <= n8_o;
  reg [69:0] n9_q;
  initial n9_q = 70'b0;
  always @(posedge clk) if (n7_q[0]) n9_q <= {n9_q[61:0], din};
  orb_sdp_ram_8_16_1_0123456789abcdef0123456789abcdef01234567 ram (
    .clk(clk), .wr_en(n7_q[0]), .wr_addr(n7_q), .wr_data(din),
    .rd_en(n7_q[1] & n7_q[0]), .rd_addr(n7_q), .out_en(1'b1), .rd_data(dout));
endmodule
"""

MAIN = """\
#include "Vorb_power_top.h"
#include "verilated.h"
#include "verilated_cov.h"
#include <cstdio>
int main() {
  VerilatedContext ctx;
  Vorb_power_top top(&ctx, "top");
  unsigned __int128 shift = 0, mask = (((unsigned __int128)1) << 70) - 1;
  long expected = 0;  // n9_q's toggles in the window, counted here
  for (int i = 0; i < 200; i++) {
    top.din = (i * 37) & 255;
    if (i % 2 == 1) {  // n7_q is odd before the clock edge of odd i: n9_q shifts
      unsigned __int128 next = ((shift << 8) | top.din) & mask;
      if (i >= 40) expected += __builtin_popcountll((unsigned long long)(next ^ shift)) +
                               __builtin_popcountll((unsigned long long)((next ^ shift) >> 64));
      shift = next;
    }
    top.clk = 0; top.eval();
    top.clk = 1; top.eval();
    if (i == 39) ctx.coveragep()->zero();  // the window: the last 160 clocks
  }
  ctx.coveragep()->write("coverage.dat");
  FILE* f = fopen("expected.txt", "w");
  fprintf(f, "%ld\\n", expected);
  fclose(f);
  return 0;
}
"""


def test_instrument_leaves_the_design_and_adds_the_probes() -> None:
    text, registers, probes = instrument(NETLIST)
    assert (registers, probes) == (3, 1)
    # a register wider than 32 bits is counted through slices (Verilator's wide toggle counts are wrong)
    assert "wire [31:0] n9_q_pwc0;" in text and "wire [5:0] n9_q_pwc2;" in text
    assert "assign n9_q_pwc2 = n9_q[69:64];" in text
    assert text.startswith("/*verilator coverage_off*/\n")
    assert "/*verilator coverage_on*/\n  reg [7:0] n12_q;\n/*verilator coverage_off*/" in text
    assert text.replace("/*verilator coverage_on*/\n", "").replace("/*verilator coverage_off*/\n", "").replace(
        "/*verilator coverage_off*/", "").count("gen_ram_ram_mem") == NETLIST.count("gen_ram_ram_mem")  # fmt: skip
    assert text.count(f"reg {PROBE_RD}") == 1 and text.index(PROBE_RD) < text.index("endmodule")
    assert text.replace("\n", "").count("endmodule") == 2
    with pytest.raises(ValueError, match="no rd_en"):
        instrument(NETLIST.replace("input  rd_en", "input  read_en"))


def test_probes_count_the_enabled_clocks(tmp_path: Path) -> None:
    from orb_sim.fast.build import verilator
    from orb_sim.runner import ToolMissing

    try:
        exe, env = verilator()
    except ToolMissing as exc:
        pytest.fail(f"{exc} (make setup installs it)")
    (tmp_path / "top.v").write_text(instrument(NETLIST)[0])
    (tmp_path / "main.cpp").write_text(MAIN)
    cmd = [str(exe), "--cc", "top.v", "--top-module", "orb_power_top", "--exe", "main.cpp", "--build", "-j", "2",
           "--coverage-toggle", "-Wno-fatal", "-Wno-lint", "-CFLAGS", "-std=c++20", "-MAKEFLAGS",
           "CFG_CXXFLAGS_PCH_I=-include", "-o", "sim"]  # fmt: skip
    r = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600, check=False)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    subprocess.run(["./obj_dir/sim"], cwd=tmp_path, check=True, timeout=60)
    inst = parse_coverage(tmp_path / "coverage.dat")
    ram = next(i for h, i in inst.items() if i.module.startswith("orb_sdp_ram"))
    top = next(i for h, i in inst.items() if i.module == "orb_power_top")
    # 160 clocks from count = 8 (clock 40): rd_en (count & 3 == 3) 1 in 4, wr_en (count odd) 1 in 2
    assert (ram.rd_clocks, ram.wr_clocks) == (40, 80), (ram.rd_clocks, ram.wr_clocks)
    # only the registers are counted: not the memory's words, the wires, the ports or the clock
    assert set(ram.nets) == {"n12_q"} and set(top.nets) == {"n7_q", "n9_q"}, (ram.nets, top.nets)
    # n7_q[0] toggles every clock, n7_q[3] every 8th: 160 + 80 + 40 + 20 over the window
    assert top.nets["n7_q"] == 300 and top.bits == 4 + 70 and ram.bits == 8, (top.nets, top.bits, ram.bits)
    # the wide register's toggles exactly, through its slices
    assert top.nets["n9_q"] == int((tmp_path / "expected.txt").read_text()), top.nets


def _activity(toggles: int, bits: int, rd: int | None, wr: int | None, clocks: int = 1000) -> power.Activity:
    """orb_fast_score with `bits` register bits toggling `toggles` times, and a RAM under it."""
    insts = {
        "top.a": Instance(module="orb_fast_score", toggles=toggles, bits=bits),
        "top.a.ram": Instance(module="orb_sdp_ram_8_16_1_abc", toggles=0, bits=0, rd_clocks=rd, wr_clocks=wr),
    }
    return power.Activity(insts, clocks, 1, [10], 0.0, 0.0)


def _cells(**over: int) -> dict[str, int]:
    base = dict(lut_logic=0, srl=0, lutram=0, ff=0, carry4=0, dsp=0, ramb36=0, ramb18=0, lut=0, bram36=0)
    return {**base, **over}


def test_estimate_scales_with_activity_and_enables() -> None:
    coef = power.load_coefficients()
    c = {k: v["typ"] for k, v in coef["coefficients"].items()}
    cells = {
        "orb_fast_score": _cells(lut_logic=1000, ff=500, dsp=2, lut=1000),
        "orb_sdp_ram_8_16_1_abc": _cells(ramb36=2, bram36=2),
    }
    tree = c["clock_tree"] * 100 / 1000  # mW at 100 MHz
    # activity 12.5 % (1,250 toggles over 10 bits x 1,000 clocks) and enables 0.5/0.5: the vectorless figure
    at_default = power.estimate(_activity(1250, 10, 500, 500), cells, {}, 100, coef)
    vec = power.estimate(_activity(1250, 10, 500, 500), cells, {}, 100, coef, vectorless=True)
    assert at_default["dynamic_mw"] == vec["dynamic_mw"]
    want = (1000 * c["lut"] + 500 * c["ff"] + 1500 * c["signal"] + 2 * c["dsp"] + 500 * c["clock_ff"]
            + 2 * c["bram36"]) * 100 / 1000 + tree  # fmt: skip
    assert at_default["dynamic_mw"] == pytest.approx(want, abs=0.06)
    # a quarter of the activity: the data terms a quarter, the clock the same; the RAM idle: none
    low = power.estimate(_activity(312, 10, 0, 0), cells, {}, 100, coef)
    data = (1000 * c["lut"] + 500 * c["ff"] + 1500 * c["signal"] + 2 * c["dsp"]) * 100 / 1000
    assert low["dynamic_mw"] == pytest.approx(data * 312 / 1250 + 500 * c["clock_ff"] * 100 / 1000 + tree, abs=0.06)
    assert low["by_class_mw"]["bram"] == 0
    assert low["by_entity_mw"]["orb_sdp_ram"]["bram_read_enable"] == 0
    # the band: low <= typ <= high
    lo, hi = (
        power.estimate(_activity(1250, 10, 500, 500), cells, {}, 100, coef, b)["dynamic_mw"] for b in ("low", "high")
    )
    assert lo < at_default["dynamic_mw"] < hi
    # two instances sharing the counters (Verilator's n*): twice the cells, the same activity per bit
    two = power.estimate(_activity(2500, 10, 1000, 1000), cells, {"orb_fast_score": 2, "orb_sdp_ram_8_16_1_abc": 2},
                         100, coef)  # fmt: skip
    assert two["dynamic_mw"] == pytest.approx(2 * (at_default["dynamic_mw"] - tree) + tree, abs=0.2)
    assert two["by_entity_mw"]["orb_fast_score"]["activity"] == 0.125


def test_module_instances_from_the_design_hierarchy() -> None:
    text = ("=== orb_a_1 ===\n\n   Number of cells:   2\n     LUT2   2\n\n=== design hierarchy ===\n\n"
            "   orb_top                1\n     orb_a_1              3\n     orb_b                1\n\n"
            "   Number of wires:    10\n")  # fmt: skip
    assert power.module_instances(text) == {"orb_top": 1, "orb_a_1": 3, "orb_b": 1}
    assert power.module_cells(text)["orb_a_1"]["lut_logic"] == 2
    with pytest.raises(power.PowerError, match="design hierarchy"):
        power.module_instances("=== orb_a_1 ===\n")


def test_estimate_names_the_modules_it_cannot_match() -> None:
    coef = power.load_coefficients()
    cells = {"orb_fast_score": _cells(lut_logic=10, lut=10), "orb_accel_zynq": _cells(lut_logic=1, ff=1, lut=1)}
    got = power.estimate(_activity(100, 10, 1, 1), cells, {}, 100, coef)
    assert got["unmatched_modules"] == ["orb_sdp_ram_8_16_1_abc"]
    assert got["unsimulated_modules"] == ["orb_accel_zynq"]
    assert "orb_accel_zynq (not simulated)" in got["by_entity_mw"]


def test_entity_names() -> None:
    assert power.entity_of("orb_line_buffer_640_2_19_1") == "orb_line_buffer"
    assert power.entity_of("orb_sdp_ram_38_327_1_bf8b4530d8d246dd74ac53a13471bba17941dff7") == "orb_sdp_ram"
    assert power.entity_of("orb_rgb_luma_e5a93a771f42e1af112bd3d7a3fd141fef3328f8") == "orb_rgb_luma"
    assert power.entity_of("orb_accel_top") == "orb_accel_top"
    assert power.entity_of("orb_feat_select_181_640_480_5_4_3") == "orb_feat_select"


def test_coefficients_have_sources_and_bands() -> None:
    data = json.loads(power.COEFFICIENTS.read_text())
    assert data["defaults"]["toggle"] == 0.125 and data["defaults"]["bram_enable"] == 0.5
    for name, c in data["coefficients"].items():
        assert c["low"] <= c["typ"] <= c["high"], name
        assert c["sources"], f"{name}: no source"
        for s in c["sources"]:
            assert s["repo"].count("/") == 1 and s["path"] and len(s["commit"]) >= 8, (name, s)
    assert 0.1 < data["static"]["device_w"] < 0.2


def test_power_refuses_bad_arguments() -> None:
    env_path = f"{ROOT / 'sw'}:{ROOT}"
    for args, msg in (
        (["--configs", "board-4k"], "unknown configuration"),
        (["--frames", "2", "--window", "2"], "--window"),
    ):
        r = subprocess.run([sys.executable, "-m", "orb_flow.power", *args], capture_output=True, text=True, cwd=ROOT,
                           env={"PYTHONPATH": env_path, "PATH": "/usr/bin:/bin"}, timeout=120, check=False)  # fmt: skip
        assert r.returncode == 2 and msg in r.stderr, (args, r.stderr)


def test_the_simulated_top_is_the_synthesised_one() -> None:
    """The activity build's top is GHDL's plain `orb_accel_top`; inside the board top's synthesis the
    same entity carries its generics in its name: the estimate counts it, nothing is unmatched."""
    coef = power.load_coefficients()
    act = power.Activity({"top": Instance(module="orb_accel_top", toggles=125, bits=1)}, 1000, 1, [1], 0.0, 0.0)
    cells = {"orb_accel_top_640_480_4_abc": _cells(lut_logic=100, ff=10, lut=100), "orb_accel_zynq": _cells()}
    got = power.estimate(act, cells, {}, 100, coef)
    assert got["unmatched_modules"] == [] and got["by_entity_mw"]["orb_accel_top"]["activity"] == 0.125
