#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Per-frame CPU cost of the board-side software (`make bench-driver`; docs/ros.md): reading and
decoding a frame of N features (default 1,000, the 640x480 budget, 2,000 and 5,000) through the
shipped driver, and building and serialising its ROS message, on this machine; with the number of
32-bit bus accesses per frame. Both feature memories side by side: the block-RAM banks (read over
the register bus) and the DDR ring (docs/feature-dma.md: read from cached memory after two cache
invalidations; N up to 4,095, a buffer's largest).

The bus is the UIO backend (orb_accel.uio.UioBus) over a file-backed map that holds the registers
and, for the banks, one bank of N features in the feature memory's layout (random features,
encoded with the golden model's codec), so the measured code is exactly what runs on the board,
minus the bus's own latency (the map is RAM here, the PL on the board). Both block modes of UioBus
are measured, and both bank-reading strategies of the driver (one block per slot, or one block for
the bank). The DDR ring is the u-dma-buf backend (orb_accel.ddr.UDmaBuf) on a fake sysfs tree: a
regular file as /dev/udmabuf0 holding buffer 0 (its record, then N features) and a regular file as
sync_for_cpu, so each invalidation is the driver's real system call, minus the kernel's cache work.

The Cortex-A9 figures are an estimate: this machine's times scaled by a stated factor plus the bus
accesses at a stated AXI latency, and for the DDR ring the modelled kernel cache work and DDR
reads (the constants below, stated assumptions). A whole frame (`next_frame`: the interrupt, the
status, the read, the decoding, the counters, the release) is measured for the default bank read
and the DDR ring, with the decoding alone (the same code in both) apart. Writes
build/bench/driver.json and prints the tables.
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
from golden_model.featmem import SLOT_BYTES, decode_features
from golden_model.frameparams import FrameParams
from golden_model.limits import BUDGET_MAX
from orb_accel import OrbAccel, UioBus
from orb_accel.ddr import CACHE_LINE, UDmaBuf
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
# The DDR ring's costs on the board that this machine cannot show (stated assumptions, not
# measurements): a write to u-dma-buf's sync_for_cpu (the system call, sysfs's store, kstrtoull, the
# module's mutex, the entry to dma_sync_single_for_cpu) at 20 us of a 667 MHz Cortex-A9; the cache
# work of dma_sync_single_for_cpu(DMA_FROM_DEVICE) on ARMv7 (arch/arm/mm/dma-mapping.c: outer_inv_range,
# one PL310 "invalidate line by PA" register write per 32-byte line, and v7_dma_inv_range, one L1
# invalidate by address per line: line by line, there is no range instruction) at 60 ns per 32-byte
# line (40 CPU cycles); the first CPU read of the invalidated bytes, cache misses to the DDR3
# through the L2, at 400 MB/s (2.5 ns per byte). Bus writes are costed as reads (AXI_READ_US).
SYNC_CALL_US = 20.0
INVALIDATE_LINE_NS = 60.0
DDR_READ_NS_PER_BYTE = 2.5
DDR_MAX_FEATURES = 4095  # a ring buffer's largest frame: DEPTH_g 4096 (mem_depth_t) less the record
DDR_PHYS = 0x1E900000  # the fake u-dma-buf's bus address (inside the fabric's window)
FRAME_REPEAT = 4  # the whole frame and the decoding alone: repeat x this (their difference is a small number)


def feature_slots(n: int, seed: int = 1) -> tuple[list[list[int]], list[int]]:
    """n random features' slot words and the record of their frame."""
    rng = np.random.default_rng(seed)
    slots = []
    for _ in range(n):
        scale = int(rng.integers(0, SCALES))
        word = encode_feature(scale=scale, x=int(rng.integers(3, (W >> scale) - 3)),
                              y=int(rng.integers(3, (H >> scale) - 3)), score=int(rng.integers(1, 2000)),
                              sector=int(rng.integers(0, SECTORS)), descriptor=rng.bytes(32),
                              response=int(rng.integers(0, 64)), low=bool(rng.integers(0, 2)))  # fmt: skip
        slots.append(feature_slot(word))
    # a budget-sized frame says grid selection with budget n; a larger one (the dense case) says
    # every-feature mode, where the budget field is not used (and n may exceed it)
    grid = n <= BUDGET_MAX
    params = FrameParams(20, 14, "orb", "grid" if grid else "all", n if grid else 0, 8, 6)
    return slots, record_slot(encode_eof(7, 0, params), n, 0)


def make_ddr(tmp: Path, n: int, depth: int) -> tuple[Path, int, Path, Path]:
    """A register map of a DDR build (CFG_DDR.ddr 1, RING_STATUS buffer 0 READY) and a fake
    u-dma-buf of two ring buffers, buffer 0 holding the record and n features: (map, its size,
    sysfs, dev)."""
    path = tmp / "ddr-map"
    size = make_map(path, 0, depth, ddr=True)
    sysfs, dev = tmp / "sys", tmp / "dev"
    (sysfs / "udmabuf0").mkdir(parents=True, exist_ok=True)
    dev.mkdir(exist_ok=True)
    ring_bytes = 2 * depth * SLOT_BYTES
    (sysfs / "udmabuf0" / "phys_addr").write_text(f"0x{DDR_PHYS:08x}\n")
    (sysfs / "udmabuf0" / "size").write_text(f"{ring_bytes}\n")
    (sysfs / "udmabuf0" / "sync_for_cpu").write_text("0\n")
    words = np.zeros(ring_bytes // 4, dtype="<u4")
    slots, rec = feature_slots(n)
    words[: len(rec)] = rec
    for s, slot in enumerate(slots, start=1):
        words[s * SLOT_BYTES // 4 : s * SLOT_BYTES // 4 + len(slot)] = slot
    (dev / "udmabuf0").write_bytes(words.tobytes())
    return path, size, sysfs, dev


def make_map(path: Path, n: int, depth: int, seed: int = 1, ddr: bool = False) -> int:
    """A file laid out as the accelerator's map: registers, bank 0 with n random features (a DDR
    build's: registers only, buffer 0 READY)."""
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
    put(regs.IRQ_STATUS, 1)
    if ddr:
        cfg = regs.CFG_DDR.field("ddr").put(1) | regs.CFG_DDR.field("win_size").put(1024)
        put(regs.CFG_DDR, cfg)
        put(regs.RING_STATUS, regs.RING_STATUS.field("ready").put(1))
        path.write_bytes(words.tobytes())
        return size
    put(regs.STATUS, regs.STATUS.field("bank_ready").put(1))
    put(regs.BANK0_INFO, regs.BANK0_INFO.field("count").put(n))
    base = regs.MEM_BASE // 4
    slots, rec = feature_slots(n, seed)
    for s, slot in enumerate(slots):
        words[base + s * SLOT_BYTES // 4 : base + s * SLOT_BYTES // 4 + len(slot)] = slot
    words[base + n * SLOT_BYTES // 4 : base + n * SLOT_BYTES // 4 + len(rec)] = rec
    path.write_bytes(words.tobytes())
    return size


def ddr_model_ms(n: int, invalidations: int) -> float:
    """The DDR ring's modelled kernel and memory cost of one frame on the Cortex-A9 (ms): the sync
    calls, the lines of the record and the n features invalidated, their bytes read from DDR."""
    nbytes = (n + 1) * SLOT_BYTES
    return (invalidations * SYNC_CALL_US + nbytes / CACHE_LINE * INVALIDATE_LINE_NS / 1e3
            + nbytes * DDR_READ_NS_PER_BYTE / 1e3) / 1e3  # fmt: skip


def time_frame(accel: OrbAccel, bus: UioBus, kernel: socket.socket, repeat: int) -> tuple[float, int, int]:
    """One whole frame through next_frame (the interrupt over the socket pair standing in for
    /dev/uioN): (median ms, 32-bit reads, 32-bit writes)."""

    def one() -> None:
        kernel.sendall(struct.pack("=I", 1))
        accel.next_frame(1.0)
        kernel.recv(4)

    r0, w0 = bus.reads, bus.writes
    one()
    reads, writes = bus.reads - r0, bus.writes - w0
    return median_ms(one, repeat), reads, writes


def measure(n: int, repeat: int, rospy, numpy_msg, msg_mod) -> dict:
    """One frame size: the read strategies, the interrupt round trip and the message."""
    depth = 1 << max(11, (n + 1).bit_length())
    rows = []
    frames = []
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
                    rows.append({"path": "bank", "block_mode": mode, "bank_read": strategy,
                                 "read_decode_ms": round(t_read, 2), "bus_reads": reads})  # fmt: skip
                    if mode == "copy" and strategy == "bank":  # the default: the whole frame too
                        t_frame, f_reads, f_writes = time_frame(accel, bus, kernel, repeat * FRAME_REPEAT)
                        frames.append({"path": "bank", "frame_ms": round(t_frame, 3), "frame_reads": f_reads,
                                       "frame_writes": f_writes, "invalidations": 0})  # fmt: skip
                t_irq = median_ms(lambda b=bus, k=kernel: (k.sendall(struct.pack("=I", 1)), b.wait_irq(1.0),
                                                           k.recv(4)), repeat)  # fmt: skip
            ours.close()
            kernel.close()
        if n <= DDR_MAX_FEATURES and depth <= DDR_MAX_FEATURES + 1:
            rows.append(measure_ddr(Path(tmp), n, depth, repeat, frames))
        slots, _ = feature_slots(n)
        words = np.array(slots, dtype=np.uint32)  # whole 64-byte slots, as both paths give them to the decoder
        t_decode = median_ms(lambda: decode_features(words, SECTORS, descriptors=True), repeat * FRAME_REPEAT)
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
        model = ddr_model_ms(n, r["invalidations"]) if r["path"] == "ddr" else 0.0
        r["a9_estimate_ms"] = round(cpu + r["bus_reads"] * AXI_READ_US / 1e3 + model, 1)
    for f in frames:  # a whole frame, and without the decoding (the same code on both paths)
        model = ddr_model_ms(n, f["invalidations"]) if f["path"] == "ddr" else 0.0
        a9 = f["frame_ms"] * A9_SLOWDOWN + (f["frame_reads"] + f["frame_writes"]) * AXI_READ_US / 1e3 + model
        f["a9_frame_ms"] = round(a9, 2)
        f["a9_transfer_ms"] = round(a9 - t_decode * A9_SLOWDOWN, 2)
    return {"features": n, "reads": rows, "frames": frames, "decode_ms": round(t_decode, 3),
            "wait_irq_roundtrip_ms": round(t_irq, 3), "message_numpy_msg_ms": round(t_msg, 2),
            "message_plain_genpy_ms": round(t_plain, 2), "message_bytes": msg_bytes}  # fmt: skip


def measure_ddr(tmp: Path, n: int, depth: int, repeat: int, frames: list[dict]) -> dict:
    """The DDR ring's row (read_bank of buffer 0) and its whole frame (appended to `frames`)."""
    path, size, sysfs, dev = make_ddr(tmp, n, depth)
    ours, kernel = socket.socketpair()
    with UioBus(path, size, irq_fd=ours.fileno()) as bus, UDmaBuf("udmabuf0", sysfs, dev) as mem:
        accel = OrbAccel(bus, memory=mem)
        assert accel.ddr and accel.ring is not None and accel.ring.count == 2
        r0, s0 = bus.reads, mem.syncs
        frame = accel.read_bank(0)
        reads, syncs = bus.reads - r0, mem.syncs - s0
        assert len(frame) == n and syncs == 2
        del frame
        t_read = median_ms(lambda: accel.read_bank(0), repeat)
        t_frame, f_reads, f_writes = time_frame(accel, bus, kernel, repeat * FRAME_REPEAT)
        frames.append({"path": "ddr", "frame_ms": round(t_frame, 3), "frame_reads": f_reads,
                       "frame_writes": f_writes, "invalidations": syncs})  # fmt: skip
        accel.close()
    ours.close()
    kernel.close()
    return {"path": "ddr", "block_mode": "-", "bank_read": "ddr", "read_decode_ms": round(t_read, 2),
            "bus_reads": reads, "invalidations": syncs, "invalidated_bytes": (n + 1) * SLOT_BYTES}  # fmt: skip


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--features", default="1000,2000,5000",
                    help="features per frame, comma-separated (default 1000,2000,5000: the 640x480 budget, twice it, "
                         "and a dense frame of the every-feature mode; the DDR ring up to 4,095)")  # fmt: skip
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
        "a9_axi_read_us": AXI_READ_US, "a9_sync_call_us": SYNC_CALL_US, "a9_invalidate_line_ns": INVALIDATE_LINE_NS,
        "a9_ddr_read_ns_per_byte": DDR_READ_NS_PER_BYTE,
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
    print()
    print("| features | path | bus reads + writes per frame | next_frame here | Cortex-A9 estimate | without the "
          "decoding |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for run in runs:
        for f in run["frames"]:
            print(f"| {run['features']:,} | {f['path']} | {f['frame_reads']:,} + {f['frame_writes']} | "
                  f"{f['frame_ms']} ms | {f['a9_frame_ms']} ms | {f['a9_transfer_ms']} ms |")  # fmt: skip
        by = {f["path"]: f for f in run["frames"]}
        if "ddr" in by:
            b, d = by["bank"], by["ddr"]
            print(f"| {run['features']:,} | bank / ddr | {b['frame_reads'] / d['frame_reads']:.0f}x reads | "
                  f"{b['frame_ms'] / d['frame_ms']:.1f}x | {b['a9_frame_ms'] / d['a9_frame_ms']:.1f}x | "
                  f"{b['a9_transfer_ms'] / d['a9_transfer_ms']:.1f}x |")  # fmt: skip
    for run in runs:
        print(f"{run['features']:,} features: message build + serialise {run['message_numpy_msg_ms']:.2f} ms with "
              f"numpy_msg ({run['message_plain_genpy_ms']:.2f} ms plain genpy), {run['message_bytes']:,} B; "
              f"wait_irq round trip {run['wait_irq_roundtrip_ms']:.3f} ms")  # fmt: skip
    print(f"Cortex-A9 estimate (not measured): CPU x {A9_SLOWDOWN:g} + bus accesses x {AXI_READ_US} us; the DDR "
          f"ring + {SYNC_CALL_US:g} us per sync_for_cpu, {INVALIDATE_LINE_NS:g} ns per 32-byte line invalidated, "
          f"{DDR_READ_NS_PER_BYTE:g} ns per byte read from DDR -> {args.out}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
