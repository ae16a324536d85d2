# SPDX-License-Identifier: MIT
"""The board-to-host feature stream (docs/stream.md): orb_accel.stream's format, orb_accel.serve's
server and frame loop, orb_accel.remote's client, `orb-accel serve` and `orb-accel board stream
--remote`.

Without the simulator (frames made with the model's codec, as the driver decodes them):
- a frame goes through encode_frame / decode_frame bit for bit (orb, fast, empty, without
  parameters or counters), and the comparison used below catches a changed dtype;
- a client that never reads gets its frames dropped, the oldest first, and counted (each FRAME
  says how many before it; BYE gives the total), while a second client receives every frame and
  publish() goes on; a client that goes away in the middle of a frame is closed and the next is
  served; a client that speaks garbage, another version, no HELLO or one too many gets ERROR with
  the reason, and the server serves the next one; the client's errors (no server, another protocol,
  another version, a server gone mid-frame) and a timeout in the middle of a frame (kept, then
  completed).
Against the simulated accelerator (one fast-engine server for the module, test_socket_bus's
128x96 photographs): the frame loop of serve() with a fast client that receives every frame bit for
bit as the loop read it (and equal to the golden model's) and a slow one that receives the newest
and is told of every drop; the CLI end to end (`orb-accel serve --connect` with OpenCV, cocotb and
the simulator packages unimportable, `orb-accel board stream --remote --csv`, SIGTERM: BYE and exit
0).
"""

from __future__ import annotations

import itertools
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from golden_model.config import RECOMMENDED_COLS, RECOMMENDED_ROWS, RECOMMENDED_THRESHOLD_LO, named
from golden_model.featcodec import encode_eof, encode_feature, feature_slot, record_slot
from golden_model.featmem import SLOT_WORDS_USED, decode_features, decode_record
from golden_model.features import Features, first_difference
from golden_model.frameparams import FrameParams
from golden_model.luma import rgb_to_luma
from orb_accel import OrbAccel
from orb_accel.csvdir import read_csv_dir
from orb_accel.driver import COUNTERS, Frame, FrameSource, HwConfig
from orb_accel.remote import RemoteAccel
from orb_accel.serve import StreamServer, hello_info, serve
from orb_accel.socket_bus import SocketBus
from orb_accel.stream import (
    ARRAYS,
    BYE,
    ENVELOPE,
    ERROR,
    FRAME,
    FRAME_CLIENT,
    HELLO,
    MAGIC,
    NAME,
    VERSION,
    StreamClosed,
    StreamError,
    decode_frame,
    encode_frame,
    json_message,
)
from orb_sim.sim_server import SimServer
from orbtb.images import colour_photo
from orbtb.scoreboard import expected_features

TINY = named("test-tiny")
W, H, SCALES, SECTORS, DEPTH = TINY.width, TINY.height, TINY.scales, TINY.sectors, TINY.mem_depth
PHOTOS = ("astronaut", "coffee", "chelsea")
CLI = [sys.executable, "-m", "orb_tools.cli"]
HW = HwConfig(1280, 720, 4, 32, 2048, 5, 4)  # the synthetic frames' accelerator (board-720p's shape)
NAMES = [c.lower() for c in COUNTERS]
INFO = {"protocol": NAME, "version": VERSION, "hw": vars(HW), "counters": NAMES, "modes": ["orb", "fast"],
        "records_params": True, "frame_wait_s": 5.0, "source": "synthetic frames"}  # fmt: skip


# ---- helpers -------------------------------------------------------------------------------------
def synthetic(n: int, mode: str = "orb", seed: int = 1, params: bool = True, counters: bool = True) -> Frame:
    """A frame as OrbAccel.read_bank makes it: n random features encoded in slots, decoded by the
    driver's decoder, with a record and counters."""
    rng = np.random.default_rng(seed)
    words = np.zeros((n, SLOT_WORDS_USED), np.uint32)
    for s in range(n):
        scale = int(rng.integers(0, HW.scales))
        word = encode_feature(scale=scale, x=int(rng.integers(3, 400)), y=int(rng.integers(3, 300)),
                              score=int(rng.integers(1, 2000)), sector=int(rng.integers(0, HW.sectors)),
                              descriptor=rng.bytes(32), response=int(rng.integers(0, 64)),
                              low=int(rng.integers(0, 2)))  # fmt: skip
        words[s] = feature_slot(word)[:SLOT_WORDS_USED]
    p = FrameParams(int(rng.integers(0, 256)), 14, mode, "grid", max(n, 1), 8, 6)
    record = decode_record(record_slot(encode_eof(int(rng.integers(0, 1 << 16)), 3, p), n, 5))
    feats = decode_features(words, HW.sectors, descriptors=mode == "orb")
    feats.step = HW.step
    values = {name: int(rng.integers(0, 1 << 32)) for name in NAMES} if counters else {}
    return Frame(int(rng.integers(0, 2)), feats, record, mode, HW, values, record.params if params else None)


