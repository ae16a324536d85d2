# SPDX-License-Identifier: MIT
"""The drift a generator cannot prevent: prose in the docs that restates a fact the code owns.

Generated views (registers, limits, configurations, entity pages, results tables) cannot go stale,
but a sentence can. This checker reads every page a user reads (README.md, docs/*.md, docs/img/README.md;
not the generated docs/entities/, not the CHANGELOG, which is history) and the comments of the code,
and fails with the page, the line and the claim for:

(a) a range claim of a limited parameter ("`SCALES_g` 1..8", "1 to 8 scales", "sectors 16, 32 or 64",
    "threshold 0..255") that is not golden_model/data/limits.json's;
(b) a repository path (hdl/..., tb/..., sw/..., docs/..., golden_model/..., vivado/..., scripts/...,
    research/..., .ci/...) that does not exist; a `make TARGET` the Makefile lacks, or a `VAR=` it
    never reads; an `orb-accel SUBCOMMAND` the CLI lacks, or a `--option` that subcommand lacks;
(c) a file outside the repository (``../shared/...``) or a ``*.md`` page that does not exist, in the
    docs and in the comments of hdl/, sw/, tb/, golden_model/ and scripts/;
(d) a dated status line ("Status (2026-...):"), a dated heading or a dated italic note: a page says
    what holds now, the records carry the dates;
(e) a named configuration (`make sim CONFIG=`, `--config`, `--sim-config`, `Config.named(...)`, or a
    backticked name like `board-vga`) that golden_model/data/configs.json does not define; a board
    configuration (`make bitstream CONFIG=`) that vivado/board.json does not define.

Run as a test (tb/house) or by hand: ``python tb/house/test_docs_drift.py [PAGE ...]``.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

# Pages whose drift is fixed by another change (the lead's generated tables); each entry is
# (page, a substring of the claim). Only entries that fail now belong here.
# (page, a substring of the claim): drift found and accepted, each with its reason (empty: none)
ALLOWED: set[tuple[str, str]] = set()

PATH_ROOTS = ("hdl", "tb", "sw", "docs", "golden_model", "vivado", "scripts", "research", ".ci")
CODE_DIRS = ("hdl", "sw", "tb", "golden_model", "scripts", "vivado")
CODE_SUFFIXES = {".py", ".vhd", ".tcl", ".sh", ".json", ".toml", ".cfg", ".txt", ".xdc"}


# --------------------------------------------------------------------------------------------- facts


@dataclass
class Facts:
    """What the code says: the limits, the make targets and variables, the CLI, the configurations."""

    limits: dict[str, dict]
    make_targets: set[str]
    make_vars: set[str]
    cli: dict[str, argparse.ArgumentParser]
    configs: set[str]
    board_configs: set[str]
    md_names: set[str] = field(default_factory=set)


def _subparsers(p: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for a in p._actions:
        if isinstance(a, argparse._SubParsersAction):
            return dict(a.choices)
    return {}


@cache
def facts(root: Path = ROOT) -> Facts:
    from orb_tools.cli import build_parser
    from orb_tools.sim_accel import build_parser as sim_parser

    limits = {d["name"]: d for d in json.loads((root / "golden_model/data/limits.json").read_text())["limits"]}
    mk = (root / "Makefile").read_text()
    targets = set(re.findall(r"(?m)^([a-z][\w-]*):", mk))
    variables = set(re.findall(r"\$\((\w+)\)", mk)) | set(re.findall(r"(?m)^(\w+)\s*[?:]?=", mk))
    cli: dict[str, argparse.ArgumentParser] = {}
    for name, sp in _subparsers(build_parser()).items():
        cli[name] = sp
        for sub, ssp in _subparsers(sp).items():
            cli[f"{name} {sub}"] = ssp
    cli["sim"] = sim_parser()  # `orb-accel sim` hands its arguments to orb_tools.sim_accel's own parser
    configs = set(json.loads((root / "golden_model/data/configs.json").read_text())["configs"])
    board_configs = json.loads((root / "vivado/board.json").read_text())["configs"]
    # a board build is named by its size key (640x480) or by the named configuration it builds (board-vga)
    board = set(board_configs) | {c["config"] for c in board_configs.values()}
    md = {p.name for p in root.glob("*.md")} | {p.name for p in (root / "docs").rglob("*.md")}
    md |= {p.name for p in (root / "research").rglob("*.md")}
    # the Markdown files the code writes (a report, a timing table) are named in a string literal somewhere
    for p in code_files(root):
        md |= set(re.findall(r"[\"']([\w-]+\.md)[\"']", p.read_text(errors="replace")))
    return Facts(limits, targets, variables, cli, configs, board, md)


# ---------------------------------------------------------------------------------------- scanning


@dataclass(frozen=True)
class Drift:
    page: str
    line: int
    claim: str
    why: str

    def __str__(self) -> str:
        return f"{self.page}:{self.line}: {self.claim!r}: {self.why}"


def _num(s: str) -> int:
    return int(s.replace(",", ""))


# The words that name a limited parameter, and the limit each names.
PARAM_WORDS: list[tuple[str, str]] = [
    (r"`?WIDTH_g`?|width", "width"),
    (r"`?HEIGHT_g`?|height", "height"),
    (r"`?SCALES_g`?|scales|levels", "scales"),
    (r"`?SECTORS_g`?|sectors", "sectors"),
    (r"`?STEP_NUM_g`?|step_num", "step_num"),
    (r"`?STEP_DEN_g`?|step_den", "step_den"),
    (r"`?MEM_DEPTH_g`?|mem[_ ]depth", "mem_depth"),
    (r"`?BLOCK_LOG2_g`?|block_log2", "block_log2"),
    (r"(?:FAST |low |high )?threshold(?:s| t| t_lo)?|t_lo", "threshold"),
    (r"budget", "budget"),
]
NUM = r"\d{1,3}(?:,\d{3})+|\d+"
RANGE = rf"(?P<lo>{NUM})\s*(?:\.\.|to|–)\s*(?P<hi>{NUM})"
LIST = rf"(?P<list>(?:{NUM})(?:(?:,\s*|/)(?:{NUM}))+,?(?:\s+or\s+|/)(?:{NUM})|(?:{NUM})/(?:{NUM}))"
# "WORD A..B" / "WORD 16, 32 or 64" / "| `WORD` | A .. B |" (a table row); "A to B WORD" /
# "16, 32 or 64 WORD" (not "from A to B": a change)
_forward = [
    (
        limit,
        re.compile(rf"(?i)(?<![\w.])(?:{words})\)?\s*(?:\|\s*)?(?:\((?:legal\s*)?)?(?:{RANGE}|{LIST})(?![\w.]|\.\d)"),
    )
    for words, limit in PARAM_WORDS
]
_backward = [
    (limit, re.compile(rf"(?i)(?<![\w.,/])(?<!from )(?:{RANGE}|{LIST})\s+(?:{words})(?!\w)"))
    for words, limit in PARAM_WORDS
]
_up_to = [
    (limit, re.compile(rf"(?i)\bup to (?P<hi>{NUM}) (?:pyramid )?(?:{words})(?!\w)")) for words, limit in PARAM_WORDS
]


def range_drifts(line: str, f: Facts) -> list[str]:
    """The range claims of a line that limits.json contradicts: a list of sectors that is not the
    legal one, a range from the minimum to another maximum (or to the maximum from another minimum)
    after the parameter's name, or from the minimum before it, and "up to N scales" below the maximum."""
    out = []
    for forward, regexes in ((True, _forward), (False, _backward)):
        for limit, rx in regexes:
            for m in rx.finditer(line):
                lim = f.limits[limit]
                if m.group("list"):
                    claimed = [_num(x) for x in re.findall(NUM, m.group("list"))]
                    legal = lim.get("values")
                    if legal is not None and claimed != legal and len(claimed) > 2:
                        out.append(f"{m.group(0)}: limits.json says {limit} is one of {legal}")
                    continue
                lo, hi = _num(m.group("lo")), _num(m.group("hi"))
                at_min, at_max = lo == lim["min"], hi == lim["max"]
                if (at_min != at_max) if forward else (at_min and not at_max):
                    out.append(f"{m.group(0)}: limits.json says {limit} is {lim['min']}..{lim['max']}")
    for limit, rx in _up_to:
        lim = f.limits[limit]
        for m in rx.finditer(line):
            if _num(m.group("hi")) != lim["max"] and limit == "scales":
                out.append(f"{m.group(0)}: limits.json says {limit} is {lim['min']}..{lim['max']}")
    return out


