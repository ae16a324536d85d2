# SPDX-License-Identifier: MIT
"""Fast checks of the synthesis-estimate flow (sw/orb_flow/synth.py) without running GHDL or yosys:
the expected-values comparison, the cache key, the committed expected values and the time estimates."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from orb_flow import synth
from orb_flow.board import estimate

ROOT = Path(__file__).resolve().parents[2]

EXPECTED: dict[str, Any] = {
    "tolerance_pct": 2,
    "jobs": {
        "orb_core 640x480x1": {"lut": 10000, "ff": 9000, "bram36": 13.5, "dsp": 8, "logic_delay_ns": 5.0},
        "orb_accel_top 640x480x2": {"lut": 20000, "tolerance_pct": 5},
    },
}


def record(top: str = "orb_core", cfg: str = "640x480x1", **figures: Any) -> dict[str, Any]:
    rec = synth.new_record(synth.job(top, cfg), "key")
    rec.update(lut=10000, ff=9000, bram36=13.5, dsp=8)
    rec.update(figures)
    return rec


# --- the expected-values check ---------------------------------------------------------------


def test_check_within_tolerance_is_ok() -> None:
    c = synth.check_record(record(lut=10200, ff=8820), EXPECTED)  # +2 %, -2 %: on the limits
    assert c.status == "ok"
    # logic_delay_ns is expected but the sta pass did not run: a note, not a failure
    assert any("logic_delay_ns" in m and "not checked" in m for m in c.messages)


def test_check_regression_fails_with_expected_got_tolerance() -> None:
    c = synth.check_record(record(lut=10201), EXPECTED)
    assert c.status == "fail"
    (msg,) = [m for m in c.messages if "lut" in m]
    assert "expected 10,000" in msg and "got 10,201" in msg and "± 2 %" in msg and "regression" in msg
    assert "9,800..10,200" in msg


@pytest.mark.parametrize(
    ("figure", "value"),
    [("ff", 9200), ("bram36", 14.0), ("dsp", 9), ("bram36", 13.0), ("dsp", 7), ("logic_delay_ns", 5.2)],
)
def test_check_each_figure_outside_tolerance_fails(figure: str, value: float) -> None:
    c = synth.check_record(record(**{figure: value}), EXPECTED)
    assert c.status == "fail"
    assert [m for m in c.messages if f" {figure} expected" in m and "got" in m]


def test_check_lower_than_expected_also_fails() -> None:
    c = synth.check_record(record(lut=9000), EXPECTED)
    assert c.status == "fail"
    assert any("lower" in m and "update" in m for m in c.messages)


def test_check_missing_figure_fails() -> None:
    assert synth.check_record(record(lut=None), EXPECTED).status == "fail"


def test_check_per_job_tolerance_and_no_expectation() -> None:
    assert synth.check_record(record("orb_accel_top", "640x480x2", lut=20900), EXPECTED).status == "ok"
    assert synth.check_record(record("orb_accel_top", "640x480x2", lut=21100), EXPECTED).status == "fail"
    c = synth.check_record(record(cfg="1920x1080x1"), EXPECTED)
    assert c.status == "no expectation"


# --- the committed expected values --------------------------------------------------------


def test_expected_file_parses_and_names_known_jobs() -> None:
    data = synth.load_expected()
    known = {(t, c) for t, c in (*synth.DEFAULT_JOBS, *synth.OTHER_JOBS)}
    board = {j.name for j in synth.board_jobs()}
    # a board frame's earlier build (another memory or depth) stays as the tables' stale stand-in
    # until its present build is synthesised (orb_flow.gen.results._board_job)
    frames = {(j.top, j.cfg.name) for j in synth.board_jobs()}
    assert 0 < data["tolerance_pct"] <= 10
    for name, entry in data["jobs"].items():
        j = synth.parse_job_name(name)
        assert j.name == name, f"{name} is not in the script's spelling ({j.name})"
        assert (j.top, j.cfg.name) in known | frames or name in board, f"{name} is not a job the script knows"
        assert {"commit", "date", "command"} <= set(entry["measured"]), name
    for top, cfg in synth.DEFAULT_JOBS:  # the default set is always checked
        entry = data["jobs"][f"{top} {cfg}"]
        assert all(isinstance(entry[k], (int, float)) for k in ("lut", "ff", "bram36", "dsp")), entry


def test_board_jobs_are_estimate_pys_runs() -> None:
    """make board-estimate runs exactly the jobs whose names synth_expected.json holds for the board."""
    cmds = estimate.commands(2, False)
    names = set()
    for cmd in cmds:
        top = cmd[cmd.index("--top") + 1]
        configs = [cmd[i + 1] for i, a in enumerate(cmd) if a == "--config"]
        generics = [cmd[i + 1] for i, a in enumerate(cmd) if a == "--generic"]
        names |= {" ".join([top, c, *generics]) for c in configs}
    assert names == {j.name for j in synth.board_jobs()}


def test_load_expected_rejects_bad_files(tmp_path: Path) -> None:
    bad = [
        {"jobs": {}},  # no tolerance
        {"tolerance_pct": 2, "jobs": {"orb_nothing 640x480x1": {"lut": 1}}},  # unknown top
        {"tolerance_pct": 2, "jobs": {"orb_core 640x480": {"lut": 1}}},  # bad config
        {"tolerance_pct": 2, "jobs": {"orb_core 640x480x1": {"luts": 1}}},  # no known figure
        {"tolerance_pct": 2, "jobs": {"orb_core 640x480x1": {"lut": "9k"}}},  # not a number
    ]
    for i, data in enumerate(bad):
        p = tmp_path / f"bad{i}.json"
        p.write_text(json.dumps(data))
        with pytest.raises(ValueError):
            synth.load_expected(p)


def test_tops_and_jobs_are_consistent() -> None:
    from orb_sim.hdl import entities

    names = entities()
    for top, extra in synth.TOPS.items():
        assert top in names, f"{top} is not in hdl/manifest.txt"
        text = names[top].path.read_text()
        for generic in extra:
            assert generic in text, f"{top} has no generic {generic}"
    for top, cfg in (*synth.DEFAULT_JOBS, *synth.OTHER_JOBS):
        synth.job(top, cfg)
    assert ("orb_core", "640x480x1") in synth.DEFAULT_JOBS and ("orb_core", "1920x1080x2") in synth.DEFAULT_JOBS


# --- the cache key -------------------------------------------------------------------------


@pytest.fixture
def hdl(tmp_path: Path) -> list[Path]:
    files = []
    for name, text in (("a_pkg.vhd", "package a_pkg is end;"), ("top.vhd", "entity top is end;")):
        (tmp_path / name).write_text(text)
        files.append(tmp_path / name)
    return files


TOOLS = {"ghdl": "GHDL 2.0.0", "yosys": "Yosys 0.23"}


def test_cache_key_is_stable(hdl: list[Path]) -> None:
    g = {"WIDTH_g": 640, "HEIGHT_g": 480, "SCALES_g": 1}
    assert synth.cache_key("orb_core", g, hdl, TOOLS) == synth.cache_key(
        "orb_core", dict(reversed(g.items())), hdl, TOOLS
    )


def test_cache_key_follows_sources_top_generics_tools_and_flow_version(
    hdl: list[Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    g = {"WIDTH_g": 640, "HEIGHT_g": 480, "SCALES_g": 1}
    base = synth.cache_key("orb_core", g, hdl, TOOLS)
    variants = [
        synth.cache_key("orb_accel_top", g, hdl, TOOLS),
        synth.cache_key("orb_core", {**g, "SCALES_g": 2}, hdl, TOOLS),
        synth.cache_key("orb_core", {**g, "INPUT_g": "RGB"}, hdl, TOOLS),
        synth.cache_key("orb_core", g, hdl[::-1], TOOLS),  # compile order
        synth.cache_key("orb_core", g, hdl[:1], TOOLS),  # a file less
        synth.cache_key("orb_core", g, hdl, {**TOOLS, "yosys": "Yosys 0.40"}),
    ]
    hdl[1].write_text("entity top is end; -- edited")
    variants.append(synth.cache_key("orb_core", g, hdl, TOOLS))
    hdl[1].write_text("entity top is end;")
    assert synth.cache_key("orb_core", g, hdl, TOOLS) == base
    monkeypatch.setattr(synth, "FLOW_VERSION", synth.FLOW_VERSION + 1)
    variants.append(synth.cache_key("orb_core", g, hdl, TOOLS))
    assert base not in variants and len(set(variants)) == len(variants)


def test_cache_key_of_the_real_sources() -> None:
    j = synth.job("orb_accel_zynq", "1920x1080x2")
    assert j.generics == {"WIDTH_g": 1920, "HEIGHT_g": 1080, "SCALES_g": 2, "MEM_DEPTH_g": 1024, "INPUT_g": "RBG",
                          "MEM_KIND_g": "BRAM"}  # fmt: skip
    key = synth.cache_key(j.top, j.generics, synth.sources(), TOOLS)
    assert len(key) == 64 and key != synth.cache_key("orb_core", j.generics, synth.sources(), TOOLS)


def test_load_cached_needs_the_same_key_and_no_errors(tmp_path: Path) -> None:
    rec = record()
    rec["cache_key"] = "abc"
    (tmp_path / "record.json").write_text(json.dumps(rec))
    assert synth.load_cached(tmp_path, "abc") == rec
    assert synth.load_cached(tmp_path, "abd") is None
    rec["errors"] = ["stat pass: yosys failed"]
    (tmp_path / "record.json").write_text(json.dumps(rec))
    assert synth.load_cached(tmp_path, "abc") is None
    assert synth.load_cached(tmp_path / "nothing", "abc") is None


# --- estimates and counting ------------------------------------------------------------------


def test_estimates_use_the_last_times_or_say_unknown() -> None:
    a, b = synth.job("orb_core", "640x480x1"), synth.job("orb_core", "1920x1080x4")
    times = {a.name: {"wall_s": {"ghdl": 2, "yosys_stat": 100, "yosys_sta": 900}, "date": "2026-11-23"}}
    none: dict[str, Any] = {"tolerance_pct": 2, "jobs": {}}
    lines = synth.estimates([a], [a, b], times, none)
    text = "\n".join(lines)
    assert "orb_core 640x480x1 " in text and "~102 s" in text
    assert any("1920x1080x4" in ln and "unknown" in ln for ln in lines)
    assert any("sta" in ln and "~15.0 min" in ln for ln in lines)
    assert synth.estimates([], [], times, none) == []
    # the expected file's wall times when this machine has none; a cached job takes seconds
    exp = {"tolerance_pct": 2, "jobs": {b.name: {"lut": 1, "wall_s": {"ghdl": 3, "yosys_stat": 600}}}}
    lines = synth.estimates([], [b], {}, exp)
    assert any("1920x1080x4" in ln and "~10.1 min" in ln and "expected file" in ln for ln in lines)
    assert any("1920x1080x4" in ln and "cached" in ln for ln in synth.estimates([], [b], {}, exp, {b.name}))


def test_parse_stat_and_counting() -> None:
    stat = """
