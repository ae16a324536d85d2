# SPDX-License-Identifier: MIT
"""Generate the docs' results tables from the measurement records, the one place of every figure.

The records: docs/results/*.json (written by orb_flow.record from the benches', make sim's, make
test's, make formal's, the fault campaigns' and orb_flow.board.recovery's outputs) and
sw/orb_flow/synth_expected.json (the synthesis estimates, written by make synth). Each table sits
in a page between the lines
``<!-- generated: NAME (orb_flow.gen.results) -->`` and ``<!-- end generated -->``; this module
replaces what is between them and leaves the rest of the page alone. A page that lacks a
table's markers, or a record a table needs, is an error. Deterministic.
Usage: python -m orb_flow.gen.results [--out DIR] (default: the repository).
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

from orb_flow import digest, formal
from orb_flow.device import DEVICE as XC7Z020
from orb_flow.gen.codegen import views_main
from orb_flow.power import THESIS_TABLE

ROOT = Path(__file__).resolve().parents[3]
GENERATOR = "orb_flow.gen.results"
BEGIN = "<!-- generated: {name} (" + GENERATOR + ") -->"
END = "<!-- end generated -->"
SYNTH = Path("sw") / "orb_flow" / "synth_expected.json"
COEFFICIENTS = Path("sw") / "orb_flow" / "power_coefficients.json"
BOARD = Path("vivado") / "board.json"


class ResultsError(ValueError):
    """A page or a record is missing what a table needs."""


class Records:
    """The measurement records of a checkout."""

    def __init__(self, root: Path) -> None:
        self.eval = self._runs(root / "docs" / "results" / "eval.json")
        self.sim = self._runs(root / "docs" / "results" / "sim.json")
        self.bench = self._runs(root / "docs" / "results" / "bench.json")
        self.test = self._runs(root / "docs" / "results" / "test.json")
        self.formal = self._runs(root / "docs" / "results" / "formal.json")
        self.recovery = self._runs(root / "docs" / "results" / "recovery.json")
        self.power = self._runs(root / "docs" / "results" / "power.json")
        self.root = root
        self.campaign = self._runs(root / "docs" / "results" / "campaign.json")
        self.synth = json.loads((root / SYNTH).read_text())["jobs"]
        self.board = json.loads((root / BOARD).read_text())
        self.hdl = digest.on_disk(root)  # the checkout's hdl/, against which an HDL record is dated

    def age(self, hdl_digest: str | None) -> str:
        """What a table appends to an HDL record's commit: nothing when it measured this checkout's
        hdl/, else that the HDL has changed since (standard 8; orb_flow.digest)."""
        if hdl_digest is None:
            return " (hdl/ of the record unknown)"
        return "" if hdl_digest == self.hdl else " (**older hdl/**: changed since)"

    @staticmethod
    def _runs(path: Path) -> dict[str, Any]:
        return json.loads(path.read_text())["runs"] if path.exists() else {}

    def run(self, kind: str, name: str) -> dict[str, Any]:
        runs = getattr(self, kind)
        if name not in runs:
            raise ResultsError(f"docs/results/{kind}.json has no run {name!r}: measure it and record it "
                               f"(python -m orb_flow.record {kind} ...)")  # fmt: skip
        return runs[name]


def _pct(v: float) -> str:
    return f"{v:.2f}%"


def _int(v: float) -> str:
    return f"{round(v):,}"


def _source(run: dict[str, Any]) -> str:
    return f"`{run['command']}`, commit {run['commit']}, {run['date']}"


def _table(head: list[str], rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)] + ["| " + " | ".join(r) + " |" for r in rows]


def extractor_label(key: str) -> str:
    """A scale-bench extractor key in words: 5:4x5s64/g1000, cv-default@2:1x4, ..."""
    if key.startswith("cv-default@"):
        return f"OpenCV defaults at the count of {extractor_label(key.removeprefix('cv-default@'))}"
    m = re.fullmatch(r"(cv-)?(\d+):(\d+)x(\d+)(?:s(\d+))?(?:/(g?)(\d+))?", key)
    if not m:
        return key
    cv, num, den, scales, sectors, grid, budget = m.groups()
    who = "OpenCV" if cv else "ours"
    text = f"{who} {num}:{den} x {scales}"
    if sectors:
        text += f", {sectors} sectors"
    if budget:
        text += f", grid selection {budget}" if grid else f", host budget {budget}"
    elif not cv:
        text += ", every feature"
    return f"{text} (`{key}`)"


# ------------------------------------------------------------------------------------------------
# the tables


def compare_fast_table(records: Records) -> list[str]:
    run = records.run("eval", "compare-fast")
    photos: dict[str, list[dict[str, Any]]] = {}
    for r in run["data"]:
        photos.setdefault(r["image"], []).append(r)
    rows = []
    for photo, rs in photos.items():
        ts = sorted(r["threshold"] for r in rs)
        same = sum(str(r["raw_identical"]) == "True" for r in rs)
        co = [r["coincident_pct"] for r in rs]
        diff = [r["mean_score_diff_pct"] for r in rs]
        rows.append([photo, f"{same} of {len(rs)}", f"{min(co):.1f} to {max(co):.1f}%",
                     f"{min(diff):+.1f} to {max(diff):+.1f}%"])  # fmt: skip
    head = [f"photo (t = {ts[0]} .. {ts[-1]})", "raw corners identical to OpenCV's", "coincident after NMS",
            "mean SAD score, ours against OpenCV's selection"]  # fmt: skip
    return [*_table(head, rows), "", f"Measured by {_source(run)}."]


def scale_table(records: Records, name: str) -> list[str]:
    run = records.run("eval", name)
    rows = []
    for r in run["data"]:
        label = extractor_label(r["extractor"])
        bold = r["extractor"] == "5:4x5s64/g1000"
        cells = [label, _pct(r["pooled_pct"]), _pct(r["scale_1_pct"]), _pct(r["scale_0.8_pct"]),
                 _pct(r["scale_0.6_pct"]), f"{r['features_per_image']:,.1f}"]  # fmt: skip
        rows.append([f"**{c}**" if bold and i < 2 else c for i, c in enumerate(cells)])
    head = ["extractor", "pooled", "scale 1.0", "scale 0.8", "scale 0.6", "features per image"]
    return [*_table(head, rows), "", f"Measured by {_source(run)}."]


def rotation_table(records: Records, name: str) -> list[str]:
    run = records.run("eval", name)
    rows = []
    for r in run["data"]:
        ours = r["method"] != "opencv"
        label = f"ours, {r['method'].split('-')[1]} sectors" if ours else "OpenCV ORB"
        rows.append([label, _pct(r["mean_correct_pct"]), _pct(r["min_correct_pct"]), _pct(r["mean_recall_pct"]),
                     _int(r["mean_matches"]), f"{r['vs_opencv']:.3f}"])  # fmt: skip
    head = ["extractor", "mean correct", "min correct", "mean recall", "mean matches", "correct, of OpenCV's"]
    return [*_table(head, rows), "", f"Measured by {_source(run)}."]


def viewpoint_table(records: Records, name: str = "viewpoint-bench-held") -> list[str]:
    """By tilt, ours (the first of ours in the record) against OpenCV's defaults at its count."""
    run = records.run("eval", name)
    names = list(dict.fromkeys(r["extractor"] for r in run["data"]))
    ours = next(n for n in names if not n.startswith("cv-"))
    cv = f"cv-default@{ours}"
    by = {(r["extractor"], str(r["tilt"])): r for r in run["data"]}
    rows = []
    for tilt in dict.fromkeys(str(r["tilt"]) for r in run["data"] if r["extractor"] == ours):
        o, c = by[(ours, tilt)], by[(cv, tilt)]
        diff = o["score_pct"] - c["score_pct"]
        rows.append([tilt if tilt == "pooled" else f"{tilt} degrees", str(o["pairs"]), _pct(o["score_pct"]),
                     _pct(c["score_pct"]), f"{diff:+.2f}", _pct(o["inlier_pct"]), _pct(c["inlier_pct"]),
                     f"{o['h_ok_pct']:.1f}%", f"{c['h_ok_pct']:.1f}%"])  # fmt: skip
    head = ["tilt", "pairs", "matching score, ours", "OpenCV", "ours - OpenCV (points)", "homography inliers, ours",
            "OpenCV", "correct homography, ours", "OpenCV"]  # fmt: skip
    return [*_table(head, rows), "", f"Ours: {extractor_label(ours)}; OpenCV: its defaults at our feature count on "
            f"the same image. Measured by {_source(run)}."]  # fmt: skip