PATH_RE = re.compile(rf"(?<![\w./~$-])(?:\.\./)*(?:{'|'.join(re.escape(r) for r in PATH_ROOTS)})/[\w./<>*{{}},+-]*")


def _path_exists(token: str, root: Path) -> bool:
    if "<" not in token:
        token = token.rstrip(">")
    token = token.rstrip(".,:;)")
    if "<" in token or "{" in token or "..." in token:
        head = re.split(r"[<{]|\.\.\.", token)[0]
        head = head[: head.rfind("/") + 1]
        return (root / head).exists()
    if "*" in token:
        return any(root.glob(token)) or any(root.glob(token.replace("/*", "/**/*", 1)))
    return (root / token).exists()


def path_drifts(line: str, root: Path, base: Path | None = None) -> list[str]:
    """Repository paths of a line that do not exist; a ``../`` path is relative to ``base`` (the
    page's folder) and must stay inside the repository."""
    out = []
    for m in PATH_RE.finditer(line):
        tok = m.group(0)
        if tok.startswith("../"):
            if base is None:
                continue  # a relative path in code (a link it writes), not a claim about the repository
            target = (base / tok.rstrip(".,:;)")).resolve()
            if not target.is_relative_to(root.resolve()):
                out.append(f"{tok}: outside the repository")
            elif not target.exists():
                out.append(f"{tok}: no such file or folder in the repository")
        elif tok.rstrip("/.,:;)") and not _path_exists(tok, root):
            out.append(f"{tok}: no such file or folder in the repository")
    return out


