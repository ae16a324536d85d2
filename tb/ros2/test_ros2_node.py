# SPDX-License-Identifier: MIT
"""The ROS 2 node end to end, with real ROS 2 (rclpy and Fast DDS from PyPI in .venv-ros2, which
`make setup` makes; docs/ros2.md), on loopback only (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST) in a
ROS domain of its own:

`orb-accel ros2 --sim --sim-engine fast` runs the node (orb_ros2.node, in the ROS 2 venv) against
orb_accel_top simulated as its synthesised netlist in Verilator, three colour photographs streamed
round and round; a subscriber in another process (ros2_client.py) receives every frame and records
them into a ROS 2 bag (mcap, PyPI's rosbags: there is no rosbag2 on PyPI); parameters are set and
the reset service is called from a third process. Checked:

- every published frame arrives (frame numbers consecutive, no overrun) and is bit-exact with the
  golden model at the threshold the message states, for a photograph in stream order;
- a threshold change through the ROS 2 parameter applies exactly from the first frame after the
  frame the node names in its log; illegal values (threshold 300, mode "brief", enable 7) are
  refused with the allowed values and the node keeps publishing;
- ~/reset restarts the frame numbers; /diagnostics carries frames per second and the counters;
- the bag reads back (rosbags, in the main venv) to the same features;
- SIGINT stops the node with status 0 and leaves no process behind (the simulator included);
- an illegal start-up parameter stops the node with status 2 before it opens the bus.

test_ros2_node_on_a_serve_stream: `orb-accel serve` on the simulator and the node as its client
(`orb-accel ros2 --remote`): every message bit-exact, changes and resets refused (the server's).
"""

from __future__ import annotations

import functools
import itertools
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from golden_model.config import RECOMMENDED_COLS, RECOMMENDED_ROWS, RECOMMENDED_THRESHOLD_LO, named
from golden_model.features import Features, first_difference
from golden_model.luma import rgb_to_luma
from orb_ros.msgs import RosUnavailable
from orb_tools.board_cli import ros2_python
from orb_tools.rosbag_convert import features_from_msg, typestore_ros2
from orbtb.images import colour_photo
from orbtb.procs import WAIT_S, alive, records, stop, wait
from orbtb.scoreboard import expected_features

TINY = named("test-tiny")  # the simulated bitstream of this test (docs/configurations.md)
W, H, SCALES, SECTORS = TINY.width, TINY.height, TINY.scales, TINY.sectors
assert (TINY.step_num, TINY.step_den) == (2, 1), "the model calls below assume the 2:1 pyramid"
BUDGET = 40  # the accelerator's grid selection keeps at most 40 features a frame (budget; docs/selection.md)
SELECTION = f"grid:{BUDGET}:{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}"
PHOTOS = ("astronaut", "coffee", "chelsea")
CLIENT = Path(__file__).with_name("ros2_client.py")
APPLIED = re.compile(r"threshold (\d+), mode \w+, enable \w+: applied from the first frame after frame (\d+)")


@pytest.fixture(scope="module")
def ros2(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, str]]:
    """The ROS 2 venv's python and an environment of a ROS domain of its own on loopback."""
    try:
        python, env = ros2_python()
    except RosUnavailable as exc:
        pytest.fail(str(exc))
    home = tmp_path_factory.mktemp("ros2-home")
    env.update(ROS_DOMAIN_ID=str(10 + os.getpid() % 80), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
               RMW_IMPLEMENTATION="rmw_fastrtps_cpp", ROS_HOME=str(home), ROS_LOG_DIR=str(home / "log"),
               ORB_ACCEL_ROS2_PYTHON=str(python), PYTHONUNBUFFERED="1", PYTHONFAULTHANDLER="1")  # fmt: skip
    # orb_accel_msgs for ROS 2 (generated and compiled once per version; a few seconds the first time)
    built = subprocess.run([str(python), "-m", "orb_ros2.interfaces"], env=env, capture_output=True, text=True)
    assert built.returncode == 0, built.stderr
    return python, env


def _call(ros2: tuple[Path, dict[str, str]], *args: str) -> object:
    python, env = ros2
    r = subprocess.run([str(python), str(CLIENT), *args], env=env, capture_output=True, text=True, timeout=WAIT_S)
    assert r.returncode == 0, r.stderr
    import json

    return json.loads(r.stdout.strip().splitlines()[-1])


def _features(record: dict) -> Features:
    msg = SimpleNamespace(**{**record, "descriptors": bytes.fromhex(record["descriptors"])})
    return features_from_msg(msg)


@functools.cache
def _model(k: int, threshold: int) -> Features:
    return expected_features(rgb_to_luma(colour_photo(PHOTOS[k], W, H)), SCALES, threshold, "orb", SECTORS, (2, 1),
                             SELECTION)  # fmt: skip


def _photo_of(feats: Features, threshold: int) -> int:
    diffs = {k: first_difference(feats, _model(k, threshold)) for k in range(len(PHOTOS))}
    found = [k for k, d in diffs.items() if d is None]
    assert len(found) == 1, f"a published frame equals no photograph at threshold {threshold}: {diffs}"
    return found[0]


