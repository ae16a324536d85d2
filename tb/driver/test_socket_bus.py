# SPDX-License-Identifier: MIT
"""The driver against the simulator in another process: orb_sim.sim_server runs orb_accel_top and
serves its AXI4-Lite bus on a socket; orb_accel.socket_bus.SocketBus is the driver's bus, as UioBus
is on the board. One server for the module (128x96 colour photographs, 2 scales) on the fast
engine: GHDL's synthesised netlist of the RTL in Verilator (docs/fast-sim.md; bit-exact with the
RTL in GHDL by tb/fast/test_fast_sim.py), the configuration test_fast_sim builds, so one build
serves both. Servers on the RTL in GHDL: test_ghdl_server_frames_log's (small luma frames) and
test_cli_sim_zynq's (the board's wrapper).

- frames read through the public API are bit-exact with the golden model (features, scores,
  angles, descriptors), with full-resolution and per-scale coordinates, counters and record;
- cv2 conversion: keypoints and a descriptor array that cv2.BFMatcher(NORM_HAMMING) takes;
- errors: an AXI error response (SLVERR) raises BusError; illegal values raise ValueError naming
  the range before anything reaches the bus; a frame that never comes raises TimeoutError with the
  status registers; the bank is released when the caller's block raises;
- the CLI (`orb-accel board info/stream --connect`), also with OpenCV, cocotb and the simulator
  packages unimportable (as on the board);
- the protocol: a client that goes away mid-stream, a bad request, a second client afterwards.
- the DDR memory operation (MEM_READ, HELLO's ddr): against a server of a fake bus (no simulator)
  reads inside the region, SocketMemory's cached view (stale until invalidated), a read outside the
  region or to a server without DDR refused with a message (client and server side), never a
  hang; on the GHDL engine a DDR build (MEM_KIND_g "DDR", its frames in the job's AXI4 RAM) read by
  the driver over the socket (SocketMemory), bit-exact.
"""

from __future__ import annotations

import itertools
import json
import os
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import cv2
import numpy as np
import pytest

from golden_model import regs
from golden_model.config import RECOMMENDED_COLS, RECOMMENDED_ROWS, RECOMMENDED_THRESHOLD_LO, named
from golden_model.features import Features, first_difference
from golden_model.luma import rgb_to_luma
from orb_accel import BusError, OrbAccel
from orb_accel.csvdir import read_csv_dir
from orb_accel.driver import HwConfig
from orb_accel.opencv import to_cv2
from orb_accel.socket_bus import MAX_MEM_BYTES, MEM_READ, REQUEST, RESPONSE, SocketBus, SocketMemory, recv_exact
from orb_sim.bus_server import handle, serve, server_info
from orb_sim.sim_server import SimServer
from orbtb.images import colour_photo
from orbtb.scoreboard import expected_features

TINY = named("test-tiny")  # the simulated bitstream of these tests (docs/configurations.md)
W, H, SCALES, SECTORS, DEPTH = TINY.width, TINY.height, TINY.scales, TINY.sectors, TINY.mem_depth
assert (TINY.step_num, TINY.step_den) == (2, 1), "the model calls below assume the 2:1 pyramid"
PHOTOS = ("astronaut", "coffee", "chelsea")
CLI = [sys.executable, "-m", "orb_tools.cli"]


@pytest.fixture(scope="module")
def frames() -> np.ndarray:
    return np.stack([colour_photo(name, W, H) for name in PHOTOS])


@pytest.fixture(scope="module")
def server(frames: np.ndarray, tmp_path_factory: pytest.TempPathFactory) -> Iterator[SimServer]:
    with SimServer(frames, TINY.name, engine="fast",
                   job_dir=tmp_path_factory.mktemp("sim-server")) as s:  # fmt: skip
        yield s


# the driver's default selection on this accelerator: the grid, the recommended budget within a bank
HW = HwConfig(W, H, SCALES, SECTORS, DEPTH)
SELECTION = f"grid:{HW.default_budget()}:{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}"


def model(frames: np.ndarray, k: int, threshold: int, mode: str = "orb") -> Features:
    return expected_features(rgb_to_luma(frames[k]), SCALES, threshold, mode, SECTORS, (2, 1), SELECTION)


