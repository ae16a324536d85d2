# SPDX-License-Identifier: MIT
"""Checks of sw/orb_flow/board/vivado_summary.py on small report texts in the layouts Vivado writes
(report_utilization, report_timing_summary, report_power; the public examples are named in the
script's docstring): the figures, the timing verdict and exit codes, a missing or unparsable report,
and the yosys estimate beside Vivado's figures."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from orb_flow.board import vivado_summary as vs

ROOT = Path(__file__).resolve().parents[2]
COMMAND = [sys.executable, "-m", "orb_flow.board.vivado_summary"]

# report_utilization, Vivado 2022+ layout (Fixed and Prohibited columns), placed design
UTILIZATION = """\
Copyright 1986-2022 Xilinx, Inc. All Rights Reserved.
| Command      : report_utilization -file utilization.rpt
| Device       : xc7z020clg400-1
| Design State : Fully Placed

1. Slice Logic
--------------

+----------------------------+-------+-------+------------+-----------+-------+
|          Site Type         |  Used | Fixed | Prohibited | Available | Util% |
+----------------------------+-------+-------+------------+-----------+-------+
| Slice LUTs                 | 21345 |     0 |          0 |     53200 | 40.12 |
|   LUT as Logic             | 20101 |     0 |          0 |     53200 | 37.78 |
|   LUT as Memory            |  1244 |     0 |          0 |     17400 |  7.15 |
|     LUT as Distributed RAM |   212 |     0 |            |           |       |
|     LUT as Shift Register  |  1032 |     0 |            |           |       |
| Slice Registers            | 24680 |     0 |          0 |    106400 | 23.20 |
|   Register as Flip Flop    | 24676 |     0 |          0 |    106400 | 23.19 |
|   Register as Latch        |     4 |     0 |          0 |    106400 | <0.01 |
| F7 Muxes                   |   310 |     0 |          0 |     26600 |  1.17 |
| F8 Muxes                   |    21 |     0 |          0 |     13300 |  0.16 |
+----------------------------+-------+-------+------------+-----------+-------+


2. Slice Logic Distribution
---------------------------

+--------------------------------------------+-------+-------+------------+-----------+-------+
|                  Site Type                 |  Used | Fixed | Prohibited | Available | Util% |
+--------------------------------------------+-------+-------+------------+-----------+-------+
| Slice                                      |  8123 |     0 |          0 |     13300 | 61.08 |
| Slice Registers                            | 99999 |     0 |          0 |    106400 | 93.98 |
+--------------------------------------------+-------+-------+------------+-----------+-------+


3. Memory
---------

+-------------------+------+-------+------------+-----------+-------+
|     Site Type     | Used | Fixed | Prohibited | Available | Util% |
+-------------------+------+-------+------------+-----------+-------+
| Block RAM Tile    | 27.5 |     0 |          0 |       140 | 19.64 |
|   RAMB36/FIFO*    |   24 |     0 |          0 |       140 | 17.14 |
|     RAMB36E1 only |   24 |       |            |           |       |
|   RAMB18          |    7 |     0 |          0 |       280 |  2.50 |
|     RAMB18E1 only |    7 |       |            |           |       |
+-------------------+------+-------+------------+-----------+-------+


4. DSP
------

+----------------+------+-------+------------+-----------+-------+
|    Site Type   | Used | Fixed | Prohibited | Available | Util% |
+----------------+------+-------+------------+-----------+-------+
| DSPs           |   16 |     0 |          0 |       220 |  7.27 |
|   DSP48E1 only |   16 |       |            |           |       |
+----------------+------+-------+------------+-----------+-------+
"""

# report_utilization, Vivado 2013 layout (a Loced column, no Prohibited), and the '*' a synthesised
# design's report puts after "Slice LUTs"; an Artix-7 200T, so the Available column differs
UTILIZATION_OLD_OTHER_PART = """\
+----------------------------+-------+-------+-----------+-------+
|          Site Type         |  Used | Loced | Available | Util% |
+----------------------------+-------+-------+-----------+-------+
| Slice LUTs*                |  1000 |     0 |    134600 |  0.74 |
| Slice Registers            |  2000 |    17 |    269200 |  0.74 |
|   Register as Flip Flop    |  2000 |    17 |    269200 |  0.74 |
+----------------------------+-------+-------+-----------+-------+

+-------------------+------+-------+-----------+-------+
|     Site Type     | Used | Loced | Available | Util% |
+-------------------+------+-------+-----------+-------+
| Block RAM Tile    |    3 |     0 |       365 |  0.82 |
+-------------------+------+-------+-----------+-------+

