# SPDX-License-Identifier: MIT
"""The board-to-host feature stream's wire format (docs/stream.md; this module defines it once:
orb_accel.serve sends it, orb_accel.remote reads it, orb_flow.gen.stream writes its tables into
docs/stream-format.md). numpy and the standard library only.

One TCP connection per client, little-endian. Every message, in either direction, is an ENVELOPE
(magic b"ORBS", the protocol VERSION, the message type, a reserved 0, the payload's length) and its
payload:

- the client opens with HELLO (a UTF-8 JSON object: who it is); the server answers HELLO (JSON:
  the protocol, the accelerator's configuration the driver's Frame needs, the counters' names, the
  queue and drop policy; HELLO_KEYS) or ERROR (UTF-8 text: why it refuses) and closes;
- then the server sends one FRAME per frame the client is given, and BYE (JSON: why it stops, the
  client's totals) before it closes; the client sends nothing more.

A FRAME's payload is the client's own part (FRAME_CLIENT: the frames dropped for this client so
far, counted by the server) and the frame's body, which is the same bytes for every client: the
head (FRAME_HEAD: sequence number, timestamps, bank, mode, the end-of-frame record with the frame's
parameters, the feature count), the counters (u32 each, HELLO's `counters` order), the array table
(ARRAY_ENTRY per array: name, numpy dtype string, shape) and the arrays' bytes as they are in the
driver's memory (C order, little-endian), each starting at a multiple of ALIGN bytes from the
body's start. encode_frame() and decode_frame() turn a driver Frame into a body and back, bit for
bit (the same dtypes, shapes and values).

Versioning: VERSION changes with any change of a message's layout; both sides speak exactly one
version and refuse another with ERROR / StreamError naming both. HELLO's JSON may gain keys within
a version (a reader ignores the ones it does not know).
"""

from __future__ import annotations

import json
import struct
from dataclasses import dataclass
from typing import Any

import numpy as np

from golden_model.config import MODES
from golden_model.featcodec import EndOfFrame
from golden_model.features import Features
from golden_model.frameparams import FrameParams

from .driver import COUNTERS, Frame, HwConfig

MAGIC = b"ORBS"
VERSION = 1
DEFAULT_PORT = 5556
NAME = "orb-accel-stream"  # HELLO's "protocol"

# message types
HELLO, FRAME, BYE, ERROR = 1, 2, 3, 4
TYPES = {HELLO: "HELLO", FRAME: "FRAME", BYE: "BYE", ERROR: "ERROR"}

NAME_BYTES = 12  # an array's name in the array table
ALIGN = 8  # every array starts at a multiple of this many bytes from the body's start
MAX_HELLO = 1 << 16  # the longest HELLO a side accepts
MAX_MESSAGE = 1 << 28  # the longest message a client accepts (a 4095-feature frame is ~0.3 MB)


def _struct(fields: tuple[tuple[str, str, str], ...]) -> struct.Struct:
    return struct.Struct("<" + "".join(code for _, code, _ in fields))


