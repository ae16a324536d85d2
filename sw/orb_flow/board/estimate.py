#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""`make board-estimate`: the yosys estimate of the board's whole accelerator (orb_accel_zynq) for
each configuration of vivado/board.json, with the board's generics (MEM_DEPTH_g, SECTORS_g, STEP_*_g, BLOCK_LOG2_g), by
sw/orb_flow/synth.py into build/vivado/estimate/ (records cached there). `make bitstream` puts
each record beside Vivado's figures in summary.json; docs/board.md quotes them.

Usage: python3 -m orb_flow.board.estimate [--jobs N] [--sta]   (plain python3; GHDL and yosys)
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]


def commands(jobs: int, sta: bool) -> list[list[str]]:
    """One synth.py run per group of configurations that share sectors, pyramid step, memory depth
    and overlay block (the generics synth.py applies to all its configurations)."""
    b = json.loads((ROOT / "vivado" / "board.json").read_text())
    groups: dict[tuple[int, int, int, int, int, str], list[str]] = {}
    for c in b["configs"].values():
        key = (c["sectors"], c["step_num"], c["step_den"], c["mem_depth"], c["block_log2"], c.get("mem_kind", "bram"))
        groups.setdefault(key, []).append(f"{c['width']}x{c['height']}x{c['scales']}")
    out = []
    for (sectors, num, den, mem_depth, block_log2, mem_kind), configs in groups.items():
        cmd = [sys.executable, "-m", "orb_flow.synth", "--top", b["accel"]["entity"]]
        for config in configs:
            cmd += ["--config", config]
        cmd += ["--generic", f"MEM_DEPTH_g={mem_depth}"]
        if sectors != 32:  # orb_accel_zynq's default SECTORS_g
            cmd += ["--generic", f"SECTORS_g={sectors}"]
        if (num, den) != (2, 1):  # orb_accel_zynq's default pyramid step
            cmd += ["--generic", f"STEP_NUM_g={num}", "--generic", f"STEP_DEN_g={den}"]
        if block_log2 != 3:  # orb_accel_zynq's default overlay block
            cmd += ["--generic", f"BLOCK_LOG2_g={block_log2}"]
        if mem_kind != "bram":  # orb_accel_zynq's default MEM_KIND_g
            cmd += ["--generic", f"MEM_KIND_g={mem_kind.upper()}"]
        cmd += ["--out", str(ROOT / "build" / "vivado" / "estimate"), "--jobs", str(jobs)]
        out.append(cmd + (["--sta"] if sta else []))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--sta", action="store_true", help="also the slow logic-delay pass")
    args = ap.parse_args()
    status = 0
    for cmd in commands(args.jobs, args.sta):
        print(" ".join(cmd), flush=True)
        status = max(status, subprocess.run(cmd, check=False).returncode)
    return status


if __name__ == "__main__":
    sys.exit(main())
