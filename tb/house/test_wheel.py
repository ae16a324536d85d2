# SPDX-License-Identifier: MIT
"""A plain (not editable) install of the wheel works without the checkout (docs/conventions.md,
"The installed package").

The wheel is built offline from a copy of the files it is made of (pyproject.toml, README.md,
golden_model/, sw/, hdl/; `pip wheel --no-deps --no-build-isolation --no-index`) and installed into
a fresh venv, which sees the project venv's site-packages (numpy, OpenCV, Verilator) through a
.pth line, not its editable install. From that venv, with the working directory outside the
checkout:
- the CLI's `orb-accel extract --default-image` writes what the model computes in-process;
- orb_sim.hdl finds the HDL the wheel carries (orb_sim/data/hdl, the manifest's files byte for
  byte the checkout's);
- `orb-accel sim --fast` runs the fast path (GHDL's netlist of the wheel's HDL in Verilator with
  the wheel's harness.cpp) on a 128x96 frame, and its features equal the model's, bit for bit.
The fast path's library is the one tb/fast builds (128x96, 2 scales, 32 sectors, 512 slots, RGB):
ORB_ACCEL_BUILD points the installed package at the checkout's build/, whose cache is keyed by the
netlist's and the harness's bytes, so a library is reused only when the wheel's GHDL netlist and
harness are the checkout's, byte for byte (else it is built: about 2 minutes more).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import cv2
import pytest

from golden_model import Config, extract, first_difference
from golden_model.config import (
    RECOMMENDED_COLS,
    RECOMMENDED_ROWS,
    RECOMMENDED_SCALES,
    RECOMMENDED_SECTORS,
    RECOMMENDED_STEP,
    RECOMMENDED_THRESHOLD_LO,
    named,
    recommended_budget,
)
from golden_model.features import read_csv
from golden_model.images import DEFAULT_IMAGE, to_luma
from golden_model.luma import rgb_to_luma
from orb_sim.hdl import BUILD, MANIFEST, ROOT, read_manifest
from orb_tools.images import load_rgb_or_grey

PARTS = ("pyproject.toml", "README.md", "golden_model", "sw", "hdl")
TINY = named("test-tiny")  # tb/fast/test_fast_sim.py's configuration (docs/configurations.md)


def run(cmd: list[str], cwd: Path, env: dict[str, str] | None = None, timeout: float = 600) -> str:
    r = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout, check=False)
    assert r.returncode == 0, f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    return r.stdout


@pytest.fixture(scope="module")
def venv(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A venv with the wheel installed (not editable); returns its bin/ folder."""
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    src.mkdir()
    for part in PARTS:
        if (ROOT / part).is_dir():
            shutil.copytree(ROOT / part, src / part, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
        else:
            shutil.copy(ROOT / part, src / part)
    run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index", "--wheel-dir",
         str(tmp / "dist"), str(src)], cwd=tmp)  # fmt: skip
    (wheel,) = (tmp / "dist").glob("orb_accel-*.whl")
    env = tmp / "venv"
    run([sys.executable, "-m", "venv", "--without-pip", str(env)], cwd=tmp)
    python = env / "bin" / "python"
    site = Path(run([str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], cwd=tmp).strip())
    # the project venv's packages (numpy, OpenCV, Verilator, ...) after the wheel's own: a plain path
    # line, so its editable install's finder (a .pth of that folder) is not run
    (site / "project-deps.pth").write_text(sysconfig.get_path("purelib") + "\n")
    run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "--no-index", str(wheel)],
        cwd=tmp)  # fmt: skip
    return env / "bin"


def outside(tmp_path: Path) -> tuple[Path, dict[str, str]]:
    """A working directory outside the checkout and an environment that names no checkout path."""
    cwd = tmp_path / "work"
    cwd.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    return cwd, env


def test_packages_come_from_the_wheel(venv: Path, tmp_path: Path) -> None:
    cwd, env = outside(tmp_path)
    code = (
        "import golden_model, orb_accel, orb_sim, orb_tools, orb_flow; print(orb_sim.__file__, golden_model.__file__)"
    )
    out = run([str(venv / "python"), "-c", code], cwd, env)
    for path in out.split():
        assert Path(path).is_relative_to(venv.parent), f"{path} is not the wheel's (venv {venv.parent})"


def test_cli_extract_is_the_model(venv: Path, tmp_path: Path) -> None:
    cwd, env = outside(tmp_path)
    run([str(venv / "orb-accel"), "extract", "--default-image", "--out", "f.csv"], cwd, env)
    img = to_luma(load_rgb_or_grey(DEFAULT_IMAGE))
    h, w = img.shape
    # the CLI's defaults: the recommended configuration and grid selection
    cfg = Config(width=w, height=h, scales=RECOMMENDED_SCALES, sectors=RECOMMENDED_SECTORS, threshold=20,
                 step_num=RECOMMENDED_STEP[0], step_den=RECOMMENDED_STEP[1], selection="grid",
                 budget=recommended_budget(w, h), cols=RECOMMENDED_COLS, rows=RECOMMENDED_ROWS,
                 threshold_lo=RECOMMENDED_THRESHOLD_LO)  # fmt: skip
    expected = extract(img, cfg)
    got = read_csv(cwd / "f.csv", sectors_total=cfg.sectors, step=cfg.step)
    assert len(expected) > 100
    assert first_difference(got, expected) is None, first_difference(got, expected)


def test_hdl_is_the_wheels(venv: Path, tmp_path: Path) -> None:
    cwd, env = outside(tmp_path)
    code = (
        "from orb_sim import hdl\n"
        "print(hdl.CHECKOUT)\nprint(hdl.HDL)\n"
        "for s in hdl.read_manifest(): print(s.rel, s.path)\n"
    )
    lines = run([str(venv / "python"), "-c", code], cwd, env).splitlines()
    assert lines[0] == "None", "the installed package took itself for a checkout"
    hdl = Path(lines[1])
    assert hdl.is_relative_to(venv.parent) and hdl.parts[-3:] == ("orb_sim", "data", "hdl"), hdl
    listed = [line.split() for line in lines[2:]]
    assert [rel for rel, _ in listed] == [s.rel for s in read_manifest()], "the wheel's manifest is not the checkout's"
    for rel, path in listed:
        assert Path(path).read_bytes() == (MANIFEST.parent / rel).read_bytes(), f"{rel} differs from the checkout's"
    assert (hdl / "manifest.txt").read_bytes() == MANIFEST.read_bytes()


def test_fast_path_is_bit_exact(venv: Path, tmp_path: Path) -> None:
    cwd, env = outside(tmp_path)
    env["ORB_ACCEL_BUILD"] = str(BUILD)  # the checkout's cache (see the module's docstring)
    rgb = cv2.resize(load_rgb_or_grey(DEFAULT_IMAGE), (TINY.width, TINY.height), interpolation=cv2.INTER_AREA)
    cv2.imwrite(str(cwd / "small.png"), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    run([str(venv / "orb-accel"), "sim", "--fast", "--image", "small.png", "--config", TINY.name, "--out-dir", "sim"],
        cwd, env, timeout=900)  # fmt: skip
    expected = extract(rgb_to_luma(rgb), TINY.config())
    got = read_csv(cwd / "sim" / "features.csv", sectors_total=TINY.sectors, step=(TINY.step_num, TINY.step_den))
    assert len(expected) > 20
    assert first_difference(got, expected) is None, first_difference(got, expected)