# (name, struct code, meaning): the documented layouts (docs/stream-format.md is generated from these)
ENVELOPE_FIELDS = (
    ("magic", "4s", 'b"ORBS"'),
    ("version", "B", "the protocol version (VERSION)"),
    ("type", "B", "1 HELLO, 2 FRAME, 3 BYE, 4 ERROR"),
    ("reserved", "H", "0"),
    ("length", "I", "bytes of payload after the envelope"),
)
FRAME_CLIENT_FIELDS = (
    ("dropped", "Q", "frames the server dropped for this client since it connected, before this one"),
)
FRAME_HEAD_FIELDS = (
    ("seq", "Q", "the server's frame sequence number: frames read since it started, from 0"),
    ("t_ready_ns", "Q", "wall clock (CLOCK_REALTIME, ns) when the driver had the frame (its interrupt taken)"),
    ("t_read_ns", "Q", "wall clock (ns) when the frame's bank was read and released"),
    ("bank", "B", "the bank the frame was read from (Frame.bank)"),
    ("mode", "B", "the mode the frame was decoded in: index in HELLO's `modes` (Frame.mode)"),
    ("flags", "B", "bit 0: the record's parameters are the frame's (Frame.params not None); bit 1: counters read"),
    ("n_counters", "B", "counters that follow the head (0 or HELLO's `counters` length)"),
    ("count", "I", "the end-of-frame record (Frame.record): features stored"),
    ("frame", "H", "record.frame: the accelerator's frame number (16 bits, wraps)"),
    ("dropped", "H", "record.dropped: features lost before the feature memory"),
    ("truncated", "I", "record.truncated: features not stored, the bank full"),
    ("truncated_flag", "B", "record.truncated_flag"),
    ("threshold", "B", "record.params.threshold"),
    ("threshold_lo", "B", "record.params.threshold_lo"),
    ("mode_orb", "B", "record.params.mode: 1 orb, 0 fast"),
    ("select_grid", "B", "record.params.selection: 1 grid, 0 all"),
    ("cols", "B", "record.params.cols"),
    ("rows", "B", "record.params.rows"),
    ("budget", "H", "record.params.budget"),
    ("n_features", "I", "features in the arrays (len(Frame))"),
    ("sectors_total", "B", "Features.sectors_total (sector to angle)"),
    ("step_num", "B", "Features.step numerator (the pyramid step the coordinates convert with)"),
    ("step_den", "B", "Features.step denominator"),
    ("n_arrays", "B", "entries of the array table"),
    ("reserved", "7s", "0"),
)
ARRAY_FIELDS = (
    ("name", f"{NAME_BYTES}s", "the Features field, ASCII, NUL-padded"),
    ("dtype", "4s", "numpy dtype string, ASCII, NUL-padded: <i8, |u1, |b1"),
    ("ndim", "B", "1 or 2"),
    ("reserved", "3s", "0"),
    ("dim0", "I", "rows (the feature count)"),
    ("dim1", "I", "columns (2-D arrays; 0 otherwise)"),
    ("offset", "I", "the array's first byte, from the body's start (a multiple of ALIGN)"),
)
ENVELOPE = _struct(ENVELOPE_FIELDS)
FRAME_CLIENT = _struct(FRAME_CLIENT_FIELDS)
FRAME_HEAD = _struct(FRAME_HEAD_FIELDS)
ARRAY_ENTRY = _struct(ARRAY_FIELDS)
COUNTER = struct.Struct("<I")

# the arrays of a frame, in this order: Features' columns (golden_model.features), as the driver decodes them
ARRAYS = ("scale", "x", "y", "score", "sector", "response", "low", "descriptor")
FLAG_PARAMS, FLAG_COUNTERS = 1, 2
assert all(len(a) <= NAME_BYTES for a in ARRAYS), "an array name longer than NAME_BYTES"

# HELLO's keys (server -> client), each with its meaning; the server may add more
HELLO_KEYS = {
    "protocol": f'"{NAME}"',
    "version": "VERSION",
    "hw": "the accelerator's configuration: HwConfig's fields (width, height, scales, sectors, mem_depth, step_num, "
    "step_den)",
    "register_map": "[major, minor] of the VERSION register",
    "records_params": "whether the accelerator's records carry the frame's parameters (register map 3.1 on)",
    "modes": 'the mode names FRAME_HEAD.mode indexes (["orb", "fast"])',
    "counters": "the counters' names (Frame.counters' keys), in the order FRAME carries them",
    "queue_depth": "frames the server queues for a client before it drops",
    "drop": '"oldest": a full queue drops its oldest frame for the newest',
    "frame_wait_s": "how long a client should wait for a frame, wall seconds (the server's suggestion)",
    "source": "what the server reads (the board through UIO, a simulator, ...)",
    "client": "this connection's number at the server, from 1",
    "seq": "the sequence number of the next frame the server reads",
}


class StreamError(ConnectionError):
    """The other side does not speak this protocol, refused, or broke it; the message says how."""


class StreamClosed(StreamError):
    """The server ended the stream (BYE): `reason`, and the client's totals at the server."""

    def __init__(self, reason: str, dropped: int = 0, sent: int = 0) -> None:
        super().__init__(f"the server ended the stream: {reason} (it sent {sent} frame(s), dropped {dropped})")
        self.reason, self.dropped, self.sent = reason, dropped, sent


def envelope(kind: int, length: int) -> bytes:
    return ENVELOPE.pack(MAGIC, VERSION, kind, 0, length)


def message(kind: int, payload: bytes) -> bytes:
    """A whole message (HELLO, BYE, ERROR); FRAME is sent as envelope + client part + body."""
    return envelope(kind, len(payload)) + payload


def json_message(kind: int, obj: dict[str, Any]) -> bytes:
    return message(kind, json.dumps(obj, sort_keys=True).encode())


