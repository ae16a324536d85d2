# SPDX-License-Identifier: MIT
"""`orb-accel serve`'s server: every frame the driver reads goes to the connected clients over TCP
in the stream format of orb_accel.stream (docs/stream.md). numpy and the standard library only: it
runs on the board's Debian with the system Python.

    server = StreamServer(hello_info(accel, "UIO device 'orb-accel'", 2.0), "0.0.0.0:5556").start()
    try:
        serve(accel, server, timeout_s=1.0)          # until Ctrl-C / SIGTERM (KeyboardInterrupt)
    finally:
        server.close("the server stopped")           # BYE to every client

The frame loop (serve) reads each frame once and releases its bank at once, encodes it once into
one immutable bytes object and offers it to every client; it never waits for a client. Each client
has a thread of its own and a queue of at most `queue_depth` frames: when the queue is full the
oldest queued frame is dropped for the newest, and counted for that client (the next FRAME it gets
says so). A frame a client's thread has begun to send is never cut. A client that takes no byte
for `send_timeout_s`, or goes away, is closed; a peer that does not open with a HELLO of this
protocol and version within `hello_timeout_s` is answered ERROR and closed. Nothing a client does
reaches the frame loop.
"""

from __future__ import annotations

import collections
import select
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from golden_model.config import MODES

from .bus import BusError
from .driver import COUNTERS, Frame, OrbAccel
from .stream import (
    BYE,
    DEFAULT_PORT,
    ENVELOPE,
    ERROR,
    FRAME,
    FRAME_CLIENT,
    HELLO,
    MAX_HELLO,
    NAME,
    VERSION,
    StreamError,
    check_envelope,
    encode_frame,
    envelope,
    json_message,
    message,
    parse_address,
    parse_json,
)

DEFAULT_QUEUE = 4  # frames queued per client before the oldest is dropped
DEFAULT_MAX_CLIENTS = 8
SLICE_S = 0.2  # the accept loop's and the shutdown's polling slice

Log = Callable[[str], None]


def hello_info(accel: OrbAccel, source: str, frame_wait_s: float) -> dict[str, Any]:
    """HELLO's fixed part for the frames of `accel` (orb_accel.stream.HELLO_KEYS)."""
    hw = accel.hw
    return {
        "protocol": NAME, "version": VERSION,
        "hw": {"width": hw.width, "height": hw.height, "scales": hw.scales, "sectors": hw.sectors,
               "mem_depth": hw.mem_depth, "step_num": hw.step_num, "step_den": hw.step_den},
        "register_map": list(accel.version()), "records_params": accel.records_params, "modes": list(MODES),
        "counters": [c.lower() for c in COUNTERS], "frame_wait_s": frame_wait_s, "source": source,
    }  # fmt: skip


def recv_exact(sock: socket.socket, n: int, deadline: float) -> bytes:
    """Exactly n bytes before `deadline` (time.monotonic()): TimeoutError after it, however the
    bytes trickle in; ConnectionError when the peer closes first."""
    buf = bytearray()
    while len(buf) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            raise TimeoutError
        sock.settimeout(left)
        chunk = sock.recv(n - len(buf))
        if not chunk:
            raise ConnectionError(f"closed after {len(buf)} of {n} bytes")
        buf += chunk
    return bytes(buf)


def send_parts(sock: socket.socket, parts: list[bytes]) -> None:
    """All of `parts`, in as few system calls as the socket takes (sendmsg)."""
    views = [memoryview(p) for p in parts if len(p)]
    while views:
        sent = sock.sendmsg(views)
        while sent:
            if sent >= len(views[0]):
                sent -= len(views.pop(0))
            else:
                views[0], sent = views[0][sent:], 0


@dataclass
class ClientStats:
    """One client as the server counts it."""

    number: int
    peer: str
    name: str = ""
    sent: int = 0  # frames sent whole
    dropped: int = 0  # frames dropped for it (its queue full)
    connected: bool = True
    why: str = ""  # why it was closed


@dataclass
class _Client:
    stats: ClientStats
    conn: socket.socket
    queue: collections.deque[bytes] = field(default_factory=collections.deque)  # FRAME bodies
    cond: threading.Condition = field(default_factory=threading.Condition)
    thread: threading.Thread | None = None
    active: bool = False  # past the handshake: frames are offered to it
    bye: str | None = None  # set at shutdown: BYE with this reason once the queue is sent


