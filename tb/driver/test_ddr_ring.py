# SPDX-License-Identifier: MIT
"""The driver's DDR path (docs/driver.md, "Features from DDR"; docs/feature-dma.md) against a
scripted DDR build (orbtb.scripted_ring: map 3.2, CFG_DDR.ddr = 1, orb_feat_dma's ring rules)
writing into an in-process memory with a model of the CPU's cache, and the memory backends
(orb_accel.ddr) on fake devices. No simulator.

- frames decode bit-exact, equal to the bank path's decoding of the same features;
- the buffers are read in ring order, gaps show in the frame numbers, each is released;
- every broken rule of the ring is refused with ValueError naming it, before a register is
  written; a device that disagrees (RING_STATUS.error) raises AccelError with the bits decoded;
- a frame costs at most a handful of 32-bit bus accesses (<= 64 at a budget of 2,000), two cache
  invalidations (the record, then count * 64 bytes) and no block read;
- faults: a lost interrupt, an error response to the release, a dead predecessor's buffers;
- u-dma-buf's sync command, PYNQ's slice invalidation, --ddr-memory's specs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from golden_model import regs
from golden_model.featmem import SLOT_BYTES, decode_features
from golden_model.featword import SLOT_WORDS_USED
from orb_accel import AccelError, BusError, OrbAccel
from orb_accel.ddr import ArrayMemory, FrameMemory, PynqMemory, UDmaBuf, memory_factory
from orb_accel.ring import DdrWindow, plan_ring, ring_error_text
from orbtb.scripted_accel import ScriptedAccel
from orbtb.scripted_ring import CachedMemory, ScriptedRing, feature_words, random_features

DEPTH = 64
PHYS = 0x1E900000  # where u-dma-buf's Readme shows its buffer (any 64-byte aligned address inside the window)


def ring(n: int = 16, depth: int = DEPTH, count: int | None = None, **kw: int) -> tuple[ScriptedRing, OrbAccel]:
    memory = CachedMemory(n * depth * SLOT_BYTES, PHYS)
    dev = ScriptedRing(memory, depth=depth, **kw)
    accel = OrbAccel(dev, memory=memory, ring_count=count)
    accel.configure(threshold=20, mode="orb")
    return dev, accel


def same(a, b) -> None:
    for name in ("scale", "x", "y", "score", "sector", "descriptor", "response", "low"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert (a.sectors_total, a.step) == (b.sectors_total, b.step)


# ---- decoding --------------------------------------------------------------------------------------
def test_frames_decode_bit_exact_and_as_the_bank_path() -> None:
    feats = random_features(DEPTH - 1, seed=3)
    dev, accel = ring()
    dev.features = feats
    frame = accel.next_frame(0.01)
    assert len(frame) == DEPTH - 1 and frame.mode == "orb" and frame.params == accel.written()
    same(frame.features, feats.sorted())
    # the bank path's decoder on the same slot words
    words = np.array([feature_words(feats, s)[:SLOT_WORDS_USED] for s in range(len(feats))], dtype=np.uint32)
    same(frame.features, decode_features(words, accel.hw.sectors, descriptors=True))
    # and the bank path itself (the scripted BRAM build, 15 features a bank)
    bank = ScriptedAccel()
    bank.features = random_features(15, seed=4, width=128, height=96)
    bank_accel = OrbAccel(bank)
    bank_accel.configure(threshold=20, mode="orb")
    bank_frame = bank_accel.next_frame(0.01)
    assert sorted(bank_frame.counters) == sorted(frame.counters)
    dev2, accel2 = ring(depth=16)
    dev2.features = bank.features
    ring_frame = accel2.next_frame(0.01)
    same(ring_frame.features, bank_frame.features)
    assert (ring_frame.mode, ring_frame.params, ring_frame.record.count) == (
        bank_frame.mode, bank_frame.params, bank_frame.record.count)  # fmt: skip


def test_fast_mode_and_empty_frames() -> None:
    dev, accel = ring()
    assert len(accel.next_frame(0.01)) == 0  # a frame without features: the record alone
    accel.configure(threshold=20, mode="fast")
    dev.features = random_features(10, seed=5)
    frame = accel.next_frame(0.01)
    assert frame.mode == "fast" and frame.descriptors.shape == (10, 0) and np.all(np.isnan(frame.angle))


def test_reads_through_invalidations_only() -> None:
    """Without invalidating, the model cache would give stale bytes: each frame invalidates its
    record's 64 bytes, then exactly its count * 64 feature bytes, and the bytes are right."""
    dev, accel = ring()
    memory = dev.memory
    assert isinstance(memory, CachedMemory)
    for n, seed in ((20, 1), (5, 2), (40, 3)):
        dev.features = random_features(n, seed=seed)
        memory.calls.clear()
        frame = accel.next_frame(0.01)
        same(frame.features, dev.features.sorted())
        (rec_at, rec_len), (feat_at, feat_len) = memory.calls
        assert (rec_len, feat_at, feat_len) == (SLOT_BYTES, rec_at + SLOT_BYTES, n * SLOT_BYTES)
        assert (rec_at - accel.ring.offset) % accel.ring.stride == 0