def assert_same(got: Frame, want: Frame) -> None:
    """Bit for bit: every field of the Frame, every array's dtype, shape and bytes."""
    for name in ("bank", "mode", "hw", "counters", "params", "record"):
        assert getattr(got, name) == getattr(want, name), f"{name}: {getattr(got, name)} != {getattr(want, name)}"
    g, w = got.features, want.features
    assert (g.sectors_total, g.step) == (w.sectors_total, w.step)
    assert type(g.step[0]) is type(w.step[0]) and type(got.counters) is type(want.counters)
    for name in ARRAYS:
        a, b = getattr(g, name), getattr(w, name)
        assert (a.dtype, a.shape) == (b.dtype, b.shape), f"{name}: {a.dtype} {a.shape} != {b.dtype} {b.shape}"
        assert a.tobytes() == b.tobytes(), f"{name} differs"


def wait_for(cond, what: str, timeout_s: float = 20.0) -> None:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout_s
    while not cond():
        assert time.monotonic() < deadline, f"waited {timeout_s} s for {what}"
        time.sleep(0.01)


class Raw:
    """A hand-driven client socket (what RemoteAccel does, step by step, or wrongly)."""

    def __init__(self, address: str, rcvbuf: int | None = None) -> None:
        host, port = address.rsplit(":", 1)
        self.sock = socket.socket()
        if rcvbuf is not None:  # before connect: the window is set then
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        self.sock.settimeout(30)
        self.sock.connect((host, int(port)))

    def read(self, n: int) -> bytes:
        buf = b""
        while len(buf) < n:
            chunk = self.sock.recv(n - len(buf))
            if not chunk:
                raise ConnectionError(f"closed after {len(buf)} of {n} bytes")
            buf += chunk
        return buf

    def message(self) -> tuple[int, bytes]:
        magic, version, kind, _, length = ENVELOPE.unpack(self.read(ENVELOPE.size))
        assert (magic, version) == (MAGIC, VERSION)
        return kind, self.read(length)

    def hello(self) -> dict:
        self.sock.sendall(json_message(HELLO, {"client": "raw"}))
        kind, payload = self.message()
        assert kind == HELLO, payload
        return json.loads(payload)

    def close(self) -> None:
        self.sock.close()


@pytest.fixture
def server() -> Iterator[StreamServer]:
    logs: list[str] = []
    s = StreamServer(INFO, "127.0.0.1:0", queue_depth=3, hello_timeout_s=1.0, log=logs.append).start()
    s.logs = logs  # type: ignore[attr-defined]
    yield s
    s.close()


# ---- the format ----------------------------------------------------------------------------------
def test_round_trip_is_bit_exact() -> None:
    cases = [synthetic(300), synthetic(50, "fast", seed=2), synthetic(0, seed=3),
             synthetic(20, seed=4, params=False, counters=False), synthetic(HW.capacity, seed=5)]  # fmt: skip
    for k, frame in enumerate(cases):
        body = encode_frame(frame, 1000 + k, 11, 12)
        got, meta = decode_frame(bytearray(body), HW, NAMES)
        assert_same(got, frame)
        assert (meta.seq, meta.t_ready_ns, meta.t_read_ns) == (1000 + k, 11, 12)
        assert got.x.flags.writeable and np.array_equal(got.x, frame.x)
        assert np.array_equal(got.angle, frame.angle, equal_nan=True)
    assert len(encode_frame(cases[0], 0, 0, 0)) > 81 * 300  # 6 int64 columns, a bool, 32 descriptor bytes
    # the comparison catches what Features.__eq__ does not: a dtype
    narrow = replace(cases[0], features=replace(cases[0].features, x=cases[0].features.x.astype(np.int32)))
    assert narrow.features == cases[0].features
    with pytest.raises(AssertionError, match="x: int32"):
        assert_same(decode_frame(bytearray(encode_frame(narrow, 0, 0, 0)), HW, NAMES)[0], cases[0])


