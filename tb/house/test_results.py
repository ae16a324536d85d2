# SPDX-License-Identifier: MIT
"""The docs' results tables against the measurement records (docs/results/README.md).

orb_flow.gen.results regenerated from the committed records must give the committed pages byte for
byte (a figure edited by hand, or a record changed without `make views`, fails); a changed record
changes the page (the planted drift); every generated block of a page is a table the generator
knows; every recorded `make eval` run's command is what the Makefile's eval recipe runs.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

from orb_flow import record
from orb_flow.gen import results

ROOT = Path(__file__).resolve().parents[2]
PAGES = sorted({page for page, _ in results.TABLES.values()})


@pytest.mark.parametrize("page", PAGES, ids=str)
def test_pages_are_what_the_records_give(page: Path) -> None:
    want = results.render(ROOT)[page]
    assert want == (ROOT / page).read_text(), (
        f"{page}'s generated tables are stale or were edited by hand: run "
        "`.venv/bin/python -m orb_flow.gen.results` (make views)"
    )


def _copy_root(tmp: Path) -> Path:
    for rel in [
        *PAGES,
        results.SYNTH,
        results.BOARD,
        results.COEFFICIENTS,
        Path("docs/results/power.json"),
        Path("docs/results/eval.json"),
        Path("docs/results/sim.json"),
        Path("docs/results/bench.json"),
        Path("docs/results/test.json"),
        Path("docs/results/formal.json"),
        Path("docs/results/recovery.json"),
        Path("docs/results/campaign.json"),
    ]:
        (tmp / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(ROOT / rel, tmp / rel)
    return tmp


def test_a_changed_record_changes_the_page(tmp_path: Path) -> None:
    """The planted drift: one figure of a record changed, the committed page is no longer fresh."""
    root = _copy_root(tmp_path)
    path = root / "docs/results/eval.json"
    recs = json.loads(path.read_text())
    row = next(r for r in recs["runs"]["scale-bench-held"]["data"] if r["extractor"] == "5:4x5s64/g1000")
    row["pooled_pct"] += 1.0
    path.write_text(json.dumps(recs))
    pages = results.render(root)
    assert pages[Path("README.md")] != (ROOT / "README.md").read_text()
    assert f"{row['pooled_pct']:.2f}%" in pages[Path("docs/evaluation.md")]


def test_missing_marker_or_record_is_an_error(tmp_path: Path) -> None:
    root = _copy_root(tmp_path)
    page = root / "docs/board.md"
    page.write_text(page.read_text().replace("<!-- generated: board-resources", "<!-- gone: board-resources"))
    with pytest.raises(results.ResultsError, match="board-resources"):
        results.render(root)
    root = _copy_root(tmp_path / "b")
    (root / "docs/results/sim.json").write_text(json.dumps({"runs": {}}))
    with pytest.raises(results.ResultsError, match="make-sim"):
        results.render(root)


def test_every_generated_block_is_a_known_table() -> None:
    marker = re.compile(r"<!-- generated: ([\w-]+) \(orb_flow\.gen\.results\) -->")
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        for name in marker.findall(path.read_text()):
            assert name in results.TABLES, f"{path.relative_to(ROOT)}: a generated block {name!r} no table fills"


def _make_eval_commands() -> str:
    text = (ROOT / "Makefile").read_text()
    recipe = text[text.index("\neval:") : text.index("\nfigures:")].replace("\\\n", " ")
    recipe = recipe.replace("$(BIN)/", "").replace("$(EVAL_PHOTOS)", "build/eval/photos")
    recipe = recipe.replace("$(EVAL_HELD)", "build/eval/held").replace("$(EVAL_DEBS)", "build/eval/debian-cache")
    return re.sub(r"\s+", " ", recipe)


def test_recorded_eval_runs_are_what_make_eval_runs() -> None:
    recipe = _make_eval_commands()
    runs = json.loads((ROOT / "docs/results/eval.json").read_text())["runs"]
    for name, run in runs.items():
        assert run["command"] == record.EVAL[name][0], f"{name}: recorded {run['command']!r}"
        cmd = re.sub(r"--step \d+", "--step $(STEP)", run["command"])
        cmd = cmd.replace("{Wood,Aqua,Garden,LadyBird,TwoWings,YellowFlower,Storm,Blinds}.png", "")
        for part in re.split(r"\s+", cmd):
            if part.startswith("build/eval/held/native/") or "vtest.avi" in part:
                continue  # the track bench's photographs and video come from variables
            assert part in recipe, f"{name}: {part!r} of {run['command']!r} is not in make eval's recipe"


def test_pytest_summary_is_read_from_a_make_test_log() -> None:
    log = "....\n= 2 failed, 1610 passed, 3 skipped in 965.45s (0:16:05) =\n"
    data = record.parse_pytest_log("=== 5 passed in 1.00s ===\n" + log)  # the last summary counts
    assert data == {"counts": {"failed": 2, "passed": 1610, "skipped": 3}, "pytest_s": 965.45}
    with pytest.raises(SystemExit, match="no pytest summary"):
        record.parse_pytest_log("rc=1\n")


def test_campaign_report_is_checked(tmp_path: Path) -> None:
    """orb_flow.record campaign takes a campaign's report, and refuses a file that is not one."""
    report = {k: 0 for k in record.CAMPAIGN_KEYS}
    path = tmp_path / "not-a-campaign.json"
    path.write_text(json.dumps({k: v for k, v in report.items() if k != "lockups"}))
    with pytest.raises(SystemExit, match="not a campaign report: no lockups"):
        record.record_campaign("x", path, "pytest", "abc1234", "2026-01-01")
    with pytest.raises(SystemExit, match="is missing"):
        record.record_campaign("x", tmp_path / "none.json", "pytest", "abc1234", "2026-01-01")
