# SPDX-License-Identifier: MIT
"""GHDL's synthesised Verilog of a top (`ghdl synth --out=verilog`), repaired where GHDL 2.0's
Verilog writer prints something that is not Verilog. One implementation for the two readers: the
yosys estimate (sw/orb_flow/synth.py, docs/synthesis.md) and the fast simulation in Verilator
(orb_sim.fast, docs/fast-sim.md).

Repairs, each recorded in the returned record's "workarounds":
  - `abs` printed as VHDL (`x <= std_logic_vector(abs $signed(y));`) -> `assign x = ($signed(y) <
    0) ? -y : y;`;
  - zero-width nets printed as `""` / `0'b...` -> dropped from the concatenations that use them;
  - a constant of more than 32 bits printed in VHDL's quotes (`n237_o = n235_o + "00...010000000000";`,
    which Verilog reads as an ASCII string: 8 bits a character) -> the sized binary literal
    `37'b00...010000000000` (orb_feat_dma's 37-bit window and buffer constants);
  - a signal named like an instance's port wire (signal `mem_frame_done` beside port `frame_done`
    of instance `mem`) declared twice with `assign x = x;` -> one declaration, no self-assignment
    (the two are the same net; Verilator refuses the duplicate, yosys merged it silently);
top.ghdl.v is GHDL's raw output, top.v the repaired file.
"""

from __future__ import annotations

import re
import subprocess
import time
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from .hdl import ROOT


class VerilogError(RuntimeError):
    """GHDL failed, or its Verilog could not be repaired safely."""


ABS_RE = re.compile(r"^(\s*)(\w+) <= std_logic_vector\(abs \$signed\((\w+)\)\);", re.M)
QUOTED_BITS_RE = re.compile(r'"([01]+)"')  # a bit-string constant in VHDL's quotes: not Verilog
RAM_NOTE_RE = re.compile(r"^(\S+?):(\d+):\d+:note: found (RAM|ROM) \"([\w.]+)\", width: (\d+) bits, depth: (\d+)", re.M)


def ghdl_verilog(ghdl: str, top: str, generics: Mapping[str, int | str], files: Sequence[Path], cdir: Path,
                 rec: dict[str, Any]) -> Path:  # fmt: skip
    """GHDL -> cdir/top.ghdl.v (raw) and cdir/top.v (repaired; returned). Fills rec: ghdl_cmd,
    wall_s.ghdl, workarounds (appended), ghdl_rams, ghdl_warnings."""
    rec.setdefault("workarounds", [])
    rec.setdefault("wall_s", {})

    def run(srcs: Iterable[Path]) -> subprocess.CompletedProcess[str]:
        cmd = [ghdl, "synth", "--std=08"]
        cmd += [f"-g{k}={v}" for k, v in generics.items()]
        cmd += ["--out=verilog", *map(str, srcs), "-e", top]
        rec["ghdl_cmd"] = " ".join(cmd).replace(str(ROOT) + "/", "")
        return subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=cdir)

    t0 = time.monotonic()
    proc = run(files)
    rec["wall_s"]["ghdl"] = round(time.monotonic() - t0, 1)
    (cdir / "ghdl.log").write_text(proc.stderr)
    (cdir / "top.ghdl.v").write_text(proc.stdout)
    if proc.returncode != 0:
        last = [ln for ln in proc.stderr.splitlines() if ln.strip()][-3:]
        raise VerilogError(f"ghdl synth failed (exit {proc.returncode}): " + " | ".join(last))
    rec["ghdl_rams"] = [
        {"file": Path(m[0]).name, "line": int(m[1]), "kind": m[2], "name": m[3], "width": int(m[4]), "depth": int(m[5])}
        for m in RAM_NOTE_RE.findall(proc.stderr)
    ]
    rec["ghdl_warnings"] = [ln for ln in proc.stderr.splitlines() if ":warning:" in ln]
    verilog = repair(proc.stdout, rec["workarounds"])
    out = cdir / "top.v"
    out.write_text(verilog)
    return out


