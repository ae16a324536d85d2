# SPDX-License-Identifier: MIT
"""orb_feat_mem: tests of the double-buffered feature memory (protocol: docs/feature-memory.md).

A Python reference (`MemModel`) follows the documented protocol one clock at a time: which frame
goes to which bank, which beats are written where (the memory's whole contents, stale slots
included), the bank headers, counters, frame_done and the read port (latency FEAT_MEM_READ_LAT, read-first).
Every clock, every output of the DUT is compared with it (the cocotb tests share one simulation:
each test starts from the RAM contents and headers the DUT has, read first). On top of that,
each scenario checks what the CPU sees against expectations taken from the stimulus alone: the
features of every published frame decoded from words read through mem_rd_*, the end-of-frame
record, the sequence of published frame numbers, and the overrun/overflow/aborted counts.

Feature beats carry random x, y, score, scale, sector and descriptor (every field distinct per
feature with high probability), so a feature in the wrong slot, bank or frame shows. The memory
registers its inputs (stream, frame_abort, release) once before its rules apply: the model takes
each clock's inputs one clock later. The grid selection's beats (sel_replace = 1 writes over the
slot its sel_slot took) are checked by `selection_replaces`: the CPU view of each frame must be
golden_model.featcodec.resolve_selection of its beats, with replacements right after their own
slot's first beat, two clocks after it, and later.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import cocotb
import numpy as np
import pytest
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge

from golden_model.featcodec import (
    decode_eof,
    encode_eof,
    encode_feature,
    feature_slot,
    is_record,
    record_slot,
    resolve_selection,
)
from golden_model.featword import EOF_BEAT, FEATURE_BEAT, SLOT_BYTES, SLOT_WORD_BITS, SLOT_WORDS, SLOT_WORDS_USED
from golden_model.frameparams import FrameParams
from golden_model.latency import FEAT_MEM_READ_LAT
from orbtb.runner import run
from orbtb.unit import SIM_ENV, env_int

WORDS = SLOT_WORDS  # 32-bit words per 64-byte slot
STORED = SLOT_WORDS_USED  # words 0 .. STORED - 1 of a slot are stored, the others read 0
WORD_SHIFT = (SLOT_WORD_BITS // 8).bit_length() - 1  # mem_rd_addr: [1:0] byte in the word,
SLOT_SHIFT = SLOT_BYTES.bit_length() - 1  # [5:2] word in the slot, then the slot, then the bank
M32 = (1 << 32) - 1
FRAME_MASK = (1 << EOF_BEAT.field("frame").width) - 1  # frame numbers count mod 2^16
DROPS_LIMIT = 1 << EOF_BEAT.field("drops").width

Beat = tuple[int, int]  # (tdata, tlast)


# ------------------------------------------------------------------------------------------------
# stimulus and the CPU view


def feature_beat(rng: np.random.Generator) -> int:
    """A feature beat (tlast = 0) with every field random (layout: docs/feature-word.md)."""
    width = {f.name: f.width for f in FEATURE_BEAT.fields}
    score, x, y = (int(v) for v in rng.integers(0, [1 << width["score"], 1 << width["x"], 1 << width["y"]]))
    scale, sector = int(rng.integers(0, 1 << width["scale"])), int(rng.integers(0, 1 << width["sector"]))
    desc = rng.bytes(width["descriptor"] // 8)
    return encode_feature(scale=scale, x=x, y=y, score=score, sector=sector, descriptor=desc)


def frame_params(rng: np.random.Generator) -> FrameParams:
    """Random parameters of a frame (every field of the end-of-frame beat that carries them random)."""
    return FrameParams.from_fields({f.name: int(rng.integers(0, 1 << f.width)) for f in EOF_BEAT.fields})


def eof_beat(number: int, dropped: int, params: FrameParams) -> int:
    return encode_eof(number, dropped, params)


def feature_words(tdata: int) -> list[int]:
    """The 16 words of a feature slot as the CPU reads them (docs/feature-word.md)."""
    return feature_slot(tdata)


def record_words(count: int, number: int, dropped: int, truncated: int, params: FrameParams) -> list[int]:
    """The 16 words of the end-of-frame record as the CPU reads them (with the frame's parameters)."""
    return record_slot(encode_eof(number, dropped, params), count, truncated & M32)


@dataclass
class TxFrame:
    """A frame as sent: its feature beats and end-of-frame values."""

    number: int
    features: list[int]
    dropped: int
    params: FrameParams  # the parameters its end-of-frame beat carries (random: the record must copy them)

    def beats(self) -> list[Beat]:
        return [(f, 0) for f in self.features] + [(eof_beat(self.number, self.dropped, self.params), 1)]


@dataclass
class CpuFrame:
    """A bank as the CPU decodes it from words read through mem_rd_*."""

    features: list[list[int]]
    record: list[int]


def decode_bank(words: list[int], depth: int) -> CpuFrame:
    """Walk the slots of one bank (words in address order) up to the end-of-frame record."""
    feats = []
    for s in range(depth):
        slot = words[s * WORDS : (s + 1) * WORDS]
        if is_record(slot):
            return CpuFrame(feats, slot)
        feats.append(slot)
    raise AssertionError("no end-of-frame record in the bank")


# ------------------------------------------------------------------------------------------------
# reference model


@dataclass
class Published:
    bank: int
    number: int
    count: int
    dropped: int
    truncated: int


@dataclass
class MemModel:
    """The documented behaviour of orb_feat_mem, one clock per `step`."""

    depth: int
    mem: list[list[int]] = field(default_factory=list)  # 2 * depth slots of STORED stored words
    ready: list[int] = field(default_factory=lambda: [0, 0])
    wbank: int = 0
    in_frame: bool = False
    storing: bool = False
    abort_f: bool = False
    cnt: int = 0
    trunc: int = 0
    done: int = 0
    last_bank: int = 0
    overrun: int = 0
    overflow: int = 0
    aborted: int = 0
    hdr: list[list[int]] = field(default_factory=lambda: [[0, 0, 0, 0], [0, 0, 0, 0]])  # count, frame, drop, trunc
    rd_pipe: deque = field(default_factory=lambda: deque([None] * (FEAT_MEM_READ_LAT - 1)))
    rd_data: int = 0
    published: list[Published] = field(default_factory=list)
    pending: tuple = (None, 0, None)  # the inputs of the last clock (the memory registers them)
    smap: dict[int, int] = field(default_factory=dict)  # sel_slot -> the slot it took

    def __post_init__(self) -> None:
        self.mem = [[0] * STORED for _ in range(2 * self.depth)]

    def word(self, addr: int) -> int:
        bank = (addr >> (self.depth.bit_length() - 1 + SLOT_SHIFT)) & 1
        slot = (addr >> SLOT_SHIFT) & (self.depth - 1)
        w = (addr >> WORD_SHIFT) & (WORDS - 1)
        return self.mem[bank * self.depth + slot][w] if w < STORED else 0

    def reset(self) -> None:
        self.ready = [0, 0]
        self.wbank = 0
        self.in_frame = self.storing = self.abort_f = False
        self.cnt = self.trunc = self.done = self.last_bank = 0
        self.overrun = self.overflow = self.aborted = 0
        self.rd_pipe = deque([None] * (FEAT_MEM_READ_LAT - 1))
        self.pending = (None, 0, None)

    def step(self, beat: Beat | None, abort: int, release: int | None, rd_addr: int | None) -> None:
        # read port: RAM read register loaded at this edge (read-first), its output register at the
        # next, the word register at the one after
        self.rd_pipe.append(None if rd_addr is None else self.word(rd_addr))
        out = self.rd_pipe.popleft()
        if out is not None:
            self.rd_data = out
        # the stream, frame_abort and release: the last clock's, registered
        (beat, abort, release), self.pending = self.pending, (beat, abort, release)
        free = not self.ready[self.wbank] or release == self.wbank
        store = self.storing if self.in_frame else free
        abort_now = self.abort_f or bool(abort)
        self.done = 0
        if release is not None:
            self.ready[release] = 0
        if abort:
            self.abort_f = True
        if beat is None:
            return
        data, last = beat
        base = self.wbank * self.depth
        if not last:
            self.in_frame, self.storing = True, store
            sel = FEATURE_BEAT.field("sel_slot").get(data)
            if store and not abort_now:
                if FEATURE_BEAT.field("sel_replace").get(data):
                    self.mem[base + self.smap[sel]] = feature_words(data)[:STORED]
                elif self.cnt < self.depth - 1:
                    self.mem[base + self.cnt] = feature_words(data)[:STORED]
                    self.smap[sel] = self.cnt
                    self.cnt += 1
                else:
                    self.trunc += 1
            return
        eof = decode_eof(data)
        number, dropped = eof.frame, eof.drops
        if store and not abort_now:
            self.mem[base + self.cnt] = record_words(self.cnt, number, dropped, self.trunc, eof.params)[:STORED]
        if abort_now:
            self.aborted += 1
        elif not store:
            self.overrun += 1
        else:
            b = self.wbank
            self.ready[b] = 1
            self.hdr[b] = [self.cnt, number, dropped, self.trunc]
            self.overflow = (self.overflow + self.trunc) & M32
            self.last_bank = b
            self.wbank ^= 1
            self.done = 1
            self.published.append(Published(b, number, self.cnt, dropped, self.trunc))
        self.in_frame = self.storing = self.abort_f = False
        self.cnt = self.trunc = 0


# ------------------------------------------------------------------------------------------------
# bench


class MemBench:
    """Drives orb_feat_mem one clock at a time; compares every output with MemModel every clock."""

    OUTPUTS = (
        "frame_done", "bank_ready", "bank_truncated", "last_bank", "overrun", "overflow", "aborted",
        "bank0_count", "bank0_frame", "bank0_dropped", "bank0_trunc",
        "bank1_count", "bank1_frame", "bank1_dropped", "bank1_trunc", "mem_rd_data", "s_axis_feat_tready",
    )  # fmt: skip

    def __init__(self, dut) -> None:
        self.dut = dut
        self.depth = env_int("ORB_DEPTH")
        self.bank_shift = self.depth.bit_length() - 1 + SLOT_SHIFT
        self.rng = np.random.default_rng(self.depth)
        self.model = MemModel(self.depth)
        self.edge = 0
        self.read_log: deque[int] = deque()  # addresses issued, data not yet returned
        self.read_data: dict[int, int] = {}  # word address -> data returned (the last read of it)
        self._pipe: deque[int | None] = deque([None] * FEAT_MEM_READ_LAT)  # reads of the last clocks
        self.learning = False
        self.overlap = 0  # clocks with a stream beat and a read at once
        self.span: dict[str, int] = {}  # clocks (of the last `run`) of the first and last beat and read
        self.frame_no = 0
        self._driven: dict[str, int] = {}
        self._outs = [getattr(dut, n) for n in self.OUTPUTS]

    async def start(self) -> None:
        dut = self.dut
        dut.rst.value = 1
        for name in ("s_axis_feat_tvalid", "s_axis_feat_tlast", "frame_abort", "release_valid", "release_bank",
                     "mem_rd_en", "mem_rd_addr"):  # fmt: skip
            getattr(dut, name).value = 0
            self._driven[name] = 0
        dut.s_axis_feat_tdata.value = 0
        cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start(start_high=False))
        await ClockCycles(dut.clk, 3)
        dut.rst.value = 0
        await self.learn()

    async def learn(self) -> None:
        """The cocotb tests share one simulation, and rst keeps the RAM and the bank headers: the
        model takes them from the DUT (the headers from their ports, the RAM's words 0..9 of every
        slot read through mem_rd_*; words 10..15 must read 0, which the model checks later)."""
        m = self.model
        m.hdr = [
            [int(getattr(self.dut, f"bank{k}_{n}").value) for n in ("count", "frame", "dropped", "trunc")]
            for k in range(2)
        ]
        addrs = [a for a in self.bank_reads(0) + self.bank_reads(1) if (a >> WORD_SHIFT) & (WORDS - 1) < STORED]
        self.learning = True
        await self.run([], reads=addrs)
        self.learning = False
        for addr, data in self.read_data.items():
            m.mem[addr >> SLOT_SHIFT][(addr >> WORD_SHIFT) & (WORDS - 1)] = data
        m.rd_data = int(self.dut.mem_rd_data.value)
        self.clear_reads()

    def _drive(self, name: str, value: int) -> None:
        if self._driven.get(name) != value:
            getattr(self.dut, name).value = value
            self._driven[name] = value

    def expected(self) -> list[int]:
        m = self.model
        h0, h1 = m.hdr
        return [
            m.done, m.ready[0] | m.ready[1] << 1, int(h0[3] != 0) | int(h1[3] != 0) << 1, m.last_bank,
            m.overrun, m.overflow, m.aborted, *h0, *h1, m.rd_data, 1,
        ]  # fmt: skip

    def check_outputs(self) -> None:
        got = [h.value for h in self._outs]
        exp = self.expected()
        for name, g, e in zip(self.OUTPUTS, got, exp, strict=True):
            if self.learning and name == "mem_rd_data":
                continue
            if not g.is_resolvable or int(g) != e:
                raise AssertionError(f"edge {self.edge}: {name} = {g}, expected {e:#x}")

    async def cycle(
        self,
        beat: Beat | None = None,
        abort: int = 0,
        release: int | None = None,
        read: int | None = None,
        rst: bool = False,
    ) -> None:
        """One clock with these inputs. Outputs are compared right after the edge (they show the
        state after the previous edge), then the model takes the clock."""
        if beat is not None:
            self.dut.s_axis_feat_tdata.value = beat[0]
            self._drive("s_axis_feat_tlast", beat[1])
        self._drive("s_axis_feat_tvalid", int(beat is not None))
        self._drive("frame_abort", abort)
        self._drive("release_valid", int(release is not None))
        if release is not None:
            self._drive("release_bank", release)
        self._drive("mem_rd_en", int(read is not None))
        if read is not None:
            self._drive("mem_rd_addr", read)
        await RisingEdge(self.dut.clk)
        self.edge += 1
        self.check_outputs()
        # A read sampled at edge e is in the mem_rd_data register after edge e + 2, i.e. read
        # right after edge e + FEAT_MEM_READ_LAT (3), which is now for the read of that many clocks ago.
        done = self._pipe.popleft()
        if done is not None:
            self.read_data[done >> WORD_SHIFT << WORD_SHIFT] = int(self.dut.mem_rd_data.value)
        self._pipe.append(read)
        self.model.step(beat, abort, release, read)
        if rst:
            self.model.reset()
        if beat is not None and read is not None:
            self.overlap += 1

    async def rst_pulse(self, clocks: int = 2) -> None:
        """Synchronous reset for `clocks` clocks, no input active."""
        self.dut.rst.value = 1
        for _ in range(clocks):
            await self.cycle(rst=True)
        self.dut.rst.value = 0

    # ---- scenario helpers ----------------------------------------------------------------------
    def frame(self, n: int, dropped: int | None = None) -> TxFrame:
        """The next frame of the stream (numbers count up like the merge's), with n features."""
        if dropped is None:
            dropped = int(self.rng.integers(0, DROPS_LIMIT))
        f = TxFrame(self.frame_no, [feature_beat(self.rng) for _ in range(n)], dropped, frame_params(self.rng))
        self.frame_no = (self.frame_no + 1) & FRAME_MASK
        return f

    def bank_reads(self, bank: int, slots: int | None = None) -> list[int]:
        """Byte addresses of every word of `slots` slots (default: the whole bank) of `bank`,
        with random (ignored) low address bits."""
        n = self.depth if slots is None else slots
        low = self.rng.integers(0, 1 << WORD_SHIFT, n * WORDS)
        return [bank << self.bank_shift | i << WORD_SHIFT | int(low[i]) for i in range(n * WORDS)]

    async def run(
        self,
        stream: list[Beat | None],
        reads: list[int] | None = None,
        releases: dict[int, int] | None = None,
        aborts: set[int] | None = None,
        read_prob: float = 1.0,
        tail: int = 3,
    ) -> None:
        """Clock i drives stream[i] (None = idle), the release releases[i] and frame_abort if i in
        aborts; reads go one per clock (with probability read_prob) from clock 0 until all issued.
        Runs until everything is driven, plus `tail` idle clocks (so read data returns)."""
        reads_q = deque(reads or [])
        releases = releases or {}
        aborts = aborts or set()
        i = 0
        self.span = {"first_beat": -1, "last_beat": -1, "first_read": -1, "last_read": -1}
        while i < len(stream) or reads_q or i <= max([*releases, *aborts], default=-1):
            beat = stream[i] if i < len(stream) else None
            rd = reads_q.popleft() if reads_q and self.rng.random() < read_prob else None
            for kind, active in (("beat", beat is not None), ("read", rd is not None)):
                if active:
                    self.span[f"last_{kind}"] = i
                    if self.span[f"first_{kind}"] < 0:
                        self.span[f"first_{kind}"] = i
            await self.cycle(beat, int(i in aborts), releases.get(i), rd)
            i += 1
        for _ in range(tail):
            await self.cycle()

    def with_gaps(self, beats: list[Beat], prob: float, max_gap: int = 4) -> list[Beat | None]:
        out: list[Beat | None] = []
        for b in beats:
            if self.rng.random() < prob:
                out += [None] * int(self.rng.integers(1, max_gap + 1))
            out.append(b)
        return out

    def cpu_view(self, bank: int, slots: int | None = None) -> list[int]:
        """Words of `bank` as returned by the reads issued (whole bank or its first slots)."""
        n = self.depth if slots is None else slots
        base = bank << self.bank_shift
        words = []
        for i in range(n * WORDS):
            data = self.read_data.get(base | i << WORD_SHIFT)
            assert data is not None, f"bank {bank} word {i} was not read"
            words.append(data)
        return words

    def check_frame(self, bank: int, tx: TxFrame, slots: int | None = None) -> None:
        """What the CPU read from `bank` is exactly frame `tx` (the first depth - 1 features)."""
        view = decode_bank(self.cpu_view(bank, slots), self.depth)
        kept = tx.features[: self.depth - 1]
        trunc = len(tx.features) - len(kept)
        assert len(view.features) == len(kept), f"bank {bank}: {len(view.features)} features, expected {len(kept)}"
        for k, (g, f) in enumerate(zip(view.features, kept, strict=True)):
            assert g == feature_words(f), f"bank {bank}, frame {tx.number}, feature {k}: {g} != {feature_words(f)}"
        exp = record_words(len(kept), tx.number, tx.dropped, trunc, tx.params)
        assert view.record == exp, f"bank {bank}: record {view.record}, expected {exp}"
        hdr = [int(getattr(self.dut, f"bank{bank}_{n}").value) for n in ("count", "frame", "dropped", "trunc")]
        assert hdr == [len(kept), tx.number, tx.dropped, trunc], f"bank {bank}: header {hdr}"

    def clear_reads(self) -> None:
        self.read_data = {}


