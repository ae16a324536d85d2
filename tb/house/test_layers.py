# SPDX-License-Identifier: MIT
"""Python layers import one way (docs/conventions.md): golden_model <- orb_accel <- orb_sim <-
orb_tools <- orbtb and the tests. The import-linter contracts of pyproject.toml hold, and nothing
outside tb/ imports the testbench package or puts tb/ on its path."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

from orb_sim.hdl import ROOT

LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")


def test_import_contracts_hold() -> None:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "tb"), os.environ.get("PYTHONPATH", "")])}
    r = subprocess.run([str(LINT_IMPORTS), "--no-cache"], cwd=ROOT, env=env, capture_output=True, text=True,
                       check=False)  # fmt: skip
    assert r.returncode == 0, f"lint-imports:\n{r.stdout[-4000:]}\n{r.stderr[-2000:]}"
    assert "broken" in r.stdout and " 0 broken" in r.stdout, r.stdout[-2000:]


def test_nothing_outside_tb_reaches_into_tb() -> None:
    bad = []
    for folder in ("golden_model", "sw", "scripts"):
        for f in sorted((ROOT / folder).rglob("*.py")):
            text = f.read_text()
            if re.search(r"(?m)^\s*(from|import)\s+orbtb\b", text) or re.search(r"""["']tb["']\s*\)""", text):
                bad.append(str(f.relative_to(ROOT)))
    assert not bad, f"files outside tb/ that import orbtb or put tb/ on the path: {bad}"


# the runtime needs of the ROS node: Debian's dist-packages appended for rospy, and the folder of the
# messages it generates at run time put first (sw/orb_ros/msgs.py)
SYS_PATH_ALLOWED = {"sw/orb_ros/msgs.py": 2, "sw/orb_ros2/interfaces.py": 1}


def test_no_sys_path_inserts_or_loaded_scripts() -> None:
    """Code imports code as packages: no sys.path insert (python -m, a package, relative imports)
    and no script loaded from its file (orb_flow's modules import normally)."""
    bad = []
    for folder in ("golden_model", "sw", "scripts", "research", "vivado", "tb"):
        for f in sorted((ROOT / folder).rglob("*.py")):
            rel = str(f.relative_to(ROOT))
            if rel == "tb/house/test_layers.py":
                continue
            text = f.read_text()
            n = len(re.findall(r"sys\.path\.(insert|append)\(|spec_from_file_location|load_script", text))
            if n > SYS_PATH_ALLOWED.get(rel, 0):
                bad.append(rel)
    assert not bad, f"sys.path inserts or scripts loaded from their files: {bad}"