@pytest.fixture
def photos(tmp_path: Path) -> Iterator[list[str]]:
    pngs = []
    for name in PHOTOS:
        pngs.append(str(tmp_path / f"{name}.png"))
        cv2.imwrite(pngs[-1], cv2.cvtColor(colour_photo(name, W, H), cv2.COLOR_RGB2BGR))
    yield pngs


def test_ros2_node_end_to_end(ros2: tuple[Path, dict[str, str]], photos: list[str], tmp_path: Path) -> None:
    python, env = ros2
    heard, node_log, bag = tmp_path / "heard.jsonl", tmp_path / "node.log", tmp_path / "features_bag"
    procs: dict[str, subprocess.Popen] = {}
    with open(tmp_path / "listener.log", "w") as fh:
        procs["listener"] = subprocess.Popen([str(python), str(CLIENT), "listen", str(heard), str(bag)], env=env,
                                             stdout=fh, stderr=subprocess.STDOUT, start_new_session=True)  # fmt: skip
    wait("the listener", lambda: heard.exists() and "ready" in heard.read_text(), procs, tmp_path / "listener.log")
    marker = f"ORB_TEST_ROS2_NODE={tmp_path.name}"  # in the environment of the node and all it starts
    with open(node_log, "w") as log:
        procs["node"] = subprocess.Popen(
            [sys.executable, "-m", "orb_tools.cli", "ros2", "--sim", *photos, "--sim-engine", "fast",
             "--sim-config", TINY.name, "--ros-args", "-p", "frame_id:=test_camera", "-p", "threshold:=20",
             "-p", f"budget:={BUDGET}"],
            env={**env, marker.split("=")[0]: marker.split("=")[1]},
            stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
        )  # fmt: skip
    got = lambda: records(heard, "features")  # noqa: E731
    try:
        wait("3 frames", lambda: len(got()) >= 3, procs, node_log)
        changed = _call(ros2, "set", "threshold=35")
        assert changed == [{"successful": True, "reason": changed[0]["reason"]}], changed
        applied = APPLIED.findall(node_log.read_text())
        assert len(applied) == 1 and applied[0][0] == "35", node_log.read_text()[-3000:]
        after = int(applied[0][1])
        for arg, text in (("threshold=300", "Min: 0, Max: 255"), ("mode=brief", "one of orb, fast"),
                          ("enable=7", "enable must be true or false")):  # fmt: skip
            refused = _call(ros2, "set", arg)
            assert not refused[0]["successful"] and text in refused[0]["reason"], refused
        wait("2 frames after the change", lambda: sum(r["frame"] > after for r in got()) >= 2, procs, node_log)
        n_before_reset = len(got())
        reset = _call(ros2, "reset")
        assert reset["success"] and "restart at 0" in reset["message"], reset
        wait("3 frames after the reset", lambda: len(got()) >= n_before_reset + 3, procs, node_log)
    finally:
        status = stop(procs["node"])
        stop(procs["listener"])
    log_text = node_log.read_text()
    assert status == 0, f"the node ended with {status}:\n{log_text[-8000:]}"
    deadline = time.monotonic() + 10
    while alive(marker) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not alive(marker), f"processes left behind: {alive(marker)}"
    assert "Traceback" not in log_text, log_text[-8000:]

    recs = got()
    assert all(r["frame_id"] == "test_camera" and (r["width"], r["height"]) == (W, H) for r in recs)
    assert all((r["scales"], r["sectors"], r["mode"], r["budget"]) == (SCALES, SECTORS, "orb", BUDGET) for r in recs)
    assert all(len(r["x"]) <= BUDGET for r in recs) and any(len(r["x"]) == BUDGET for r in recs)
    numbers = [r["frame"] for r in recs]
    cut = next(i for i in range(n_before_reset, len(recs)) if numbers[i] < numbers[i - 1])
    for part in (numbers[:cut], numbers[cut:]):  # every frame arrived, in order, in both epochs
        assert part == list(range(part[0], part[0] + len(part))), f"frame numbers {numbers}"
    assert numbers[cut] <= 1, f"after the reset the numbering restarts: {numbers}"
    assert all(r["overrun_total"] == 0 for r in recs), "the node fell behind"
    assert [r["threshold"] for r in recs[:cut]] == [20 if n <= after else 35 for n in numbers[:cut]]
    assert all(r["threshold"] == 35 for r in recs[cut:])
    shown = [_photo_of(_features(r), r["threshold"]) for r in recs]
    for part in (shown[:cut], shown[cut:]):
        assert all((b - a) % len(PHOTOS) == 1 for a, b in itertools.pairwise(part)), f"photographs {shown}"

    diag = [s for r in records(heard, "diagnostics") for s in r["status"] if s["name"] == "orb_accel: accelerator"]
    assert diag and {"frames_per_second", "published", "overrun", "proto_errors"} <= set(diag[-1]["values"])

    # the bag the listener recorded, read back here (rosbags, the main venv): the same messages
    from rosbags.rosbag2 import Reader

    by_stamp = {r["stamp"]: r for r in recs}
    ts = typestore_ros2()
    n = 0
    with Reader(bag) as reader:
        assert [c.msgtype for c in reader.connections] == ["orb_accel_msgs/msg/Features"]
        for conn, _t, raw in reader.messages():
            msg = ts.deserialize_cdr(raw, conn.msgtype)
            rec = by_stamp[msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9]
            assert (msg.frame, msg.threshold) == (rec["frame"], rec["threshold"])
            assert first_difference(features_from_msg(msg), _features(rec)) is None
            n += 1
    assert n >= len(recs) - 2, f"{n} messages in the bag, {len(recs)} received"


