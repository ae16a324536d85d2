# SPDX-License-Identifier: MIT
"""The formal property checks (orb_flow.formal, docs/formal.md): every check of CHECKS passes (proven
or bounded to its depth) and every planted bug fails in the property it names, the named property
alone kept. The quick checks (seconds each) run in `make test`, the others are marked slow. The tools
come from PyPI with the project's `formal` extra (`make setup`); a missing one fails the test with the
install command, never skips it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from orb_flow import formal

CHECKS = list(formal.CHECKS.values())


def test_tools_installed() -> None:
    try:
        formal.sby_exe()
        formal.ghdl_exe()
    except FileNotFoundError as e:
        pytest.fail(str(e))


def _mark(check: formal.Check) -> tuple[pytest.MarkDecorator, ...]:
    return () if check.quick else (pytest.mark.slow,)


@pytest.mark.parametrize("check", [pytest.param(c, id=c.key, marks=_mark(c)) for c in CHECKS])
def test_check(check: formal.Check, tmp_path: Path) -> None:
    """The check passes, and each of its asserted properties has a planted bug aimed at it."""
    try:
        rec = formal.run_check(check, mutations=False, out=tmp_path)
    except FileNotFoundError as e:
        pytest.fail(str(e))
    assert rec["status"] == "PASS", (
        f"{check.entity}: {rec['status']}, failed {rec['failed']} at step {rec['cex_step']} ({rec['traces']})"
    )
    names = [p["name"] for p in rec["properties"] if p["kind"] == "assert"]
    assert names, f"{check.entity}: no property asserted"
    aimed = {m.expect for m in check.mutations}
    for prefix, other in check.bugs_of.items():  # the same RTL's planted bugs, run by the other check
        aimed |= {m.expect for m in formal.CHECKS[other].mutations if m.expect.startswith(prefix)}
    uncovered = [n for n in names if not any(n == e or n.startswith(e + ".") for e in aimed)]
    assert not uncovered, f"{check.entity}: properties without a planted bug: {uncovered}"


@pytest.mark.parametrize(
    ("check", "bug"),
    [pytest.param(c, m, id=f"{c.key}-{m.name}", marks=_mark(c)) for c in CHECKS for m in c.mutations],
)
def test_planted_bug(check: formal.Check, bug: formal.Mutation, tmp_path: Path) -> None:
    """The planted bug fails in the property it names, the other properties removed."""
    try:
        rec = formal.run_one(check, tmp_path / bug.name, bug)
    except FileNotFoundError as e:
        pytest.fail(str(e))
    assert rec["status"] == "FAIL", f"{check.entity}, planted bug {bug.name} ({bug.what}): {rec['status']}"
    assert all(f == bug.expect or f.startswith(bug.expect + ".") for f in rec["failed"]) and rec["failed"], (
        f"{check.entity}, planted bug {bug.name}: failed {rec['failed']}, expected {bug.expect}"
    )


def test_wrapper_binds_every_stream_port() -> None:
    """The wrapper binds a checker to every AXI4-Stream port and the AXI4-Lite checker to s_axil."""
    verilog = """module orb_x
  (input  clk,
   input  rst,
   input  [3:0] s_axis_a_tdata,
   input  s_axis_a_tvalid,
   output s_axis_a_tready,
   output [7:0] m_axis_b_tdata,
   output m_axis_b_tvalid,
   input  m_axis_b_tready,
   output m_axis_b_tlast);
"""
    ports = formal.ports(verilog, "orb_x")
    assert [(p.dir, p.width, p.name) for p in ports][2:4] == [
        ("input", 4, "s_axis_a_tdata"),
        ("input", 1, "s_axis_a_tvalid"),
    ]
    text = formal.wrapper(formal.Check("orb_x", {}), ports)
    assert re.search(r"orb_axis_chk #\(\.W\(4\), \.ASSUME\(1\)\) chk_s_axis_a .*\.tuser\(1'b0\)", text)
    assert re.search(r"orb_axis_chk #\(\.W\(8\), \.ASSUME\(0\)\) chk_m_axis_b .*\.tlast\(m_axis_b_tlast\)", text)
    assert "assume (rst)" in text


def test_wrapper_binds_board_wrapper_ports() -> None:
    """The flat board wrapper's names: clock aclk, reset aresetn (active low, inverted for the checkers), the
    AXI4-Lite slave s_axi_ctrl bound to the same checker (chk_s_axil)."""
    names = [f"s_axi_ctrl_{n}" for n in formal.AXIL_PORTS]
    verilog = "module orb_y\n  (input  aclk,\n   input  aresetn,\n" + "".join(
        f"   {'output' if n.endswith(('ready', 'resp', 'bvalid', 'rvalid', 'rdata')) else 'input '} {n},\n"
        for n in names
    )
    verilog = verilog.rstrip(",\n") + ");\n"
    ports = formal.ports(verilog, "orb_y")
    assert formal.axil_prefix(p.name for p in ports) == "s_axi_ctrl"
    text = formal.wrapper(formal.Check("orb_y", {}), ports)
    assert "wire rst = !aresetn;" in text
    assert ".aclk(clk)" in text and "input wire aclk" not in text
    assert re.search(r"orb_axil_chk #\(.*\) chk_s_axil \(.*\.awvalid\(s_axi_ctrl_awvalid\)", text)


def test_probes_become_outputs() -> None:
    """add_probes makes internal nets of the entity's module outputs probe_<net>, read by ports()."""
    verilog = (
        "module orb_z\n  (input  clk,\n   output [1:0] q);\n  wire [4:0] wr_addr;\n  reg wr_en;\n"
        "  assign q = 2'b00;\nendmodule\n"
    )
    out = formal.add_probes(verilog, "orb_z", ("wr_en", "wr_addr"))
    assert [(p.dir, p.width, p.name) for p in formal.ports(out, "orb_z")] == [
        ("input", 1, "clk"),
        ("output", 2, "q"),
        ("output", 1, "probe_wr_en"),
        ("output", 5, "probe_wr_addr"),
    ]
    assert "assign probe_wr_addr = wr_addr;" in out
    with pytest.raises(formal.VerilogError):
        formal.add_probes(verilog, "orb_z", ("no_such_net",))
