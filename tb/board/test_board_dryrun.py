# SPDX-License-Identifier: MIT
"""The Zybo Z7-20 build checked without Vivado (docs/board.md, "Checked without Vivado").

- vivado/board.json's generated views are fresh; the device-tree overlays compile with dtc and
  carry the address map and the interrupt, and for a DDR build the ring's u-dma-buf node (its size,
  compatible, device name and sync mode); the PYNQ overlays: the address map only;
- tclint passes over every TCL and XDC file with the Vivado command spec;
- vivado/build.tcl runs in tclsh against the recording stubs for every configuration, with and
  without board files, and every check of sw/orb_flow/board/dryrun.py passes on the record (sources =
  hdl/manifest.txt, accelerator ports read from the VHDL, IP facts, nets, pins = Digilent's master
  XDC, clocks, addresses, the DDR path of the feature memory, overlay, documented VLNVs); docs/board.md's
  table is this dry run;
- the checks can fail: a wrong pin, a connection to a port the wrapper does not have, an
  overlapping address segment, an IP property value outside its choices, a switch Vivado does not
  know and a bad argument each make the dry run or a check fail; so do an HP port at 32 bits, the
  feature master wired to the HP port without the interconnect, the HP port on another clock and a
  DDR segment that is not the window; a BRAM build has none of the DDR path and passes;
- the build's TCL helpers: the kClkRange choice-list extension, the manifest reader;
- make bitstream without Vivado stops at once with one line naming what is missing; its outputs lie
  side by side with one stem (.bit and .hwh from the TCL, .bit.bin and .dtbo from the packaging step),
  and a build that does not copy the hardware handoff fails the check.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from orb_flow.board import bit2bin, bitstream, dryrun
from orb_flow.gen import board as gen_board
from orbtb.bitfile import SYNC_AT, make_bit
from orbtb.views import assert_view_fresh

ROOT = Path(__file__).resolve().parents[2]
BOARD = json.loads((ROOT / "vivado" / "board.json").read_text())
CONFIGS = list(BOARD["configs"])
BOARD_PART = BOARD["vivado_boards"]["board_part"]
DMA = BOARD["feat_dma"]


def need(tool: str, package: str) -> str:
    path = shutil.which(tool)
    assert path is not None, f"{tool} is not installed: apt-get install {package}"
    return path


# --- generated views and the overlays ------------------------------------------------------------------


@pytest.mark.parametrize(
    "view",
    [
        "vivado/gen/board.tcl",
        "docs/board-configs.md",
        *(f"vivado/linux/orb-accel-{c}.dtso" for c in CONFIGS),
        *(f"vivado/linux/orb-accel-{c}-pynq.dtso" for c in CONFIGS),
    ],
)
def test_board_views_fresh(view: str) -> None:
    assert_view_fresh(gen_board, Path(view), ROOT)


@pytest.mark.parametrize("config", CONFIGS)
def test_overlay_compiles_with_address_and_interrupt(config: str, tmp_path: Path) -> None:
    dtc = need("dtc", "device-tree-compiler")
    src = ROOT / "vivado" / "linux" / f"orb-accel-{config}.dtso"
    dtbo = tmp_path / "o.dtbo"
    subprocess.run([dtc, "-@", "-I", "dts", "-O", "dtb", "-o", str(dtbo), str(src)], check=True, capture_output=True)
    back = subprocess.run([dtc, "-I", "dtb", "-O", "dts", str(dtbo)], check=True, capture_output=True, text=True).stdout
    acc = BOARD["accel"]
    base, size = int(acc["base"], 16), int(acc["range"], 16)
    assert f"reg = <0x{base:x} 0x{size:x}>;" in back, back
    assert f"interrupts = <0x00 0x{acc['gic_spi']:02x} 0x04>;" in back, back
    assert 'compatible = "generic-uio";' in back
    assert f'firmware-name = "{BOARD["design_name"]}_{config}.bit.bin";' in back
    assert acc["gic_spi"] == 29 + acc["irq_f2p"], "IRQ_F2P[n] is GIC SPI 29 + n (SPI IDs 61..68 - 32)"
    # the ring's buffer (docs/board.md, "Features to DDR"): one u-dma-buf node of count x DEPTH_g x 64
    # bytes, cached when opened without O_SYNC (sync-mode 1, no sync-always), synced from the device
    cfg = BOARD["configs"][config]
    nodes = re.findall(r"\n(\t+)orb-ring \{\n(.*?)\n\1\};", back, re.S)
    if cfg["mem_kind"] != "ddr":
        assert "u-dma-buf" not in back, back
        return
    assert len(nodes) == 1, back
    body = nodes[0][1]
    ring = DMA["ring_buffers"] * cfg["mem_depth"] * 64
    assert 'compatible = "ikwzm,u-dma-buf";' in body
    assert f"size = <0x{ring:02x}>;" in body, body
    assert (
        f'device-name = "{DMA["udmabuf_name"]}";' in body and f"minor-number = <0x{DMA['udmabuf_minor']:02x}>;" in body
    )
    assert f"sync-mode = <0x{DMA['udmabuf_sync_mode']:02x}>;" in body and DMA["udmabuf_sync_mode"] == 1
    assert f"sync-direction = <0x{DMA['udmabuf_sync_direction']:02x}>;" in body and DMA["udmabuf_sync_direction"] == 2
    assert "sync-always" not in body and "dma-coherent" not in body and "memory-region" not in body, body
    if config == "1920x1080":
        assert ring == 512 * 1024, "4 buffers x 2,048 slots x 64 bytes at 1080p"


def test_udmabuf_name_is_the_drivers_default() -> None:
    """The overlay's u-dma-buf device is the one orb_accel.ddr.UDmaBuf opens when given no name."""
    from orb_accel import ddr

    assert DMA["udmabuf_name"] == ddr.UDMABUF_NAME


