# SPDX-License-Identifier: MIT
"""The accelerator as a PYNQ IP driver (docs/pynq.md): importing this module registers OrbAccelIP
for the accelerator's VLNV, so that

    import orb_accel.pynq_driver
    from pynq import Overlay
    ol = Overlay("orb_board_1280x720.bit")     # with orb_board_1280x720.hwh (and .dtbo) beside it
    accel = ol.orb_accel                       # an OrbAccel on PynqBus: pynq.MMIO and the UIO interrupt
    accel.configure(threshold=20, mode="orb")
    frame = accel.next_frame(timeout_s=0.5)

The VLNV: the block design instantiates the accelerator as a module reference to the VHDL entity
orb_accel_zynq (vivado/lib/bd.tcl), and Vivado names a module reference's IP
`xilinx.com:module_ref:<module>:1.0` (the "IP VLNV" header of the files it generates for one). That
the .hwh carries the same VLNV is inferred, not seen in a hardware handoff of this design: nothing
has been built in Vivado here. tb/pynq checks VLNV (orb_accel.pynq_bus) against vivado/board.json's entity.

A DDR build (CFG_DDR.ddr = 1: docs/feature-dma.md) writes its frames into a ring in memory that
pynq.allocate gives (allocate_ring: an orb_accel.ddr.PynqMemory, cacheable; OrbAccelIP.ddr_memory),
allocated when the IP is bound; a build with block-RAM banks allocates nothing.

This is the one module of orb_accel that imports pynq (PyPI `pynq`; the board's PYNQ image has it);
everything else stays numpy only.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import pynq
from pynq import DefaultIP

from .ddr import MemoryFactory, PynqMemory
from .driver import OrbAccel
from .pynq_bus import ACCEL_IRQ, VLNV, PynqBus
from .uio import PROC_INTERRUPTS, SYSFS_UIO, UioInterrupt, find_uio_irq


def allocate_ring(size: int) -> PynqMemory:
    """`size` bytes for a DDR build's ring from pynq.allocate, cacheable (the driver invalidates
    before each read; docs/pynq.md)."""
    return PynqMemory(pynq.allocate(shape=(int(size),), dtype=np.uint8, cacheable=True))


class OrbAccelIP(OrbAccel, DefaultIP):  # type: ignore[misc]  # pynq has no type information
    """The driver PYNQ binds to the accelerator (`bindto` its VLNV): an OrbAccel (docs/driver.md) on
    a PynqBus over the pynq.MMIO that DefaultIP maps (`mmio`), with the interrupt of the UIO device
    that holds the accelerator's line (ACCEL_IRQ); without one a warning, and wait_irq polls.

    OrbAccel's methods come first: `read`/`write` take a register of golden_model.regs, not PYNQ's
    raw offsets (those are `mmio.read(offset)` and `mmio.write(offset, value)`). The class attributes
    `interrupts`, `sysfs` and `dev` are where the interrupt's UIO device is looked for; `ddr_memory`
    and `ring_count` what a DDR build's ring lies in (default: a cacheable pynq.allocate buffer of
    16 buffers; docs/pynq.md) and how many buffers it has (None: as many as fit, at most 16)."""

    bindto: ClassVar[list[str]] = [VLNV]
    interrupts: ClassVar[Path] = PROC_INTERRUPTS
    sysfs: ClassVar[Path] = SYSFS_UIO
    dev: ClassVar[Path] = Path("/dev")
    ddr_memory: ClassVar[MemoryFactory] = staticmethod(allocate_ring)  # type: ignore[assignment]
    ring_count: ClassVar[int | None] = None

    def __init__(self, description: dict[str, Any]) -> None:
        DefaultIP.__init__(self, description)
        self.uio: str | None = None  # the UIO device whose interrupt is waited for ("uioN (name)")
        self.pynq_bus = PynqBus(self.mmio, self._open_irq())
        try:
            OrbAccel.__init__(self, self.pynq_bus, memory=self.ddr_memory, ring_count=self.ring_count)
        except BaseException:
            self.pynq_bus.close()
            raise

    def _open_irq(self) -> UioInterrupt | None:
        try:
            device, name = find_uio_irq(ACCEL_IRQ, self.interrupts, self.sysfs)
        except (FileNotFoundError, RuntimeError) as exc:
            warnings.warn(f"orb_accel: no UIO device for interrupt {ACCEL_IRQ} ({exc}); wait_irq polls "
                          "IRQ_STATUS every millisecond instead (docs/pynq.md)", stacklevel=3)  # fmt: skip
            return None
        self.uio = f"{device} ({name})"
        return self.open_interrupt(self.dev / device)

    @staticmethod
    def open_interrupt(path: str | os.PathLike) -> UioInterrupt:
        """The UIO interrupt of the device file `path` (a seam for the tests' fake device)."""
        return UioInterrupt.open(path)

    def close(self) -> None:
        """Close the interrupt's descriptor and free a DDR build's ring buffer (the MMIO stays
        PYNQ's); calling it again does nothing."""
        OrbAccel.close(self)
        self.pynq_bus.close()
