# SPDX-License-Identifier: MIT
"""A client of `orb-accel serve` (docs/stream.md): the driver's Frame objects from an accelerator
on another machine, through the same calls as a local OrbAccel (orb_accel.driver.FrameSource):

    with RemoteAccel("board.local:5556") as accel:
        print(accel.hw)                              # the accelerator's HwConfig, from the HELLO
        for frame in accel.frames(None, timeout_s=accel.frame_wait_s):
            print(frame.number, len(frame), frame.descriptors.shape, accel.last.dropped)

Each Frame is bit for bit the one the server's driver read (the same arrays, dtypes, record,
parameters, counters and configuration). `last` (a FrameMeta) is what the stream says beside it:
the server's sequence number and timestamps, and the frames the server dropped for this client
(its queue full: a client that reads slower than the frames come loses the oldest; `dropped` counts
them). Timeouts are wall seconds. Errors: TimeoutError (no frame within the timeout; the stream
stays usable, a message half received is kept), StreamError (a ConnectionError: the other side is
no stream server of this version, refused, or broke the protocol), StreamClosed (the server ended
the stream), ConnectionError (the connection went). numpy and the standard library only.
"""

from __future__ import annotations

import os
import socket
import time
from collections.abc import Iterator
from types import TracebackType
from typing import Any

from .driver import Frame
from .stream import (
    BYE,
    ENVELOPE,
    ERROR,
    FRAME,
    FRAME_CLIENT,
    HELLO,
    MAX_HELLO,
    MAX_MESSAGE,
    NAME,
    TYPES,
    VERSION,
    FrameMeta,
    StreamClosed,
    StreamError,
    check_envelope,
    decode_frame,
    hw_config,
    json_message,
    parse_address,
    parse_json,
)

SLICE_S = 0.2  # the longest a recv sleeps before Python runs again (signals, Ctrl-C)
HINT = " (a simulator's bus, `orb-accel sim-server`, is no stream: drivers reach it with --connect)"