def check_envelope(data: bytes, who: str) -> tuple[int, int]:
    """(type, length) of an envelope; StreamError naming `who` when the magic, the version or the
    type is not this protocol's."""
    magic, version, kind, _, length = ENVELOPE.unpack(data)
    if magic != MAGIC:
        raise StreamError(f"{who} does not speak the {NAME} protocol (first bytes {data[:8]!r}, not {MAGIC!r})")
    if version != VERSION:
        raise StreamError(f"{who} speaks {NAME} version {version}; this side speaks version {VERSION}")
    if kind not in TYPES:
        raise StreamError(f"{who} sent an unknown message type {kind}")
    return kind, length


def parse_json(payload: bytes, what: str) -> dict[str, Any]:
    try:
        obj = json.loads(payload.decode())
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise StreamError(f"{what} is not a UTF-8 JSON object ({exc})") from None
    if not isinstance(obj, dict):
        raise StreamError(f"{what} is not a JSON object: {obj!r:.80}")
    return obj


def parse_address(address: str, default_host: str = "127.0.0.1") -> tuple[str, int]:
    """("host", port) of "host:port", ":port" or "port"; ValueError otherwise."""
    host, _, port = address.rpartition(":")
    try:
        number = int(port)
    except ValueError:
        raise ValueError(f"address {address!r} is not HOST:PORT") from None
    if not 0 <= number < 65536:
        raise ValueError(f"address {address!r}: port {number} outside 0..65535")
    return host or default_host, number


# ---- frames --------------------------------------------------------------------------------------
def _pad(n: int) -> int:
    return -n % ALIGN


def encode_frame(frame: Frame, seq: int, t_ready_ns: int, t_read_ns: int) -> bytes:
    """The body of a FRAME: one immutable bytes object every client is sent."""
    f, rec = frame.features, frame.record
    p = rec.params
    counters = [frame.counters[name.lower()] for name in COUNTERS] if frame.counters else []
    arrays = [np.ascontiguousarray(getattr(f, name)) for name in ARRAYS]
    arrays = [a if a.dtype.byteorder != ">" else a.astype(a.dtype.newbyteorder("<")) for a in arrays]
    values = {
        "seq": seq, "t_ready_ns": t_ready_ns, "t_read_ns": t_read_ns, "bank": frame.bank,
        "mode": MODES.index(frame.mode), "n_counters": len(counters), "n_features": len(f), "n_arrays": len(arrays),
        "flags": (FLAG_PARAMS if frame.params is not None else 0) | (FLAG_COUNTERS if counters else 0),
        "count": rec.count, "frame": rec.frame, "dropped": rec.dropped, "truncated": rec.truncated,
        "truncated_flag": int(rec.truncated_flag), "threshold": p.threshold, "threshold_lo": p.threshold_lo,
        "mode_orb": int(p.mode == "orb"), "select_grid": int(p.selection == "grid"), "budget": p.budget,
        "cols": p.cols, "rows": p.rows, "sectors_total": f.sectors_total, "step_num": f.step[0],
        "step_den": f.step[1], "reserved": b"",
    }  # fmt: skip
    head = FRAME_HEAD.pack(*(values[name] for name, _, _ in FRAME_HEAD_FIELDS))
    table: list[bytes] = []
    data: list[bytes | memoryview] = []
    at = len(head) + COUNTER.size * len(counters) + ARRAY_ENTRY.size * len(arrays)
    for name, a in zip(ARRAYS, arrays, strict=True):
        data.append(bytes(_pad(at)))
        at += _pad(at)
        dims = (*a.shape, 0)[:2]
        table.append(ARRAY_ENTRY.pack(name.encode(), a.dtype.str.encode(), a.ndim, b"", dims[0], dims[1], at))
        data.append(memoryview(a).cast("B") if a.nbytes else b"")
        at += a.nbytes
    parts = [head, *(COUNTER.pack(c) for c in counters), *table, *data]
    return b"".join(parts)


@dataclass(frozen=True)
class FrameMeta:
    """What a FRAME says beside the driver's Frame: the server's sequence number, its timestamps
    (wall clock, ns) and the frames it dropped for this client so far."""

    seq: int
    t_ready_ns: int
    t_read_ns: int
    dropped: int


