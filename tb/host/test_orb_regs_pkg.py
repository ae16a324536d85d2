# SPDX-License-Identifier: MIT
"""The register map's generated views against their one definition, golden_model/data/regmap.json.

No cocotb: sw/orb_flow/gen/regmap.py regenerated into a temporary directory must give the committed
hdl/host/orb_regs_pkg.vhd, golden_model/regs.py and docs/registers.md byte for byte (a stale view
fails); the generator must refuse inconsistent data; the VHDL constants and the register-file tables
REGS_c and REG_LIMITS_c, parsed from the text, must equal golden_model.regs; GHDL must synthesise
orb_axil_regs with the package for extreme generics and refuse an illegal SECTORS_g with a message
naming the entity; and a map with two registers added must work in orb_axil_regs unchanged (a small
VHDL testbench run by GHDL).
"""

from __future__ import annotations

import copy
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from golden_model import regs
from golden_model.config import MODES
from orb_flow.gen import regmap as gen_regmap
from orbtb.runner import ghdl_path_env
from orbtb.views import assert_deterministic, assert_view_fresh

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "golden_model" / "data" / "regmap.json"
VIEWS = (Path("hdl") / "host" / "orb_regs_pkg.vhd", Path("golden_model") / "regs.py", Path("docs") / "registers.md")
GHDL_FILES = (
    "common/orb_limits_pkg.vhd",
    "host/orb_regs_types_pkg.vhd",
    "host/orb_regs_pkg.vhd",
    "host/orb_axil_regs.vhd",
)


@pytest.mark.parametrize("view", VIEWS, ids=lambda p: p.name)
def test_views_are_what_the_generator_writes(view: Path) -> None:
    assert_view_fresh(gen_regmap, view, ROOT)


def test_generator_is_deterministic(tmp_path: Path) -> None:
    assert_deterministic(gen_regmap, VIEWS, tmp_path)


def _broken(raw: dict, what: str) -> dict:
    raw = copy.deepcopy(raw)
    regs_ = {r["name"]: r for r in raw["registers"]}
    if what == "overlap":
        regs_["CTRL"]["fields"][2]["bits"] = [5, 1]
    elif what == "misaligned":
        regs_["THRESHOLD"]["offset"] = 26
    elif what == "duplicate offset":
        regs_["THRESHOLD"]["offset"] = regs_["CTRL"]["offset"]
    elif what == "reset too wide":
        regs_["THRESHOLD"]["fields"][0]["reset"] = 256
    elif what == "beyond MEM_BASE":
        regs_["THRESHOLD"]["offset"] = raw["constants"]["MEM_BASE"]["value"]
    elif what == "bad access":
        regs_["CTRL"]["access"] = "rc"
    elif what == "generic in rw":
        regs_["THRESHOLD"]["fields"][0]["reset"] = "WIDTH_g"
    elif what == "unknown reset name":
        regs_["ID"]["fields"][0]["reset"] = "NO_SUCH"
    elif what == "max of ro":
        regs_["STATUS"]["fields"][1]["max"] = 0
    return raw


@pytest.mark.parametrize(
    "what",
    [
        "overlap",
        "misaligned",
        "duplicate offset",
        "reset too wide",
        "beyond MEM_BASE",
        "bad access",
        "generic in rw",
        "unknown reset name",
        "max of ro",
    ],
)
def test_generator_refuses_inconsistent_data(tmp_path: Path, what: str) -> None:
    gen = gen_regmap
    path = tmp_path / "regmap.json"
    path.write_text(json.dumps(_broken(json.loads(DATA.read_text()), what)))
    with pytest.raises(gen.RegMapError):
        gen.load(path)