# ---- ring order, gaps, release --------------------------------------------------------------------
def test_ring_order_gaps_and_release() -> None:
    dev, accel = ring(count=4)
    dev.video = False
    assert accel.ring.count == 4 and dev.count == 4 and dev.base == PHYS and dev.stride == DEPTH * SLOT_BYTES
    for _ in range(6):  # 4 published into buffers 0..3, then 2 skipped: every buffer is READY
        dev.publish()
    assert dev.ready == 0b1111 and dev.overruns == 2
    frames = [accel.next_frame(0.01) for _ in range(4)]
    assert [f.bank for f in frames] == [0, 1, 2, 3]
    assert [f.number for f in frames] == [0, 1, 2, 3]
    assert dev.ready == 0, "every buffer released"
    assert dev.accesses["write RING_RELEASE"] == 4
    dev.publish()  # frame 6 (4 and 5 were skipped) into buffer 0
    dev.publish()
    got = [accel.next_frame(0.01) for _ in range(2)]
    assert [(f.bank, f.number) for f in got] == [(0, 6), (1, 7)]
    assert got[0].number - frames[-1].number - 1 == 2, "the gap is in the frame numbers"
    assert got[0].counters["overrun"] == 2
    # the ring wraps: buffers 2, 3, 0 in that order
    for _ in range(3):
        dev.publish()
    assert [accel.next_frame(0.01).bank for _ in range(3)] == [2, 3, 0]


def test_several_frames_per_interrupt_are_all_read() -> None:
    dev, accel = ring(count=8)
    dev.video = False
    for _ in range(3):
        dev.publish()  # one interrupt flag for three frames
    dev.accesses.clear()
    numbers = [accel.next_frame(0.01).number for _ in range(3)]
    assert numbers == [0, 1, 2]
    # one acknowledgement and one RING_STATUS read for the three; then counters and release each
    assert dev.accesses["read RING_STATUS"] == 1 and dev.accesses["write IRQ_STATUS"] == 1
    assert dev.total() == 3 + 3 * (len(accel.counters()) + 1)
    with pytest.raises(TimeoutError):
        accel.next_frame(0.01)


def test_holding_releases_on_an_exception() -> None:
    dev, accel = ring()
    with pytest.raises(RuntimeError), accel.frame(0.01) as frame:
        assert dev.ready >> frame.bank & 1
        raise RuntimeError("the caller's code fails")
    assert dev.ready == 0


def test_settle_discards_the_published_frames() -> None:
    dev, accel = ring(count=4)
    dev.video = False
    dev.publish()
    dev.publish()
    accel.configure(threshold=30, mode="fast")
    dev.video = True
    frame = accel.settle(0.01)
    assert frame.number == 2 and frame.bank == 2, "the frames published before settle() are released unread"
    assert dev.ready == 0
    assert [accel.next_frame(0.01).bank for _ in range(3)] == [3, 0, 1]


def test_soft_reset_restarts_the_ring() -> None:
    _, accel = ring(count=4)
    accel.next_frame(0.01)
    accel.next_frame(0.01)
    accel.soft_reset()
    assert [accel.next_frame(0.01).bank for _ in range(2)] == [0, 1]


