#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Dry run of the Vivado build (vivado/build.tcl) in plain tclsh, and the checks on what it records.

Vivado cannot run here. The build's own TCL runs unchanged in `tclsh` against recording stubs of
the Vivado commands (sw/orb_flow/board/vivado_stub.tcl); the record (cells, CONFIG properties, pins,
nets, ports, address segments, constraints, runs, reports) is then checked against facts that do
not come from the TCL:
- the accelerator's ports and generics, read from hdl/top/orb_accel_zynq.vhd;
- each IP's interfaces, pins and CONFIG properties, from vivado/facts/ip/*.json (extracted from the
  IPs' published definitions: Digilent's component.xml, Vivado-written block designs, AMD product
  guides; each fact names its source);
- the board's package pins and I/O standards, from vivado/facts/zybo_z7_master_xdc.json
  (Digilent's Zybo Z7 master XDC);
- the address map, the DDR path of the feature memory (m_axi_feat through one interconnect to the
  PS7's HP port, its clock, its address segment = the window) and the device-tree overlays (the
  ring's u-dma-buf node among them), from vivado/board.json and vivado/linux/;
- the list of IP in docs/board.md, and the HDL manifest.

Usage: python3 -m orb_flow.board.dryrun [--config NAME ...] [--board-files] [--table]
(plain python3 and tclsh; exit 1 if a check fails). Imported by tb/board/test_board_dryrun.py.
"""

from __future__ import annotations

import argparse
import itertools
import json
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from orb_flow.board import config_key

ROOT = Path(__file__).resolve().parents[3]
VIVADO = ROOT / "vivado"
STUB = Path(__file__).resolve().parent / "vivado_stub.tcl"
BOARD = VIVADO / "board.json"
FACTS = VIVADO / "facts"
ZYNQ_VHDL = ROOT / "hdl" / "top" / "orb_accel_zynq.vhd"
MANIFEST = ROOT / "hdl" / "manifest.txt"
BOARD_DOC = ROOT / "docs" / "board.md"
COMMANDS = VIVADO / "tclint" / "vivado_commands.json"

# the block-design wrapper names an interface port's members <port>_<member>; an iic_rtl port
# becomes <port>_scl_io and <port>_sda_io (IOBUFs in the wrapper)
IIC_MEMBERS = ("scl_io", "sda_io")
# external ports that are the PS7's own (fixed MIO and DDR pins, no XDC)
PS_PORTS = ("DDR", "FIXED_IO")
# Digilent's tmds_rtl interface (vivado-library if/tmds_v1_0; the portMaps of dvi2rgb's and rgb2dvi's
# component.xml): logical ports CLK_P, CLK_N and the 3-bit DATA_P, DATA_N
TMDS_MEMBERS = (("clk_p", 0), ("clk_n", 0), ("data_p", 3), ("data_n", 3))
# orb_accel_zynq's AXI4 write master of the DDR feature memory (docs/feature-dma.md), idle and
# unconnected in a BRAM build (MEM_KIND_g "BRAM", the wrapper's default)
FEAT_MASTER = "m_axi_feat"
PS_DATA_SPACE = "ps7/Data"  # the CPU's address space (M_AXI_GP0)
UDMABUF_COMPATIBLE = "ikwzm,u-dma-buf"


def master_name(port: str) -> str:
    """The master XDC's name of a wrapper port: hdmi_rx_data_p[0] -> hdmi_rx_p[0],
    hdmi_rx_ddc_scl_io -> hdmi_rx_scl; other names are the same."""
    port = re.sub(r"^(hdmi_(?:rx|tx))_data_([pn])\[(\d)\]$", r"\1_\2[\3]", port)
    return re.sub(r"^(hdmi_(?:rx|tx))_ddc_(scl|sda)_io$", r"\1_\2", port)


# A fake vivado-library for the dry run: only what vivado/lib/ip_repo.tcl reads (the folders it
# checks and the kClkRange choice entries it extends), written here, not copied from Digilent.
FAKE_CHOICES = {
    "dvi2rgb": '      <spirit:enumeration spirit:text="&lt; 80 MHz (720p)">3</spirit:enumeration>\n',
    "rgb2dvi": '      <spirit:enumeration spirit:text="&lt; 80MHz (720p)">3</spirit:enumeration>\n',
}


@dataclass
class Cell:
    name: str
    kind: str  # "ip" or "module"
    vlnv: str
    reference: str
    config: dict[str, str] = field(default_factory=dict)


@dataclass
class Design:
    """What one dry run recorded."""

    config: str
    records: list[dict[str, Any]]
    cells: dict[str, Cell] = field(default_factory=dict)
    pin_props: dict[str, dict[str, str]] = field(default_factory=dict)
    ports: dict[str, dict[str, str]] = field(default_factory=dict)
    intf_ports: dict[str, dict[str, str]] = field(default_factory=dict)
    nets: list[list[str]] = field(default_factory=list)
    intf_nets: list[list[str]] = field(default_factory=list)
    addresses: list[dict[str, str]] = field(default_factory=list)
    sources: list[tuple[str, str]] = field(default_factory=list)
    file_types: dict[str, str] = field(default_factory=dict)
    xdc: dict[str, dict[str, str]] = field(default_factory=dict)
    xdc_ports: list[str] = field(default_factory=list)
    clocks: list[dict[str, Any]] = field(default_factory=list)
    clock_groups: list[list[str]] = field(default_factory=list)
    outputs: dict[str, str] = field(default_factory=dict)  # the files the build left in --out: name -> first line

    @classmethod
    def from_records(cls, config: str, records: list[dict[str, Any]]) -> Design:
        d = cls(config, records)
        for r in records:
            cmd = r["cmd"]
            if cmd == "create_bd_cell":
                d.cells[r["name"]] = Cell(r["name"], r["type"], r["vlnv"], r["reference"])
            elif cmd == "set_property" and r["name"] == "file_type":
                d.file_types[r["object"]] = r["value"]
            elif cmd == "set_property":
                obj = r["object"].strip("/")
                if obj in d.cells:
                    d.cells[obj].config[r["name"]] = r["value"]
                elif "/" in obj:
                    d.pin_props.setdefault(obj, {})[r["name"]] = r["value"]
            elif cmd == "create_bd_port":
                d.ports[r["name"]] = r
            elif cmd == "create_bd_intf_port":
                d.intf_ports[r["name"]] = r
            elif cmd == "connect_bd_net":
                d.nets.append([e.strip("/") for e in r["ends"]])
            elif cmd == "connect_bd_intf_net":
                d.intf_nets.append([e.strip("/") for e in r["ends"]])
            elif cmd == "assign_bd_address":
                d.addresses.append(r)
            elif cmd == "add_files":
                d.sources.append((r["fileset"], r["file"]))
            elif cmd == "xdc_property":
                d.xdc.setdefault(r["object"].removeprefix("port:"), {})[r["name"]] = r["value"]
            elif cmd == "xdc_port":
                d.xdc_ports.append(r["name"])
            elif cmd == "create_clock":
                d.clocks.append(r)
            elif cmd == "set_clock_groups":
                d.clock_groups.append(r["groups"])
        return d

    def wrapper_ports(self) -> dict[str, str]:
        """The top-level ports of the HDL wrapper Vivado makes: name (bits as name[i]) -> direction."""
        out: dict[str, str] = {}
        for name, p in self.ports.items():
            if p["from"] != "":
                lo, hi = sorted((int(p["from"]), int(p["to"])))
                out |= {f"{name}[{i}]": p["dir"] for i in range(lo, hi + 1)}
            else:
                out[name] = p["dir"]
        for name, p in self.intf_ports.items():
            if name in PS_PORTS:
                continue
            if p["vlnv"].startswith("xilinx.com:interface:iic_rtl"):
                out |= {f"{name}_{m}": "IO" for m in IIC_MEMBERS}
            elif p["vlnv"].startswith("digilentinc.com:interface:tmds_rtl"):
                direction = "I" if p["mode"] == "Slave" else "O"
                for m, width in TMDS_MEMBERS:
                    bits = [f"{name}_{m}[{i}]" for i in range(width)] if width else [f"{name}_{m}"]
                    out |= dict.fromkeys(bits, direction)
            else:
                out[name] = "intf:" + p["vlnv"]
        return out


# --- running ------------------------------------------------------------------------------------------


def board() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(BOARD.read_text())
    return data


def fake_vivado_library(path: Path) -> Path:
    for ip, line in FAKE_CHOICES.items():
        d = path / "ip" / ip
        d.mkdir(parents=True, exist_ok=True)
        (d / "component.xml").write_text(f"<!-- dry-run stand-in for Digilent's {ip} component.xml -->\n{line}")
    (path / "if" / "tmds_v1_0").mkdir(parents=True, exist_ok=True)
    return path


def stub_spec(path: Path = COMMANDS) -> str:
    """The tclint command spec as the stub's TCL dict: command -> switch -> 1 (value) / 0 (flag)."""
    spec = json.loads(path.read_text())["commands"]
    parts = []
    for cmd, s in spec.items():
        sws = " ".join(f"{name} {0 if v['value'] is None else 1}" for name, v in (s or {}).get("switches", {}).items())
        parts.append(f"{cmd} {{{sws}}}")
    return " ".join(parts)


def tcl_quote(s: str | Path) -> str:
    return "{" + str(s) + "}"


def run(config: str, work: Path, *, board_part: str = "", vivado_dir: Path = VIVADO,
        library: Path | None = None, extra_args: tuple[str, ...] = ()) -> Design:  # fmt: skip
    """Run vivado_dir/build.tcl for `config` in tclsh against the stubs; RuntimeError with the TCL
    error if the build's TCL fails."""
    tclsh = shutil.which("tclsh")
    if tclsh is None:
        raise RuntimeError("tclsh not found: apt-get install tcl")
    work.mkdir(parents=True, exist_ok=True)
    lib = library if library is not None else fake_vivado_library(work / "vivado-library")
    run_dir = work / "runs"
    run_dir.mkdir(exist_ok=True)
    (run_dir / "orb_board_wrapper.bit").write_bytes(b"")
    record = work / "record.jsonl"
    record.unlink(missing_ok=True)
    version = board()["vivado_version"]
    args = ["--config", config, "--vivado-library", str(lib), "--out", str(work / "out"), *extra_args]
    driver = "\n".join(
        [
            f"source {tcl_quote(STUB)}",
            f"set ::orb_stub::spec {tcl_quote(stub_spec())}",
            f"set ::orb_stub::record {tcl_quote(record)}",
            f"set ::orb_stub::board_part {tcl_quote(board_part)}",
            f"set ::orb_stub::version {tcl_quote(version)}",
            f"set ::orb_stub::run_dir {tcl_quote(run_dir)}",
            "set argv [list " + " ".join(tcl_quote(a) for a in args) + "]",
            "set argc [llength $argv]",
            f"source {tcl_quote(vivado_dir / 'build.tcl')}",
            "",
        ]
    )
    (work / "driver.tcl").write_text(driver)
    proc = subprocess.run([tclsh, str(work / "driver.tcl")], capture_output=True, text=True, timeout=120)
    if proc.returncode != 0:
        raise RuntimeError(f"the build's TCL failed in the dry run:\n{proc.stderr.strip() or proc.stdout.strip()}")
    records = [json.loads(line) for line in record.read_text().splitlines() if line.strip()]
    d = Design.from_records(config, records)
    out = work / "out"
    d.outputs = {f.name: _first_line(f) for f in sorted(out.iterdir()) if f.is_file()} if out.is_dir() else {}
    return d


def _first_line(path: Path) -> str:
    with path.open("rb") as f:
        return f.readline().decode(errors="replace").strip()


# --- facts --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Entity:
    generics: dict[str, str]
    ports: dict[str, str]  # name -> direction (in/out/inout)


def read_entity(path: Path = ZYNQ_VHDL) -> Entity:
    """Generics and ports of the (one) entity of a plain VHDL file, read from its declaration."""
    text = re.sub(r"--[^\n]*", "", path.read_text())
    m = re.search(r"\bentity\s+(\w+)\s+is(.*?)\bend\s+entity", text, re.S | re.I)
    if m is None:
        raise ValueError(f"{path}: no entity declaration")
    body = m.group(2)
    gen = re.search(r"\bgeneric\s*\((.*?)\)\s*;\s*(?=port\b)", body, re.S | re.I)
    prt = re.search(r"\bport\s*\((.*)\)\s*;", body, re.S | re.I)
    if prt is None:
        raise ValueError(f"{path}: no port list")
    generics = {g.group(1): g.group(2).strip() for g in re.finditer(r"(\w+)\s*:\s*(\w+)", gen.group(1) if gen else "")}
    ports = {p.group(1): p.group(2).lower() for p in re.finditer(r"(\w+)\s*:\s*(in|out|inout)\b", prt.group(1), re.I)}
    return Entity(generics, ports)


def module_interfaces(ports: dict[str, str]) -> dict[str, list[str]]:
    """The interfaces Vivado infers on a module reference from Xilinx-style port names (UG994):
    AXI4-Lite s_axi_<name>_*, AXI4 m_axi_<name>_*, AXI4-Stream s_axis_/m_axis_<name>_*."""
    out: dict[str, list[str]] = {}
    for p in ports:
        m = re.fullmatch(r"((?:s_axi|m_axi|s_axis|m_axis)_[a-z0-9]+)_(\w+)", p)
        if m:
            out.setdefault(m.group(1), []).append(p)
    return out


def ip_facts(vlnv: str) -> dict[str, Any]:
    vendor, _, name = vlnv.split(":")[:3]
    path = FACTS / "ip" / f"{vendor}_{name}.json"
    if not path.exists():
        raise FileNotFoundError(f"no facts for {vlnv}: {path.relative_to(ROOT)} is missing")
    data: dict[str, Any] = json.loads(path.read_text())
    return data


def master_xdc() -> dict[str, dict[str, str]]:
    data = json.loads((FACTS / "zybo_z7_master_xdc.json").read_text())
    ports: dict[str, dict[str, str]] = data["ports"]
    return ports


def manifest() -> list[str]:
    lines = (line.split("#", 1)[0].strip() for line in MANIFEST.read_text().splitlines())
    return [line for line in lines if line]


def documented_vlnvs(doc: Path = BOARD_DOC) -> set[str]:
    """The VLNVs of docs/board.md's IP table (rows starting with | `vendor:library:name` |)."""
    return set(re.findall(r"^\|\s*`([\w.]+:[\w.]+:\w+)`\s*\|", doc.read_text(), re.M))


# --- checks (each returns a list of errors; empty = fine) -------------------------------------------


def _confirmed(entry: Any) -> bool:
    return not (isinstance(entry, dict) and entry.get("confirmed") is False)


def check_sources(d: Design) -> list[str]:
    errs = []
    wanted = [str(ROOT / "hdl" / rel) for rel in manifest()]
    got = [f for fs, f in d.sources if fs == "sources_1" and f.startswith(str(ROOT / "hdl"))]
    if got != wanted:
        missing = sorted(set(wanted) - set(got))
        extra = sorted(set(got) - set(wanted))
        errs.append(f"sources differ from hdl/manifest.txt (order or set): missing {missing}, extra {extra}")
    for f in got:
        if not Path(f).exists():
            errs.append(f"source {f} does not exist")
        want = "VHDL" if Path(f).stem == "orb_accel_zynq" else "VHDL 2008"
        if d.file_types.get(f) != want:
            errs.append(f"{Path(f).name}: file_type {d.file_types.get(f)!r}, want {want!r}")
    for fs, f in d.sources:
        if fs == "constrs_1" and not Path(f).exists():
            errs.append(f"constraint file {f} does not exist")
    return errs


def _pin_owner(pin: str, d: Design) -> tuple[Cell | None, str]:
    cell, _, name = pin.partition("/")
    return d.cells.get(cell), name


def check_accel(d: Design, entity: Entity | None = None) -> list[str]:
    """Every pin/interface of the module reference is a real port or inferred interface of
    orb_accel_zynq, every CONFIG is one of its generics, every port is connected."""
    ent = entity or read_entity()
    errs = []
    accel = [c for c in d.cells.values() if c.kind == "module"]
    if [c.reference for c in accel] != ["orb_accel_zynq"]:
        return [f"expected one module reference to orb_accel_zynq, got {[c.reference for c in accel]}"]
    cell = accel[0]
    intfs = module_interfaces(ent.ports)
    for k in cell.config:
        if k.removeprefix("CONFIG.") not in ent.generics:
            errs.append(f"{cell.name}: {k} is not a generic of orb_accel_zynq ({sorted(ent.generics)})")
    used_pins = {n for net in d.nets for e in net if (o := _pin_owner(e, d))[0] is cell for n in [o[1]]}
    used_intf = {n for net in d.intf_nets for e in net if (o := _pin_owner(e, d))[0] is cell for n in [o[1]]}
    for p in sorted(used_pins):
        if p not in ent.ports:
            errs.append(f"connection to {cell.name}/{p}: orb_accel_zynq has no port {p}")
    for i in sorted(used_intf):
        if i not in intfs:
            errs.append(f"interface connection to {cell.name}/{i}: orb_accel_zynq has no interface {i}")
    for pin in d.pin_props:
        c, name = _pin_owner(pin, d)
        if c is cell and name not in ent.ports:
            errs.append(f"property on {pin}: orb_accel_zynq has no port {name}")
    covered = used_pins | {p for i in used_intf for p in intfs.get(i, [])}
    if cell.config.get("CONFIG.MEM_KIND_g", "BRAM").upper() == "BRAM":
        covered |= set(intfs.get(FEAT_MASTER, []))  # the DDR master is idle in a BRAM build
    for p in sorted(set(ent.ports) - covered):
        errs.append(f"{cell.name}/{p} ({ent.ports[p]}) is not connected")
    return errs


def _names(facts: dict[str, Any], key: str) -> dict[str, Any]:
    entries: dict[str, Any] = facts.get(key, {})
    return entries


def absent_because(entry: Any, config: dict[str, str]) -> str | None:
    """The term of an entry's `when_config` (terms "(NAME == value)" joined by "and") that the
    cell's explicit CONFIG makes false, or None. Terms of another form, and names the cell does not
    set, are not judged: only what is certainly false counts."""
    cond = entry.get("when_config") if isinstance(entry, dict) else None
    for term in re.split(r"\band\b", cond or ""):
        m = re.fullmatch(r"\s*\(?\s*(\w+)\s*==\s*(\w+)\s*\)?\s*", term)
        if m and f"CONFIG.{m.group(1)}" in config and config[f"CONFIG.{m.group(1)}"].lower() != m.group(2).lower():
            return f"{m.group(1)} == {m.group(2)}"
    return None


def check_ip(d: Design) -> list[str]:
    """Every pin, interface and CONFIG property used on an IP exists in its published definition;
    values with a choice list are in it."""
    errs = []
    patched = board()["configs"][d.config].get("patched_clk_range", False)
    for cell in d.cells.values():
        if cell.kind != "ip":
            continue
        try:
            facts = ip_facts(cell.vlnv)
        except FileNotFoundError as exc:
            errs.append(str(exc))
            continue
        config = _names(facts, "config")
        for k, v in cell.config.items():
            name = k.removeprefix("CONFIG.")
            entry = config.get(name)
            if entry is None:
                errs.append(f"{cell.name} ({cell.vlnv}): CONFIG.{name} is not a property of this IP")
                continue
            if not _confirmed(entry):
                errs.append(f"{cell.name} ({cell.vlnv}): CONFIG.{name} is not confirmed by a published source")
            values = entry.get("values") if isinstance(entry, dict) else None
            if values:
                allowed = [str(x) for x in values]
                if patched and name == "kClkRange":
                    allowed += ["4", "5"]  # vivado/lib/ip_repo.tcl's build-time copy
                if str(v) not in allowed:
                    errs.append(f"{cell.name}: CONFIG.{name} = {v!r} is not one of {allowed}")
        pins, intfs = _names(facts, "pins"), _names(facts, "interfaces")
        for kind, net_list, table in (("pin", d.nets, pins), ("interface", d.intf_nets, intfs)):
            for net in net_list:
                for e in net:
                    c, name = _pin_owner(e, d)
                    if c is not cell:
                        continue
                    if name not in table:
                        errs.append(f"connection to {e}: {cell.vlnv} has no {kind} {name}")
                    elif not _confirmed(table[name]):
                        errs.append(f"connection to {e}: {kind} {name} of {cell.vlnv} is not confirmed")
                    elif (why := absent_because(table[name], cell.config)) is not None:
                        errs.append(f"connection to {e}: {kind} {name} exists only when {why}")
                    elif kind == "pin" and table[name].get("bd_pin_visible") is False:
                        via = ", ".join(table[name].get("in_interfaces", []))
                        errs.append(f"connection to {e}: pin {name} belongs to the bus interface {via}; connect that")
        for a in d.addresses:
            owner, _, rest = a["segment"].strip("/").partition("/")
            if owner != cell.name:
                continue
            intf = rest.partition("/")[0]
            if intf not in intfs:
                errs.append(f"address segment {a['segment']}: {cell.vlnv} has no interface {intf}")
            elif (why := absent_because(intfs[intf], cell.config)) is not None:
                errs.append(f"address segment {a['segment']}: interface {intf} exists only when {why}")
    return errs


def check_nets(d: Design) -> list[str]:
    """Every end of a net is a created cell pin or port; no pin is on two nets."""
    errs = []
    seen: dict[str, int] = {}
    for i, net in enumerate(d.nets + d.intf_nets):
        for e in net:
            if "/" in e:
                if e.partition("/")[0] not in d.cells:
                    errs.append(f"net end {e}: no cell {e.partition('/')[0]}")
            elif e not in d.ports and e not in d.intf_ports:
                errs.append(f"net end {e}: no such port")
            if e in seen:
                errs.append(f"{e} is on two nets")
            seen[e] = i
    for name in list(d.ports) + list(d.intf_ports):
        if name not in seen:
            errs.append(f"external port {name} is not connected")
    return errs


def check_xdc(d: Design) -> list[str]:
    """Every constrained port exists on the wrapper; every wrapper port (not the PS7's) has a pin;
    pins and I/O standards equal Digilent's master XDC."""
    errs = []
    top = d.wrapper_ports()
    master = master_xdc()
    for port in sorted(set(d.xdc_ports)):
        if port not in top:
            errs.append(f"XDC constrains port {port}, which the block design's top does not have")
    for port in sorted(top):
        if top[port].startswith("intf:"):
            errs.append(f"external interface port {port} ({top[port]}) has no pin-level name to constrain")
            continue
        props = d.xdc.get(port)
        if not props or "PACKAGE_PIN" not in props:
            errs.append(f"port {port} has no PACKAGE_PIN")
            continue
        ref = master.get(master_name(port))
        if ref is None:
            errs.append(f"port {port} is not in Digilent's Zybo Z7 master XDC")
            continue
        for prop, key in (("PACKAGE_PIN", "pin"), ("IOSTANDARD", "iostandard")):
            if props.get(prop) != ref[key]:
                errs.append(f"port {port}: {prop} {props.get(prop)} but the master XDC says {ref[key]}")
    return errs


def check_clocks(d: Design) -> list[str]:
    cfg = board()["configs"][d.config]
    errs = []
    want = f"{1000.0 / cfg['pixel_mhz']:.3f}"
    rx = [c for c in d.clocks if "port:hdmi_rx_clk_p" in c["objects"]]
    if len(rx) != 1 or rx[0]["period"] != want:
        errs.append(f"HDMI input clock: want one create_clock on hdmi_rx_clk_p at {want} ns, got {rx}")
    core = [c for c in d.cells.values() if c.vlnv.endswith(":clk_wiz")]
    if len(core) != 1 or float(core[0].config.get("CONFIG.CLKOUT1_REQUESTED_OUT_FREQ", "nan")) != cfg["core_mhz"]:
        errs.append(f"core clock: want one clk_wiz at {cfg['core_mhz']} MHz")
    if not d.clock_groups or len(d.clock_groups[0]) != 3:
        errs.append("the pixel, core and reference clock families must be declared asynchronous")
    return errs


def _segments(d: Design, space: str | None = PS_DATA_SPACE) -> list[tuple[int, int, str]]:
    """(base, range, segment) of the segments assigned in one address space (None: every space)."""
    return [(int(a["offset"], 16), int(a["range"], 16), a["segment"]) for a in d.addresses
            if space is None or a["space"].strip("/") == space]  # fmt: skip


def check_addresses(d: Design) -> list[str]:
    """In each address space no two segments overlap and each is a power of two at a multiple of
    itself; the CPU's (ps7/Data) lie in M_AXI_GP0's window and hold the accelerator at board.json's
    address. (The DDR master's space: check_feature_dma.)"""
    errs = []
    for space in sorted({a["space"].strip("/") for a in d.addresses}):
        segs = sorted(_segments(d, space))
        for (b0, r0, s0), (b1, _, s1) in itertools.pairwise(segs):
            if b0 + r0 > b1:
                errs.append(f"address segments overlap: {s0} at 0x{b0:08X}+0x{r0:X} and {s1} at 0x{b1:08X}")
        for base, size, seg in segs:
            if size & (size - 1) or base % size:
                errs.append(f"{seg}: range 0x{size:X} is not a power of two aligned at its base 0x{base:08X}")
    for base, size, seg in sorted(_segments(d)):
        if not (0x40000000 <= base and base + size <= 0x80000000):
            errs.append(f"{seg}: 0x{base:08X} is outside M_AXI_GP0's 0x40000000..0x7FFFFFFF")
    acc = board()["accel"]
    mine = [s for s in sorted(_segments(d)) if s[2].startswith(f"/{acc['cell']}/")]
    if mine != [(int(acc["base"], 16), int(acc["range"], 16), f"/{acc['cell']}/s_axi_ctrl/reg0")]:
        errs.append(f"the accelerator's segment {mine} is not vivado/board.json's {acc['base']}+{acc['range']}")
    return errs


def check_dtso(d: Design) -> list[str]:
    """The device-tree overlays of this configuration describe the recorded address segment: the
    plain one with the interrupt, the PYNQ one (docs/pynq.md) without it and without an fpga-region
    (PYNQ programs the PL itself; on its images IRQ_F2P[0] belongs to PYNQ's `fabric` node)."""
    acc = board()["accel"]
    errs = []
    segs = [s for s in _segments(d) if s[2].startswith(f"/{acc['cell']}/")]
    for name in (f"orb-accel-{d.config}.dtso", f"orb-accel-{d.config}-pynq.dtso"):
        text = (VIVADO / "linux" / name).read_text()
        reg = re.search(r"reg = <0x([0-9a-f]+) 0x([0-9a-f]+)>;", text)
        if reg is None or not segs or (int(reg.group(1), 16), int(reg.group(2), 16)) != segs[0][:2]:
            errs.append(f"{name} reg {reg and reg.groups()} differs from the address map {segs}")
    pynq = (VIVADO / "linux" / f"orb-accel-{d.config}-pynq.dtso").read_text()
    if re.search(r"^\s*(interrupts|firmware-name)\b|&fpga_full", pynq, re.M):
        errs.append(f"orb-accel-{d.config}-pynq.dtso must have neither an interrupt nor an fpga-region")
    text = (VIVADO / "linux" / f"orb-accel-{d.config}.dtso").read_text()
    errs += check_udmabuf_node(d.config, text, pynq)
    irq = re.search(r"interrupts = <0 (\d+) 4>;", text)
    accel_irq = [n for n in d.nets if f"{acc['cell']}/irq" in n]
    f2p = "ps7/IRQ_F2P"
    if irq is None or int(irq.group(1)) != 29 + acc["irq_f2p"] or not accel_irq or f2p not in accel_irq[0]:
        errs.append("the overlay's interrupt must be GIC SPI 29 + n for the accelerator's irq on IRQ_F2P[n]")
    return errs


def udmabuf_nodes(text: str) -> list[dict[str, str]]:
    """The u-dma-buf nodes of an overlay's source: property name -> value text, per node."""
    nodes = []
    for body in re.findall(r"\{([^{}]*)\}", text):
        props = dict(re.findall(r"^\s*([\w,-]+)\s*=\s*(.+?);", body, re.M))
        if props.get("compatible") == f'"{UDMABUF_COMPATIBLE}"':
            nodes.append(props)
    return nodes


def check_udmabuf_node(config: str, plain: str, pynq: str) -> list[str]:
    """A DDR build's plain overlay has one u-dma-buf node for the ring: ring_buffers x mem_depth x 64
    bytes, board.json's device name, minor number, sync mode and direction (docs/board.md, "Features to
    DDR"); PYNQ's overlay has none (PYNQ allocates with pynq.allocate); a BRAM build's has none."""
    b = board()
    cfg, dma = b["configs"][config], b.get("feat_dma", {})
    nodes, errs = udmabuf_nodes(plain), []
    if udmabuf_nodes(pynq):
        errs.append(f"orb-accel-{config}-pynq.dtso must have no u-dma-buf node (PYNQ allocates the ring itself)")
    if str(cfg.get("mem_kind", "bram")).lower() != "ddr":
        return errs + ([f"orb-accel-{config}.dtso: a u-dma-buf node in a BRAM build"] if nodes else [])
    if len(nodes) != 1:
        return [*errs, f"orb-accel-{config}.dtso: {len(nodes)} u-dma-buf nodes, want one for the ring"]
    want = {
        "size": f"<0x{dma['ring_buffers'] * cfg['mem_depth'] * 64:08x}>",
        "device-name": f'"{dma["udmabuf_name"]}"',
        "minor-number": f"<{dma['udmabuf_minor']}>",
        "sync-mode": f"<{dma['udmabuf_sync_mode']}>",
        "sync-direction": f"<{dma['udmabuf_sync_direction']}>",
    }
    errs += [f"orb-accel-{config}.dtso: u-dma-buf {k} = {nodes[0].get(k)}, want {v}"
             for k, v in want.items() if nodes[0].get(k) != v]  # fmt: skip
    return errs


def _net_of(pin: str, nets: list[list[str]]) -> list[str]:
    return next((n for n in nets if pin in n), [])


def check_feature_dma(d: Design) -> list[str]:
    """The DDR path of the feature memory (docs/board.md, "Features to DDR"). A DDR build: the
    accelerator's MEM_KIND_g, WIN_BASE_MB_g and WIN_SIZE_MB_g are vivado/board.json's; the PS7's HP port
    is enabled at 64 bits; m_axi_feat reaches it through one axi_interconnect with one slave and one
    master interface; the HP port's clock, the interconnect's clocks and the accelerator's aclk are one
    net, the interconnect's resets the core reset's; m_axi_feat's address space holds one segment, the
    HP port's DDR segment, exactly the window, and the window lies in the board's DDR. A BRAM build:
    MEM_KIND_g BRAM, no HP port, m_axi_feat unconnected, no segment in its space."""
    b = board()
    cfg, dma, acc = b["configs"][d.config], b["feat_dma"], b["accel"]["cell"]
    hp, cell = dma["hp_port"], d.cells.get(b["accel"]["cell"])
    ps7 = next((c for c in d.cells.values() if c.vlnv.endswith(":processing_system7")), None)
    if cell is None or ps7 is None:
        return ["no accelerator or no processing_system7 cell"]
    ddr = str(cfg["mem_kind"]).lower() == "ddr"
    errs = []
    want = {"MEM_KIND_g": "DDR" if ddr else "BRAM", "WIN_BASE_MB_g": str(dma["win_base_mb"]),
            "WIN_SIZE_MB_g": str(dma["win_size_mb"])}  # fmt: skip
    for k, v in want.items():
        if cell.config.get(f"CONFIG.{k}") != v:
            errs.append(f"{acc}: CONFIG.{k} = {cell.config.get(f'CONFIG.{k}')!r}, vivado/board.json wants {v!r}")
    space = f"{acc}/{FEAT_MASTER}"
    segs = [a for a in d.addresses if a["space"].strip("/") == space]
    master_net = _net_of(space, d.intf_nets)
    if not ddr:
        if ps7.config.get(f"CONFIG.PCW_USE_{hp}") == "1":
            errs.append(f"ps7: {hp} enabled in a BRAM build")
        if master_net or segs:
            errs.append(f"{space} is connected or has an address segment in a BRAM build")
        return errs
    # the HP port, 64 bits
    if ps7.config.get(f"CONFIG.PCW_USE_{hp}") != "1":
        errs.append(f"ps7: CONFIG.PCW_USE_{hp} = {ps7.config.get(f'CONFIG.PCW_USE_{hp}')!r}, want '1'")
    width = ps7.config.get(f"CONFIG.PCW_{hp}_DATA_WIDTH")
    if width != str(dma["hp_data_width"]):
        errs.append(f"ps7: CONFIG.PCW_{hp}_DATA_WIDTH = {width!r}, want {str(dma['hp_data_width'])!r}")
    # m_axi_feat -> one axi_interconnect (1 SI, 1 MI) -> ps7/<hp>
    others = [e for e in master_net if e != space]
    ic = d.cells.get(others[0].partition("/")[0]) if len(others) == 1 else None
    if ic is None or not ic.vlnv.endswith(":axi_interconnect"):
        return [*errs, f"{space} must go to one axi_interconnect's slave interface, goes to {others}"]
    if (ic.config.get("CONFIG.NUM_SI"), ic.config.get("CONFIG.NUM_MI")) != ("1", "1"):
        errs.append(f"{ic.name}: NUM_SI {ic.config.get('CONFIG.NUM_SI')}, NUM_MI {ic.config.get('CONFIG.NUM_MI')}; "
                    "want one of each (one master, one slave, no crossbar)")  # fmt: skip
    if others[0] != f"{ic.name}/S00_AXI":
        errs.append(f"{space} goes to {others[0]}, want {ic.name}/S00_AXI")
    if f"ps7/{hp}" not in _net_of(f"{ic.name}/M00_AXI", d.intf_nets):
        errs.append(f"{ic.name}/M00_AXI does not reach ps7/{hp}")
    # one clock: the accelerator's
    clock = _net_of(f"{acc}/aclk", d.nets)
    for pin in (f"ps7/{hp}_ACLK", f"{ic.name}/ACLK", f"{ic.name}/S00_ACLK", f"{ic.name}/M00_ACLK"):
        if pin not in clock:
            errs.append(f"{pin} is not on the accelerator's clock net ({clock[:1]})")
    resets = _net_of(f"{acc}/aresetn", d.nets)
    for pin in (f"{ic.name}/S00_ARESETN", f"{ic.name}/M00_ARESETN"):
        if pin not in resets:
            errs.append(f"{pin} is not on the accelerator's reset net")
    ic_reset = _net_of(f"{ic.name}/ARESETN", d.nets)
    if not any(e.endswith("/interconnect_aresetn") for e in ic_reset):
        errs.append(f"{ic.name}/ARESETN is not driven by a proc_sys_reset's interconnect_aresetn")
    # the address segment: the HP port's DDR segment, exactly the window, inside the board's DDR
    lo, size = dma["win_base_mb"] << 20, dma["win_size_mb"] << 20
    ddr_lo = int(dma["ddr_base"], 16)
    want_seg = (f"/ps7/{hp}/{dma['hp_segment']}", lo, size)
    got = [(a["segment"], int(a["offset"], 16), int(a["range"], 16)) for a in segs]
    if got != [want_seg]:
        errs.append(f"{space}: segments {got}, want exactly {want_seg} (the window WIN_BASE_MB_g, WIN_SIZE_MB_g)")
    if not (ddr_lo <= lo and lo + size <= ddr_lo + (dma["ddr_size_mb"] << 20)):
        errs.append(f"the window 0x{lo:08X}+0x{size:X} is not inside the DDR at {dma['ddr_base']}")
    return errs


def check_outputs(d: Design) -> list[str]:
    """The build leaves the bitstream and the hardware handoff side by side with one stem (PYNQ's
    Overlay("<stem>.bit") reads <stem>.hwh; docs/pynq.md), the handoff copied from where Vivado writes it
    (the stub's stand-in), and the XSA with the same stem."""
    stem = f"{board()['design_name']}_{d.config}"
    errs = [f"no {stem}{ext} in the build's output folder (found {sorted(d.outputs)})"
            for ext in (".bit", ".hwh") if f"{stem}{ext}" not in d.outputs]  # fmt: skip
    hwh = d.outputs.get(f"{stem}.hwh", "")
    if hwh and "stand-in for the hardware handoff" not in hwh:
        errs.append(f"{stem}.hwh is not the block design's hardware handoff: {hwh!r}")
    xsa = [Path(r["file"]).name for r in d.records if r["cmd"] == "write_hw_platform"]
    if xsa != [f"{stem}.xsa"]:
        errs.append(f"write_hw_platform wrote {xsa}, expected [{stem}.xsa]")
    return errs


def check_vlnvs(d: Design) -> list[str]:
    documented = documented_vlnvs()
    return [
        f"{c.name}: IP {c.vlnv} is not in docs/board.md's IP table"
        for c in d.cells.values()
        if c.kind == "ip" and c.vlnv not in documented
    ]


# the PS7 settings that are the design's own (vivado/lib/ps7.tcl orb_ps7_design_settings); every
# other PCW_* value must be the Zybo Z7-20's, as Digilent's Vivado-written HDMI demo sets it
PS7_DESIGN_KEYS = {
    "PCW_USE_M_AXI_GP0", "PCW_FPGA_FCLK0_ENABLE", "PCW_FPGA0_PERIPHERAL_FREQMHZ", "PCW_EN_CLK1_PORT",
    "PCW_FPGA_FCLK1_ENABLE", "PCW_FPGA1_PERIPHERAL_FREQMHZ", "PCW_USE_FABRIC_INTERRUPT", "PCW_IRQ_F2P_INTR",
    "PCW_USE_S_AXI_HP0", "PCW_S_AXI_HP0_DATA_WIDTH",  # DDR builds: the feature master's port
}  # fmt: skip


def check_ps7_board_values(d: Design) -> list[str]:
    """The explicit PS7 settings (no board files) equal the board's (facts: zybo_z7_20_values)."""
    ps7 = [c for c in d.cells.values() if c.vlnv.endswith(":processing_system7")]
    if len(ps7) != 1:
        return [f"expected one processing_system7, got {len(ps7)}"]
    board_values = ip_facts(ps7[0].vlnv)["zybo_z7_20_values"]["values"]
    errs = []
    for k, v in ps7[0].config.items():
        name = k.removeprefix("CONFIG.")
        if name in PS7_DESIGN_KEYS:
            continue
        if name not in board_values:
            errs.append(f"ps7: {name} is not among the Zybo Z7-20's PS7 settings")
        elif str(v) != board_values[name]:
            errs.append(f"ps7: {name} = {v!r}, the Zybo Z7-20 has {board_values[name]!r}")
    return errs


CHECKS = {
    "sources": check_sources,
    "accelerator": check_accel,
    "ip": check_ip,
    "ps7": check_ps7_board_values,
    "nets": check_nets,
    "xdc": check_xdc,
    "clocks": check_clocks,
    "addresses": check_addresses,
    "feature_dma": check_feature_dma,
    "overlay": check_dtso,
    "outputs": check_outputs,
    "vlnv": check_vlnvs,
}


def check_all(d: Design) -> dict[str, list[str]]:
    return {name: fn(d) for name, fn in CHECKS.items()}


# --- the table of docs/board.md ---------------------------------------------------------------------


def _settings(c: Cell) -> str:
    """A cell's CONFIG settings for the table (the PS7's design settings only)."""
    items = [(k.removeprefix("CONFIG."), v) for k, v in c.config.items()]
    if c.vlnv.endswith("processing_system7"):
        keys = ("FPGA", "GP0", "HP0", "IRQ", "FABRIC", "CLK1")
        items = [(k, v) for k, v in items if any(s in k for s in keys)]
        return ", ".join(f"{k}={v}" for k, v in items) + " (and the board's DDR/MIO settings)"
    return ", ".join(f"{k}={v}" for k, v in items)


def table(d: Design) -> str:
    """Cells, clocks, address map, external ports of one dry run, as Markdown."""
    lines = [f"Dry run of `{d.config}` (`python3 -m orb_flow.board.dryrun --table --config {d.config}`):", ""]
    lines += ["| cell | IP | settings |", "|---|---|---|"]
    for c in d.cells.values():
        what = c.vlnv or f"module reference {c.reference}"
        lines.append(f"| {c.name} | `{what}` | {_settings(c)} |")
    lines += ["", "| clock (driver) | loads |", "|---|---|"]
    for net in d.nets:
        if net[0].endswith(("FCLK_CLK0", "FCLK_CLK1", "clk_out1", "PixelClk")):
            lines.append(f"| {net[0]} | {', '.join(net[1:])} |")
    lines += ["", "| address space | address segment | base | range |", "|---|---|---|---|"]
    lines += [f"| {a['space']} | {a['segment']} | {a['offset']} | {a['range']} |" for a in d.addresses]
    lines += ["", "| external port | direction | package pin |", "|---|---|---|"]
    for name, direction in d.wrapper_ports().items():
        lines.append(f"| {name} | {direction} | {d.xdc.get(name, {}).get('PACKAGE_PIN', '')} |")
    lines += [f"| {name} | PS7 interface | fixed (MIO/DDR) |" for name in PS_PORTS]
    return "\n".join(lines) + "\n"


DOC_BEGIN = "<!-- dry-run table: sw/orb_flow/board/dryrun.py --update-doc writes this section -->"
DOC_END = "<!-- end of the dry-run table -->"


def doc_table() -> str:
    """The docs/board.md section: the default configuration's dry run without board files."""
    with tempfile.TemporaryDirectory() as tmp:
        return table(run(board()["default_config"], Path(tmp)))


def doc_section(doc: str) -> str:
    """The text between docs/board.md's dry-run markers (ValueError if they are missing)."""
    i, j = doc.find(DOC_BEGIN), doc.find(DOC_END)
    if i < 0 or j < i:
        raise ValueError(f"docs/board.md lacks the markers {DOC_BEGIN!r} ... {DOC_END!r}")
    return doc[i + len(DOC_BEGIN) : j].strip("\n") + "\n"


def update_doc(path: Path = BOARD_DOC) -> None:
    doc = path.read_text()
    doc_section(doc)  # the markers are there
    head, _, rest = doc.partition(DOC_BEGIN)
    _, _, tail = rest.partition(DOC_END)
    path.write_text(f"{head}{DOC_BEGIN}\n{doc_table()}{DOC_END}{tail}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--config", action="append", help="configuration(s) (default: all of vivado/board.json)")
    ap.add_argument("--board-files", action="store_true", help="dry-run as if Digilent's board files were found")
    ap.add_argument("--table", action="store_true", help="print the block-design table of docs/board.md")
    ap.add_argument("--update-doc", action="store_true", help="rewrite the dry-run table of docs/board.md")
    args = ap.parse_args(argv)
    if args.update_doc:
        update_doc()
        print(f"wrote the dry-run table of {BOARD_DOC.relative_to(ROOT)}")
        return 0
    try:
        configs = [config_key(board(), c) for c in args.config] if args.config else list(board()["configs"])
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    part = board()["vivado_boards"]["board_part"] if args.board_files else ""
    failed = 0
    for cfg in configs:
        with tempfile.TemporaryDirectory() as tmp:
            try:
                d = run(cfg, Path(tmp), board_part=part)
            except RuntimeError as exc:
                print(f"{cfg}: {exc}", file=sys.stderr)
                failed += 1
                continue
            results = check_all(d)  # while the build's files (the timing XDC) exist
        if args.table:
            print(table(d))
        for name, errs in results.items():
            for e in errs:
                print(f"{cfg}: {name}: {e}", file=sys.stderr)
            failed += bool(errs)
        print(f"{cfg}: {len(d.cells)} cells, {len(d.nets)} nets, {len(d.intf_nets)} interface nets, "
              f"{len(d.addresses)} address segment(s), {len(d.xdc)} constrained ports")  # fmt: skip
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