class RemoteAccel:
    """The frames of an `orb-accel serve` at `address` ("HOST:PORT"); `name` is sent in the HELLO
    (the server's log shows it)."""

    def __init__(self, address: str, connect_timeout_s: float = 10.0, name: str = "orb_accel.remote") -> None:
        self.address = address
        host, port = parse_address(address)
        self.received = 0  # frames received
        self.bytes_received = 0
        self.last: FrameMeta | None = None
        self._closed: StreamClosed | None = None
        try:
            self._sock = socket.create_connection((host, port), timeout=connect_timeout_s)
        except OSError as exc:
            raise ConnectionError(f"no orb-accel serve at {host}:{port} ({exc}); start one on the board with "
                                  "`orb-accel serve`") from None  # fmt: skip
        self._sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._head = bytearray(ENVELOPE.size)
        self._payload: bytearray | None = None  # the message being received
        self._kind = 0  # its type
        self._got = 0  # its bytes so far (head, then payload)
        try:
            self._sock.sendall(json_message(HELLO, {"client": name, "pid": os.getpid()}))
            kind, payload = self._message(time.monotonic() + connect_timeout_s, MAX_HELLO)
        except TimeoutError:
            self.close()
            why = f"{address} sent no HELLO within {connect_timeout_s:g} s: not an orb-accel serve"
            raise StreamError(why + HINT) from None
        except StreamError as exc:
            self.close()
            raise StreamError(f"{exc}{HINT}") from None
        except BaseException:
            self.close()
            raise
        if kind != HELLO:
            self.close()
            if kind == ERROR:
                raise StreamError(f"{address} refused: {payload.decode(errors='replace')}")
            raise StreamError(f"{address} answered {TYPES[kind]}, not HELLO")
        self.info: dict[str, Any] = parse_json(bytes(payload), f"{address}'s HELLO")
        if self.info.get("protocol") != NAME or self.info.get("version") != VERSION:
            self.close()
            raise StreamError(f"{address} is not an {NAME} server of version {VERSION}: {self.info}")
        self.hw = hw_config(self.info)
        self.counter_names: list[str] = [str(c) for c in self.info.get("counters", [])]
        self.modes: list[str] = [str(m) for m in self.info.get("modes", [])]
        self.frame_wait_s = float(self.info.get("frame_wait_s", 2.0))

    # ---- messages --------------------------------------------------------------------------------
    def _fill(self, buf: bytearray, deadline: float) -> None:
        view = memoryview(buf)
        while self._got < len(buf):
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError
            self._sock.settimeout(min(SLICE_S, left))
            try:
                n = self._sock.recv_into(view[self._got :])
            except TimeoutError:
                continue
            except OSError as exc:
                raise ConnectionError(f"the connection to {self.address} went ({exc})") from None
            if n == 0:
                where = "in the middle of a message" if self._got or self._payload is not None else "between messages"
                raise ConnectionError(f"{self.address} closed the connection {where}")
            self._got += n
            self.bytes_received += n

    def _message(self, deadline: float, limit: int = MAX_MESSAGE) -> tuple[int, bytearray]:
        """The next whole message (type, payload); TimeoutError at the deadline (what came of a
        message is kept for the next call)."""
        if self._payload is None:
            self._fill(self._head, deadline)
            kind, length = check_envelope(bytes(self._head), self.address)
            if length > limit:
                raise StreamError(f"{self.address} announced a {TYPES[kind]} of {length} bytes (at most {limit})")
            self._kind, self._payload, self._got = kind, bytearray(length), 0
        self._fill(self._payload, deadline)
        kind, payload = self._kind, self._payload
        self._payload, self._got = None, 0
        return kind, payload

    # ---- frames ----------------------------------------------------------------------------------
    def receive(self, timeout_s: float) -> tuple[Frame, FrameMeta]:
        """The next frame and what the stream says beside it. Raises TimeoutError when none comes
        within timeout_s (wall seconds), StreamClosed after the server's BYE."""
        if self._closed is not None:
            raise self._closed
        deadline = time.monotonic() + timeout_s
        while True:
            try:
                kind, payload = self._message(deadline)
            except TimeoutError:
                raise TimeoutError(f"no frame from {self.address} within {timeout_s:g} s") from None
            if kind == FRAME:
                break
            if kind == BYE:
                bye = parse_json(bytes(payload), f"{self.address}'s BYE")
                self._closed = StreamClosed(str(bye.get("reason", "")), int(bye.get("dropped", 0)),
                                            int(bye.get("sent", 0)))  # fmt: skip
                raise self._closed
            if kind == ERROR:
                raise StreamError(f"{self.address}: {payload.decode(errors='replace')}")
            raise StreamError(f"{self.address} sent {TYPES[kind]} in the middle of the stream")
        if len(payload) < FRAME_CLIENT.size:
            raise StreamError(f"{self.address} sent a FRAME of {len(payload)} bytes")
        (dropped,) = FRAME_CLIENT.unpack_from(payload)
        frame, meta = decode_frame(memoryview(payload)[FRAME_CLIENT.size :], self.hw, self.counter_names,
                                   self.modes)  # fmt: skip
        meta = FrameMeta(meta.seq, meta.t_ready_ns, meta.t_read_ns, dropped)
        self.received += 1
        self.last = meta
        return frame, meta

    def next_frame(self, timeout_s: float) -> Frame:
        """The next frame (as OrbAccel.next_frame)."""
        return self.receive(timeout_s)[0]

    def frames(self, count: int | None, timeout_s: float) -> Iterator[Frame]:
        """`count` frames (None: on and on), as OrbAccel.frames; StreamClosed when the server
        ends the stream."""
        n = 0
        while count is None or n < count:
            yield self.next_frame(timeout_s)
            n += 1

    @property
    def dropped(self) -> int:
        """The frames the server dropped for this client, as of the last frame (or its BYE)."""
        if self._closed is not None:
            return self._closed.dropped
        return self.last.dropped if self.last is not None else 0

    def close(self) -> None:
        self._sock.close()

    def __enter__(self) -> RemoteAccel:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.close()
