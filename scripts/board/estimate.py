#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""`make board-estimate`: the yosys estimate of the board's whole accelerator (orb_accel_zynq) for
each configuration of vivado/board.json, with the board's generics (MEM_DEPTH_g, SECTORS_g), by
scripts/flow/synth.py into build/vivado/estimate/ (records cached there). `make bitstream` puts
each record beside Vivado's figures in summary.json; docs/board.md quotes them.

Usage: scripts/board/estimate.py [--jobs N] [--sta]   (plain python3; GHDL and yosys)
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def command(jobs: int, sta: bool) -> list[str]:
    b = json.loads((ROOT / "vivado" / "board.json").read_text())
    cmd = [sys.executable, str(ROOT / "scripts" / "flow" / "synth.py"), "--top", b["accel"]["entity"]]
    for c in b["configs"].values():
        cmd += ["--config", f"{c['width']}x{c['height']}x{c['scales']}"]
    sectors = {c["sectors"] for c in b["configs"].values()}
    steps = {(c["step_num"], c["step_den"]) for c in b["configs"].values()}
    if len(sectors) != 1 or len(steps) != 1:
        raise SystemExit("estimate.py: the configurations differ in sectors or pyramid step; run synth.py per "
                         "configuration")  # fmt: skip
    if (step := steps.pop()) != (2, 1):  # orb_accel_zynq's default
        cmd += ["--generic", f"STEP_NUM_g={step[0]}", "--generic", f"STEP_DEN_g={step[1]}"]
    cmd += ["--generic", f"MEM_DEPTH_g={b['accel']['mem_depth']}"]
    if (s := sectors.pop()) != 32:  # orb_accel_zynq's default SECTORS_g
        cmd += ["--generic", f"SECTORS_g={s}"]
    cmd += ["--out", str(ROOT / "build" / "vivado" / "estimate"), "--jobs", str(jobs)]
    return cmd + (["--sta"] if sta else [])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--sta", action="store_true", help="also the slow logic-delay pass")
    args = ap.parse_args()
    cmd = command(args.jobs, args.sta)
    print(" ".join(cmd))
    return subprocess.run(cmd, check=False).returncode


if __name__ == "__main__":
    sys.exit(main())
