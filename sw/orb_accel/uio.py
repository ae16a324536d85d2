# SPDX-License-Identifier: MIT
"""The driver's bus on the board: the accelerator as a Linux UIO device (docs/uio.md).

The device-tree overlay (vivado/linux/orb-accel-*.dtso) declares the accelerator as a
`generic-uio` node named UIO_NAME; with the kernel argument `uio_pdrv_genirq.of_id=generic-uio`
it appears as /dev/uioN, with /sys/class/uio/uioN/name = UIO_NAME and its register window as
map 0. `UioBus.open()` finds it, maps the window and takes the interrupt from the same file:

    with UioBus.open() as bus:
        accel = OrbAccel(bus)

Register access: every read32/write32 is one typed 32-bit load or store through a numpy uint32
view of the mmap (`int(view[i])`, `view[i] = np.uint32(v)`), never a slice of the mmap object
(that goes through memcpy, which may split or merge accesses). read_block has two modes, see
MappedWindow.

AXI errors: on the board an error response (SLVERR or DECERR) to a CPU load or store is a
synchronous external abort. Linux delivers SIGBUS to the process and Python cannot turn it into
an exception: the interpreter dies. So this backend checks alignment and range before every
access (ValueError), and the driver (orb_accel.driver) refuses writes to read-only registers and
illegal values before they reach the bus. (The socket simulation backend, orb_accel.socket_bus,
returns the response as orb_accel.bus.BusError instead.) To get a Python traceback if it happens
anyway, run `python3 -X faulthandler` or call `faulthandler.enable()`.

The interrupt protocol is UioInterrupt, on the device's own file descriptor or on another one:
the PYNQ backend (orb_accel.pynq_bus) waits on the UIO device that holds the accelerator's
interrupt line, found through /proc/interrupts (find_uio_irq), while it reaches the registers
through pynq.MMIO.

The sysfs and /dev directories are parameters (find_uio, find_uio_irq, UioBus.open) and the interrupt
file descriptor can be given apart from the map (UioBus(irq_fd=...)): that is what lets the tests run
against a fake device (tb/driver/test_uio_bus.py: a temporary sysfs tree, a regular file as the
map and a socket pair as the interrupt). numpy and the standard library only.
"""

from __future__ import annotations

import math
import mmap
import operator
import os
import select
import struct
import time
from pathlib import Path
from types import TracebackType

import numpy as np

# The device-tree node name of the accelerator: vivado/board.json "accel"/"dt_name", the node of
# the generated overlays vivado/linux/orb-accel-*.dtso. tb/driver/test_uio_bus.py checks that the
# two agree.
UIO_NAME = "orb-accel"
SYSFS_UIO = Path("/sys/class/uio")
PROC_INTERRUPTS = Path("/proc/interrupts")
BLOCK_MODES = ("copy", "words")
_U32 = struct.Struct("=I")  # the UIO interrupt protocol's words are native-endian 32-bit integers
_ENABLE = _U32.pack(1)  # the word that re-enables the interrupt
_HINT = ("check that the device-tree overlay (vivado/linux/orb-accel-*.dtso) is loaded and that the kernel "
         "command line has uio_pdrv_genirq.of_id=generic-uio (docs/uio.md)")  # fmt: skip


def _uio_number(path: Path) -> tuple[int, str]:
    digits = path.name[3:]
    return (int(digits), "") if digits.isdigit() else (1 << 30, path.name)


def find_uio(name: str = UIO_NAME, sysfs: Path = SYSFS_UIO) -> tuple[str, int]:
    """("uioN", size of its map 0 in bytes) of the UIO device called `name` under `sysfs`.

    FileNotFoundError (listing the devices found) when there is none; RuntimeError when several
    devices have that name."""
    found: list[tuple[str, str]] = []
    for d in sorted(Path(sysfs).glob("uio*"), key=_uio_number):
        try:
            found.append((d.name, (d / "name").read_text().strip()))
        except OSError:
            continue
    matches = [dev for dev, dev_name in found if dev_name == name]
    if not matches:
        seen = ", ".join(f"{dev} ({dev_name!r})" for dev, dev_name in found) if found else "no UIO devices at all"
        raise FileNotFoundError(f"no UIO device named {name!r} in {sysfs}; found: {seen}. {_HINT}")
    if len(matches) > 1:
        raise RuntimeError(f"{len(matches)} UIO devices named {name!r} in {sysfs}: {', '.join(matches)}")
    dev = matches[0]
    size_file = Path(sysfs) / dev / "maps" / "map0" / "size"
    try:
        size = int(size_file.read_text().strip(), 0)
    except (OSError, ValueError) as exc:
        raise FileNotFoundError(f"UIO device {dev} ({name!r}): no readable map 0 size ({size_file}: {exc})") from None
    return dev, size


