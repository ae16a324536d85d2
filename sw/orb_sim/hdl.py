# SPDX-License-Identifier: MIT
"""The HDL compile manifest (hdl/manifest.txt): every VHDL file of hdl/ in dependency order.

The one list of sources that simulation, lint, the synthesis estimate, the FuseSoC core and the
Vivado TCL read. One entity (or package) per file, named after the file.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HDL = ROOT / "hdl"
MANIFEST = HDL / "manifest.txt"


@dataclass(frozen=True)
class Source:
    path: Path  # absolute
    rel: str  # relative to hdl/, as the manifest lists it

    @property
    def name(self) -> str:
        """The design unit the file holds (entity or package), named after the file."""
        return self.path.stem

    @property
    def area(self) -> str:
        """The data-flow area (the folder under hdl/)."""
        return self.rel.split("/")[0]

    @property
    def is_package(self) -> bool:
        return self.name.endswith("_pkg")


def read_manifest(manifest: Path = MANIFEST) -> tuple[Source, ...]:
    """The manifest's sources in compile order; raises ValueError on a duplicate or a missing file."""
    out: list[Source] = []
    seen: set[str] = set()
    for n, line in enumerate(manifest.read_text().splitlines(), 1):
        rel = line.split("#", 1)[0].strip()
        if not rel:
            continue
        if rel in seen:
            raise ValueError(f"{manifest}:{n}: {rel} listed twice")
        path = manifest.parent / rel
        if not path.is_file():
            raise ValueError(f"{manifest}:{n}: {rel} does not exist")
        seen.add(rel)
        out.append(Source(path, rel))
    return tuple(out)


def sources() -> list[Path]:
    """Every VHDL file in compile order."""
    return [s.path for s in read_manifest()]


def packages() -> list[Path]:
    """The package files only (all a synthesised netlist needs besides itself)."""
    return [s.path for s in read_manifest() if s.is_package]


def entities() -> dict[str, Source]:
    """Entity name -> its source, for every non-package file."""
    return {s.name: s for s in read_manifest() if not s.is_package}


def find_entity(name: str) -> Source:
    try:
        return entities()[name]
    except KeyError:
        raise ValueError(f"entity {name} is not in {MANIFEST}") from None