def trajectory_table(records: Records) -> list[str]:
    """One row per sequence and extractor: frames, lost, ATE, RPE, inliers, features, 3D points."""
    run = records.run("eval", "trajectory-bench")
    names = {"cv-default": "OpenCV ORB's defaults (`cv-default`)", "orbslam": "ORB-SLAM-style (`orbslam`)"}
    rows = [[r["sequence"], names.get(r["extractor"], extractor_label(r["extractor"])), f"{r['budget']:,}",
             str(r["frames"]), str(r["lost"]), f"{r['ate_m'] * 100:.2f} cm", f"{r['rpe_m'] * 100:.2f} cm",
             f"{r['rpe_deg']:.3f}", f"{r['inliers']:.1f}", f"{r['features']:.1f}", f"{r['points']:.1f}"]
            for r in run["data"]]  # fmt: skip
    head = ["sequence", "extractor", "budget", "frames", "lost", "ATE (RMSE)", "RPE, translation", "RPE (degrees)",
            "PnP inliers a frame", "features a frame", "stereo points a frame"]  # fmt: skip
    return [*_table(head, rows), "", f"Measured by {_source(run)}."]


def track_tables(records: Records) -> list[str]:
    run = records.run("eval", "track-bench")
    rows = []
    for r in run["data"]["summary"]:
        ours = r["extractor"] == "ours"
        rows.append([("**ours**" if ours else "OpenCV"), str(r["gap"]), str(r["pairs"]), _int(r["features"]),
                     f"{r['inliers']:.1f}", f"{r['inliers_per_feature']:.3f}", f"{r['coverage']:.3f}",
                     f"{100 * r['failed_share']:.1f}%", str(r["failed_alone"])])  # fmt: skip
    head = ["extractor", "gap", "pairs", "features", "inliers", "inliers per feature", "inlier coverage",
            "failed pairs", "failed alone"]  # fmt: skip
    out = _table(head, rows)
    clips = []
    for clip, rs in run["data"]["by_clip"].items():
        by = {(r["extractor"], r["gap"]): r for r in rs}
        o1, c1, o5, c5 = by[("ours", 1)], by[("opencv", 1)], by[("ours", 5)], by[("opencv", 5)]
        clips.append([clip, f"{_int(o1['features'])} / {_int(c1['features'])}",
                      f"{_int(o1['inliers'])} / {_int(c1['inliers'])}",
                      f"{_int(o5['inliers'])} / {_int(c5['inliers'])}",
                      f"{100 * o1['failed_share']:.0f}% / {100 * c1['failed_share']:.0f}%",
                      f"{100 * o5['failed_share']:.0f}% / {100 * c5['failed_share']:.0f}%"])  # fmt: skip
    head = ["clip", "features, ours / OpenCV", "inliers gap 1", "inliers gap 5", "failed gap 1", "failed gap 5"]
    return [*out, "", *_table(head, clips), "", f"Measured by {_source(run)}."]


def density_table(records: Records) -> list[str]:
    run = records.run("eval", "density-bench")
    by: dict[tuple[str, float], dict[str, dict[str, Any]]] = {}
    for r in run["data"]["summary"]:
        by.setdefault((r["size"], r["contrast"]), {})[r["extractor"]] = r
    levels = run["data"]["settings"]["scales"]
    rows = []
    for (size, contrast), rs in by.items():
        o, cv, c5 = rs["ours"], rs["cv-ours"], rs["cv-500"]
        rows.append([f"{size}, {contrast:g}", f"{_int(o['features'])} ({o['budget']:,})",
                     " / ".join(f"{x['coverage']:.3f}" for x in (o, cv, c5)),
                     " / ".join(f"{x['row_share']:.3f}" for x in (o, cv, c5)), str(o["corner_cells"]),
                     " / ".join(str(x["corner_cells_empty"]) for x in (o, cv, c5)),
                     " / ".join(str(x["empty_with_candidates"]) for x in (o, cv, c5)),
                     f"{o['frames_fewer_than_cv500']} of {o['frames']}",
                     f"{o['unfilled_levels']} of {o['frames'] * levels}"])  # fmt: skip
    head = ["size, contrast", "ours: mean features (budget)", "coverage, ours / cv-ours / cv-500",
            "rows with a feature", "corner cells", "left empty, ours / cv-ours / cv-500",
            "empty frames with candidates", "frames where ours has fewer than cv-500",
            "levels under their share (ours)"]  # fmt: skip
    return [*_table(head, rows), "", f"Measured by {_source(run)}."]


def bench_model_table(records: Records) -> list[str]:
    run = records.run("bench", "model")
    rows = [[f"{r['width']}x{r['height']}", str(r["scales"]), str(r["sectors"]), f"{r['features']:,}",
             f"{r['median_s']:.3f} s"] for r in run["data"]["results"]]  # fmt: skip
    head = ["size", "scales", "sectors", "features", "median time per frame"]
    return [*_table(head, rows), "", f"Measured by {_source(run)} ({run['tools']})."]


