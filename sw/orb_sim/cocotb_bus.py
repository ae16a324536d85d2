# SPDX-License-Identifier: MIT
"""The driver's bus in simulation: orb_accel.bus.Bus over cocotbext-axi's AXI4-Lite master.

The driver is blocking Python; a cocotb coroutine runs it with `cocotb.task.bridge` (in a
thread the scheduler steps in lockstep with the simulation), and each bus operation here goes
back into the simulation with `cocotb.task.resume`. So the same driver code that runs on the board
drives the RTL:

    bus = CocotbBus(axil, dut.clk, dut.irq)
    accel = await bridge(OrbAccel)(bus)
    frame = await bridge(accel.next_frame)(timeout_s=0.01)   # simulated seconds

Times are simulated time. No AXI4-Lite transaction may take longer than OP_TIMEOUT_CLOCKS: a hung
bus fails the simulation instead of hanging it.

A DDR build's memory (orb_sim.ddr_ram.RegionRam on m_axi_feat, `ram`): `read_mem(addr, n)` and
`memory_region` serve the socket bus's memory operation (orb_sim.bus_server), as
orb_sim.fast.sim.FastBus does for the fast engine; the in-process driver takes `ram.memory()`.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator

import numpy as np
from cocotb.task import resume
from cocotb.triggers import First, RisingEdge, Timer, with_timeout

from orb_accel.bus import BusError

PERIOD_NS = 10  # the clock period of every bench (100 MHz)
OP_TIMEOUT_CLOCKS = 5000
OKAY, SLVERR = 0, 2


def pause_pattern(seed: int, prob: float, length: int = 997) -> Iterator[bool]:
    """A seeded, repeating pause pattern for cocotbext-axi's set_pause_generator: True with
    probability `prob`."""
    rng = np.random.default_rng(seed)
    return itertools.cycle((rng.random(length) < prob).tolist())


def set_axil_pauses(axil, prob: float, seed: int = 1) -> None:
    """Random pauses (probability `prob`, 0: none) on all five channels of an AxiLiteMaster."""
    w, r = axil.write_if, axil.read_if
    for i, ch in enumerate((w.aw_channel, w.w_channel, w.b_channel, r.ar_channel, r.r_channel)):
        ch.set_pause_generator(pause_pattern(seed * 10 + i, prob) if prob > 0 else None)
        if prob <= 0:
            ch.pause = False  # a killed generator leaves its last value


class CocotbBus:
    """Bus operations of the driver as AXI4-Lite transactions of `axil` (an AxiLiteMaster);
    `irq` is the level interrupt output. Call only from a `bridge`d function."""

    def __init__(self, axil, clk, irq, period_ns: int = PERIOD_NS, ram=None) -> None:
        self.axil, self.clk, self.irq, self.period_ns = axil, clk, irq, period_ns
        self.ram = ram  # a DDR build's RegionRam (orb_sim.ddr_ram), else None
        self.reads = self.writes = 0  # single 32-bit accesses, for reports

    @property
    def memory_region(self) -> tuple[int, int] | None:
        """(base, size) of the simulated DDR region; None without one (a BRAM build)."""
        return None if self.ram is None else self.ram.region

    def read_mem(self, addr: int, nbytes: int) -> bytes:
        """`nbytes` bytes of the simulated DDR at bus address `addr` (no simulated time passes);
        BusError outside the region, ValueError without one."""
        if self.ram is None:
            raise ValueError("this simulation has no DDR memory (MEM_KIND_g is not DDR)")
        return self.ram.read_mem(addr, nbytes)

    async def _read(self, addr: int, count: int) -> tuple[int, bytes]:
        resp = await with_timeout(self.axil.read(addr, 4 * count), OP_TIMEOUT_CLOCKS * count * self.period_ns, "ns")
        return int(resp.resp), bytes(resp.data)

    async def _write(self, addr: int, value: int) -> int:
        resp = await with_timeout(self.axil.write(addr, value.to_bytes(4, "little")),
                                  OP_TIMEOUT_CLOCKS * self.period_ns, "ns")  # fmt: skip
        return int(resp.resp)

    async def _wait_irq(self, timeout_ns: int) -> bool:
        if self.irq.value == 1:  # a registered output: stable between clock edges
            return True
        await First(RisingEdge(self.irq), Timer(max(timeout_ns, 1), "ns"))
        return self.irq.value == 1

    def read32(self, addr: int) -> int:
        resp, data = resume(self._read)(addr, 1)
        self.reads += 1
        if resp != OKAY:
            raise BusError("read", addr, resp)
        return int.from_bytes(data, "little")

    def write32(self, addr: int, value: int) -> None:
        resp = resume(self._write)(addr, value)
        self.writes += 1
        if resp != OKAY:
            raise BusError("write", addr, resp, value)

    def read_block(self, addr: int, count: int) -> np.ndarray:
        resp, data = resume(self._read)(addr, count)
        self.reads += count
        if resp != OKAY:
            raise BusError("read", addr, resp)
        return np.frombuffer(data, dtype="<u4").astype(np.uint32)

    def wait_irq(self, timeout_s: float) -> bool:
        return resume(self._wait_irq)(round(timeout_s * 1e9 / self.period_ns) * self.period_ns)