class StreamServer:
    """The stream's TCP server: `info` (hello_info) goes into every HELLO; publish() hands each
    frame to the clients. address "HOST:PORT" (port 0: any free one; `address` tells which)."""

    def __init__(self, info: dict[str, Any], address: str = f"0.0.0.0:{DEFAULT_PORT}",
                 queue_depth: int = DEFAULT_QUEUE, max_clients: int = DEFAULT_MAX_CLIENTS,
                 hello_timeout_s: float = 5.0, send_timeout_s: float = 30.0, sndbuf: int | None = None,
                 log: Log | None = None) -> None:  # fmt: skip
        if queue_depth < 1:
            raise ValueError(f"queue depth {queue_depth} must be 1 or more")
        if max_clients < 1:
            raise ValueError(f"max clients {max_clients} must be 1 or more")
        self.info = {**info, "queue_depth": queue_depth, "drop": "oldest"}
        self.queue_depth, self.max_clients = queue_depth, max_clients
        self.hello_timeout_s, self.send_timeout_s, self.sndbuf = hello_timeout_s, send_timeout_s, sndbuf
        self.log: Log = log or (lambda line: print(line, flush=True))
        host, port = parse_address(address, "0.0.0.0")
        try:
            self._listen = socket.create_server((host, port))
        except OSError as exc:
            raise OSError(exc.errno, f"cannot listen on {host}:{port} ({exc.strerror or exc})") from None
        self._listen.settimeout(SLICE_S)
        bound = self._listen.getsockname()
        self.address = f"{bound[0]}:{bound[1]}"
        self.seq = 0  # the next frame's sequence number
        self.bytes_encoded = 0
        self._lock = threading.Lock()
        self._clients: list[_Client] = []
        self._all: list[ClientStats] = []
        self._closing = threading.Event()
        self._accept_thread = threading.Thread(target=self._accept_loop, name="orb-stream-accept", daemon=True)

    # ---- lifecycle -------------------------------------------------------------------------------
    def start(self) -> StreamServer:
        self._accept_thread.start()
        return self

    def __enter__(self) -> StreamServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close("the server stopped")

    def close(self, reason: str = "the server stopped", timeout_s: float = 2.0) -> None:
        """BYE (with `reason`) to every client after the frames queued for it, then close; a client
        that does not take them within `timeout_s` is cut. Idempotent."""
        if self._closing.is_set():
            return
        with self._lock:  # the handshake's lock: a client is in this list, or refused as the server stops
            self._closing.set()
            clients = list(self._clients)
        for c in clients:
            with c.cond:
                c.bye = reason
                c.cond.notify()
        deadline = time.monotonic() + timeout_s
        for c in clients:
            if c.thread is not None:
                c.thread.join(max(0.0, deadline - time.monotonic()))
        for c in clients:  # still sending to a client that takes nothing: cut it
            if c.thread is not None and c.thread.is_alive():
                try:
                    c.conn.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass
                c.thread.join(timeout_s)
        if self._accept_thread.is_alive():
            self._accept_thread.join(timeout_s)
        self._listen.close()

    # ---- the frame loop's side -------------------------------------------------------------------
    def publish(self, frame: Frame, t_ready_ns: int | None = None, t_read_ns: int | None = None) -> int:
        """Offer `frame` to every client (never blocks on one); returns the bytes of its FRAME
        body (0: no client, nothing encoded). Takes the next sequence number either way."""
        with self._lock:  # with the handshake's lock: a client's first frame is the one its HELLO names
            seq, self.seq = self.seq, self.seq + 1
            clients = [c for c in self._clients if c.active]
        if not clients or self._closing.is_set():
            return 0
        now = time.time_ns()
        body = encode_frame(frame, seq, t_ready_ns or now, t_read_ns or now)
        self.bytes_encoded += len(body)
        for c in clients:
            with c.cond:
                if len(c.queue) >= self.queue_depth:
                    c.queue.popleft()  # the oldest queued frame goes (one being sent is no longer queued)
                    c.stats.dropped += 1
                c.queue.append(body)
                c.cond.notify()
        return len(body)

    def clients(self) -> list[ClientStats]:
        """Every client since the start (connected or not), in connection order."""
        with self._lock:
            return list(self._all)

    # ---- the clients' side -----------------------------------------------------------------------
    def _accept_loop(self) -> None:
        number = 0
        while not self._closing.is_set():
            try:
                conn, peer = self._listen.accept()
            except TimeoutError:
                continue
            except OSError as exc:
                if not self._closing.is_set():
                    self.log(f"stream: accept failed: {exc}")
                continue
            number += 1
            stats = ClientStats(number, f"{peer[0]}:{peer[1]}")
            client = _Client(stats, conn)
            client.thread = threading.Thread(target=self._serve_client, args=(client,), daemon=True,
                                             name=f"orb-stream-client-{number}")  # fmt: skip
            with self._lock:
                self._all.append(stats)
                self._clients.append(client)
            client.thread.start()

    def _refuse(self, conn: socket.socket, text: str) -> None:
        try:
            conn.sendall(message(ERROR, text.encode()))
        except OSError:
            pass
        _linger(conn)

    def _handshake(self, c: _Client) -> bool:
        conn, who = c.conn, f"client {c.stats.number} ({c.stats.peer})"
        deadline = time.monotonic() + self.hello_timeout_s
        try:
            kind, length = check_envelope(recv_exact(conn, ENVELOPE.size, deadline), who)
            if kind != HELLO:
                raise StreamError(f"{who} opened with message type {kind}, not HELLO ({HELLO})")
            if length > MAX_HELLO:
                raise StreamError(f"{who}: a HELLO of {length} bytes (at most {MAX_HELLO})")
            hello = parse_json(recv_exact(conn, length, deadline), f"{who}'s HELLO")
        except StreamError as exc:
            self._refuse(conn, str(exc))
            c.stats.why = str(exc)
            return False
        except TimeoutError:
            c.stats.why = f"no HELLO within {self.hello_timeout_s:g} s"
            self._refuse(conn, f"{who}: {c.stats.why}")
            return False
        c.stats.name = str(hello.get("client", ""))[:80]
        refusal = ""
        with self._lock:  # never held across a send: publish() takes it
            active = sum(1 for k in self._clients if k.active)
            if self._closing.is_set():  # close() has taken its list of clients: this one would get no BYE
                refusal = "the server is stopping"
            elif active >= self.max_clients:
                refusal = f"this server serves at most {self.max_clients} clients at once"
            else:
                # registered under the lock, with the HELLO's "seq", so that the first frame it is
                # offered is the frame HELLO names
                info = {**self.info, "client": c.stats.number, "seq": self.seq}
                c.active = True
        if refusal:
            c.stats.why = f"refused: {refusal}"
            self._refuse(conn, refusal)
            return False
        conn.settimeout(self.send_timeout_s)
        if self.sndbuf is not None:
            conn.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, self.sndbuf)
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        conn.sendall(json_message(HELLO, info))
        return True

    def _serve_client(self, c: _Client) -> None:
        s = c.stats
        try:
            if not self._handshake(c):
                self.log(f"stream: client {s.number} ({s.peer}) closed: {s.why}")
                return
            self.log(f"stream: client {s.number} ({s.peer}, {s.name or 'unnamed'}) connected")
            while True:
                with c.cond:
                    if not c.queue and c.bye is None:
                        c.cond.wait(SLICE_S)
                    body = c.queue.popleft() if c.queue else None
                    bye, dropped = c.bye, s.dropped
                if body is None and bye is not None:
                    s.why = bye
                    c.conn.sendall(json_message(BYE, {"reason": bye, "sent": s.sent, "dropped": dropped}))
                    _linger(c.conn)
                    return
                if body is None:  # idle: has the client gone, or spoken out of turn?
                    if select.select([c.conn], [], [], 0)[0]:
                        data = c.conn.recv(1 << 12)
                        s.why = "closed the connection" if not data else f"sent {len(data)} byte(s) after its HELLO"
                        if data:
                            self._refuse(c.conn, f"client {s.number}: {s.why} (a client sends nothing after HELLO)")
                        return
                    continue
                send_parts(c.conn, [envelope(FRAME, FRAME_CLIENT.size + len(body)), FRAME_CLIENT.pack(dropped), body])
                s.sent += 1
        except TimeoutError:
            s.why = f"took no byte for {self.send_timeout_s:g} s (too slow, or gone without closing)"
        except OSError as exc:
            s.why = f"went away ({exc.strerror or exc})"
        finally:
            with self._lock:
                c.active = False
                if c in self._clients:
                    self._clients.remove(c)
            s.connected = False
            try:
                c.conn.close()
            except OSError:
                pass
            if s.sent or s.dropped or s.name:
                self.log(f"stream: client {s.number} ({s.peer}) closed after {s.sent} frame(s), "
                         f"{s.dropped} dropped: {s.why}")  # fmt: skip


