# SPDX-License-Identifier: MIT
"""A plain `pip install .` (numpy only) leaves out the extras' modules: a command that needs one
(`orb-accel extract` needs OpenCV) says in one line which extra to install, instead of a traceback;
a missing module that belongs to no extra is still a traceback (a bug, not a missing extra). Run
in a subprocess with the extras' modules hidden (None in sys.modules: importing one raises
ModuleNotFoundError, as on a machine without them)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from golden_model.images import DEFAULT_IMAGE
from orb_tools.cli import EXTRAS

ROOT = Path(__file__).resolve().parents[2]

HIDE = """
import sys
for name in {hidden!r}:
    sys.modules[name] = None
from orb_tools.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _run(hidden: list[str], *args: str) -> subprocess.CompletedProcess[str]:
    env = {"PYTHONPATH": f"{ROOT}:{ROOT / 'sw'}", "PATH": "/usr/bin:/bin"}
    code = HIDE.format(hidden=hidden)
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=120,
                          cwd=ROOT, env=env)  # fmt: skip


@pytest.mark.parametrize("command", ["extract", "sim"])
def test_missing_extra_is_one_line(command: str, tmp_path: Path) -> None:
    args = [str(DEFAULT_IMAGE), "--out", str(tmp_path / "f.csv")] if command == "extract" else ["--size", "64x48"]
    r = _run(sorted(EXTRAS), command, *args)
    assert r.returncode == 2, (r.returncode, r.stderr[-2000:])
    lines = r.stderr.strip().splitlines()
    assert "Traceback" not in r.stderr and len(lines) == 1, r.stderr[-2000:]
    assert lines[0].startswith(f"orb-accel: error: `orb-accel {command}` needs OpenCV (the module cv2)"), lines[0]
    assert "pip install 'orb-accel[tools]'" in lines[0], lines[0]
    assert not (tmp_path / "f.csv").exists()


def test_other_missing_module_is_a_traceback() -> None:
    # numpy belongs to no extra (a base dependency): its absence is not dressed as a missing extra
    r = _run(["numpy"], "extract", str(DEFAULT_IMAGE), "--out", "/dev/null")
    assert r.returncode == 1 and "Traceback" in r.stderr and "ModuleNotFoundError" in r.stderr, r.stderr[-2000:]
    assert "pip install 'orb-accel[" not in r.stderr


def test_extras_are_pyproject_extras() -> None:
    # every extra named in the message is one pyproject.toml declares
    import tomllib

    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert {extra for extra, _ in EXTRAS.values()} <= set(declared), declared
