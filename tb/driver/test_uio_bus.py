# SPDX-License-Identifier: MIT
"""The board-side bus backends of orb_accel (docs/uio.md) against a fake device.

Nothing here touches real hardware. The fake UIO device: a temporary sysfs tree (uio0 named
"orb-accel", uio1 another device), a regular 1 MiB file as map 0 and one end of a socket pair as
the interrupt file descriptor, with a thread playing the kernel on the other end (it takes the
4-byte enable write, then answers with the 4-byte event count). The map holds what a real
accelerator shows: ID, VERSION, the CFG_* read-back, STATUS and one bank of features of a
photograph, extracted by the golden model and encoded with the one slot codec
(golden_model.featcodec). The /dev/mem backend runs against a regular file with the window at a
page-aligned offset.

- find_uio: by name among several devices; the errors list what was found (or say nothing was);
- UioBus under the real driver: ID and configuration, a bank read back equal to the model's
  features, the access counters; the interrupt protocol (enable write, event count, timeout,
  missed events, a short read), next_frame acknowledging and releasing, TimeoutError with the
  status registers;
- every bad address or value is a ValueError before any access; both block modes agree;
- DevMemBus: ID, polled interrupt (status AND enable), the timeout, page alignment;
- close() is idempotent and closes the descriptor it opened (not the caller's);
- UIO_NAME is the device-tree name of vivado/board.json and the generated overlays.
"""

from __future__ import annotations

import json
import mmap
import os
import socket
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from golden_model import regs
from golden_model.config import Config
from golden_model.featcodec import encode_eof, encode_feature, feature_slot, record_slot
from golden_model.featmem import SLOT_BYTES, SLOT_RECORD_WORDS, SLOT_WORDS_USED
from golden_model.features import Features, first_difference
from golden_model.frameparams import FrameParams
from golden_model.latency import FEAT_MEM_READ_LAT
from golden_model.pipeline import extract
from orb_accel import UIO_NAME, DevMemBus, OrbAccel, UioBus, find_uio
from orb_accel import uio as uio_module
from orbtb.images import photo

ROOT = Path(__file__).resolve().parents[2]
W, H, SCALES, SECTORS, DEPTH = 128, 96, 2, 32, 2048
MAP_SIZE = 0x100000
FRAME = 7
# the parameters the frame's record says it was made with (the registers show others: the record wins)
PARAMS = FrameParams(threshold=31, threshold_lo=9, mode="orb", selection="grid", budget=100, cols=5, rows=4)
SLOT_WORDS = SLOT_BYTES // 4
ENABLE = (1).to_bytes(4, sys.byteorder)  # b"\x01\x00\x00\x00" on the little-endian ARM and x86
# BANK_RELEASE is write-only on the device; the file starts with a mark the driver's write must replace
RELEASE_MARK = 0xFFFFFFFF
WAIT_S = 0.05


@cache
def model_features() -> Features:
    return extract(photo("astronaut", W, H), Config(W, H, scales=SCALES, sectors=SECTORS))


