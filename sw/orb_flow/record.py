# SPDX-License-Identifier: MIT
"""Keep a measurement: copy a benchmark's or a simulation's machine-readable output into the
committed records under docs/results/ (docs/results/README.md), with the command that produced it,
the commit, the date and the tools. The docs' results tables are generated from these records
(orb_flow.gen.results) and byte-checked, so a figure lives in one place.

    python -m orb_flow.record eval [NAME ...]          # the outputs of `make eval` under build/eval
    python -m orb_flow.record sim NAME REPORT --command "make sim ..."   # a make sim report.json
    python -m orb_flow.record test NAME LOG --command "make test" [--total-s S]  # a make test log
    python -m orb_flow.record formal                   # make formal's build/formal/summary.json
    python -m orb_flow.record recovery [NAME]          # orb_flow.board.recovery's build/recovery/recovery.json
    python -m orb_flow.record power [NAME]             # make power's build/power/power.json
    python -m orb_flow.record campaign NAME REPORT --command "pytest ..."  # a fault campaign's JSON report

--commit / --date say when the measured tree is not the checkout's HEAD or today.
"""

from __future__ import annotations

import argparse
import csv
import datetime as dt
import json
import os
import platform
import re
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

from orb_flow import digest

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "docs" / "results"
EVAL_OUT = ROOT / "build" / "eval"
MODEL_TOOLS = "the golden model (numpy), OpenCV (opencv-python-headless) for the OpenCV rows"


def _csv_rows(path: Path) -> list[dict[str, Any]]:
    def value(text: str) -> Any:
        for kind in (int, float):
            try:
                return kind(text)
            except ValueError:
                pass
        return text

    with path.open(newline="") as f:
        return [{k: value(v) for k, v in row.items()} for row in csv.DictReader(f)]


def _json(path: Path) -> Any:
    return json.loads(path.read_text())


def _density(path: Path) -> dict[str, Any]:
    """The density bench's summary, with what only its per-frame CSV holds: per size and contrast,
    ours' budget and the frames where ours keeps fewer features than OpenCV's defaults (500)."""
    data = _json(path)
    frames: dict[tuple[str, str, str], dict[str, dict[str, Any]]] = {}
    for r in _csv_rows(path.with_name("density_bench.csv")):
        frames.setdefault((r["photo"], r["size"], str(r["contrast"])), {})[r["extractor"]] = r
    for row in data["summary"]:
        if row["extractor"] != "ours":
            continue
        mine = [f for (_, size, c), f in frames.items() if size == row["size"] and float(c) == row["contrast"]]
        row["budget"] = mine[0]["ours"]["budget"]
        row["frames_fewer_than_cv500"] = sum(f["ours"]["features"] < f["cv-500"]["features"] for f in mine)
    return data


# name -> (the command `make eval` runs, its summary file under build/eval, reader). The Makefile's
# eval recipe runs each command (tb/house/test_results.py checks it).
EVAL: dict[str, tuple[str, str, Callable[[Path], Any]]] = {
    "compare-fast": (
        "orb-accel compare-fast build/eval/photos/*.png --threshold 15 20 25 30 35 40 "
        "--out-dir build/eval/compare-fast",
        "compare-fast/compare_fast.csv",
        _csv_rows,
    ),
    "rotation-bench": (
        "orb-accel rotation-bench build/eval/photos/*.png --sectors 16 32 64 --step 1 --threshold 20 --scales 1 "
        "--out-dir build/eval/rotation-bench",
        "rotation-bench/rotation_summary.csv",
        _csv_rows,
    ),
    "rotation-bench-grid": (
        "orb-accel rotation-bench build/eval/photos/*.png --sectors 32 --step 5 --threshold 20 --scales 1 "
        "--budget 1000 --out-dir build/eval/rotation-bench-grid",
        "rotation-bench-grid/rotation_summary.csv",
        _csv_rows,
    ),
    "scale-bench": (
        "orb-accel scale-bench build/eval/photos/*.png --out-dir build/eval/scale-bench",
        "scale-bench/scale_bench_summary.csv",
        _csv_rows,
    ),
    "scale-bench-held": (
        "orb-accel scale-bench build/eval/held/640x480/*.png --extractors 5:4x5s64/g1000 cv-default@5:4x5s64/g1000 "
        "--out-dir build/eval/scale-bench-held",
        "scale-bench-held/scale_bench_summary.csv",
        _csv_rows,
    ),
    "viewpoint-bench-held": (
        "orb-accel viewpoint-bench build/eval/held/640x480/*.png --out-dir build/eval/viewpoint-bench-held",
        "viewpoint-bench-held/viewpoint_bench_summary.csv",
        _csv_rows,
    ),
    "trajectory-bench": (
        "orb-accel trajectory-bench build/eval/held/native/*.png --out-dir build/eval/trajectory-bench",
        "trajectory-bench/trajectory_bench.csv",
        _csv_rows,
    ),
    "track-bench": (
        "orb-accel track-bench build/eval/held/native/{Wood,Aqua,Garden,LadyBird,TwoWings,YellowFlower,Storm,"
        "Blinds}.png build/eval/debian-cache/opencv-doc/usr/share/doc/opencv-doc/examples/data/vtest.avi "
        "--out-dir build/eval/track-bench",
        "track-bench/track_bench_summary.json",
        _json,
    ),
    "density-bench": (
        "orb-accel density-bench build/eval/held/native/*.png --sizes 640x480 1280x720 1920x1080 "
        "--out-dir build/eval/density-bench",
        "density-bench/density_bench_summary.json",
        _density,
    ),
}


