# SPDX-License-Identifier: MIT
"""The driver's bus under PYNQ: the registers through a pynq.MMIO, the interrupt through UIO
(docs/pynq.md).

On a PYNQ image the Overlay maps the accelerator's window with pynq.MMIO (/dev/mem on a Zynq, so
root); PynqBus makes every register access one `mmio.read(offset)` or `mmio.write(offset, int)`
(a single 32-bit load or store on PYNQ's memory-mapped devices) and reads a block of the feature
memory as a copy of `mmio.array` (or word by word, block_mode="words"; the two modes of
orb_accel.uio.MappedWindow). Alignment and range are checked before every access, as in the UIO
backend: an access the bus answers with an error is a SIGBUS on the board (docs/uio.md).

The interrupt: PYNQ's Overlay lists no interrupt for a pin wired straight to IRQ_F2P (its metadata
views follow AXI interrupt controllers only), so the frame interrupt is taken from the UIO device
that holds the line, found the way PYNQ itself finds one (orb_accel.uio.find_uio_irq: the GIC's
interrupt number in /proc/interrupts; on a PYNQ image the boot device tree's `fabric` node holds
IRQ_F2P[0]), and waited for with the UIO protocol (orb_accel.uio.UioInterrupt). Without such a
device wait_irq polls IRQ_STATUS and IRQ_ENABLE like the /dev/mem backend.

No pynq import here: PynqBus takes any object with pynq.MMIO's read, write, array and length.
orb_accel.pynq_driver (which imports pynq) binds it to the Overlay. numpy only.
"""

from __future__ import annotations

from types import TracebackType
from typing import Any, Protocol

import numpy as np

from .devmem import poll_irq
from .uio import BLOCK_MODES, UioInterrupt, check_value, word_index

# The GIC interrupt ID of the accelerator's interrupt: IRQ_F2P[0] (vivado/board.json "accel"/"irq_f2p"),
# GIC SPI 29 ("gic_spi"), + 32 = 61, the number /proc/interrupts shows and PYNQ's IRQ_F2P map starts at.
# tb/pynq checks it against board.json.
ACCEL_IRQ = 61
# The accelerator's IP as the .hwh names it, which PYNQ binds orb_accel.pynq_driver.OrbAccelIP to: the
# block design instantiates the VHDL entity orb_accel_zynq as a module reference (vivado/lib/bd.tcl,
# vivado/board.json "accel"/"entity"), whose IP Vivado calls xilinx.com:module_ref:<module>:1.0 (inferred
# for the .hwh: see orb_accel.pynq_driver). tb/pynq checks it against board.json.
VLNV = "xilinx.com:module_ref:orb_accel_zynq:1.0"


class Mmio(Protocol):
    """What PynqBus uses of a pynq.MMIO."""

    length: int
    array: Any

    def read(self, offset: int = 0, length: int = 4) -> int: ...

    def write(self, offset: int, data: int) -> None: ...


class PynqBus:
    """orb_accel.bus.Bus on `mmio` (a pynq.MMIO of the accelerator's window) and `irq` (the UIO
    interrupt of the line; None: wait_irq polls every `poll_s` seconds). `block_mode` as for
    orb_accel.uio.MappedWindow; `reads` and `writes` count 32-bit accesses. close() closes the
    interrupt's descriptor if it owns it."""

    def __init__(self, mmio: Mmio, irq: UioInterrupt | None = None, poll_s: float = 0.001,
                 block_mode: str = "copy") -> None:  # fmt: skip
        if block_mode not in BLOCK_MODES:
            raise ValueError(f"block_mode {block_mode!r} not one of {BLOCK_MODES}")
        if not poll_s > 0:
            raise ValueError(f"poll_s {poll_s!r} must be positive")
        size = int(mmio.length)
        if size <= 0 or size % 4:
            raise ValueError(f"MMIO length {size:#x} is not a positive multiple of 4 bytes")
        self.mmio = mmio
        self.size = size
        self.irq = irq
        self.poll_s = poll_s
        self.block_mode = block_mode
        self.reads = self.writes = 0

    # ---- the bus -------------------------------------------------------------------------------
    def read32(self, addr: int) -> int:
        i = word_index(addr, 1, self.size)
        self.reads += 1
        return int(self.mmio.read(4 * i))

    def write32(self, addr: int, value: int) -> None:
        i = word_index(addr, 1, self.size)
        value = check_value(addr, value)
        self.writes += 1
        self.mmio.write(4 * i, value)  # a plain int: pynq.MMIO.write takes `int` or `bytes`, nothing else

    def read_block(self, addr: int, count: int) -> np.ndarray:
        i = word_index(addr, count, self.size)
        self.reads += count
        if self.block_mode == "copy":
            return np.array(self.mmio.array[i : i + count], dtype=np.uint32)
        return np.array([self.mmio.read(4 * (i + k)) for k in range(count)], dtype=np.uint32)

    def wait_irq(self, timeout_s: float) -> bool:
        """The UIO interrupt's wait (orb_accel.uio.UioInterrupt.wait), or without one True as soon as
        IRQ_STATUS & IRQ_ENABLE is not 0, polled every poll_s seconds; False on the timeout."""
        if self.irq is not None:
            return self.irq.wait(timeout_s)
        return poll_irq(self.read32, timeout_s, self.poll_s)

    # ---- lifetime ------------------------------------------------------------------------------
    def close(self) -> None:
        """Close the interrupt's descriptor (if the UioInterrupt owns it); calling it again does nothing."""
        if self.irq is not None:
            self.irq.close()

    def __enter__(self) -> PynqBus:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.close()