def _linger(conn: socket.socket, timeout_s: float = 0.5) -> None:
    """Before a close after a last message: end our side and read what the peer still sends (a
    close with unread input sends a reset, which can discard the message before the peer reads it)."""
    try:
        conn.shutdown(socket.SHUT_WR)
        conn.settimeout(timeout_s)
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline and conn.recv(1 << 16):
            pass
    except OSError:
        pass


@dataclass
class ServeStats:
    frames: int = 0  # frames read and published
    timeouts: int = 0  # waits that ended without a frame
    bus_errors: int = 0  # frames lost to an error response (the driver recovers)


def serve(accel: OrbAccel, server: StreamServer, timeout_s: float, count: int | None = None,
          on_frame: Callable[[Frame, int], None] | None = None, log: Log | None = None) -> ServeStats:  # fmt: skip
    """The frame loop: `count` frames (None: until KeyboardInterrupt), each read once, its bank
    released at once, then published; `on_frame(frame, seq)` after each. A wait without a frame
    (TimeoutError) and an error response (BusError) are logged, counted and waited past: the
    driver recovers (docs/driver.md, "Faults and recovery")."""
    log = log or server.log
    stats = ServeStats()
    quiet = 0  # timeouts in a row
    while count is None or stats.frames < count:
        try:
            bank = accel.wait_frame(timeout_s)
            t_ready = time.time_ns()
            with accel.holding(bank):
                frame = accel.read_bank(bank)
            t_read = time.time_ns()
        except TimeoutError as exc:
            stats.timeouts += 1
            quiet += 1
            if quiet == 1:
                log(f"stream: no frame: {exc}")
            continue
        except BusError as exc:
            stats.bus_errors += 1
            log(f"stream: a frame lost to a bus error: {exc}")
            continue
        if quiet:
            log(f"stream: frames again after {quiet} timeout(s)")
            quiet = 0
        seq = server.seq
        server.publish(frame, t_ready, t_read)
        stats.frames += 1
        if on_frame is not None:
            on_frame(frame, seq)
    return stats
