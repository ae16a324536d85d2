# SPDX-License-Identifier: MIT
"""The memory the DDR builds write their frames into (docs/feature-dma.md; docs/driver.md,
"Features from DDR"): a physically contiguous buffer the fabric writes through the HP port and the
CPU reads through a cached mapping.

A FrameMemory is `phys_addr` (the bus address of byte 0, what RING_BASE is computed from), `size`
(bytes), `view(offset, length)` (a read-only numpy uint8 view of the CPU's mapping) and
`invalidate(offset, length)`: make the CPU's caches coherent with what the device wrote there,
before reading it. The driver (orb_accel.ring) never writes into the memory: the mapping is
read-only where the backend allows it, so the CPU never holds a dirty line the device could
have its data overwritten with when the line is evicted.

Backends:

- UDmaBuf: the ikwzm u-dma-buf kernel module's buffer (/dev/udmabufN), mapped without O_SYNC (the
  CPU's caches on), invalidated by writing a one-shot sync command to
  /sys/class/u-dma-buf/udmabufN/sync_for_cpu with direction DMA_FROM_DEVICE: the module calls
  dma_sync_single_for_cpu() on that range, which on the Zynq-7000's Cortex-A9 invalidates the
  lines of the L1 data cache and of the PL310 L2 cache;
- PynqMemory: a `pynq.allocate` buffer (cacheable; orb_accel.pynq_driver.allocate_ring makes one),
  invalidated with PynqBuffer.invalidate() on the slice (pynq 3.0.1 syncs that range; pynq 4.0.0
  syncs the whole buffer);
- ArrayMemory: an in-process numpy array at a stated bus address, for the tests and the simulator
  (whose memory model writes into `array`); invalidate only checks the range.

`memory_factory(spec)` turns a command line's `--ddr-memory` into what OrbAccel(memory=) takes: a
FrameMemory, or a callable that opens one given the bytes the ring wants, called only when the
accelerator writes its features to DDR (CFG_DDR.ddr = 1). numpy and the standard library only
(the one allocation through pynq is orb_accel.pynq_driver's, imported when the `pynq` spec opens).
"""

from __future__ import annotations

import mmap
import operator
import os
from collections.abc import Callable
from pathlib import Path
from types import TracebackType
from typing import Any, Protocol, runtime_checkable

import numpy as np

SYSFS_UDMABUF = Path("/sys/class/u-dma-buf")
UDMABUF_NAME = "udmabuf0"  # the default device: the module's first buffer (insmod u-dma-buf.ko udmabuf0=SIZE)
CACHE_LINE = 32  # bytes of a Cortex-A9 L1 data-cache line and of a PL310 L2 line (the Zynq-7000's)
# u-dma-buf's one-shot sync command (its Readme, "sync_for_cpu"): bits 63..32 the offset, 31..4 the
# size (a multiple of 16), 3..2 the direction, 0 the command bit
_DMA_FROM_DEVICE = 2
_SYNC_SIZE_MASK = 0xFFFFFFF0


@runtime_checkable
class FrameMemory(Protocol):
    """Physically contiguous memory the device writes and the CPU reads (the module docstring)."""

    phys_addr: int  # bus address of byte 0
    size: int  # bytes

    def invalidate(self, offset: int, length: int) -> None:
        """Make the CPU's view of bytes offset .. offset + length - 1 coherent with what the device
        wrote there (call it after the device finished writing them, before reading them)."""
        ...

    def view(self, offset: int, length: int) -> np.ndarray:
        """Bytes offset .. offset + length - 1 as a read-only uint8 array (no copy)."""
        ...


# a FrameMemory, or what opens one given the bytes the ring would like (OrbAccel(memory=))
MemoryFactory = Callable[[int], FrameMemory]


def check_range(offset: int, length: int, size: int) -> tuple[int, int]:
    """(offset, length) as ints, after checking they lie in a memory of `size` bytes (ValueError)."""
    offset, length = operator.index(offset), operator.index(length)
    if offset < 0 or length < 0 or offset + length > size:
        raise ValueError(f"bytes {offset:#x} .. {offset + length:#x} outside the memory of {size:#x} bytes")
    return offset, length


