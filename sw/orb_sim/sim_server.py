# SPDX-License-Identifier: MIT
"""Start and stop the simulated accelerator as a bus server (orb_sim.jobs.sim_server_job) in its
own process group, so that a driver in any other process reaches it through
orb_accel.socket_bus.SocketBus exactly as it reaches the board through UIO:

    with SimServer(frames, "sim-qvga") as server:      # frames: (N, H, W, 3) RGB or (N, H, W) luma
        with SocketBus(server.address) as bus:
            accel = OrbAccel(bus)

The bitstream-like configuration is fixed when the server starts: the generics of a named
configuration (docs/configurations.md; default DEFAULT_CONFIG, the board's shape at 320x240) at
the frames' size (WIDTH_g, HEIGHT_g; the CLI resizes the frames to the configuration's size unless
told), each of SCALES_g, STEP_*_g, SECTORS_g, MEM_DEPTH_g replaceable by an argument; the frames
stream in round and round with blanking (h_blank clocks per line, v_blank_lines blank lines per
frame). `python -m orb_sim.sim_server JOB` is the child process: engine "ghdl" runs the cocotb job
through orb_sim.runner, engine "fast" serves the synthesised netlist in Verilator (orb_sim.fast;
orb_accel_top only; no frames.log). `faults` (orb_sim.faults: cable cuts, error responses) are
injected by the server, for the CPU side's fault tests (docs/driver.md, "Faults and recovery").

`mem_kind` (default: the configuration's; the board builds' is "ddr"): "ddr" builds the DDR
feature memory (MEM_KIND_g "DDR", docs/feature-dma.md), whose frames go into a simulated DDR
region (`ddr_region`, default DDR_REGION, orb_sim.ddr_ram's): the HELLO answer gives it
(SocketBus.memory_region) and the client reads it with orb_accel.socket_bus.SocketMemory:

    with SimServer(frames, "board-vga") as server, SocketBus(server.address) as bus:
        accel = OrbAccel(bus, memory=SocketMemory(bus))
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from types import TracebackType

import numpy as np

from golden_model import limits
from golden_model.config import Config, named
from golden_model.overlay import marker_block_log2

from .faults import AxiFault, Cut, parse
from .hdl import MANIFEST
from .runner import run

TOPLEVELS = ("orb_accel_top", "orb_accel_zynq")
ENGINES = ("ghdl", "fast")
DEFAULT_CONFIG = "sim-qvga"  # the simulated bitstream of sim-server, ros --sim, board --sim
MEM_KINDS = ("bram", "ddr")  # golden_model's mem_kind: MEM_KIND_g "BRAM", "DDR"
# a DDR build's emulated reserved region (base, size): orb_sim.ddr_ram's DDR_BASE, DDR_SIZE (and the
# fast harness's), written out here: this module is pure Python at import (the board's CLI imports it)
DDR_REGION = (0x1000_0000, 4 << 20)


class SimServerError(RuntimeError):
    """The simulation server did not start (no simulator, a failed build); the message says why."""


class SimServer:
    def __init__(self, frames: np.ndarray, config: str = DEFAULT_CONFIG, *, scales: int | None = None,
                 sectors: int | None = None, mem_depth: int | None = None, step: tuple[int, int] | None = None,
                 toplevel: str = "orb_accel_top", port: int = 0, h_blank: int = 16, v_blank_lines: int = 20,
                 job_dir: Path | None = None, engine: str = "ghdl", faults: Sequence[str] = (),
                 mem_kind: str | None = None, ddr_region: tuple[int, int] = DDR_REGION) -> None:  # fmt: skip
        nc = named(config)
        mem_kind = nc.mem_kind if mem_kind is None else mem_kind
        if mem_kind not in MEM_KINDS:
            raise ValueError(f"mem_kind {mem_kind!r} not one of {MEM_KINDS}")
        # the overlay's block: the configuration's, or the smallest that fits replaced scales
        block_log2 = nc.block_log2 if scales is None else marker_block_log2(scales)
        scales = nc.scales if scales is None else scales
        sectors = nc.sectors if sectors is None else sectors
        mem_depth = nc.mem_depth if mem_depth is None else mem_depth
        step = (nc.step_num, nc.step_den) if step is None else step
        frames = np.asarray(frames)
        if frames.dtype != np.uint8 or frames.ndim not in (3, 4) or (frames.ndim == 4 and frames.shape[3] != 3):
            raise ValueError(f"frames must be (N, H, W, 3) or (N, H, W) uint8, got {frames.shape} {frames.dtype}")
        if len(frames) == 0:
            raise ValueError("no frames to stream")
        if toplevel not in TOPLEVELS:
            raise ValueError(f"toplevel {toplevel!r} not one of {TOPLEVELS}")
        if engine not in ENGINES or (engine == "fast" and toplevel != "orb_accel_top"):
            raise ValueError(f"engine {engine!r}: one of {ENGINES} ('fast' simulates orb_accel_top only)")
        height, width = frames.shape[1:3]
        for lim, value in ((limits.WIDTH, width), (limits.HEIGHT, height), (limits.SCALES, scales),
                           (limits.SECTORS, sectors), (limits.MEM_DEPTH, mem_depth)):  # fmt: skip
            if not lim.legal(value):
                raise ValueError(f"{lim.name} must be {lim.text}, got {value}")
        Config(
            int(width), int(height), scales, sectors, step_num=step[0], step_den=step[1]
        )  # the step and the level sizes
        parsed = [parse(f) for f in faults]
        if engine != "fast" and any(isinstance(f, Cut) for f in parsed):
            raise ValueError("a cable cut (fault cut:...) is played by the fast engine only (engine='fast')")
        if engine != "fast" and any(isinstance(f, AxiFault) for f in parsed):
            raise ValueError("an interconnect fault (axistall, axierr, axislow) is the fast engine's (engine='fast')")
        if toplevel == "orb_accel_zynq" and frames.ndim != 4:
            raise ValueError("orb_accel_zynq takes colour frames (N, H, W, 3)")
        self.frames = frames
        self.generics: dict[str, int | str] = {
            "WIDTH_g": int(width), "HEIGHT_g": int(height), "SCALES_g": scales, "STEP_NUM_g": int(step[0]),
            "STEP_DEN_g": int(step[1]), "SECTORS_g": sectors, "BLOCK_LOG2_g": block_log2,
            "MEM_DEPTH_g": mem_depth,
            "INPUT_g": ("RBG" if toplevel == "orb_accel_zynq" else "RGB") if frames.ndim == 4 else "LUMA",
        }  # fmt: skip
        if mem_kind == "ddr":  # left out for "bram" (the tops' default): the BRAM build keeps its build directory
            self.generics["MEM_KIND_g"] = "DDR"
        self.mem_kind = mem_kind
        self.toplevel = toplevel
        ddr = {"base": int(ddr_region[0]), "size": int(ddr_region[1])} if mem_kind == "ddr" else None
        self.config = {"toplevel": toplevel, "generics": self.generics, "host": "127.0.0.1", "port": port,
                       "engine": engine, "h_blank": h_blank,
                       "v_blank": v_blank_lines * (int(width) + h_blank),
                       "faults": [f.text for f in parsed],
                       "ddr": ddr}  # fmt: skip
        self._tmp: tempfile.TemporaryDirectory | None = None
        self.job = None if job_dir is None else Path(job_dir).resolve()
        self.address = ""
        self.proc: subprocess.Popen | None = None

    @property
    def log(self) -> Path:
        assert self.job is not None
        return self.job / "sim.log"

    def start(self, timeout_s: float = 900.0) -> str:
        """Build and start the simulation; returns its address once it listens."""
        if not MANIFEST.is_file():
            raise SimServerError(f"the simulator needs the HDL ({MANIFEST} is missing)")
        if self.job is None:
            self._tmp = tempfile.TemporaryDirectory(prefix="orb-sim-server-")
            self.job = Path(self._tmp.name)
        self.job.mkdir(parents=True, exist_ok=True)
        (self.job / "address").unlink(missing_ok=True)
        np.save(self.job / "frames.npy", np.ascontiguousarray(self.frames))
        (self.job / "config.json").write_text(json.dumps(self.config, indent=1) + "\n")
        with open(self.log, "w") as log:
            self.proc = subprocess.Popen([sys.executable, "-m", "orb_sim.sim_server", str(self.job)],
                                         stdout=log, stderr=subprocess.STDOUT, start_new_session=True)  # fmt: skip
        deadline = time.monotonic() + timeout_s
        address = self.job / "address"
        while not address.exists():
            if self.proc.poll() is not None:
                tail = "\n".join(self.log.read_text(errors="replace").splitlines()[-15:])
                raise SimServerError(f"the simulation server exited ({self.proc.returncode}); {self.log}:\n{tail}")
            if time.monotonic() > deadline:
                self.stop()
                raise SimServerError(f"the simulation server did not listen within {timeout_s:g} s; see {self.log}")
            time.sleep(0.1)
        self.address = address.read_text().strip()
        return self.address

    def frames_sent(self) -> list[tuple[int, int, int]]:
        """(sequence number, index in the frames, clock of its first pixel) of every frame started."""
        assert self.job is not None
        path = self.job / "frames.log"
        rows = path.read_text().split("\n") if path.exists() else []
        return [tuple(int(v) for v in r.split()) for r in rows if r.count(" ") == 2]  # type: ignore[misc]

    def stop(self) -> None:
        """Stop the simulation and everything it started (its process group)."""
        if self.proc is not None and self.proc.poll() is None:
            for sig, wait_s in ((signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
                try:
                    os.killpg(self.proc.pid, sig)
                except ProcessLookupError:
                    break
                try:
                    self.proc.wait(wait_s)
                    break
                except subprocess.TimeoutExpired:
                    continue
        if self.proc is not None:
            try:  # a child (ghdl) may outlive the leader: the group goes too
                os.killpg(self.proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        self.proc = None

    def close(self) -> None:
        self.stop()
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None

    def __enter__(self) -> SimServer:
        self.start()
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.close()


def _child(job: Path) -> int:
    cfg = json.loads((job / "config.json").read_text())
    if cfg.get("engine") == "fast":
        return _serve_fast(job, cfg)
    run(cfg["toplevel"], "orb_sim.jobs.sim_server_job", cfg["generics"], env={"ORB_JOB_DIR": str(job)})
    return 0


def _serve_fast(job: Path, cfg: dict) -> int:
    """The fast engine: the netlist in Verilator, frames looping, served until SHUTDOWN."""
    from .bus_server import listen, serve, server_info
    from .fast.build import build_fast
    from .fast.jobs import pack
    from .fast.sim import PERIOD_NS, FastBus, FastSim
    from .faults import FaultyBus, apply_axi_faults, video_schedule

    frames = np.load(job / "frames.npy")
    faults = [parse(f) for f in cfg.get("faults", [])]
    sim = FastSim(build_fast(cfg["generics"]))
    ddr = cfg.get("ddr")
    if ddr:
        sim.set_mem_region(int(ddr["base"]), int(ddr["size"]))
    sim.reset()
    apply_axi_faults(sim, faults)  # the DDR interconnect's stalls, slowness and error responses
    # as orb_sim.video.Gaps("blanking"), with the cuts of the faults
    for program in video_schedule([pack(img) for img in frames], faults, cfg["h_blank"], cfg["v_blank"]):
        sim.push(*program)
    sim.set_loop(True)
    listener = listen(job, cfg["host"], cfg["port"])
    info = server_info(cfg, len(frames), PERIOD_NS, "fast", sim.memory_region if ddr else None)
    try:
        serve(listener, FaultyBus(FastBus(sim), faults), info)
    finally:
        listener.close()
        sim.close()
    return 0


if __name__ == "__main__":
    sys.exit(_child(Path(sys.argv[1])))
