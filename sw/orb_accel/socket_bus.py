# SPDX-License-Identifier: MIT
"""The driver's bus over a local socket: the simulated accelerator served by another process
(orb_sim.bus_server inside a cocotb simulation; `orb-accel sim-server`), a drop-in for the board's
UioBus. A user's script, the CLI and the ROS node run unchanged against the simulator:

    with SocketBus("127.0.0.1:5555") as bus:
        accel = OrbAccel(bus)

The protocol (this module defines it once; the server imports it) is a request-response exchange
over one TCP connection, little-endian:

- request: REQUEST (op u8, addr u32, arg u64). Ops: READ (arg unused), WRITE (arg = value),
  BLOCK (arg = word count), WAIT_IRQ (arg = timeout in nanoseconds of simulated time), HELLO
  (server information), SHUTDOWN (ends the simulation), MEM_READ (addr = a bus address of the
  simulated DDR, arg = byte count, 1 .. MAX_MEM_BYTES: a DDR build's memory, protocol 2).
- response: RESPONSE (status u8, length u32) and `length` payload bytes. Status OK: READ gives 4
  bytes, BLOCK 4 x count, WAIT_IRQ one byte (1: the interrupt line is high, 0: timeout), HELLO a
  UTF-8 JSON object, MEM_READ the bytes, WRITE and SHUTDOWN nothing. BUS_ERROR: one byte, the AXI
  response (2 SLVERR, 3 DECERR), raised here as orb_accel.bus.BusError. BAD_REQUEST: a UTF-8
  message (a MEM_READ outside the DDR region, or to a simulator without one, is refused so).

HELLO's `ddr`: {"base", "size"} of the simulated DDR region a DDR build (MEM_KIND_g "DDR",
docs/feature-dma.md) writes its frames into, the emulated reserved region of the board's DDR; null
for a BRAM build. SocketMemory is the driver's FrameMemory (orb_accel.ddr) over it:

    with SocketBus(address) as bus:
        accel = OrbAccel(bus, memory=SocketMemory(bus))    # bus.memory_region is not None

Time: the simulation advances only inside bus operations, so `wait_irq(timeout_s)` counts
simulated seconds (as in orb_accel.bus.Bus); the wall-clock limit of one operation is
`op_timeout_s` (a simulated frame takes seconds to minutes of wall time), waited in slices of
SLICE_S so that Ctrl-C or SIGTERM stops a client within a slice whichever thread the signal
reached (the ROS node's rospy threads). numpy only.
"""

from __future__ import annotations

import json
import socket
import struct
import time
from types import TracebackType

import numpy as np

from .bus import BusError

PROTOCOL = 2  # 2: MEM_READ and HELLO's ddr
MAGIC = "orb-accel-sim"
REQUEST = struct.Struct("<BIQ")
RESPONSE = struct.Struct("<BI")
READ, WRITE, BLOCK, WAIT_IRQ, HELLO, SHUTDOWN, MEM_READ = 1, 2, 3, 4, 5, 6, 7
OK, BUS_ERROR, BAD_REQUEST = 0, 1, 2
MAX_BLOCK_WORDS = 1 << 20
MAX_MEM_BYTES = 1 << 24  # one MEM_READ's bytes at most
SLICE_S = 0.2  # the longest a client's recv sleeps before Python runs again (signals, Ctrl-C)


def parse_address(address: str) -> tuple[str, int]:
    """("host", port) of "host:port" or ":port" / "port" (host 127.0.0.1); ValueError otherwise."""
    host, _, port = address.rpartition(":")
    try:
        number = int(port)
    except ValueError:
        raise ValueError(f"simulator address {address!r} is not HOST:PORT") from None
    if not 0 < number < 65536:
        raise ValueError(f"simulator address {address!r}: port {number} outside 1..65535")
    return host or "127.0.0.1", number