@pytest.mark.parametrize(("param", "message"), [("threshold:=999", "Min: 0, Max: 255"),
                                               ("mode:=brief", "mode must be one of orb, fast"),
                                               ("budget:=-3", "budget must be -1 (recommended)")])  # fmt: skip
def test_illegal_startup_parameter(ros2: tuple[Path, dict[str, str]], param: str, message: str) -> None:
    _, env = ros2
    cmd = [sys.executable, "-m", "orb_tools.cli", "ros2", "--connect", "127.0.0.1:1", "--ros-args", "-p", param]
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stdout + r.stderr
    assert message in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert "127.0.0.1:1" not in r.stderr, "the bus was opened before the parameters were checked"


def test_ros2_node_on_a_serve_stream(ros2: tuple[Path, dict[str, str]], tmp_path: Path) -> None:
    """`orb-accel serve` on the simulator (as on the board) and the ROS 2 node on another process as
    its client (`orb-accel ros2 --remote`): every message bit-exact with the model at the server's
    threshold, frame numbers increasing, a parameter change and a reset refused (the server's), a
    clean stop of both."""
    from orb_sim.sim_server import SimServer

    python, env = ros2
    frames = np.stack([colour_photo(name, W, H) for name in PHOTOS])
    heard, node_log = tmp_path / "heard.jsonl", tmp_path / "node.log"
    marker = f"ORB_TEST_ROS2_REMOTE={tmp_path.name}"
    env = {**env, marker.split("=")[0]: marker.split("=")[1]}
    procs: dict[str, subprocess.Popen] = {}
    with SimServer(frames, TINY.name, engine="fast", job_dir=tmp_path / "sim") as sim:
        serve_cmd = [sys.executable, "-m", "orb_tools.cli", "serve", "--connect", sim.address, "--listen",
                     "127.0.0.1:0", "--threshold", "20", "--budget", str(BUDGET)]  # fmt: skip
        procs["serve"] = subprocess.Popen(serve_cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                          text=True, start_new_session=True)  # fmt: skip
        first = procs["serve"].stdout.readline()  # type: ignore[union-attr]
        assert "serving the frames of simulator" in first, first
        host, port = first.split(" on ")[1].split(":")[:2]
        with open(tmp_path / "listener.log", "w") as fh:
            listen = [str(python), str(CLIENT), "listen", str(heard), str(tmp_path / "bag")]
            procs["listener"] = subprocess.Popen(listen, env=env, stdout=fh, stderr=subprocess.STDOUT,
                                                 start_new_session=True)  # fmt: skip
        wait("the listener", lambda: heard.exists() and "ready" in heard.read_text(), procs, tmp_path / "listener.log")
        with open(node_log, "w") as log:
            procs["node"] = subprocess.Popen(
                [sys.executable, "-m", "orb_tools.cli", "ros2", "--remote", f"{host}:{port}", "--ros-args", "-p",
                 "frame_id:=remote"], env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
            )  # fmt: skip
        got = lambda: records(heard, "features")  # noqa: E731
        try:
            wait("5 frames", lambda: len(got()) >= 5, {k: p for k, p in procs.items() if k != "serve"}, node_log)
            refused = _call(ros2, "set", "threshold=35")
            assert not refused[0]["successful"] and "sets the accelerator's parameters" in refused[0]["reason"]
            reset = _call(ros2, "reset")
            assert not reset["success"] and "orb-accel serve at" in reset["message"], reset
            n = len(got())
            wait("2 more frames", lambda: len(got()) >= n + 2, {k: p for k, p in procs.items() if k != "serve"},
                 node_log)  # fmt: skip
        finally:
            status = stop(procs["node"])
            stop(procs["listener"])
            served = stop(procs["serve"], signal.SIGTERM)
    log_text = node_log.read_text()
    assert status == 0 and "Traceback" not in log_text, f"the node ended with {status}:\n{log_text[-8000:]}"
    assert served == 0, procs["serve"].stdout.read()  # type: ignore[union-attr]
    deadline = time.monotonic() + 10
    while alive(marker) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not alive(marker), f"processes left behind: {alive(marker)}"
    recs = got()
    numbers = [r["frame"] for r in recs]
    assert numbers == sorted(set(numbers)) and len(recs) >= 7, f"frame numbers {numbers}"
    assert all(r["frame_id"] == "remote" and r["threshold"] == 20 and r["budget"] == BUDGET for r in recs)
    for r in recs:
        _photo_of(_features(r), 20)