def which_photo(frames: np.ndarray, feats: Features, threshold: int, mode: str = "orb") -> int:
    """The index of the photograph whose model features equal `feats` exactly."""
    diffs = {k: first_difference(feats, model(frames, k, threshold, mode)) for k in range(len(frames))}
    found = [k for k, d in diffs.items() if d is None]
    assert len(found) == 1, f"the frame equals no photograph at threshold {threshold} ({mode}): {diffs}"
    return found[0]


def test_frames_bit_exact(server: SimServer, frames: np.ndarray) -> None:
    with SocketBus(server.address) as bus:
        accel = OrbAccel(bus)
        assert accel.hw.width == W and accel.hw.height == H and accel.hw.scales == SCALES
        accel.configure(threshold=20, mode="orb")
        got = list(accel.frames(3, timeout_s=0.01))
        ks = [which_photo(frames, f.features, 20) for f in got]
        numbers = [f.number for f in got]
        assert numbers == list(range(numbers[0], numbers[0] + 3)), f"frame numbers {numbers} not consecutive"
        assert [(k - ks[0]) % len(PHOTOS) for k in ks] == [0, 1, 2], f"photographs {ks} out of stream order"
        f = got[0]
        assert f.descriptors.shape == (len(f), 32) and f.descriptors.dtype == np.uint8
        sx, sy = f.scale_x.astype(float), f.scale_y.astype(float)
        np.testing.assert_array_equal(f.x, (sx + 0.5) * 2.0**f.scale - 0.5)
        np.testing.assert_array_equal(f.y, (sy + 0.5) * 2.0**f.scale - 0.5)
        np.testing.assert_array_equal(f.angle, f.features.sector * 360.0 / SECTORS)
        assert set(f.counters) == {"frame_count", "dropped", "proto_errors", "overrun", "overflow_count",
                                   "desc_lost", "discarded"}  # fmt: skip
        assert f.counters["frame_count"] >= f.number + 1 and f.counters["overrun"] == 0
        assert f.dropped == 0 and f.truncated == 0

        # fast mode from the next frame: no angles, no descriptors
        accel.configure(threshold=30, mode="fast")
        accel.settle(0.01)
        fast = accel.next_frame(0.01)
        which_photo(frames, fast.features, 30, "fast")
        assert fast.mode == "fast" and fast.descriptors.shape == (len(fast), 0)
        assert np.all(fast.keypoint_arrays()["angle"] == -1.0)
        kps, des = to_cv2(fast)
        assert des is None and len(kps) == len(fast)