def recv_exact(sock: socket.socket, n: int, deadline: float | None = None) -> bytes:
    """Exactly n bytes; ConnectionError when the peer closes first. With `deadline` (a
    time.monotonic() value) the socket must have a short timeout (SLICE_S): each slice that
    passes without data returns to Python, so a KeyboardInterrupt is raised within a slice even
    when the signal was delivered to another thread (rospy's), which leaves this thread's recv
    asleep; TimeoutError once the deadline has passed."""
    buf = bytearray()
    while len(buf) < n:
        try:
            chunk = sock.recv(n - len(buf))
        except TimeoutError:
            if deadline is None or time.monotonic() >= deadline:
                raise
            continue
        if not chunk:
            raise ConnectionError(f"connection closed after {len(buf)} of {n} bytes")
        buf += chunk
    return bytes(buf)


class SocketBus:
    """orb_accel.bus.Bus over a connection to a simulation bus server."""

    def __init__(self, address: str, op_timeout_s: float = 600.0, connect_timeout_s: float = 10.0) -> None:
        self.address = address
        host, port = parse_address(address)
        self.reads = self.writes = 0
        self.mem_reads = 0  # MEM_READ requests
        self._broken = False
        try:
            self._sock = socket.create_connection((host, port), timeout=connect_timeout_s)
        except OSError as exc:
            raise ConnectionError(
                f"no simulator at {host}:{port} ({exc}); start one with `orb-accel sim-server`"
            ) from None
        self.op_timeout_s = op_timeout_s
        self._sock.settimeout(SLICE_S)  # recv_exact waits in slices up to op_timeout_s
        self._sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.info: dict = json.loads(self._call(HELLO, 0, 0).decode())
        if self.info.get("magic") != MAGIC or self.info.get("protocol") != PROTOCOL:
            self.close()
            raise ConnectionError(f"{address} is not an orb-accel simulator of protocol {PROTOCOL}: {self.info}")

    def _call(self, op: int, addr: int, arg: int) -> bytes:
        if self._broken:
            raise ConnectionError(f"the connection to {self.address} is out of step after an interrupted operation")
        self._broken = True  # until the answer is complete (a KeyboardInterrupt may cut it)
        try:
            self._sock.sendall(REQUEST.pack(op, addr, arg))
            deadline = time.monotonic() + self.op_timeout_s
            status, length = RESPONSE.unpack(recv_exact(self._sock, RESPONSE.size, deadline))
            payload = recv_exact(self._sock, length, deadline)
            self._broken = False
        except TimeoutError:
            raise TimeoutError(f"the simulator at {self.address} did not answer within {self.op_timeout_s} s") from None
        except (ConnectionError, OSError) as exc:
            raise ConnectionError(f"the simulator at {self.address} went away ({exc})") from None
        if status == BUS_ERROR:
            raise BusError({WRITE: "write"}.get(op, "read"), addr, payload[0], arg if op == WRITE else None)
        if status != OK:
            raise ValueError(f"the simulator refused the request: {payload.decode(errors='replace')}")
        return payload

    @staticmethod
    def _check(addr: int) -> None:
        if addr < 0 or addr % 4 or addr >= 1 << 32:
            raise ValueError(f"address {addr:#x} is not a 32-bit aligned offset")

    def read32(self, addr: int) -> int:
        self._check(addr)
        self.reads += 1
        return int.from_bytes(self._call(READ, addr, 0), "little")

    def write32(self, addr: int, value: int) -> None:
        self._check(addr)
        if not 0 <= value <= 0xFFFFFFFF:
            raise ValueError(f"value {value!r} is not a 32-bit value")
        self.writes += 1
        self._call(WRITE, addr, value)

    def read_block(self, addr: int, count: int) -> np.ndarray:
        self._check(addr)
        if not 0 < count <= MAX_BLOCK_WORDS:
            raise ValueError(f"block of {count} words outside 1..{MAX_BLOCK_WORDS}")
        self.reads += count
        return np.frombuffer(self._call(BLOCK, addr, count), dtype="<u4").astype(np.uint32)

    def wait_irq(self, timeout_s: float) -> bool:
        return self._call(WAIT_IRQ, 0, max(0, round(timeout_s * 1e9)))[0] == 1

    @property
    def memory_region(self) -> tuple[int, int] | None:
        """(base, size) of the simulated DDR region (HELLO's ddr); None for a BRAM build."""
        ddr = self.info.get("ddr")
        return None if not ddr else (int(ddr["base"]), int(ddr["size"]))

    def read_mem(self, addr: int, nbytes: int) -> bytes:
        """`nbytes` bytes of the simulated DDR at bus address `addr` (no simulated time passes).
        ValueError, before anything is sent, for a range outside the region or a simulator
        without one."""
        region = self.memory_region
        if region is None:
            raise ValueError(f"the simulator at {self.address} has no DDR memory (a BRAM build: MEM_KIND_g BRAM)")
        base, size = region
        if not 0 < nbytes <= MAX_MEM_BYTES:
            raise ValueError(f"DDR read of {nbytes} bytes outside 1..{MAX_MEM_BYTES}")
        if addr < base or addr + nbytes > base + size:
            raise ValueError(f"DDR read of {nbytes} bytes at {addr:#x} outside the simulated DDR region "
                             f"[{base:#x}, {base + size:#x})")  # fmt: skip
        self.mem_reads += 1
        return self._call(MEM_READ, addr, nbytes)

    def frame_period_s(self) -> float:
        """One frame of the simulated video (its pixels and blanking), in the bus's (simulated) seconds."""
        g = self.info["generics"]
        clocks = (g["WIDTH_g"] + self.info["h_blank"]) * g["HEIGHT_g"] + self.info["v_blank"]
        return clocks * self.info["period_ns"] * 1e-9

    def shutdown_server(self) -> None:
        """End the simulation (the server answers, then stops)."""
        self._call(SHUTDOWN, 0, 0)

    def close(self) -> None:
        self._sock.close()

    def __enter__(self) -> SocketBus:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.close()


