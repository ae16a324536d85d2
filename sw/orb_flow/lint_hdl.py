#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""HDL lint for hdl/: GHDL analysis and synthesis check, and the vsg style check.

1. `ghdl -a --std=08` of every hdl/*.vhd (in sw/orb_sim/runner.py's dependency order; a file missing
   from that list is reported, since the testbenches and sw/orb_flow/synth.py would not see it);
2. `ghdl synth --std=08 --out=none` of every entity on its own, with its default generics
   (packages are only analysed); fails on errors and on GHDL crashes, reports warnings;
3. vsg with the repository's vsg.yaml over every file, all phases (-ap).
Exit status 1 if any check failed. Usage: python3 -m orb_flow.lint_hdl [--no-ghdl] [--no-vsg]
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
from pathlib import Path

from orb_sim.hdl import HDL, sources  # the one list of hdl files (hdl/manifest.txt)

ROOT = Path(__file__).resolve().parents[2]

WORK = ROOT / "build" / "lint"
VSG = ROOT / ".venv" / "bin" / "vsg"
VSG_CONFIG = ROOT / "vsg.yaml"
ENTITY_RE = re.compile(r"^\s*entity\s+(\w+)\s+is\b", re.M | re.I)
RAM_NOTE_RE = re.compile(r"note: found (RAM|ROM) \"([\w.]+)\", width: (\d+) bits, depth: (\d+)")


def rel(p: Path | str) -> str:
    return str(p).replace(str(ROOT) + "/", "")


def hdl_files() -> tuple[list[Path], list[Path]]:
    listed = sources()
    extra = sorted(p for p in HDL.rglob("*.vhd") if p not in listed)
    return [p for p in listed if p.exists()] + extra, extra


def ghdl_checks(ghdl: str, files: list[Path]) -> int:
    WORK.mkdir(parents=True, exist_ok=True)
    errors = 0
    proc = subprocess.run(
        [ghdl, "-a", "--std=08", f"--workdir={WORK}", *map(str, files)], capture_output=True, text=True, check=False
    )
    msgs = (proc.stdout + proc.stderr).strip()
    if proc.returncode != 0:
        print(f"FAIL ghdl -a: analysis failed\n{rel(msgs)}")
        return 1
    print(f"ok   ghdl -a --std=08: {len(files)} files analysed" + (f"\n{rel(msgs)}" if msgs else ""))

    for f in files:
        for entity in ENTITY_RE.findall(f.read_text()):
            cmd = [ghdl, "synth", "--std=08", "--out=none", *map(str, files), "-e", entity]
            proc = subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=WORK)
            out = proc.stderr + proc.stdout
            warnings = [rel(ln) for ln in out.splitlines() if ":warning:" in ln]
            rams = [f"{m[1]} {m[4]}x{m[3]}" for m in RAM_NOTE_RE.finditer(out)]
            info = f"; {len(rams)} RAM(s): {', '.join(rams)}" if rams else ""
            if proc.returncode == 0:
                print(
                    f"ok   ghdl synth {entity} ({f.name}){info}" + (f"; {len(warnings)} warning(s)" if warnings else "")
                )
                for w in warnings:
                    print(f"     {w}")
                continue
            errors += 1
            if "GHDL Bug occurred" in out:
                where = next((ln for ln in out.splitlines() if "raised" in ln), "internal error")
                print(f"FAIL ghdl synth {entity} ({f.name}): GHDL crashed ({where.strip()})")
            else:
                print(f"FAIL ghdl synth {entity} ({f.name}):")
                for ln in out.strip().splitlines()[:20]:
                    print(f"     {rel(ln)}")
    return errors


def vsg_check(files: list[Path]) -> int:
    if not VSG.exists():
        print(f"FAIL vsg: {rel(VSG)} not found; run `make setup`")
        return 1
    cmd = [str(VSG), "-c", str(VSG_CONFIG), "-ap", "-of", "syntastic", "-f", *map(str, files)]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=ROOT)
    lines = [ln for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip()]
    if proc.returncode == 0:
        print(f"ok   vsg ({rel(VSG_CONFIG)}): {len(files)} files clean")
        return 0
    print(f"FAIL vsg ({rel(VSG_CONFIG)}): {len(lines)} message(s); `{rel(VSG)} -c vsg.yaml --fix -f FILE` fixes many")
    for ln in lines:
        print(f"     {rel(ln)}")
    return 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--no-ghdl", action="store_true", help="skip the GHDL analysis and synthesis checks")
    ap.add_argument("--no-vsg", action="store_true", help="skip the vsg style check")
    args = ap.parse_args()

    files, extra = hdl_files()
    failures = 0
    for p in extra:
        print(f"warn {rel(p)} is not in hdl/manifest.txt (analysed last)")
    if not args.no_ghdl:
        ghdl = next((p for p in (shutil.which(n) for n in ("ghdl", "ghdl-llvm", "ghdl-mcode")) if p), None)
        if ghdl is None:
            print("FAIL GHDL is not installed; install it with: apt-get install ghdl-llvm")
            failures += 1
        else:
            failures += ghdl_checks(ghdl, files)
    if not args.no_vsg:
        failures += vsg_check(files)
    print("HDL lint: " + (f"{failures} check(s) failed" if failures else "all checks passed"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
