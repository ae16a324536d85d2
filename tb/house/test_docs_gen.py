# SPDX-License-Identifier: MIT
"""The generated documentation (docs/entities/, docs/img/architecture.svg, docs/tools.md) is what
its generator in orb_flow.gen writes now, byte for byte, and twice the same; every entity's header
names its page."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from orb_flow.gen import architecture, entities, tools
from orb_flow.vhdl import PAGE_LINE
from orb_sim.hdl import ROOT, read_manifest

GENERATORS: tuple[ModuleType, ...] = (entities, architecture, tools)


@pytest.mark.parametrize("gen", GENERATORS, ids=lambda g: g.__name__)
def test_views_are_fresh(gen: ModuleType, tmp_path: Path) -> None:
    """Run the generator's command line into a temporary root; every view equals the committed one."""
    subprocess.run([sys.executable, "-m", gen.__name__, "--out", str(tmp_path)], check=True, capture_output=True)
    views = gen.render(ROOT)
    assert views, f"{gen.__name__} renders nothing"
    for rel in views:
        assert (tmp_path / rel).read_bytes() == (ROOT / rel).read_bytes(), (
            f"{rel} is stale: run `.venv/bin/python -m {gen.__name__}`"
        )


@pytest.mark.parametrize("gen", GENERATORS, ids=lambda g: g.__name__)
def test_views_are_deterministic(gen: ModuleType) -> None:
    assert gen.render(ROOT) == gen.render(ROOT)


def test_no_stale_entity_page() -> None:
    """docs/entities/ holds exactly the generated pages (a page of a removed entity is stale)."""
    have = {p.relative_to(ROOT) for p in (ROOT / entities.PAGES).iterdir()}
    assert have == set(entities.render(ROOT)), "docs/entities/ has files no entity makes or lacks pages"


def test_every_entity_header_names_its_page() -> None:
    for s in read_manifest():
        if s.is_package:
            continue
        header = []
        for line in s.path.read_text().splitlines():
            if not line.startswith("--"):
                break
            header.append(line)
        line = PAGE_LINE.format(name=s.name)
        assert line in header, f"hdl/{s.rel}: the header lacks `{line}`"


def test_pages_hold_every_port_and_generic() -> None:
    """A mutation check of the parser: each port and generic name of the VHDL entity (counted by a
    plain regular expression over the entity declaration) appears in its page's tables."""
    views = entities.render(ROOT)
    for s in read_manifest():
        if s.is_package:
            continue
        text = s.path.read_text()
        decl = text[text.index(f"entity {s.name} is") : text.index(f"end entity {s.name};")]
        names = re.findall(r"(?m)^\s+(\w+)\s*:\s*(?!entity)", decl)
        page = views[entities.PAGES / f"{s.name}.md"]
        rows = re.findall(r"(?m)^\| `(\w+)` \|", page)
        assert sorted(rows) == sorted(names), f"{s.name}: page rows {sorted(set(rows) ^ set(names))} differ"


def test_architecture_follows_the_hierarchy(monkeypatch: pytest.MonkeyPatch) -> None:
    """The picture refuses to drift from the HDL: an instance without a place, or a place of no instance."""
    layout = dict(architecture.LAYOUT)
    del layout["detect/path/selection"]
    monkeypatch.setattr(architecture, "LAYOUT", layout)
    with pytest.raises(ValueError, match="detect/path/selection"):
        architecture.render(ROOT)
    monkeypatch.setattr(architecture, "LAYOUT", {**architecture.LAYOUT, "detect/ghost": (0, 0, 10, 10, "")})
    with pytest.raises(ValueError, match="detect/ghost"):
        architecture.render(ROOT)


def test_relative_links_resolve() -> None:
    """Every relative Markdown link of README, CHANGELOG and docs/ (generated pages included) names a file."""
    pages = [ROOT / "README.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").rglob("*.md"))]
    broken = []
    for page in pages:
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text()):
            if not target.startswith(("http://", "https://", "mailto:")) and not (page.parent / target).exists():
                broken.append(f"{page.relative_to(ROOT)}: {target}")
    assert not broken, f"links to no file: {broken}"
