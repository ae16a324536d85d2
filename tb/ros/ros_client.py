# SPDX-License-Identifier: MIT
"""A ROS client in its own process for test_ros_node.py (rospy.init_node works once per process):

ros_client.py listen OUT.jsonl           every /orb_accel/features and /diagnostics message, one
                                         JSON line each (arrays as lists, descriptors as hex)
ros_client.py set_params T MODE ENABLE   call /orb_accel/set_params, print the response as JSON
ros_client.py reset                      call /orb_accel/reset, print the response as JSON
"""

from __future__ import annotations

import json
import sys
import threading

from orb_ros import msgs as rosmsgs

rospy = rosmsgs.import_rospy()
msg_mod, srv_mod = rosmsgs.load()
TIMEOUT_S = 300.0


def _features(m) -> dict:
    out = {name: getattr(m, name) for name in ("width", "height", "frame", "threshold", "mode", "scales", "sectors",
                                               "step_num", "step_den", "budget", "dropped", "truncated",
                                               "frames_total", "overrun_total")}  # fmt: skip
    for name in ("x", "y", "size", "angle", "response", "octave", "scale_x", "scale_y", "corner_response", "low"):
        out[name] = list(getattr(m, name))
    out["descriptors"] = bytes(m.descriptors).hex()
    out["frame_id"] = m.header.frame_id
    out["stamp"] = m.header.stamp.to_sec()
    return out


def listen(path: str) -> None:
    from diagnostic_msgs.msg import DiagnosticArray

    rospy.init_node("orb_test_listener", anonymous=True)
    lock = threading.Lock()
    fh = open(path, "a", buffering=1)

    def write(record: dict) -> None:
        with lock:
            fh.write(json.dumps(record) + "\n")

    rospy.Subscriber("/orb_accel/features", msg_mod.Features, lambda m: write({"topic": "features", **_features(m)}),
                     queue_size=100)  # fmt: skip
    rospy.Subscriber("/diagnostics", DiagnosticArray, lambda a: write({"topic": "diagnostics", "status": [
        {"name": s.name, "level": int(s.level),
         "message": s.message, "values": {kv.key: kv.value for kv in s.values}} for s in a.status]}))  # fmt: skip
    write({"topic": "ready"})
    rospy.spin()


def call(name: str, *args: object) -> None:
    service = f"/orb_accel/{name}"
    rospy.wait_for_service(service, timeout=TIMEOUT_S)
    kind = srv_mod.SetParams if name == "set_params" else __import__("std_srvs.srv", fromlist=["Trigger"]).Trigger
    response = rospy.ServiceProxy(service, kind)(*args)
    print(json.dumps({k: getattr(response, k) for k in response.__slots__}))


if __name__ == "__main__":
    command = sys.argv[1]
    if command == "listen":
        listen(sys.argv[2])
    elif command == "set_params":
        call("set_params", int(sys.argv[2]), sys.argv[3], int(sys.argv[4]))
    elif command == "reset":
        call("reset")
    else:
        sys.exit(f"unknown command {command}")