=== design hierarchy ===

   orb_core                          1

   Number of cells:                 9
     DSP48E1                         1
     FDRE                            3
     FDSE                            1
     LUT2                            2
     LUT6                            1
     RAM32M                          1
     RAMB18E1                        1
     RAMB36E1                        2
     SRLC32E                         1
"""
    s = synth.summarise(synth.parse_stat(stat, "orb_core"))
    assert (s["lut"], s["lut_logic"], s["srl"], s["lutram"]) == (8, 3, 1, 4)
    assert (s["ff"], s["bram36"], s["dsp"]) == (4, 2.5, 1)


def test_named_jobs_are_the_board_builds() -> None:
    """`make synth CONFIG=board-720p TOP=orb_accel_zynq` runs the job (name, generics, cache key) that
    make board-estimate runs for the build of that named configuration, and an unknown name is refused."""
    board = json.loads((synth.ROOT / "vivado" / "board.json").read_text())
    by_config = {c["config"]: j.name for c, j in zip(board["configs"].values(), synth.board_jobs(), strict=True)}
    for name, job_name in by_config.items():
        assert synth.named_job("orb_accel_zynq", name).name == job_name, name
    assert int(synth.named_job("orb_core", "recommended-vga").generics["SECTORS_g"]) == 64
    with pytest.raises(ValueError, match="no configuration named 'board-qvga'"):
        synth.named_job("orb_accel_zynq", "board-qvga")


HIER_STAT = """
=== orb_harris ===

   Number of cells:                 4
     DSP48E1                         2
     FDRE                            1
     LUT6                            1

