# SPDX-License-Identifier: MIT
"""The nextpnr-xilinx flow (sw/orb_flow/pnr.py) without the tool: the one-line message and exit 2
when nextpnr-xilinx or its chip database is missing, the search for both, the port wrapper and its
constraints, and the log parser.

tb/flow/data/nextpnr_xilinx_timing.log is a log in nextpnr-xilinx's format, written from the format
strings of its common/timing.cc (openXC7/nextpnr-xilinx e22bcf6): a post-placement report, the
router's lines, then the post-route report the parser must pick. The wrapper goes through yosys
(synth.py's -abc9 script split, as pnr.py runs it) on a small module (~5 s; yosys is one of make test's tools).
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from orb_flow import pnr

DATA = Path(__file__).resolve().parent / "data"
LOG = DATA / "nextpnr_xilinx_timing.log"

SMALL_V = """
module orb_accel_zynq
  (input  aclk,
   input  aresetn,
   input  [7:0] a,
   input  b,
   output [8:0] s,
   output irq);
  reg [8:0] r;
  always @(posedge aclk) if (!aresetn) r <= 0; else r <= r + a + b;
  assign s = r;
  assign irq = r[8];
endmodule
"""


@pytest.fixture
def no_tool_dirs(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Path:
    """TOOL_DIRS and CHIPDB_DIRS pointed at an empty folder: only the environment given counts."""
    empty = tmp_path / "empty"
    empty.mkdir()
    monkeypatch.setattr(pnr, "TOOL_DIRS", (empty,))
    monkeypatch.setattr(pnr, "CHIPDB_DIRS", (empty,))
    return empty


def fake_tool(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    exe = folder / "nextpnr-xilinx"
    exe.write_text("#!/bin/sh\necho 'nextpnr-xilinx -- Next Generation Place and Route (Version fake)'\n")
    exe.chmod(0o755)
    return exe


def test_missing_tool_is_one_line_and_exit_2(
    no_tool_dirs: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("PATH", str(no_tool_dirs))
    monkeypatch.delenv(pnr.ENV_TOOL, raising=False)
    monkeypatch.delenv(pnr.ENV_CHIPDB, raising=False)
    assert pnr.main([]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.splitlines() == [pnr.MISSING_TOOL]
    assert "docs/pnr.md" in err and pnr.ENV_TOOL in err and pnr.ENV_CHIPDB in err


def test_missing_chipdb_is_one_line_and_exit_2(
    no_tool_dirs: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv(pnr.ENV_TOOL, str(fake_tool(tmp_path / "bin")))
    monkeypatch.delenv(pnr.ENV_CHIPDB, raising=False)
    assert pnr.main([]) == 2
    assert capsys.readouterr().err.splitlines() == [pnr.MISSING_CHIPDB]


def test_finds_tool_on_path_and_chipdb_beside_a_build_tree(no_tool_dirs: Path, tmp_path: Path) -> None:
    exe = fake_tool(tmp_path / "nextpnr-xilinx" / "build")
    db = tmp_path / "nextpnr-xilinx" / "xilinx" / "xc7z020.bin"
    db.parent.mkdir()
    db.write_bytes(b"\0")
    found = pnr.find_tools({"PATH": str(exe.parent)})
    assert found == pnr.Tools(str(exe), db)


def test_env_chipdb_may_be_a_file_or_a_folder(no_tool_dirs: Path, tmp_path: Path) -> None:
    exe = fake_tool(tmp_path / "bin")
    db = tmp_path / "db" / f"{pnr.PART}.bin"
    db.parent.mkdir()
    db.write_bytes(b"\0")
    for given in (db, db.parent):
        env = {pnr.ENV_TOOL: str(exe), pnr.ENV_CHIPDB: str(given), "PATH": ""}
        assert pnr.find_tools(env) == pnr.Tools(str(exe), db)
    assert pnr.find_tools({pnr.ENV_TOOL: str(exe), pnr.ENV_CHIPDB: str(tmp_path / "nothing")}) == pnr.MISSING_CHIPDB
    assert pnr.find_tools({pnr.ENV_TOOL: str(tmp_path / "no-such-tool")}) == pnr.MISSING_TOOL


def test_post_route_report_is_the_one_kept() -> None:
    parsed = pnr.parse_log(LOG.read_text())
    assert parsed["post_route"] is True
    assert parsed["errors"] == []
    assert list(parsed["clocks"]) == ["clk_IBUF_BUFG"]
    clk = parsed["clocks"]["clk_IBUF_BUFG"]
    assert (clk["fmax_mhz"], clk["target_mhz"], clk["pass"]) == (163.93, 150.0, True)
    assert clk["critical_path"] == {
        "clock": "clk_IBUF_BUFG",
        "edges": "posedge -> posedge",
        "from": "isr_DFF_Q_7.Q",
        "to": "osr_DFFE_Q_3.D",
        "delay_ns": 6.1,
        "logic_ns": 1.2,
        "routing_ns": 4.9,
        "nets": 3,
    }
    # the delay is 1000 / Fmax, to the report's 0.1 ns
    assert abs(1000 / clk["fmax_mhz"] - clk["critical_path"]["delay_ns"]) < 0.05


def test_failed_clock_and_unrouted_log() -> None:
    placed_only = LOG.read_text().split("Info: Routing global clocks")[0]
    parsed = pnr.parse_log(placed_only + "ERROR: Max frequency for clock 'clk': 120.00 MHz (FAIL at 150.00 MHz)\n")
    assert parsed["post_route"] is False
    assert parsed["clocks"]["clk"] == {"fmax_mhz": 120.0, "target_mhz": 150.0, "pass": False}
    assert pnr.main_clock(parsed) == ("clk", parsed["clocks"]["clk"])
    rec: dict = {"errors": []}
    pnr.fill_timing(rec, "Info: Routing..\nERROR: Failed to route arc 3 of net 'x'.\n")
    assert rec["errors"] == ["Failed to route arc 3 of net 'x'."]
    assert "fmax_mhz" not in rec


def test_wrapper_puts_every_port_but_the_clock_on_a_register() -> None:
    ports = pnr.parse_ports(SMALL_V, "orb_accel_zynq")
    assert [(p.direction, p.name, p.width) for p in ports] == [
        ("input", "aclk", 1),
        ("input", "aresetn", 1),
        ("input", "a", 8),
        ("input", "b", 1),
        ("output", "s", 9),
        ("output", "irq", 1),
    ]
    v = pnr.wrapper("orb_accel_zynq", ports)
    assert ".aclk(clk)" in v and ".a(isr[8:1])" in v and ".b(isr[9:9])" in v and ".irq(o[9:9])" in v
    assert "reg [9:0] isr" in v and "reg [9:0] osr" in v
    x = pnr.xdc()
    assert f"PACKAGE_PIN {pnr.CLOCK_PIN} [get_ports clk]" in x and "create_clock -period 6.667" in x
    assert all(f"IOSTANDARD LVCMOS33 [get_ports {p}]" in x for p in ("clk", "si", "ld", "so"))
    with pytest.raises(pnr.PnrError):
        pnr.parse_ports(SMALL_V, "orb_core")


def test_wrapper_synthesises_to_a_json_netlist(tmp_path: Path) -> None:
    if shutil.which("yosys") is None:  # make test checks its tools first; never skipped silently
        pytest.fail("yosys is not installed: apt-get install yosys")
    (tmp_path / "top.v").write_text(SMALL_V)
    (tmp_path / "wrap.v").write_text(pnr.wrapper("orb_accel_zynq", pnr.parse_ports(SMALL_V, "orb_accel_zynq")))
    (tmp_path / "pnr.ys").write_text(pnr.YOSYS_SCRIPT.format(top=pnr.WRAP_TOP))
    subprocess.run(["yosys", "-q", "-s", "pnr.ys"], cwd=tmp_path, check=True, timeout=300)
    net = json.loads((tmp_path / "top.json").read_text())
    top = net["modules"][pnr.WRAP_TOP]
    assert set(top["ports"]) == {"clk", "si", "ld", "so"}
    types = {c["type"] for c in top["cells"].values()}
    assert {"BUFG", "IBUF", "OBUF", "FDRE", "CARRY4"} <= types


def test_synth_only_needs_no_tool(
    no_tool_dirs: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("PATH", str(no_tool_dirs))
    monkeypatch.delenv(pnr.ENV_TOOL, raising=False)
    calls: list[tuple] = []

    def fake_run(config: str, tools: pnr.Tools | None, *rest: object) -> dict:
        calls.append((config, tools))
        return record()

    monkeypatch.setattr(pnr, "run", fake_run)
    assert pnr.main(["--synth-only", "--named", "board-720p"]) == 0
    assert calls == [("board-720p", None)]
    assert "pnr: record: " in capsys.readouterr().out


def record() -> dict:
    rec = {
        "config": "board-vga",
        "job": "orb_accel_zynq 640x480x4",
        "part": pnr.PART,
        "chipdb": "xc7z020.bin",
        "tools": {"nextpnr-xilinx": "fake"},
        "cells": {"lut": 42000, "ff": 50000, "bram36": 100.5, "dsp": 40, "carry4": 3000, "srl": 0, "lutram": 0},
        "utilisation_pct": {"lut": 78.9, "ff": 47.0, "bram36": 71.8, "dsp": 18.2},
        "wall_s": {"yosys": 600.0, "nextpnr": 3600.0},
        "errors": [],
    }
    pnr.fill_timing(rec, LOG.read_text())
    return rec


def test_summary_names_fmax_path_and_cells() -> None:
    md = pnr.summary_md(record())
    assert "timing (post-route): Fmax 163.93 MHz for clock clk_IBUF_BUFG, target 150.0 MHz, met" in md
    assert "isr_DFF_Q_7.Q -> osr_DFFE_Q_3.D, 6.1 ns (1.2 ns logic, 4.9 ns routing, 3 nets)" in md
    assert "42000 lut (78.9 %)" in md and "3000 CARRY4" in md


def test_a_report_before_the_routers_end_is_not_post_route() -> None:
    text = LOG.read_text()
    cut = text.index("Info: Critical path report", text.index("Routing complete."))
    assert pnr.parse_log(text[:cut])["post_route"] is False  # routed, but only the placement report
