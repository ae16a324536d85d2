# SPDX-License-Identifier: MIT
"""Run a cocotb test module of tb/ through orb_sim.runner, with tb/ and the module's own folder on
the simulation's Python path (test modules live in tb/<area>/, docs/index.md)."""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache
from pathlib import Path

from orb_sim import runner
from orb_sim.runner import ghdl_path_env

__all__ = ["ghdl_path_env", "run"]

TB = Path(__file__).resolve().parents[1]


@cache
def module_dir(module: str) -> Path:
    """The folder of tb/ that holds test module `module` (test module names are unique in tb/)."""
    found = sorted(TB.rglob(f"{module}.py"))
    if len(found) != 1:
        raise FileNotFoundError(f"test module {module}: {len(found)} files named {module}.py under {TB}")
    return found[0].parent


def run(toplevel: str, module: str, generics: Mapping[str, int | str], **kwargs) -> Path:
    """orb_sim.runner.run for a test module of tb/ (keyword arguments as there)."""
    return runner.run(toplevel, module, generics, python_path=[TB, module_dir(module)], **kwargs)
