# SPDX-License-Identifier: MIT
"""The ROS 1 node end to end, through a real roscore (Debian's ROS packages; CI installs them):

`orb-accel ros --sim --sim-engine fast` runs the node against orb_accel_top simulated as its
synthesised netlist in Verilator (docs/fast-sim.md; bit-exact with the RTL in GHDL by
tb/fast/test_fast_sim.py; the GHDL engine of the same server is tb/driver/test_socket_bus.py's),
three colour photographs streamed round and round; a rospy subscriber in another process (ros_client.py)
receives every frame, `rosbag record` records the topic, services are called from a third
process. Checked:

- every published frame arrives (frame numbers consecutive, no overrun) and is bit-exact with the
  golden model at the threshold the message states, for a photograph in stream order;
- a threshold change through ~set_params applies exactly from the first frame after the frame the
  response names; illegal values are refused with the allowed range and the node keeps publishing;
- ~reset restarts the frame numbers; diagnostics carry frames per second and the counters;
- the bag reads back (orb_tools.rosbag_convert) to the same features, also as a ROS 2 bag;
- SIGINT stops the node with status 0 and leaves no process behind (the simulator included);
- an illegal start-up parameter stops the node with status 2 before it opens the bus;
- under faults (docs/ros.md, "Faults and recovery"; the server injects them, orb_sim.faults): a
  previous process killed holding a bank, a cable cut every 8 frames, SLVERR to STATUS reads and
  to feature-memory reads: the node keeps publishing frames bit-exact, none skipped by the
  accelerator, /diagnostics WARNs (the released bank, the stall, the bus errors) with the counters
  and is OK again once frames flow.
"""

from __future__ import annotations

import itertools
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import xmlrpc.client
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from golden_model.config import RECOMMENDED_COLS, RECOMMENDED_ROWS, RECOMMENDED_THRESHOLD_LO, named
from golden_model.features import Features, first_difference
from golden_model.luma import rgb_to_luma
from orb_accel.csvdir import read_csv_dir
from orb_ros.msgs import APT_PACKAGES, ros_env
from orb_sim.sim_server import SimServer
from orb_tools.rosbag_convert import bag_to_csv, bag_to_ros2, features_from_msg
from orbtb.images import colour_photo
from orbtb.procs import WAIT_S
from orbtb.procs import alive as _alive
from orbtb.procs import records as _records
from orbtb.procs import stop as _stop
from orbtb.procs import wait as _wait
from orbtb.scoreboard import expected_features

TINY = named("test-tiny")  # the simulated bitstream of this test (docs/configurations.md)
W, H, SCALES, SECTORS = TINY.width, TINY.height, TINY.scales, TINY.sectors
assert (TINY.step_num, TINY.step_den) == (2, 1), "the model calls below assume the 2:1 pyramid"
BUDGET = 40  # the accelerator's grid selection keeps at most 40 features a frame (~budget; docs/selection.md)
# ... with the driver's grid (8 x 6 cells) and low threshold
SELECTION = f"grid:{BUDGET}:{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}"
PHOTOS = ("astronaut", "coffee", "chelsea")
CLIENT = Path(__file__).with_name("ros_client.py")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def ros_master(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, str]]:
    roscore = shutil.which("roscore")
    if roscore is None:
        pytest.fail(f"ROS 1 is not installed: apt-get install {APT_PACKAGES}")
    home = tmp_path_factory.mktemp("ros-home")
    port = _free_port()
    env = ros_env(dict(os.environ))
    env.update(ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_HOSTNAME="127.0.0.1", ROS_HOME=str(home))
    with open(home / "roscore.log", "w") as log:
        proc = subprocess.Popen([roscore, "-p", str(port)], env=env, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)  # fmt: skip
    master = xmlrpc.client.ServerProxy(env["ROS_MASTER_URI"])
    deadline = time.monotonic() + 60
    while True:
        try:
            if master.getSystemState("/test")[0] == 1:
                break
        except OSError:
            pass
        assert proc.poll() is None and time.monotonic() < deadline, (home / "roscore.log").read_text()
        time.sleep(0.2)
    yield env
    _stop(proc)