def test_bad_bodies_are_refused() -> None:
    body = encode_frame(synthetic(10), 0, 0, 0)
    with pytest.raises(StreamError, match="shorter than its head"):
        decode_frame(body[:20], HW, NAMES)
    with pytest.raises(StreamError, match="does not fit the frame"):
        decode_frame(body[:-1], HW, NAMES)
    with pytest.raises(StreamError, match="7 counters; HELLO named 3"):
        decode_frame(body, HW, NAMES[:3])
    renamed = body.replace(b"response\0", b"respons3\0", 1)
    with pytest.raises(StreamError, match="'respons3', not 'response'"):
        decode_frame(renamed, HW, NAMES)


# ---- the server and the client, synthetic frames ------------------------------------------------
def test_slow_client_is_dropped_for_fast_client_gets_everything() -> None:
    """A client that never reads (a small receive buffer, the server's send buffer small) loses
    frames, the oldest first, each loss counted and reported; a client that reads gets every frame
    bit for bit; publish() never waits for either."""
    s = StreamServer(INFO, "127.0.0.1:0", queue_depth=3, sndbuf=8192, log=lambda _: None).start()
    try:
        slow = Raw(s.address, rcvbuf=4096)
        assert slow.hello()["seq"] == 0
        fast = RemoteAccel(s.address, name="fast")
        assert fast.info["queue_depth"] == 3 and fast.info["drop"] == "oldest" and fast.hw == HW
        wait_for(lambda: sum(c.connected for c in s.clients()) == 2, "two clients")
        frames = [synthetic(400, seed=k) for k in range(4)]  # ~32 KB each: a few fill the slow client's buffers
        n = 30
        for seq in range(n):
            assert s.publish(frames[seq % 4]) > 32_000
            got, meta = fast.receive(10.0)  # paced by the fast client, never by the slow one
            assert (meta.seq, meta.dropped) == (seq, 0)
            assert_same(got, frames[seq % 4])
        wait_for(lambda: s.clients()[0].dropped > 0, "drops for the slow client")
        closing = threading.Thread(target=s.close, args=("the test is done", 30.0))
        closing.start()
        # now the slow client reads: what was queued or in its buffers, then BYE with the total
        seqs, told = [], []
        while True:
            kind, payload = slow.message()
            if kind == BYE:
                bye = json.loads(payload)
                break
            assert kind == FRAME
            (dropped,) = FRAME_CLIENT.unpack_from(payload)
            frame, meta = decode_frame(bytearray(payload[FRAME_CLIENT.size :]), HW, NAMES)
            assert_same(frame, frames[meta.seq % 4])
            seqs.append(meta.seq)
            told.append(dropped)
        closing.join(30)
        assert bye["reason"] == "the test is done" and bye["sent"] == len(seqs)
        assert bye["dropped"] > 0 and len(seqs) + bye["dropped"] == n, (seqs, bye)
        assert seqs[-1] == n - 1 and seqs == sorted(seqs), "the newest frame is never dropped"
        # each FRAME says how many were dropped before it: the gaps in the sequence
        assert all(d == q - k for k, (q, d) in enumerate(zip(seqs, told, strict=True))), (seqs, told)
        with pytest.raises(StreamClosed, match="the test is done"):
            fast.next_frame(5.0)
        assert fast.dropped == 0 and s.clients()[0].dropped == bye["dropped"]
    finally:
        s.close()


def test_client_gone_in_the_middle_of_a_frame(server: StreamServer) -> None:
    gone = Raw(server.address)
    gone.hello()
    wait_for(lambda: server.clients() and server.clients()[0].connected, "the client")
    frame = synthetic(2000)
    server.publish(frame)
    gone.read(ENVELOPE.size + 1000)  # a part of the frame, then away
    gone.sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\1\0\0\0\0\0\0\0")  # a reset, as a crash
    gone.close()
    deadline = time.monotonic() + 20
    while server.clients()[0].connected and time.monotonic() < deadline:  # the frame loop goes on
        server.publish(frame)
        time.sleep(0.02)
    assert not server.clients()[0].connected
    assert "went away" in server.clients()[0].why, server.clients()[0]
    with RemoteAccel(server.address) as next_client:
        server.publish(frame)
        assert_same(next_client.next_frame(5.0), frame)