def test_python_view_matches_the_data() -> None:
    raw = json.loads(DATA.read_text())
    assert [r["name"] for r in raw["registers"]] == [r.name for r in regs.REGISTERS]
    for rj, r in zip(raw["registers"], regs.REGISTERS, strict=True):
        assert (rj["offset"], rj["access"]) == (r.offset, r.access), r.name
        assert [(f["name"], f["bits"][1], f["bits"][0] - f["bits"][1] + 1) for f in rj["fields"]] == [
            (f.name, f.lsb, f.width) for f in r.fields
        ], r.name
    assert regs.ORB_ID == 0x4F524231 and regs.MEM_BASE == 0x10000
    assert regs.ORB_ID.to_bytes(4, "big") == b"ORB1"


def parse_vhdl_constants(text: str) -> dict[str, int]:
    out = {}
    for name, value in re.findall(r"constant\s+(\w+)_c\s*:\s*\w+(?:\(31 downto 0\))?\s*:=\s*([^;]+);", text):
        value = value.strip()
        if m := re.fullmatch(r'x"([0-9A-F]+)"', value):
            out[name] = int(m[1], 16)
        elif m := re.fullmatch(r"16#([0-9A-F]+)#", value):
            out[name] = int(m[1], 16)
        elif value.isdigit():
            out[name] = int(value)
        else:
            out[name] = out[value.removesuffix("_c")]
    return out


def test_vhdl_constants_equal_the_python_view() -> None:
    c = parse_vhdl_constants((ROOT / VIEWS[0]).read_text())
    assert c["ORB_ID"] == regs.ORB_ID and c["MEM_BASE"] == regs.MEM_BASE and c["BANKS"] == regs.BANKS
    assert (c["VERSION_MAJOR"], c["VERSION_MINOR"]) == (regs.VERSION_MAJOR, regs.VERSION_MINOR)
    for r in regs.REGISTERS:
        assert c[f"REG_{r.name}"] == r.offset, r.name
        assert c[f"REG_{r.name}_MASK"] == r.mask, r.name
        if all(f.generic is None and f.port is None for f in r.fields):
            assert c[f"REG_{r.name}_RESET"] == r.reset_value(), r.name
        for f in r.fields:
            p = f"{r.name}_{f.name.upper()}"
            assert (c[f"{p}_LSB"], c[f"{p}_MSB"]) == (f.lsb, f.lsb + f.width - 1), p
            if f.max is not None:
                assert c[f"{p}_MAX"] == f.max, p


def parse_vhdl_tables(text: str) -> tuple[list[tuple], list[tuple[str, int, int]]]:
    """REGS_c's rows (index name, offset name, access, mask, reset, live, pulse) and REG_LIMITS_c's
    rows (register index name, mask, min, max, depth flag, lsb), parsed from the package text."""
    regs_rows = re.findall(
        r"(REG_\w+_IDX)_c\s*=>\s*\((REG_\w+)_c, access_(\w+), "
        r'x"([0-9A-F]{8})", x"([0-9A-F]{8})", x"([0-9A-F]{8})", x"([0-9A-F]{8})"\)',
        text,
    )
    limit_rows = re.findall(
        r'\d+\s*=>\s*\((REG_\w+_IDX)_c, x"([0-9A-F]{8})", x"([0-9A-F]{8})", x"([0-9A-F]{8})", (true|false), (\d+)\)',
        text,
    )
    return (
        [(i, o, a, *(int(w, 16) for w in ws)) for i, o, a, *ws in regs_rows],
        [(r, int(m, 16), int(lo, 16), int(x, 16), d == "true", int(lsb)) for r, m, lo, x, d, lsb in limit_rows],
    )


