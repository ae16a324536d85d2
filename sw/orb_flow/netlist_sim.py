#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Netlist simulation: existing cocotb tests run on GHDL's synthesised netlist instead of the RTL.

Each case is a pytest test of tb/ run with ORB_NETLIST=1: orbtb.runner.run then synthesises the
toplevel with `ghdl synth --std=08 -g... --out=vhdl` (the test's own generics, fixed at synthesis)
and simulates that netlist with the same cocotb test (docs/netlist-sim.md). A test that fails on
the netlist but passes on the RTL means GHDL's synthesis changed the behaviour (or the RTL relies
on something synthesis does not keep, e.g. initial values of signals).

Tests that read internal signals by hierarchical name cannot run on a netlist (only the toplevel's
ports exist there); they are listed in SKIPPED with the reason and printed as SKIP.

Results: a table on stdout, build/netlist_sim/report.md and report.json; one log per case in
build/netlist_sim/logs/. Exit status 1 when a case fails.

Usage: python3 -m orb_flow.netlist_sim [-k SUBSTRING ...] [--quick] [--rtl] [--timeout S] [--list]
  -k      run only the cases whose entity or test contains one of the substrings
  --quick leave out the cases marked slow (orb_desc_path, orb_core's grid selection, orb_accel_top: minutes each)
  --rtl   also run each case on the RTL, for the time comparison
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "build" / "netlist_sim"


@dataclass(frozen=True)
class Case:
    entity: str
    test: str  # pytest node id relative to tb/
    slow: bool = False  # minutes as a netlist (left out by --quick)


# Small and fast configurations first; the entity is the toplevel the test simulates.
CASES = (
    Case("orb_feat_mem", "host/test_orb_feat_mem.py::test_feat_mem[16]"),
    Case("orb_axil_regs", "host/test_orb_axil_regs.py::test_orb_axil_regs[lat1]"),
    Case("orb_axil_regs", "host/test_orb_axil_regs.py::test_orb_axil_regs[lat2]"),
    Case("orb_axil_regs", "host/test_orb_axil_regs.py::test_orb_axil_regs[lat5]"),
    Case("orb_video_check", "input/test_orb_video_check.py::test_video_check_16x6"),
    Case("orb_video_check", "input/test_orb_video_check.py::test_video_check_33x5"),
    Case("orb_frame_gate", "input/test_orb_frame_gate.py::test_frame_gate_24"),
    Case("orb_rgb_luma", "input/test_orb_rgb_luma.py::test_rgb_luma_rgb"),
    Case("orb_rgb_luma", "input/test_orb_rgb_luma.py::test_rgb_luma_rbg"),
    Case("orb_rgb_luma", "input/test_orb_rgb_luma.py::test_rgb_luma_luma"),
    Case("orb_smooth", "describe/test_orb_smooth.py::test_smooth"),
    Case("orb_fast_score", "detect/test_orb_fast_score.py::test_fast_score"),
    Case("orb_fast_nms", "detect/test_orb_fast_nms.py::test_nms[8-8-all8x8,ties:1]"),
    Case("orb_harris", "detect/test_orb_harris.py::test_orb_harris"),
    Case("orb_fast_detect", "detect/test_orb_fast_detect.py::test_fast_detect[8-6-noise@0,dots@0,flat@20/5-0.2]"),
    Case("orb_feat_select", "core/test_orb_feat_select.py::test_orb_feat_select[level2]"),
    Case("orb_orient_moments", "describe/test_orb_orient_moments.py::test_orient_moments"),
    Case("orb_orient_sector", "describe/test_orb_orient_sector.py::test_orient_sector[16]"),
    Case("orb_overlay", "output/test_orb_overlay.py::test_overlay_photos[64-48-1-3-env0]"),
    Case("orb_desc_rotate", "describe/test_orb_desc_rotate.py::test_desc_rotate[32-1]"),
    Case("orb_desc_path", "describe/test_orb_desc_path.py::test_desc_path[16-True-128]", slow=True),
    Case("orb_core", "core/test_orb_core.py::test_orb_small[64-48-1-32-photo:camera-5-none-orb]"),
    Case(
        "orb_core",
        "core/test_orb_core.py::test_grid_selection"
        "[128-96-2-step1-photo:chelsea,photo:chelsea-20,20-none-orb,orb-all,grid:40:5x4:7]",
        slow=True,
    ),
    Case("orb_accel_top", "top/test_orb_accel_top.py::test_accel_overflow_overrun", slow=True),
)

# (entity, test, reason): never run on a netlist, always printed. None today: the jobs of
# orb_sim.jobs (make sim) are not tests.
SKIPPED: tuple[tuple[str, str, str], ...] = ()


@dataclass
class Result:
    entity: str
    test: str
    status: str  # PASS, FAIL, TIMEOUT, SKIP
    seconds: float = 0.0
    rtl_status: str = ""
    rtl_seconds: float = 0.0
    netlists: list[dict[str, Any]] = field(default_factory=list)
    note: str = ""
    log: str = ""


def slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text)[:120]


