#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Per-frame cost of the board-to-host feature stream (`make bench-stream`; docs/stream.md): for a
frame of N features (default 1,000, the 640x480 budget, 2,047 and 4,095: the capacity of a bank of
the board's 720p build and of the largest bank, MEM_DEPTH_g 4096), the bytes of its FRAME message,
the server's encoding (orb_accel.stream.encode_frame, once per frame whatever the clients), the
client's decoding into the driver's Frame (decode_frame), and the whole way through the shipped
server and client on this machine: StreamServer.publish() to the decoded Frame in a RemoteAccel of
another process over loopback TCP (the client acknowledges each frame on a pipe; the median of the
round trips).

The frames are what OrbAccel.read_bank makes: N random features encoded in feature-memory slots
with the golden model's codec and decoded by the driver's decoder, with a record and counters; the
round trip through the stream is checked bit for bit. Writes build/bench/stream.json and prints a
table; `python -m orb_flow.record bench stream` keeps it (docs/results/bench.json).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from timing import median_ms  # scripts/bench/timing.py

from golden_model.featcodec import encode_eof, encode_feature, feature_slot, record_slot
from golden_model.featmem import SLOT_WORDS_USED, decode_features, decode_record
from golden_model.frameparams import FrameParams
from orb_accel.driver import COUNTERS, Frame, HwConfig
from orb_accel.serve import StreamServer
from orb_accel.stream import ARRAYS, ENVELOPE, FRAME_CLIENT, NAME, VERSION, decode_frame, encode_frame

NAMES = [c.lower() for c in COUNTERS]
CLIENT = """
import sys
from orb_accel.remote import RemoteAccel
with RemoteAccel(sys.argv[1], name="bench-stream") as accel:
    print("ready", flush=True)
    while True:
        frame, meta = accel.receive(60.0)
        print(meta.seq, len(frame), flush=True)
"""


def make_frame(n: int, hw: HwConfig, seed: int = 1) -> Frame:
    rng = np.random.default_rng(seed)
    words = np.zeros((n, SLOT_WORDS_USED), np.uint32)
    for s in range(n):
        scale = int(rng.integers(0, hw.scales))
        word = encode_feature(scale=scale, x=int(rng.integers(3, 600)), y=int(rng.integers(3, 400)),
                              score=int(rng.integers(1, 2000)), sector=int(rng.integers(0, hw.sectors)),
                              descriptor=rng.bytes(32), response=int(rng.integers(0, 64)),
                              low=int(rng.integers(0, 2)))  # fmt: skip
        words[s] = feature_slot(word)[:SLOT_WORDS_USED]
    record = decode_record(record_slot(encode_eof(7, 0, FrameParams(20, 14, "orb", "grid", n, 8, 6)), n, 0))
    feats = decode_features(words, hw.sectors, descriptors=True)
    feats.step = hw.step
    return Frame(0, feats, record, "orb", hw, {name: 0 for name in NAMES}, record.params)


def same(a: Frame, b: Frame) -> bool:
    fa, fb = a.features, b.features
    arrays = all(getattr(fa, k).dtype == getattr(fb, k).dtype and getattr(fa, k).tobytes() == getattr(fb, k).tobytes()
                 for k in ARRAYS)  # fmt: skip
    return arrays and (a.record, a.params, a.counters, a.hw, a.mode) == (b.record, b.params, b.counters, b.hw, b.mode)


def loopback_ms(frame: Frame, hw: HwConfig, repeat: int) -> float:
    """publish() to the decoded Frame in another process, acknowledged on its stdout; median."""
    info = {"protocol": NAME, "version": VERSION, "hw": vars(hw), "counters": NAMES, "modes": ["orb", "fast"],
            "records_params": True, "frame_wait_s": 60.0, "source": "bench-stream"}  # fmt: skip
    with StreamServer(info, "127.0.0.1:0", log=lambda _: None) as server:
        child = subprocess.Popen([sys.executable, "-c", CLIENT, server.address], stdout=subprocess.PIPE, text=True)
        try:
            assert child.stdout is not None and child.stdout.readline().strip() == "ready"
            while not any(c.connected and c.name for c in server.clients()):
                time.sleep(0.01)
            times = []
            for _ in range(repeat + 1):
                t0 = time.perf_counter()
                server.publish(frame)
                seq, n = (int(v) for v in child.stdout.readline().split())
                times.append(time.perf_counter() - t0)
                assert n == len(frame) and seq == server.seq - 1
            return statistics.median(times[1:]) * 1e3
        finally:
            child.kill()
            child.wait()


def measure(n: int, repeat: int) -> dict:
    hw = HwConfig(1280, 720, 4, 32, 1 << max(4, n.bit_length()), 5, 4)  # the smallest bank that holds n
    frame = make_frame(n, hw)
    body = encode_frame(frame, 0, 0, 0)
    payload = bytearray(FRAME_CLIENT.size) + body
    back, _ = decode_frame(memoryview(payload)[FRAME_CLIENT.size :], hw, NAMES)
    if not same(back, frame):
        raise SystemExit(f"error: the stream's round trip of {n} features is not bit-exact")
    t_enc = median_ms(lambda: encode_frame(frame, 0, 0, 0), repeat)
    t_dec = median_ms(lambda: decode_frame(memoryview(payload)[FRAME_CLIENT.size :], hw, NAMES), repeat)
    return {"features": n, "message_bytes": ENVELOPE.size + len(payload), "bytes_per_feature": round(len(body) / n, 1),
            "encode_ms": round(t_enc, 3), "decode_ms": round(t_dec, 3),
            "loopback_ms": round(loopback_ms(frame, hw, repeat), 3)}  # fmt: skip


def main() -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--features", default="1000,2047,4095",
                    help="features per frame, comma-separated (default 1000,2047,4095: the 640x480 budget, a full "
                         "bank of the board's 720p build, a full bank of the largest memory)")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=31)
    ap.add_argument("--out", type=Path, default=Path("build/bench/stream.json"))
    args = ap.parse_args()
    runs = [measure(int(v), args.repeat) for v in args.features.split(",")]
    machine = f"{platform.processor() or platform.machine()} ({os.cpu_count()} cores)"
    report = {"command": "make bench-stream", "machine": machine, "python": platform.python_version(),
              "numpy": np.__version__, "repeat": args.repeat, "protocol_version": VERSION, "runs": runs}  # fmt: skip
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")
    print(f"{machine}, Python {platform.python_version()}, numpy {np.__version__}; median of {args.repeat}")
    print("| features | FRAME message | bytes per feature | encode (server) | decode (client) | publish to Frame |")
    print("|---|---|---|---|---|---|")
    for r in runs:
        print(f"| {r['features']:,} | {r['message_bytes']:,} B | {r['bytes_per_feature']} | {r['encode_ms']} ms | "
              f"{r['decode_ms']} ms | {r['loopback_ms']} ms |")  # fmt: skip
    print(f"-> {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