def repair(verilog: str, workarounds: list[str]) -> str:
    """The Verilog repairs of the module docstring, each one that applied noted in `workarounds`."""
    verilog, n_abs = ABS_RE.subn(r"\1assign \2 = ($signed(\3) < 0) ? -\3 : \3;  // was VHDL 'abs'", verilog)
    if n_abs:
        workarounds.append(f"GHDL 2.0 Verilog writer emitted VHDL 'abs' in {n_abs} lines; rewritten as Verilog")
    verilog, n_quoted = QUOTED_BITS_RE.subn(lambda m: f"{len(m[1])}'b{m[1]}", verilog)
    if n_quoted:
        workarounds.append(
            f"GHDL 2.0 Verilog writer printed {n_quoted} constants in VHDL's quotes (a string in Verilog); "
            "rewritten as sized binary literals"
        )
    verilog, n_zero = drop_zero_width(verilog)
    if n_zero:
        workarounds.append(
            f'GHDL 2.0 Verilog writer printed {n_zero} zero-width nets as invalid Verilog ("", 0\'b); removed them'
        )
    verilog, n_dup = merge_duplicate_nets(verilog)
    if n_dup:
        workarounds.append(
            f"GHDL 2.0 Verilog writer declared {n_dup} net(s) twice (a signal named like an instance's port wire) "
            "with a self-assignment; one declaration kept"
        )
    leftover = [ln for ln in verilog.splitlines() if "std_logic" in ln and not ln.lstrip().startswith(("/*", "//"))]
    if leftover:
        raise VerilogError(f"GHDL's Verilog still has VHDL in it (unhandled writer bug): {leftover[0].strip()}")
    return verilog


def merge_duplicate_nets(verilog: str) -> tuple[str, int]:
    """Drop the second `wire x;` of a module that also has `assign x = x;`, and that assignment.
    Any other duplicate declaration is left for the reader to refuse."""
    out, merged = [], 0
    for mod in re.split(r"(?=^module )", verilog, flags=re.M):
        selfs = set(re.findall(r"^\s*assign (\w+) = \1;", mod, re.M))
        if not selfs:
            out.append(mod)
            continue
        seen: set[str] = set()
        lines = []
        for line in mod.split("\n"):
            m = re.match(r"^\s*wire (?:\[[^\]]*\] )?(\w+);", line)
            if m and m[1] in selfs:
                if m[1] in seen:
                    merged += 1
                    continue
                seen.add(m[1])
            if re.match(r"^\s*assign (\w+) = \1;", line):
                continue
            lines.append(line)
        out.append("\n".join(lines))
    return "".join(out), merged


def drop_zero_width(verilog: str) -> tuple[str, int]:
    """Remove the zero-width nets GHDL 2.0 writes as `assign n = "";` / `assign m = 0'b - n;`.

    A zero-width value contributes nothing, so it is dropped from the concatenations that use it;
    any other use is an error (the Verilog could not be repaired safely)."""
    zero: set[str] = set()
    for m in re.finditer(r"^\s*assign (\w+) = (.*);", verilog, re.M):
        if m[2].strip() == '""' or re.search(r"(?<![\w'])0'[bdh]", m[2]):
            zero.add(m[1])
    if not zero:
        return verilog, 0
    name_re = re.compile(r"\b(" + "|".join(sorted(zero)) + r")\b")
    out = []
    for line in verilog.splitlines():
        m = re.match(r"^\s*(?:wire|assign)\s+(\w+)\s*[;=]", line)
        if m and m[1] in zero:
            continue
        if name_re.search(line) and not line.lstrip().startswith(("/*", "//")):

            def strip_concat(c: re.Match) -> str:
                parts = [p for p in c[1].split(",") if p.strip() not in zero]
                return "{" + ",".join(parts).strip() + "}"

            line = re.sub(r"\{([^{}]*)\}", strip_concat, line)
            if name_re.search(line.split("//")[0]):
                raise VerilogError(f"GHDL's Verilog uses a zero-width net outside a concatenation: {line.strip()}")
        out.append(line)
    return "\n".join(out) + "\n", len(zero)


RUNNING: set[subprocess.Popen[bytes]] = set()