def test_vhdl_register_file_tables_equal_the_python_view() -> None:
    """REGS_c and REG_LIMITS_c, which orb_axil_regs decodes with, describe exactly golden_model.regs."""
    text = (ROOT / VIEWS[0]).read_text()
    c = parse_vhdl_constants(text)
    rows, limits = parse_vhdl_tables(text)
    assert c["REG_COUNT"] == len(regs.REGISTERS) == len(rows)
    for i, (r, row) in enumerate(zip(regs.REGISTERS, rows, strict=True)):
        assert c[f"REG_{r.name}_IDX"] == i, r.name
        live = sum(f.mask for f in r.fields if f.generic is not None or f.port is not None)
        pulse = sum(f.mask for f in r.fields if f.pulse)
        fixed = sum((f.reset or 0) << f.lsb for f in r.fields if f.generic is None and f.port is None)
        assert row == (f"REG_{r.name}_IDX", f"REG_{r.name}", r.access, r.mask, fixed, live, pulse), r.name
    # (a map without maxima gets one entry `0 => (0, ...)` with mask 0, which the pattern skips)
    expected = [
        (
            f"REG_{r.name}_IDX",
            f.mask,
            (f.min or 0) << f.lsb,
            f.mask if f.max is None else f.max << f.lsb,
            f.max_generic is not None,
            f.lsb,
        )
        for r in regs.REGISTERS
        for f in r.fields
        if f.max is not None or f.min is not None or f.max_generic is not None
    ]
    assert limits == expected


def test_docs_list_every_register() -> None:
    text = (ROOT / VIEWS[2]).read_text()
    for r in regs.REGISTERS:
        assert f"| 0x{r.offset:03X} | [{r.name}](#{r.name.lower()}) | {r.access} |" in text, r.name
    assert "mem_rd_en" in text and "MEM_LATENCY_g" in text, "the memory port contract is missing"


def _ghdl(args: list[str], cwd: Path, check: bool = True) -> subprocess.CompletedProcess:
    env = {**os.environ, **ghdl_path_env()}
    proc = subprocess.run(["ghdl", *args], cwd=cwd, env=env, capture_output=True, text=True, check=False)
    if check and proc.returncode != 0:
        raise AssertionError(f"ghdl {' '.join(args)} failed:\n{proc.stdout}{proc.stderr}")
    return proc


EXTREMES = {"MEM_LATENCY_g": 1, "ADDR_BITS_g": 20, "SCALES_g": 4, "SECTORS_g": 64, "MEM_DEPTH_g": 16777215}


@pytest.mark.parametrize(
    "generics",
    [{}, {**EXTREMES, "MEM_DDR_g": 1, "WIN_BASE_MB_g": 4095, "WIN_SIZE_MB_g": 4096}],
    ids=["defaults", "extremes"],
)
def test_ghdl_synth_of_the_register_bank(tmp_path: Path, generics: dict[str, int]) -> None:
    files = [str(ROOT / "hdl" / f) for f in GHDL_FILES]
    _ghdl(["-a", "--std=08", *files], tmp_path)
    gargs = [f"-g{k}={v}" for k, v in generics.items()]
    proc = _ghdl(["synth", "--std=08", *gargs, "--out=none", "orb_axil_regs"], tmp_path)
    assert "error" not in (proc.stdout + proc.stderr).lower(), proc.stdout + proc.stderr


def test_illegal_sectors_generic_is_refused(tmp_path: Path) -> None:
    files = [str(ROOT / "hdl" / f) for f in GHDL_FILES]
    _ghdl(["-a", "--std=08", *files], tmp_path)
    proc = _ghdl(["synth", "--std=08", "-gSECTORS_g=24", "--out=none", "orb_axil_regs"], tmp_path, check=False)
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0 and "orb_axil_regs: SECTORS_g" in out, out