def bench_sim_table(records: Records) -> list[str]:
    run = records.run("bench", "sim")
    rows = []
    for r in run["data"]:
        path = "Verilator, netlist" if r["path"] == "verilator-netlist" else "GHDL " + r["path"].split("-")[1] + ", RTL"
        rows.append([f"{r['width']}x{r['height']}x{r['scales']}", path, f"{r['frame_wall_s']:.2f} s",
                     f"{r['clocks_per_s']:,}", f"{r['features']:,}", "yes" if r["bit_exact"] else "**no**",
                     f"{r['cold_build_s']} s" if "cold_build_s" in r else "-"])  # fmt: skip
    head = ["frame", "path", "frame wall time", "clocks per second", "features", "bit-exact", "cold build"]
    return [*_table(head, rows), "", f"Measured by {_source(run)} ({run['tools']})."]


def bench_driver_table(records: Records) -> list[str]:
    run = records.run("bench", "driver")
    d = run["data"]
    rows, notes = [], []
    for frame in d["runs"]:
        for r in frame["reads"]:
            if r.get("path") == "ddr":
                mode, how = "-", "DDR ring (u-dma-buf, 2 invalidations)"
            else:
                default = " (default)" if r["block_mode"] == "copy" and r["bank_read"] == "bank" else ""
                mode, how = r["block_mode"], r["bank_read"] + default
            rows.append([f"{frame['features']:,}", mode, how,
                         f"{r['read_decode_ms']:.2f} ms", f"{r['bus_reads']:,}", f"{r['host_total_ms']:.2f} ms",
                         f"{r['a9_estimate_ms']:.1f} ms"])  # fmt: skip
        notes.append(f"{frame['features']:,} features: message build and serialisation "
                     f"{frame['message_numpy_msg_ms']:.2f} ms with `numpy_msg` "
                     f"({frame['message_plain_genpy_ms']:.2f} ms plain genpy), {frame['message_bytes']:,} bytes; "
                     f"wait for the interrupt, round trip {frame['wait_irq_roundtrip_ms']:.3f} ms.")  # fmt: skip
    head = ["features", "UioBus block mode", "bank read", "read + decode", "32-bit bus reads", "+ message",
            "Cortex-A9 estimate"]  # fmt: skip
    assume = (f"Cortex-A9 estimate (not measured): this machine's time x {d['a9_slowdown']:g} plus "
              f"{d['a9_axi_read_us']} us per bus access")  # fmt: skip
    if "a9_sync_call_us" in d:
        assume += (f"; the DDR ring also {d['a9_sync_call_us']:g} us per sync_for_cpu call, "
                   f"{d['a9_invalidate_line_ns']:g} ns per 32-byte line invalidated and "
                   f"{d['a9_ddr_read_ns_per_byte']:g} ns per byte read from DDR")  # fmt: skip
    out = [*_table(head, rows), "", *notes, assume + ".", ""]
    frames = [(f["features"], x, f["decode_ms"]) for f in d["runs"] for x in f.get("frames", [])]
    if frames:
        by = {(n, x["path"]): x for n, x, _ in frames}
        frows = []
        for n, x, _ in frames:
            ratio = ["", ""]
            if x["path"] == "ddr":
                b = by[(n, "bank")]
                ratio = [f"{b[k] / x[k]:.1f}x" for k in ("a9_frame_ms", "a9_transfer_ms")]
            frows.append([f"{n:,}", "DDR ring" if x["path"] == "ddr" else "bank (default)",
                          f"{x['frame_reads']:,} + {x['frame_writes']}", f"{x['frame_ms']:.3f} ms",
                          f"{x['a9_frame_ms']:.2f} ms", f"{x['a9_transfer_ms']:.2f} ms", *ratio])  # fmt: skip
        fhead = ["features", "feature memory", "32-bit reads + writes per frame", "`next_frame` here",
                 "Cortex-A9 estimate", "without the decoding", "bank / DDR", "bank / DDR, without the decoding",
                 ]  # fmt: skip
        decodes = ", ".join(f"{n:,} features {decode:.3f} ms" for n, x, decode in frames if x["path"] == "bank")
        out += ["A whole frame (`next_frame`: the interrupt, the status, the read, the decoding, the counters, the "
                "release), the default bank read against the DDR ring:", "", *_table(fhead, frows), "",
                f"The decoding alone (the same code on both paths), here: {decodes}; \"without the decoding\" is "
                f"the estimate less {d['a9_slowdown']:g} times it.", ""]  # fmt: skip
    return [*out, f"Measured by {_source(run)} ({run['tools']}; median of {d['repeat']})."]


GIGABIT_BYTES_S = 125e6  # 1 Gb/s (the Zybo Z7-20's Ethernet) in bytes per second, before framing overheads


def bench_stream_table(records: Records) -> list[str]:
    run = records.run("bench", "stream")
    d = run["data"]
    slowdown = records.run("bench", "driver")["data"]["a9_slowdown"]  # the driver's stated factor, one source
    rows = []
    for r in d["runs"]:
        rows.append([f"{r['features']:,}", f"{r['message_bytes']:,} B", f"{r['bytes_per_feature']:g}",
                     f"{r['encode_ms']:.3f} ms", f"{r['decode_ms']:.3f} ms", f"{r['loopback_ms']:.3f} ms",
                     f"{r['message_bytes'] * 60 / 1e6:.1f} MB/s",
                     f"{r['message_bytes'] / GIGABIT_BYTES_S * 1e3:.2f} ms",
                     f"{r['encode_ms'] * slowdown:.2f} ms"])  # fmt: skip
    head = ["features", "FRAME message", "bytes per feature", "encode (server, once per frame)",
            "decode (client)", "publish() to the client's Frame, loopback", "at 60 frames/s", "on 1 Gb/s",
            "encode, Cortex-A9 estimate"]  # fmt: skip
    notes = (f"The last three columns are arithmetic, not measurements: the message's bytes at 60 frames/s, its "
             f"time on a 1 Gb/s link (payload only), and the encoding time x {slowdown:g} (the driver benchmark's "
             f"assumed CPython slowdown of the board's Cortex-A9).")  # fmt: skip
    return [*_table(head, rows), "", notes, "",
            f"Measured by {_source(run)} ({run['tools']}; protocol version {d['protocol_version']}; median of "
            f"{d['repeat']})."]  # fmt: skip


def bench_ros2_table(records: Records) -> list[str]:
    run = records.run("bench", "ros2")
    d = run["data"]
    rows = [[f"{r['features']:,}", f"{r['build_ms']:.3f} ms", f"{r['serialize_ms']:.3f} ms",
             f"{r['publish_ms']:.3f} ms", f"{r['build_ms'] + r['publish_ms']:.3f} ms", f"{r['deserialize_ms']:.3f} ms",
             f"{r['message_bytes']:,}"] for r in d["runs"]]  # fmt: skip
    head = ["features", "build from the Frame", "serialise (CDR)", "publish (no subscriber)", "node: build + publish",
            "subscriber: deserialise", "bytes"]  # fmt: skip
    return [*_table(head, rows), "", f"Measured by {_source(run)} ({run['tools']}; median of {d['repeat']})."]