@pytest.mark.parametrize("config", CONFIGS)
def test_pynq_overlay_has_the_registers_only(config: str, tmp_path: Path) -> None:
    """PYNQ programs the PL itself and its images give IRQ_F2P[0] to their own `fabric` node: the
    overlay beside the .bit adds the register window and nothing else (docs/pynq.md)."""
    dtc = need("dtc", "device-tree-compiler")
    src = ROOT / "vivado" / "linux" / f"orb-accel-{config}-pynq.dtso"
    dtbo = tmp_path / "o.dtbo"
    subprocess.run([dtc, "-@", "-I", "dts", "-O", "dtb", "-o", str(dtbo), str(src)], check=True, capture_output=True)
    back = subprocess.run([dtc, "-I", "dtb", "-O", "dts", str(dtbo)], check=True, capture_output=True, text=True).stdout
    acc = BOARD["accel"]
    base, size = int(acc["base"], 16), int(acc["range"], 16)
    assert f"{acc['dt_name']}@{base:x} {{" in back and f"reg = <0x{base:x} 0x{size:x}>;" in back, back
    assert 'compatible = "generic-uio";' in back
    assert "interrupts" not in back and "firmware-name" not in back and "fpga_full" not in back, back
    assert "u-dma-buf" not in back, "under PYNQ the ring comes from pynq.allocate (docs/pynq.md)"