# A testbench for a map with two registers added (SCRATCH rw with a maximum and a pulse field,
# MAGIC2 ro constant): orb_axil_regs, unchanged, must decode them from the generated tables.
ADDED_TB = """
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.orb_regs_pkg.all;

entity tb is
end entity tb;

architecture sim of tb is
  signal clk, done, awvalid, wvalid, arvalid : std_logic := '0';
  signal rst                                 : std_logic := '1';
  signal awready, wready, bvalid, arready, rvalid : std_logic;
  signal awaddr, araddr : std_logic_vector(17 downto 0) := (others => '0');
  signal wdata, rdata   : std_logic_vector(31 downto 0) := (others => '0');
  signal bresp, rresp   : std_logic_vector(1 downto 0);
  constant Z_c : std_logic_vector(31 downto 0) := (others => '0');
begin
  clk <= not clk after 5 ns when done = '0';
  dut : entity work.orb_axil_regs
    port map (clk => clk, rst => rst, s_axil_awaddr => awaddr, s_axil_awprot => "000", s_axil_awvalid => awvalid,
      s_axil_awready => awready, s_axil_wdata => wdata, s_axil_wstrb => "1111", s_axil_wvalid => wvalid,
      s_axil_wready => wready, s_axil_bresp => bresp, s_axil_bvalid => bvalid, s_axil_bready => '1',
      s_axil_araddr => araddr, s_axil_arprot => "000", s_axil_arvalid => arvalid, s_axil_arready => arready,
      s_axil_rdata => rdata, s_axil_rresp => rresp, s_axil_rvalid => rvalid, s_axil_rready => '1',
      frame_count => Z_c, dropped => Z_c, proto_errors => Z_c, bank_ready => "00", last_bank => '0',
      overflow => '0', bank0_count => x"0000", bank0_frame => x"0000", bank1_count => x"0000",
      bank1_frame => x"0000", overrun => Z_c, overflow_count => Z_c, desc_lost => Z_c, discarded => Z_c,
      frame_done_pulse => '0', error_pulse => '0', mem_rd_data => Z_c);
  stim : process is
    procedure wr (a : natural; d : std_logic_vector(31 downto 0); resp : std_logic_vector(1 downto 0)) is
    begin
      awaddr <= std_logic_vector(to_unsigned(a, 18)); wdata <= d; awvalid <= '1'; wvalid <= '1';
      wait until rising_edge(clk);
      awvalid <= '0'; wvalid <= '0';
      wait until rising_edge(clk) and bvalid = '1';
      assert bresp = resp report "write " & integer'image(a) & ": bresp " & to_string(bresp) severity failure;
    end procedure;
    procedure rd (a : natural; d : std_logic_vector(31 downto 0); resp : std_logic_vector(1 downto 0)) is
    begin
      araddr <= std_logic_vector(to_unsigned(a, 18)); arvalid <= '1';
      wait until rising_edge(clk);
      arvalid <= '0';
      wait until rising_edge(clk) and rvalid = '1';
      assert rresp = resp and rdata = d
        report "read " & integer'image(a) & ": " & to_hstring(rdata) & " " & to_string(rresp) severity failure;
    end procedure;
  begin
    wait until rising_edge(clk);
    rst <= '0';
    wait until rising_edge(clk);
    rd(REG_SCRATCH_c, x"000002A5", "00");
    rd(REG_MAGIC2_c, x"BEEF0000", "00");
    wr(REG_SCRATCH_c, x"0000153C", "00");
    rd(REG_SCRATCH_c, x"0000053C", "00");
    wr(REG_SCRATCH_c, x"00000600", "10");
    wr(REG_SCRATCH_c, x"00010000", "10");
    wr(REG_MAGIC2_c, x"00000000", "10");
    rd(REG_SCRATCH_c, x"0000053C", "00");
    rd(REG_THRESHOLD_c, REG_THRESHOLD_RESET_c, "00");
    rd(REG_LEAST_c, x"00000014", "00");
    wr(REG_LEAST_c, x"0000000F", "10");
    wr(REG_LEAST_c, x"00000010", "00");
    rd(REG_LEAST_c, x"00000010", "00");
    wr(REG_LEAST_c, x"000000FF", "00");
    report "added registers: passed";
    done <= '1';
    wait;
  end process;
end architecture sim;
"""