OUTSIDE_RE = re.compile(r"\.\./shared\b")
MD_RE = re.compile(r"(?<![\w./-])([\w-]{3,}\.md)(?![\w(])")


def md_drifts(line: str, f: Facts, prose: str | None = None) -> list[str]:
    """Files outside the repository (``../shared/...``) and bare page names (``toolchain.md``) that no
    page of the repository has (in ``prose``, the line without its code spans, if given)."""
    out = [f"{m.group(0)}: a file outside the repository" for m in OUTSIDE_RE.finditer(line)]
    for m in MD_RE.finditer(line if prose is None else prose):
        if m.group(1) not in f.md_names:
            out.append(f"{m.group(1)}: no such page in the repository")
    return out


DATE = r"20\d\d-\d\d-\d\d"
DATED_RES = [
    (re.compile(rf"Status \({DATE}"), "a dated status line: say what holds now"),
    (re.compile(rf"^#+ .*\b{DATE}\b"), "a dated heading: say what holds now (the records carry the dates)"),
    (re.compile(rf"(?<![\w*])[*_](?![*_\s])[^*_|]*\b{DATE}\b[^*_|]*[*_](?![\w*])"), "a dated italic note"),
]


def dated_drifts(line: str) -> list[str]:
    return [f"{m.group(0)}: {why}" for rx, why in DATED_RES for m in rx.finditer(line)]


CMD_END = re.compile(r"[|;&`]|$")
MAKE_RE = re.compile(r"(?<![\w-])make ([a-z][\w-]*)((?:\s+[A-Z][A-Z_0-9]*=\S*)*)")
CLI_RE = re.compile(r"(?<![\w-])orb-accel ([a-z][\w-]*)(?: ([a-z][\w-]*))?([^`|;&]*)")
CONFIG_NAME_RE = re.compile(r"`((?:thesis|recommended|board|sim|test)-(?:vga|qvga|720p|1080p|tiny|small))`")
NAMED_RE = re.compile(r"Config\.named\(\s*[\"']([\w-]+)[\"']")


def _options(p: argparse.ArgumentParser) -> set[str]:
    return {o for a in p._actions for o in a.option_strings}


