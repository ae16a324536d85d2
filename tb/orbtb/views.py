# SPDX-License-Identifier: MIT
"""Byte checks of generated views (docs/conventions.md, one source per shared fact): a generator of
orb_flow.gen renders its views in-process and they must equal the committed files; run as a
command twice into temporary folders, it must write the same bytes."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from types import ModuleType


def regenerate(module: ModuleType, out: Path) -> None:
    """Run the generator as a command with every view written under `out` instead of the repository."""
    subprocess.run([sys.executable, "-m", module.__name__, "--out", str(out)], check=True, capture_output=True)


def assert_view_fresh(module: ModuleType, view: Path, root: Path) -> None:
    """The committed `view` (relative to root) is byte for byte what the generator renders now."""
    text = module.render(root)[Path(view)]
    assert text.encode() == (root / view).read_bytes(), f"{view} is stale: run `make views`"


def assert_deterministic(module: ModuleType, views: tuple[Path, ...], tmp: Path) -> None:
    """Two runs of the generator, in two processes, write byte-identical views."""
    for d in ("a", "b"):
        regenerate(module, tmp / d)
    for view in views:
        assert (tmp / "a" / view).read_bytes() == (tmp / "b" / view).read_bytes(), f"{view} differs between two runs"
