# SPDX-License-Identifier: MIT
"""The DDR of the simulated DDR builds in GHDL (orb_accel_top / orb_accel_zynq with MEM_KIND_g
"DDR", docs/feature-dma.md): cocotbext-axi's AXI4 RAM model, write side only, on the top's
m_axi_feat master, holding an emulated reserved region of DDR (a base address and a size, as a
u-dma-buf or pynq.allocate buffer would be on the board: default DDR_BASE and DDR_SIZE, those of the
fast engine's harness, orb_sim.fast.sim).

The master has no read channel and no ID ports: cocotbext-axi's AxiRam would attach a read slave
too (AxiReadBus.from_prefix finds none of the ar*/r* ports and AxiSlaveRead then fails on the
missing arid), and its write slave requires awid and bid (the write bus lists them as required
signals: a missing one becomes None and AxiSlaveWrite takes len() of it). So RegionRam is an
AxiRamWrite on an AxiWriteBus whose absent awid/bid are a tied-off 1-bit stand-in (ID 0, the
master's one ID). A write that leaves the region is not stored and its burst is answered SLVERR
(cocotbext-axi's answer to a failing write; the fast harness answers DECERR): counted in
`outside_writes`, which a test expects to stay 0, since the fabric writes only inside the ring.

The CPU's side: `memory()` is an orb_accel.ddr.ArrayMemory over the RAM's bytes (the driver reads
the frames from there directly: the simulation is frozen while driver code runs, so there is no
cache to model), `read_mem(addr, n)` the bytes at a bus address (for the socket bus's memory
operation, orb_sim.bus_server). Random stalls: `set_pauses(prob, seed)` on AW, W and B.
"""

from __future__ import annotations

import logging
import os

import numpy as np
from cocotb.types import LogicArray
from cocotbext.axi import AxiWriteBus
from cocotbext.axi.axi_ram import AxiRamWrite

from orb_accel.bus import BusError
from orb_accel.ddr import ArrayMemory

from .cocotb_bus import pause_pattern

DDR_BASE, DDR_SIZE = 0x1000_0000, 4 << 20  # as orb_sim.fast.sim's: 16 buffers of 4,096 slots fit
PREFIX = "m_axi_feat"
SLVERR = 2


def mem_kind(generics_env: dict[str, str] | None = None) -> str:
    """The MEM_KIND_g the top was built with, "DDR" or "BRAM" (orb_sim.runner passes every generic
    as ORB_<NAME>; not given: the tops' default, BRAM)."""
    env = os.environ if generics_env is None else generics_env
    return env.get("ORB_MEM_KIND", "BRAM").strip('"').upper()


def region_from_env() -> tuple[int, int]:
    """(base, size) of the emulated region: ORB_DDR_BASE and ORB_DDR_SIZE, default DDR_BASE, DDR_SIZE."""
    return int(os.environ.get("ORB_DDR_BASE", str(DDR_BASE)), 0), int(os.environ.get("ORB_DDR_SIZE", str(DDR_SIZE)), 0)


class _TiedId:
    """A stand-in for an absent 1-bit ID port: reads 0, takes what is driven on it."""

    def __init__(self) -> None:
        self.value: object = LogicArray("0")
        self._name = "tied_id"

    def __len__(self) -> int:
        return 1

    def setimmediatevalue(self, value: object) -> None:
        self.value = value


def write_bus(dut, prefix: str = PREFIX) -> AxiWriteBus:
    """The AXI4 write bus of `dut`'s `prefix`_* ports, absent awid and bid tied off."""
    bus = AxiWriteBus.from_prefix(dut, prefix)
    for channel, sig in ((bus.aw, "awid"), (bus.b, "bid")):
        if getattr(channel, sig, None) is None:
            tied = _TiedId()
            setattr(channel, sig, tied)
            channel._signals[sig] = tied
    return bus


class RegionRam(AxiRamWrite):
    """The write-only AXI4 RAM of [base, base + size) bus addresses (the module docstring)."""

    def __init__(self, dut, clock, reset, reset_active_level: bool, base: int = DDR_BASE, size: int = DDR_SIZE,
                 prefix: str = PREFIX) -> None:  # fmt: skip
        if base < 0 or size <= 0 or base + size > 1 << 32 or base % 64:
            raise ValueError(f"DDR region {base:#x} + {size:#x}: must lie in 32 bits, 64-byte aligned")
        self.base = base
        self.bytes = bytearray(size)
        self.outside_writes = 0  # bytes the master tried to write outside the region
        self.stored = 0  # bytes written into the region
        super().__init__(write_bus(dut, prefix), clock, reset, reset_active_level, mem=self.bytes)
        self.log.setLevel(logging.WARNING)  # not a line per burst (its INFO); failed writes still show

    @property
    def region(self) -> tuple[int, int]:
        return self.base, self.size

    async def _write(self, address: int, data: bytes) -> None:
        offset = address - self.base
        if offset < 0 or offset + len(data) > self.size:
            self.outside_writes += len(data)
            raise ValueError(f"write of {len(data)} bytes at {address:#x} outside the DDR region")
        self.write(offset, data)
        self.stored += len(data)

    def set_pauses(self, prob: float, seed: int = 1) -> None:
        """Random stalls (probability `prob` per clock, 0: none) on AW, W (ready low) and B (valid held back)."""
        for i, ch in enumerate((self.aw_channel, self.w_channel, self.b_channel)):
            ch.set_pause_generator(pause_pattern(seed * 10 + 5 + i, prob) if prob > 0 else None)
            if prob <= 0:
                ch.pause = False

    def memory(self) -> ArrayMemory:
        """The region as the driver's FrameMemory (orb_accel.ddr): the RAM's own bytes, no copy."""
        return ArrayMemory(self.size, self.base, np.frombuffer(self.bytes, dtype=np.uint8))

    def read_mem(self, addr: int, nbytes: int) -> bytes:
        """`nbytes` bytes at bus address `addr`; BusError (SLVERR) outside the region."""
        offset = addr - self.base
        if nbytes < 0 or offset < 0 or offset + nbytes > self.size:
            raise BusError("read", addr, SLVERR)
        return bytes(self.bytes[offset : offset + nbytes])