def put(words: np.ndarray, reg: regs.Register, **fields: int) -> None:
    value = 0
    for name, v in fields.items():
        value = reg.field(name).put(v, value)
    words[reg.offset // 4] = value


def device_words(feats: Features) -> np.ndarray:
    """The 32-bit words a real accelerator shows (registers and bank 0 holding `feats`)."""
    n = len(feats)
    words = np.zeros(MAP_SIZE // 4, dtype=np.uint32)
    put(words, regs.ID, magic=regs.ORB_ID)
    put(words, regs.VERSION, major=regs.VERSION_MAJOR, minor=regs.VERSION_MINOR)
    put(words, regs.CFG_SIZE, width=W, height=H)
    put(words, regs.CFG_ORB, scales=SCALES, sectors=SECTORS, banks=regs.BANKS)
    put(words, regs.CFG_MEM, depth=DEPTH, latency=FEAT_MEM_READ_LAT)  # orb_accel_top's MEM_LATENCY_g
    put(words, regs.CTRL, enable=1, mode=0)  # mode 0: orb
    put(words, regs.THRESHOLD, threshold=20)
    put(words, regs.STATUS, bank_ready=0b01, last_bank=0)
    put(words, regs.IRQ_ENABLE, frame_done=1)
    put(words, regs.BANK0_INFO, count=n, frame=FRAME)
    words[regs.BANK_RELEASE.offset // 4] = RELEASE_MARK
    base = (regs.MEM_BASE + 0 * DEPTH * SLOT_BYTES) // 4  # bank 0
    for s in range(n):
        beat = encode_feature(scale=int(feats.scale[s]), x=int(feats.x[s]), y=int(feats.y[s]),
                              score=int(feats.score[s]), sector=int(feats.sector[s]),
                              descriptor=bytes(feats.descriptor[s]), response=int(feats.response[s]),
                              low=int(feats.low[s]))  # fmt: skip
        words[base + s * SLOT_WORDS : base + (s + 1) * SLOT_WORDS] = feature_slot(beat)
    words[base + n * SLOT_WORDS : base + (n + 1) * SLOT_WORDS] = record_slot(encode_eof(FRAME, 0, PARAMS), n, 0)
    return words


def word_at(path: Path, offset: int) -> int:
    with path.open("rb") as f:
        f.seek(offset)
        return int.from_bytes(f.read(4), sys.byteorder)


def set_word(path: Path, offset: int, value: int) -> None:
    with path.open("r+b") as f:
        f.seek(offset)
        f.write(value.to_bytes(4, sys.byteorder))


@dataclass
class FakeDevice:
    sysfs: Path
    dev: Path
    map_file: Path  # dev / "uio0"
    irq: socket.socket  # the bus's end
    kernel: socket.socket  # the fake kernel's end


def make_sysfs(root: Path, devices: dict[str, tuple[str, int]]) -> Path:
    sysfs = root / "sys" / "class" / "uio"
    sysfs.mkdir(parents=True)
    for dev, (name, size) in devices.items():
        (sysfs / dev / "maps" / "map0").mkdir(parents=True)
        (sysfs / dev / "name").write_text(name + "\n")
        (sysfs / dev / "maps" / "map0" / "size").write_text(f"{size:#010x}\n")
    return sysfs


@pytest.fixture
def device(tmp_path: Path) -> Iterator[FakeDevice]:
    sysfs = make_sysfs(tmp_path, {"uio0": (UIO_NAME, MAP_SIZE), "uio1": ("axi-gpio", 0x1000)})
    dev = tmp_path / "dev"
    dev.mkdir()
    map_file = dev / "uio0"
    device_words(model_features()).tofile(map_file)
    irq, kernel = socket.socketpair()
    yield FakeDevice(sysfs, dev, map_file, irq, kernel)
    irq.close()
    kernel.close()


class FakeKernel:
    """The kernel's side of the UIO interrupt: for each entry of `counts`, take the 4-byte enable
    write, then send the event count (None: no event; bytes: sent as they are)."""

    def __init__(self, sock: socket.socket, counts: list[int | bytes | None]) -> None:
        self.sock, self.counts = sock, counts
        self.enables: list[bytes] = []
        self.errors: list[BaseException] = []
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        self.sock.settimeout(5.0)
        try:
            for count in self.counts:
                data = b""
                while len(data) < 4:
                    chunk = self.sock.recv(4 - len(data))
                    if not chunk:
                        raise ConnectionError("the bus closed its end")
                    data += chunk
                self.enables.append(data)
                if isinstance(count, int):
                    self.sock.sendall(count.to_bytes(4, sys.byteorder))
                elif isinstance(count, bytes):
                    self.sock.sendall(count)
        except BaseException as exc:  # reported by join()
            self.errors.append(exc)

    def join(self) -> None:
        self.thread.join(10.0)
        assert not self.thread.is_alive(), "the fake kernel is still waiting for an enable write"
        assert not self.errors, f"fake kernel: {self.errors}"
        assert self.enables == [ENABLE] * len(self.counts), f"enable writes {self.enables}, expected {ENABLE!r} each"


def uio_bus(d: FakeDevice, **kw) -> UioBus:
    return UioBus(d.map_file, MAP_SIZE, irq_fd=d.irq.fileno(), **kw)


# ------------------------------------------------------------------------------------------------
# finding the device


def test_uio_name_is_the_device_tree_name() -> None:
    board = json.loads((ROOT / "vivado" / "board.json").read_text())
    assert board["accel"]["dt_name"] == UIO_NAME
    overlays = sorted((ROOT / "vivado" / "linux").glob("orb-accel-*.dtso"))
    assert overlays
    for path in overlays:
        assert f"\t{UIO_NAME}@" in path.read_text(), f"{path.name} has no node {UIO_NAME}@..."


def test_find_uio_by_name(device: FakeDevice) -> None:
    assert find_uio(sysfs=device.sysfs) == ("uio0", MAP_SIZE)
    assert find_uio("axi-gpio", device.sysfs) == ("uio1", 0x1000)


def test_find_uio_missing_lists_what_was_found(device: FakeDevice) -> None:
    with pytest.raises(FileNotFoundError) as err:
        find_uio("orb-accel-nope", device.sysfs)
    msg = str(err.value)
    for text in ("orb-accel-nope", "uio0", f"'{UIO_NAME}'", "uio1", "'axi-gpio'", "uio_pdrv_genirq.of_id=generic-uio"):
        assert text in msg, f"{text!r} not in: {msg}"


@pytest.mark.parametrize("exists", [True, False])
def test_find_uio_none_at_all(tmp_path: Path, exists: bool) -> None:
    sysfs = tmp_path / "uio"
    if exists:
        sysfs.mkdir()
    with pytest.raises(FileNotFoundError, match="no UIO devices at all"):
        find_uio(sysfs=sysfs)


def test_find_uio_twice_the_name(tmp_path: Path) -> None:
    sysfs = make_sysfs(tmp_path, {"uio0": (UIO_NAME, MAP_SIZE), "uio3": (UIO_NAME, MAP_SIZE)})
    with pytest.raises(RuntimeError, match="uio0, uio3"):
        find_uio(sysfs=sysfs)


def test_open_by_name(device: FakeDevice) -> None:
    with UioBus.open(sysfs=device.sysfs, dev=device.dev) as bus:
        assert bus.size == MAP_SIZE
        assert bus.read32(regs.ID.offset) == regs.ORB_ID


def test_permission_errors_say_what_to_do(device: FakeDevice, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # the tests run as root here, so a file mode cannot refuse: os.open refuses instead
    def refuse(path, flags, *args):
        raise PermissionError(13, "Permission denied", path)

    devmem = tmp_path / "mem"
    devmem.write_bytes(bytes(MAP_SIZE))
    monkeypatch.setattr(uio_module.os, "open", refuse)
    with pytest.raises(PermissionError, match=r"root.*udev rule.*SUBSYSTEM==\"uio\""):
        UioBus.open(sysfs=device.sysfs, dev=device.dev)
    with pytest.raises(PermissionError, match=r"root \(CAP_SYS_RAWIO\).*CONFIG_STRICT_DEVMEM"):
        DevMemBus(0, MAP_SIZE, path=devmem)


# ------------------------------------------------------------------------------------------------
# the driver on UioBus


def test_driver_reads_id_config_and_bank(device: FakeDevice) -> None:
    register_reads: list[int] = []

    class Spy(UioBus):
        def read32(self, addr: int) -> int:
            register_reads.append(addr)
            return super().read32(addr)

    with Spy(device.map_file, MAP_SIZE, irq_fd=device.irq.fileno()) as bus:
        # the fake's bank 0 is READY with its interrupt taken: a looking driver leaves it alone
        accel = OrbAccel(bus, bank_read="slot", release_stale=False)
        assert (accel.hw.width, accel.hw.height, accel.hw.scales, accel.hw.sectors, accel.hw.mem_depth) == (
            W, H, SCALES, SECTORS, DEPTH)  # fmt: skip
        assert accel.mode == "orb"
        reads_before = bus.reads
        register_reads.clear()
        frame = accel.read_bank(0)
        want = model_features()
        diff = first_difference(frame.features, want)
        assert diff is None, diff
        assert len(want) > 20
        assert (frame.record.count, frame.record.frame, frame.record.truncated) == (len(want), FRAME, 0)
        assert frame.params == PARAMS and frame.mode == "orb", (frame.params, frame.mode)
        assert regs.BANK0_INFO.offset in register_reads
        words = len(want) * SLOT_WORDS_USED + SLOT_RECORD_WORDS + len(register_reads)
        assert bus.reads - reads_before == words
        assert bus.writes == 0
        # the default: the bank's whole slots in one block, the same frame
        whole = OrbAccel(bus, release_stale=False)
        reads_before = bus.reads
        register_reads.clear()
        again = whole.read_bank(0)
        assert first_difference(again.features, want) is None and again.record == frame.record
        assert bus.reads - reads_before == (len(want) + 1) * SLOT_BYTES // 4 + len(register_reads)


def test_wait_irq_protocol(device: FakeDevice) -> None:
    with uio_bus(device) as bus:
        kernel = FakeKernel(device.kernel, [3])
        assert bus.wait_irq(5.0)
        kernel.join()
        assert (bus.irq_count, bus.irq_missed) == (3, 0)

        kernel = FakeKernel(device.kernel, [None])
        t0 = time.monotonic()
        assert not bus.wait_irq(WAIT_S)
        elapsed = time.monotonic() - t0
        kernel.join()
        assert WAIT_S * 0.9 <= elapsed < 2.0, f"wait_irq({WAIT_S}) took {elapsed:.3f} s"
        assert bus.irq_count == 3


def test_wait_irq_zero_timeout_looks_once(device: FakeDevice) -> None:
    with uio_bus(device) as bus:
        t0 = time.monotonic()
        assert not bus.wait_irq(0)
        assert time.monotonic() - t0 < 0.5
        device.kernel.sendall((9).to_bytes(4, sys.byteorder))  # an event already pending
        assert bus.wait_irq(0)
        assert bus.irq_count == 9
        assert device.kernel.recv(8) == ENABLE * 2


@pytest.mark.parametrize(("counts", "missed"), [([10, 11, 14], 2), ([0xFFFFFFFE, 0xFFFFFFFF, 1], 1), ([5, 6, 7], 0)])
def test_irq_missed(device: FakeDevice, counts: list[int], missed: int) -> None:
    with uio_bus(device) as bus:
        kernel = FakeKernel(device.kernel, list(counts))
        for _ in counts:
            assert bus.wait_irq(5.0)
        kernel.join()
        assert (bus.irq_count, bus.irq_missed) == (counts[-1], missed)


def test_short_interrupt_read(device: FakeDevice) -> None:
    with uio_bus(device) as bus:
        kernel = FakeKernel(device.kernel, [b"\x01\x00"])
        with pytest.raises(OSError, match="2 bytes"):
            bus.wait_irq(5.0)
        kernel.join()


def test_next_frame_acknowledges_and_releases(device: FakeDevice) -> None:
    # bank 0's frame-done interrupt pending: a frame to take, not a stale bank
    set_word(device.map_file, regs.IRQ_STATUS.offset, regs.IRQ_STATUS.field("frame_done").put(1))
    with uio_bus(device) as bus:
        accel = OrbAccel(bus)
        assert accel.released_at_open == [] and word_at(device.map_file, regs.BANK_RELEASE.offset) == RELEASE_MARK
        kernel = FakeKernel(device.kernel, [1, None])
        frame = accel.next_frame(timeout_s=5.0)
        diff = first_difference(frame.features, model_features())
        assert diff is None, diff
        assert (frame.bank, frame.number) == (0, FRAME)
        assert word_at(device.map_file, regs.BANK_RELEASE.offset) == 0  # was RELEASE_MARK
        set_word(device.map_file, regs.IRQ_STATUS.offset, 0)
        t0 = time.monotonic()
        with pytest.raises(TimeoutError, match="STATUS"):
            accel.next_frame(WAIT_S)
        assert time.monotonic() - t0 < 2.0
        kernel.join()


@pytest.mark.parametrize("release_stale", [True, False])
def test_open_releases_a_dead_predecessors_bank(device: FakeDevice, release_stale: bool) -> None:
    """Bank 0 READY and its interrupt already taken (IRQ_STATUS 0): a process died holding it. The
    driver releases it at open (and counts it); a looking driver (board info) does not."""
    with uio_bus(device) as bus:
        accel = OrbAccel(bus, release_stale=release_stale)
        if release_stale:
            assert accel.released_at_open == [0] and accel.faults.stale_banks == 1
            assert word_at(device.map_file, regs.BANK_RELEASE.offset) == 0  # was RELEASE_MARK
            assert bus.writes == 1
        else:
            assert accel.released_at_open == [] and accel.faults.stale_banks == 0 and bus.writes == 0
            assert word_at(device.map_file, regs.BANK_RELEASE.offset) == RELEASE_MARK


# ------------------------------------------------------------------------------------------------
# checks before every access


@pytest.mark.parametrize(
    ("op", "args", "text"),
    [
        ("read32", (2,), "aligned"),
        ("read32", (MAP_SIZE,), "outside the map of 0x100000"),
        ("read32", (-4,), "outside the map"),
        ("write32", (0x14, 1 << 32), "32-bit value"),
        ("write32", (0x14, -1), "32-bit value"),
        ("write32", (0x16, 0), "aligned"),
        ("write32", (MAP_SIZE + 4, 0), "outside the map"),
        ("read_block", (MAP_SIZE - 8, 3), "block of 3 words"),
        ("read_block", (regs.MEM_BASE + 1, 4), "aligned"),
        ("read_block", (regs.MEM_BASE, -1), "-1 words"),
    ],
)
def test_bad_access_is_refused(device: FakeDevice, op: str, args: tuple[int, ...], text: str) -> None:
    before = device.map_file.read_bytes()
    with uio_bus(device) as bus:
        with pytest.raises(ValueError, match=text):
            getattr(bus, op)(*args)
        assert (bus.reads, bus.writes) == (0, 0)
        assert bus.read32(MAP_SIZE - 4) == 0  # the last word is inside
        assert len(bus.read_block(MAP_SIZE - 8, 2)) == 2
    assert device.map_file.read_bytes() == before


def test_write32_is_one_word(device: FakeDevice) -> None:
    with uio_bus(device) as bus:
        bus.write32(regs.THRESHOLD.offset, 0xA5C3E1F7)
        assert bus.writes == 1
    assert word_at(device.map_file, regs.THRESHOLD.offset) == 0xA5C3E1F7
    assert word_at(device.map_file, regs.THRESHOLD.offset + 4) == regs.STATUS.field("bank_ready").put(1)


def test_block_modes_agree(device: FakeDevice) -> None:
    count = (len(model_features()) + 1) * SLOT_WORDS
    want = np.fromfile(device.map_file, dtype=np.uint32, count=count, offset=regs.MEM_BASE)
    with uio_bus(device, block_mode="copy") as a, uio_bus(device, block_mode="words") as b:
        ca, cb = a.read_block(regs.MEM_BASE, count), b.read_block(regs.MEM_BASE, count)
        assert ca.dtype == cb.dtype == np.uint32
        np.testing.assert_array_equal(ca, want)
        np.testing.assert_array_equal(cb, want)
        assert a.reads == b.reads == count
        ca[0] ^= 1  # a copy, not a view of the map
        assert a.read32(regs.MEM_BASE) == want[0]
    with pytest.raises(ValueError, match="block_mode"):
        uio_bus(device, block_mode="bytes")


# ------------------------------------------------------------------------------------------------
# /dev/mem


@pytest.fixture
def devmem(tmp_path: Path) -> tuple[Path, int]:
    base = 4 * mmap.PAGESIZE
    path = tmp_path / "mem"
    with path.open("wb") as f:
        f.write(bytes(base))
        device_words(model_features()).tofile(f)
    return path, base


def test_devmem_reads_and_polls(devmem: tuple[Path, int]) -> None:
    path, base = devmem
    frame_done = regs.IRQ_STATUS.field("frame_done").put(1)
    with DevMemBus(base, MAP_SIZE, path=path, poll_s=0.002) as bus:
        assert bus.read32(regs.ID.offset) == regs.ORB_ID
        accel = OrbAccel(bus)
        assert accel.hw.mem_depth == DEPTH

        set_word(path, base + regs.IRQ_ENABLE.offset, 0)
        set_word(path, base + regs.IRQ_STATUS.offset, frame_done)  # pending but not enabled: no interrupt
        t0 = time.monotonic()
        assert not bus.wait_irq(WAIT_S)
        elapsed = time.monotonic() - t0
        assert WAIT_S * 0.9 <= elapsed < 2.0, f"wait_irq({WAIT_S}) took {elapsed:.3f} s"

        set_word(path, base + regs.IRQ_ENABLE.offset, frame_done)
        assert bus.wait_irq(0)

        set_word(path, base + regs.IRQ_STATUS.offset, 0)
        timer = threading.Timer(0.1, set_word, (path, base + regs.IRQ_STATUS.offset, frame_done))
        timer.start()
        t0 = time.monotonic()
        assert bus.wait_irq(5.0)
        assert 0.05 < time.monotonic() - t0 < 2.0
        timer.join()


def test_devmem_base_must_be_page_aligned(devmem: tuple[Path, int]) -> None:
    path, base = devmem
    with pytest.raises(ValueError, match="PAGESIZE"):
        DevMemBus(base + 0x100, MAP_SIZE, path=path)


# ------------------------------------------------------------------------------------------------
# lifetime


def test_close_is_idempotent_and_closes_its_fd(device: FakeDevice) -> None:
    bus = uio_bus(device)
    fd = bus._fd
    assert fd is not None
    os.fstat(fd)
    bus.close()
    bus.close()
    with pytest.raises(OSError):
        os.fstat(fd)
    os.fstat(device.irq.fileno())  # the caller's interrupt descriptor stays open
    with pytest.raises(ValueError, match="closed"):
        bus.read32(0)
    with pytest.raises(ValueError, match="closed"):
        bus.wait_irq(0)

    with UioBus.open(sysfs=device.sysfs, dev=device.dev) as own:
        fd = own._fd
        assert fd is not None
    with pytest.raises(OSError):
        os.fstat(fd)


def test_devmem_close(devmem: tuple[Path, int]) -> None:
    path, base = devmem
    bus = DevMemBus(base, MAP_SIZE, path=path)
    fd = bus._fd
    assert fd is not None
    bus.close()
    bus.close()
    with pytest.raises(OSError):
        os.fstat(fd)