def test_opencv_conversion(server: SimServer, frames: np.ndarray) -> None:
    with SocketBus(server.address) as bus:
        accel = OrbAccel(bus)
        accel.configure(threshold=20)
        accel.settle(0.01)
        frame = accel.next_frame(0.01)
        which_photo(frames, frame.features, 20)
        kps, des = to_cv2(frame)
        assert len(kps) == len(frame) > 50
        assert des is not None and des.shape == (len(frame), 32) and des.dtype == np.uint8
        for i in (0, len(kps) // 2, len(kps) - 1):
            kp = kps[i]
            assert kp.pt == pytest.approx((frame.x[i], frame.y[i]))
            assert kp.octave == frame.scale[i] and kp.size == 31 * 2 ** int(frame.scale[i])
            assert kp.angle == pytest.approx(frame.angle[i], abs=1e-4) and kp.response == frame.score[i]
        matches = cv2.BFMatcher(cv2.NORM_HAMMING, crossCheck=True).match(des, des)
        assert len(matches) == len(kps) and all(m.distance == 0 for m in matches)


def test_errors(server: SimServer) -> None:
    with SocketBus(server.address) as bus:
        accel = OrbAccel(bus)
        reads = bus.reads
        with pytest.raises(BusError, match="SLVERR"):
            bus.read32(0x3C)  # an offset below MEM_BASE that names no register
        with pytest.raises(BusError, match="SLVERR"):
            bus.write32(regs.ID.offset, 1)
        for bad, text in ((256, "0..255"), (-1, "0..255"), (True, "0..255")):
            with pytest.raises(ValueError, match=text):
                accel.configure(threshold=bad)  # type: ignore[arg-type]
        with pytest.raises(ValueError, match="mode"):
            accel.configure(threshold=20, mode="brief")
        with pytest.raises(ValueError, match="read-only"):
            accel.write(regs.STATUS, 0)
        with pytest.raises(ValueError, match=r"bank 0\.\.1"):
            accel.write(regs.BANK_RELEASE, 2)
        with pytest.raises(ValueError, match="write-only"):
            accel.read(regs.BANK_RELEASE)
        assert bus.reads == reads + 1 and bus.writes == 1, "a refused value reached the bus"

        # the bank goes back also when the caller's code raises; the stream goes on
        accel.configure(threshold=20)
        with pytest.raises(RuntimeError, match="caller"), accel.frame(0.01) as frame:
            held = frame.bank
            assert regs.STATUS.field("bank_ready").get(accel.read(regs.STATUS)) >> held & 1
            raise RuntimeError("the caller's code failed")
        # a release shows in STATUS from a read that starts a clock or more after the write's
        # response (docs/feature-memory.md); the fast engine's bus issues the next read at once
        accel.read(regs.ID)
        assert not regs.STATUS.field("bank_ready").get(accel.read(regs.STATUS)) >> held & 1, "bank not released"
        after = accel.next_frame(0.01)
        assert after.number == frame.number + 1

        # a frame that never comes: disabled, then 0.4 ms of simulated time (2.4 frame periods).
        # Up to two frames still come first: one already complete in the other bank (reading a bank
        # over AXI4-Lite takes longer than a frame period here) and the one that passed the gate
        # before the write (docs/frame-gate.md); which of them exist depends on the frames this
        # worker's server ran before (CI saw two at 868ee63). A third means the disable did nothing.
        accel.configure(threshold=20, enable=False)
        late = 0
        with pytest.raises(TimeoutError, match=r"no interrupt within 0.0004 s: STATUS = 0x.*IRQ_STATUS"):
            for _ in range(3):
                accel.next_frame(0.0004)
                late += 1
        assert late <= 2, f"{late} frames after the disable"
        accel.configure(threshold=20)


def test_protocol(server: SimServer) -> None:
    host, port = server.address.rsplit(":", 1)
    with socket.create_connection((host, int(port)), timeout=60) as s:
        s.sendall(REQUEST.pack(99, 0, 0))
        status, length = RESPONSE.unpack(recv_exact(s, RESPONSE.size))
        assert status == 2 and b"unknown operation 99" in recv_exact(s, length)
        s.sendall(REQUEST.pack(1, 0, 0)[:5])  # half a request, then gone
    with SocketBus(server.address) as bus:  # the next client is served
        assert bus.read32(regs.ID.offset) == regs.ORB_ID
        with pytest.raises(ValueError, match=r"1\.\.1048576"):
            bus.read_block(regs.MEM_BASE, 0)
        assert bus.memory_region is None  # a BRAM build
        with pytest.raises(ValueError, match="no DDR memory"):
            bus.read_mem(0x1000_0000, 64)
    with socket.create_connection((host, int(port)), timeout=60) as s:  # the server refuses it too
        s.sendall(REQUEST.pack(MEM_READ, 0x1000_0000, 64))
        status, length = RESPONSE.unpack(recv_exact(s, RESPONSE.size))
        assert status == 2 and b"no DDR memory" in recv_exact(s, length)
    with pytest.raises(ConnectionError, match="no simulator"):
        SocketBus("127.0.0.1:1")
    with pytest.raises(ValueError, match="HOST:PORT"):
        SocketBus("localhost")


def _png(frames: np.ndarray, tmp: Path) -> None:
    for k, rgb in enumerate(frames):
        cv2.imwrite(str(tmp / f"{k}.png"), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))


def test_cli_board(server: SimServer, frames: np.ndarray, tmp_path: Path) -> None:
    info = subprocess.run([*CLI, "board", "info", "--connect", server.address], capture_output=True, text=True)
    assert info.returncode == 0, info.stderr
    assert "ID 0x4f524231" in info.stdout and f"{W}x{H}, {SCALES} scales of 2:1, {SECTORS} sectors" in info.stdout
    out = tmp_path / "csv"
    stream = subprocess.run([*CLI, "board", "stream", "--connect", server.address, "--frames", "2", "--threshold",
                             "25", "--csv", str(out)], capture_output=True, text=True)  # fmt: skip
    assert stream.returncode == 0, stream.stderr
    assert "2 frames in" in stream.stdout and "features per frame" in stream.stdout
    rows = read_csv_dir(out)
    assert len(rows) == 2 and all(r["threshold"] == 25 for r, _ in rows)
    for _, feats in rows:
        which_photo(frames, feats, 25)
    bad = subprocess.run([*CLI, "board", "stream", "--connect", server.address, "--threshold", "300"],
                         capture_output=True, text=True)  # fmt: skip
    assert bad.returncode == 2 and "0..255" in bad.stderr and "Traceback" not in bad.stderr
    gone = subprocess.run([*CLI, "board", "info", "--connect", "127.0.0.1:1"], capture_output=True, text=True)
    assert gone.returncode == 2 and "no simulator" in gone.stderr


