# SPDX-License-Identifier: MIT
"""The latency drift check: every latency number the docs and the HDL headers state against
golden_model/data/latency.json (docs/latency.md), the one definition.

Claims are found by their wording: "latency N" / "**Latency** N clocks" / "N-clock latency", a
constant with its value ("HARRIS_LAT_c = 17", "`FEAT_MEM_READ_LAT_c` = 3"), a change "3 -> 4" in a
table's latency column, and a number at the start of a latency column's cell. A constant's value
must be the data's; any other number must be a latency of a block named beside it (in the same
paragraph, table row or header: an entity `orb_*` of the data or one of its constants), so a number
with no block named fails too. Every HDL header of an entity in the data names its constants and
links docs/latency.md; an entity outside the data states no latency number. Generated
docs/latency.md itself is checked by tb/common/test_orb_latency_pkg.py.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

import pytest

from golden_model import latency
from golden_model.latency_types import Latency

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
HDL = ROOT / "hdl"

CLAIM = re.compile(r"\b[Ll]atency\**:?\**\s+(?:of\s+)?(\d+)\b|\b(\d+)[- ]clock latency\b")
CONST = re.compile(r"\b([A-Z][A-Z0-9_]*_LAT)(?:_c)?`?\s*=\s*`?(\d+)\b")
CHANGE = re.compile(r"(\d+)\s*->\s*(\d+)")
ENTITY = re.compile(r"\borb_[a-z0-9_]+\b")
NAME = re.compile(r"\b([A-Z][A-Z0-9_]*_LAT)(?:_c)?\b|\b([a-z_]+)_lat\(")
# A RAM primitive's read latency is a generic (the instance's choice), not a published latency:
# text about one may state the generic's legal values.
GENERIC = re.compile(r"\b[A-Z_]*LATENCY_g\b")
RAM_LATENCIES = {
    "orb_sdp_ram": {1, 2},
    "orb_line_buffer": {1, 2},
    "LATENCY_g": {1, 2},
    "MEM_LATENCY_g": set(range(1, 9)),
}


def fixed(lat: Latency) -> set[int]:
    return {lat.clocks} if lat.clocks is not None else set()


BY_ENTITY: dict[str, set[int]] = {}
for _lat in latency.LATENCIES:
    BY_ENTITY.setdefault(_lat.entity, set()).update(fixed(_lat))
BY_CONST: dict[str, int] = {
    f"{lat.name.upper()}_LAT": lat.clocks for lat in latency.LATENCIES if lat.clocks is not None
}
CONST_NAMES = (
    set(BY_CONST)
    | {f"{lat.name.upper()}_LAT_PER_LEVEL" for lat in latency.LATENCIES}
    | {f"{lat.name.upper()}_LAT_PLUS" for lat in latency.LATENCIES}
)


def named(text: str) -> set[int]:
    """The latencies of the blocks a piece of text names (entities of the data, constants)."""
    out: set[int] = set()
    for e in ENTITY.findall(text):
        out |= BY_ENTITY.get(e, set())
    for const, func in NAME.findall(text):
        if const in BY_CONST:
            out.add(BY_CONST[const])
        lat = latency.BY_NAME.get(func) if func else None
        if lat is not None:
            out |= fixed(lat)
    return out


def check_text(text: str, where: str, own: set[int] | None = None) -> list[str]:
    """The wrong claims of one paragraph, table row or header (own: the latencies it is about)."""
    bad = []
    for name, value in CONST.findall(text):
        if name in BY_CONST and BY_CONST[name] != int(value):
            bad.append(f"{where}: {name} = {value}, latency.json says {BY_CONST[name]}")
        elif name not in CONST_NAMES:
            bad.append(f"{where}: {name} is not a constant of orb_latency_pkg")
    candidates = (own or set()) | named(text)
    for word, values in RAM_LATENCIES.items():
        if re.search(rf"\b{word}\b", text):
            candidates |= values
    for m in CLAIM.finditer(GENERIC.sub("", text)):
        n = int(m[1] or m[2])
        if n not in candidates:
            bad.append(f"{where}: claims latency {n} ({m[0]!r}); the blocks named there have {sorted(candidates)}")
    return bad


def paragraphs(text: str) -> Iterator[tuple[int, str]]:
    """Paragraphs (blank-line separated) and table rows (one each), with their first line number."""
    block: list[str] = []
    start = 0
    for i, line in enumerate([*text.split("\n"), ""], 1):
        if line.startswith("|"):
            if block:
                yield start, "\n".join(block)
                block = []
            yield i, line
        elif line.strip():
            if not block:
                start = i
            block.append(line)
        elif block:
            yield start, "\n".join(block)
            block = []


def table_claims(text: str, page: str) -> list[str]:
    """Latency columns of the page's tables: the cell's number against the row's block."""
    bad = []
    col = None
    for i, line in enumerate(text.split("\n"), 1):
        if not line.startswith("|"):
            col = None
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if col is None:
            col = next((k for k, c in enumerate(cells) if "latency" in c.lower()), -1)
            continue
        if col < 0 or col >= len(cells) or set(cells[col]) <= set("-: "):
            continue
        cell = cells[col]
        change = CHANGE.findall(cell)
        num = re.match(r"(\d+)\b", cell)
        value = int(change[-1][1]) if change else int(num[1]) if num else None
        if value is None:
            continue
        own = named(cells[0]) or named(line)
        if value not in own:
            bad.append(f"docs/{page}:{i}: latency column says {value}; the row's block has {sorted(own)}")
    return bad


