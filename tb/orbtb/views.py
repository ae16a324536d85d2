# SPDX-License-Identifier: MIT
"""Byte checks of generated views (docs/conventions.md, one source per shared fact): run a
generator of scripts/gen/ into a temporary folder, or load it as a module to test its parts."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path
from types import ModuleType


def load_script(script: Path) -> ModuleType:
    """A generator script loaded as a module (registered in sys.modules: dataclasses need it)."""
    spec = importlib.util.spec_from_file_location(script.stem, script)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[script.stem] = mod
    spec.loader.exec_module(mod)
    return mod


def regenerate(script: Path, out: Path) -> None:
    """Run the generator with every view written under `out` instead of the repository."""
    subprocess.run([sys.executable, str(script), "--out", str(out)], check=True, capture_output=True)


def assert_view_fresh(script: Path, view: Path, root: Path, tmp: Path) -> None:
    """The committed `view` (relative to root) is byte for byte what the generator writes now."""
    regenerate(script, tmp)
    assert (tmp / view).read_bytes() == (root / view).read_bytes(), (
        f"{view} is stale: run `.venv/bin/python {script.relative_to(root)}`"
    )


def assert_deterministic(script: Path, views: tuple[Path, ...], tmp: Path) -> None:
    for d in ("a", "b"):
        regenerate(script, tmp / d)
    for view in views:
        assert (tmp / "a" / view).read_bytes() == (tmp / "b" / view).read_bytes(), f"{view} differs between two runs"
