# SPDX-License-Identifier: MIT
"""The bus the driver runs on: four blocking operations, whatever carries them (UIO or /dev/mem
on the board, cocotb in simulation: orb_sim.cocotb_bus). numpy only."""

from __future__ import annotations

from typing import Protocol

import numpy as np

# how long a program waits for a frame unless told (orb-accel board, ros, ros2)
BOARD_TIMEOUT_S = 1.0  # on the board: a frame at 24 fps and more, with margin
SIM_TIMEOUT_FRAMES = 3  # in simulation: three frame periods of simulated time (SocketBus.frame_period_s)


class BusError(OSError):
    """An AXI4-Lite error response (SLVERR or DECERR) to a read or a write."""

    def __init__(self, op: str, addr: int, resp: int, value: int | None = None) -> None:
        name = {2: "SLVERR", 3: "DECERR"}.get(resp, f"resp {resp}")
        what = f"{op} at {addr:#07x}" + (f" of {value:#x}" if value is not None else "")
        super().__init__(f"{what} answered {name}")
        self.op, self.addr, self.resp = op, addr, resp


class Bus(Protocol):
    """Byte addresses relative to the accelerator's base; 32-bit aligned single accesses."""

    def read32(self, addr: int) -> int:
        """One 32-bit load; raises BusError on an error response."""
        ...

    def write32(self, addr: int, value: int) -> None:
        """One 32-bit store; raises BusError on an error response."""
        ...

    def read_block(self, addr: int, count: int) -> np.ndarray:
        """`count` consecutive 32-bit words from `addr` as a uint32 array (32-bit loads only)."""
        ...

    def wait_irq(self, timeout_s: float) -> bool:
        """Wait until the interrupt line is high (at most `timeout_s` seconds of the bus's time:
        wall time on the board, simulated time in simulation); False on a timeout."""
        ...