def synth_table(records: Records) -> list[str]:
    rows = []
    for key, j in sorted(records.synth.items(), key=lambda kv: (kv[0].split()[0], kv[0])):
        top, size, *generics = key.split()
        delay = f"{j['logic_delay_ns']:.3f} ns" if j.get("logic_delay_ns") is not None else "-"
        m = j["measured"]
        rows.append([f"`{top}`", size, ", ".join(f"`{g}`" for g in generics) or "the top's defaults",
                     f"{j['lut']:,} ({100 * j['lut'] / XC7Z020['lut']:.1f}%)", f"{j['ff']:,}", f"{j['bram36']:g}",
                     str(j["dsp"]), delay,
                     f"{m['commit']}, {m['date']}{records.age(m.get('hdl_digest'))}"])  # fmt: skip
    head = ["top", "W x H x levels", "other generics", "LUT (of the XC7Z020)", "FF", "RAMB36", "DSP48",
            "logic delay (pre-route)", "commit, date"]  # fmt: skip
    return [*_table(head, rows), "", f"From `{SYNTH}` (yosys estimates; the commands and wall times are there)."]


def _span(v: list[float]) -> str:
    lo, hi = (f"{x:,g}" if isinstance(x, float) else f"{x:,}" for x in v)
    return lo if lo == hi else f"{lo} to {hi}"


def blocks_table(records: Records, only: tuple[str, ...] = ()) -> list[str]:
    """Each entity's own cells in the board builds (the `blocks` of their synth_expected.json
    entries): per build LUT / FF / RAMB36 / DSP48, the smallest to the largest over its variants."""
    jobs = {name: _board_job(records, name)[1] for name in records.board["configs"]}
    for name, j in jobs.items():
        if "blocks" not in j:
            raise ResultsError(f"{SYNTH}: the board configuration {name} has no 'blocks': measure it with "
                               "make synth CONFIG=... TOP=orb_accel_zynq UPDATE=1")  # fmt: skip
    names = sorted({b for j in jobs.values() for b in j["blocks"]} if not only else only)
    rows = []
    for b in names:
        cells = []
        for j in jobs.values():
            f = j["blocks"].get(b)
            cells.append(" / ".join(_span(f[k]) for k in ("lut", "ff", "bram36", "dsp")) if f else "-")
        variants = sorted({j["blocks"][b]["variants"] for j in jobs.values() if b in j["blocks"]})
        rows.append([f"`{b}`", " / ".join(map(str, variants)), *cells])
    head = ["entity", "variants", *(f"{n}: LUT / FF / RAMB36 / DSP48" for n in jobs)]
    commits = sorted({f"{j['measured']['commit']}, {j['measured']['date']}" for j in jobs.values()})
    return [
        *_table(head, rows),
        "",
        f"From the `blocks` of `{SYNTH}` (yosys estimates; measured at {'; '.join(commits)}).",
    ]


def _endpoint(text: str) -> str:
    """A path's endpoint in words: a register's name, or a primitive abc named, by its type and pin."""
    m = re.fullmatch(r"\$abc\$\S+ \((\w+)\.(\w+)\)", text)
    return f"a {m[1]}'s {m[2]} input" if m else f"`{text}`"


def worst_paths_table(records: Records) -> list[str]:
    """The board builds' worst register-to-register paths (the `timing` of their entries)."""
    rows = []
    for name in records.board["configs"]:
        _, j = _board_job(records, name)
        if "timing" not in j:
            raise ResultsError(f"{SYNTH}: the board configuration {name} has no 'timing': measure it with "
                               "make synth CONFIG=... TOP=orb_accel_zynq UPDATE=1")  # fmt: skip
        t = j["timing"]
        for p in t["worst_paths"]:
            rows.append([name, f"{p['delay_ns']:.3f} ns", str(p["lut_levels"]), f"`{p['start']}`",
                         _endpoint(p["endpoint"])])  # fmt: skip
        rows.append([name, f"endpoint bits over {t['goal_ns']} ns: {t['endpoints_over_goal']:,} of "
                           f"{t['endpoints']:,}", "", "", ""])  # fmt: skip
    head = ["build", "logic delay", "LUT levels", "from", "to"]
    return [*_table(head, rows), "", f"From the `timing` of `{SYNTH}` (yosys `sta`, pre-route estimates; the "
            "whole list per build: build/synth/orb_accel_zynq/<job>/timing.md)."]  # fmt: skip


def test_table(records: Records) -> list[str]:
    rows = []
    for run in records.test.values():
        d = run["data"]
        counts = ", ".join(f"{n:,} {kind}" for kind, n in d["counts"].items())
        total = f"{d['total_s'] / 60:.1f} min" if "total_s" in d else "-"
        rows.append([f"`{run['command']}`", counts, f"{d['pytest_s'] / 60:.1f} min", total, d["machine"],
                     f"{run['commit']}, {run['date']}"])  # fmt: skip
    head = ["command", "tests", "pytest's time", "whole command", "machine", "commit, date"]
    return _table(head, rows)


def formal_table(records: Records) -> list[str]:
    """The checks of the whole run (make-formal), each replaced by the newest run of some checks
    (make formal K=...) that holds it; the footer says which run measured which checks."""
    whole = records.run("formal", "make-formal")
    runs = sorted(records.formal.values(), key=lambda r: (r["date"], r is not whole))
    source: dict[str, dict[str, Any]] = {}
    for run in runs:
        for k in run["data"]:
            source[k] = run
    missing = [k for k in formal.CHECKS if k not in source]
    if missing:
        raise ResultsError(f"docs/results/formal.json lacks the checks {', '.join(missing)}: run make formal and "
                           "record it (python -m orb_flow.record formal)")  # fmt: skip
    text = formal.table({k: source[k]["data"][k] for k in formal.CHECKS})
    foot = []
    for run in runs:
        mine = [k for k in formal.CHECKS if source[k] is run]
        if not mine:
            continue
        what = "the other checks" if run is whole and len(runs) > 1 else ", ".join(f"`{k}`" for k in mine)
        foot.append(f"{what}: {_source(run)}{records.age(run.get('hdl_digest'))} ({run['tools']})")
    return [*text.rstrip("\n").split("\n"), "", "Measured by " + "; ".join(foot) + "."]


