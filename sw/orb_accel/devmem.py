# SPDX-License-Identifier: MIT
"""The driver's bus on a board without UIO: the accelerator's window mapped from /dev/mem.

The fallback when the overlay or the kernel argument for generic-uio is missing (docs/uio.md).
Registers are accessed exactly as by orb_accel.uio.UioBus (single typed 32-bit loads and stores,
alignment and range checked first: an AXI error response is a SIGBUS on the board, see the
docstring of orb_accel.uio). Without UIO there is no interrupt: wait_irq polls the IRQ_STATUS and
IRQ_ENABLE registers every `poll_s` seconds, which costs CPU time and adds up to `poll_s` of
latency. The driver then acknowledges IRQ_STATUS as usual. Needs root. numpy only.

    with DevMemBus(0x43C00000) as bus:    # vivado/board.json "accel"/"base"
        accel = OrbAccel(bus)
"""

from __future__ import annotations

import mmap
import operator
import os
import time
from collections.abc import Callable

from golden_model import regs

from .uio import MappedWindow


def poll_irq(read32: Callable[[int], int], timeout_s: float, poll_s: float) -> bool:
    """The interrupt without an interrupt: True as soon as IRQ_STATUS & IRQ_ENABLE (read through
    `read32`) is not 0 (the accelerator's interrupt line is high), False when `timeout_s` passes
    first (<= 0: look once). Polls every `poll_s` seconds."""
    deadline = time.monotonic() + max(timeout_s, 0.0)
    while True:
        if read32(regs.IRQ_STATUS.offset) & read32(regs.IRQ_ENABLE.offset):
            return True
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return False
        time.sleep(min(poll_s, remaining))


class DevMemBus(MappedWindow):
    """orb_accel.bus.Bus on `size` bytes of physical memory at `base` (page aligned) of `path`.

    wait_irq polls (status & enable) every `poll_s` seconds; `block_mode` as for MappedWindow."""

    def __init__(self, base: int, size: int = 0x100000, path: str | os.PathLike = "/dev/mem", poll_s: float = 0.001,
                 block_mode: str = "copy") -> None:  # fmt: skip
        base = operator.index(base)
        if base < 0 or base % mmap.PAGESIZE:
            raise ValueError(f"base {base:#x} is not aligned to the page size (mmap.PAGESIZE = {mmap.PAGESIZE:#x})")
        if not poll_s > 0:
            raise ValueError(f"poll_s {poll_s!r} must be positive")
        self.base = base
        self.poll_s = poll_s
        try:
            # O_SYNC: an uncached mapping (the kernel maps addresses outside RAM uncached in any case)
            super().__init__(path, size, base, os.O_RDWR | os.O_SYNC | os.O_CLOEXEC, block_mode)
        except PermissionError as exc:
            raise PermissionError(
                exc.errno,
                f"cannot map {os.fspath(path)} at {base:#x} ({exc.strerror}): /dev/mem needs root "
                "(CAP_SYS_RAWIO), and a kernel built with CONFIG_STRICT_DEVMEM refuses RAM, with "
                "CONFIG_IO_STRICT_DEVMEM also device ranges a driver has claimed (a loaded generic-uio node); "
                "the UIO backend (orb_accel.uio.UioBus) needs neither (docs/uio.md)",
            ) from None

    def wait_irq(self, timeout_s: float) -> bool:
        """True as soon as IRQ_STATUS & IRQ_ENABLE is not 0 (the accelerator's interrupt line is
        high), False when `timeout_s` passes first (<= 0: look once). Polls every poll_s seconds."""
        return poll_irq(self.read32, timeout_s, self.poll_s)

    def __enter__(self) -> DevMemBus:
        return self