# ------------------------------------------------------------------------------------------------
# cocotb tests


@cocotb.test()
async def ping_pong_reads_during_writes(dut) -> None:
    """Five consecutive frames (both banks, full rate and with gaps). Each READY bank is read in
    full through mem_rd_* while the next frame is written into the other bank, compared exactly
    (model: the whole bank, stale slots included; CPU view: the frame sent), then released."""
    b = MemBench(dut)
    await b.start()
    d = b.depth
    sizes = [d // 2, 3, d - 1, d // 3, 1]
    frames = [b.frame(n) for n in sizes]
    # frame 0 at full rate, nothing to read yet
    await b.run([*frames[0].beats()])
    assert [p.number for p in b.model.published] == [0]
    for k in range(1, len(frames)):
        bank = (k - 1) % 2
        assert int(dut.bank_ready.value) == 1 << bank and int(dut.last_bank.value) == bank
        # the next frame is spread over the reads of the whole READY bank (d * 16 clocks)
        beats = frames[k].beats()
        stream = b.with_gaps(beats, prob=1.0, max_gap=d * WORDS // len(beats))
        if k == 3:
            stream = [None] * (d * 4) + beats  # full rate, in the middle of the reads
        b.clear_reads()
        await b.run(stream, reads=b.bank_reads(bank), read_prob=0.9)
        # the whole next frame, its publication included, fell between the first and last read
        assert b.span["first_beat"] >= b.span["first_read"] and b.span["last_beat"] < b.span["last_read"]
        assert b.model.published[-1].number == frames[k].number
        b.check_frame(bank, frames[k - 1])
        await b.run([], releases={0: bank})
        assert int(dut.bank_ready.value) == 1 << (1 - bank)
    assert b.overlap > 0
    b.clear_reads()
    await b.run([], reads=b.bank_reads(0))
    b.check_frame(0, frames[4])
    assert [p.number for p in b.model.published] == [f.number for f in frames]
    assert int(dut.overrun.value) == 0 and int(dut.overflow.value) == 0
    dut._log.info("%d clocks, %d with a beat and a read at once", b.edge, b.overlap)


@cocotb.test()
async def back_to_back_frames(dut) -> None:
    """Frames at full rate with no idle clock between them; the CPU releases each bank in the
    very clock of the next frame's first beat into that bank (a release in that clock frees it)."""
    b = MemBench(dut)
    await b.start()
    frames = [b.frame(int(n)) for n in b.rng.integers(0, b.depth // 2, 6)]
    stream: list[Beat | None] = []
    releases: dict[int, int] = {}
    for k, f in enumerate(frames):
        if k >= 2:
            releases[len(stream)] = k % 2
        stream += f.beats()
    await b.run(stream, releases=releases)
    assert [p.number for p in b.model.published] == [f.number for f in frames]
    assert int(dut.overrun.value) == 0
    b.clear_reads()
    for bank, f in ((0, frames[4]), (1, frames[5])):
        await b.run([], reads=b.bank_reads(bank, len(f.features) + 1))
        b.check_frame(bank, f, len(f.features) + 1)


@cocotb.test()
async def overrun_skips_whole_frames(dut) -> None:
    """The CPU holds both banks: the following frames are skipped whole and counted; released
    banks take the next frames again; the frame numbers show the gap. A release arriving in the
    middle of a skipped frame does not let its remainder in (never torn)."""
    b = MemBench(dut)
    await b.start()
    f = [b.frame(5 + k) for k in range(7)]
    await b.run(f[0].beats() + [None] * 2 + f[1].beats())
    assert int(dut.bank_ready.value) == 3
    # frames 2 and 3 find bank 0 held; bank 0 is released in the middle of frame 3
    s3 = f[3].beats()
    await b.run(f[2].beats() + s3, releases={len(f[2].beats()) + 2: 0})
    assert int(dut.overrun.value) == 2 and int(dut.bank_ready.value) == 2
    # frame 4 goes to bank 0 (the bank the next frame needs); bank 1 still held: frame 5 skipped
    await b.run(f[4].beats() + f[5].beats())
    assert int(dut.overrun.value) == 3 and int(dut.bank_ready.value) == 3
    await b.run([None], releases={0: 1})
    await b.run(f[6].beats())
    assert [p.number for p in b.model.published] == [0, 1, 4, 6]
    b.clear_reads()
    n4, n6 = len(f[4].features) + 1, len(f[6].features) + 1
    await b.run([], reads=b.bank_reads(0, n4) + b.bank_reads(1, n6))
    b.check_frame(0, f[4], n4)
    b.check_frame(1, f[6], n6)
    assert int(dut.bank0_frame.value) == 4 and int(dut.bank1_frame.value) == 6


@cocotb.test()
async def truncation(dut) -> None:
    """Frames of depth - 1 (fits), depth (one too many) and 2 * depth + 3 features: the first
    depth - 1 are kept, the record takes the last slot, the truncated count and flag are in the
    record and the header, `overflow` sums them. A frame after that is clean again."""
    b = MemBench(dut)
    await b.start()
    d = b.depth
    frames = [b.frame(d - 1), b.frame(d), b.frame(2 * d + 3), b.frame(2)]
    expect_overflow = 0
    for k, f in enumerate(frames):
        bank = k % 2
        stream = f.beats() if k % 2 == 0 else b.with_gaps(f.beats(), 0.3)
        await b.run(stream)
        trunc = max(0, len(f.features) - (d - 1))
        expect_overflow += trunc
        assert int(dut.overflow.value) == expect_overflow
        assert (int(dut.bank_truncated.value) >> bank) & 1 == int(trunc > 0)
        b.clear_reads()
        await b.run([], reads=b.bank_reads(bank))
        b.check_frame(bank, f)
        await b.run([], releases={0: bank})


def selection_frame(b: MemBench, n_new: int, n_repl: int) -> tuple[TxFrame, list[int]]:
    """A frame of the grid selection: n_new beats taking places for distinct sel_slots (not in
    order), and n_repl beats replacing earlier ones: right after their own slot's first beat, two
    beats after it, and at random later. Returns the frame and the words the memory keeps."""
    slots = [int(v) for v in b.rng.permutation(2 * n_new + 5)[:n_new]]
    words: list[int] = []
    taken: list[int] = []
    for k, slot in enumerate(slots):
        words.append(feature_beat(b.rng) | FEATURE_BEAT.field("sel_slot").put(slot))
        taken.append(slot)
        if k % 5 == 0 or (k % 5 == 2 and len(taken) > 2):
            target = slot if k % 5 == 0 else taken[-3]  # the beat just before, two before it
            words.append(feature_beat(b.rng) | FEATURE_BEAT.field("sel_slot").put(target)
                         | FEATURE_BEAT.field("sel_replace").put(1))  # fmt: skip
    for _ in range(n_repl):
        target = taken[int(b.rng.integers(0, len(taken)))]
        words.append(feature_beat(b.rng) | FEATURE_BEAT.field("sel_slot").put(target)
                     | FEATURE_BEAT.field("sel_replace").put(1))  # fmt: skip
    f = TxFrame(b.frame_no, words, int(b.rng.integers(0, DROPS_LIMIT)), frame_params(b.rng))
    b.frame_no = (b.frame_no + 1) & FRAME_MASK
    return f, resolve_selection(words)


@cocotb.test()
async def selection_replaces(dut) -> None:
    """Frames of the grid selection: each bank holds resolve_selection of its beats, in the order
    their places were taken; replacements right after their slot's first beat (the map is read
    before that beat's write lands: forwarded), two beats later, later, and with input gaps."""
    b = MemBench(dut)
    await b.start()
    d = b.depth
    for k, (n_new, n_repl, gaps) in enumerate(((d - 1, 3 * d, 0.0), (d // 2, d, 0.5), (3, 9, 0.0), (1, 0, 0.0))):
        bank = k % 2
        f, kept = selection_frame(b, min(n_new, d - 1), n_repl)
        await b.run(b.with_gaps(f.beats(), prob=gaps))
        assert b.model.published[-1].number == f.number
        b.clear_reads()
        await b.run([], reads=b.bank_reads(bank))
        b.check_frame(bank, TxFrame(f.number, kept, f.dropped, f.params))
        await b.run([], releases={0: bank})


@cocotb.test()
async def empty_frames(dut) -> None:
    """Frames without features: the record is in slot 0, count 0, in both banks."""
    b = MemBench(dut)
    await b.start()
    frames = [b.frame(0), b.frame(0), b.frame(1), b.frame(0)]
    for k, f in enumerate(frames):
        bank = k % 2
        await b.run([None, *f.beats()])
        b.clear_reads()
        await b.run([], reads=b.bank_reads(bank, 2))
        b.check_frame(bank, f, 2)
        assert int(getattr(dut, f"bank{bank}_count").value) == len(f.features)
        await b.run([], releases={0: bank})
    assert [p.count for p in b.model.published] == [0, 0, 1, 0]


@cocotb.test()
async def abort(dut) -> None:
    """frame_abort discards the frame in progress (pulsed mid-frame, in the clock of the
    end-of-frame beat, and during a frame that would have been skipped): not published, counted
    in `aborted`, the bank is used by the next frame; truncated features of an aborted frame do not
    count in `overflow`."""
    b = MemBench(dut)
    await b.start()
    d = b.depth
    f = [b.frame(n) for n in (6, d + 4, 4, 3, 7, 5, 2, 9)]
    await b.run(f[0].beats())  # frame 0 -> bank 0
    s1 = f[1].beats()
    await b.run(s1, aborts={len(s1) - 3})  # frame 1 (truncated) aborted near its end
    assert int(dut.aborted.value) == 1 and int(dut.overflow.value) == 0
    s2 = f[2].beats()
    await b.run(s2, aborts={len(s2) - 1})  # aborted in the clock of its end-of-frame beat
    assert int(dut.aborted.value) == 2 and int(dut.bank_ready.value) == 1
    await b.run(f[3].beats())  # frame 3 -> bank 1 (the bank frames 1 and 2 would have used)
    assert int(dut.bank_ready.value) == 3 and int(dut.last_bank.value) == 1
    s4 = f[4].beats()
    await b.run(s4, aborts={2})  # would be skipped (both held): counted as aborted, not overrun
    await b.run(f[5].beats())  # skipped
    assert int(dut.aborted.value) == 3 and int(dut.overrun.value) == 1
    await b.run([None], releases={0: 0})
    s6 = f[6].beats()
    await b.run([None, None, *s6], aborts={0})  # pulsed between frames: aborts the next frame
    await b.run(f[7].beats())
    assert int(dut.aborted.value) == 4
    assert [p.number for p in b.model.published] == [0, 3, 7]
    b.clear_reads()
    await b.run([], reads=b.bank_reads(0, 10) + b.bank_reads(1, 10))
    b.check_frame(0, f[7], 10)
    b.check_frame(1, f[3], 10)


@cocotb.test()
async def reset_mid_frame(dut) -> None:
    """rst in the middle of a frame (with a READY bank, while it is read): banks free, bank 0
    next, counters 0; then a clean frame is stored in bank 0 and read back."""
    b = MemBench(dut)
    await b.start()
    d = b.depth
    f0, f1, f2 = b.frame(d // 2), b.frame(d), b.frame(d // 2 + 1)
    await b.run(f0.beats() + f1.beats())  # bank 0 READY, bank 1 READY and truncated
    await b.run([None], releases={0: 0})
    await b.run(f2.beats()[: d // 4], reads=b.bank_reads(1, 1), tail=0)
    await b.rst_pulse()
    assert int(dut.bank_ready.value) == 0 and int(dut.overflow.value) == 0
    b.frame_no = 0
    clean = b.frame(d // 3)
    await b.run(b.with_gaps(clean.beats(), 0.3))
    assert int(dut.bank_ready.value) == 1 and int(dut.frame_done.value) == 0
    b.clear_reads()
    await b.run([], reads=b.bank_reads(0))
    b.check_frame(0, clean)


@cocotb.test()
async def random_soak(dut) -> None:
    """Random frame sizes (0 .. depth + 2), gaps, releases, aborts and reads of READY banks, all
    at once; the model checks every clock, and every published frame is read back whole."""
    b = MemBench(dut)
    await b.start()
    d = b.depth
    sent: dict[int, TxFrame] = {}
    for _ in range(14):
        f = b.frame(int(b.rng.integers(0, d + 3)))
        sent[f.number] = f
        beats = b.with_gaps(f.beats(), float(b.rng.choice([0.0, 0.2, 0.6])))
        aborts = {int(b.rng.integers(0, len(beats)))} if b.rng.random() < 0.15 else set()
        # read a READY bank (the oldest) while this frame streams in; release it at the end
        ready = [k for k in range(2) if b.model.ready[k]]
        bank = None
        reads = []
        if ready and b.rng.random() < 0.8:
            bank = b.model.last_bank if len(ready) == 1 or b.rng.random() < 0.3 else 1 - b.model.last_bank
            bank = bank if b.model.ready[bank] else ready[0]
            reads = b.bank_reads(bank, b.model.hdr[bank][0] + 1)
        b.clear_reads()
        n_before = len(b.model.published)
        await b.run(beats, reads=reads, aborts=aborts, read_prob=0.7)
        if bank is not None:
            number = b.model.hdr[bank][1]
            b.check_frame(bank, sent[number], b.model.hdr[bank][0] + 1)
            if b.rng.random() < 0.7:
                await b.run([], releases={0: bank})
        assert len(b.model.published) - n_before <= 1
    dut._log.info(
        "published %s, overrun %d, aborted %d, overflow %d",
        [p.number for p in b.model.published], b.model.overrun, b.model.aborted, b.model.overflow,
    )  # fmt: skip


# ------------------------------------------------------------------------------------------------
# pytest runners


@pytest.mark.parametrize("depth", [16, 64])
def test_feat_mem(depth: int) -> None:
    run("orb_feat_mem", "test_orb_feat_mem", {"DEPTH_g": depth}, env=SIM_ENV)