=== orb_line_buffer_640_2_19_1 ===

   Number of cells:                 2
     FDRE                            2

=== orb_line_buffer_320_30_8_2 ===

   Number of cells:                 3
     FDRE                            1
     RAMB18E1                        1
     LUT3                            1

=== orb_core ===

   Number of cells:                 3
     orb_harris                      1
     orb_line_buffer_640_2_19_1      1
     LUT2                            1

=== design hierarchy ===

   orb_core                          1
"""


def test_parse_blocks_names_entities_and_spans_their_variants() -> None:
    blocks = synth.parse_blocks(HIER_STAT)
    assert set(blocks) == {"orb_harris", "orb_line_buffer", "orb_core"}
    assert blocks["orb_harris"] == {"variants": 1, "lut": [1, 1], "ff": [1, 1], "bram36": [0, 0], "dsp": [2, 2]}
    lb = blocks["orb_line_buffer"]
    assert (lb["variants"], lb["lut"], lb["ff"], lb["bram36"]) == (2, [0, 1], [1, 2], [0, 0.5])
    assert blocks["orb_core"]["lut"] == [1, 1]  # its own LUT2, not its sub-blocks'


def test_update_expected_writes_a_finished_record_and_refuses_the_rest(tmp_path: Path) -> None:
    path = tmp_path / "expected.json"
    expected = json.loads(json.dumps(EXPECTED))
    good = record(lut=10500, ff=9100)
    good.update(passes=["stat"], date="2026-11-26", hdl_revision="commit abc1234",
                tools={"ghdl": "GHDL 2.0.0", "yosys": "Yosys 0.23"}, wall_s={"yosys_stat": 60.0})  # fmt: skip
    (tmp_path / "good").mkdir()
    (tmp_path / "good" / "stat.txt").write_text(HIER_STAT)
    dirty = record("orb_accel_top", "640x480x2")
    dirty.update(passes=["stat"], date="2026-11-26", hdl_revision="commit abc1234 + local changes",
                 tools=good["tools"], wall_s={})  # fmt: skip
    refused = synth.update_expected(path, expected, [(good, tmp_path / "good"), (dirty, tmp_path)], "synth ...")
    assert refused == ["orb_accel_top 640x480x2"]
    written = synth.load_expected(path)["jobs"]
    entry = written["orb_core 640x480x1"]
    assert (entry["lut"], entry["ff"], entry["measured"]["commit"]) == (10500, 9100, "abc1234")
    assert "logic_delay_ns" not in entry  # the timing pass did not run: the old delay is not kept
    assert entry["blocks"]["orb_harris"]["dsp"] == [2, 2]
    assert written["orb_accel_top 640x480x2"] == EXPECTED["jobs"]["orb_accel_top 640x480x2"]  # untouched
    assert written["orb_accel_top 640x480x2"]["tolerance_pct"] == 5