def command_drifts(span: str, f: Facts) -> list[str]:
    """`make ...` and `orb-accel ...` inside a code span or block."""
    out = []
    for m in MAKE_RE.finditer(span):
        target, assigns = m.group(1), m.group(2)
        if target not in f.make_targets:
            out.append(f"make {target}: the Makefile has no target {target}")
            continue
        for var, val in re.findall(r"([A-Z][A-Z_0-9]*)=(\S*)", assigns):
            if var not in f.make_vars:
                out.append(f"make {target} {var}=: the Makefile reads no variable {var}")
            elif var == "CONFIG" and val and not val.startswith(("<", "NAME", "$")):
                known = f.board_configs if target in ("bitstream", "board-dryrun") else f.configs
                for v in val.split("|"):
                    if v not in known:
                        out.append(f"make {target} CONFIG={v}: not one of {sorted(known)}")
    for m in CLI_RE.finditer(span):
        sub, sub2, rest = m.group(1), m.group(2), m.group(3)
        if sub not in f.cli:
            out.append(f"orb-accel {sub}: the CLI has no subcommand {sub}")
            continue
        name = sub
        if sub2 and f"{sub} {sub2}" in f.cli:
            name = f"{sub} {sub2}"
        elif _subparsers(f.cli[sub]):
            if sub2 is None or sub2.upper() == sub2:
                continue
            out.append(f"orb-accel {sub} {sub2}: {sub} has no subcommand {sub2}")
            continue
        opts = _options(f.cli[name])
        for opt in re.findall(r"(?<![\w-])(--[a-z][\w-]*)", rest):
            if opt not in opts:
                out.append(f"orb-accel {name} {opt}: no such option")
        for opt, val in re.findall(r"(--(?:sim-)?config)[ =]([\w-]+)", rest):
            if name in ("extract", "sim-server", "ros") and val not in f.configs and val.upper() != val:
                out.append(f"orb-accel {name} {opt} {val}: no named configuration {val}")
    return out


def config_drifts(line: str, f: Facts) -> list[str]:
    names = CONFIG_NAME_RE.findall(line) + NAMED_RE.findall(line)
    return [f"{n}: no named configuration {n} in golden_model/data/configs.json" for n in names if n not in f.configs]


def _code_spans(lines: list[str]) -> list[tuple[int, str]]:
    """(line number, text) of every inline code span and every line of a fenced block."""
    out, fence = [], False
    for i, line in enumerate(lines, 1):
        if line.lstrip().startswith("```"):
            fence = not fence
            continue
        if fence:
            out.append((i, line))
        else:
            out.extend((i, s) for s in re.findall(r"`([^`]+)`", line))
    return out


def check_page(path: Path, root: Path = ROOT, f: Facts | None = None) -> list[Drift]:
    """Every drift of one Markdown page."""
    f = f or facts(root)
    try:
        name = str(path.resolve().relative_to(root))
    except ValueError:
        name = str(path)
    lines = path.read_text().splitlines()
    found: list[Drift] = []
    fence = False
    for i, line in enumerate(lines, 1):
        if line.lstrip().startswith("```"):
            fence = not fence
        prose = re.sub(r"`[^`]*`", "", line)  # a backticked name may be a build output (`timing.md`)
        whys = range_drifts(line, f) + path_drifts(line, root, path.parent) + md_drifts(line, f, prose)
        whys += config_drifts(line, f)
        if not fence:
            whys += dated_drifts(line)
        found += [Drift(name, i, line.strip()[:160], w) for w in whys]
    for i, span in _code_spans(lines):
        found += [Drift(name, i, span.strip()[:160], w) for w in command_drifts(span, f)]
    for i, line in enumerate(lines, 1):  # `make TARGET VAR=...` in prose (a table cell) is a command too
        prose = re.sub(r"`[^`]*`", "", line)
        for m in MAKE_RE.finditer(prose):
            if m.group(2):
                found += [Drift(name, i, m.group(0), w) for w in command_drifts(m.group(0), f)]
    return _allowed(found)


def check_code_comments(path: Path, root: Path = ROOT, f: Facts | None = None) -> list[Drift]:
    """Files outside the repository and pages that do not exist, named in a source file."""
    f = f or facts(root)
    name = str(path.relative_to(root))
    found = []
    for i, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
        whys = md_drifts(line, f) + path_drifts(line, root)
        found += [Drift(name, i, line.strip()[:160], w) for w in whys]
    return _allowed(found)


def _allowed(found: list[Drift]) -> list[Drift]:
    _seen.extend(found)
    return [d for d in found if not any(d.page == p and s in d.claim for p, s in ALLOWED)]


_seen: list[Drift] = []  # every drift found, allowed or not (for the allow-list's own test)


def pages(root: Path = ROOT) -> list[Path]:
    return [root / "README.md", *sorted((root / "docs").glob("*.md")), root / "docs" / "img" / "README.md"]


def code_files(root: Path = ROOT) -> list[Path]:
    out = []
    for d in CODE_DIRS:
        for p in sorted((root / d).rglob("*")):
            if p.is_file() and p.suffix in CODE_SUFFIXES and "__pycache__" not in p.parts and p != Path(__file__):
                out.append(p)
    return out