def _call(env: dict[str, str], *args: str) -> dict:
    r = subprocess.run([sys.executable, str(CLIENT), *args], env=env, capture_output=True, text=True, timeout=WAIT_S)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def _features(record: dict) -> Features:
    msg = SimpleNamespace(**{**record, "descriptors": bytes.fromhex(record["descriptors"])})
    return features_from_msg(msg)


def _photo_of(frames: np.ndarray, feats: Features, threshold: int) -> int:
    diffs = {}
    for k in range(len(frames)):
        model = expected_features(rgb_to_luma(frames[k]), SCALES, threshold, "orb", SECTORS, (2, 1), SELECTION)
        diffs[k] = first_difference(feats, model)
    found = [k for k, d in diffs.items() if d is None]
    assert len(found) == 1, f"a published frame equals no photograph at threshold {threshold}: {diffs}"
    return found[0]


def test_node_end_to_end(ros_master: dict[str, str], tmp_path: Path) -> None:
    env = ros_master
    frames = np.stack([colour_photo(name, W, H) for name in PHOTOS])
    pngs = []
    for name, rgb in zip(PHOTOS, frames, strict=True):
        pngs.append(str(tmp_path / f"{name}.png"))
        cv2.imwrite(pngs[-1], cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    heard, node_log, bag = tmp_path / "heard.jsonl", tmp_path / "node.log", tmp_path / "features.bag"
    procs: dict[str, subprocess.Popen] = {}
    logs = [open(tmp_path / f"{n}.log", "w") for n in ("listener", "rosbag")]
    procs["listener"] = subprocess.Popen([sys.executable, str(CLIENT), "listen", str(heard)], env=env,
                                         stdout=logs[0], stderr=subprocess.STDOUT, start_new_session=True)  # fmt: skip
    _wait("the listener", lambda: heard.exists() and "ready" in heard.read_text(), procs, tmp_path / "listener.log")
    procs["rosbag"] = subprocess.Popen(["rosbag", "record", "-O", str(bag), "/orb_accel/features"], env=env,
                                       stdout=logs[1], stderr=subprocess.STDOUT, start_new_session=True)  # fmt: skip
    with open(node_log, "w") as log:
        procs["node"] = subprocess.Popen(
            [sys.executable, "-m", "orb_tools.cli", "ros", "--sim", *pngs, "--sim-engine", "fast",
             "--sim-config", TINY.name, "_frame_id:=test_camera", "_threshold:=20", f"_budget:={BUDGET}"],
            env={**env, "PYTHONUNBUFFERED": "1", "PYTHONFAULTHANDLER": "1"},  # a hang leaves its stacks in the log
            stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
        )  # fmt: skip
    got = lambda: _records(heard, "features")  # noqa: E731
    try:
        _wait("3 frames", lambda: len(got()) >= 3, procs, node_log)
        changed = _call(env, "set_params", "35", "", "-1")
        assert changed["success"], changed
        after = changed["after_frame"]
        for args, text in ((("300", "", "-1"), "0..255"), (("-1", "brief", "-1"), "orb, fast"),
                           (("-1", "", "7"), "enable")):  # fmt: skip
            refused = _call(env, "set_params", *args)
            assert not refused["success"] and text in refused["message"], refused
        _wait("2 frames after the change", lambda: sum(r["frame"] > after for r in got()) >= 2, procs, node_log)
        n_before_reset = len(got())
        reset = _call(env, "reset")
        assert reset["success"] and "restart at 0" in reset["message"], reset
        _wait("2 frames after the reset", lambda: len(got()) >= n_before_reset + 3, procs, node_log)
    finally:
        status = _stop(procs["node"])
        _stop(procs["rosbag"])
        _stop(procs["listener"])
        for fh in logs:
            fh.close()
    log_text = node_log.read_text()
    assert status == 0, f"the node ended with {status}:\n{log_text[-8000:]}"
    job = log_text.split("(log: ")[1].split("/sim.log")[0]
    deadline = time.monotonic() + 10
    while _alive(job) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not _alive(job), f"processes left behind: {_alive(job)}"

    records = got()
    assert all(r["frame_id"] == "test_camera" and (r["width"], r["height"]) == (W, H) for r in records)
    assert all((r["scales"], r["sectors"], r["mode"], r["budget"]) == (SCALES, SECTORS, "orb", BUDGET) for r in records)
    assert all(len(r["x"]) <= BUDGET for r in records) and any(len(r["x"]) == BUDGET for r in records)
    numbers = [r["frame"] for r in records]
    cut = next(i for i in range(n_before_reset, len(records)) if numbers[i] < numbers[i - 1])
    for part in (numbers[:cut], numbers[cut:]):  # every frame arrived, in order, in both epochs
        assert part == list(range(part[0], part[0] + len(part))), f"frame numbers {numbers}"
    assert numbers[cut] <= 1, f"after the reset the numbering restarts: {numbers}"
    assert all(r["overrun_total"] == 0 for r in records), "the node fell behind"
    assert [r["threshold"] for r in records[:cut]] == [20 if n <= after else 35 for n in numbers[:cut]]
    assert all(r["threshold"] == 35 for r in records[cut:])
    photos = [_photo_of(frames, _features(r), r["threshold"]) for r in records]
    for part in (photos[:cut], photos[cut:]):
        assert all((b - a) % len(PHOTOS) == 1 for a, b in itertools.pairwise(part)), f"photographs {photos}"

    diag = [s for r in _records(heard, "diagnostics") for s in r["status"] if s["name"] == "orb_accel: accelerator"]
    assert diag and {"frames_per_second", "published", "overrun", "proto_errors"} <= set(diag[-1]["values"])

    out = tmp_path / "csv"
    n = bag_to_csv(bag, out)
    rows = read_csv_dir(out)
    assert n == len(rows) > 0
    by_frame = {(r["frame"], r["threshold"]): _features(r) for r in records}
    for row, feats in rows:
        ours = by_frame[(row["frame"], row["threshold"])]
        assert first_difference(feats, ours) is None, f"bag frame {row['frame']}: {first_difference(feats, ours)}"
    assert bag_to_ros2(bag, tmp_path / "ros2", storage="mcap") == n


@pytest.mark.parametrize(("param", "message"), [("_threshold:=999", "threshold must be an integer 0..255, got 999"),
                                               ("_budget:=-3", "budget must be a non-negative integer")])  # fmt: skip
def test_illegal_startup_parameter(ros_master: dict[str, str], param: str, message: str) -> None:
    # a node name of its own: the parameter server keeps a private parameter after the node is gone
    name = "orb_accel_bad_" + param.strip("_").split(":")[0]
    cmd = [sys.executable, "-m", "orb_tools.cli", "ros", "--connect", "127.0.0.1:1", param, f"__name:={name}"]
    r = subprocess.run(cmd, env=ros_master, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stdout + r.stderr
    assert message in r.stderr and "Traceback" not in r.stderr
    assert "no simulator" not in r.stderr, "the bus was opened before the parameters were checked"


def test_ros_tools_know_the_messages(ros_master: dict[str, str]) -> None:
    """Under `orb-accel ros-env`'s environment Debian's rosmsg/rossrv find orb_accel_msgs (and
    std_msgs, which Debian ships without a package.xml) with genpy's md5 of the generated class."""
    from orb_ros.msgs import load

    msg_mod, srv_mod = load()
    md5 = subprocess.run(["rosmsg", "md5", "orb_accel_msgs/Features"], env=ros_master, capture_output=True, text=True)
    assert md5.returncode == 0 and md5.stdout.strip() == msg_mod.Features._md5sum, md5.stdout + md5.stderr
    show = subprocess.run(["rossrv", "show", "orb_accel_msgs/SetParams"], env=ros_master, capture_output=True,
                          text=True)  # fmt: skip
    assert show.returncode == 0 and "int16 threshold" in show.stdout and "uint32 after_frame" in show.stdout, show
    assert srv_mod.SetParams._md5sum


PREDECESSOR = """
import os, signal, sys
from orb_accel import OrbAccel
from orb_accel.socket_bus import SocketBus
accel = OrbAccel(SocketBus(sys.argv[1]))
accel.configure(threshold=20)
print(accel.wait_frame(0.01), flush=True)   # a bank held ...
os.kill(os.getpid(), signal.SIGKILL)        # ... when the process dies
"""
FAULTS = ("cut:8:20", "buserr:read:STATUS:9:11", "buserr:block:mem:7:9")


def _diag(heard: Path) -> list[dict]:
    return [s for r in _records(heard, "diagnostics") for s in r["status"] if s["name"] == "orb_accel: accelerator"]


def test_node_under_faults(ros_master: dict[str, str], tmp_path: Path) -> None:
    env = ros_master
    frames = np.stack([colour_photo(name, W, H) for name in PHOTOS])
    heard, node_log = tmp_path / "heard.jsonl", tmp_path / "node.log"
    procs: dict[str, subprocess.Popen] = {}
    with SimServer(frames, TINY.name, engine="fast", job_dir=tmp_path / "sim", faults=FAULTS) as srv:
        dead = subprocess.run([sys.executable, "-c", PREDECESSOR, srv.address], capture_output=True, text=True,
                              timeout=300)  # fmt: skip
        assert dead.returncode == -9, dead.stderr
        listen = [sys.executable, str(CLIENT), "listen", str(heard)]
        with open(tmp_path / "listener.log", "w") as fh:
            procs["listener"] = subprocess.Popen(listen, env=env, stdout=fh, stderr=subprocess.STDOUT,
                                                 start_new_session=True)  # fmt: skip
        _wait("the listener", lambda: heard.exists() and "ready" in heard.read_text(), procs, tmp_path / "listener.log")
        with open(node_log, "w") as log:
            procs["node"] = subprocess.Popen(
                [sys.executable, "-m", "orb_tools.cli", "ros", "--connect", srv.address, "_threshold:=20",
                 f"_budget:={BUDGET}", "_diagnostics_period:=0.2", "_frame_id:=faulty"],
                env={**env, "PYTHONUNBUFFERED": "1", "PYTHONFAULTHANDLER": "1"},
                stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
            )  # fmt: skip

        def enough() -> bool:
            d = _diag(heard)
            if not d:
                return False
            v = d[-1]["values"]
            warned_stall = [i for i, s in enumerate(d) if "no frame for" in s["message"]]
            ok_after = warned_stall and any(s["level"] == 0 for s in d[warned_stall[-1] :])
            return int(v.get("stalls", 0)) >= 2 and int(v.get("bus_errors", 0)) >= 4 and bool(ok_after)

        try:
            _wait("two cuts and four bus errors, then an OK report", enough, procs, node_log)
        finally:
            status = _stop(procs["node"])
            _stop(procs["listener"])
    log_text = node_log.read_text()
    assert status == 0, f"the node ended with {status}:\n{log_text[-8000:]}"
    records = [r for r in _records(heard, "features") if r["frame_id"] == "faulty"]
    numbers = [r["frame"] for r in records]
    assert len(records) >= 10 and numbers == sorted(set(numbers)), f"frame numbers {numbers}"
    for r in records:
        _photo_of(frames, _features(r), r["threshold"])
    assert all(r["overrun_total"] == 0 for r in records), "a bank left held made the accelerator skip frames"

    d = _diag(heard)
    first, last = d[0], d[-1]
    assert first["level"] == 1 and "stale_banks +1" in first["message"], first
    assert "released bank(s)" in log_text and "a previous process left held" in log_text
    stall = next(s for s in d if "no frame for" in s["message"])
    assert stall["level"] == 1 and stall["values"]["stalled"] == "true", stall
    errs = next(s for s in d if "bus_errors +" in s["message"])
    assert errs["level"] == 1 and "answered SLVERR" in errs["values"]["last_error"], errs
    v = last["values"]
    assert int(v["stale_banks"]) >= 1 and int(v["timeouts"]) >= 2 * 3 and int(v["frames_missed"]) >= 2, v
    assert int(v["bus_errors"]) >= 4 and v["errors"] == "0", v
    assert any(s["level"] == 0 and s["values"]["stalled"] == "false" for s in d[d.index(stall) :])
    assert "Traceback" not in log_text