def find_uio_irq(irq: int, interrupts: Path = PROC_INTERRUPTS, sysfs: Path = SYSFS_UIO) -> tuple[str, str]:
    """("uioN", its name) of the UIO device that holds the interrupt whose hardware number is `irq`
    (the GIC's interrupt ID: IRQ_F2P[0] of a Zynq-7000 is 61), found as PYNQ finds it: the line of
    `interrupts` whose hardware-irq column (third from the end: `47:  0  0  GIC-0  61 Level  fabric`)
    is `irq` names the action, which for generic-uio is the UIO device's name, then find_uio.

    FileNotFoundError when no line has that number (the line is not requested by anyone) or no UIO
    device has the name; RuntimeError when several lines have it."""
    try:
        text = Path(interrupts).read_text()
    except OSError as exc:
        raise FileNotFoundError(f"cannot read {interrupts}: {exc}") from None
    names = [cols[-1] for line in text.splitlines() if len(cols := line.split()) >= 4 and cols[-3] == str(irq)]
    if not names:
        raise FileNotFoundError(
            f"no interrupt with hardware number {irq} in {interrupts}: no driver holds that line; a generic-uio "
            "node with it is missing (on a PYNQ image: the boot device tree's `fabric`; docs/pynq.md)"
        )
    if len(names) > 1:
        raise RuntimeError(f"{len(names)} lines of {interrupts} have hardware interrupt {irq}: {', '.join(names)}")
    dev, _ = find_uio(names[0], sysfs)
    return dev, names[0]


def word_index(addr: int, count: int, size: int) -> int:
    """Word index of byte address `addr`, after checking that `count` 32-bit words from it lie in a
    window of `size` bytes (ValueError otherwise: an access the bus answers with an error is a
    SIGBUS on the board, see the module docstring)."""
    addr, count = operator.index(addr), operator.index(count)
    if addr % 4:
        raise ValueError(f"address {addr:#x} is not 32-bit aligned")
    if count < 0:
        raise ValueError(f"block of {count} words")
    if addr < 0 or addr + 4 * max(count, 1) > size:
        what = f"address {addr:#x}" if count <= 1 else f"block of {count} words at {addr:#x}"
        raise ValueError(f"{what} outside the map of {size:#x} bytes")
    return addr // 4


def check_value(addr: int, value: int) -> int:
    """`value` as an int, after checking it is a 32-bit value (ValueError otherwise)."""
    value = operator.index(value)
    if not 0 <= value <= 0xFFFFFFFF:
        raise ValueError(f"value {value:#x} at {addr:#x} is not a 32-bit value")
    return value