def test_board_json_rules(tmp_path: Path) -> None:
    gen = gen_board
    bad = json.loads(json.dumps(BOARD))
    bad["accel"]["range"] = "0x00080000"
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match="2\\*\\*addr_width"):
        gen.load(tmp_path / "b.json")
    bad = json.loads(json.dumps(BOARD))
    bad["configs"]["1920x1080"]["core_mhz"] = 100
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match="at least the pixel clock"):
        gen.load(tmp_path / "b.json")
    bad = json.loads(json.dumps(BOARD))
    bad["configs"]["640x480"]["mem_depth"] = 4096  # the budget of 1,000 needs 1,024 slots
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match=r"640x480: mem_depth 4096 is more than the recommended budget needs \(1024"):
        gen.load(tmp_path / "b.json")
    bad = json.loads(json.dumps(BOARD))
    bad["configs"]["640x480"] |= {"scales": 5, "block_log2": 3}  # 8-pixel blocks hold 4 rings
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match="640x480: block_log2: block size 8 too small for 5"):
        gen.load(tmp_path / "b.json")
    bad = json.loads(json.dumps(BOARD))
    bad["configs"]["640x480"]["sectors"] = 64  # the generics are the named configuration's
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match="640x480: sectors 64 is not board-vga's 32"):
        gen.load(tmp_path / "b.json")
    bad["configs"]["640x480"]["config"] = "board-qvga"
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match="640x480: 'config' must name a configuration"):
        gen.load(tmp_path / "b.json")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"win_base_mb": 512}, "window 512 \\+ 1024 MiB is not inside the DDR"),
        ({"win_base_mb": 256, "win_size_mb": 512}, "must be a power of two at a multiple of itself"),
        ({"win_size_mb": 768}, "must be a power of two at a multiple of itself"),
        ({"hp_data_width": 32}, "m_axi_feat is 64 bits wide"),
        ({"ring_buffers": 17}, "ring_buffers 17 is not 1 .. 16"),
        ({"win_size_mb": 1, "ring_buffers": 16}, "1280x720: the ring \\(2097152 bytes\\) does not fit"),
    ],
)
def test_board_json_feat_dma_rules(change: dict[str, int], message: str, tmp_path: Path) -> None:
    """The DDR window lies in the board's DDR and is one address segment; every ring fits in it."""
    bad = json.loads(json.dumps(BOARD))
    bad["feat_dma"] |= change
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match=message):
        gen_board.load(tmp_path / "b.json")
    del bad["feat_dma"]
    (tmp_path / "b.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match="mem_kind ddr but there is no feat_dma"):
        gen_board.load(tmp_path / "b.json")


# --- tclint -----------------------------------------------------------------------------------------


def test_tclint_clean() -> None:
    tclint = Path(sys.executable).parent / "tclint"
    proc = subprocess.run(
        [str(tclint), "vivado", "sw/orb_flow/board/vivado_stub.tcl"], cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_tclint_knows_the_vivado_switches(tmp_path: Path) -> None:
    """The command spec is in force: a switch UG835 does not list is reported."""
    tclint = Path(sys.executable).parent / "tclint"
    bad = tmp_path / "bad.tcl"
    bad.write_text("create_bd_cell -type ip -vnlv xilinx.com:ip:v_tc vtc\n")
    proc = subprocess.run(
        [str(tclint), "-c", str(ROOT / "tclint.toml"), str(bad)], cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode != 0 and "-vnlv" in proc.stdout, proc.stdout


# --- the dry run --------------------------------------------------------------------------------------


@pytest.mark.parametrize("board_files", [False, True], ids=["explicit-ps7", "board-files"])
@pytest.mark.parametrize("config", CONFIGS)
def test_dry_run_checks(config: str, board_files: bool, tmp_path: Path) -> None:
    need("tclsh", "tcl")
    d = dryrun.run(config, tmp_path, board_part=BOARD_PART if board_files else "")
    errors = {name: errs for name, errs in dryrun.check_all(d).items() if errs}
    assert not errors, json.dumps(errors, indent=1)
    launched = [r for r in d.records if r["cmd"] == "launch_runs"]
    assert [r["run"] for r in launched] == ["synth_1", "impl_1"] and launched[1]["to_step"] == "write_bitstream"
    assert {r["what"] for r in d.records if r["cmd"] == "report"} >= {"utilization", "timing_summary", "power"}
    assert any(r["cmd"] == "write_hw_platform" for r in d.records)
    ps7 = d.cells["ps7"].config
    if board_files:
        assert any(r["cmd"] == "apply_bd_automation" and 'apply_board_preset "1"' in r["config"] for r in d.records)
    else:
        assert ps7["CONFIG.PCW_UIPARAM_DDR_PARTNO"] == "MT41K256M16 RE-125"


def test_dry_run_table_in_docs(tmp_path: Path) -> None:
    need("tclsh", "tcl")
    doc = (ROOT / "docs" / "board.md").read_text()
    assert dryrun.doc_section(doc) == dryrun.doc_table(), "docs/board.md: run sw/orb_flow/board/dryrun.py --update-doc"


def test_accel_sources_from_manifest(tmp_path: Path) -> None:
    d = dryrun.run("1280x720", tmp_path)
    hdl = [Path(f).relative_to(ROOT / "hdl").as_posix() for fs, f in d.sources if fs == "sources_1" and "/hdl/" in f]
    assert hdl == dryrun.manifest()
    assert d.file_types[str(ROOT / "hdl" / "top" / "orb_accel_zynq.vhd")] == "VHDL"


def test_interface_attributes_set_from_tcl(tmp_path: Path) -> None:
    """orb_accel_zynq's commented interface attributes are set on the module reference's pins."""
    d = dryrun.run("1920x1080", tmp_path)
    aclk, aresetn = d.pin_props["orb_accel/aclk"], d.pin_props["orb_accel/aresetn"]
    assert set(aclk["CONFIG.ASSOCIATED_BUSIF"].split(":")) == set(dryrun.module_interfaces(dryrun.read_entity().ports))
    assert aclk["CONFIG.ASSOCIATED_RESET"] == "aresetn" and aresetn["CONFIG.POLARITY"] == "ACTIVE_LOW"


def test_entity_reader() -> None:
    ent = dryrun.read_entity()
    assert {"aclk", "aresetn", "irq", "s_axi_ctrl_awaddr", "m_axis_video_tlast"} <= set(ent.ports)
    assert ent.ports["irq"] == "out" and ent.ports["s_axis_video_tdata"] == "in"
    assert {"WIDTH_g", "MEM_DEPTH_g", "C_S_AXI_CTRL_ADDR_WIDTH"} <= set(ent.generics)
    assert {"MEM_KIND_g", "WIN_BASE_MB_g", "WIN_SIZE_MB_g"} <= set(ent.generics)
    assert sorted(dryrun.module_interfaces(ent.ports)) == ["m_axi_feat", "m_axis_video", "s_axi_ctrl", "s_axis_video"]
    feat = {p.removeprefix("m_axi_feat_") for p in dryrun.module_interfaces(ent.ports)["m_axi_feat"]}
    need = {"awaddr", "awlen", "awsize", "awburst", "awcache", "awprot", "awvalid", "awready",
            "wdata", "wstrb", "wlast", "wvalid", "wready", "bresp", "bvalid", "bready"}  # fmt: skip
    assert need <= feat and feat - need <= {"awid", "bid"}, feat  # write channels only (an ID at most)


# --- the checks can fail --------------------------------------------------------------------------------


def mutated_run(tmp_path: Path, edit: Callable[[Path], None], config: str = "1280x720") -> object:
    """The dry run of a copy of vivado/ changed by `edit` (hdl/ linked in, as the TCL finds it)."""
    repo = tmp_path / "repo"
    shutil.copytree(ROOT / "vivado", repo / "vivado")
    os.symlink(ROOT / "hdl", repo / "hdl")
    edit(repo / "vivado")
    return dryrun.run(config, tmp_path / "work", vivado_dir=repo / "vivado")


def replace_in(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert text.count(old) == 1, f"{old!r} not once in {path}"
    path.write_text(text.replace(old, new))


def test_wrong_pin_fails(tmp_path: Path) -> None:
    d = mutated_run(tmp_path, lambda v: replace_in(v / "xdc" / "zybo_z7_20.xdc", "PACKAGE_PIN U18", "PACKAGE_PIN U17"))
    assert dryrun.check_xdc(d) == ["port hdmi_rx_clk_p: PACKAGE_PIN U17 but the master XDC says U18"]


def test_wrong_iostandard_and_unknown_port_fail(tmp_path: Path) -> None:
    def edit(v: Path) -> None:
        replace_in(
            v / "xdc" / "zybo_z7_20.xdc", "PACKAGE_PIN D18 IOSTANDARD LVCMOS33", "PACKAGE_PIN D18 IOSTANDARD LVCMOS18"
        )
        with (v / "xdc" / "zybo_z7_20.xdc").open("a") as f:
            f.write("set_property -dict { PACKAGE_PIN K18 IOSTANDARD LVCMOS33 } [get_ports { btn[0] }]\n")

    errs = dryrun.check_xdc(mutated_run(tmp_path, edit))
    assert "XDC constrains port btn[0], which the block design's top does not have" in errs
    assert "port led[3]: IOSTANDARD LVCMOS18 but the master XDC says LVCMOS33" in errs


def test_connection_to_missing_wrapper_port_fails(tmp_path: Path) -> None:
    d = mutated_run(
        tmp_path,
        lambda v: replace_in(
            v / "lib" / "bd.tcl", "orb_net $accel/irq ps7/IRQ_F2P", "orb_net $accel/interrupt ps7/IRQ_F2P"
        ),
    )
    errs = dryrun.check_accel(d)
    assert "connection to orb_accel/interrupt: orb_accel_zynq has no port interrupt" in errs
    assert "orb_accel/irq (out) is not connected" in errs


def test_overlapping_address_fails(tmp_path: Path) -> None:
    extra = (
        "  assign_bd_address -offset 0x43C80000 -range 0x00010000 -target_address_space "
        "[get_bd_addr_spaces ps7/Data] [get_bd_addr_segs vtc/ctrl/Reg]\n  validate_bd_design\n"
    )
    d = mutated_run(tmp_path, lambda v: replace_in(v / "lib" / "bd.tcl", "  validate_bd_design\n", extra))
    assert "address segment /vtc/ctrl/Reg: interface ctrl exists only when HAS_AXI4_LITE == true" in dryrun.check_ip(d)
    errs = dryrun.check_addresses(d)
    assert errs == [
        "address segments overlap: /orb_accel/s_axi_ctrl/reg0 at 0x43C00000+0x100000 and /vtc/ctrl/Reg at 0x43C80000"
    ]


def test_ip_property_checks_fail(tmp_path: Path) -> None:
    def edit(v: Path) -> None:
        replace_in(v / "lib" / "bd.tcl", "CONFIG.kDebug {false}", "CONFIG.kDebug {false} CONFIG.kNoSuchThing {1}")
        replace_in(v / "lib" / "bd.tcl", "orb_net vid_out/locked leds/In1", "orb_net vid_out/lock leds/In1")

    errs = dryrun.check_ip(mutated_run(tmp_path, edit))
    assert "hdmi_in (digilentinc.com:ip:dvi2rgb): CONFIG.kNoSuchThing is not a property of this IP" in errs
    assert "connection to vid_out/lock: xilinx.com:ip:v_axi4s_vid_out has no pin lock" in errs


def test_clk_range_outside_choices_fails(tmp_path: Path) -> None:
    """kClkRange 5 is legal only where the build extends the choice list (pixel clock < 40 MHz)."""
    d = mutated_run(tmp_path, lambda v: replace_in(v / "gen" / "board.tcl", "kClkRange 2", "kClkRange 5"))
    assert "hdmi_in: CONFIG.kClkRange = '5' is not one of ['1', '2', '3']" in dryrun.check_ip(d)


def test_unknown_switch_and_bad_arguments_fail(tmp_path: Path) -> None:
    with pytest.raises(RuntimeError, match="unknown switch -vnlv"):
        mutated_run(
            tmp_path / "a",
            lambda v: replace_in(
                v / "lib" / "bd.tcl", "create_bd_cell -type ip -vlnv", "create_bd_cell -type ip -vnlv"
            ),
        )
    with pytest.raises(RuntimeError, match=r"unknown configuration 800x600 \(known: 640x480 1280x720 1920x1080\)"):
        dryrun.run("800x600", tmp_path / "b")
    with pytest.raises(RuntimeError, match="--jobs must be a positive integer"):
        dryrun.run("1280x720", tmp_path / "c", extra_args=("--jobs", "0"))
    with pytest.raises(RuntimeError, match="is not Digilent's vivado-library"):
        dryrun.run("1280x720", tmp_path / "d", library=tmp_path)


def test_feature_dma_recorded(tmp_path: Path) -> None:
    """The dry run's record of the DDR path, spelled out: HP0 on at 64 bits, m_axi_feat -> feat_ic
    (one SI, one MI) -> S_AXI_HP0, S_AXI_HP0_ACLK on the accelerator's clock, the HP0 DDR segment in
    m_axi_feat's space exactly the window, the wrapper's generics from vivado/board.json."""
    d = dryrun.run("1920x1080", tmp_path)
    ps7, accel, ic = d.cells["ps7"].config, d.cells["orb_accel"].config, d.cells[DMA["interconnect"]]
    assert (ps7["CONFIG.PCW_USE_S_AXI_HP0"], ps7["CONFIG.PCW_S_AXI_HP0_DATA_WIDTH"]) == ("1", "64")
    assert (accel["CONFIG.MEM_KIND_g"], accel["CONFIG.WIN_BASE_MB_g"], accel["CONFIG.WIN_SIZE_MB_g"]) == (
        "DDR",
        "0",
        "1024",
    )
    assert ic.vlnv == "xilinx.com:ip:axi_interconnect" and (ic.config["CONFIG.NUM_SI"], ic.config["CONFIG.NUM_MI"]) == (
        "1",
        "1",
    )
    assert ["orb_accel/m_axi_feat", "feat_ic/S00_AXI"] in d.intf_nets and [
        "feat_ic/M00_AXI",
        "ps7/S_AXI_HP0",
    ] in d.intf_nets
    clock = next(n for n in d.nets if "orb_accel/aclk" in n)
    assert clock[0] == "core_clk/clk_out1" and "ps7/S_AXI_HP0_ACLK" in clock
    seg = [a for a in d.addresses if a["space"] == "/orb_accel/m_axi_feat"]
    assert [(a["segment"], a["offset"], a["range"]) for a in seg] == [
        ("/ps7/S_AXI_HP0/HP0_DDR_LOWOCM", "0x00000000", "0x40000000")
    ]


@pytest.mark.parametrize(
    ("old", "new", "error"),
    [
        (
            "PCW_[dict get $dma hp_port]_DATA_WIDTH [dict get $dma hp_data_width]",
            "PCW_[dict get $dma hp_port]_DATA_WIDTH 32",
            "ps7: CONFIG.PCW_S_AXI_HP0_DATA_WIDTH = '32', want '64'",
        ),
        (
            "    orb_intf $accel/m_axi_feat $feat_ic/S00_AXI\n    orb_intf $feat_ic/M00_AXI ps7/$hp\n",
            "    orb_intf $accel/m_axi_feat ps7/$hp\n",
            "orb_accel/m_axi_feat must go to one axi_interconnect's slave interface, goes to ['ps7/S_AXI_HP0']",
        ),
        (
            "lappend core_loads ps7/${hp}_ACLK ",
            "lappend core_loads ",
            "ps7/S_AXI_HP0_ACLK is not on the accelerator's clock net (['core_clk/clk_out1'])",
        ),
        (
            "-range [orb_mb_hex [dict get $dma win_size_mb]]",
            "-range 0x20000000",
            "orb_accel/m_axi_feat: segments [('/ps7/S_AXI_HP0/HP0_DDR_LOWOCM', 0, 536870912)], want exactly "
            "('/ps7/S_AXI_HP0/HP0_DDR_LOWOCM', 0, 1073741824) (the window WIN_BASE_MB_g, WIN_SIZE_MB_g)",
        ),
        (
            "CONFIG.WIN_SIZE_MB_g [dict get $dma win_size_mb]",
            "CONFIG.WIN_SIZE_MB_g 512",
            "orb_accel: CONFIG.WIN_SIZE_MB_g = '512', vivado/board.json wants '1024'",
        ),
    ],
    ids=["hp0-32-bit", "no-interconnect", "hp0-other-clock", "segment-not-window", "window-generic"],
)
def test_feature_dma_checks_fail(old: str, new: str, error: str, tmp_path: Path) -> None:
    def edit(v: Path) -> None:
        lib = "ps7.tcl" if "DATA_WIDTH" in old else "bd.tcl"
        replace_in(v / "lib" / lib, old, new)

    d = mutated_run(tmp_path, edit)
    assert error in dryrun.check_feature_dma(d), dryrun.check_feature_dma(d)


def test_bram_build_has_no_ddr_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A configuration with mem_kind bram (a board.json the named configurations do not have, so its
    views are written without gen_board.load's checks): no HP port, no feat_ic, m_axi_feat left
    unconnected, no DDR segment, no u-dma-buf node, and every check passes."""
    b = json.loads(json.dumps(BOARD))
    b["configs"]["1280x720"]["mem_kind"] = "bram"
    repo = tmp_path / "repo"
    shutil.copytree(ROOT / "vivado", repo / "vivado")
    os.symlink(ROOT / "hdl", repo / "hdl")
    (repo / "vivado" / "board.json").write_text(json.dumps(b))
    (repo / "vivado" / "gen" / "board.tcl").write_text(gen_board.render_tcl(b))
    for name in b["configs"]:
        (repo / "vivado" / "linux" / f"orb-accel-{name}.dtso").write_text(gen_board.render_dtso(b, name))
    monkeypatch.setattr(dryrun, "BOARD", repo / "vivado" / "board.json")
    monkeypatch.setattr(dryrun, "VIVADO", repo / "vivado")
    d = dryrun.run("1280x720", tmp_path / "work", vivado_dir=repo / "vivado")
    # (sources: the copy's hdl/ is a link, so its paths are not ROOT's; test_dry_run_checks covers them)
    errors = {name: errs for name, errs in dryrun.check_all(d).items() if errs and name != "sources"}
    assert not errors, json.dumps(errors, indent=1)
    assert "feat_ic" not in d.cells and "CONFIG.PCW_USE_S_AXI_HP0" not in d.cells["ps7"].config
    assert d.cells["orb_accel"].config["CONFIG.MEM_KIND_g"] == "BRAM"
    assert [a["space"] for a in d.addresses] == ["/ps7/Data"]
    assert "u-dma-buf" not in (repo / "vivado" / "linux" / "orb-accel-1280x720.dtso").read_text()


def test_missing_hardware_handoff_copy_fails(tmp_path: Path) -> None:
    d = mutated_run(
        tmp_path, lambda v: replace_in(v / "build.tcl", "file copy -force $hwh [file join $out ${base_name}.hwh]", "")
    )
    assert dryrun.check_outputs(d) == [
        f"no orb_board_1280x720.hwh in the build's output folder (found {sorted(d.outputs)})"
    ]


# --- TCL helpers ---------------------------------------------------------------------------------------


def tcl(script: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([need("tclsh", "tcl"), "/dev/stdin"], input=script, capture_output=True, text=True)


def test_clk_range_extension() -> None:
    lib = ROOT / "vivado" / "lib" / "ip_repo.tcl"
    item = '<spirit:enumeration spirit:text="&lt; 80 MHz (720p)">3</spirit:enumeration>'
    proc = tcl(f"source {{{lib}}}\nputs [orb_extend_clk_range {{<c>\n  {item}\n</c>}}]\n")
    assert proc.returncode == 0, proc.stderr
    values = re.findall(r">(\d)</spirit:enumeration>", proc.stdout)
    assert values == ["3", "4", "5"] and "&gt;=25 MHz (640x480)" in proc.stdout, proc.stdout
    for text in ("<c></c>", f"<c>{item}{item}</c>"):
        bad = tcl(f"source {{{lib}}}\norb_extend_clk_range {{{text}}}\n")
        assert bad.returncode != 0 and "not found exactly once" in bad.stderr


def test_manifest_reader_matches_python() -> None:
    args = ROOT / "vivado" / "lib" / "args.tcl"
    proc = tcl(f"source {{{args}}}\nputs [join [orb_read_manifest {{{ROOT / 'hdl' / 'manifest.txt'}}}] \\n]\n")
    assert proc.stdout.split() == dryrun.manifest()


# --- make bitstream without Vivado -------------------------------------------------------------------


def test_bitstream_without_vivado_stops_at_once(tmp_path: Path) -> None:
    env = {**os.environ, "VIVADO_LIBRARY": "", "PATH": "/usr/bin:/bin"}
    proc = subprocess.run(
        [sys.executable, "-m", "orb_flow.board.bitstream", "--vivado", "no-vivado-here"],
        capture_output=True, text=True, env=env, timeout=30,
    )  # fmt: skip
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert "Vivado ('no-vivado-here' not on PATH" in lines[0]
    assert f"git -C ../vivado-library checkout {BOARD['vivado_library']['commit']}" in lines[0]


def test_outputs_side_by_side_with_one_stem(tmp_path: Path) -> None:
    """make bitstream's outputs for PYNQ and for the plain UIO flow: the TCL's .bit and .hwh (the dry
    run's, the .bit replaced by a synthetic one), then package() adds the .bit.bin and the .dtbo."""
    need("dtc", "device-tree-compiler")
    config = BOARD["default_config"]
    dryrun.run(config, tmp_path)
    out = tmp_path / "out"
    stem = f"{BOARD['design_name']}_{config}"
    (out / f"{stem}.bit").write_bytes(make_bit())
    files = bitstream.package(out, config)
    assert {p.name for p in files.values()} == {f"{stem}{ext}" for ext in (".bit", ".hwh", ".bit.bin", ".dtbo")}
    assert all(p.parent == out and p.is_file() for p in files.values())
    assert bit2bin.check_bin(files[".bit.bin"].read_bytes()) == SYNC_AT
    assert "stand-in for the hardware handoff" in files[".hwh"].read_text()
    dts = subprocess.run(["dtc", "-I", "dtb", "-O", "dts", str(files[".dtbo"])], capture_output=True, text=True)
    assert dts.returncode == 0 and 'compatible = "generic-uio";' in dts.stdout and "interrupts" not in dts.stdout

    (out / f"{stem}.hwh").unlink()
    with pytest.raises(FileNotFoundError, match=rf"{stem}\.hwh: Vivado wrote no \.hwh"):
        bitstream.package(out, config)