BLOCKER = """
import importlib.abc, sys
class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.split(".")[0] in {"cv2", "cocotb", "cocotb_tools", "cocotbext", "skimage", "matplotlib", "scipy"}:
            raise ImportError(f"{name} is not on the board")
sys.meta_path.insert(0, Block())
"""


def test_board_needs_numpy_only(server: SimServer, tmp_path: Path) -> None:
    """The board commands, the driver and the node with OpenCV, cocotb, scikit-image, matplotlib
    and scipy unimportable (the board's Debian has numpy and ROS only)."""
    code = (
        BLOCKER
        + f"""
import orb_accel, orb_accel.uio, orb_accel.devmem, orb_accel.socket_bus, orb_accel.csvdir, orb_ros.node
from orb_tools.cli import main
sys.exit(main(["board", "stream", "--connect", "{server.address}", "--frames", "1", "--csv", "{tmp_path / "c"}"]))
"""
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "1 frames in" in r.stdout
    check = subprocess.run([sys.executable, "-c", BLOCKER + "import cv2"], capture_output=True, text=True)
    assert "not on the board" in check.stderr, "the import blocker blocks nothing"


def test_server_info(server: SimServer) -> None:
    with SocketBus(server.address) as bus:
        assert bus.info["generics"]["WIDTH_g"] == W and bus.info["toplevel"] == "orb_accel_top"
        assert bus.info["engine"] == "fast"
    assert json.loads((server.job / "config.json").read_text())["generics"]["MEM_DEPTH_g"] == DEPTH
    assert os.path.exists(server.log)


def test_ghdl_server_frames_log(tmp_path: Path) -> None:
    """The GHDL engine's server: two small luma frames round and round, the frames it started in
    frames.log in stream order, each published frame bit-exact."""
    small = np.stack([rgb_to_luma(colour_photo(name, 64, 48)) for name in ("coffee", "rocket")])
    with SimServer(small, TINY.name, scales=1, mem_depth=64, job_dir=tmp_path / "job") as srv, \
            SocketBus(srv.address) as bus:  # fmt: skip
        assert bus.info["engine"] == "ghdl" and bus.info["generics"]["INPUT_g"] == "LUMA"
        accel = OrbAccel(bus)
        accel.configure(threshold=20)
        got = list(accel.frames(3, timeout_s=0.01))
        sent = srv.frames_sent()
    assert len(sent) >= 3 and [k for _, k, _ in sent] == [i % 2 for i in range(len(sent))], sent
    hw = HwConfig(64, 48, 1, SECTORS, 64)
    selection = f"grid:{hw.default_budget()}:{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}"
    want = [expected_features(img, 1, 20, "orb", SECTORS, (2, 1), selection) for img in small]
    ks = []
    for f in got:
        diffs = [first_difference(f.features, w) for w in want]
        assert diffs.count(None) == 1, f"frame {f.number} equals no photograph: {diffs}"
        ks.append(diffs.index(None))
    assert [(k - ks[0]) % 2 for k in ks] == [0, 1, 0], f"photographs {ks} out of stream order"


class _MemBus:
    """A fake bus with a DDR region: registers read their address, the memory a known pattern."""

    BASE, SIZE = 0x1000_0000, 1 << 16

    def __init__(self) -> None:
        self.mem = bytearray((np.arange(self.SIZE) * 7 % 251).astype(np.uint8).tobytes())

    def read32(self, addr: int) -> int:
        return addr

    def write32(self, addr: int, value: int) -> None:
        pass

    def read_block(self, addr: int, count: int) -> np.ndarray:
        return np.arange(addr, addr + 4 * count, 4, dtype=np.uint32)

    def wait_irq(self, timeout_s: float) -> bool:
        return False

    def read_mem(self, addr: int, nbytes: int) -> bytes:
        off = addr - self.BASE
        assert 0 <= off and off + nbytes <= self.SIZE, "the server let a read outside the region through"
        return bytes(self.mem[off : off + nbytes])


CFG = {"toplevel": "orb_accel_top", "generics": {"WIDTH_g": 64, "HEIGHT_g": 48}, "h_blank": 16, "v_blank": 1280}


def test_mem_read_handle() -> None:
    """The server's answer to MEM_READ, without a socket: inside the region the bytes, outside it,
    of no length, too long, or with no region a message."""
    from orb_sim.ddr_ram import DDR_BASE, DDR_SIZE
    from orb_sim.sim_server import DDR_REGION

    assert DDR_REGION == (DDR_BASE, DDR_SIZE), "SimServer's default region is not the DDR model's"
    bus = _MemBus()
    info = server_info(CFG, 1, 10, "fake", (bus.BASE, bus.SIZE))
    assert info["ddr"] == {"base": bus.BASE, "size": bus.SIZE}
    assert handle(bus, info, MEM_READ, bus.BASE + 64, 16) == (0, bytes(bus.mem[64:80]))  # type: ignore[arg-type]
    for addr, n, text in ((bus.BASE - 64, 64, "outside the simulated DDR region [0x10000000, 0x10010000)"),
                          (bus.BASE + bus.SIZE - 32, 64, "outside the simulated DDR region"),
                          (bus.BASE, 0, f"outside 1..{MAX_MEM_BYTES}"),
                          (bus.BASE, MAX_MEM_BYTES + 1, f"outside 1..{MAX_MEM_BYTES}")):  # fmt: skip
        status, payload = handle(bus, info, MEM_READ, addr, n)  # type: ignore[arg-type]
        assert status == 2 and text in payload.decode(), (addr, n, payload)
    status, payload = handle(bus, server_info(CFG, 1, 10, "fake"), MEM_READ, bus.BASE, 64)  # type: ignore[arg-type]
    assert status == 2 and b"no DDR memory" in payload


def test_socket_memory() -> None:
    """SocketMemory over a server of the fake bus: the region from HELLO, a stale (zero) view until
    invalidate fetches the range, reads outside the region refused on the client's side (ValueError
    before anything is sent) and on the server's (a raw request: an answer, not a hang)."""
    import threading

    bus = _MemBus()
    listener = socket.create_server(("127.0.0.1", 0))
    port = listener.getsockname()[1]
    info = server_info(CFG, 1, 10, "fake", (bus.BASE, bus.SIZE))
    thread = threading.Thread(target=serve, args=(listener, bus, info), daemon=True)
    thread.start()
    try:
        with SocketBus(f"127.0.0.1:{port}", op_timeout_s=30) as client:
            assert client.memory_region == (bus.BASE, bus.SIZE)
            mem = SocketMemory(client)
            assert (mem.phys_addr, mem.size) == (bus.BASE, bus.SIZE)
            assert not np.any(mem.view(0, bus.SIZE)), "the view before any invalidate is not the stale (zero) copy"
            mem.invalidate(128, 192)
            np.testing.assert_array_equal(mem.view(128, 192), np.frombuffer(bytes(bus.mem[128:320]), np.uint8))
            assert not np.any(mem.view(0, 128)) and not np.any(mem.view(320, 64)), "invalidate fetched beyond its range"
            with pytest.raises(ValueError):
                mem.view(0, 64).__setitem__(0, 1)  # read-only
            bus.mem[128] ^= 0xFF  # the device writes: the CPU sees it only after an invalidate
            assert mem.view(128, 1)[0] != bus.mem[128]
            mem.invalidate(128, 64)
            assert mem.view(128, 1)[0] == bus.mem[128] and mem.invalidations == 2 and mem.fetched_bytes == 256
            mem.invalidate(0, bus.SIZE)  # the whole region
            np.testing.assert_array_equal(mem.view(0, bus.SIZE), np.frombuffer(bytes(bus.mem), np.uint8))
            with pytest.raises(ValueError, match="outside the memory"):
                mem.invalidate(bus.SIZE - 64, 128)
            reads = client.mem_reads
            with pytest.raises(ValueError, match=r"outside the simulated DDR region \[0x10000000, 0x10010000\)"):
                client.read_mem(bus.BASE + bus.SIZE, 64)
            with pytest.raises(ValueError, match="outside the simulated DDR region"):
                client.read_mem(0, 64)
            assert client.mem_reads == reads, "a refused read reached the server"
            assert client.read32(0x14) == 0x14  # the connection is still in step
        with socket.create_connection(("127.0.0.1", port), timeout=30) as s:
            s.settimeout(30)  # an answer, not a hang
            s.sendall(REQUEST.pack(MEM_READ, bus.BASE - 4096, 64))
            status, length = RESPONSE.unpack(recv_exact(s, RESPONSE.size))
            assert status == 2 and b"outside the simulated DDR region" in recv_exact(s, length)
            s.sendall(REQUEST.pack(MEM_READ, bus.BASE, 8))
            status, length = RESPONSE.unpack(recv_exact(s, RESPONSE.size))
            assert status == 0 and recv_exact(s, length) == bytes(bus.mem[:8])
            s.sendall(REQUEST.pack(6, 0, 0))  # SHUTDOWN
            recv_exact(s, RESPONSE.size)
        thread.join(10)
        assert not thread.is_alive()
    finally:
        listener.close()


def test_ghdl_server_ddr(tmp_path: Path) -> None:
    """The GHDL engine's server of a DDR build (MEM_KIND_g "DDR"): its frames go through m_axi_feat
    into the job's AXI4 RAM (an emulated reserved region, HELLO's ddr) and the driver reads them
    over the socket (SocketMemory): three frames bit-exact, in stream order, the DMA counters
    clean; a read outside the region is refused with a message."""
    small = np.stack([rgb_to_luma(colour_photo(name, 64, 48)) for name in ("coffee", "rocket")])
    with SimServer(small, TINY.name, scales=1, mem_depth=64, mem_kind="ddr", job_dir=tmp_path / "job") as srv, \
            SocketBus(srv.address) as bus:  # fmt: skip
        assert bus.info["generics"]["MEM_KIND_g"] == "DDR" and bus.info["engine"] == "ghdl"
        base, size = bus.memory_region or (0, 0)
        assert (base, size) == (0x1000_0000, 4 << 20), bus.info["ddr"]
        memory = SocketMemory(bus)
        accel = OrbAccel(bus, memory=memory, ring_count=4)
        assert accel.ddr and accel.ring is not None and accel.ring.base == base
        accel.configure(threshold=20)
        got = list(accel.frames(3, timeout_s=0.01))
        with pytest.raises(ValueError, match="outside the simulated DDR region"):
            bus.read_mem(base + size, 64)
        dma = accel.dma_counters()
        assert dma["dma_dropped"] == 0 and dma["dma_bus_errors"] == 0 and dma["dma_beats"] > 0, dma
        assert memory.invalidations >= 2 * len(got)  # the record, then the features, of each frame
    hw = HwConfig(64, 48, 1, SECTORS, 64)
    selection = f"grid:{hw.default_budget()}:{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}"
    want = [expected_features(img, 1, 20, "orb", SECTORS, (2, 1), selection) for img in small]
    ks = []
    for f in got:
        diffs = [first_difference(f.features, w) for w in want]
        assert diffs.count(None) == 1, f"frame {f.number} equals no photograph: {diffs}"
        ks.append(diffs.index(None))
    assert [(k - ks[0]) % 2 for k in ks] == [0, 1, 0], f"photographs {ks} out of stream order"
    assert [f.number for f in got] == list(range(got[0].number, got[0].number + 3))


def test_cli_sim_zynq(frames: np.ndarray, tmp_path: Path) -> None:
    """`--sim` starts a simulator for the command: here the board's wrapper orb_accel_zynq (RBG
    video, active-low reset, s_axi_ctrl), from image files of two sizes resized by --sim-size."""
    _png(frames[:2], tmp_path)
    big = cv2.resize(cv2.imread(str(tmp_path / "1.png")), (2 * W, 2 * H), interpolation=cv2.INTER_NEAREST)
    cv2.imwrite(str(tmp_path / "1.png"), big)  # resized back to W x H (exactly: nearest) by --sim-size
    out = tmp_path / "csv"
    r = subprocess.run([*CLI, "board", "stream", "--sim", str(tmp_path / "0.png"), str(tmp_path / "1.png"),
                        "--sim-top", "orb_accel_zynq", "--sim-config", TINY.name, "--sim-size", f"{W}x{H}",
                        "--sim-mem-depth", "256",
                        "--frames", "2", "--csv", str(out)], capture_output=True, text=True, timeout=900)  # fmt: skip
    assert r.returncode == 0, r.stdout + r.stderr
    assert "starting the simulator (ghdl): orb_accel_zynq" in r.stdout
    second = cv2.cvtColor(cv2.resize(big, (W, H), interpolation=cv2.INTER_AREA), cv2.COLOR_BGR2RGB)
    shown = np.stack([frames[0], second])
    ks = [which_photo(shown, feats, 20) for _, feats in read_csv_dir(out)]
    assert sorted(ks) == [0, 1], ks
    bad = subprocess.run([*CLI, "board", "info", "--sim", str(tmp_path / "0.png"), str(tmp_path / "1.png"),
                          "--sim-size", "native"],
                         capture_output=True, text=True)  # fmt: skip
    assert bad.returncode == 2 and "not 128x96 as the first frame" in bad.stderr, bad.stderr


def test_cli_sim_fast_engine(frames: np.ndarray, tmp_path: Path) -> None:
    """`--sim-engine fast`: the same socket server on the synthesised netlist in Verilator
    (docs/fast-sim.md), driven by the same CLI: frames bit-exact, in stream order."""
    _png(frames, tmp_path)
    out = tmp_path / "csv"
    r = subprocess.run([*CLI, "board", "stream", "--sim", *(str(tmp_path / f"{k}.png") for k in range(3)),
                        "--sim-engine", "fast", "--sim-config", TINY.name, "--frames", "4", "--csv", str(out)],
                       capture_output=True, text=True, timeout=900)  # fmt: skip
    assert r.returncode == 0, r.stdout + r.stderr
    assert "starting the simulator (fast): orb_accel_top" in r.stdout
    rows = read_csv_dir(out)
    ks = [which_photo(frames, feats, 20) for _, feats in rows]
    assert len(ks) == 4 and all((b - a) % 3 == 1 for a, b in itertools.pairwise(ks)), ks
    assert [row["frame"] for row, _ in rows] == list(range(rows[0][0]["frame"], rows[0][0]["frame"] + 4))


class _Interrupted(Exception):
    pass


def test_client_wait_stops_on_a_signal_taken_by_another_thread() -> None:
    """A client waiting for a silent simulator (the ROS node in wait_irq) must stop at a signal
    even when the kernel hands it to another thread (rospy's): its recv waits in slices of
    SLICE_S, so the main thread runs the Python handler within a slice, not after op_timeout_s."""
    import signal
    import threading
    import time

    from orb_accel import socket_bus

    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(1)
    conns: list[socket.socket] = []

    def serve() -> None:  # answers HELLO, then reads the next request and never answers
        conn, _ = srv.accept()
        conns.append(conn)
        recv_exact(conn, REQUEST.size)
        hello = json.dumps({"magic": socket_bus.MAGIC, "protocol": socket_bus.PROTOCOL}).encode()
        conn.sendall(RESPONSE.pack(0, len(hello)) + hello)
        recv_exact(conn, REQUEST.size)

    def raise_interrupted(_sig: int, _frame: object) -> None:
        raise _Interrupted

    server = threading.Thread(target=serve, daemon=True)
    server.start()
    old = signal.signal(signal.SIGUSR1, raise_interrupted)
    try:
        with SocketBus(f"127.0.0.1:{srv.getsockname()[1]}", op_timeout_s=120.0) as bus:

            def signal_this_thread() -> None:  # the signal goes to a helper thread, as a process-directed one may
                time.sleep(0.5)
                signal.pthread_kill(threading.get_ident(), signal.SIGUSR1)

            helper = threading.Thread(target=signal_this_thread)
            t0 = time.monotonic()
            helper.start()
            with pytest.raises(_Interrupted):
                bus.wait_irq(1.0)
            waited = time.monotonic() - t0
            helper.join()
        assert waited < 30.0, f"the client slept {waited:.1f} s through the signal (op_timeout_s 120 s)"
    finally:
        signal.signal(signal.SIGUSR1, old)
        for c in conns:
            c.close()
        srv.close()