class UioInterrupt:
    """The UIO interrupt protocol on a file descriptor of a UIO device (docs/uio.md, "The interrupt").

    `fd`: the descriptor (`owns_fd`: close() closes it); `path` names the device in messages.
    `count`: the kernel's event count read by the last successful wait (None before).
    `missed`: interrupts that fired between two waits beyond the one expected: when the count jumps
    by k > 1 from one read to the next, k - 1 are added. (The first read only sets the baseline:
    the kernel counts from when the device appeared, not from when it was opened.)"""

    def __init__(self, fd: int, path: str | os.PathLike, owns_fd: bool = False) -> None:
        self.fd: int | None = fd
        self.path = os.fspath(path)
        self.owns_fd = owns_fd
        self.count: int | None = None
        self.missed = 0
        self._poller: select.poll | None = None

    @classmethod
    def open(cls, path: str | os.PathLike) -> UioInterrupt:
        """The interrupt of the UIO device file `path`, on a descriptor of its own."""
        try:
            fd = os.open(path, os.O_RDWR | os.O_CLOEXEC)
        except PermissionError as exc:
            raise PermissionError(exc.errno, f"cannot open {os.fspath(path)} ({exc.strerror}): run as root, or "
                                  "give your group access with a udev rule (docs/uio.md)") from None  # fmt: skip
        return cls(fd, path, owns_fd=True)

    def wait(self, timeout_s: float) -> bool:
        """Re-enable the interrupt, then wait up to `timeout_s` seconds (<= 0: look once) for it.

        The UIO protocol: the kernel's generic-uio handler disables the interrupt line when it
        fires; writing a 32-bit 1 enables it again. The file becomes readable when the interrupt
        has fired; a read gives exactly 4 bytes, the event count. The accelerator's line is a level
        (OR of IRQ_STATUS AND IRQ_ENABLE), so it must be acknowledged (the driver writes
        IRQ_STATUS) before the next wait, or it fires again at once."""
        if self.fd is None:
            raise ValueError(f"the interrupt of {self.path} is closed")
        fd = self.fd
        try:
            os.write(fd, _ENABLE)
        except OSError as exc:
            raise OSError(exc.errno, f"cannot enable the interrupt of {self.path} ({exc.strerror}); does the "
                          "device-tree node have an interrupts property? (docs/uio.md)") from None  # fmt: skip
        poller = self._poller
        if poller is None:  # one poll object for the descriptor, made at the first wait
            poller = self._poller = select.poll()
            poller.register(fd, select.POLLIN)
        deadline = time.monotonic() + max(timeout_s, 0.0)
        while True:
            # Python retries poll() after EINTR itself (PEP 475); the loop also covers a signal
            # handler that raises InterruptedError, with the remaining time
            ms = max(0, math.ceil((deadline - time.monotonic()) * 1000))
            try:
                events = poller.poll(ms)
            except InterruptedError:
                continue
            break
        if not events:
            return False
        data = os.read(fd, _U32.size)
        if len(data) != _U32.size:
            raise OSError(f"interrupt read on {self.path} returned {len(data)} bytes, not the 4-byte event count")
        count = _U32.unpack(data)[0]
        if self.count is not None:
            jump = (count - self.count) & 0xFFFFFFFF
            if jump > 1:
                self.missed += jump - 1
        self.count = count
        return True

    def close(self) -> None:
        """Close the descriptor if it is ours; calling it again does nothing."""
        fd, self.fd, self._poller = self.fd, None, None
        if fd is not None and self.owns_fd:
            os.close(fd)


class MappedWindow:
    """The accelerator's register window mmap'd from a device file, as 32-bit words.

    Shared by UioBus and orb_accel.devmem.DevMemBus (which add the interrupt). read32/write32
    are single typed 32-bit accesses through a numpy uint32 view of the mmap, after checking
    that the address is 4-aligned and inside the map (ValueError otherwise: an access the bus
    would answer with an error is a SIGBUS on the board, see the module docstring).

    read_block(addr, count) returns a new uint32 array; `block_mode` chooses how it loads:
    - "copy" (default): a numpy copy of the view's slice. libc's memcpy may merge neighbouring
      words into wider loads; the Zynq's AXI interconnect splits them into 32-bit AXI4-Lite
      reads. The feature-memory window has no read side effects (docs/registers.md, Bus rules:
      a read there only pulses mem_rd_en), so a merged or repeated read there is harmless.
    - "words": one typed 32-bit load per word in a Python loop (slower), for users who want
      single 32-bit loads guaranteed.
    Registers (read32) always use single loads.

    `reads` and `writes` count 32-bit accesses (a block of n words counts n reads)."""

    def __init__(self, path: str | os.PathLike, size: int, offset: int, flags: int, block_mode: str = "copy") -> None:
        if block_mode not in BLOCK_MODES:
            raise ValueError(f"block_mode {block_mode!r} not one of {BLOCK_MODES}")
        size = operator.index(size)
        if size <= 0 or size % 4:
            raise ValueError(f"map size {size:#x} is not a positive multiple of 4 bytes")
        self.path = os.fspath(path)
        self.size = size
        self.block_mode = block_mode
        self.reads = self.writes = 0
        self._fd: int | None = None
        self._mm: mmap.mmap | None = None
        self._view: np.ndarray | None = None
        self._fd = os.open(self.path, flags)  # PermissionError is reworded by the subclasses
        try:
            self._mm = mmap.mmap(self._fd, size, mmap.MAP_SHARED, mmap.PROT_READ | mmap.PROT_WRITE, offset=offset)
            self._view = np.frombuffer(self._mm, dtype=np.uint32)
        except BaseException:
            self.close()
            raise

    # ---- checks --------------------------------------------------------------------------------
    def _words(self) -> np.ndarray:
        if self._view is None:
            raise ValueError(f"{type(self).__name__} on {self.path} is closed")
        return self._view

    def _index(self, addr: int, count: int = 1) -> int:
        """Word index of byte address `addr`, after checking that `count` words from it lie in the map."""
        return word_index(addr, count, self.size)

    # ---- the bus -------------------------------------------------------------------------------
    def read32(self, addr: int) -> int:
        view = self._view
        if view is None:
            view = self._words()  # raises: closed
        if type(addr) is int and not addr & 3 and 0 <= addr <= self.size - 4:  # the checks of word_index
            i = addr >> 2
        else:
            i = self._index(addr)  # another integer type, or raises naming what is wrong
        self.reads += 1
        return int(view[i])

    def write32(self, addr: int, value: int) -> None:
        view = self._view
        if view is None:
            view = self._words()  # raises: closed
        if type(addr) is int and not addr & 3 and 0 <= addr <= self.size - 4:
            i = addr >> 2
        else:
            i = self._index(addr)
        if type(value) is not int or not 0 <= value <= 0xFFFFFFFF:
            value = check_value(addr, value)
        self.writes += 1
        view[i] = np.uint32(value)

    def read_block(self, addr: int, count: int) -> np.ndarray:
        view = self._words()
        i = self._index(addr, count)
        self.reads += count
        if self.block_mode == "copy":
            return view[i : i + count].copy()
        out = np.empty(count, dtype=np.uint32)
        for k in range(count):
            out[k] = view[i + k]
        return out

    # ---- lifetime ------------------------------------------------------------------------------
    @property
    def closed(self) -> bool:
        return self._view is None and self._mm is None and self._fd is None

    def close(self) -> None:
        """Release the view, the mapping and the file descriptor; calling it again does nothing."""
        # np.frombuffer holds an export of the mmap: mmap.close() raises BufferError until it is gone
        self._view = None
        if self._mm is not None:
            mm, self._mm = self._mm, None
            mm.close()
        if self._fd is not None:
            fd, self._fd = self._fd, None
            os.close(fd)

    def __enter__(self) -> MappedWindow:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.close()


