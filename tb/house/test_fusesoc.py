# SPDX-License-Identifier: MIT
"""orb_accel.core, the FuseSoC CAPI2 view of hdl/manifest.txt: generated (byte-checked against the
generator), listed and shown by `fusesoc`, and its lint target built by fusesoc with GHDL (every
manifest file analysed in order, orb_accel_top elaborated)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from orb_sim.hdl import ROOT, read_manifest

CORE = ROOT / "orb_accel.core"
FUSESOC = Path(sys.executable).with_name("fusesoc")


def fusesoc(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    # only the core's folder is a cores root: the generated file and nothing else of the tree
    return subprocess.run([str(FUSESOC), "--cores-root", str(cwd / "cores"), *args], cwd=cwd, capture_output=True,
                          text=True, timeout=600, check=False)  # fmt: skip


@pytest.fixture
def cores(tmp_path: Path) -> Path:
    """A cores root holding orb_accel.core with hdl/ beside it (as a user's checkout has)."""
    (tmp_path / "cores").mkdir()
    shutil.copy(CORE, tmp_path / "cores" / CORE.name)
    (tmp_path / "cores" / "hdl").symlink_to(ROOT / "hdl")
    return tmp_path


def test_core_is_what_the_generator_writes(tmp_path: Path) -> None:
    out = tmp_path / "orb_accel.core"
    subprocess.run([sys.executable, "-m", "orb_flow.gen.core", "--out", str(out)], check=True, capture_output=True)
    assert out.read_bytes() == CORE.read_bytes(), "orb_accel.core is stale: run `make views`"


def test_core_lists_every_manifest_file_in_order() -> None:
    listed = [line.strip()[2:] for line in CORE.read_text().splitlines() if line.strip().startswith("- hdl/")]
    assert listed == [f"hdl/{s.rel}" for s in read_manifest()]


def test_fusesoc_lists_and_shows_the_core(cores: Path) -> None:
    listed = fusesoc(["core", "list"], cores)
    assert listed.returncode == 0, listed.stderr
    assert "::orb_accel:0.1.0" in listed.stdout, listed.stdout
    shown = fusesoc(["core", "show", "orb_accel"], cores)
    assert shown.returncode == 0, shown.stderr
    assert "lint" in shown.stdout and "default" in shown.stdout, shown.stdout


def test_fusesoc_builds_the_lint_target_with_ghdl(cores: Path) -> None:
    if shutil.which("ghdl") is None:
        pytest.fail("GHDL is not installed: apt-get install ghdl")
    built = fusesoc(["run", "--target=lint", "--setup", "--build", "--build-root", str(cores / "build"),
                     "::orb_accel"], cores)  # fmt: skip
    assert built.returncode == 0, f"fusesoc run --target=lint failed:\n{built.stdout[-3000:]}\n{built.stderr[-3000:]}"
    assert (cores / "build" / "orb_accel_0.1.0" / "lint-ghdl" / "work-obj08.cf").exists(), "GHDL library not built"
