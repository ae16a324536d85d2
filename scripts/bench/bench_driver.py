#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Per-frame CPU cost of the board-side software (`make bench-driver`; docs/ros.md): reading and
decoding a frame of N features (default 1,000, the 640x480 budget, and 5,000) through the shipped
driver, and building and serialising its ROS message, on this machine; with the number of 32-bit
bus reads per frame.

The bus is the UIO backend (orb_accel.uio.UioBus) over a file-backed map that holds the registers
and one bank of N features in the feature memory's layout (random features, encoded with the
golden model's codec), so the measured code is exactly what runs on the board, minus the bus's own
latency (the map is RAM here, the PL on the board). Both block modes of UioBus are measured, and
both bank-reading strategies of the driver (one block per slot, or one block for the bank). The
Cortex-A9 figures are an estimate: this machine's times scaled by a stated factor plus the bus
reads at a stated AXI read latency. Writes build/bench/driver.json and prints a table.
"""

from __future__ import annotations

import argparse
import io
import json
import os
import platform
import socket
import struct
import tempfile
from pathlib import Path

import numpy as np
from timing import median_ms  # scripts/bench/timing.py

from golden_model import regs
from golden_model.featcodec import encode_eof, encode_feature, feature_slot, record_slot
from golden_model.featmem import SLOT_BYTES
from golden_model.frameparams import FrameParams
from golden_model.limits import BUDGET_MAX
from orb_accel import OrbAccel, UioBus
from orb_ros import msgs as rosmsgs
from orb_ros.node import build_message

W, H, SCALES, SECTORS = 1920, 1080, 2, 32
# Estimate for the Zybo's Cortex-A9 at 667 MHz (not measured): CPython single-thread speed of a
# 667 MHz Cortex-A9 against a current x86 server core taken as 15x slower (a stated assumption,
# between CoreMark-per-clock ratios, ~8x, and interpreter-bound measurements on small ARM
# boards, ~20x), and one uncached 32-bit AXI4-Lite read over M_AXI_GP0 at 0.25 us (a stated
# assumption: tens of FCLK cycles through the interconnect).
A9_SLOWDOWN = 15.0
AXI_READ_US = 0.25


def make_map(path: Path, n: int, depth: int, seed: int = 1) -> int:
    """A file laid out as the accelerator's map: registers, bank 0 with n random features."""
    size = regs.MEM_BASE + 2 * depth * SLOT_BYTES
    words = np.zeros(size // 4, dtype=np.uint32)

    def put(reg: regs.Register, value: int) -> None:
        words[reg.offset // 4] = value

    put(regs.ID, regs.ORB_ID)
    version = regs.VERSION.field("major").put(regs.VERSION_MAJOR)
    put(regs.VERSION, regs.VERSION.field("minor").put(regs.VERSION_MINOR, version))
    put(regs.CFG_SIZE, regs.CFG_SIZE.field("height").put(H, regs.CFG_SIZE.field("width").put(W)))
    orb = regs.CFG_ORB.field("sectors").put(SECTORS, regs.CFG_ORB.field("scales").put(SCALES))
    orb = regs.CFG_ORB.field("step_num").put(2, regs.CFG_ORB.field("step_den").put(1, orb))
    put(regs.CFG_ORB, regs.CFG_ORB.field("banks").put(2, orb))
    put(regs.CFG_MEM, regs.CFG_MEM.field("depth").put(depth))
    put(regs.CTRL, regs.CTRL.field("enable").put(1))
    put(regs.THRESHOLD, 20)
    put(regs.STATUS, regs.STATUS.field("bank_ready").put(1))
    put(regs.IRQ_STATUS, 1)
    put(regs.BANK0_INFO, regs.BANK0_INFO.field("count").put(n))
    rng = np.random.default_rng(seed)
    base = regs.MEM_BASE // 4
    for s in range(n):
        scale = int(rng.integers(0, SCALES))
        word = encode_feature(scale=scale, x=int(rng.integers(3, (W >> scale) - 3)),
                              y=int(rng.integers(3, (H >> scale) - 3)), score=int(rng.integers(1, 2000)),
                              sector=int(rng.integers(0, SECTORS)), descriptor=rng.bytes(32),
                              response=int(rng.integers(0, 64)), low=bool(rng.integers(0, 2)))  # fmt: skip
        slot = feature_slot(word)
        words[base + s * SLOT_BYTES // 4 : base + s * SLOT_BYTES // 4 + len(slot)] = slot
    # a budget-sized frame says grid selection with budget n; a larger one (the dense case) says
    # every-feature mode, where the budget field is not used (and n may exceed it)
    grid = n <= BUDGET_MAX
    params = FrameParams(20, 14, "orb", "grid" if grid else "all", n if grid else 0, 8, 6)
    rec = record_slot(encode_eof(7, 0, params), n, 0)
    words[base + n * SLOT_BYTES // 4 : base + n * SLOT_BYTES // 4 + len(rec)] = rec
    path.write_bytes(words.tobytes())
    return size


def measure(n: int, repeat: int, rospy, numpy_msg, msg_mod) -> dict:
    """One frame size: the read strategies, the interrupt round trip and the message."""
    depth = 1 << max(11, (n + 1).bit_length())
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "map"
        size = make_map(path, n, depth)
        for mode in ("copy", "words"):
            ours, kernel = socket.socketpair()
            with UioBus(path, size, irq_fd=ours.fileno(), block_mode=mode) as bus:
                for strategy in ("bank", "slot"):
                    accel = OrbAccel(bus, bank_read=strategy)
                    r0 = bus.reads
                    frame = accel.read_bank(0)
                    reads = bus.reads - r0
                    assert len(frame) == n
                    t_read = median_ms(lambda a=accel: a.read_bank(0), repeat)
                    rows.append({"block_mode": mode, "bank_read": strategy, "read_decode_ms": round(t_read, 2),
                                 "bus_reads": reads})  # fmt: skip
                t_irq = median_ms(lambda b=bus, k=kernel: (k.sendall(struct.pack("=I", 1)), b.wait_irq(1.0),
                                                           k.recv(4)), repeat)  # fmt: skip
            ours.close()
            kernel.close()
    np_cls, plain_cls = numpy_msg(msg_mod.Features), msg_mod.Features

    def message(cls: type) -> int:
        buf = io.BytesIO()
        build_message(cls, frame, rospy.Time(1, 0), "orb_accel").serialize(buf)
        return buf.tell()

    msg_bytes = message(np_cls)
    t_msg = median_ms(lambda: message(np_cls), repeat)
    t_plain = median_ms(lambda: message(plain_cls), max(3, repeat // 3))
    for r in rows:
        r["host_total_ms"] = round(r["read_decode_ms"] + t_msg, 2)
        cpu = (r["read_decode_ms"] + t_msg) * A9_SLOWDOWN
        r["a9_estimate_ms"] = round(cpu + r["bus_reads"] * AXI_READ_US / 1e3, 1)
    return {"features": n, "reads": rows, "wait_irq_roundtrip_ms": round(t_irq, 3),
            "message_numpy_msg_ms": round(t_msg, 2), "message_plain_genpy_ms": round(t_plain, 2),
            "message_bytes": msg_bytes}  # fmt: skip


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--features", default="1000,5000",
                    help="features per frame, comma-separated (default 1000,5000: the 640x480 budget and a dense "
                         "frame of the every-feature mode)")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--out", type=Path, default=Path("build/bench/driver.json"))
    args = ap.parse_args()
    sizes = [int(v) for v in args.features.split(",")]
    rospy = rosmsgs.import_rospy()  # numpy_msg lives in rospy
    from rospy.numpy_msg import numpy_msg

    msg_mod, _ = rosmsgs.load()
    runs = [measure(n, args.repeat, rospy, numpy_msg, msg_mod) for n in sizes]
    machine = f"{platform.processor() or platform.machine()} ({os.cpu_count()} cores)"
    report = {
        "command": "make bench-driver", "machine": machine, "python": platform.python_version(),
        "numpy": np.__version__, "repeat": args.repeat, "runs": runs, "a9_slowdown": A9_SLOWDOWN,
        "a9_axi_read_us": AXI_READ_US,
    }  # fmt: skip
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")
    print(f"{machine}, Python {platform.python_version()}, numpy {np.__version__}; median of {args.repeat}")
    print("| features | UioBus block mode | bank read | read + decode | bus reads | + message | Cortex-A9 estimate |")
    print("|---|---|---|---|---|---|---|")
    for run in runs:
        for r in run["reads"]:
            print(f"| {run['features']:,} | {r['block_mode']} | {r['bank_read']} | {r['read_decode_ms']} ms | "
                  f"{r['bus_reads']:,} | {r['host_total_ms']} ms | {r['a9_estimate_ms']} ms |")  # fmt: skip
    for run in runs:
        print(f"{run['features']:,} features: message build + serialise {run['message_numpy_msg_ms']:.2f} ms with "
              f"numpy_msg ({run['message_plain_genpy_ms']:.2f} ms plain genpy), {run['message_bytes']:,} B; "
              f"wait_irq round trip {run['wait_irq_roundtrip_ms']:.3f} ms")  # fmt: skip
    print(f"Cortex-A9 estimate (not measured): CPU x {A9_SLOWDOWN:g} + bus reads x {AXI_READ_US} us -> {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