def sim_table(records: Records) -> list[str]:
    rows = []
    for run in records.sim.values():
        d = run["data"]
        what = Path(d.get("image") or d.get("video", "")).name
        engine = "netlist in Verilator" if d["engine"] == "verilator-netlist" else "RTL in GHDL"
        device = f"{d['scales']} x {d['step']}, {d['sectors']} sectors, {d['mem_depth']:,} slots"
        if "config" in d:
            device = f"{d['config']}: {device}"
        if "block_log2" in d:
            device += f", {1 << d['block_log2']}-pixel overlay blocks"
        memory = "block RAM"
        if d.get("mem_kind") == "ddr":
            ddr = d.get("ddr", {})
            memory = "DDR ring" + (f", {_int(ddr['axi_bursts'])} bursts" if "axi_bursts" in ddr else "")
        rows.append([f"`{run['command']}`", f"{what} {d['width']}x{d['height']}", device, memory, engine,
                     _int(d["features"]), "yes" if d["bit_exact"] and d.get("overlay_bit_exact", True) else "**no**",
                     str(d["dropped"]), str(d.get("latency_cycles", "-")), f"{d['sim_wall_s']:,.0f} s",
                     f"{run['commit']}, {run['date']}{records.age(run.get('hdl_digest'))}"])  # fmt: skip
    head = ["command", "image", "device", "feature memory", "engine", "features", "bit-exact (features, overlay)",
            "lost", "last pixel to end-of-frame record, clocks", "simulation", "commit, date"]  # fmt: skip
    return _table(head, rows)


HP0_BYTES_PER_S = 8 * 150e6  # S_AXI_HP0: 64 bits at the 150 MHz core clock (docs/feature-dma.md)


def bus_table(records: Records) -> list[str]:
    """docs/feature-dma.md's bus load: per make sim run through the DDR ring, the bursts of 64 bytes a
    frame, the bytes and the share of S_AXI_HP0 at 60 frames a second."""
    rows = []
    for run in records.sim.values():
        d = run["data"]
        ddr = d.get("ddr", {})
        if d.get("mem_kind") != "ddr" or "axi_bursts" not in ddr:
            continue
        frame = ddr["axi_bursts"] * 64
        rate = frame * 60
        errors = ddr.get("axi_slverr", 0) + ddr.get("axi_decerr", 0) + ddr.get("axi_protocol_errors", 0)
        rows.append([f"`{run['command']}`", f"{d['width']}x{d['height']}", _int(d["features"]),
                     _int(ddr["axi_bursts"]), f"{frame / 1e3:,.0f} KB", f"{rate / 1e6:.1f} MB/s",
                     f"{100 * rate / HP0_BYTES_PER_S:.1f} %", str(errors),
                     f"{run['commit']}, {run['date']}{records.age(run.get('hdl_digest'))}"])  # fmt: skip
    if not rows:
        raise ResultsError("docs/results/sim.json has no make sim run through the DDR ring: run make sim "
                           "CONFIG=board-vga FAST=1 and record it (python -m orb_flow.record sim ...)")  # fmt: skip
    head = ["command", "frame", "features", "bursts (64 B)", "bytes a frame", "at 60 frames a second",
            "share of S_AXI_HP0", "bus errors and protocol faults", "commit, date"]  # fmt: skip
    return _table(head, rows)


CAMPAIGN_LABELS = {"no_sof": "no start of frame", "early_sof": "early start of frame", "hold": "CPU holding banks"}


def _kinds(counts: dict[str, int]) -> str:
    return ", ".join(f"{CAMPAIGN_LABELS.get(k, k.replace('_', ' '))} {n:,}" for k, n in counts.items())


def _wall(seconds: float) -> str:
    return f"{seconds / 60:.1f} min" if seconds >= 120 else f"{seconds:.0f} s"


def campaign_table(records: Records) -> list[str]:
    """The recorded fault campaigns (docs/results/campaign.json)."""
    if not records.campaign:
        raise ResultsError("docs/results/campaign.json has no run: run a campaign (tb/fast/test_fast_regressions.py) "
                           "and record it (python -m orb_flow.record campaign ...)")  # fmt: skip
    rows = []
    for run in records.campaign.values():
        d = run["data"]
        g = d["generics"]
        step = f"{g.get('STEP_NUM_g', 2)}:{g.get('STEP_DEN_g', 1)}"
        device = f"{g['WIDTH_g']}x{g['HEIGHT_g']}, {g['SCALES_g']} x {step}, {g['SECTORS_g']} sectors, "
        device += f"{g['MEM_DEPTH_g']:,} slots"
        seed = str(d["seed"]) + (f" (initial state {d['init_seed']})" if d["init_seed"] else "")
        frames = (f"{d['frames_sent']:,} sent; {d['frames_closed_good']:,} closed good, "
                  f"{d['frames_closed_bad']:,} bad; {d['frames_published']:,} published, "
                  f"{d['frames_skipped_bank_held']:,} skipped (bank held)")  # fmt: skip
        bad = {k: str(d[k]) if d[k] == 0 else f"**{d[k]}**" for k in ("lockups", "mismatches")}
        rows.append([f"`{run['command']}`", device, seed, f"{d['events']:,}", frames,
                     f"{d['faults_injected']:,}: {_kinds(d['faults_by_kind'])}", _kinds(d["changes_by_kind"]),
                     bad["lockups"], bad["mismatches"], f"{d['features_checked']:,}",
                     f"{_wall(d['wall_s'])}, {d['machine']}",
                     f"{run['commit']}, {run['date']}{records.age(run.get('hdl_digest'))}"])  # fmt: skip
    head = ["command", "device", "seed", "events", "frames", "faults injected", "changes (each with a good frame)",
            "lock-ups", "mismatches", "features checked", "wall time", "commit, date"]  # fmt: skip
    return _table(head, rows)


def _board_job(records: Records, name: str) -> tuple[str, dict[str, Any]]:
    """The synthesis record of a board configuration (its job's name: orb_flow.synth.generics_job).
    A configuration whose own build has no record yet (its HDL or generics changed and the slow
    board synthesis has not been run again) gets the newest record of the same frame and pyramid
    with the block-RAM memory, marked `stale` with what was measured instead: the tables say so
    (standard 8: a record is evidence only for what it measured)."""
    from orb_flow.synth import generics_job

    c = records.board["configs"][name]
    key = generics_job("orb_accel_zynq", c).name
    if key in records.synth:
        return key, records.synth[key]
    prefix = f"orb_accel_zynq {c['width']}x{c['height']}x{c['scales']} MEM_DEPTH_g="
    rest = f" STEP_NUM_g={c['step_num']} STEP_DEN_g={c['step_den']} BLOCK_LOG2_g={c['block_log2']}"
    older = [(j["measured"]["date"], k) for k, j in records.synth.items()
             if k.startswith(prefix) and k.endswith(rest) and "MEM_KIND_g" not in k]  # fmt: skip
    if not older:
        raise ResultsError(f"{SYNTH} has no entry {key!r} for the board configuration {name}")
    k = max(older)[1]
    depth = int(k[len(prefix) :].split()[0])
    j = dict(records.synth[k])
    kind = c.get("mem_kind", "bram").upper()
    j["stale"] = (f"the block-RAM build ({depth:,}-slot banks) at {j['measured']['commit']}: the "
                  f"{kind} build of {c['mem_depth']:,} slots is not yet synthesised")  # fmt: skip
    return k, j