def head_commit() -> str:
    done = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    return done.stdout.strip() or "unknown"


def load(kind: str) -> dict[str, Any]:
    path = RESULTS / f"{kind}.json"
    if path.exists():
        return json.loads(path.read_text())
    return {"about": "", "runs": {}}


def save(kind: str, records: dict[str, Any]) -> Path:
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"{kind}.json"
    records["runs"] = dict(sorted(records["runs"].items()))
    path.write_text(json.dumps(records, indent=1, ensure_ascii=False) + "\n")
    return path


def entry(command: str, data: Any, commit: str | None, date: str | None, tools: str, **extra: Any) -> dict:
    return {"command": command, "commit": commit or head_commit(), "date": date or dt.date.today().isoformat(),
            "tools": tools, **extra, "data": data}  # fmt: skip


def record_eval(names: list[str], commit: str | None, date: str | None, out: Path = EVAL_OUT) -> list[str]:
    records = load("eval")
    done = []
    for name in names or list(EVAL):
        if name not in EVAL:
            raise SystemExit(f"error: no evaluation named {name!r}; known: {', '.join(EVAL)}")
        command, rel, read = EVAL[name]
        path = out / rel
        if not path.exists():
            if names:
                raise SystemExit(f"error: {path} is missing: run `{command}` (or make eval) first")
            continue
        records["runs"][name] = entry(command, read(path), commit, date, MODEL_TOOLS)
        done.append(name)
    save("eval", records)
    return done


BENCH = {
    "model": ("make bench", ROOT / "build" / "bench" / "model.json"),
    "sim": ("make bench-sim", ROOT / "build" / "bench" / "sim.json"),
    "driver": ("make bench-driver", ROOT / "build" / "bench" / "driver.json"),
    "stream": ("make bench-stream", ROOT / "build" / "bench" / "stream.json"),
    "ros2": ("make bench-ros2", ROOT / "build" / "bench" / "ros2.json"),
}


def record_bench(names: list[str], commit: str | None, date: str | None, command: str | None = None) -> list[str]:
    """The benchmarks' JSON (build/bench/) into docs/results/bench.json (`command`: what ran, when
    not the make target, e.g. one size of bench-sim)."""
    records = load("bench")
    done = []
    for name in names or list(BENCH):
        target, path = BENCH[name]
        if not path.exists():
            raise SystemExit(f"error: {path} is missing: run `{target}` first")
        data = json.loads(path.read_text())
        if name == "model":
            tools = f"Python {data['meta']['python']}, numpy {data['meta']['numpy']}, {data['meta']['cpu_count']} cores"
        elif name in ("driver", "stream"):
            tools = f"Python {data['python']}, numpy {data['numpy']}, {data['machine']}"
        elif name == "ros2":
            tools = (f"Python {data['python']}, numpy {data['numpy']}, rclpy {data['rclpy']} ({data['rmw']}), "
                     f"{data['machine']}")  # fmt: skip
        else:
            tools = "GHDL 2.0.0 (the back end in each row's path), Verilator 5.48.0"
        records["runs"][name] = entry(command or target, data, commit, date, tools)
        done.append(name)
    save("bench", records)
    return done


PYTEST_SUMMARY_RE = re.compile(r"=+ (?P<counts>[^=]*?) in (?P<seconds>[\d.]+)s(?: \([^)]*\))? =+\s*$", re.M)


