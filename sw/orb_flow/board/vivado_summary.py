#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Summarise a Vivado batch build's reports into summary.json: resources, timing, power.

Reads three text reports from REPORT_DIR:
  utilization.rpt     report_utilization: "Slice LUTs", "Slice Registers" (and "Register as Flip
                      Flop"), "Block RAM Tile" (RAMB36 equivalent, may be fractional: 13.5) and
                      "DSPs", each from the first table row of that name; the "Used" and
                      "Available" columns are found by the table header, since the columns
                      differ between Vivado versions (Fixed/Loced, with or without Prohibited), and
                      a trailing '*' on the name (synthesised-design reports: "Slice LUTs*") is
                      ignored. Percentages are of the XC7Z020 (53,200 LUT, 106,400 FF, 140 BRAM
                      tiles, 220 DSP); a report whose Available column differs gets a warning.
  timing_summary.rpt  report_timing_summary: the first row under "| Design Timing Summary",
                      mapped by its header (WNS(ns), TNS(ns), TNS Failing Endpoints, ...,
                      WHS(ns), THS(ns), ...; the WPWS/TPWS columns are absent in older versions),
                      and Vivado's verdict line "All user specified timing constraints are met."
                      or "Timing constraints are not met.".
                      Timing met = WNS >= 0 and WHS >= 0 and the verdict, if present, is not
                      "not met" (it also covers pulse-width violations); a report saying "There
                      are no user specified timing constraints." (inf/NA in the table) is not met.
  power.rpt           report_power: "Total On-Chip Power (W)", "Dynamic (W)", "Device Static (W)"
                      from the summary table, and the "PS7" row of "1.1 On-Chip Components" when
                      present (on a Zynq the processing system dominates the total), printed
                      beside the thesis's measured 159 mW.

The layouts were checked against these public Vivado reports:
  - Wendy5755/LAB6: design_1_wrapper_utilization_placed.rpt (Vivado 2022.1, xc7z020clg400-1,
    Used/Fixed/Prohibited/Available/Util% columns) and timing_report.txt (2022.1, 7z020-clg400,
    12-column Design Timing Summary, "All user specified timing constraints are met.");
  - Nianze/TaikoGestureMaster: xapp1167_vivado/sw/demo/ipi_proj/project/zynq_base_trd_2013.2.runs/
    impl_1/system_top_wrapper_utilization_placed.rpt (Vivado 2013.2, xc7z020, Used/Loced/Available/
    Util% columns) and system_top_wrapper_power_routed.rpt (xc7z020clg484-1, summary table without
    the budget rows, PS7 row in the On-Chip Components);
  - f4tnk/LibreSDR_UHD_B220_Mini_FPGA: build_output/post_impl_utilization.rpt ("Block RAM Tile |
    115.5"), build_output/post_synth_utilization.rpt ("Slice LUTs*"), build_output/timing_summary.rpt
    and build_output/power.rpt (Vivado 2025.2, xc7a200t, summary table with "Design Power Budget
    (W)" and "Power Budget Margin (W)" rows).
The failing verdict "Timing constraints are not met." is the text that public build scripts grep
for in routed timing summaries.

Usage:
    PYTHONPATH=sw python3 -m orb_flow.board.vivado_summary REPORT_DIR --config NAME [--estimate ESTIMATE.json]
                                            [--out summary.json]
--estimate takes a yosys estimate (sw/orb_flow/synth.py's report.json, a list of records, or one
record); the record whose <W>x<H>x<S> (and top, if NAME names one) matches NAME is kept, its lut,
ff, bram36 and dsp written under "yosys_estimate". --out defaults to REPORT_DIR/summary.json.
Exit status: 0 timing met, 1 timing not met, 2 a report (or the estimate) missing or unparsable,
with one line `error: FILE: what was not found`.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from orb_flow.device import DEVICE

THESIS_MEASURED_W = 0.159  # the thesis's measured board power
REPORTS = {"utilization": "utilization.rpt", "timing": "timing_summary.rpt", "power": "power.rpt"}
UTIL_ROWS = {  # our key -> report_utilization row name
    "lut": "Slice LUTs",
    "ff": "Slice Registers",
    "ff_flip_flop": "Register as Flip Flop",
    "bram36": "Block RAM Tile",
    "dsp": "DSPs",
}
REQUIRED_UTIL = ("lut", "ff", "bram36", "dsp")
MET_LINE = "All user specified timing constraints are met."
NOT_MET_LINE = "Timing constraints are not met."
NO_CONSTRAINTS_LINE = "There are no user specified timing constraints."
TIMING_COLUMNS = {  # our key -> Design Timing Summary column
    "wns_ns": "WNS(ns)",
    "tns_ns": "TNS(ns)",
    "tns_failing_endpoints": "TNS Failing Endpoints",
    "whs_ns": "WHS(ns)",
    "ths_ns": "THS(ns)",
    "ths_failing_endpoints": "THS Failing Endpoints",
    "wpws_ns": "WPWS(ns)",
}
REQUIRED_TIMING = ("wns_ns", "tns_ns", "whs_ns", "ths_ns")
POWER_ROWS = {"total_w": "Total On-Chip Power (W)", "dynamic_w": "Dynamic (W)", "static_w": "Device Static (W)"}
ESTIMATE_KEYS = ("lut", "ff", "bram36", "dsp")
PREFERRED_TOP = "orb_accel_zynq"  # the wrapper the Vivado build synthesises


class ReportError(ValueError):
    """A report (or the estimate) is missing or lacks something; str() is the one-line message."""

    def __init__(self, path: Path | str, what: str) -> None:
        super().__init__(f"{path}: {what}")


@dataclass(frozen=True)
class Row:
    """One table row of report_utilization, by the header's column names."""

    used: float
    available: float | None


# --- report_utilization --------------------------------------------------------------------------


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def _number(text: str) -> float | None:
    try:
        return float(text.lstrip("<").replace(",", ""))
    except ValueError:
        return None


def _int_if_whole(v: float) -> int | float:
    return int(v) if v == int(v) else v


def utilization_rows(text: str) -> dict[str, Row]:
    """First row of each name in the report's '|'-tables that have a 'Site Type'/'Used' header."""
    rows: dict[str, Row] = {}
    header: list[str] | None = None
    for line in text.splitlines():
        if not line.startswith("|"):
            if not line.startswith("+"):
                header = None  # between tables
            continue
        cells = _cells(line)
        if "Site Type" in cells and "Used" in cells:
            header = cells
            continue
        if header is None or len(cells) != len(header):
            continue
        name = cells[0].rstrip("*").strip()
        used = _number(cells[header.index("Used")])
        if name in rows or used is None:
            continue
        available = cells[header.index("Available")] if "Available" in header else ""
        rows[name] = Row(used, _number(available))
    return rows


def parse_utilization(text: str, path: Path | str = REPORTS["utilization"]) -> dict[str, Any]:
    """LUT, FF, BRAM tiles, DSP used, their % of the XC7Z020, and warnings on another device."""
    rows = utilization_rows(text)
    missing = [UTIL_ROWS[k] for k in REQUIRED_UTIL if UTIL_ROWS[k] not in rows]
    if missing:
        raise ReportError(path, f"no {', '.join(repr(m) for m in missing)} row in a 'Site Type | Used' table")
    used: dict[str, int | float | None] = {}
    warnings: list[str] = []
    for key, name in UTIL_ROWS.items():
        row = rows.get(name)
        used[key] = None if row is None else _int_if_whole(row.used)
        if key in DEVICE and row is not None and row.available is not None and row.available != DEVICE[key]:
            warnings.append(
                f"{path}: {name} available {row.available:g}, not the {DEVICE['name']}'s {DEVICE[key]} (another part?)"
            )
    pct = {k: round(100 * float(used[k] or 0) / DEVICE[k], 2) for k in REQUIRED_UTIL}
    return {"used": used, "util_pct": pct, "warnings": warnings}


# --- report_timing_summary ---------------------------------------------------------------------


def _design_timing_table(lines: list[str], path: Path | str) -> dict[str, str]:
    start = next((i for i, ln in enumerate(lines) if ln.strip().startswith("| Design Timing Summary")), None)
    if start is None:
        raise ReportError(path, "no '| Design Timing Summary' section")
    head = next((i for i in range(start, len(lines)) if "WNS(ns)" in lines[i]), None)
    if head is None:
        raise ReportError(path, "no WNS(ns) header under 'Design Timing Summary'")
    columns = re.split(r"\s{2,}", lines[head].strip())
    values = next((ln.split() for ln in lines[head + 2 :] if ln.strip()), [])  # skip the ------- line
    if len(values) != len(columns):
        raise ReportError(
            path, f"Design Timing Summary row has {len(values)} values for {len(columns)} columns {columns}"
        )
    return dict(zip(columns, values, strict=True))


def _verdict(text: str) -> str | None:
    return next((line for line in (MET_LINE, NOT_MET_LINE, NO_CONSTRAINTS_LINE) if line in text), None)


def parse_timing(text: str, path: Path | str = REPORTS["timing"]) -> dict[str, Any]:
    """WNS, TNS, WHS, THS (ns), failing endpoints, Vivado's verdict line and whether timing is met.

    Without user constraints Vivado prints inf or NA in the table and "There are no user specified
    timing constraints.": the figures are then null and timing counts as not met."""
    table = _design_timing_table(text.splitlines(), path)
    verdict = _verdict(text)
    out: dict[str, Any] = {}
    for key, column in TIMING_COLUMNS.items():
        raw = table.get(column)
        if raw is None and key in REQUIRED_TIMING:
            raise ReportError(path, f"no {column} column in the Design Timing Summary")
        value = None if raw is None else _number(raw)
        if value is not None and not math.isfinite(value):
            value = None
        if value is None and raw is not None and verdict != NO_CONSTRAINTS_LINE:
            raise ReportError(path, f"{column} is {raw!r}, not a number")
        out[key] = int(value) if value is not None and key.endswith("endpoints") else value
    out["verdict"] = verdict
    out["met"] = verdict not in (NOT_MET_LINE, NO_CONSTRAINTS_LINE) and out["wns_ns"] >= 0 and out["whs_ns"] >= 0
    return out


# --- report_power --------------------------------------------------------------------------------


def _table_value(text: str, name: str) -> str | None:
    m = re.search(rf"^\|\s*{re.escape(name)}\s*\|\s*([^|]*?)\s*\|", text, re.M)
    return m.group(1) if m else None


def parse_power(text: str, path: Path | str = REPORTS["power"]) -> dict[str, Any]:
    """Total on-chip, dynamic and device static power (W), the PS7's share, beside the thesis figure."""
    out: dict[str, Any] = {}
    for key, name in POWER_ROWS.items():
        raw = _table_value(text, name)
        value = None if raw is None else _number(raw)
        if value is None:
            raise ReportError(path, f"no numeric '{name}' row" + ("" if raw is None else f" (found {raw!r})"))
        out[key] = value
    ps7 = _table_value(text, "PS7")
    out["ps7_w"] = None if ps7 is None else _number(ps7)
    out["confidence"] = _table_value(text, "Confidence Level")
    out["thesis_measured_w"] = THESIS_MEASURED_W
    return out


# --- make power's estimate (docs/power.md) ------------------------------------------------------
POWER_RECORD = Path(__file__).resolve().parents[3] / "docs" / "results" / "power.json"


def power_estimate(config: str, path: Path = POWER_RECORD) -> dict[str, Any] | None:
    """The newest recorded `make power` estimate of `config` (a board configuration's key, e.g.
    640x480, or its named configuration, e.g. board-vga) to stand beside Vivado's report_power:
    dynamic mW with its band, the core clock, the run and its commit; None when none is recorded."""
    try:
        runs = json.loads(path.read_text())["runs"]
    except (OSError, ValueError, KeyError):
        return None
    board = json.loads((path.parents[2] / "vivado" / "board.json").read_text())["configs"]
    names = {config, board.get(config, {}).get("config", config)}
    found = None
    for name, run in runs.items():
        if name.startswith("what-if"):
            continue
        for r in run["data"]:
            if r["config"] in names:
                found = {"run": name, "commit": run["commit"], "core_mhz": r["core_mhz"], **r["dynamic_mw"]}
    return found


# --- the yosys estimate --------------------------------------------------------------------------


def _cfg_name(rec: dict[str, Any]) -> str:
    return f"{rec.get('width')}x{rec.get('height')}x{rec.get('scales')}"


def pick_estimate(data: Any, config: str, path: Path | str) -> dict[str, Any]:
    """The estimate record for `config` (one record, or the one of a report.json list that matches)."""
    if isinstance(data, dict):
        records = [data]
    elif isinstance(data, list):
        tokens = config.split()
        records = [r for r in data if isinstance(r, dict) and _cfg_name(r) in tokens]
        named = [r for r in records if r.get("top") in tokens]
        records = named or [r for r in records if r.get("top") == PREFERRED_TOP] or records
        if not records and len(data) == 1 and isinstance(data[0], dict):
            records = data
    else:
        raise ReportError(path, "not a JSON record or list of records")
    if len(records) != 1:
        jobs = ", ".join(f"{r.get('top')} {_cfg_name(r)}" for r in (records or data) if isinstance(r, dict))
        raise ReportError(path, f"{len(records)} estimate records match config {config!r} (records: {jobs or 'none'})")
    rec = records[0]
    missing = [k for k in ESTIMATE_KEYS if k not in rec]
    if missing:
        raise ReportError(path, f"estimate record lacks {', '.join(missing)}")
    out = {k: rec[k] for k in ESTIMATE_KEYS}
    out["source"] = str(path)
    if "top" in rec:
        out["job"] = f"{rec['top']} {_cfg_name(rec)}"
    return out


def load_estimate(path: Path, config: str) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text())
    except OSError as exc:
        raise ReportError(path, f"cannot read the estimate ({exc.strerror})") from exc
    except ValueError as exc:
        raise ReportError(path, f"not valid JSON ({exc})") from exc
    return pick_estimate(data, config, path)


# --- the summary ---------------------------------------------------------------------------------


def _read(report_dir: Path, kind: str) -> tuple[Path, str]:
    path = report_dir / REPORTS[kind]
    try:
        return path, path.read_text(errors="replace")
    except OSError as exc:
        raise ReportError(path, f"missing report ({exc.strerror})") from exc


def summarise(report_dir: Path, config: str, estimate: Path | None = None) -> dict[str, Any]:
    """The summary.json content; ReportError if a report or the estimate is missing or unparsable."""
    util_path, util_text = _read(report_dir, "utilization")
    util = parse_utilization(util_text, util_path)
    timing_path, timing_text = _read(report_dir, "timing")
    timing = parse_timing(timing_text, timing_path)
    power_path, power_text = _read(report_dir, "power")
    power = parse_power(power_text, power_path)
    summary: dict[str, Any] = {
        "config": config,
        "report_dir": str(report_dir),
        "device": DEVICE,
        "vivado": util["used"],
        "util_pct": util["util_pct"],
        "timing": timing,
        "timing_met": timing["met"],
        "power": power,
        "warnings": util["warnings"],
    }
    if estimate is not None:
        summary["yosys_estimate"] = load_estimate(estimate, config)
    summary["power_estimate_mw"] = power_estimate(config)
    return summary


def _fmt(v: float | None) -> str:
    if v is None:
        return "—"
    return f"{v:,}" if isinstance(v, int) else f"{v:,g}"


def _ns(v: float | None) -> str:
    return "—" if v is None else f"{v:.3f} ns"


def table(s: dict[str, Any]) -> str:
    """A short human-readable table of the summary."""
    est = s.get("yosys_estimate")
    lines = [f"{s['config']}: Vivado reports in {s['report_dir']} ({DEVICE['name']})"]
    lines.append(f"  {'resource':<8} {'Vivado':>10} {'% of device':>12}" + (f" {'yosys est.':>11}" if est else ""))
    for key, label in (("lut", "LUT"), ("ff", "FF"), ("bram36", "BRAM36"), ("dsp", "DSP")):
        row = f"  {label:<8} {_fmt(s['vivado'][key]):>10} {s['util_pct'][key]:>11.2f}%"
        lines.append(row + (f" {_fmt(est[key]):>11}" if est else ""))
    t = s["timing"]
    slacks = ", ".join(f"{k[:3].upper()} {_ns(t[k])}" for k in REQUIRED_TIMING)
    verdict = "met" if t["met"] else "NOT MET" + (f" ({t['verdict']})" if t["verdict"] else "")
    lines.append(f"  timing   {slacks}: {verdict}")
    p = s["power"]
    ps7 = "" if p["ps7_w"] is None else f", PS7 {p['ps7_w']:.3f} W"
    lines.append(
        f"  power    total on-chip {p['total_w']:.3f} W (dynamic {p['dynamic_w']:.3f} W, static "
        f"{p['static_w']:.3f} W{ps7}); thesis measured {p['thesis_measured_w'] * 1000:.0f} mW"
    )
    pe = s.get("power_estimate_mw")
    if pe:
        lines.append(f"  beside it, make power's estimate ({pe['run']}, commit {pe['commit']}, {pe['core_mhz']} MHz): "
                     f"dynamic {pe['typ']:.0f} mW ({pe['low']:.0f}-{pe['high']:.0f}) against Vivado's "
                     f"{p['dynamic_w'] * 1000:.0f} mW (whole design; the accelerator's share: report_power's "
                     "hierarchy)")  # fmt: skip
    lines += [f"  warning: {w}" for w in s["warnings"]]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Summarise Vivado utilization/timing/power reports into summary.json.")
    ap.add_argument("report_dir", type=Path, metavar="REPORT_DIR")
    ap.add_argument("--config", required=True, metavar="NAME", help="configuration name, e.g. 640x480x2")
    ap.add_argument("--estimate", type=Path, metavar="ESTIMATE.json", help="yosys estimate to put beside")
    ap.add_argument("--out", type=Path, metavar="summary.json", help="default: REPORT_DIR/summary.json")
    args = ap.parse_args(argv)
    try:
        summary = summarise(args.report_dir, args.config, args.estimate)
    except ReportError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    out = args.out or args.report_dir / "summary.json"
    out.write_text(json.dumps(summary, indent=2) + "\n")
    print(table(summary))
    print(f"  written {out}")
    return 0 if summary["timing_met"] else 1


if __name__ == "__main__":
    sys.exit(main())