def board_table(records: Records) -> list[str]:
    rows = []
    for name, c in records.board["configs"].items():
        _, j = _board_job(records, name)
        rows.append([name, f"{c['scales']} x {c['step_num']}:{c['step_den']}, {c['sectors']} sectors, "
                           f"{c['mem_depth']:,} slots",
                     f"{j['lut']:,} ({100 * j['lut'] / XC7Z020['lut']:.1f}%)", f"{j['ff']:,}",
                     f"{j['bram36']:g} ({100 * j['bram36'] / XC7Z020['bram36']:.1f}%)",
                     f"{j['dsp']} ({100 * j['dsp'] / XC7Z020['dsp']:.1f}%)", f"{j['logic_delay_ns']:.3f} ns",
                     f"{1000 / c['core_mhz']:.2f} ns ({c['core_mhz']} MHz)",
                     f"{j['measured']['commit']}, {j['measured']['date']}"
                     + (f" (**stale**: {j['stale']})" if "stale" in j
                        else records.age(j["measured"].get("hdl_digest"))),
                     "not run"])  # fmt: skip
    head = ["configuration", "device", "LUT", "FF", "RAMB36", "DSP48", "logic delay (pre-route)",
            "core clock period", "commit, date", "Vivado"]  # fmt: skip
    return _table(head, rows)


def _frames_lost(r: dict[str, Any] | None) -> str:
    if r is None:
        return "-"
    after = r["lost"] - 1
    text = f"{r['lost']} (the event frame{f' and {after} after it' if after else ' only'})"
    return text if after else f"**{text}**"


def recovery_table(records: Records) -> list[str]:
    """The board's recovery after a cut (orb_flow.board.recovery): frames lost per configuration and
    event, with the old checker (IDLE_TIMEOUT_g 0) and the board's."""
    if not records.recovery:
        raise ResultsError("docs/results/recovery.json has no run: measure it (python -m orb_flow.board.recovery) "
                           "and record it (python -m orb_flow.record recovery)")  # fmt: skip
    rows, sources, timeouts = [], [], set[int]()
    for run in records.recovery.values():
        sources.append(f"Measured by {_source(run)} ({run['tools']}).")
        cases: dict[tuple[str, str, float], dict[int, dict[str, Any]]] = {}
        for r in run["data"]:
            cases.setdefault((r["config"], r["event"], r["at"]), {})[r["idle_timeout"]] = r
        for (config, event, _), by in cases.items():
            old, new = by.get(0), next((r for t, r in sorted(by.items()) if t), None)
            r = new or old
            assert r is not None
            height = int(config.split("x")[1])  # board configurations are named WIDTHxHEIGHT
            line = r["cut_after_pixels"] // (r["pixels"] // height)
            if event == "cut":
                out_ms = r["cable_out_pixel_clocks"] / r["pixel_mhz"] / 1000
                what = f"cable out in line {line} of {height}, for {out_ms:.1f} ms"
            else:
                what = f"a start of frame in line {line} of {height} (a restart, no gap)"
            dropped = " / ".join(f"{x['fifo_dropped']:,}" if x else "-" for x in (old, new))
            timeouts.update(t for t in by if t)
            rows.append([config, f"{r['pixel_mhz']:g} / {r['core_mhz']} MHz", what, _frames_lost(old),
                         _frames_lost(new), dropped])  # fmt: skip
    board = ", ".join(f"{t:,}" for t in sorted(timeouts)) or "-"
    head = ["configuration", "pixel / core clock", "event", "frames lost: old checker (IDLE_TIMEOUT_g 0)",
            f"frames lost: the board's checker (IDLE_TIMEOUT_g {board})",
            "pixels the input FIFO dropped (old / board's)"]  # fmt: skip
    return [*_table(head, rows), "", *sources]


def _power_run(records: Records) -> dict[str, Any]:
    if not records.power:
        raise ResultsError("docs/results/power.json has no run: measure it (make power) and record it "
                           "(python -m orb_flow.record power)")  # fmt: skip
    return list(records.power.values())[-1]


def _power_latest(records: Records) -> dict[str, tuple[dict[str, Any], dict[str, Any]]]:
    """Each configuration's newest power estimate: configuration -> (its run, its record). A run
    named what-if-* (another clock, a study) is not a configuration's estimate."""
    _power_run(records)
    latest: dict[str, tuple[dict[str, Any], dict[str, Any]]] = {}
    runs = sorted((run["date"], run["commit"] != "-", k, run) for k, run in records.power.items()
                  if not k.startswith("what-if"))  # fmt: skip
    for *_, run in runs:  # the later measurement of a configuration replaces the earlier
        for r in run["data"]:
            latest[r["config"]] = (run, r)
    return latest


def _band(d: dict[str, float], fmt: str = "{:.0f}") -> str:
    return f"{fmt.format(d['typ'])} ({fmt.format(d['low'])}-{fmt.format(d['high'])})"


def power_table(records: Records) -> list[str]:
    """make power's estimate per recorded run and configuration: resources, activity, dynamic power
    and energy a frame with the coefficients' band, the vectorless figure, the thesis's Table 5.3
    beside its device."""
    last = _power_run(records)
    rows = []
    for name, run in records.power.items():
        for r in run["data"]:
            res = r["resources"]
            thesis = f"{r['thesis_mw']} mW, {r['thesis_mj']} mJ" if "thesis_mw" in r else "-"
            rows.append([f"{name}: `{r['config']}`",
                         f"{r['width']}x{r['height']}, {r['scales']} levels, {r['sectors']} sectors",
                         f"{res['lut']:,} / {res['ff']:,} / {res['bram36']:g} / {res['dsp']}",
                         f"{r['pixel_mhz']:g} / {r['core_mhz']} MHz", f"{100 * r['mean_activity']:.1f}%",
                         _band(r["dynamic_mw"]), _band(r["energy_mj"], "{:.2f}"), _band(r["dynamic_vectorless_mw"]),
                         thesis, f"{run['commit']}, {run['date']}{records.age(run.get('hdl_digest'))}"])  # fmt: skip
    head = ["run: configuration", "frame, pyramid", "LUT / FF / RAMB36 / DSP48 (yosys)", "pixel / core clock",
            "register activity (toggles a bit a clock)", "dynamic power, mW (band)",
            "energy a frame at 60 fps, mJ (band)", "vectorless (12.5%, BRAM 0.5/0.5), mW (band)",
            "the thesis's Table 5.3", "measured"]  # fmt: skip
    static = last["data"][0]
    commands = "; ".join(f"{n}: `{r['command']}` ({r['tools']})" for n, r in records.power.items())
    unprobed = ", ".join(f"{c} {r['bram_unprobed']['tiles']:g} tiles, {r['bram_unprobed']['mw']:.1f} mW"
                         for c, (_, r) in _power_latest(records).items() if "bram_unprobed" in r)  # fmt: skip
    foot = [f"Commands: {commands}. Static power (the device's, not in the columns): "
            f"{1000 * static['static_device_w']:.0f} mW at a junction of {static['static_tj_c']} C, of it "
            f"{1000 * static['static_pl_w']:.0f} mW on the PL's rails. Block RAM without an enable probe (a memory "
            f"outside orb_sdp_ram, at Vivado's default enables; newest runs): {unprobed or '-'}."]  # fmt: skip
    return [*_table(head, rows), "", *foot]


