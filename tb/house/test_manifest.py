# SPDX-License-Identifier: MIT
"""hdl/manifest.txt, the one list of HDL sources: it names every VHDL file under hdl/ exactly once,
each file holds one design unit named after it (prefix orb_, in its data-flow area), and the
order is a valid compile order (GHDL analyses the files one by one in that order)."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from orb_sim.hdl import HDL, read_manifest

AREAS = ("common", "input", "detect", "describe", "core", "host", "output", "top")


def test_manifest_names_every_vhdl_file_once() -> None:
    listed = sorted(s.path for s in read_manifest())
    on_disk = sorted(HDL.rglob("*.vhd")) + sorted(HDL.rglob("*.vhdl"))
    missing, absent = sorted(set(on_disk) - set(listed)), sorted(set(listed) - set(on_disk))
    assert listed == sorted(on_disk), f"not in the manifest: {missing}; listed but absent: {absent}"


def test_one_unit_per_file_named_after_it() -> None:
    for s in read_manifest():
        text = re.sub(r"--[^\n]*", "", s.path.read_text())
        units = re.findall(r"(?im)^\s*(entity|package)\s+(\w+)\s+is\b", text)
        assert [u[1].lower() for u in units] == [s.name], f"{s.rel}: design units {units}, expected only {s.name}"
        assert s.name.startswith("orb_"), f"{s.rel}: names start with orb_"
        assert s.area in AREAS, f"{s.rel}: area {s.area} not one of {AREAS}"
        assert (units[0][0].lower() == "package") == s.is_package, f"{s.rel}: packages and only packages end in _pkg"


def test_manifest_order_is_a_compile_order(tmp_path: Path) -> None:
    ghdl = shutil.which("ghdl")
    if ghdl is None:
        pytest.fail("GHDL is not installed: apt-get install ghdl")
    for s in read_manifest():  # one file at a time: a unit used before it is analysed fails
        r = subprocess.run([ghdl, "-a", "--std=08", f"--workdir={tmp_path}", str(s.path)], capture_output=True,
                           text=True, check=False)  # fmt: skip
        assert r.returncode == 0, f"{s.rel} does not analyse after the files before it:\n{r.stderr[-2000:]}"