def test_a_register_added_to_the_map_needs_no_decode_code(tmp_path: Path) -> None:
    raw = json.loads(DATA.read_text())
    top = max(r["offset"] for r in raw["registers"])
    raw["registers"] += [
        {
            "name": "SCRATCH",
            "offset": top + 4,
            "access": "rw",
            "description": "test",
            "fields": [
                {"name": "lo", "bits": [7, 0], "reset": 0xA5, "description": "byte"},
                {"name": "sel", "bits": [10, 8], "reset": 2, "max": 5, "description": "limited"},
                {"name": "go", "bits": [12, 12], "reset": 0, "pulse": True, "description": "pulse"},
            ],
        },
        {
            "name": "LEAST",
            "offset": top + 12,
            "access": "rw",
            "description": "test",
            "fields": [{"name": "value", "bits": [7, 0], "reset": 20, "min": 16, "description": "at least 16"}],
        },
        {
            "name": "MAGIC2",
            "offset": top + 8,
            "access": "ro",
            "description": "test",
            "fields": [{"name": "value", "bits": [31, 16], "reset": 0xBEEF, "description": "constant"}],
        },
    ]
    (tmp_path / "map.json").write_text(json.dumps(raw))
    gen = [sys.executable, "-m", "orb_flow.gen.regmap", "--data", str(tmp_path / "map.json"), "--out"]
    gen.append(str(tmp_path / "gen"))
    subprocess.run(gen, check=True, capture_output=True)
    files = [str(tmp_path / "gen" / "hdl" / f if f.endswith("regs_pkg.vhd") else ROOT / "hdl" / f) for f in GHDL_FILES]
    (tmp_path / "tb.vhd").write_text(ADDED_TB)
    _ghdl(["-a", "--std=08", *files, "tb.vhd"], tmp_path)
    proc = _ghdl(["--elab-run", "--std=08", "tb"], tmp_path, check=False)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0 and "added registers: passed" in out, out


def test_ring_fields_fit_the_ring() -> None:
    """The DDR ring's fields against orb_feat_dma's contract (docs/feature-dma.md): RING_COUNT 0 .. 16 and
    one RING_STATUS.ready bit per buffer, RING_RELEASE.index reaching every buffer (its full 4 bits, no max),
    RING_STATUS.last naming one, CFG_DDR's fields holding the generics' ranges (WIN_BASE_MB_g 0 .. 4095,
    WIN_SIZE_MB_g 1 .. 4096), and the address and counter registers 32 bits wide; they came with map 3.2, a
    compatible addition (the driver refuses another major version only)."""
    count = regs.RING_COUNT.field("count")
    assert count.max == 16 and count.reset == 0 and count.legal_value(16) and not count.legal_value(17)
    assert regs.RING_STATUS.field("ready").width == count.max
    index = regs.RING_RELEASE.field("index")
    assert 1 << index.width == count.max and index.max is None and regs.RING_RELEASE.access == "wo"
    assert 1 << regs.RING_STATUS.field("last").width == count.max
    assert regs.RING_STATUS.field("error").width == 4 and regs.RING_STATUS.field("busy").width == 1
    assert regs.CFG_DDR.field("ddr").width == 1
    assert (1 << regs.CFG_DDR.field("win_base").width) - 1 == 4095
    assert (1 << regs.CFG_DDR.field("win_size").width) - 1 >= 4096
    assert [f.generic for f in regs.CFG_DDR.fields] == ["MEM_DDR_g", "WIN_BASE_MB_g", "WIN_SIZE_MB_g"]
    for r in (regs.RING_BASE, regs.RING_STRIDE, regs.DMA_DROPPED, regs.DMA_BUS_ERRORS, regs.DMA_BEATS):
        assert r.mask == 0xFFFFFFFF and len(r.fields) == 1, r.name
    assert [f.port for f in regs.RING_INFO.fields] == ["ring_last_count", "ring_last_frame"]
    assert regs.VERSION_MAJOR == 3 and regs.VERSION_MINOR >= 2


def test_ctrl_mode_values_follow_the_model_modes() -> None:
    """The driver writes CTRL.mode = MODES.index(mode): the map's value names must be in that order."""
    ctrl = next(r for r in json.loads(DATA.read_text())["registers"] if r["name"] == "CTRL")
    values = next(f for f in ctrl["fields"] if f["name"] == "mode")["values"]
    assert [values[str(i)].split()[0] for i in range(len(values))] == list(MODES), values