def power_classes_table(records: Records) -> list[str]:
    """make power's dynamic power per resource class (typ coefficients), measured and vectorless: each
    configuration's newest estimate."""
    latest = _power_latest(records)
    classes = list(next(iter(latest.values()))[1]["by_class_mw"])
    rows = []
    for config, (run, r) in latest.items():
        mw, vec = r["by_class_mw"], r["by_class_vectorless_mw"]
        rows.append([f"`{config}` at {r['core_mhz']} MHz", *(f"{mw[k]:.1f} ({vec[k]:.1f})" for k in classes),
                     f"{run['commit']}{records.age(run.get('hdl_digest'))}"])  # fmt: skip
    head = ["configuration", *(f"{k}, mW (vectorless)" for k in classes), "measured"]
    return _table(head, rows)


def power_entities_table(records: Records) -> list[str]:
    """make power's largest entities per configuration (typ coefficients): each configuration's
    newest estimate."""
    rows = []
    for config, (run, r) in _power_latest(records).items():
        for ent, p in list(r["by_entity_mw"].items())[:8]:
            en = (f"{100 * p['bram_read_enable']:.0f}% / {100 * p['bram_write_enable']:.0f}%"
                  if "bram_read_enable" in p else "-")  # fmt: skip
            act = f"{100 * p['activity']:.1f}%" if "activity" in p else "-"
            rows.append([f"`{config}` ({run['commit']})", f"`{ent}`", f"{p['total']:.1f}", act, en,
                         f"{p.get('clock', 0):.1f}", f"{p.get('signal', 0) + p.get('lut', 0):.1f}",
                         f"{p.get('bram', 0):.1f}", f"{p.get('dsp', 0):.1f}"])  # fmt: skip
    head = ["configuration (commit)", "entity (all its instances)", "mW", "register activity",
            "RAM read / write enable", "clock, mW", "LUT + routing, mW", "block RAM, mW", "DSP48, mW"]  # fmt: skip
    return _table(head, rows)


def power_coefficients_table(records: Records) -> list[str]:
    """The coefficients (sw/orb_flow/power_coefficients.json) with their band and their sources."""
    data = json.loads((records.root / COEFFICIENTS).read_text())
    rows = []
    for name, c in data["coefficients"].items():
        points = ", ".join(f"{s['report']} {s['value']:g}{' (bound)' if s.get('upper_bound') else ''}"
                           for s in c["sources"] if s.get("value") is not None)  # fmt: skip
        rows.append([f"`{name}`", f"{c['typ']:g}", f"{c['low']:g}-{c['high']:g}", c["unit"], points or "-"])
    reports = {}
    for c in data["coefficients"].values():
        for s in c["sources"]:
            reports.setdefault(s["report"], f"{s['report']}: `{s['repo']}` `{s['path']}` at {s['commit']} "
                                            f"({s.get('part') or '?'}; {s.get('activity') or '?'})")  # fmt: skip
    head = ["coefficient", "typ", "band (low-high)", "unit", "the reports' point values"]
    return [*_table(head, rows), "", "Reports (Vivado report_power of routed designs, public repositories):", "",
            *(f"- {reports[k]}" for k in sorted(reports))]  # fmt: skip


def _power_headline(records: Records) -> list[str]:
    """The README's power row: each board configuration's newest dynamic power and energy a frame,
    the thesis's 2-scale, 32-sector row beside it."""
    cells = [f"{c}: {r['dynamic_mw']['typ']:.0f} mW ({r['dynamic_mw']['low']:.0f}-{r['dynamic_mw']['high']:.0f}) "
             f"at {r['core_mhz']} MHz, {r['energy_mj']['typ']:.2f} mJ a frame (commit {run['commit']})"
             f"{records.age(run.get('hdl_digest'))}"
             for c, (run, r) in _power_latest(records).items() if c.startswith("board-")]  # fmt: skip
    mw, mj = THESIS_TABLE[(2, 32)]  # the thesis's Table 5.3 row of its 2-scale, 32-sector device
    return ["Dynamic power and energy a frame at 60 fps, estimate (yosys resources x Verilator activity x coefficients "
            "from published Vivado reports; not run in Vivado or on a board)", "<br>".join(cells),
            f"the thesis (Table 5.3, 2 scales, 32 sectors): {mw} mW, {mj} mJ", "[power.md](docs/power.md)"]  # fmt: skip