def parse_pytest_log(text: str) -> dict[str, Any]:
    """The counts and the time of pytest's last summary line ("=== 1612 passed, 3 deselected in
    965.12s (0:16:05) ===")."""
    found = list(PYTEST_SUMMARY_RE.finditer(text))
    if not found:
        raise SystemExit("error: no pytest summary line (`=== N passed ... in S s ===`) in the log")
    m = found[-1]
    counts = {kind: int(n) for n, kind in re.findall(r"(\d+) (\w+)", m["counts"])}
    return {"counts": counts, "pytest_s": float(m["seconds"])}


def record_test(name: str, log: Path, command: str, total_s: float | None, commit: str | None,
                date: str | None) -> None:  # fmt: skip
    """A `make test` run's log (its pytest summary) into docs/results/test.json; `total_s`: the
    whole command's wall time, set-up included, when it was timed."""
    records = load("test")
    data = parse_pytest_log(log.read_text())
    if total_s is not None:
        data["total_s"] = total_s
    data["machine"] = f"{platform.machine()} ({os.cpu_count()} cores)"
    records["runs"][name] = entry(command, data, commit, date, "GHDL 2.0.0 (llvm back end), Verilator 5.48.0")
    save("test", records)


FORMAL_KEPT = ("entity", "generics", "mode", "wall_s", "status", "failed", "properties", "cex_step", "ok", "mutations")


def record_formal(summary: Path, command: str, commit: str | None, date: str | None) -> None:
    """make formal's summary (build/formal/summary.json) into docs/results/formal.json, without the
    run's paths and logs (the GHDL command, the traces)."""
    if not summary.exists():
        raise SystemExit(f"error: {summary} is missing: run `make formal` first")
    data = {name: {k: rec[k] for k in FORMAL_KEPT if k in rec} for name, rec in _json(summary).items()}
    for rec in data.values():
        rec["mutations"] = [{k: v for k, v in m.items() if k != "traces"} for m in rec.get("mutations", [])]
    from orb_flow import formal  # the check list (a tool, not the model's or the driver's layer)

    records = load("formal")
    tools = "GHDL 2.0.0; Yosys 0.70, SymbiYosys and Boolector from PyPI (yowasp)"
    if set(formal.CHECKS) <= set(data):
        # a whole run: it replaces the whole record and the partial runs it supersedes
        records["runs"] = {"make-formal": entry(command, data, commit, date, tools, hdl_digest=_hdl(commit))}
    else:
        # a run of some checks (make formal K=...): kept beside the whole run with its own commit; the
        # table takes each check from the newest run that holds it
        unknown = sorted(set(data) - set(formal.CHECKS))
        if unknown:
            raise SystemExit(f"error: {summary} holds checks make formal no longer lists: {', '.join(unknown)}")
        key = "make-formal K=" + " ".join(sorted(data))
        for name in [k for k, run in records["runs"].items() if k != "make-formal" and set(run["data"]) <= set(data)]:
            del records["runs"][name]
        records["runs"][key] = entry(command, data, commit, date, tools, hdl_digest=_hdl(commit))
    save("formal", records)


CAMPAIGN_ABOUT = (
    "Randomised fault campaigns on the fast path (docs/fast-sim.md, the fault campaign; "
    "tb/orbtb/campaign.py): per run the seed, the device's generics, the events and faults by kind, "
    "the frames sent, closed good and bad, published and skipped, the features checked, the lock-ups "
    "and mismatches (with the first messages), the simulated clocks and the wall time. Written by "
    "python -m orb_flow.record campaign from the report a campaign test writes under build/campaign."
)
CAMPAIGN_KEYS = ("seed", "init_seed", "generics", "events", "faults_injected", "faults_by_kind", "changes_by_kind",
                 "frames_sent", "frames_closed_good", "frames_published", "frames_skipped_bank_held", "lockups",
                 "mismatches", "features_checked", "wall_s")  # fmt: skip


def record_campaign(name: str, report: Path, command: str, commit: str | None, date: str | None) -> None:
    """A fault campaign's report (orbtb.campaign.CampaignResult.report(), written by the campaign
    tests under build/campaign/) into docs/results/campaign.json, with the machine it ran on."""
    if not report.exists():
        raise SystemExit(f"error: {report} is missing: run the campaign first (tb/fast/test_fast_regressions.py)")
    data = _json(report)
    missing = [k for k in CAMPAIGN_KEYS if k not in data]
    if missing:
        raise SystemExit(f"error: {report} is not a campaign report: no {', '.join(missing)}")
    data["machine"] = f"{platform.machine()} ({os.cpu_count()} cores)"
    records = load("campaign")
    records["about"] = CAMPAIGN_ABOUT
    records["runs"][name] = entry(command, data, commit, date, "Verilator 5.48.0 (GHDL 2.0.0's synthesised netlist), "
                                  "the golden model", hdl_digest=_hdl(commit))  # fmt: skip
    save("campaign", records)


