# SPDX-License-Identifier: MIT
"""A ROS 2 client in its own process, run with the ROS 2 venv's python (.venv-ros2: rclpy lives
only there), for test_ros2_node.py:

ros2_client.py listen OUT.jsonl BAG      every /orb_accel/features message and /diagnostics report,
                                         one JSON line each (arrays as lists, descriptors as hex), and
                                         every features message as it came (CDR) into the ROS 2 bag
                                         BAG (mcap, written with PyPI's rosbags: there is no rosbag2
                                         on PyPI), closed at SIGINT
ros2_client.py set NAME=VALUE ...        set the node's parameters (rcl_interfaces/srv/SetParameters),
                                         print each result as JSON
ros2_client.py reset                     call /orb_accel/reset, print the response as JSON

The subscriber asks for a reliable stream (every frame; the node publishes reliable, docs/ros2.md).
"""

from __future__ import annotations

import json
import signal
import sys
import threading
from pathlib import Path

import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import Trigger

from orb_ros2 import interfaces

msg_mod, _ = interfaces.load()
TOPIC = "/orb_accel/features"
MSGTYPE = "orb_accel_msgs/msg/Features"
TIMEOUT_S = 300.0
EVERY_FRAME = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.VOLATILE)  # fmt: skip


def _features(m) -> dict:
    out = {name: getattr(m, name) for name in ("width", "height", "frame", "threshold", "mode", "scales", "sectors",
                                               "step_num", "step_den", "budget", "selection", "threshold_lo", "cols",
                                               "rows", "dropped", "truncated", "frames_total",
                                               "overrun_total")}  # fmt: skip
    for name in ("x", "y", "size", "angle", "response", "octave", "scale_x", "scale_y", "corner_response", "low"):
        out[name] = list(getattr(m, name))
    out["descriptors"] = bytes(m.descriptors).hex()
    out["frame_id"] = m.header.frame_id
    out["stamp"] = m.header.stamp.sec + m.header.stamp.nanosec * 1e-9
    return out


def listen(path: str, bag: str) -> None:
    from rosbags.rosbag2 import StoragePlugin, Writer

    from orb_tools.rosbag_convert import typestore_ros2

    node = Node("orb_test_listener")
    lock = threading.Lock()
    fh = open(path, "a", buffering=1)
    writer = Writer(Path(bag), version=8, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    conn = writer.add_connection(TOPIC, MSGTYPE, typestore=typestore_ros2())

    def write(record: dict) -> None:
        with lock:
            fh.write(json.dumps(record) + "\n")

    def raw(data: bytes) -> None:
        with lock:
            writer.write(conn, node.get_clock().now().nanoseconds, data)

    node.create_subscription(msg_mod.Features, TOPIC, lambda m: write({"topic": "features", **_features(m)}),
                             EVERY_FRAME)  # fmt: skip
    node.create_subscription(msg_mod.Features, TOPIC, raw, EVERY_FRAME, raw=True)
    node.create_subscription(DiagnosticArray, "/diagnostics", lambda a: write({"topic": "diagnostics", "status": [
        {"name": s.name, "level": int.from_bytes(s.level, "little") if isinstance(s.level, bytes) else int(s.level),
         "message": s.message, "values": {kv.key: kv.value for kv in s.values}} for s in a.status]}), 10)  # fmt: skip
    write({"topic": "ready"})
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    while not stop.is_set():
        rclpy.spin_once(node, timeout_sec=0.1)
    with lock:
        writer.close()
        fh.close()
    node.destroy_node()


def _value(text: str) -> ParameterValue:
    if text in ("true", "false"):
        return ParameterValue(type=ParameterType.PARAMETER_BOOL, bool_value=text == "true")
    try:
        return ParameterValue(type=ParameterType.PARAMETER_INTEGER, integer_value=int(text))
    except ValueError:
        return ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=text)


def _call(node: Node, kind: type, name: str, request: object) -> object:
    client = node.create_client(kind, name)
    if not client.wait_for_service(timeout_sec=TIMEOUT_S):
        sys.exit(f"no service {name}")
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future, timeout_sec=TIMEOUT_S)
    if not future.done():
        sys.exit(f"{name}: no answer within {TIMEOUT_S:g} s")
    return future.result()


def set_parameters(assignments: list[str]) -> None:
    node = Node("orb_test_client")
    params = [Parameter(name=a.split("=", 1)[0], value=_value(a.split("=", 1)[1])) for a in assignments]
    result = _call(node, SetParameters, "/orb_accel/set_parameters", SetParameters.Request(parameters=params))
    print(json.dumps([{"successful": r.successful, "reason": r.reason} for r in result.results]))  # type: ignore[attr-defined]


def reset() -> None:
    node = Node("orb_test_client")
    r = _call(node, Trigger, "/orb_accel/reset", Trigger.Request())
    print(json.dumps({"success": r.success, "message": r.message}))  # type: ignore[attr-defined]


if __name__ == "__main__":
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    command = sys.argv[1]
    if command == "listen":
        listen(sys.argv[2], sys.argv[3])
    elif command == "set":
        set_parameters(sys.argv[2:])
    elif command == "reset":
        reset()
    else:
        sys.exit(f"unknown command {command}")
    rclpy.shutdown()