DOC_PAGES = sorted(p.name for p in DOCS.glob("*.md") if p.name != "latency.md")


@pytest.mark.parametrize("page", DOC_PAGES)
def test_doc_latency_claims_match_the_data(page: str) -> None:
    text = (DOCS / page).read_text()
    bad = table_claims(text, page)
    for line, para in paragraphs(text):
        if para.startswith("|"):
            cells = [c.strip() for c in para.strip().strip("|").split("|")]
            para = " | ".join(cells[:1] + [c for c in cells[1:] if "->" not in c])  # changes: table_claims
        bad += check_text(para, f"docs/{page}:{line}")
    assert not bad, "latency claims that disagree with golden_model/data/latency.json:\n" + "\n".join(bad)


def header(path: Path) -> str:
    lines = []
    for line in path.read_text().split("\n"):
        if not line.startswith("--"):
            break
        lines.append(line[2:].strip())
    return " ".join(lines)


HDL_FILES = sorted(p.relative_to(HDL).as_posix() for p in HDL.rglob("*.vhd"))


@pytest.mark.parametrize("rel", HDL_FILES)
def test_hdl_header_latencies_match_the_data(rel: str) -> None:
    path = HDL / rel
    if path.name == "orb_latency_pkg.vhd":
        return  # the generated view (tb/common/test_orb_latency_pkg.py)
    text = header(path)
    entity = path.stem
    own = BY_ENTITY.get(entity, set())
    bad = check_text(text, f"hdl/{rel} header", own)
    for lat in latency.LATENCIES:
        if lat.entity != entity:
            continue
        name = f"{lat.name.upper()}_LAT_c" if lat.clocks is not None else f"{lat.name}_lat"
        if name not in text:
            bad.append(f"hdl/{rel} header: does not name its latency {name}")
        if "docs/latency.md" not in text:
            bad.append(f"hdl/{rel} header: no link to docs/latency.md")
    assert not bad, "\n".join(bad)


def test_the_check_finds_a_wrong_claim() -> None:
    """The patterns catch the wordings the docs use (a check that cannot fail is a defect)."""
    assert check_text("`orb_smooth` ... latency 6 clocks", "x")
    assert check_text("**Latency** 4 clocks (`orb_orient_sector`)", "x")
    assert check_text("HARRIS_LAT_c = 16", "x")
    assert check_text("`FEAT_MEM_READ_LAT_c` = 2 in orb_accel_top", "x")
    assert check_text("a 2-clock latency", "x")
    assert check_text("latency 3 with no block named", "x")
    assert not check_text("`orb_smooth`: latency 5 clocks; `LATENCY_g = 2` is a generic", "x")
    table = "| entity | latency (clocks) |\n|---|---|\n| `orb_window` | 3 |\n| `orb_scaler` | 1 -> 3 |\n"
    assert len(table_claims(table, "x.md")) == 2