# ---- bus accesses per frame ------------------------------------------------------------------------
def test_bus_accesses_per_frame_at_budget_2000() -> None:
    depth = 2048
    dev, accel = ring(n=4, depth=depth)
    accel.configure(threshold=20, budget=2000)
    dev.features = random_features(2000, seed=7)
    accel.next_frame(0.01)  # the first: the ring's position after open
    dev.accesses.clear()
    frame = accel.next_frame(0.01)
    per_frame = sum(dev.accesses.values())
    assert len(frame) == 2000
    assert per_frame <= 64, dict(dev.accesses)
    assert dev.accesses["block"] == 0
    # exactly: the interrupt's acknowledgement (read, write), RING_STATUS, the counters, the release
    assert per_frame == 2 + 1 + len(accel.counters()) + 1, dict(dev.accesses)
    without = accel.read_bank  # counters=False: no bus access at all for the frame's data
    dev.accesses.clear()
    index = accel.wait_frame(0.01)
    without(index, counters=False)
    accel.release(index)
    assert sum(dev.accesses.values()) == 2 + 1 + 1


# ---- the checks -------------------------------------------------------------------------------------
WIN = DdrWindow(True, 0, 4096)


@pytest.mark.parametrize(
    ("phys", "size", "kw", "window", "message"),
    [
        (PHYS, 4 * DEPTH * 64, {"count": 0}, WIN, r"count 0 not in 1\.\.16"),
        (PHYS, 17 * DEPTH * 64, {"count": 17}, WIN, r"count 17 not in 1\.\.16"),
        (PHYS, DEPTH * 64 - 64, {}, WIN, r"count must be 1\.\.16, but the memory .* holds no buffer"),
        (PHYS, 4 * DEPTH * 64, {"offset": 32}, WIN, r"64-byte aligned .*base 0x1e900020"),
        (PHYS + 16, 4 * DEPTH * 64, {"offset": 0}, WIN, r"64-byte aligned"),
        (PHYS, 4 * DEPTH * 64, {"stride": DEPTH * 64 + 32}, WIN, r"64-byte aligned .*stride"),
        (PHYS, 4 * DEPTH * 64, {"count": 2, "stride": DEPTH * 64 - 64}, WIN, r"overlap: stride 0xfc0 < depth 64 x 64"),
        (PHYS, 4 * DEPTH * 64, {"count": 5}, WIN, r"outside the mapped memory of 0x4000 bytes"),
        (PHYS, 4 * DEPTH * 64, {"count": 2, "offset": 3 * DEPTH * 64}, WIN, r"outside the mapped memory"),
        (PHYS, 4 * DEPTH * 64, {}, DdrWindow(True, 512, 256), r"outside the fabric's DDR window \[0x20000000"),
        (0x3FFFF000, 4 * DEPTH * 64, {"count": 2}, DdrWindow(True, 0, 1024), r"outside the fabric's DDR window"),
    ],
)
def test_bad_rings_are_refused(phys: int, size: int, kw: dict, window: DdrWindow, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        plan_ring(ArrayMemory(size, phys), DEPTH, window, **kw)


def test_a_bad_ring_is_refused_before_any_register_is_written() -> None:
    memory = ArrayMemory(4 * DEPTH * SLOT_BYTES, PHYS)
    dev = ScriptedRing(memory, depth=DEPTH, win_base_mb=0, win_size_mb=256)  # PHYS is at 489 MiB
    with pytest.raises(ValueError, match="outside the fabric's DDR window"):
        OrbAccel(dev, memory=memory)
    assert not any(k.startswith("write") for k in dev.accesses), dict(dev.accesses)
    with pytest.raises(ValueError, match="overlap"):
        OrbAccel(ScriptedRing(memory, depth=DEPTH), memory=memory).open_ring(memory, 2, stride=64)


def test_the_defaults_fill_the_memory_up_to_16_buffers() -> None:
    assert plan_ring(ArrayMemory(40 * DEPTH * 64, PHYS), DEPTH, WIN).count == 16
    layout = plan_ring(ArrayMemory(3 * DEPTH * 64 + 8, PHYS + 48), DEPTH, WIN)
    assert (layout.count, layout.offset, layout.base % 64) == (2, 16, 0), "aligned up, 2 whole buffers after"


def test_a_device_that_disagrees_raises_with_the_bits_decoded() -> None:
    memory = ArrayMemory(4 * DEPTH * SLOT_BYTES, PHYS)
    dev = ScriptedRing(memory, depth=DEPTH)
    dev.extra_error = 0b0110
    with pytest.raises(AccelError, match=r"RING_STATUS.error = 0x6 .*bit 1 overlap .*bit 2 outside"):
        OrbAccel(dev, memory=memory)
    assert not regs.CTRL.field("enable").get(dev.ctrl), "left stopped"
    assert ring_error_text(0b1001).startswith("bit 0 unaligned") and "bit 3 off" in ring_error_text(0b1001)
    assert ring_error_text(0) == "none"


def test_open_writes_the_ring_while_stopped_and_restores_enable() -> None:
    memory = ArrayMemory(4 * DEPTH * SLOT_BYTES, PHYS)
    dev = ScriptedRing(memory, depth=DEPTH)
    dev.ctrl = regs.CTRL.field("enable").put(1)
    log: list[tuple[str, int]] = []
    write = dev.write32

    def logged(addr: int, value: int) -> None:
        log.append((regs.BY_OFFSET[addr].name, value))
        write(addr, value)

    dev.write32 = logged  # type: ignore[method-assign]
    OrbAccel(dev, memory=memory)
    names = [n for n, _ in log]
    assert names == ["CTRL", "RING_BASE", "RING_STRIDE", "RING_COUNT", "CTRL", "CTRL"]
    assert log[0][1] == 0 and log[4][1] == regs.CTRL.field("soft_reset").put(1) and log[5][1] == dev.ctrl == 1
    assert memory.invalidated_bytes == 4 * DEPTH * SLOT_BYTES, "the whole ring invalidated once at open"


# ---- open, faults -----------------------------------------------------------------------------------
def test_a_ddr_build_without_memory() -> None:
    memory = ArrayMemory(4 * DEPTH * SLOT_BYTES, PHYS)
    with pytest.raises(ValueError, match=r"DDR ring \(CFG_DDR.ddr = 1\): open it with memory="):
        OrbAccel(ScriptedRing(memory))
    look = OrbAccel(ScriptedRing(memory), release_stale=False)  # orb-accel board info: looks only
    assert look.ddr and look.ring is None and "RING_STATUS" in look.status_text()
    with pytest.raises(AccelError, match="without memory"):
        look.wait_frame(0.01)


def test_a_memory_factory_is_called_only_for_a_ddr_build() -> None:
    asked: list[int] = []

    def factory(size: int) -> ArrayMemory:
        asked.append(size)
        return ArrayMemory(size, PHYS)

    OrbAccel(ScriptedAccel(), memory=factory)  # a BRAM build: never called
    assert asked == []
    accel = OrbAccel(ScriptedRing(ArrayMemory(64, 0), depth=DEPTH), memory=factory, ring_count=3)
    assert asked == [3 * DEPTH * SLOT_BYTES + 64] and accel.ring.count == 3


def test_older_maps_and_bram_builds_keep_the_banks() -> None:
    memory = ArrayMemory(4 * DEPTH * SLOT_BYTES, PHYS)
    old = OrbAccel(ScriptedRing(memory, minor=1), memory=memory, release_stale=False)  # CFG_DDR not read
    assert old.window is None and not old.ddr and old.ring is None
    bram = ScriptedAccel()  # map 3.2, CFG_DDR reads 0: the banks, whatever memory is given
    accel = OrbAccel(bram, memory=memory)
    accel.configure(threshold=20)
    assert accel.window == DdrWindow(False, 0, 0) and accel.ring is None
    assert memory.invalidations == 0
    assert accel.next_frame(0.01).bank == 0


def test_a_lost_interrupt_costs_its_wait_not_the_frame() -> None:
    dev, accel = ring(count=4)
    dev.video = False
    dev.publish()
    dev.lose_irq()
    frame = accel.next_frame(0.01)
    assert frame.number == 0 and accel.faults.timeouts == 1 and accel.faults.stale_banks == 0
    with pytest.raises(TimeoutError, match=r"no interrupt within 0.01 s: RING_STATUS = 0x0, .*dma_dropped = 0"):
        accel.next_frame(0.01)


def test_an_error_response_to_the_release_is_recovered() -> None:
    dev, accel = ring(count=4)
    dev.fail("write", regs.RING_RELEASE)
    with pytest.raises(BusError):
        accel.next_frame(0.01)
    assert dev.ready == 1 and accel.faults.bus_errors == 1
    frame = accel.next_frame(0.01)  # the recovery releases buffer 0 first, then reads the next frame
    assert accel.faults.stale_banks == 1
    assert frame.bank == 1 and dev.ready == 0
    assert [accel.next_frame(0.01).bank for _ in range(3)] == [2, 3, 0]


def test_an_error_response_to_ring_status_is_recovered() -> None:
    dev, accel = ring(count=4)
    dev.fail("read", regs.RING_STATUS)
    with pytest.raises(BusError):
        accel.next_frame(0.01)
    numbers = [accel.next_frame(0.01).number for _ in range(3)]
    assert numbers == [0, 1, 2], "the frame whose status read failed is read next, not lost"


def test_a_dead_predecessors_buffers_are_freed_at_open() -> None:
    memory = ArrayMemory(4 * DEPTH * SLOT_BYTES, PHYS)
    dev = ScriptedRing(memory, depth=DEPTH)
    OrbAccel(dev, memory=memory)
    dev.video = False
    dev.publish()
    dev.publish()  # the first driver dies holding buffers 0 and 1
    accel = OrbAccel(dev, memory=memory)
    assert accel.released_at_open == [0, 1] and accel.faults.stale_banks == 2 and dev.ready == 0
    dev.video = True
    assert accel.next_frame(0.01).bank == 0


# ---- memory backends --------------------------------------------------------------------------------
def fake_udmabuf(tmp: Path, size: int = 1 << 16, phys: int = PHYS, coherent: str | None = None) -> tuple[Path, Path]:
    sysfs, dev = tmp / "sys", tmp / "dev"
    attrs = sysfs / "udmabuf0"
    attrs.mkdir(parents=True)
    dev.mkdir()
    (attrs / "phys_addr").write_text(f"0x{phys:08x}\n")
    (attrs / "size").write_text(f"{size}\n")
    (attrs / "sync_for_cpu").write_text("0\n")
    if coherent is not None:
        (attrs / "dma_coherent").write_text(coherent + "\n")
    data = np.arange(size, dtype=np.uint32).astype(np.uint8)
    (dev / "udmabuf0").write_bytes(data.tobytes())
    return sysfs, dev


def test_udmabuf_maps_read_only_and_syncs_for_cpu(tmp_path: Path) -> None:
    sysfs, dev = fake_udmabuf(tmp_path)
    with UDmaBuf("udmabuf0", sysfs, dev) as mem:
        assert isinstance(mem, FrameMemory)
        assert (mem.phys_addr, mem.size, mem.dma_coherent) == (PHYS, 1 << 16, False)
        v = mem.view(0x1000, 64)
        assert v.tolist() == list(range(64)) and not v.flags.writeable
        with pytest.raises(ValueError):
            v[0] = 1
        mem.invalidate(0x1040, 2000)  # widened to whole 32-byte lines: 0x1040 .. 0x1820
        text = (sysfs / "udmabuf0" / "sync_for_cpu").read_text().strip()
        cmd = int(text, 16)
        assert text.startswith("0x") and cmd >> 32 == 0x1040 and cmd & 0xFFFFFFF0 == 2016
        assert (cmd >> 2) & 3 == 2 and cmd & 1 == 1, "DMA_FROM_DEVICE, the command bit"
        assert mem.syncs == 1
        mem.invalidate(0, 0)
        assert mem.syncs == 1
        with pytest.raises(ValueError, match="outside the memory"):
            mem.invalidate(0xFFC0, 128)
        del v
    with pytest.raises(ValueError, match="closed"):
        mem.invalidate(0, 64)


def test_udmabuf_under_the_driver(tmp_path: Path) -> None:
    """The ring in a u-dma-buf (a regular file here): the device writes the file, the driver reads
    the map after each sync command."""
    sysfs, devdir = fake_udmabuf(tmp_path, size=4 * DEPTH * SLOT_BYTES)
    with UDmaBuf("udmabuf0", sysfs, devdir) as mem:
        shadow = ArrayMemory(mem.size, mem.phys_addr)  # the device's side: written, then copied to the file
        dev = ScriptedRing(shadow, depth=DEPTH)
        accel = OrbAccel(dev, memory=mem)
        accel.configure(threshold=20)
        dev.video = False
        dev.features = random_features(30, seed=9)
        dev.publish()
        with open(devdir / "udmabuf0", "r+b") as f:
            f.write(shadow.array.tobytes())
        syncs = mem.syncs
        frame = accel.next_frame(0.01)
        same(frame.features, dev.features.sorted())
        assert mem.syncs - syncs == 2
        del frame
        accel.close()


def test_udmabuf_missing_or_coherent(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="u-dma-buf module loaded"):
        UDmaBuf("udmabuf3", tmp_path, tmp_path)
    sysfs, dev = fake_udmabuf(tmp_path, coherent="1")
    with UDmaBuf("udmabuf0", sysfs, dev) as mem:
        assert mem.dma_coherent
    assert UDmaBuf.command(64, 128) == (64 << 32) | 128 | 2 << 2 | 1
    with pytest.raises(ValueError, match="multiple of 16"):
        UDmaBuf.command(0, 40)


class FakePynqBuffer(np.ndarray):
    """What PynqMemory uses of pynq's PynqBuffer: physical_address, and invalidate() on a slice,
    which knows its offset in the buffer (PynqBuffer.__array_finalize__ does the same)."""

    def __new__(cls, size: int, phys: int, log: list) -> FakePynqBuffer:
        self = np.zeros(size, dtype=np.uint8).view(cls)
        self.device_address, self.offset, self.log = phys, 0, log
        return self

    def __array_finalize__(self, obj) -> None:
        if isinstance(obj, FakePynqBuffer):
            delta = self.__array_interface__["data"][0] - obj.__array_interface__["data"][0]
            self.device_address, self.offset, self.log = obj.device_address + delta, obj.offset + delta, obj.log

    @property
    def physical_address(self) -> int:
        return self.device_address

    def invalidate(self) -> None:
        self.log.append((self.offset, self.nbytes))


def test_pynq_memory_invalidates_the_slice() -> None:
    log: list[tuple[int, int]] = []
    mem = PynqMemory(FakePynqBuffer(4096, 0x18000000, log))
    assert isinstance(mem, FrameMemory) and (mem.phys_addr, mem.size) == (0x18000000, 4096)
    mem.invalidate(128, 640)
    assert log == [(128, 640)]
    v = mem.view(64, 64)
    assert not v.flags.writeable and type(v) is np.ndarray
    mem.invalidate(0, 0)
    assert log == [(128, 640)]


def test_memory_specs(tmp_path: Path) -> None:
    a = memory_factory("array:0x10000000")(4096)
    assert isinstance(a, ArrayMemory) and (a.phys_addr, a.size) == (0x10000000, 4096)
    assert memory_factory(None, board=False)(64).phys_addr == 0
    assert callable(memory_factory("pynq"))
    with pytest.raises(FileNotFoundError, match="udmabuf7"):
        memory_factory("udmabuf:udmabuf7")(0)
    for bad in ("ram", "array:x", "pynq:1"):
        with pytest.raises(ValueError, match="--ddr-memory"):
            memory_factory(bad)


def test_the_default_device_is_the_overlays() -> None:
    """The u-dma-buf device the driver opens by default is the one the board's overlay declares."""
    import json

    from orb_accel.ddr import UDMABUF_NAME

    board = json.loads((Path(__file__).resolve().parents[2] / "vivado" / "board.json").read_text())
    assert board["feat_dma"]["udmabuf_name"] == UDMABUF_NAME
    assert board["feat_dma"]["udmabuf_sync_direction"] == 2  # DMA_FROM_DEVICE, as the driver's command says