def record_sim(name: str, report: Path, command: str, tools: str, commit: str | None, date: str | None) -> None:
    records = load("sim")
    data = json.loads(report.read_text())
    for key in ("image", "video"):  # paths relative to the checkout, as the command names them
        if key in data and Path(data[key]).is_absolute() and Path(data[key]).is_relative_to(ROOT):
            data[key] = str(Path(data[key]).relative_to(ROOT))
    records["runs"][name] = entry(command, data, commit, date, tools, hdl_digest=_hdl(commit))
    save("sim", records)


RECOVERY_OUT = ROOT / "build" / "recovery" / "recovery.json"
RECOVERY_ABOUT = (
    "The board's recovery after a cut in its HDMI input (docs/board.md, 'Recovery after a cut'): per board "
    "configuration, video checker (IDLE_TIMEOUT_g) and event, which frames were published and how many lost. "
    "Written by python -m orb_flow.record recovery from orb_flow.board.recovery's build/recovery/recovery.json."
)


def record_recovery(name: str, report: Path, commit: str | None, date: str | None) -> None:
    """orb_flow.board.recovery's output (its command and runs) into docs/results/recovery.json."""
    if not report.exists():
        raise SystemExit(f"error: {report} is missing: run `python -m orb_flow.board.recovery` first")
    data = _json(report)
    records = load("recovery")
    records["about"] = RECOVERY_ABOUT
    records["runs"][name] = entry(data["command"], data["runs"], commit, date,
                                  "GHDL 2.0.0 (the netlist), Verilator 5.48.0, the golden model",
                                  hdl_digest=_hdl(commit))  # fmt: skip
    save("recovery", records)


POWER_OUT = ROOT / "build" / "power" / "power.json"
POWER_ABOUT = (
    "The power estimate (docs/power.md): per configuration, yosys's resources, the netlist's activity in "
    "Verilator on photographs, dynamic power in mW (typ and the coefficients' band), the vectorless figure, "
    "energy a frame at 60 fps, the largest entities. Written by python -m orb_flow.record power from make "
    "power's build/power/power.json."
)


def record_power(name: str, report: Path, commit: str | None, date: str | None) -> None:
    """make power's output (its command and one record per configuration) into docs/results/power.json."""
    if not report.exists():
        raise SystemExit(f"error: {report} is missing: run `make power` first")
    data = _json(report)
    records = load("power")
    records["about"] = POWER_ABOUT
    for run in data["runs"]:  # the per-entity table keeps the ten largest (the record stays small)
        run["by_entity_mw"] = dict(list(run["by_entity_mw"].items())[:10])
    records["runs"][name] = entry(data["command"], data["runs"], commit, date,
                                  "GHDL 2.0.0, Yosys 0.23 (resources), Verilator 5.48.0 (activity)",
                                  hdl_digest=_hdl(commit))  # fmt: skip
    save("power", records)


# the records of the HDL: each keeps the digest of the hdl/ it measured (orb_flow.digest)
HDL_RECORDS = ("sim", "formal", "campaign", "recovery", "power")


def _hdl(commit: str | None) -> str:
    return digest.of_record(commit, ROOT)


