# SPDX-License-Identifier: MIT
"""Generate docs/tools.md: every tool version the project names, in one place, from the files that
hold them (pyproject.toml's requirements, the PYNQ checks' venv's tb/pynq/requirements.txt,
.ci/run's and sw/orb_ros/debian-packages.txt's Debian packages, vivado/board.json's Vivado release
and Digilent repositories, the IP facts of vivado/facts/ip/ and the tools each expected synthesis
figure of sw/orb_flow/synth_expected.json was measured with). The page says which versions are
pinned and which are whatever is installed.

A generated view: committed, byte-checked by tb/house/test_docs_gen.py. It holds no version of
its own: change the source, then run `python -m orb_flow.gen.tools [--out ROOT]`.
"""

from __future__ import annotations

import json
import re
import sys
from collections import defaultdict
from pathlib import Path

from orb_flow.gen.codegen import views_main
from orb_sim.hdl import ROOT

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: tomli, which pytest itself requires there
    import tomli as tomllib

VIEW = Path("docs/tools.md")
GENERATOR = "sw/orb_flow/gen/tools.py"
SOURCES = (
    "pyproject.toml",
    "tb/pynq/requirements.txt",
    ".ci/run",
    "sw/orb_ros/debian-packages.txt",
    "vivado/board.json",
    "vivado/facts/ip/*.json",
    "sw/orb_flow/synth_expected.json",
)

_REQ = re.compile(r"^(?P<name>[A-Za-z0-9_.-]+)(?:\[(?P<extras>[^\]]*)\])?\s*(?P<spec>[^;#]*)")
_NEED = re.compile(r"command -v (?P<tool>\S+) .*\|\| need\+=\((?P<pkgs>[^)]*)\)\s*(?:#\s*(?P<why>.*))?$")


def _kind(spec: str) -> str:
    if spec.startswith("=="):
        return "pinned"
    if not spec:
        return "any (as installed)"
    return "range (the newest that fits, as installed)"


def python_rows(pyproject: dict) -> list[str]:
    proj = pyproject["project"]
    rows = [f"| Python | `{proj['requires-python']}` | (interpreter) | as installed (the system's python3) |"]
    rows += [
        f"| {m['name']} | `{m['spec'].strip()}` | build | {_kind(m['spec'].strip())} |"
        for req in pyproject["build-system"]["requires"]
        if (m := _REQ.match(req))
    ]
    groups = [("(base)", proj.get("dependencies", [])), *sorted(proj.get("optional-dependencies", {}).items())]
    for extra, reqs in groups:
        for req in reqs:
            m = _REQ.match(req)
            if not m or m["name"] == proj["name"]:  # an extra that pulls in other extras
                continue
            spec = m["spec"].strip()
            rows.append(f"| {m['name']} | `{spec}` | {extra} | {_kind(spec)} |" if spec else "")
    return [r for r in rows if r]


def requirement_rows(text: str) -> list[str]:
    """A pip requirements file's lines (comments and blank lines left out) as table rows."""
    rows = []
    for line in text.splitlines():
        m = _REQ.match(line.split("#", 1)[0].strip())
        if m:
            spec = m["spec"].strip()
            rows.append(f"| {m['name']} | `{spec or '(any)'}` | {_kind(spec)} |")
    return rows


def debian_rows(ci_run: str, ros: list[str]) -> list[str]:
    rows = []
    for line in ci_run.splitlines():
        m = _NEED.search(line)
        if m:
            why = (m["why"] or "").strip()
            pkgs = ", ".join(f"`{p}`" for p in m["pkgs"].split())
            rows.append(f"| {pkgs} | `{m['tool']}` | {why or '-'} |")
    rows.append(
        f"| {', '.join(f'`{p}`' for p in ros)} | ROS 1 | the ROS node, bag tests (tb/ros); the one list "
        "`sw/orb_ros/debian-packages.txt` |"
    )
    return rows


