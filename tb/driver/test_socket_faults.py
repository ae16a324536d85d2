# SPDX-License-Identifier: MIT
"""The driver under faults against the simulated accelerator in another process (docs/driver.md,
"Faults and recovery"): orb_sim.sim_server on the fast engine (orb_accel_top's netlist in
Verilator, the 128x96 colour photographs of test_socket_bus.py) injects the faults
(orb_sim.faults), the shipped driver reads frames over orb_accel.socket_bus.SocketBus.

- a cable cut (the video stops half-way through a frame for 20 frame periods, every 6 frames):
  TimeoutError with the status registers while it lasts, counted; frames come back bit-exact with
  rising frame numbers, the driver unchanged;
- error responses (SLVERR to STATUS reads, DECERR to feature-memory reads): BusError naming the
  access and the response, counted; frames keep coming bit-exact without a timeout and the
  accelerator skips none (no bank left held);
- a previous process killed (SIGKILL) while holding a bank: the next driver releases it at open,
  and frames flow, consecutive, none skipped.
The pure-Python versions of these (and the races) are test_driver_faults.py.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator

import numpy as np
import pytest

from golden_model import regs
from golden_model.config import RECOMMENDED_COLS, RECOMMENDED_ROWS, RECOMMENDED_THRESHOLD_LO, named
from golden_model.features import Features, first_difference
from golden_model.luma import rgb_to_luma
from orb_accel import BusError, OrbAccel
from orb_accel.driver import HwConfig
from orb_accel.socket_bus import SocketBus
from orb_sim.sim_server import SimServer
from orbtb.images import colour_photo
from orbtb.scoreboard import expected_features

TINY = named("test-tiny")
W, H, SCALES, SECTORS, DEPTH = TINY.width, TINY.height, TINY.scales, TINY.sectors, TINY.mem_depth
PHOTOS = ("astronaut", "coffee", "chelsea")
SELECTION = (f"grid:{HwConfig(W, H, SCALES, SECTORS, DEPTH).default_budget()}:"
             f"{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}")  # fmt: skip


@pytest.fixture(scope="module")
def frames() -> np.ndarray:
    return np.stack([colour_photo(name, W, H) for name in PHOTOS])


@pytest.fixture(scope="module")
def models(frames: np.ndarray) -> list[Features]:
    return [expected_features(rgb_to_luma(f), SCALES, 20, "orb", SECTORS, (2, 1), SELECTION) for f in frames]


def server(frames: np.ndarray, tmp_path, *faults: str) -> SimServer:
    return SimServer(frames, TINY.name, engine="fast", job_dir=tmp_path / "job", faults=faults)


def period_s(bus: SocketBus) -> float:
    """One frame period of the server's video, in simulated seconds."""
    g = bus.info["generics"]
    return ((g["WIDTH_g"] + bus.info["h_blank"]) * g["HEIGHT_g"] + bus.info["v_blank"]) * bus.info["period_ns"] * 1e-9


def check_photo(feats: Features, models: list[Features]) -> int:
    diffs = [first_difference(feats, m) for m in models]
    assert diffs.count(None) == 1, f"a frame equals no photograph: {diffs}"
    return diffs.index(None)


