# SPDX-License-Identifier: MIT
"""The worst-paths report (sw/orb_flow/timing.py) against yosys's own `sta` on a small design.

A hand-written Verilog module with four kinds of path (a 16-bit adder: a carry chain; a 64:1
multiplexer: LUT levels and MUXF7/F8; a 16x16 product: a DSP48E1 with its output register; a
registered copy: no logic) goes through synth.py's timing-pass script (yosys synth_xilinx -abc9
-flatten, write_json, sta). The report's longest path must equal the arrival yosys prints, and each
path must be found between the registers it runs between, with its logic depth. About 10 s
(yosys; `.ci/run` installs it).
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest

from orb_flow import synth, timing

ROOT = Path(__file__).resolve().parents[2]

TINY_V = """
module tiny(input clk, input [15:0] a, input [15:0] b, input [5:0] sel, input [63:0] wide,
            output reg [16:0] sum, output reg mux, output reg [31:0] prod, output reg [15:0] copy);
  reg [15:0] ra, rb, ma, mb;
  reg [5:0] rsel;
  reg [63:0] rwide;
  always @(posedge clk) begin
    ra <= a; rb <= b; ma <= a; mb <= b; rsel <= sel; rwide <= wide;
    sum <= ra + rb;
    mux <= rwide[rsel];
    prod <= ma * mb;
    copy <= ra;
  end
endmodule
"""


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, Any], int]:
    yosys = shutil.which("yosys")
    assert yosys, "yosys is missing: apt-get install yosys (.ci/run installs it)"
    d = tmp_path_factory.mktemp("timing")
    (d / "top.v").write_text(TINY_V)
    (d / "sta.ys").write_text(synth.STA_SCRIPT.format(top="tiny"))
    subprocess.run([yosys, "-q", "-l", "yosys.log", "sta.ys"], cwd=d, check=True, capture_output=True)
    m = re.search(r"Latest arrival time in 'tiny' is (\d+):", (d / "sta.txt").read_text())
    assert m, "yosys sta printed no arrival time"
    return timing.report(timing.load(d / "net.json", "tiny"), 3.5, 20), int(m[1])


def paths_to(rep: dict[str, Any], endpoint: str) -> list[dict[str, Any]]:
    return [p for p in rep["worst_paths"] if re.search(rf"(^|\$){endpoint}(\[\d+\])?( |$)", p["endpoint"])]


def test_endpoints_over_a_limit_are_counted(tiny: tuple[dict[str, Any], int]) -> None:
    rep, _ = tiny
    hist = sum(rep["histogram"].values())
    assert hist == rep["endpoints"] > 0
    assert sum(n for k, n in rep["histogram"].items() if float(k.split(",")[0][1:]) >= 1.0) > 0


def test_longest_path_is_yosys_sta(tiny: tuple[dict[str, Any], int]) -> None:
    rep, yosys_ps = tiny
    assert rep["logic_delay_ns"] == yosys_ps / 1000, f"timing.py {rep['logic_delay_ns']} ns, yosys sta {yosys_ps} ps"


def test_paths_are_found_with_their_depth(tiny: tuple[dict[str, Any], int]) -> None:
    rep, _ = tiny
    summary = [(p["endpoint"], p["start"], p["lut_levels"], p["carry4"], p["delay_ns"]) for p in rep["worst_paths"]]
    adder = paths_to(rep, "sum")
    assert adder and re.match(r"[rm][ab]\[\d+\]", adder[0]["start"]), summary  # yosys merges ra/ma, rb/mb
    assert adder[0]["carry4"] >= 4 and adder[0]["start_type"] == "FDRE", summary  # 16 bits: four CARRY4 at least
    mux = paths_to(rep, "mux")
    assert mux and re.match(r"r(wide|sel)\[\d+\]", mux[0]["start"]) and mux[0]["lut_levels"] + mux[0]["muxf"] >= 2, (
        summary
    )
    # the product: yosys packs ma/mb into the DSP48E1's input registers, prod leaves its register
    assert any(p["endpoint"].endswith(("(DSP48E1.A)", "(DSP48E1.B)")) for p in rep["worst_paths"]), summary
    assert any(p["start_type"] == "DSP48E1" for p in rep["worst_paths"]), summary
    # the worst path per block names the top's only block
    assert list(rep["worst_by_block"]) == ["(top)"]
    # every path of the design is under 3.5 ns, the adder's bits are over 1.0 ns
    assert rep["endpoints_over_limit"] == 0 and all(p["delay_ns"] <= 3.5 for p in rep["worst_paths"]), summary


def test_delay_model_is_read_from_the_cell_library() -> None:
    models = timing.read_models(timing.find_cells_sim())
    lut6 = {c[0]: c[5] for c in models["LUT6"].comb}
    assert set(lut6) == {f"I{i}" for i in range(6)} and lut6["I0"] > lut6["I5"] > 0
    assert models["FDRE"].arrival[("Q", None)][0] == "C" and models["FDRE"].required[("CE", None)] > 0
    assert any(c[0] == "CI" and c[3] == "CO" for c in models["CARRY4"].comb)
    # a block RAM output is as late as its slowest (unregistered) clock-to-output figure, as yosys takes it
    assert models["RAMB36E1"].arrival[("DOADO", None)][1] > 2000
    # a DSP48E1 without registers is combinational; with input and output registers it is not
    comb = timing.dsp_model({"AREG": 0, "BREG": 0, "MREG": 0, "PREG": 0, "CREG": 0, "DREG": 0, "ADREG": 0})
    regd = timing.dsp_model({"AREG": 1, "BREG": 1, "MREG": 0, "PREG": 1})
    assert any(c[0] == "A" and c[3] == "P" for c in comb.comb) and not comb.arrival
    assert not any(c[3] == "P" and c[0] in "AB" for c in regd.comb) and ("A", None) in regd.required
