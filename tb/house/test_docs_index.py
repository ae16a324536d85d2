# SPDX-License-Identifier: MIT
"""docs/index.md maps the house: exactly one row per design unit of hdl/manifest.txt, with the
unit's real source path and area, a test file, a doc page and a spec section that exist, and the
link to the entity's generated page (docs/entities/, "-" for a package)."""

from __future__ import annotations

import re

from orb_sim.hdl import ROOT, read_manifest

INDEX = ROOT / "docs" / "index.md"


def rows() -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for line in INDEX.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 7 and cells[0].startswith("orb_"):
            assert cells[0] not in out, f"docs/index.md: {cells[0]} has two rows"
            out[cells[0]] = cells
    return out


def test_one_row_per_unit() -> None:
    units = {s.name for s in read_manifest()}
    have = set(rows())
    assert have == units, f"units without a row: {sorted(units - have)}; rows of no unit: {sorted(have - units)}"


def test_rows_name_real_files_and_sections() -> None:
    spec = (ROOT / "docs" / "spec.md").read_text()
    sections = set(re.findall(r"(?m)^## (\d+)\.", spec))
    by_name = {s.name: s for s in read_manifest()}
    for name, (_, area, source, test, page, section, ports) in rows().items():
        s = by_name[name]
        assert (area, source) == (s.area, f"hdl/{s.rel}"), f"{name}: row says {area}, {source}; manifest {s.rel}"
        assert (ROOT / test).is_file(), f"{name}: test {test} does not exist"
        assert (ROOT / "docs" / page).is_file(), f"{name}: doc page {page} does not exist"
        assert section == "-" or section in sections, f"{name}: spec section {section} not in docs/spec.md"
        link = "-" if s.is_package else f"[{name}](entities/{name}.md)"
        assert ports == link, f"{name}: ports-and-generics cell {ports!r}, expected {link!r}"
        assert link == "-" or (ROOT / "docs" / "entities" / f"{name}.md").is_file(), f"{name}: no entity page"


def test_every_figure_names_its_command() -> None:
    img = ROOT / "docs" / "img"
    table = (img / "README.md").read_text()
    listed = set(re.findall(r"(?m)^\| (\S+\.(?:png|svg|jpg)) \| `[^`]+`", table))
    present = {p.name for p in img.iterdir() if p.suffix in (".png", ".svg", ".jpg")}
    assert listed == present, (
        f"figures without a command: {sorted(present - listed)}; rows of no file: {sorted(listed - present)}"
    )