def record_digests() -> list[str]:
    """Give every HDL record without `hdl_digest` (docs/results/{sim,formal,campaign,recovery}.json,
    sw/orb_flow/synth_expected.json's jobs) the digest of hdl/ at its commit; the ones whose commit
    this checkout does not hold are listed and left without."""
    unknown = []
    for kind in HDL_RECORDS:
        records = load(kind)
        for name, run in records["runs"].items():
            if "hdl_digest" not in run:
                got = digest.at_commit(run["commit"], ROOT)
                if got is None:
                    unknown.append(f"{kind}: {name} ({run['commit']})")
                    continue
                # keep the key order of entry(): the digest before the data
                data = run.pop("data")
                run["hdl_digest"] = got
                run["data"] = data
        save(kind, records)
    path = ROOT / "sw" / "orb_flow" / "synth_expected.json"
    synth = json.loads(path.read_text())
    for name, job in synth["jobs"].items():
        m = job.get("measured", {})
        if "commit" in m and "hdl_digest" not in m:
            got = digest.at_commit(m["commit"], ROOT)
            if got is None:
                unknown.append(f"synth: {name} ({m['commit']})")
                continue
            m["hdl_digest"] = got
    from orb_flow.synth import dump_expected  # the file's own layout

    path.write_text(dump_expected(synth))
    return unknown


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="kind", required=True)
    ev = sub.add_parser("eval", help="the outputs of make eval (build/eval) into docs/results/eval.json")
    ev.add_argument("names", nargs="*", help=f"which (default: every one present): {', '.join(EVAL)}")
    bench = sub.add_parser("bench", help="the benchmarks' outputs (build/bench) into docs/results/bench.json")
    bench.add_argument("names", nargs="*", help=f"which (default: all): {', '.join(BENCH)}")
    bench.add_argument("--command", help="the command that wrote the output, when not the make target")
    sub.add_parser("digests", help="the hdl/ digest of every HDL record that lacks one, from its commit")
    sim = sub.add_parser("sim", help="a make sim report.json into docs/results/sim.json")
    sim.add_argument("name")
    sim.add_argument("report", type=Path)
    sim.add_argument("--command", required=True, help="the command that wrote the report")
    sim.add_argument("--tools", default="GHDL 2.0.0 (llvm back end); Verilator 5.48.0 (FAST=1)")
    test = sub.add_parser("test", help="a make test log (its pytest summary) into docs/results/test.json")
    test.add_argument("name", help="e.g. make-test-fresh-clone")
    test.add_argument("log", type=Path)
    test.add_argument("--command", required=True, help="what ran, e.g. 'git clone . X && cd X && make test'")
    test.add_argument("--total-s", type=float, help="the whole command's wall time, set-up included")
    formal = sub.add_parser("formal", help="make formal's summary into docs/results/formal.json")
    formal.add_argument("--summary", type=Path, default=ROOT / "build" / "formal" / "summary.json")
    formal.add_argument("--command", default="make formal")
    campaign = sub.add_parser("campaign", help="a fault campaign's report into docs/results/campaign.json")
    campaign.add_argument("name", help="e.g. long-campaign")
    campaign.add_argument("report", type=Path, help="e.g. build/campaign/long-2026.json")
    campaign.add_argument("--command", required=True, help="the command that ran the campaign")
    recovery = sub.add_parser("recovery", help="orb_flow.board.recovery's output into docs/results/recovery.json")
    recovery.add_argument("name", nargs="?", default="board-recovery", help="the run's name (board-recovery)")
    recovery.add_argument("--report", type=Path, default=RECOVERY_OUT)
    power = sub.add_parser("power", help="make power's build/power/power.json into docs/results/power.json")
    power.add_argument("name", nargs="?", default="make-power", help="the run's name (make-power)")
    power.add_argument("--report", type=Path, default=POWER_OUT)
    for p in (ev, bench, sim, test, formal, campaign, recovery, power):
        p.add_argument("--commit", help="the measured commit (default: HEAD)")
        p.add_argument("--date", help="the measurement's date, YYYY-MM-DD (default: today)")
    args = ap.parse_args(argv)
    if args.kind == "digests":
        unknown = record_digests()
        print("hdl/ digests written" + (f"; commits not in this checkout: {'; '.join(unknown)}" if unknown else ""))
    elif args.kind == "eval":
        print(f"recorded {', '.join(record_eval(args.names, args.commit, args.date)) or 'nothing'} "
              f"in {RESULTS / 'eval.json'}; now `make views` (or python -m orb_flow.gen.results)")  # fmt: skip
    elif args.kind == "bench":
        done = record_bench(args.names, args.commit, args.date, args.command)
        print(f"recorded {', '.join(done)} in {RESULTS / 'bench.json'}")
    elif args.kind == "formal":
        record_formal(args.summary, args.command, args.commit, args.date)
        print(f"recorded make-formal in {RESULTS / 'formal.json'}; now `make views`")
    elif args.kind == "recovery":
        record_recovery(args.name, args.report, args.commit, args.date)
        print(f"recorded {args.name} in {RESULTS / 'recovery.json'}; now `make views`")
    elif args.kind == "power":
        record_power(args.name, args.report, args.commit, args.date)
        print(f"recorded {args.name} in {RESULTS / 'power.json'}; now `make views`")
    elif args.kind == "campaign":
        record_campaign(args.name, args.report, args.command, args.commit, args.date)
        print(f"recorded {args.name} in {RESULTS / 'campaign.json'}; now `make views`")
    elif args.kind == "test":
        record_test(args.name, args.log, args.command, args.total_s, args.commit, args.date)
        print(f"recorded {args.name} in {RESULTS / 'test.json'}; now `make views`")
    else:
        record_sim(args.name, args.report, args.command, args.tools, args.commit, args.date)
        print(f"recorded {args.name} in {RESULTS / 'sim.json'}; now `make views` (or python -m orb_flow.gen.results)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
