# SPDX-License-Identifier: MIT
"""Build and run a cocotb test on GHDL through cocotb_tools.runner.

One build directory per (toplevel, generics) so `pytest -n` workers never share one. GHDL's llvm
back end is used when installed (`apt-get install ghdl-llvm`: native code, faster simulation),
else the mcode back end. Generics are also passed to Python through the environment (ORB_<NAME>),
since GHDL's VPI cannot read them reliably. ORB_GHDL_BACKEND=mcode forces the mcode back end.
"""

from __future__ import annotations

import hashlib
import os
import shutil
from collections.abc import Mapping, Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HDL = ROOT / "hdl"
TB = ROOT / "tb"
BUILD = ROOT / "build" / "sim_build"

# Dependency order (packages first).
SOURCES = (
    "orb_util_pkg.vhd",
    "orb_fast_pkg.vhd",
    "orb_feat_pkg.vhd",
    "orb_rgb_luma.vhd",
    "orb_video_check.vhd",
    "orb_pattern_pkg.vhd",
    "orb_regs_pkg.vhd",
    "orb_line_buffer.vhd",
    "orb_window.vhd",
    "orb_fast_score.vhd",
    "orb_fast_nms.vhd",
    "orb_smooth.vhd",
    "orb_orient_moments.vhd",
    "orb_orient_sector.vhd",
    "orb_scaler.vhd",
    "orb_fast_detect.vhd",
    "orb_desc_path.vhd",
    "orb_scale_path.vhd",
    "orb_feat_fifo.vhd",
    "orb_feat_merge.vhd",
    "orb_feat_mem.vhd",
    "orb_axil_regs.vhd",
    "orb_overlay.vhd",
    "orb_detect_top.vhd",
    "orb_accel_top.vhd",
    "orb_accel_zynq.vhd",
)


class ToolMissing(RuntimeError):
    """A simulator or tool is not installed; the message says how to install it."""


def ghdl_path_env() -> dict[str, str]:
    """PATH with `ghdl` resolving to ghdl-llvm when it is installed."""
    if shutil.which("ghdl") is None and shutil.which("ghdl-llvm") is None:
        raise ToolMissing("GHDL is not installed: apt-get install ghdl-llvm (or ghdl-mcode)")
    env_path = os.environ.get("PATH", "")
    llvm = shutil.which("ghdl-llvm")
    if llvm is None or os.environ.get("ORB_GHDL_BACKEND") == "mcode":
        return {"PATH": env_path}
    shim = BUILD / "ghdl-llvm-bin"
    shim.mkdir(parents=True, exist_ok=True)
    link = shim / "ghdl"
    if not link.exists():
        tmp = shim / f"ghdl.{os.getpid()}"
        tmp.symlink_to(llvm)
        tmp.replace(link)
    return {"PATH": f"{shim}{os.pathsep}{env_path}"}


def run(
    toplevel: str,
    module: str,
    generics: Mapping[str, int | str],
    env: Mapping[str, str] | None = None,
    testcase: str | Sequence[str] | None = None,
    waves: bool = False,
    log_file: Path | None = None,
) -> Path:
    """Build `toplevel` (once per generic set) and run the cocotb `module` (in tb/) on it."""
    from cocotb_tools.runner import get_runner

    os.environ.update(ghdl_path_env())
    # One build directory per (pytest-xdist worker, test module, back end, generics): two tests
    # with the same generics running at once on different workers never share one.
    backend = os.environ.get("ORB_GHDL_BACKEND", "llvm" if shutil.which("ghdl-llvm") else "mcode")
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    tag = hashlib.sha1(repr((worker, module, backend, sorted(generics.items()))).encode()).hexdigest()[:10]
    build_dir = BUILD / f"{toplevel}-{tag}"
    runner = get_runner("ghdl")
    runner.build(
        sources=[HDL / s for s in SOURCES],
        hdl_toplevel=toplevel,
        build_args=["--std=08"],
        build_dir=build_dir,
        always=True,
        waves=waves,
        log_file=log_file,
    )
    extra_env = {f"ORB_{k.removesuffix('_g')}": str(v) for k, v in generics.items()}
    # Rewrite asserts only in test modules (rewriting numpy/scikit-image costs seconds per start).
    extra_env["COCOTB_REWRITE_ASSERTION_FILES"] = "test_*.py"
    extra_env.update(env or {})
    extra_env["PYTHONPATH"] = os.pathsep.join([str(TB), str(ROOT), os.environ.get("PYTHONPATH", "")])
    return runner.test(
        test_module=module,
        hdl_toplevel=toplevel,
        parameters=dict(generics),
        test_args=["--std=08"],
        build_dir=build_dir,
        test_dir=build_dir,  # ghdl -r runs where the build is; tb/ is on PYTHONPATH
        extra_env=extra_env,
        testcase=testcase,
        waves=waves,
        log_file=log_file,
    )
