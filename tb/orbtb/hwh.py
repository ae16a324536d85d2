# SPDX-License-Identifier: MIT
"""A hardware handoff (.hwh) for the PYNQ checks (tb/pynq), written from a dry run of the board's
block design (orb_flow.board.dryrun): the part of Vivado's file that PYNQ reads, in the layout of
the public .hwh files vivado/facts/ was extracted from. Not Vivado's file: nothing here has run in
Vivado (docs/pynq.md says what that leaves open).

What it holds, all from the dry run's record or the VHDL:
- SYSTEMINFO: the block design's name and the part;
- the processing_system7 cell with its recorded PCW_* settings, the PL clocks' divisors (from the
  requested frequencies and a 1,000 MHz IO PLL: Vivado's own choice may differ), the address map
  (one MEMRANGE per assign_bd_address in the PS's address space ps7/Data, through the PS's master
  interface), IRQ_F2P connected to what the record connects it to, and each slave port a fabric
  master reaches (a DDR build: S_AXI_HP0) as a SLAVE bus interface;
- each module reference (the accelerator) with Vivado's module-reference VLNV
  (xilinx.com:module_ref:<entity>:1.0), its CONFIG generics as parameters, every port of the
  entity (read from the VHDL), the interfaces Vivado infers from their names (m_axi_feat a MASTER
  aximm interface) and, for a master with an address space, its MEMORYMAP: one MEMRANGE per
  assign_bd_address in that space (a DDR build: HP0_DDR_LOWOCM of ps7 through S_AXI_HP0, MEMTYPE
  MEMORY, as a public Vivado .hwh writes a DMA master's view of DDR: pynqmetadata's test design
  resizer.hwh, an axi_dma on S_AXI_HP0 of a Zynq-7000);
- no other cell (the video IP, the interconnects, the resets): PYNQ reads cells through the PS's
  address map and interrupt pins, and the accelerator is the only one either reaches (its DDR
  master's bus interface names a bus, feat_ic's, whose interconnect is not written).

Standard library only (it runs in .venv-pynq too).
"""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from pathlib import Path

from orb_flow.board.dryrun import FACTS, Design, Entity, board, module_interfaces, read_entity

IO_PLL_MHZ = 1000.0  # the PS's IO PLL the PL clocks divide (the Zybo Z7's 33.333 MHz x 30)
PL_CLOCKS = 4


def _version(vlnv: str) -> str:
    """The one version of an IP that vivado/facts/ip/ has seen (the .hwh's VLNVs carry one)."""
    vendor, _, name = vlnv.split(":")[:3]
    seen = json.loads((FACTS / "ip" / f"{vendor}_{name}.json").read_text())["versions_seen"]
    if len(seen) != 1:
        raise ValueError(f"{vlnv}: versions seen {sorted(seen)}, expected one")
    return next(iter(seen))


def _divisors(mhz: float) -> tuple[int, int]:
    div = round(IO_PLL_MHZ / mhz)
    if not 1 <= div <= 63:
        raise ValueError(f"{mhz} MHz is not reachable from the {IO_PLL_MHZ} MHz IO PLL with one divisor")
    return div, 1


def _params(parent: ET.Element, params: dict[str, str]) -> None:
    el = ET.SubElement(parent, "PARAMETERS")
    for name, value in params.items():
        ET.SubElement(el, "PARAMETER", NAME=name, VALUE=value)


def _connections(port: ET.Element, peers: list[str]) -> None:
    if peers:
        conns = ET.SubElement(port, "CONNECTIONS")
        for peer in peers:
            cell, _, pin = peer.partition("/")
            ET.SubElement(conns, "CONNECTION", INSTANCE=cell, PORT=pin)


def _peers(d: Design, pin: str, written: set[str]) -> list[str]:
    """The pins on `pin`'s net that the .hwh has."""
    return [e for net in d.nets if pin in net for e in net if e != pin and e in written]