def line_range(offset: int, length: int, size: int, line: int = CACHE_LINE) -> tuple[int, int]:
    """The range widened to whole cache lines, within `size` (the driver's ranges, whole 64-byte
    slots at 64-byte aligned addresses, are already whole lines)."""
    start = offset - offset % line
    end = min(size, -(-(offset + length) // line) * line)
    return start, end - start


class ArrayMemory:
    """An in-process array as the ring's memory: the tests and the simulator. `array` is the
    device's side (writable: the simulator's memory model, or a test, writes frames into it);
    view() gives the CPU's side, read-only. invalidate() does no cache work (there is none to do)
    but checks the range and counts the calls and bytes (`invalidations`, `invalidated_bytes`)."""

    def __init__(self, size: int, phys_addr: int = 0, array: np.ndarray | None = None) -> None:
        size, phys_addr = operator.index(size), operator.index(phys_addr)
        if size <= 0:
            raise ValueError(f"memory size {size} is not positive")
        if phys_addr < 0:
            raise ValueError(f"physical address {phys_addr:#x} is negative")
        if array is None:
            array = np.zeros(size, dtype=np.uint8)
        if array.dtype != np.uint8 or array.ndim != 1 or len(array) != size:
            raise ValueError(f"array must be {size} uint8 bytes, got {array.dtype} {array.shape}")
        self.array = array
        self.phys_addr = phys_addr
        self.size = size
        self.invalidations = 0
        self.invalidated_bytes = 0

    @classmethod
    def allocate(cls, size: int, phys_addr: int = 0) -> ArrayMemory:
        return cls(size, phys_addr)

    def invalidate(self, offset: int, length: int) -> None:
        offset, length = check_range(offset, length, self.size)
        self.invalidations += 1
        self.invalidated_bytes += length

    def view(self, offset: int, length: int) -> np.ndarray:
        offset, length = check_range(offset, length, self.size)
        v = self.array[offset : offset + length]
        v = v.view()
        v.flags.writeable = False
        return v

    def close(self) -> None:
        pass


def _read_attr(path: Path) -> str:
    try:
        return path.read_text().strip()
    except OSError as exc:
        raise FileNotFoundError(f"cannot read {path}: {exc}. Is the u-dma-buf module loaded (insmod "
                                "u-dma-buf.ko udmabuf0=SIZE)? docs/driver.md, Features from DDR") from None  # fmt: skip


class UDmaBuf:
    """The u-dma-buf kernel module's buffer `name` (/dev/<name>, /sys/class/u-dma-buf/<name>/) as
    the ring's memory.

    Opened read-only and without O_SYNC, so the mapping is cached (u-dma-buf's "manual cache
    management with the CPU cache still being enabled"; on ARM its quirk-mmap, on by default, is
    what keeps the mapping cached); `phys_addr` and `size` are read from sysfs. invalidate()
    writes the one-shot command `0x<offset:08X><size | DMA_FROM_DEVICE << 2 | 1:08X>` to
    `sync_for_cpu` (one pwrite on a descriptor kept open), on which the module calls
    dma_sync_single_for_cpu(phys_addr + offset, size, DMA_FROM_DEVICE): the CPU's caches drop the
    range's lines, and the next loads read what the device wrote. The range is widened to whole
    cache lines. When the module says the device is DMA-coherent (`dma_coherent` 1: the buffer
    is reached through the ACP) the module does no cache work; invalidate() still writes the
    command, which costs a system call. `syncs` counts the commands written.

    The sysfs and /dev directories are parameters (the tests run it on a fake tree: a regular file
    as the device, a regular file as sync_for_cpu)."""

    def __init__(self, name: str = UDMABUF_NAME, sysfs: Path = SYSFS_UDMABUF, dev: Path = Path("/dev")) -> None:
        self.name = name
        attrs = Path(sysfs) / name
        self.phys_addr = int(_read_attr(attrs / "phys_addr"), 16)
        self.size = int(_read_attr(attrs / "size"), 0)
        coherent = attrs / "dma_coherent"
        self.dma_coherent = coherent.exists() and _read_attr(coherent) == "1"
        if self.size <= 0:
            raise ValueError(f"u-dma-buf {name}: size {self.size}")
        self.path = Path(dev) / name
        self.syncs = 0
        self._fd: int | None = None
        self._sync_fd: int | None = None
        self._mm: mmap.mmap | None = None
        self._bytes: np.ndarray | None = None
        try:
            self._fd = os.open(self.path, os.O_RDONLY | os.O_CLOEXEC)  # no O_SYNC: the mapping stays cached
            self._sync_fd = os.open(attrs / "sync_for_cpu", os.O_WRONLY | os.O_CLOEXEC)
            self._mm = mmap.mmap(self._fd, self.size, mmap.MAP_SHARED, mmap.PROT_READ)
            self._bytes = np.frombuffer(self._mm, dtype=np.uint8)  # read-only: the mapping is PROT_READ
        except PermissionError as exc:
            self.close()
            raise PermissionError(exc.errno, f"cannot open u-dma-buf {name} ({exc.filename}: {exc.strerror}): "
                                  "run as root, or give your group access with a udev rule, e.g. "
                                  'SUBSYSTEM=="u-dma-buf", GROUP="orb", MODE="0660" (docs/driver.md)'
                                  ) from None  # fmt: skip
        except BaseException:
            self.close()
            raise

    @staticmethod
    def command(offset: int, length: int) -> int:
        """The one-shot sync_for_cpu command for DMA_FROM_DEVICE over offset .. offset + length - 1
        (length a multiple of 16, offset below 2^32)."""
        if length & ~_SYNC_SIZE_MASK or offset >> 32:
            raise ValueError(f"u-dma-buf sync of {length} bytes at {offset:#x}: size must be a multiple of 16 "
                             "below 4 GiB, offset below 4 GiB")  # fmt: skip
        return offset << 32 | length | _DMA_FROM_DEVICE << 2 | 1

    def invalidate(self, offset: int, length: int) -> None:
        if type(offset) is not int or type(length) is not int:
            offset, length = operator.index(offset), operator.index(length)
        if offset < 0 or length < 0 or offset + length > self.size:
            check_range(offset, length, self.size)  # raises
        if length == 0:
            return
        if self._sync_fd is None:
            raise ValueError(f"u-dma-buf {self.name} is closed")
        if offset % CACHE_LINE or length % CACHE_LINE:  # the driver's ranges are whole slots: whole lines
            offset, length = line_range(offset, length, self.size)
        os.pwrite(self._sync_fd, b"0x%016X\n" % self.command(offset, length), 0)
        self.syncs += 1

    def view(self, offset: int, length: int) -> np.ndarray:
        if type(offset) is not int or type(length) is not int:
            offset, length = operator.index(offset), operator.index(length)
        if offset < 0 or length < 0 or offset + length > self.size:
            check_range(offset, length, self.size)  # raises
        if self._bytes is None:
            raise ValueError(f"u-dma-buf {self.name} is closed")
        return self._bytes[offset : offset + length]

    def close(self) -> None:
        """Unmap and close; calling it again does nothing (views taken before must be gone)."""
        self._bytes = None
        if self._mm is not None:
            mm, self._mm = self._mm, None
            mm.close()
        for attr in ("_sync_fd", "_fd"):
            fd = getattr(self, attr)
            if fd is not None:
                setattr(self, attr, None)
                os.close(fd)

    def __enter__(self) -> UDmaBuf:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.close()


class PynqMemory:
    """A pynq.allocate buffer (a PynqBuffer: a numpy array with `physical_address`, `invalidate()`)
    as the ring's memory. invalidate() calls invalidate() on the uint8 slice of the range, which
    PYNQ turns into a sync of the buffer object from the device (pynq 3.0.1: xclSyncBO over that
    offset and size; pynq 4.0.0: bo.sync of the whole buffer, whatever the slice). Allocate it
    cacheable (orb_accel.pynq_driver.allocate_ring does), or every CPU read of it is uncached."""

    def __init__(self, buffer: Any) -> None:
        self.buffer = buffer
        self._bytes = np.asarray(buffer).reshape(-1).view(np.uint8)
        self._slices = buffer.reshape(-1).view(np.uint8)  # PynqBuffer slices keep the buffer object and offset
        self.phys_addr = int(buffer.physical_address)
        self.size = int(self._bytes.size)

    def invalidate(self, offset: int, length: int) -> None:
        offset, length = check_range(offset, length, self.size)
        if length:
            self._slices[offset : offset + length].invalidate()

    def view(self, offset: int, length: int) -> np.ndarray:
        offset, length = check_range(offset, length, self.size)
        v = self._bytes[offset : offset + length].view(np.ndarray)
        v.flags.writeable = False
        return v

    def close(self) -> None:
        free = getattr(self.buffer, "freebuffer", None)
        self._bytes = self._slices = None  # type: ignore[assignment]
        if free is not None:
            free()


MEMORY_SPECS = ("udmabuf[:NAME]", "array[:PHYS]", "pynq")


def memory_factory(spec: str | None, board: bool = True, bus: object | None = None) -> MemoryFactory:
    """What OrbAccel(memory=) takes for a command line's `--ddr-memory SPEC` (None: the default,
    `udmabuf` on the board; on a simulator the simulated DDR of `bus` when it has one (a
    SocketBus whose server reports a DDR region: orb_accel.socket_bus.SocketMemory), else `array`):
    `udmabuf[:NAME]` the u-dma-buf buffer NAME (default udmabuf0), `array[:PHYS]` an in-process
    array at bus address PHYS (default 0), `pynq` a pynq.allocate buffer. The factory opens its
    memory only when called: only for an accelerator that writes its features to DDR."""
    if spec is None and not board and getattr(bus, "memory_region", None) is not None:
        from .socket_bus import SocketMemory  # the simulator's DDR, read over the socket

        return lambda _size: SocketMemory(bus)  # type: ignore[arg-type]
    if spec is None:
        spec = "udmabuf" if board else "array"
    kind, _, arg = spec.partition(":")
    if kind == "udmabuf":
        name = arg or UDMABUF_NAME
        return lambda _size: UDmaBuf(name)
    if kind == "array":
        try:
            phys = int(arg, 0) if arg else 0
        except ValueError:
            raise ValueError(f"--ddr-memory {spec!r}: PHYS must be an address, e.g. array:0x10000000") from None
        return lambda size: ArrayMemory(size, phys)
    if kind == "pynq" and not arg:
        return _pynq_ring
    raise ValueError(f"--ddr-memory {spec!r} is not one of {', '.join(MEMORY_SPECS)}")


def _pynq_ring(size: int) -> FrameMemory:
    from .pynq_driver import allocate_ring  # imports pynq: only under PYNQ, only for a DDR build

    return allocate_ring(size)