+----------------+------+-------+-----------+-------+
|    Site Type   | Used | Loced | Available | Util% |
+----------------+------+-------+-----------+-------+
| DSPs           |    2 |     0 |       740 |  0.27 |
+----------------+------+-------+-----------+-------+
"""

TIMING_HEAD = """\
Timing Summary Report

------------------------------------------------------------------------------------------------
| Design Timing Summary
| ---------------------
------------------------------------------------------------------------------------------------

"""
TIMING_COLS = (
    "    WNS(ns)      TNS(ns)  TNS Failing Endpoints  TNS Total Endpoints      WHS(ns)      THS(ns)  "
    "THS Failing Endpoints  THS Total Endpoints     WPWS(ns)     TPWS(ns)  TPWS Failing Endpoints  "
    "TPWS Total Endpoints  \n"
    "    -------      -------  ---------------------  -------------------      -------      -------  "
    "---------------------  -------------------     --------     --------  ----------------------  "
    "--------------------  \n"
)


def timing(row: str, verdict: str) -> str:
    tail = "\n\n------------------------------------------------------------------------------------------------\n"
    return TIMING_HEAD + TIMING_COLS + row + "\n\n\n" + verdict + tail + "| Clock Summary\n"


TIMING_MET = timing(
    "      0.412        0.000                      0                52311        0.031        0.000"
    "                      0                52311        2.750        0.000                       0"
    "                 21034  ",
    "All user specified timing constraints are met.",
)
TIMING_NOT_MET = timing(
    "     -0.734      -41.208                    123                52311        0.027        0.000"
    "                      0                52311        2.750        0.000                       0"
    "                 21034  ",
    "Timing constraints are not met.",
)
TIMING_HOLD_FAILS = timing(
    "      0.215        0.000                      0                52311       -0.050       -0.350"
    "                      9                52311        2.750        0.000                       0"
    "                 21034  ",
    "Timing constraints are not met.",
)
# before WPWS/TPWS existed the table had six columns; no verdict line here
TIMING_SIX_COLUMNS = (
    TIMING_HEAD
    + "WNS(ns)      TNS(ns)  TNS Failing Endpoints  TNS Total Endpoints      WHS(ns)      THS(ns)\n"
    + "-------      -------  ---------------------  -------------------      -------      -------\n"
    + "  0.172        0.000                      0               172305        0.017        0.000\n"
)
TIMING_UNCONSTRAINED = timing(
    "        inf        0.000                      0                 2271          inf        0.000"
    "                      0                 2271           NA           NA                      NA"
    "                    NA  ",
    "There are no user specified timing constraints.",
)

# report_power, Vivado 2022+ layout (budget rows), a Zynq with its PS7 row
POWER = """\
Power Report

1. Summary
----------

+--------------------------+--------------+
| Total On-Chip Power (W)  | 1.734        |
| Design Power Budget (W)  | Unspecified* |
| Power Budget Margin (W)  | NA           |
| Dynamic (W)              | 1.589        |
| Device Static (W)        | 0.145        |
| Effective TJA (C/W)      | 11.5         |
| Max Ambient (C)          | 65.0         |
| Junction Temperature (C) | 45.0         |
| Confidence Level         | Low          |
| Setting File             | ---          |
| Simulation Activity File | ---          |
| Design Nets Matched      | NA           |
+--------------------------+--------------+


1.1 On-Chip Components
----------------------