def render(d: Design, entity: Entity | None = None) -> str:
    """The .hwh text of the dry run `d` (entity: the accelerator's ports, read from the VHDL)."""
    ent = entity or read_entity()
    b = board()
    part = re.fullmatch(r"xc(\w+?)(clg\d+)(-\d)", b["part"])
    if part is None:
        raise ValueError(f"part {b['part']!r} is not xc<device><package>-<speed>")
    bd = next(r["name"] for r in d.records if r["cmd"] == "create_bd_design")
    root = ET.Element("EDKSYSTEM", EDWVERSION="1.2", VIVADOVERSION=b["vivado_version"])
    ET.SubElement(root, "SYSTEMINFO", ARCH="zynq", DEVICE=part[1], NAME=bd, PACKAGE=part[2], SPEEDGRADE=part[3])
    ET.SubElement(root, "EXTERNALPORTS")
    ET.SubElement(root, "EXTERNALINTERFACES")
    modules = ET.SubElement(root, "MODULES")

    ps = next(c for c in d.cells.values() if c.vlnv.endswith(":processing_system7"))
    refs = [c for c in d.cells.values() if c.kind == "module"]
    written = {f"{ps.name}/IRQ_F2P"} | {f"{c.name}/{p}" for c in refs for p in ent.ports}
    masters = sorted({e.split("/")[1] for net in d.intf_nets for e in net if e.startswith(f"{ps.name}/M_AXI_")})
    slaves = sorted({e.split("/")[1] for net in d.intf_nets for e in net if e.startswith(f"{ps.name}/S_AXI_")})
    if len(masters) != 1:
        raise ValueError(f"{ps.name}: expected one master interface in use, found {masters}")
    params = {k.removeprefix("CONFIG."): v for k, v in ps.config.items()}
    for i in range(PL_CLOCKS):
        params.setdefault(f"PCW_FPGA_FCLK{i}_ENABLE", "0")
        d0, d1 = _divisors(float(params.get(f"PCW_FPGA{i}_PERIPHERAL_FREQMHZ", "100")))
        params |= {f"PCW_FCLK{i}_PERIPHERAL_DIVISOR0": str(d0), f"PCW_FCLK{i}_PERIPHERAL_DIVISOR1": str(d1),
                   f"PCW_FCLK{i}_PERIPHERAL_CLKSRC": "IO PLL"}  # fmt: skip
    mod = ET.SubElement(modules, "MODULE", FULLNAME=f"/{ps.name}", INSTANCE=ps.name, IS_PL="FALSE",
                        MODTYPE="processing_system7", VLNV=f"{ps.vlnv}:{_version(ps.vlnv)}")  # fmt: skip
    _params(mod, params)
    memmap = ET.SubElement(mod, "MEMORYMAP")
    for a in d.addresses:
        if a["space"].strip("/") != f"{ps.name}/Data":
            continue  # a fabric master's view (below, in its module)
        cell, intf, block = a["segment"].strip("/").split("/")
        base, size = int(a["offset"], 16), int(a["range"], 16)
        ET.SubElement(memmap, "MEMRANGE", ADDRESSBLOCK=block, BASENAME="C_BASEADDR", BASEVALUE=f"0x{base:08X}",
                      HIGHNAME="C_HIGHADDR", HIGHVALUE=f"0x{base + size - 1:08X}", INSTANCE=cell, IS_DATA="TRUE",
                      IS_INSTRUCTION="TRUE", MASTERBUSINTERFACE=masters[0], MEMTYPE="REGISTER",
                      SLAVEBUSINTERFACE=intf)  # fmt: skip
    ports = ET.SubElement(mod, "PORTS")
    irq = ET.SubElement(ports, "PORT", DIR="I", LEFT="0", NAME="IRQ_F2P", RIGHT="0", SIGIS="INTERRUPT")
    _connections(irq, _peers(d, f"{ps.name}/IRQ_F2P", written))
    ET.SubElement(ports, "PORT", DIR="O", LEFT="31", NAME=f"{masters[0]}_ARADDR", RIGHT="0", SIGIS="undef")
    intfs = ET.SubElement(mod, "BUSINTERFACES")
    bus = ET.SubElement(intfs, "BUSINTERFACE", BUSNAME=f"{ps.name}_{masters[0]}", NAME=masters[0], TYPE="MASTER",
                        VLNV="xilinx.com:interface:aximm:1.0")  # fmt: skip
    maps = ET.SubElement(bus, "PORTMAPS")
    ET.SubElement(maps, "PORTMAP", LEFT="31", LOGICAL="ARADDR", PHYSICAL=f"{masters[0]}_ARADDR", RIGHT="0")
    for slave in slaves:  # the bus is the interconnect's master interface on that net
        peer = next(e for net in d.intf_nets if f"{ps.name}/{slave}" in net for e in net if e != f"{ps.name}/{slave}")
        ET.SubElement(ports, "PORT", DIR="I", LEFT="31", NAME=f"{slave}_AWADDR", RIGHT="0", SIGIS="undef")
        bus = ET.SubElement(intfs, "BUSINTERFACE", BUSNAME=peer.replace("/", "_"), NAME=slave, TYPE="SLAVE",
                            VLNV="xilinx.com:interface:aximm:1.0")  # fmt: skip
        maps = ET.SubElement(bus, "PORTMAPS")
        ET.SubElement(maps, "PORTMAP", LEFT="31", LOGICAL="AWADDR", PHYSICAL=f"{slave}_AWADDR", RIGHT="0")

    for cell in refs:
        vlnv = f"xilinx.com:module_ref:{cell.reference}:1.0"
        mod = ET.SubElement(modules, "MODULE", FULLNAME=f"/{cell.name}", HWVERSION="1.0", INSTANCE=cell.name,
                            IPTYPE="PERIPHERAL", IS_ENABLE="1", MODCLASS="PERIPHERAL", MODTYPE=cell.reference,
                            VLNV=vlnv)  # fmt: skip
        _params(mod, {k.removeprefix("CONFIG."): v for k, v in cell.config.items()})
        views = [a for a in d.addresses if a["space"].strip("/").startswith(f"{cell.name}/")]
        if views:
            memmap = ET.SubElement(mod, "MEMORYMAP")
            for a in views:
                target, intf, block = a["segment"].strip("/").split("/")
                base, size = int(a["offset"], 16), int(a["range"], 16)
                ET.SubElement(memmap, "MEMRANGE", ADDRESSBLOCK=block, BASENAME="C_BASEADDR",
                              BASEVALUE=f"0x{base:08X}", HIGHNAME="C_HIGHADDR", HIGHVALUE=f"0x{base + size - 1:08X}",
                              INSTANCE=target, IS_DATA="TRUE", IS_INSTRUCTION="TRUE",
                              MASTERBUSINTERFACE=a["space"].strip("/").split("/")[1], MEMTYPE="MEMORY",
                              SLAVEBUSINTERFACE=intf)  # fmt: skip
        ports = ET.SubElement(mod, "PORTS")
        for name, direction in ent.ports.items():
            port = ET.SubElement(ports, "PORT", DIR={"in": "I", "out": "O"}.get(direction, "IO"), NAME=name,
                                 SIGIS="INTERRUPT" if name == "irq" else "undef")  # fmt: skip
            _connections(port, _peers(d, f"{cell.name}/{name}", written))
        intfs = ET.SubElement(mod, "BUSINTERFACES")
        for intf, members in sorted(module_interfaces(ent.ports).items()):
            kind = "aximm" if intf.startswith(("s_axi_", "m_axi_")) else "axis"
            bus = ET.SubElement(intfs, "BUSINTERFACE", BUSNAME=f"{cell.name}_{intf}", NAME=intf,
                                TYPE="MASTER" if intf.startswith("m_") else "SLAVE",
                                VLNV=f"xilinx.com:interface:{kind}:1.0")  # fmt: skip
            maps = ET.SubElement(bus, "PORTMAPS")
            for m in members:
                ET.SubElement(maps, "PORTMAP", LOGICAL=m.removeprefix(f"{intf}_").upper(), PHYSICAL=m)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write(d: Design, path: Path) -> Path:
    path.write_text(render(d))
    return path