# ------------------------------------------------------------------------------------------- tests


@pytest.mark.parametrize("page", pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_page_agrees_with_the_code(page: Path) -> None:
    drifts = check_page(page)
    assert not drifts, "\n".join(map(str, drifts))


def test_code_names_no_missing_page() -> None:
    drifts = [d for p in code_files() for d in check_code_comments(p)]
    assert not drifts, "\n".join(map(str, drifts))


def test_allow_list_holds_only_current_drift() -> None:
    """An allow-list entry whose drift is gone must go too (the lead removes them when fixed)."""
    _seen.clear()
    for page in pages():
        check_page(page)
    for path in code_files():
        check_code_comments(path)
    stale = [(p, c) for p, c in ALLOWED if not any(d.page == p and c in d.claim for d in _seen)]
    assert not stale, f"allow-list entries with no drift left, remove them from ALLOWED: {stale}"


def test_a_planted_drift_fails(tmp_path: Path) -> None:
    """The checker finds each kind of drift on a page written for it (the issue's "show one")."""
    page = tmp_path / "planted.md"
    page.write_text(
        "# Planted\n"
        "The core takes `SCALES_g` 1..4 and 16 or 32 or 64 sectors.\n"
        "It runs 1 to 4 scales.\n"
        "Sectors 16, 32, 48 or 64 are legal.\n"
        "Read `hdl/core/orb_nowhere.vhd` and [the toolchain](../shared/toolchain.md).\n"
        "Status (2026-11-23): implemented.\n"
        "| `SCALES_g` | 1 .. 4 | 4 | scales drawn |\n"
        "Run `make simulate` or `make sim CONFIG=board-qvga COLOUR=red`, `orb-accel extrakt x.png`,\n"
        "`orb-accel extract x.png --colour red` and `orb-accel sim-server --config board-vgaa`.\n"
        "The scales 1..8, sectors 16, 32 or 64 and `hdl/core/orb_core.vhd`, `make sim CONFIG=board-vga` hold.\n"
        "| board-qvga | make bitstream CONFIG=board-qvga and make board-dryrun CONFIG=board-vga |\n"
    )
    by_line: dict[int, list[str]] = {}
    for d in check_page(page):
        by_line.setdefault(d.line, []).append(d.why)
        assert str(page) in str(d) and f":{d.line}:" in str(d)  # page and line in the message
    assert any("scales is 1..8" in w for w in by_line[2]), by_line
    assert any("scales is 1..8" in w for w in by_line[3]), by_line
    assert any("one of [16, 32, 64]" in w for w in by_line[4]), by_line
    assert any("orb_nowhere" in w for w in by_line[5]) and any("outside" in w for w in by_line[5]), by_line
    assert any("status" in w for w in by_line[6]), by_line
    assert any("scales is 1..8" in w for w in by_line[7]), by_line
    assert {"simulate", "COLOUR", "board-qvga", "extrakt"} <= {
        k for w in by_line[8] for k in ("simulate", "COLOUR", "board-qvga", "extrakt") if k in w
    }, by_line
    assert any("--colour" in w for w in by_line[9]) and any("board-vgaa" in w for w in by_line[9]), by_line
    assert 10 not in by_line, by_line[10]
    assert [w for w in by_line[11] if "CONFIG=" in w] == [
        w for w in by_line[11] if "CONFIG=board-qvga: not one of" in w
    ], by_line  # board-vga names the 640x480 build (its "config"), board-qvga nothing
    assert by_line[11], by_line


def test_a_planted_code_comment_fails(tmp_path: Path) -> None:
    src = tmp_path / "hdl" / "orb_x.vhd"
    src.parent.mkdir()
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "spec.md").write_text("# Spec\n")
    src.write_text("-- see ../shared/notes/design-facts.md and toolchain.md\n-- docs/spec.md is fine\n")
    drifts = check_code_comments(src, tmp_path, facts())
    assert [d.line for d in drifts] == [1, 1], drifts


if __name__ == "__main__":
    args = [Path(a).resolve() for a in sys.argv[1:]] or pages()
    all_drifts = [d for p in args for d in check_page(p)]
    print("\n".join(map(str, all_drifts)) or "no drift")
    sys.exit(1 if all_drifts else 0)
