#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Per-frame CPU cost of the ROS 2 message (`make bench-ros2`, in the ROS 2 venv; docs/ros2.md):
for a frame of N features (1,000, the 640x480 budget; the largest bank of the board builds; the
largest bank the feature memory allows), the time to build the orb_accel_msgs/msg/Features message
from the driver's Frame (orb_ros2.node.build_message, as the node does), to serialise it to CDR
(rclpy.serialization: the conversion to the C message and rmw's serialisation that publish runs),
to publish it (a reliable publisher with the node's QoS, no subscriber, its own ROS domain on
loopback) and to deserialise it (what a Python subscriber pays); median of the repeats, with the
message's size. Writes build/bench/ros2.json and prints a table.

The frame holds random features of the board-720p build's shape (4 levels of 5:4, 32 sectors, at
1280x720), descriptors included; its content does not change the cost, its length does.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
from importlib import metadata
from pathlib import Path

import numpy as np
from timing import median_ms  # scripts/bench/timing.py

from golden_model import limits
from golden_model.config import named
from golden_model.featcodec import EndOfFrame
from golden_model.features import Features
from golden_model.frameparams import FrameParams
from orb_accel.driver import Frame, HwConfig

BOARD = "board-720p"  # the board build with the largest bank (vivado/board.json)


def frame_of(n: int, seed: int = 1) -> Frame:
    """A frame of n random features of the board build's shape."""
    nc = named(BOARD)
    rng = np.random.default_rng(seed)
    scale = rng.integers(0, nc.scales, n)
    feats = Features(scale=scale, x=rng.integers(3, 600, n), y=rng.integers(3, 400, n),
                     score=rng.integers(1, 2000, n), sector=rng.integers(0, nc.sectors, n),
                     descriptor=rng.integers(0, 256, (n, 32), dtype=np.uint8), sectors_total=nc.sectors,
                     step=(nc.step_num, nc.step_den), response=rng.integers(0, 64, n),
                     low=rng.integers(0, 2, n).astype(bool))  # fmt: skip
    hw = HwConfig(nc.width, nc.height, nc.scales, nc.sectors, limits.MEM_DEPTH_MAX, nc.step_num, nc.step_den)
    grid = n <= limits.BUDGET_MAX
    params = FrameParams(20, 14, "orb", "grid" if grid else "all", n if grid else 0, 8, 6)
    record = EndOfFrame(count=n, frame=7, dropped=0, truncated=0, truncated_flag=False, params=params)
    counters = {"frame_count": 8, "dropped": 0, "proto_errors": 0, "overrun": 0, "overflow_count": 0,
                "desc_lost": 0, "discarded": 0}  # fmt: skip
    return Frame(0, feats, record, "orb", hw, counters, params)


def main() -> int:
    board_bank = named(BOARD).mem_depth - 1
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--features", default=f"1000,{board_bank},{limits.MEM_DEPTH_MAX - 1}",
                    help=f"features per frame, comma-separated (default 1000,{board_bank},{limits.MEM_DEPTH_MAX - 1}: "
                         f"the 640x480 budget, {BOARD}'s bank, the largest bank)")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=25)
    ap.add_argument("--out", type=Path, default=Path("build/bench/ros2.json"))
    args = ap.parse_args()
    # a ROS domain of its own, loopback only: the publisher reaches nobody
    os.environ.setdefault("ROS_DOMAIN_ID", str(100 + os.getpid() % 30))
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ.setdefault("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp")
    import rclpy
    from rclpy.serialization import deserialize_message, serialize_message

    from orb_ros2 import interfaces
    from orb_ros2.node import FEATURES_QOS, build_message

    msgs, _ = interfaces.load()
    rclpy.init()
    node = rclpy.create_node("orb_accel_bench")
    pub = node.create_publisher(msgs.Features, "~/features", FEATURES_QOS)
    stamp = node.get_clock().now().to_msg()
    runs = []
    for n in [int(v) for v in args.features.split(",")]:
        frame = frame_of(n)
        msg = build_message(msgs.Features, frame, stamp, "orb_accel")
        data = serialize_message(msg)
        back = deserialize_message(data, msgs.Features)
        assert bytes(back.descriptors) == frame.descriptors.tobytes() and len(back.x) == n
        runs.append({
            "features": n,
            "build_ms": round(median_ms(lambda f=frame: build_message(msgs.Features, f, stamp, "orb_accel"),
                                        args.repeat), 3),
            "serialize_ms": round(median_ms(lambda m=msg: serialize_message(m), args.repeat), 3),
            "publish_ms": round(median_ms(lambda m=msg: pub.publish(m), args.repeat), 3),
            "deserialize_ms": round(median_ms(lambda d=data: deserialize_message(d, msgs.Features), args.repeat), 3),
            "message_bytes": len(data),
        })  # fmt: skip
    node.destroy_node()
    rclpy.shutdown()
    machine = f"{platform.processor() or platform.machine()} ({os.cpu_count()} cores)"
    report = {"command": "make bench-ros2", "machine": machine, "python": platform.python_version(),
              "numpy": np.__version__, "rclpy": metadata.version("ros-rclpy"), "rmw": os.environ["RMW_IMPLEMENTATION"],
              "repeat": args.repeat, "runs": runs}  # fmt: skip
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")
    print(f"{machine}, Python {platform.python_version()}, rclpy {report['rclpy']}, {report['rmw']}; "
          f"median of {args.repeat}")  # fmt: skip
    print("| features | build | serialise | publish | deserialise | bytes |")
    print("|---|---|---|---|---|---|")
    for r in runs:
        print(f"| {r['features']:,} | {r['build_ms']} ms | {r['serialize_ms']} ms | {r['publish_ms']} ms | "
              f"{r['deserialize_ms']} ms | {r['message_bytes']:,} |")  # fmt: skip
    print(f"-> {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