def test_cable_cut(frames: np.ndarray, models: list[Features], tmp_path) -> None:
    with server(frames, tmp_path, "cut:6:20") as srv, SocketBus(srv.address) as bus:
        assert bus.info["faults"] == ["cut:6:20"]
        accel = OrbAccel(bus)
        accel.configure(threshold=20)
        accel.settle(3 * period_s(bus))
        timeout = 3 * period_s(bus)
        events: list[str] = []  # "F<number>" per frame, "T" per timeout
        numbers: list[int] = []
        for _ in range(60):
            try:
                frame = accel.next_frame(timeout)
            except TimeoutError as exc:
                assert "no interrupt within" in str(exc) and "STATUS = " in str(exc)
                events.append("T")
                continue
            check_photo(frame.features, models)
            numbers.append(frame.number)
            events.append(f"F{frame.number}")
        trail = " ".join(events)
        # runs of frames between the runs of timeouts: every cut ends, and the stream comes back
        runs = [r.split() for r in " ".join("T" if e == "T" else "F" for e in events).split("T") if r.strip()]
        assert events.count("T") >= 6 and len(runs) >= 3, f"no cut seen: {trail}"
        assert all(len(r) >= 5 for r in runs[1:-1]), f"frames did not come back after every cut: {trail}"
        assert numbers == sorted(set(numbers)), f"frame numbers not rising: {trail}"
        assert accel.faults.timeouts == events.count("T") and accel.faults.bus_errors == 0
        assert frame.counters["overrun"] == 0, trail
        print(f"cable cut: {trail}; counters {frame.counters}")


def test_error_responses(frames: np.ndarray, models: list[Features], tmp_path) -> None:
    faults = ("buserr:read:STATUS:4:5", "buserr:block:mem:3:4:decerr")
    with server(frames, tmp_path, *faults) as srv, SocketBus(srv.address) as bus:
        accel = OrbAccel(bus)
        accel.configure(threshold=20)
        accel.settle(3 * period_s(bus))
        errors: dict[str, int] = {}
        got = 0
        for _ in range(40):
            try:
                frame = accel.next_frame(3 * period_s(bus))
            except BusError as exc:
                assert exc.op == "read" and exc.resp in (2, 3), exc
                where = "STATUS" if exc.addr == regs.STATUS.offset else "mem"
                assert (where == "mem") == (exc.addr >= regs.MEM_BASE), exc
                assert str(exc).endswith("answered SLVERR" if where == "STATUS" else "answered DECERR"), exc
                errors[where] = errors.get(where, 0) + 1
                continue
            check_photo(frame.features, models)
            got += 1
        assert errors.get("STATUS", 0) >= 2 and errors.get("mem", 0) >= 2, errors
        assert accel.faults.bus_errors == sum(errors.values()) and accel.faults.timeouts == 0, accel.faults
        assert frame.counters["overrun"] == 0, "a bank left held by an error made the accelerator skip frames"
        assert got >= 20, f"{got} frames in 40 tries"
        print(f"error responses: {errors}, {got} frames, {accel.faults}")


PREDECESSOR = """
import os, signal, sys
from orb_accel import OrbAccel
from orb_accel.socket_bus import SocketBus
bus = SocketBus(sys.argv[1])
accel = OrbAccel(bus)
accel.configure(threshold=20)
accel.next_frame(float(sys.argv[2]))
bank = accel.wait_frame(float(sys.argv[2]))   # held ...
print(bank, flush=True)
os.kill(os.getpid(), signal.SIGKILL)          # ... when the process dies
"""


@pytest.fixture
def plain_server(frames: np.ndarray, tmp_path) -> Iterator[SimServer]:
    with server(frames, tmp_path) as srv:
        yield srv


def test_a_dead_predecessors_bank(plain_server: SimServer, models: list[Features]) -> None:
    with SocketBus(plain_server.address) as probe:
        timeout = 3 * period_s(probe)
    dead = subprocess.run([sys.executable, "-c", PREDECESSOR, plain_server.address, str(timeout)],
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert dead.returncode == -9, dead.stderr
    held = int(dead.stdout.split()[-1])
    with SocketBus(plain_server.address) as bus:
        accel = OrbAccel(bus)
        accel.configure(threshold=20)
        got = [accel.next_frame(timeout) for _ in range(5)]
        numbers = [f.number for f in got]
        assert numbers == list(range(numbers[0], numbers[0] + 5)), f"frames {numbers} not consecutive"
        for f in got:
            check_photo(f.features, models)
        assert got[-1].counters["overrun"] == got[0].counters["overrun"], "frames skipped after the start"
        assert accel.released_at_open == [held] and accel.faults.stale_banks == 1