def first_failure(log: str) -> str:
    """The first line of a cocotb/pytest log that tells what failed."""
    for pattern in (r"AssertionError.*", r"\S*:error: .*", r"\w*Error: .*", r"\bFAIL\b.*"):
        m = re.search(pattern, log)
        if m:
            return m.group(0).strip()[:300]
    return ""


def run_pytest(test: str, netlist: bool, timeout: float, log: Path) -> tuple[str, float, list[dict[str, Any]]]:
    """Run one pytest node of tb/; returns (status, seconds, netlist records)."""
    with tempfile.NamedTemporaryFile("r", suffix=".jsonl", delete=False) as tmp:
        report = Path(tmp.name)
    env = {**os.environ, "ORB_NETLIST": "1" if netlist else "0", "ORB_NETLIST_REPORT": str(report)}
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", f"tb/{test}"]
    t0 = time.perf_counter()
    try:
        with log.open("w") as f:
            rc = subprocess.run(cmd, cwd=ROOT, env=env, stdout=f, stderr=subprocess.STDOUT, timeout=timeout).returncode
        status = "PASS" if rc == 0 else "FAIL"
    except subprocess.TimeoutExpired:
        status = "TIMEOUT"
    seconds = time.perf_counter() - t0
    records = [json.loads(line) for line in report.read_text().splitlines() if line.strip()]
    report.unlink()
    return status, seconds, records


def table(results: list[Result], with_rtl: bool) -> str:
    head = ["entity", "test", "netlist", "netlist size", "synth s", "netlist sim s"]
    if with_rtl:
        head += ["RTL", "RTL sim s"]
    rows = [head, ["---"] * len(head)]
    for r in results:
        sizes = ", ".join(f"{n['lines']} lines / {int(n['bytes']) // 1024} KiB" for n in r.netlists)
        synth = ", ".join(f"{n['synth_s']}" for n in r.netlists)
        status = r.status + (f" ({r.note})" if r.note else "")
        row = [r.entity, r.test.replace("|", "\\|"), status, sizes or "-", synth or "-"]
        row.append(f"{r.seconds:.1f}" if r.status != "SKIP" else "-")
        if with_rtl:
            row += [r.rtl_status or "-", f"{r.rtl_seconds:.1f}" if r.rtl_status else "-"]
        rows.append(row)
    return "\n".join("| " + " | ".join(row) + " |" for row in rows)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-k", dest="keys", action="append", default=[], help="only cases matching this substring")
    ap.add_argument("--rtl", action="store_true", help="also run each case on the RTL (time comparison)")
    ap.add_argument("--timeout", type=float, default=900, help="seconds per test run (default 900)")
    ap.add_argument("--quick", action="store_true", help="leave out the slow cases (several minutes each)")
    ap.add_argument("--list", action="store_true", help="list the cases and the skipped tests, run nothing")
    args = ap.parse_args()

    cases = [c for c in CASES if not args.keys or any(k in c.entity or k in c.test for k in args.keys)]
    cases = [c for c in cases if not (args.quick and c.slow)]
    skipped = [s for s in SKIPPED if not args.keys or any(k in s[0] or k in s[1] for k in args.keys)]
    if args.list:
        for c in cases:
            print(f"{c.entity:20s} {c.test}{'  (slow)' if c.slow else ''}")
        for entity, test, reason in skipped:
            print(f"{entity:20s} {test}  SKIP: {reason}")
        return 0

    logs = OUT / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    results: list[Result] = []
    for c in cases:
        log = logs / f"{slug(c.test)}.netlist.log"
        print(f"netlist sim: {c.entity}: {c.test} ...", end=" ", flush=True)
        status, seconds, records = run_pytest(c.test, True, args.timeout, log)
        r = Result(c.entity, c.test, status, seconds, netlists=records, log=str(log.relative_to(ROOT)))
        problems = [p for n in records for p in n.get("interface_problems", [])]
        if problems:
            r.note = "interface: " + "; ".join(problems)
        if status != "PASS":
            r.note = (r.note + "; " if r.note else "") + first_failure(log.read_text(errors="replace"))
        print(f"{status} ({seconds:.1f} s){' ' + r.note if r.note else ''}", flush=True)
        if args.rtl:
            rtl_log = logs / f"{slug(c.test)}.rtl.log"
            r.rtl_status, r.rtl_seconds, _ = run_pytest(c.test, False, args.timeout, rtl_log)
            print(f"    RTL: {r.rtl_status} ({r.rtl_seconds:.1f} s)", flush=True)
        results.append(r)
    results += [Result(entity, test, "SKIP", note=reason) for entity, test, reason in skipped]

    text = table(results, args.rtl)
    print()
    print(text)
    (OUT / "report.md").write_text(text + "\n")
    (OUT / "report.json").write_text(json.dumps([asdict(r) for r in results], indent=2) + "\n")
    failed = [r for r in results if r.status in ("FAIL", "TIMEOUT")]
    for r in failed:
        print(f"\n{r.status}: {r.entity} {r.test}: see {r.log}")
    print(f"\n{sum(r.status == 'PASS' for r in results)} passed, {len(failed)} failed, "
          f"{sum(r.status == 'SKIP' for r in results)} skipped; {OUT.relative_to(ROOT)}/report.md")  # fmt: skip
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