def test_protocol_errors_get_a_reason_and_the_server_goes_on(server: StreamServer) -> None:
    def refused(payload: bytes) -> str:
        raw = Raw(server.address)
        raw.sock.sendall(payload)
        kind, text = raw.message()
        raw.close()
        assert kind == ERROR
        return text.decode()

    assert "does not speak the orb-accel-stream protocol" in refused(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n" * 50)
    other = ENVELOPE.pack(MAGIC, VERSION + 1, HELLO, 0, 2) + b"{}"
    assert f"speaks orb-accel-stream version {VERSION + 1}; this side speaks version {VERSION}" in refused(other)
    assert "not HELLO" in refused(ENVELOPE.pack(MAGIC, VERSION, FRAME, 0, 0))
    assert "a HELLO of 1000000 bytes" in refused(ENVELOPE.pack(MAGIC, VERSION, HELLO, 0, 1_000_000))
    assert "not a UTF-8 JSON object" in refused(ENVELOPE.pack(MAGIC, VERSION, HELLO, 0, 3) + b"\xff\xfe{")
    silent = Raw(server.address)
    kind, text = silent.message()  # says nothing: answered after hello_timeout_s
    assert kind == ERROR and b"no HELLO within 1 s" in text
    silent.close()
    full = [RemoteAccel(server.address) for _ in range(server.max_clients)]
    with pytest.raises(StreamError, match=f"at most {server.max_clients} clients"):
        RemoteAccel(server.address)
    for c in full:
        c.close()
    # a client that goes while no frame comes is noticed all the same (its place is free again)
    wait_for(lambda: not any(c.connected for c in server.clients()), "the clients' departure")
    assert all(c.why == "closed the connection" for c in server.clients()[-server.max_clients - 1 : -1])
    talker = Raw(server.address)
    talker.hello()
    talker.sock.sendall(b"more")
    kind, text = talker.message()
    assert kind == ERROR and b"sent 4 byte(s) after its HELLO" in text
    frame = synthetic(5)
    with RemoteAccel(server.address) as good:  # served after all that
        wait_for(lambda: sum(c.connected for c in server.clients()) == 1, "the others' departure")
        server.publish(frame)
        assert_same(good.next_frame(5.0), frame)
    assert any("does not speak" in line for line in server.logs)  # type: ignore[attr-defined]
    with pytest.raises(OSError, match=f"cannot listen on {server.address}"):
        StreamServer(INFO, server.address)


def fake_server(script) -> str:  # type: ignore[no-untyped-def]
    """A listening socket whose one connection `script(conn)` answers, in a thread."""
    lst = socket.create_server(("127.0.0.1", 0))

    def run() -> None:
        conn, _ = lst.accept()
        with conn:
            script(conn)
        lst.close()

    threading.Thread(target=run, daemon=True).start()
    return f"127.0.0.1:{lst.getsockname()[1]}"


def read_hello(conn: socket.socket) -> None:
    _, _, _, _, length = ENVELOPE.unpack(conn.recv(ENVELOPE.size, socket.MSG_WAITALL))
    conn.recv(length, socket.MSG_WAITALL)


def test_client_errors() -> None:
    with pytest.raises(ConnectionError, match=r"no orb-accel serve at 127\.0\.0\.1:1"):
        RemoteAccel("127.0.0.1:1")
    with pytest.raises(ValueError, match="HOST:PORT"):
        RemoteAccel("board")
    addr = fake_server(lambda c: (read_hello(c), c.sendall(b"\x02\x15\0\0\0unknown operation 79")))
    with pytest.raises(StreamError, match=r"does not speak the orb-accel-stream protocol.*sim-server"):
        RemoteAccel(addr)
    addr = fake_server(lambda c: (read_hello(c), c.sendall(ENVELOPE.pack(MAGIC, 9, HELLO, 0, 0))))
    with pytest.raises(StreamError, match="speaks orb-accel-stream version 9"):
        RemoteAccel(addr)
    addr = fake_server(lambda c: (read_hello(c), c.sendall(json_message(HELLO, {**INFO, "version": 0}))))
    with pytest.raises(StreamError, match="not an orb-accel-stream server of version"):
        RemoteAccel(addr)
    addr = fake_server(lambda c: (read_hello(c), time.sleep(1.0)))
    with pytest.raises(StreamError, match=r"sent no HELLO within 0\.3 s"):
        RemoteAccel(addr, connect_timeout_s=0.3)

    # a frame in two halves: a timeout between them keeps the first half; the server then goes
    frame = synthetic(100)
    body = encode_frame(frame, 7, 1, 2)
    msg = ENVELOPE.pack(MAGIC, VERSION, FRAME, 0, FRAME_CLIENT.size + len(body)) + FRAME_CLIENT.pack(4) + body
    go_on, go_away = threading.Event(), threading.Event()

    def halves(conn: socket.socket) -> None:
        read_hello(conn)
        conn.sendall(json_message(HELLO, INFO) + msg[: len(msg) // 2])
        go_on.wait(10)
        conn.sendall(msg[len(msg) // 2 :] + msg[:100])
        go_away.wait(10)

    with RemoteAccel(fake_server(halves)) as accel:
        with pytest.raises(TimeoutError, match=r"no frame from .* within 0\.3 s"):
            accel.next_frame(0.3)
        go_on.set()
        got, meta = accel.receive(5.0)
        assert_same(got, frame)
        assert (meta.seq, meta.dropped) == (7, 4) and accel.dropped == 4
        go_away.set()
        with pytest.raises(ConnectionError, match="closed the connection in the middle of a message"):
            accel.next_frame(5.0)


def test_frame_source_interface() -> None:
    """OrbAccel and RemoteAccel both are FrameSources (what a consumer such as the ROS 2 node takes)."""
    for cls in (OrbAccel, RemoteAccel):
        for name in ("next_frame", "frames"):
            assert callable(getattr(cls, name)), f"{cls.__name__}.{name}"
    want = {n: p for n, p in FrameSource.__dict__.items() if n in ("next_frame", "frames")}
    import inspect

    for cls in (OrbAccel, RemoteAccel):
        for name, fn in want.items():
            assert list(inspect.signature(getattr(cls, name)).parameters) == list(inspect.signature(fn).parameters)


# ---- against the simulated accelerator ----------------------------------------------------------
@pytest.fixture(scope="module")
def photos() -> np.ndarray:
    return np.stack([colour_photo(name, W, H) for name in PHOTOS])


@pytest.fixture(scope="module")
def sim(photos: np.ndarray, tmp_path_factory: pytest.TempPathFactory) -> Iterator[SimServer]:
    with SimServer(photos, TINY.name, engine="fast", job_dir=tmp_path_factory.mktemp("sim-server")) as s:
        yield s


@pytest.fixture(scope="module")
def models(photos: np.ndarray) -> list[Features]:
    budget = HwConfig(W, H, SCALES, SECTORS, DEPTH).default_budget()
    selection = f"grid:{budget}:{RECOMMENDED_COLS}x{RECOMMENDED_ROWS}:{RECOMMENDED_THRESHOLD_LO}"
    return [expected_features(rgb_to_luma(p), SCALES, 20, "orb", SECTORS, (2, 1), selection) for p in photos]


def which_photo(models: list[Features], feats: Features) -> int:
    diffs = [first_difference(feats, m) for m in models]
    assert diffs.count(None) == 1, f"the frame equals no photograph's model features: {diffs}"
    return diffs.index(None)


def test_serve_from_the_simulator(sim: SimServer, models: list[Features]) -> None:
    """serve()'s frame loop over the simulator: a client that reads receives every frame bit for
    bit as the loop read it (each the model's features of a photograph, in stream order); a client
    that never reads gets the newest frames and is told of every one it lost."""
    n = 16
    with SocketBus(sim.address) as bus:
        accel = OrbAccel(bus)
        accel.configure(threshold=20)
        accel.settle(0.01)
        server = StreamServer(hello_info(accel, "the simulator", 60.0), "127.0.0.1:0", queue_depth=2, sndbuf=4096,
                              log=lambda _: None).start()  # fmt: skip
        try:
            slow = Raw(server.address, rcvbuf=4096)
            slow.hello()
            fast = RemoteAccel(server.address, name="fast")
            assert fast.hw == accel.hw and fast.info["source"] == "the simulator"
            wait_for(lambda: sum(c.connected for c in server.clients()) == 2, "two clients")
            got: dict[int, Frame] = {}
            local: dict[int, Frame] = {}

            def receive() -> None:
                for _ in range(n):
                    frame, meta = fast.receive(60.0)
                    got[meta.seq] = frame

            reader = threading.Thread(target=receive)
            reader.start()

            def keep(frame: Frame, seq: int) -> None:  # the loop goes on once the fast client has it
                local[seq] = frame
                wait_for(lambda: seq in got, f"frame {seq} at the fast client", 60.0)

            stats = serve(accel, server, timeout_s=0.01, count=n, on_frame=keep)
            reader.join(60)
            closing = threading.Thread(target=server.close, args=("done", 30.0))
            closing.start()
            seqs = []
            while (m := slow.message())[0] == FRAME:
                seqs.append(decode_frame(bytearray(m[1][FRAME_CLIENT.size :]), fast.hw, fast.counter_names)[1].seq)
            closing.join(30)
        finally:
            server.close()
    assert stats.frames == n and sorted(got) == list(range(n)) and fast.dropped == 0
    for seq in range(n):
        assert_same(got[seq], local[seq])
    ks = [which_photo(models, got[seq].features) for seq in range(n)]
    assert all((b - a) % len(PHOTOS) == 1 for a, b in itertools.pairwise(ks)), ks
    assert [got[s].number for s in range(n)] == list(range(got[0].number, got[0].number + n))
    bye = json.loads(m[1])
    assert m[0] == BYE and bye["dropped"] > 0 and len(seqs) + bye["dropped"] == n and seqs[-1] == n - 1, (seqs, bye)


BLOCKER = """
import importlib.abc, sys
class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.split(".")[0] in {"cv2", "cocotb", "cocotb_tools", "cocotbext", "skimage", "matplotlib", "scipy"}:
            raise ImportError(f"{name} is not on the board")
sys.meta_path.insert(0, Block())
"""


def test_cli_serve_and_board_stream_remote(sim: SimServer, models: list[Features], tmp_path: Path) -> None:
    """`orb-accel serve` (as on the board: no OpenCV, cocotb or simulator packages) and `orb-accel
    board stream --remote` end to end; SIGTERM stops the server cleanly (BYE, exit 0)."""
    code = BLOCKER + f"""
import sys
from orb_tools.cli import main
sys.exit(main(["serve", "--connect", "{sim.address}", "--listen", "127.0.0.1:0", "--threshold", "20"]))
"""  # fmt: skip
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=env)  # fmt: skip
    try:
        first = proc.stdout.readline()  # type: ignore[union-attr]
        assert "serving the frames of simulator" in first, first + proc.communicate(timeout=30)[0]
        address = first.split(" on ")[1].split(":", 2)
        address = f"{address[0]}:{address[1]}"
        out = tmp_path / "csv"
        r = subprocess.run([*CLI, "board", "stream", "--remote", address, "--frames", "3", "--csv", str(out)],
                           capture_output=True, text=True, timeout=120)  # fmt: skip
        assert r.returncode == 0, r.stdout + r.stderr
        assert "3 frames in" in r.stdout and "0 frame(s) dropped by the server" in r.stdout
        rows = read_csv_dir(out)
        assert len(rows) == 3 and all(row["threshold"] == 20 for row, _ in rows)
        for _, feats in rows:
            which_photo(models, feats)
        bad = subprocess.run([*CLI, "board", "stream", "--remote", address, "--threshold", "30"],
                             capture_output=True, text=True)  # fmt: skip
        assert bad.returncode == 2 and "the server sets the accelerator's parameters" in bad.stderr, bad.stderr
        with RemoteAccel(address) as accel:
            accel.next_frame(30.0)
            proc.send_signal(signal.SIGTERM)
            with pytest.raises(StreamClosed, match=r"stopped \(Ctrl-C or SIGTERM\)"):
                for _ in range(20):
                    accel.next_frame(30.0)
        rest, _ = proc.communicate(timeout=30)
        assert proc.returncode == 0, first + rest
        assert "stopped: the server was stopped (Ctrl-C or SIGTERM)" in rest and "orb-accel board stream" in rest
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    # the simulator's bus is no stream: a clear error
    wrong = subprocess.run([*CLI, "board", "stream", "--remote", sim.address], capture_output=True, text=True,
                           timeout=60)  # fmt: skip
    assert wrong.returncode == 2 and "does not speak the orb-accel-stream protocol" in wrong.stderr, wrong.stderr