def headline(records: Records) -> list[str]:
    held = {r["extractor"]: r for r in records.run("eval", "scale-bench-held")["data"]}
    rot = {r["method"]: r for r in records.run("eval", "rotation-bench-grid")["data"]}
    track = {(r["extractor"], r["gap"]): r for r in records.run("eval", "track-bench")["data"]["summary"]}
    view = {(r["extractor"], str(r["tilt"])): r for r in records.run("eval", "viewpoint-bench-held")["data"]}
    traj = {r["extractor"]: r for r in records.run("eval", "trajectory-bench")["data"] if r["sequence"] == "wall"}
    dens = records.run("eval", "density-bench")["data"]["summary"]
    simrun = records.run("sim", "make-sim")
    sim = simrun["data"]
    ours_h, cv_h = held["5:4x5s64/g1000"], held["cv-default@5:4x5s64/g1000"]
    ours_r = next(r for m, r in rot.items() if m != "opencv")
    empty = {x: sum(r["corner_cells_empty"] for r in dens if r["extractor"] == x) for x in ("ours", "cv-ours")}
    cells = sum(r["corner_cells"] for r in dens if r["extractor"] == "ours")
    boards = []
    for name in records.board["configs"]:
        _, j = _board_job(records, name)
        boards.append(f"{name}: {j['lut']:,} LUT ({100 * j['lut'] / XC7Z020['lut']:.0f}%), "
                      f"{j['bram36']:g} RAMB36, {j['dsp']} DSP48, {j['logic_delay_ns']:.2f} ns pre-route logic delay"
                      + (" (block-RAM build: not yet synthesised with the DDR ring)" if "stale" in j
                         else records.age(j["measured"].get("hdl_digest"))))  # fmt: skip
    rows = [
        ["Matching under scale change (32 held-out photographs, 0.6 to 1.0)",
         f"**{_pct(ours_h['pooled_pct'])}**", f"{_pct(cv_h['pooled_pct'])} (OpenCV ORB, its defaults, same count)",
         "[evaluation.md](docs/evaluation.md#scale-bench-on-the-held-out-photographs)"],
        ["Matching under rotation (32 sectors, 72 angles)", f"**{_pct(ours_r['mean_correct_pct'])}** correct",
         f"{_pct(rot['opencv']['mean_correct_pct'])} (OpenCV ORB, same count)",
         "[evaluation.md](docs/evaluation.md#rotation-with-the-selection)"],
        ["Matching under a change of viewpoint (32 held-out photographs, tilts 0 to 60 degrees, both axes)",
         f"**{_pct(view[('5:4x5s64/g1000', 'pooled')]['score_pct'])}**",
         f"{_pct(view[('cv-default@5:4x5s64/g1000', 'pooled')]['score_pct'])} (OpenCV ORB, its defaults, same count)",
         "[evaluation.md](docs/evaluation.md#viewpoint-change-issue-39)"],
        ["Stereo odometry on the rendered diver sequence: ATE, lost frames "
         f"({traj['5:4x5s64/g1000']['frames']} frames, {traj['5:4x5s64/g1000']['budget']:,} features)",
         f"**{traj['5:4x5s64/g1000']['ate_m'] * 100:.2f} cm, {traj['5:4x5s64/g1000']['lost']} lost**",
         f"{traj['cv-default']['ate_m'] * 100:.2f} cm, {traj['cv-default']['lost']} lost (OpenCV ORB); "
         f"{traj['orbslam']['ate_m'] * 100:.2f} cm, {traj['orbslam']['lost']} lost (ORB-SLAM-style)",
         "[evaluation.md](docs/evaluation.md#trajectory-issue-39)"],
        ["Tracking: inliers per feature, frame gap 1 / 5 (9 clips)",
         f"**{track[('ours', 1)]['inliers_per_feature']:.3f} / {track[('ours', 5)]['inliers_per_feature']:.3f}**",
         f"{track[('opencv', 1)]['inliers_per_feature']:.3f} / {track[('opencv', 5)]['inliers_per_feature']:.3f}",
         "[evaluation.md](docs/evaluation.md#tracking)"],
        ["Spread: cells with a corner left without a feature (3 sizes, 2 contrasts)",
         f"**{empty['ours']} of {cells:,}**", f"{empty['cv-ours']:,} (OpenCV ORB, same count)",
         "[evaluation.md](docs/evaluation.md#dense-and-sparse-scenes)"],
        ["Board resources, yosys estimate (XC7Z020; not run in Vivado)", "<br>".join(boards), "-",
         "[board.md](docs/board.md#resources)"],
        ["Throughput", "one pixel per clock: 1080p60, 720p60 and 480p60 HDMI in real time (design; not run on a board)",
         "-", "[board.md](docs/board.md)"],
        _power_headline(records),
        ["`make sim`: the bundled photograph in GHDL", f"{sim['features']:,} features, bit-exact, "
         f"{sim['dropped']} lost, {sim['sim_wall_s']:.0f} s (commit {simrun['commit']})"
         f"{records.age(simrun.get('hdl_digest'))}", "-", "[fast-sim.md](docs/fast-sim.md#results)"],
    ]  # fmt: skip
    return _table(["", "this accelerator", "reference", "where"], rows)


TABLES: dict[str, tuple[Path, Callable[[Records], list[str]]]] = {
    "headline": (Path("README.md"), headline),
    "compare-fast": (Path("docs/evaluation.md"), compare_fast_table),
    "rotation-bench": (Path("docs/evaluation.md"), lambda r: rotation_table(r, "rotation-bench")),
    "scale-bench": (Path("docs/evaluation.md"), lambda r: scale_table(r, "scale-bench")),
    "scale-bench-held": (Path("docs/evaluation.md"), lambda r: scale_table(r, "scale-bench-held")),
    "rotation-bench-grid": (Path("docs/evaluation.md"), lambda r: rotation_table(r, "rotation-bench-grid")),
    "track-bench": (Path("docs/evaluation.md"), track_tables),
    "viewpoint-bench-held": (Path("docs/evaluation.md"), viewpoint_table),
    "trajectory-bench": (Path("docs/evaluation.md"), trajectory_table),
    "density-bench": (Path("docs/evaluation.md"), density_table),
    "sim-runs": (Path("docs/fast-sim.md"), sim_table),
    "campaigns": (Path("docs/fast-sim.md"), campaign_table),
    "bench-model": (Path("docs/benchmarks.md"), bench_model_table),
    "bench-sim": (Path("docs/benchmarks.md"), bench_sim_table),
    "board-resources": (Path("docs/board.md"), board_table),
    "board-recovery": (Path("docs/board.md"), recovery_table),
    "bench-driver": (Path("docs/ros.md"), bench_driver_table),
    "bench-stream": (Path("docs/stream.md"), bench_stream_table),
    "bench-ros2": (Path("docs/ros2.md"), bench_ros2_table),
    "synth-jobs": (Path("docs/synthesis.md"), synth_table),
    "synth-blocks": (Path("docs/synthesis.md"), blocks_table),
    "select-blocks": (Path("docs/selection.md"), lambda r: blocks_table(r, ("orb_harris", "orb_feat_select"))),
    "board-worst-paths": (Path("docs/synthesis.md"), worst_paths_table),
    "make-test": (Path("docs/conventions.md"), test_table),
    "formal": (Path("docs/formal.md"), formal_table),
    "bus-load": (Path("docs/feature-dma.md"), bus_table),
    "power": (Path("docs/power.md"), power_table),
    "power-classes": (Path("docs/power.md"), power_classes_table),
    "power-entities": (Path("docs/power.md"), power_entities_table),
    "power-coefficients": (Path("docs/power.md"), power_coefficients_table),
}


def fill(text: str, name: str, lines: list[str], page: Path) -> str:
    begin = BEGIN.format(name=name)
    pattern = re.compile(re.escape(begin) + r"\n.*?" + re.escape(END), re.S)
    if len(pattern.findall(text)) != 1:
        raise ResultsError(f"{page} must hold the table {name!r} once, between `{begin}` and `{END}`")
    return pattern.sub(lambda _: "\n".join([begin, *lines, END]), text)


def render(root: Path = ROOT) -> dict[Path, str]:
    records = Records(root)
    pages: dict[Path, str] = {}
    for name, (page, make) in TABLES.items():
        text = pages.get(page) or (root / page).read_text()
        pages[page] = fill(text, name, make(records), page)
    return pages


def main(argv: list[str] | None = None) -> None:
    views_main(__doc__, render, ROOT, argv)


if __name__ == "__main__":
    main()