def hw_config(info: dict[str, Any]) -> HwConfig:
    """The HwConfig of a server's HELLO; StreamError when it is not one."""
    try:
        return HwConfig(**{k: int(v) for k, v in info["hw"].items()})
    except (KeyError, TypeError, ValueError) as exc:
        raise StreamError(f"the server's HELLO has no accelerator configuration (hw: {exc})") from None


def decode_frame(body: bytes | bytearray | memoryview, hw: HwConfig, counter_names: list[str],
                 modes: tuple[str, ...] | list[str] = MODES) -> tuple[Frame, FrameMeta]:  # fmt: skip
    """A FRAME body back into the driver's Frame (arrays viewing `body`: writable when it is a
    bytearray) and its FrameMeta (dropped 0: the client part is not in the body). StreamError when
    the body is inconsistent (a size, a name, a dtype)."""
    buf = memoryview(body).cast("B")
    if len(buf) < FRAME_HEAD.size:
        raise StreamError(f"a FRAME body of {len(buf)} bytes, shorter than its head ({FRAME_HEAD.size})")
    h = dict(zip((name for name, _, _ in FRAME_HEAD_FIELDS), FRAME_HEAD.unpack_from(buf), strict=True))
    at = FRAME_HEAD.size
    n_counters = h["n_counters"]
    if n_counters not in (0, len(counter_names)):
        raise StreamError(f"a FRAME with {n_counters} counters; HELLO named {len(counter_names)}")
    values = [COUNTER.unpack_from(buf, at + COUNTER.size * k)[0] for k in range(n_counters)]
    at += COUNTER.size * n_counters
    if h["mode"] >= len(modes):
        raise StreamError(f"a FRAME in mode {h['mode']}; HELLO named {len(modes)} modes")
    if h["n_arrays"] != len(ARRAYS) or len(buf) < at + ARRAY_ENTRY.size * len(ARRAYS):
        raise StreamError(f"a FRAME with {h['n_arrays']} arrays (this client reads {len(ARRAYS)}: {', '.join(ARRAYS)})")
    arrays: dict[str, np.ndarray] = {}
    for k, want in enumerate(ARRAYS):
        name, dtype, ndim, _, dim0, dim1, offset = ARRAY_ENTRY.unpack_from(buf, at + ARRAY_ENTRY.size * k)
        name = name.rstrip(b"\0").decode(errors="replace")
        if name != want:
            raise StreamError(f"FRAME array {k} is {name!r}, not {want!r}")
        try:
            dt = np.dtype(dtype.rstrip(b"\0").decode())
        except (TypeError, UnicodeDecodeError) as exc:
            raise StreamError(f"FRAME array {name!r}: dtype {dtype!r} ({exc})") from None
        shape = (dim0,) if ndim == 1 else (dim0, dim1)
        nbytes = dt.itemsize * dim0 * (dim1 if ndim == 2 else 1)
        if dt.kind not in "biu" or ndim not in (1, 2) or dim0 != h["n_features"] or offset + nbytes > len(buf):
            raise StreamError(f"FRAME array {name!r}: {dt} {shape} at byte {offset} does not fit the frame "
                              f"({h['n_features']} features, {len(buf)} bytes)")  # fmt: skip
        arrays[name] = np.frombuffer(buf, dtype=dt, count=nbytes // dt.itemsize if dt.itemsize else 0,
                                     offset=offset).reshape(shape)  # fmt: skip
    params = FrameParams(threshold=h["threshold"], threshold_lo=h["threshold_lo"],
                         mode="orb" if h["mode_orb"] else "fast", selection="grid" if h["select_grid"] else "all",
                         budget=h["budget"], cols=h["cols"], rows=h["rows"])  # fmt: skip
    record = EndOfFrame(count=h["count"], frame=h["frame"], dropped=h["dropped"], truncated=h["truncated"],
                        truncated_flag=bool(h["truncated_flag"]), params=params)  # fmt: skip
    feats = Features(arrays["scale"], arrays["x"], arrays["y"], arrays["score"], arrays["sector"],
                     arrays["descriptor"], h["sectors_total"], (h["step_num"], h["step_den"]), arrays["response"],
                     arrays["low"])  # fmt: skip
    frame = Frame(h["bank"], feats, record, modes[h["mode"]], hw, dict(zip(counter_names, values, strict=False)),
                  params if h["flags"] & FLAG_PARAMS else None)  # fmt: skip
    return frame, FrameMeta(h["seq"], h["t_ready_ns"], h["t_read_ns"], 0)