def vivado_rows(board: dict, facts: list[dict], tcl: str) -> list[str]:
    lib, boards = board["vivado_library"], board["vivado_boards"]
    rows = [
        f"| Vivado | {board['vivado_version']}, {board['vivado_edition']} | written for it; `vivado/build.tcl` "
        "warns on another release (not run here: no Vivado) |",
        f"| Digilent vivado-library ({lib['url']}) | commit `{lib['commit']}` | pinned: {lib['why']} |",
    ]
    rows += [
        f"| Digilent IP `digilentinc.com:ip:{ip}` | {v} | the vivado-library commit's (no version in the TCL) |"
        for ip, v in sorted(lib["ips"].items())
    ]
    rows.append(
        f"| Digilent board files ({boards['url']}) | `{boards['board_part']}` | the board part the build asks for |"
    )
    for f in sorted(facts, key=lambda f: f["vlnv"]):
        if not f["vlnv"].startswith("xilinx.com:"):  # Digilent's: the library's rows above
            continue
        used = "used by vivado/lib/" if f["vlnv"] in tcl else "not used by vivado/lib/ (facts only)"
        seen = ", ".join(sorted(f.get("versions_seen", {})))
        rows.append(
            f"| Xilinx IP `{f['vlnv']}` | Vivado's own (no version in the TCL); "
            f"versions in the facts' sources: {seen} | {used} |"
        )
    return rows


def measured_rows(expected: dict) -> list[str]:
    by_tools: dict[str, list[tuple[str, str]]] = defaultdict(list)
    for job, entry in expected["jobs"].items():
        m = entry.get("measured", {})
        by_tools[m.get("tools", "(not recorded)")].append((job, m.get("commit", "?")))
    rows = []
    for tools, jobs in sorted(by_tools.items()):
        commits = ", ".join(sorted({c for _, c in jobs}))
        rows.append(f"| {tools} | {len(jobs)} | {commits} |")
    return rows


def render(root: Path) -> dict[Path, str]:
    pyproject = tomllib.loads((root / "pyproject.toml").read_text())
    ci_run = (root / ".ci" / "run").read_text()
    pynq_reqs = (root / "tb" / "pynq" / "requirements.txt").read_text()
    ros = (root / "sw" / "orb_ros" / "debian-packages.txt").read_text().split()
    board = json.loads((root / "vivado" / "board.json").read_text())
    facts = [json.loads(p.read_text()) for p in sorted((root / "vivado" / "facts" / "ip").glob("*.json"))]
    tcl = "\n".join(p.read_text() for p in sorted((root / "vivado" / "lib").glob("*.tcl")))
    expected = json.loads((root / "sw" / "orb_flow" / "synth_expected.json").read_text())
    sources = ", ".join(f"`{s}`" for s in SOURCES)
    out = [
        "# Tool versions",
        "",
        f"<!-- Generated by {GENERATOR}: do not edit; change the sources and run"
        " `.venv/bin/python -m orb_flow.gen.tools`. -->",
        "",
        f"Every tool version the project names, in one place, generated from the files that hold them: {sources}.",
        "**Pinned** means the exact version is required; **range** and **as installed** mean whatever the",
        "package manager installs within the bounds (pip: the newest that fits; Debian: the release's",
        "package, Debian 12 on the machines this was written on). `make tools`",
        "(`scripts/flow/check_tools.sh`) prints the versions installed on a machine.",
        "",
        "## Python packages (`pyproject.toml`)",
        "",
        "`make setup` installs them into `.venv` (`pip install -e '.[test]'`).",
        "",
        "| package | requirement | extra | kind |",
        "|---|---|---|---|",
        *python_rows(pyproject),
        "",
        "## The PYNQ checks' venv (`tb/pynq/requirements.txt`)",
        "",
        "`make setup` installs them into `.venv-pynq` (PyPI's pynq pins numpy below 2; docs/pynq.md).",
        "",
        "| package | requirement | kind |",
        "|---|---|---|",
        *requirement_rows(pynq_reqs),
        "",
        "## Debian packages (`.ci/run`, `sw/orb_ros/debian-packages.txt`)",
        "",
        "Not pinned: `.ci/run` installs each when its command is missing, at the Debian release's version.",
        "",
        "| packages | missing command | for |",
        "|---|---|---|",
        *debian_rows(ci_run, ros),
        "",
        "## Vivado, Digilent and the IP (`vivado/board.json`, `vivado/facts/ip/`)",
        "",
        "| what | version | kind |",
        "|---|---|---|",
        *vivado_rows(board, facts, tcl),
        "",
        "## What the recorded figures were measured with (`sw/orb_flow/synth_expected.json`)",
        "",
        "The expected synthesis estimates of `make synth` and the board configurations, by the tools",
        "each entry records (`measured.tools`):",
        "",
        "| tools | entries | commits |",
        "|---|---|---|",
        *measured_rows(expected),
        "",
    ]
    return {VIEW: "\n".join(out)}


def main(argv: list[str] | None = None) -> None:
    views_main(__doc__, render, ROOT, argv)


if __name__ == "__main__":
    main()
