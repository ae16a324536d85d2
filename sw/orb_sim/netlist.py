# SPDX-License-Identifier: MIT
"""Netlist simulation support (docs/netlist-sim.md): `ghdl synth --out=vhdl` of a toplevel with
its generics, and the text fix-ups that make GHDL 2.0's netlist simulable as the hardware behaves.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .hdl import find_entity, sources


def _strip_vhdl(text: str) -> str:
    """VHDL text without comments, lower case, whitespace removed (for comparing declarations)."""
    return re.sub(r"\s+", "", re.sub(r"--[^\n]*", "", text)).lower()


def _clause(text: str, entity: str, keyword: str) -> str | None:
    """The stripped `generic (...)` or `port (...)` list of `entity` in VHDL `text`, or None."""
    flat = _strip_vhdl(text)
    m = re.search(rf"entity{entity.lower()}is(.*?)end(?:entity)?(?:{entity.lower()})?;", flat)
    if m is None:
        return None
    body = m.group(1)
    start = body.find(f"{keyword}(")
    if start < 0:
        return ""
    first = start + len(keyword)  # the opening parenthesis
    depth = 0
    for i in range(first, len(body)):
        depth += {"(": 1, ")": -1}.get(body[i], 0)
        if depth == 0:
            return body[first + 1 : i]
    return None


def _decls(clause: str) -> dict[str, str]:
    """name -> stripped `mode type` (ports) or `type:=default` (generics) of a stripped clause."""
    out: dict[str, str] = {}
    for decl in clause.split(";"):
        names, _, rest = decl.partition(":")
        for name in names.split(","):
            if name:
                out[name] = rest
    return out


def check_netlist_interface(toplevel: str, netlist_text: str, generics: Mapping[str, int | str]) -> list[str]:
    """Differences between the ports of `toplevel` in the RTL and in its netlist (name, mode, type,
    compared as declared text), and generics whose netlist default is not the synthesised value."""
    try:
        rtl = find_entity(toplevel).path.read_text()
    except ValueError as exc:
        return [str(exc)]
    problems: list[str] = []
    rtl_ports, net_ports = _clause(rtl, toplevel, "port"), _clause(netlist_text, toplevel, "port")
    if net_ports is None or rtl_ports is None:
        return [f"no port clause of {toplevel} found in the {'netlist' if net_ports is None else 'RTL'}"]
    want, got = _decls(rtl_ports), _decls(net_ports)
    for name in want.keys() - got.keys():
        problems.append(f"port {name} missing in the netlist")
    for name in got.keys() - want.keys():
        problems.append(f"port {name} only in the netlist")
    for name in want.keys() & got.keys():
        if want[name] != got[name]:
            problems.append(f"port {name}: RTL '{want[name]}', netlist '{got[name]}'")
    net_generics = _decls(_clause(netlist_text, toplevel, "generic") or "")
    for name, value in generics.items():
        default = net_generics.get(name.lower(), "").partition(":=")[2]
        expected = f'"{value}"'.lower() if isinstance(value, str) else str(value)
        if default != expected:
            problems.append(f"generic {name}: netlist default '{default}', synthesised with '{expected}'")
    return problems


_ARRAY_TYPE = re.compile(r"^\s*type (\w+) is array \(0 to (\d+)\)\s+of ([^;]+);", re.M)
_ARRAY_VAR = re.compile(r"^\s*variable (\w+) : (\w+)\b", re.M)
_UNINIT_VAR = re.compile(r"^(\s*variable \w+ : (\w+_type));$", re.M)
_ASYNC_READ = re.compile(r"^(\s*)(\w+) <= (\w+)\(to_integer \(unsigned \((\w+)\)\)\);$", re.M)


def fix_memories(netlist_text: str, zero_init: bool = True) -> tuple[str, int, int]:
    """GHDL's netlist with its memories made simulable as the hardware behaves; returns the text,
    the number of reads guarded and the number of memories given an initial value.

    1. Out-of-range reads.
    GHDL writes every inferred RAM/ROM as a process whose read `data <= mem(to_integer(unsigned(
    addr)));` runs whenever the address changes, the output register being a separate process.
    When the depth is not a power of two, a delta-cycle glitch of the address (or a value of a
    clock where the RTL's read is not enabled) beyond the last word stops GHDL with "index out of
    bounds", where the RTL only indexes the memory at enabled clock edges. Such a read now gives
    all 'X' instead (as undefined as the hardware's): a value that is sampled still shows.
    2. (zero_init) Memories without an initial value (the RTL gives none, e.g. orb_overlay's
    bitmaps) start all '0', as 7-series block and distributed RAM do (INIT defaults to 0). Their
    'U' words are harmless in the RTL (`if bit = '1'` is false) but not in the netlist, where GHDL
    writes the same choice as a multiplexer `a when bit = '0' else b` that takes b for 'U'."""
    reads = inits = 0
    out: list[str] = []
    for chunk in re.split(r"(?m)(?=^\s*process\b)", netlist_text):  # memory types are local to a process
        types = {m.group(1): m.group(3).strip() for m in _ARRAY_TYPE.finditer(chunk)}
        elems = {m.group(1): types[m.group(2)] for m in _ARRAY_VAR.finditer(chunk) if m.group(2) in types}
        if zero_init:
            for m in _UNINIT_VAR.finditer(chunk):
                if m.group(2) in types:
                    zero = "'0'" if types[m.group(2)] == "std_logic" else "(others => '0')"
                    chunk = chunk.replace(m.group(0), f"{m.group(1)} := (others => {zero});", 1)
                    inits += 1
        pos = 0
        for m in _ASYNC_READ.finditer(chunk):
            indent, target, mem, addr = m.groups()
            if mem not in elems:
                continue
            undefined = "'X'" if elems[mem] == "std_logic" else "(others => 'X')"
            out += [
                chunk[pos : m.start()],
                f"{indent}if to_integer (unsigned ({addr})) <= {mem}'high then\n",
                f"{indent}  {m.group(0).strip()}\n",
                f"{indent}else\n{indent}  {target} <= {undefined};\n{indent}end if;",
            ]
            pos = m.end()
            reads += 1
        out.append(chunk[pos:])
    return "".join(out), reads, inits


_SELF_ASSIGN = re.compile(r"^\s*(\w+) <= \1; -- \(signal\)\n", re.M)


def merge_duplicate_signals(netlist_text: str) -> tuple[str, list[str]]:
    """Netlist without GHDL 2.0's duplicate net names; returns the text and the names merged.

    GHDL names the net of an instance's output `<instance>_<port>`. When the RTL has a signal of
    that very name connected to that output (orb_accel_top: `mem_frame_done` on `mem.frame_done`),
    the writer declares `signal mem_frame_done` twice in one architecture and adds
    `mem_frame_done <= mem_frame_done;` (GHDL rejects the file; the Verilog output has the same
    two `wire`s and `assign`, which yosys accepts). Both names stand for the same net, so the
    second declaration and the self-assignment are dropped."""
    merged: list[str] = []
    out: list[str] = []
    for chunk in re.split(r"(?m)(?=^architecture\b)", netlist_text):
        for m in list(_SELF_ASSIGN.finditer(chunk)):
            name = m.group(1)
            decls = list(re.finditer(rf"(?m)^\s*signal {name} : [^;]+;\n", chunk))
            if len(decls) < 2 or len({d.group(0) for d in decls}) != 1:
                continue
            chunk = chunk.replace(m.group(0), "", 1)
            first = chunk.index(decls[0].group(0)) + len(decls[0].group(0))
            chunk = chunk[:first] + chunk[first:].replace(decls[0].group(0), "")
            merged.append(name)
        out.append(chunk)
    return "".join(out), merged


def synth_netlist(toplevel: str, generics: Mapping[str, int | str], build_dir: Path) -> tuple[Path, dict[str, Any]]:
    """`ghdl synth --out=vhdl` of `toplevel` with `generics` into build_dir/<toplevel>.ghdl.vhd
    (GHDL's output as is) and build_dir/<toplevel>.netlist.vhd (the same after fix_memories and
    merge_duplicate_signals, unless ORB_NETLIST_RAW=1), the file that is simulated.

    Returns the netlist and a record (size, synthesis time, interface check) also written to
    build_dir/netlist.json and, when ORB_NETLIST_REPORT names a file, appended to it as a JSON line."""
    build_dir.mkdir(parents=True, exist_ok=True)
    raw = build_dir / f"{toplevel}.ghdl.vhd"
    netlist = build_dir / f"{toplevel}.netlist.vhd"
    log = build_dir / "ghdl_synth.log"
    cmd = [
        "ghdl",
        "synth",
        "--std=08",
        *(f"-g{k}={v}" for k, v in generics.items()),
        "--out=vhdl",
        *(str(p) for p in sources()),
        "-e",
        toplevel,
    ]
    t0 = time.perf_counter()
    with raw.open("w") as out, log.open("w") as err:
        rc = subprocess.run(cmd, stdout=out, stderr=err, cwd=build_dir, check=False).returncode
    seconds = time.perf_counter() - t0
    if rc != 0:
        tail = "\n".join(log.read_text().splitlines()[-15:])
        raise RuntimeError(f"ghdl synth of {toplevel} failed (exit {rc}; {log}):\n{tail}")
    text = raw.read_text()
    # ORB_NETLIST_RAW=1: simulate GHDL's output as is (no fix-ups)
    raw_only = os.environ.get("ORB_NETLIST_RAW", "") not in ("", "0")
    fixed, reads, inits = (text, 0, 0) if raw_only else fix_memories(text)
    fixed, merged = (fixed, []) if raw_only else merge_duplicate_signals(fixed)
    netlist.write_text(fixed)
    record: dict[str, Any] = {
        "toplevel": toplevel,
        "generics": dict(generics),
        "netlist": str(netlist),
        "bytes": len(text.encode()),
        "lines": text.count("\n"),
        "instances": len(re.findall(r"(?m)^\s*\w+\s*:\s*entity\s", text)),
        "signals": len(re.findall(r"(?m)^\s*signal\s", text)),
        "memories": len(re.findall(r"(?m)^\s*variable \w+ : \w+_type\b", text)),
        "guarded_reads": reads,
        "zero_initialised_memories": inits,
        "merged_duplicate_signals": merged,
        "synth_s": round(seconds, 2),
        "interface_problems": check_netlist_interface(toplevel, text, generics),
    }
    (build_dir / "netlist.json").write_text(json.dumps(record, indent=2) + "\n")
    report = os.environ.get("ORB_NETLIST_REPORT")
    if report:
        with open(report, "a") as f:
            f.write(json.dumps(record) + "\n")
    return netlist, record