class SocketMemory:
    """orb_accel.ddr's FrameMemory over a SocketBus's simulated DDR (HELLO's ddr region): what
    OrbAccel(bus, memory=SocketMemory(bus)) reads a DDR build's frames from in another process.

    A local copy stands for the CPU's cached view: invalidate(offset, length) fetches the range
    from the simulator (MEM_READ, in requests of MAX_MEM_BYTES at most), view(offset, length)
    returns the copy, read-only. So, as on the board, a reader that does not invalidate what the
    accelerator wrote reads stale bytes (zeros at first). `invalidations` and `fetched_bytes`
    count the work."""

    def __init__(self, bus: SocketBus) -> None:
        region = bus.memory_region
        if region is None:
            raise ValueError(f"the simulator at {bus.address} has no DDR memory (a BRAM build: MEM_KIND_g BRAM)")
        self.bus = bus
        self.phys_addr, self.size = region
        self._copy = np.zeros(self.size, dtype=np.uint8)
        self.invalidations = 0
        self.fetched_bytes = 0

    def _check(self, offset: int, length: int) -> None:
        if offset < 0 or length < 0 or offset + length > self.size:
            raise ValueError(f"bytes {offset:#x} .. {offset + length:#x} outside the memory of {self.size:#x} bytes")

    def invalidate(self, offset: int, length: int) -> None:
        self._check(offset, length)
        self.invalidations += 1
        end = offset + length
        while offset < end:
            n = min(end - offset, MAX_MEM_BYTES)
            data = self.bus.read_mem(self.phys_addr + offset, n)
            self._copy[offset : offset + n] = np.frombuffer(data, dtype=np.uint8)
            self.fetched_bytes += n
            offset += n

    def view(self, offset: int, length: int) -> np.ndarray:
        self._check(offset, length)
        v = self._copy[offset : offset + length].view()
        v.flags.writeable = False
        return v

    def close(self) -> None:
        pass