+--------------------------+-----------+----------+-----------+-----------------+
| On-Chip                  | Power (W) | Used     | Available | Utilization (%) |
+--------------------------+-----------+----------+-----------+-----------------+
| Clocks                   |     0.021 |        3 |       --- |             --- |
| Slice Logic              |     0.012 |    51233 |       --- |             --- |
| Block RAM                |     0.018 |     27.5 |       140 |           19.64 |
| DSPs                     |     0.004 |       16 |       220 |            7.27 |
| PS7                      |     1.507 |        1 |       --- |             --- |
| Static Power             |     0.145 |          |           |                 |
| Total                    |     1.734 |          |           |                 |
+--------------------------+-----------+----------+-----------+-----------------+
"""

ESTIMATE = [
    {"top": "orb_core", "width": 640, "height": 480, "scales": 2, "lut": 19000, "ff": 20000, "bram36": 25, "dsp": 16},
    {
        "top": "orb_accel_zynq",
        "width": 640,
        "height": 480,
        "scales": 2,
        "lut": 20877,
        "ff": 24102,
        "bram36": 27.5,
        "dsp": 16,
    },
    {"top": "orb_core", "width": 1920, "height": 1080, "scales": 2, "lut": 1, "ff": 1, "bram36": 1, "dsp": 1},
]


def reports(tmp_path: Path, util: str = UTILIZATION, tim: str = TIMING_MET, power: str | None = POWER) -> Path:
    d = tmp_path / "reports"
    d.mkdir()
    (d / "utilization.rpt").write_text(util)
    (d / "timing_summary.rpt").write_text(tim)
    if power is not None:
        (d / "power.rpt").write_text(power)
    return d


# --- the parsers ---------------------------------------------------------------------------------


def test_utilization_figures_and_percentages() -> None:
    u = vs.parse_utilization(UTILIZATION)
    # the first "Slice Registers" row (section 1), not the distribution table's
    assert u["used"] == {"lut": 21345, "ff": 24680, "ff_flip_flop": 24676, "bram36": 27.5, "dsp": 16}
    assert u["util_pct"] == {"lut": 40.12, "ff": 23.2, "bram36": 19.64, "dsp": 7.27}
    assert u["warnings"] == []


def test_utilization_columns_by_header_and_another_part_warns() -> None:
    u = vs.parse_utilization(UTILIZATION_OLD_OTHER_PART)
    assert u["used"] == {"lut": 1000, "ff": 2000, "ff_flip_flop": 2000, "bram36": 3, "dsp": 2}
    assert u["util_pct"] == {"lut": 1.88, "ff": 1.88, "bram36": 2.14, "dsp": 0.91}  # of the XC7Z020
    assert len(u["warnings"]) == 4
    assert "Slice LUTs available 134600, not the XC7Z020's 53200" in u["warnings"][0]


def test_utilization_missing_row_names_it() -> None:
    text = UTILIZATION.replace("| DSPs           |", "| DSP48s         |")
    with pytest.raises(vs.ReportError, match=r"^utilization\.rpt: no 'DSPs' row"):
        vs.parse_utilization(text)


def test_timing_met() -> None:
    t = vs.parse_timing(TIMING_MET)
    assert t == {
        "wns_ns": 0.412,
        "tns_ns": 0.0,
        "tns_failing_endpoints": 0,
        "whs_ns": 0.031,
        "ths_ns": 0.0,
        "ths_failing_endpoints": 0,
        "wpws_ns": 2.75,
        "verdict": "All user specified timing constraints are met.",
        "met": True,
    }


def test_timing_setup_violation() -> None:
    t = vs.parse_timing(TIMING_NOT_MET)
    assert (t["wns_ns"], t["tns_ns"], t["tns_failing_endpoints"], t["met"]) == (-0.734, -41.208, 123, False)


def test_timing_hold_violation_is_not_met() -> None:
    t = vs.parse_timing(TIMING_HOLD_FAILS)
    assert (t["wns_ns"], t["whs_ns"], t["ths_ns"], t["ths_failing_endpoints"]) == (0.215, -0.05, -0.35, 9)
    assert t["met"] is False


def test_timing_older_six_column_table() -> None:
    t = vs.parse_timing(TIMING_SIX_COLUMNS)
    assert (t["wns_ns"], t["whs_ns"], t["wpws_ns"], t["verdict"], t["met"]) == (0.172, 0.017, None, None, True)


@pytest.mark.parametrize(("wns", "whs"), [("-0.010", "0.017"), ("0.172", "-0.004")])
def test_timing_negative_slack_without_a_verdict_line_is_not_met(wns: str, whs: str) -> None:
    text = TIMING_SIX_COLUMNS.replace("  0.172", wns.rjust(7)).replace("       0.017", whs.rjust(12))
    t = vs.parse_timing(text)
    assert (t["wns_ns"], t["whs_ns"], t["verdict"], t["met"]) == (float(wns), float(whs), None, False)


def test_timing_without_constraints_is_not_met() -> None:
    t = vs.parse_timing(TIMING_UNCONSTRAINED)
    assert (t["wns_ns"], t["whs_ns"], t["wpws_ns"], t["met"]) == (None, None, None, False)
    assert t["verdict"] == "There are no user specified timing constraints."


def test_timing_without_the_section() -> None:
    with pytest.raises(vs.ReportError, match=r"^timing_summary\.rpt: no '\| Design Timing Summary' section$"):
        vs.parse_timing("Timing Summary Report\n\nnothing here\n")


def test_power_figures() -> None:
    p = vs.parse_power(POWER)
    assert p == {
        "total_w": 1.734,
        "dynamic_w": 1.589,
        "static_w": 0.145,
        "ps7_w": 1.507,
        "confidence": "Low",
        "thesis_measured_w": 0.159,
    }


def test_power_missing_row() -> None:
    with pytest.raises(vs.ReportError, match=r"^power\.rpt: no numeric 'Device Static \(W\)' row$"):
        vs.parse_power(POWER.replace("Device Static (W)", "Device Leakage   "))


# --- the command line ----------------------------------------------------------------------------


def summary_of(d: Path) -> dict[str, Any]:
    return json.loads((d / "summary.json").read_text())


def test_met_exits_0_and_writes_the_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = reports(tmp_path)
    assert vs.main([str(d), "--config", "640x480x2"]) == 0
    s = summary_of(d)
    assert s["config"] == "640x480x2"
    assert s["vivado"] == {"lut": 21345, "ff": 24680, "ff_flip_flop": 24676, "bram36": 27.5, "dsp": 16}
    assert s["util_pct"]["lut"] == 40.12
    assert (s["timing"]["wns_ns"], s["timing"]["whs_ns"], s["timing_met"]) == (0.412, 0.031, True)
    assert (s["power"]["total_w"], s["power"]["dynamic_w"], s["power"]["static_w"]) == (1.734, 1.589, 0.145)
    assert "yosys_estimate" not in s
    out = capsys.readouterr().out
    assert "LUT          21,345       40.12%" in out
    assert "WNS 0.412 ns, TNS 0.000 ns, WHS 0.031 ns, THS 0.000 ns: met" in out
    assert "total on-chip 1.734 W (dynamic 1.589 W, static 0.145 W, PS7 1.507 W); thesis measured 159 mW" in out


def test_not_met_exits_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = reports(tmp_path, tim=TIMING_NOT_MET)
    assert vs.main([str(d), "--config", "640x480x2"]) == 1
    assert summary_of(d)["timing_met"] is False
    assert "NOT MET (Timing constraints are not met.)" in capsys.readouterr().out


def test_missing_report_exits_2_naming_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = reports(tmp_path, power=None)
    assert vs.main([str(d), "--config", "640x480x2"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {d / 'power.rpt'}: missing report") and err.count("\n") == 1
    assert not (d / "summary.json").exists()


def test_unparsable_report_exits_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = reports(tmp_path, tim="Timing Summary Report\n")
    assert vs.main([str(d), "--config", "640x480x2"]) == 2
    assert capsys.readouterr().err == f"error: {d / 'timing_summary.rpt'}: no '| Design Timing Summary' section\n"


def test_estimate_beside_vivado(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    d = reports(tmp_path)
    est = tmp_path / "report.json"
    est.write_text(json.dumps(ESTIMATE))
    out = tmp_path / "out" / "s.json"
    out.parent.mkdir()
    assert vs.main([str(d), "--config", "640x480x2", "--estimate", str(est), "--out", str(out)]) == 0
    s = json.loads(out.read_text())
    # two records are 640x480x2: the board wrapper orb_accel_zynq is the one Vivado builds
    assert s["yosys_estimate"] == {
        "lut": 20877,
        "ff": 24102,
        "bram36": 27.5,
        "dsp": 16,
        "source": str(est),
        "job": "orb_accel_zynq 640x480x2",
    }
    assert s["vivado"]["lut"] == 21345
    assert "LUT          21,345       40.12%      20,877" in capsys.readouterr().out


def test_estimate_top_named_in_the_config() -> None:
    e = vs.pick_estimate(ESTIMATE, "orb_core 640x480x2", "report.json")
    assert (e["lut"], e["job"]) == (19000, "orb_core 640x480x2")


def test_estimate_single_record_and_no_match() -> None:
    assert vs.pick_estimate(ESTIMATE[1], "anything", "e.json")["ff"] == 24102
    with pytest.raises(vs.ReportError, match=r"^report\.json: 0 estimate records match config '1280x720x2'"):
        vs.pick_estimate(ESTIMATE, "1280x720x2", "report.json")


def test_cli_exit_codes_through_the_interpreter(tmp_path: Path) -> None:
    d = reports(tmp_path, tim=TIMING_HOLD_FAILS)
    r = subprocess.run([*COMMAND, str(d), "--config", "640x480x2"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 1, r.stderr
    (d / "utilization.rpt").unlink()
    r = subprocess.run([*COMMAND, str(d), "--config", "640x480x2"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert r.stderr.startswith(f"error: {d / 'utilization.rpt'}: missing report")


def test_make_powers_estimate_stands_beside_report_power() -> None:
    """The newest recorded make power estimate of a board configuration, by its key or its name."""
    from orb_flow.board.vivado_summary import power_estimate

    by_key, by_name = power_estimate("640x480"), power_estimate("board-vga")
    assert by_key is not None and by_key == by_name
    assert by_key["low"] <= by_key["typ"] <= by_key["high"] and not by_key["run"].startswith("what-if")
    assert power_estimate("no-such-config") is None
