# SPDX-License-Identifier: MIT
"""The HDL compile manifest (hdl/manifest.txt): every VHDL file of hdl/ in dependency order.

The one list of sources that simulation, lint, the synthesis estimate, the FuseSoC core and the
Vivado TCL read. One entity (or package) per file, named after the file.

Where the HDL is (docs/conventions.md, "The installed package"), one rule: when this module runs
from a source checkout (sw/orb_sim/hdl.py with hdl/manifest.txt two folders up: `make setup`'s
editable install, PYTHONPATH=sw), the checkout's hdl/; otherwise (an installed wheel) the copy the
wheel carries as package data, orb_sim/data/hdl/ (hdl/manifest.txt and every hdl/*/*.vhd).
Outputs (simulation builds, the fast path's libraries) go to BUILD: the checkout's build/, or for
an installed package $XDG_CACHE_HOME/orb-accel (~/.cache/orb-accel); ORB_ACCEL_BUILD overrides both.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path


def _checkout() -> Path | None:
    """The source checkout this module runs from, or None for an installed package."""
    root = Path(__file__).resolve().parents[2]
    here = Path(__file__).resolve().parent
    return root if here == root / "sw" / "orb_sim" and (root / "hdl" / "manifest.txt").is_file() else None


def _package_data() -> Path:
    """orb_sim/data, where the wheel puts hdl/ (a folder on disk: GHDL and Verilator read the files)."""
    return Path(str(files(__package__ or "orb_sim") / "data"))


CHECKOUT = _checkout()
ROOT = CHECKOUT if CHECKOUT is not None else _package_data()  # the folder holding hdl/
HDL = ROOT / "hdl"
MANIFEST = HDL / "manifest.txt"


def _build() -> Path:
    if os.environ.get("ORB_ACCEL_BUILD"):
        return Path(os.environ["ORB_ACCEL_BUILD"]).resolve()
    if CHECKOUT is not None:
        return CHECKOUT / "build"
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "orb-accel"


BUILD = _build()


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
