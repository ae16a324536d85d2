# SPDX-License-Identifier: MIT
"""The simulator's side of orb_accel.socket_bus: serve the driver's bus operations, received over
a socket from another process, on the simulated AXI4-Lite bus: orb_sim.cocotb_bus.CocotbBus in
GHDL, or orb_sim.fast.sim.FastBus on the netlist in Verilator (any orb_accel.bus.Bus).

`serve` is blocking Python: the cocotb job runs it with `cocotb.task.bridge`, and each operation
goes into the simulation through CocotbBus (`cocotb.task.resume`). Simulated time advances only
inside an operation, so the simulation waits, frozen, while no client asks for anything: what a
client sees is the same whether it is fast or slow. One client at a time; the next connection is
accepted when the present one closes. The protocol is orb_accel.socket_bus's.

A DDR build's memory (MEM_READ): the bus's `read_mem(addr, nbytes)` (CocotbBus over the job's
orb_sim.ddr_ram.RegionRam, FastBus over the harness's memory), within the region the HELLO answer
gives (`ddr`, server_info's): a read outside it, or to a server without one, is refused with a
message (BAD_REQUEST) before it reaches the bus.
"""

from __future__ import annotations

import json
import socket
from pathlib import Path

from orb_accel.bus import Bus, BusError
from orb_accel.socket_bus import (
    BAD_REQUEST,
    BLOCK,
    BUS_ERROR,
    HELLO,
    MAGIC,
    MAX_BLOCK_WORDS,
    MAX_MEM_BYTES,
    MEM_READ,
    OK,
    PROTOCOL,
    READ,
    REQUEST,
    RESPONSE,
    SHUTDOWN,
    WAIT_IRQ,
    WRITE,
    recv_exact,
)


def handle(bus: Bus, info: dict, op: int, addr: int, arg: int) -> tuple[int, bytes]:
    """(status, payload) of one request."""
    try:
        if op == READ:
            return OK, bus.read32(addr).to_bytes(4, "little")
        if op == WRITE:
            if arg > 0xFFFFFFFF:
                return BAD_REQUEST, f"write value {arg:#x} is wider than 32 bits".encode()
            bus.write32(addr, arg)
            return OK, b""
        if op == BLOCK:
            if not 0 < arg <= MAX_BLOCK_WORDS:
                return BAD_REQUEST, f"block of {arg} words outside 1..{MAX_BLOCK_WORDS}".encode()
            return OK, bus.read_block(addr, arg).astype("<u4").tobytes()
        if op == WAIT_IRQ:
            return OK, bytes([int(bus.wait_irq(arg * 1e-9))])
        if op == HELLO:
            return OK, json.dumps(info).encode()
        if op == SHUTDOWN:
            return OK, b""
        if op == MEM_READ:
            refused = check_mem_read(info.get("ddr"), addr, arg)
            if refused:
                return BAD_REQUEST, refused.encode()
            return OK, bytes(bus.read_mem(addr, arg))  # type: ignore[attr-defined]
    except BusError as exc:
        return BUS_ERROR, bytes([exc.resp])
    except (ValueError, AttributeError) as exc:  # a memory the bus does not have after all
        if op != MEM_READ:
            raise
        return BAD_REQUEST, f"DDR read refused: {exc}".encode()
    return BAD_REQUEST, f"unknown operation {op}".encode()


def check_mem_read(ddr: dict | None, addr: int, nbytes: int) -> str | None:
    """Why a MEM_READ of `nbytes` at `addr` is refused (None: it is not), for the region `ddr`
    ({"base", "size"}, or None: no DDR memory)."""
    if not ddr:
        return "this simulator has no DDR memory (a BRAM build: MEM_KIND_g BRAM)"
    if not 0 < nbytes <= MAX_MEM_BYTES:
        return f"DDR read of {nbytes} bytes outside 1..{MAX_MEM_BYTES}"
    base, size = int(ddr["base"]), int(ddr["size"])
    if addr < base or addr + nbytes > base + size:
        return f"DDR read of {nbytes} bytes at {addr:#x} outside the simulated DDR region [{base:#x}, {base + size:#x})"
    return None


def serve(listener: socket.socket, bus: Bus, info: dict) -> None:
    """Serve clients of `listener` one after another until one sends SHUTDOWN."""
    while True:
        conn, _ = listener.accept()
        with conn:
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            while True:
                try:
                    op, addr, arg = REQUEST.unpack(recv_exact(conn, REQUEST.size))
                except OSError:  # the client closed (or reset) the connection
                    break
                status, payload = handle(bus, info, op, addr, arg)
                try:
                    conn.sendall(RESPONSE.pack(status, len(payload)) + payload)
                except OSError:
                    break
                if op == SHUTDOWN:
                    return


def listen(job: Path, host: str, port: int) -> socket.socket:
    """A listening socket on host:port (0: any free port), its address written atomically to
    job/address, where orb_sim.sim_server.SimServer waits for it."""
    listener = socket.create_server((host, port))
    bound_host, bound_port = listener.getsockname()[:2]
    tmp = job / "address.tmp"
    tmp.write_text(f"{bound_host}:{bound_port}\n")
    tmp.replace(job / "address")
    return listener


def server_info(cfg: dict, frames: int, period_ns: int, engine: str,
                ddr: tuple[int, int] | None = None) -> dict:  # fmt: skip
    """The HELLO answer: the protocol and the simulated configuration (SimServer's config.json);
    `ddr` the (base, size) of a DDR build's memory region (None: a BRAM build)."""
    return {"magic": MAGIC, "protocol": PROTOCOL, "toplevel": cfg["toplevel"], "generics": cfg["generics"],
            "period_ns": period_ns, "frames": frames, "h_blank": cfg["h_blank"], "v_blank": cfg["v_blank"],
            "engine": engine, "faults": cfg.get("faults", []),
            "ddr": None if ddr is None else {"base": int(ddr[0]), "size": int(ddr[1])}}  # fmt: skip
