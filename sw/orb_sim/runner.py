# SPDX-License-Identifier: MIT
"""Build and run a cocotb module on GHDL through cocotb_tools.runner: a test of tb/ or a job of
orb_sim.jobs.

One build directory per (toplevel, back end, worker), so `pytest -n` workers never share one, built
once while hdl/ stays as it is: GHDL takes the generics when the simulation starts (`ghdl -r
-gNAME=VALUE`), so one build serves every generic set; a stamp of the sources' contents says when to
build again (GHDL's `-i` then `-m` would analyse every file again on each call: about 5 to 10 s a
test). A netlist simulation keeps one directory per generic set (its generics are fixed at
synthesis). GHDL's llvm back end is used when installed (`apt-get install ghdl-llvm`: native code, faster
simulation), else the mcode back end; ORB_GHDL_BACKEND=mcode forces mcode. Generics are also
passed to Python through the environment (ORB_<NAME>), since GHDL's VPI cannot read them
reliably. The sources are hdl/manifest.txt's (orb_sim.hdl).

Netlist simulation (`run(..., netlist=True)` or ORB_NETLIST=1; docs/netlist-sim.md): the toplevel
is first synthesised by orb_sim.netlist.synth_netlist, and the same module runs on that netlist
(compiled with the packages only) instead of the RTL. The generics are fixed at synthesis; the
ORB_<NAME> environment is the same. Only the toplevel's ports exist in a netlist.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
from collections.abc import Mapping, Sequence
from pathlib import Path

from .hdl import BUILD as BUILD_ROOT
from .hdl import packages, sources
from .netlist import synth_netlist

BUILD = BUILD_ROOT / "sim_build"


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


def build_stamp(toplevel: str, backend: str, files: Sequence[Path], waves: bool) -> str:
    """What a build depends on: the toplevel, the back end, the waves option and each source's
    path and contents, as one digest."""
    h = hashlib.sha1(repr((toplevel, backend, waves, "--std=08")).encode())
    for f in files:
        h.update(str(f).encode() + b"\0" + Path(f).read_bytes() + b"\0")
    return h.hexdigest()


def run(
    toplevel: str,
    module: str,
    generics: Mapping[str, int | str],
    env: Mapping[str, str] | None = None,
    testcase: str | Sequence[str] | None = None,
    waves: bool = False,
    log_file: Path | None = None,
    netlist: bool | None = None,
    python_path: Sequence[Path] = (),
) -> Path:
    """Build `toplevel` (when its sources changed) and run the cocotb `module` on it (a test module of
    tb/, found through `python_path`, or a job module of orb_sim.jobs).

    netlist (default: ORB_NETLIST=1 in the environment): simulate GHDL's synthesised netlist of
    `toplevel` with these generics instead of the RTL (see the module docstring)."""
    from cocotb_tools.runner import get_runner

    if netlist is None:
        netlist = os.environ.get("ORB_NETLIST", "") not in ("", "0")
    os.environ.update(ghdl_path_env())
    # One build directory per (pytest-xdist worker, toplevel, back end), and per generic set and
    # test module for a netlist: two tests running at once on different workers never share one.
    backend = os.environ.get("ORB_GHDL_BACKEND", "llvm" if shutil.which("ghdl-llvm") else "mcode")
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    key: tuple[object, ...] = (worker, toplevel, backend)
    if netlist:
        key = (*key, module, sorted(generics.items()), "netlist")
    tag = hashlib.sha1(repr(key).encode()).hexdigest()[:10]
    build_dir = BUILD / f"{toplevel}-{tag}"
    runner = get_runner("ghdl")
    if netlist:
        netlist_file, record = synth_netlist(toplevel, generics, build_dir)
        for problem in record["interface_problems"]:
            print(f"orbtb.runner: netlist interface of {toplevel}: {problem}")
        files = [*packages(), netlist_file]
    else:
        files = sources()
    build_dir.mkdir(parents=True, exist_ok=True)
    # A lock, since a test may start a second simulation of the same toplevel (a server) at once.
    with open(build_dir / ".build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        stamp = build_dir / ".build.stamp"
        want = build_stamp(toplevel, backend, files, waves)
        if netlist or not stamp.exists() or stamp.read_text() != want:
            stamp.unlink(missing_ok=True)
            runner.build(
                sources=files,
                hdl_toplevel=toplevel,
                build_args=["--std=08"],
                build_dir=build_dir,
                always=True,
                waves=waves,
                log_file=log_file,
            )
            stamp.write_text(want)
    extra_env = {f"ORB_{k.removesuffix('_g')}": str(v) for k, v in generics.items()}
    # Rewrite asserts only in test modules (rewriting numpy/scikit-image costs seconds per start).
    extra_env["COCOTB_REWRITE_ASSERTION_FILES"] = "test_*.py"
    extra_env.update(env or {})
    extra_env["PYTHONPATH"] = os.pathsep.join([*(str(p) for p in python_path), os.environ.get("PYTHONPATH", "")])
    return runner.test(
        test_module=module,
        hdl_toplevel=toplevel,
        hdl_toplevel_lang="vhdl",  # said, since build() may not have run in this process
        parameters={} if netlist else dict(generics),  # a netlist's generics are fixed at synthesis
        test_args=["--std=08"],
        build_dir=build_dir,
        test_dir=build_dir,  # ghdl -r runs where the build is; tb/ is on PYTHONPATH
        extra_env=extra_env,
        testcase=testcase,
        waves=waves,
        log_file=log_file,
    )