class UioBus(MappedWindow):
    """orb_accel.bus.Bus on a UIO device: map 0 of `device` (`size` bytes) and its interrupt.

    The interrupt is taken from the device's own file descriptor unless `irq_fd` is given (the
    caller keeps ownership of it; the tests pass one end of a socket pair). `irq` is its
    UioInterrupt; `irq_count` and `irq_missed` are its event count and missed interrupts."""

    def __init__(self, device: str | os.PathLike, size: int, irq_fd: int | None = None,
                 block_mode: str = "copy") -> None:  # fmt: skip
        try:
            # map 0 of a UIO device is at offset 0 * page size; UIO maps are uncached without O_SYNC
            super().__init__(device, size, 0, os.O_RDWR | os.O_CLOEXEC, block_mode)
        except PermissionError as exc:
            raise PermissionError(
                exc.errno,
                f"cannot open {os.fspath(device)} ({exc.strerror}): run as root, or add a udev rule giving "
                f'your group access, e.g. SUBSYSTEM=="uio", ATTR{{name}}=="{UIO_NAME}", GROUP="orb", MODE="0660" '
                "(docs/uio.md)",
            ) from None
        assert self._fd is not None
        self.irq = UioInterrupt(self._fd if irq_fd is None else irq_fd, self.path)

    @property
    def irq_count(self) -> int | None:
        """The kernel's event count read by the last successful wait_irq (None before)."""
        return self.irq.count

    @property
    def irq_missed(self) -> int:
        """Interrupts that fired between two wait_irq calls beyond the one expected (UioInterrupt)."""
        return self.irq.missed

    @classmethod
    def open(cls, name: str = UIO_NAME, sysfs: Path = SYSFS_UIO, dev: Path = Path("/dev"),
             block_mode: str = "copy") -> UioBus:  # fmt: skip
        """The UIO device called `name` (find_uio), mapped whole."""
        device, size = find_uio(name, sysfs)
        return cls(Path(dev) / device, size, block_mode=block_mode)

    def wait_irq(self, timeout_s: float) -> bool:
        """Re-enable the interrupt, then wait up to `timeout_s` seconds (<= 0: look once) for it
        (UioInterrupt.wait: the UIO protocol)."""
        if self.irq.fd is None:
            raise ValueError(f"UioBus on {self.path} is closed")
        return self.irq.wait(timeout_s)

    def close(self) -> None:
        """Release the view, the mapping and the device's file descriptor (not an irq_fd the
        caller gave); calling it again does nothing."""
        self.irq.close()  # never owns the descriptor: the map's is closed below, a caller's stays open
        super().close()

    def __enter__(self) -> UioBus:
        return self
