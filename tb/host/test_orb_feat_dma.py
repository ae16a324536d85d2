# SPDX-License-Identifier: MIT
"""orb_feat_dma: tests of the DDR feature writer (contract: docs/feature-dma.md), written from the
contract alone.

The DDR is cocotbext-axi's AxiRamWrite over a 4 MiB byte array filled with a canary pattern; the
entity has no ID ports (the contract's "one ID"), so a constant stand-in takes the place of
awid/bid in the model's buses. For error responses a subclass answers chosen bursts (picked by
their address and data) with SLVERR or DECERR and still stores their data. AW, W and B pause
generators stall the three channels.

A protocol monitor (a coroutine sampling every clock) checks the AXI4 rules of the contract:
AWLEN 7, AWSIZE 3, AWBURST INCR, AWCACHE 0011, AWPROT 000, WSTRB all ones, the address 64-byte
aligned, inside a buffer of a ring the test configured, and no burst across 4 KiB; WLAST exactly
on the 8th beat; every valid held with its payload until its ready (also across a soft reset);
AWVALID and WVALID rising together for a burst (the first W beat of burst j first shown in the
clock AW j is first shown), so W beats never run ahead of the bursts whose AWVALID was raised; at
most OUTSTANDING_g bursts accepted and not answered; BREADY 1; busy 1 while a burst is shown or
answered; valids 0 during bus_rst. It records every burst (address, 8 beats, response).

The reference works per frame, by the stream rules (shared with orb_feat_mem) and the ring rules:
at a frame's first beat it picks the buffer (skipped if READY without a release in that clock or
still in flight, dropped if ring_error /= 0, else written; the active ring reloaded, and the
position restarted when it differs, when the DUT is idle), then computes every slot write
(address, 16 words) beat by beat: new features to slots 1 .. count, replacements over their
sel_slot's slot, truncation beyond DEPTH_g - 1, the record (record_slot) to slot 0 last. Observed
bursts are matched in order against these writes (a frame may be cut short only when it was
aborted, reset, or dropped by a full FIFO). A frame is published iff its record was written and
every one of its bursts answered OKAY: on each frame_done pulse the oldest such frame must be the
one published (ring_last, ring_ready, last_count, last_frame) and its buffer, decoded from the
DDR in that very clock, must hold its record in slot 0 and its features in slots 1 .. count
(the first mismatch is named: frame, slot, word). At every check the counters (overrun,
overflow, aborted, dma_dropped, bus_errors, beats = 8 x bursts), ring_ready, ring_last, busy,
ring_error and the dma_error pulses must be the reference's, and the whole DDR must be the canary
with exactly the monitored bursts applied (and the canary outside every configured buffer).

Scenarios are laid out so that every outcome is fixed by the contract, not by the DUT's latency:
the stimulus waits before a frame whose buffer is still in flight or READY (unless the scenario
means it to be skipped), keeps the burst FIFO below FIFO_DEPTH_g - 3 slots (unless the scenario
means it to overflow), and the bench raises BenchError if a frame's first beat falls within a few
clocks of an event that decides its buffer.
"""

from __future__ import annotations

import os
from collections import deque
from dataclasses import dataclass, field
from typing import ClassVar

import cocotb
import numpy as np
import pytest
from cocotb.clock import Clock
from cocotb.triggers import RisingEdge
from cocotb.types import LogicArray
from cocotb.utils import get_sim_time
from cocotbext.axi import AxiRamWrite, AxiWriteBus

from golden_model.featcodec import (
    decode_record,
    decode_stream_features,
    encode_eof,
    encode_feature,
    feature_slot,
    is_record,
    record_slot,
    resolve_selection,
)
from golden_model.featword import EOF_BEAT, FEATURE_BEAT, SLOT_BYTES, SLOT_WORDS, SLOT_WORDS_USED
from golden_model.frameparams import FrameParams
from orbtb.runner import run
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int, pause_pattern

MIB = 1 << 20
RAM_BYTES = 4 * MIB  # the DDR model: addresses 0 .. 4 MiB (the builds' window is 1 .. 2 MiB)
BEAT_BYTES = 8
BURST_BEATS = SLOT_BYTES // BEAT_BYTES  # 8 beats of 64 bits a slot
WORDS = SLOT_WORDS  # 32-bit words per slot
M32 = (1 << 32) - 1
OKAY, SLVERR, DECERR = 0, 2, 3
FRAME_MASK = (1 << EOF_BEAT.field("frame").width) - 1
DROPS_LIMIT = 1 << EOF_BEAT.field("drops").width
SEL_SLOT, SEL_REPLACE = FEATURE_BEAT.field("sel_slot"), FEATURE_BEAT.field("sel_replace")
MARGIN = 4  # clocks between a frame's first beat and any event deciding its buffer
RING_SETTLE = 8  # clocks after a change of the ring registers before a frame starts (see ring_change_timing)
# the contract (docs/feature-dma.md): a frame whose first beat is sampled 0 .. SETTLE_DROP edges after
# the edge that samples a change of the ring registers is dropped (their check has not settled)
SETTLE_DROP = 4
PUB_LATENCY = 24  # clocks from a record's write response to its publication, at most (test bound)
DEBUG = bool(os.environ.get("ORB_DMA_DEBUG"))
TIMEOUT = int(os.environ.get("ORB_DMA_TIMEOUT", "60000"))  # clocks any wait may take


class BenchError(RuntimeError):
    """The scenario is ambiguous (an outcome that depends on the DUT's latency): a bug of the test."""


# ------------------------------------------------------------------------------------------------
# the build, the ring and its checks


@dataclass(frozen=True)
class Build:
    depth: int
    fifo: int
    outstanding: int
    win_lo: int
    win_hi: int

    @classmethod
    def from_env(cls) -> Build:
        lo = env_int("ORB_WIN_BASE_MB", 0) * MIB
        return cls(env_int("ORB_DEPTH"), env_int("ORB_FIFO_DEPTH", 256), env_int("ORB_OUTSTANDING", 4), lo,
                   lo + env_int("ORB_WIN_SIZE_MB", 4096) * MIB)  # fmt: skip

    @property
    def buffer_bytes(self) -> int:
        return self.depth * SLOT_BYTES


@dataclass(frozen=True)
class Ring:
    base: int
    stride: int
    count: int

    def buffer(self, i: int) -> int:
        return self.base + i * self.stride

    def regions(self, depth: int) -> list[tuple[int, int]]:
        return [(self.buffer(i), self.buffer(i) + depth * SLOT_BYTES) for i in range(self.count)]


def ring_error(ring: Ring, b: Build) -> int:
    """RING_STATUS.error of the contract: bit 0 unaligned, 1 overlap, 2 outside the window (no wrap
    at 2^32), 3 off. With RING_COUNT 0 the ring has no extent: bit 2 is not defined (masked)."""
    e = 0
    if ring.base % SLOT_BYTES or ring.stride % SLOT_BYTES:
        e |= 1
    if ring.count > 1 and ring.stride < b.buffer_bytes:
        e |= 2
    if ring.count > 0:
        end = ring.base + (ring.count - 1) * ring.stride + b.buffer_bytes
        if ring.base < b.win_lo or end > b.win_hi:
            e |= 4
    else:
        e |= 8
    return e


def ring_error_mask(ring: Ring) -> int:
    return 0b1011 if ring.count == 0 else 0b1111


# ------------------------------------------------------------------------------------------------
# stimulus: frames and their slot writes


def feature_beat(rng: np.random.Generator, sel_slot: int = 0, replace: int = 0) -> int:
    """A feature beat with every field random (layout: docs/feature-word.md)."""
    width = {f.name: f.width for f in FEATURE_BEAT.fields}
    v = {n: int(rng.integers(0, 1 << width[n])) for n in ("score", "x", "y", "scale", "sector", "response", "low")}
    return encode_feature(**v, descriptor=rng.bytes(width["descriptor"] // 8), sel_slot=sel_slot, sel_replace=replace)


def frame_params(rng: np.random.Generator) -> FrameParams:
    return FrameParams.from_fields({f.name: int(rng.integers(0, 1 << f.width)) for f in EOF_BEAT.fields})


@dataclass
class TxFrame:
    """A frame as sent: its feature beats and its end-of-frame values."""

    number: int
    features: list[int]
    dropped: int
    params: FrameParams
    label: str = ""

    def eof_word(self) -> int:
        return encode_eof(self.number, self.dropped, self.params)

    def slots(self, depth: int) -> list[list[int]]:
        """Slots 0 .. count of the buffer this frame fills (the record first)."""
        w = SlotWriter(depth)
        for f in self.features:
            w.feature(f)
        w.eof(self.eof_word())
        return [w.slots[s] for s in range(w.count + 1)]


class SlotWriter:
    """The slot writes of one frame, beat by beat (docs/feature-memory.md's stream rules, slots
    shifted by one for the record in slot 0): a new feature takes the next of slots 1 ..
    DEPTH_g - 1 (beyond them it is truncated and counted), a sel_replace beat is written over the
    slot its sel_slot took, the end-of-frame beat writes the record into slot 0."""

    def __init__(self, depth: int) -> None:
        self.depth = depth
        self.count = 0
        self.trunc = 0
        self.place: dict[int, int] = {}
        self.slots: dict[int, list[int]] = {}

    def feature(self, word: int) -> tuple[int, list[int]] | None:
        sel = SEL_SLOT.get(word)
        if SEL_REPLACE.get(word):
            if sel not in self.place:
                raise ValueError(f"a replacement of sel_slot {sel}, which no stored beat of the frame took")
            slot = self.place[sel]
        elif self.count < self.depth - 1:
            self.count += 1
            slot = self.place[sel] = self.count
        else:
            self.trunc += 1
            return None
        words = feature_slot(word)
        self.slots[slot] = words
        return slot, words

    def eof(self, word: int) -> tuple[int, list[int]]:
        words = record_slot(word, self.count, self.trunc & M32)
        self.slots[0] = words
        return 0, words


def slot_mismatch(got: np.ndarray, want: list[list[int]]) -> str | None:
    """The first (slot, word) where a buffer's words (an (n, 16) array) differ from `want`."""
    for s, exp in enumerate(want):
        for k in range(WORDS):
            if int(got[s, k]) != exp[k]:
                what = "the record" if s == 0 else f"feature {s - 1}"
                extra = " (words 10 .. 15 must be 0)" if k >= SLOT_WORDS_USED else ""
                return f"slot {s} ({what}) word {k} = {int(got[s, k]):#010x}, expected {exp[k]:#010x}{extra}"
    return None


def selection_frame(rng: np.random.Generator, number: int, n_new: int, n_repl: int) -> TxFrame:
    """A grid-selection frame: n_new beats taking places for distinct sel_slots (not in order) and
    replacements right after their own slot's first beat, two beats after it, and at random later."""
    slots = [int(v) for v in rng.permutation(2 * n_new + 5)[:n_new]]
    words: list[int] = []
    taken: list[int] = []
    for k, slot in enumerate(slots):
        words.append(feature_beat(rng, slot))
        taken.append(slot)
        if k % 5 == 0 or (k % 5 == 2 and len(taken) > 2):
            words.append(feature_beat(rng, slot if k % 5 == 0 else taken[-3], 1))
    for _ in range(n_repl):
        words.append(feature_beat(rng, taken[int(rng.integers(0, len(taken)))], 1))
    return TxFrame(number, words, int(rng.integers(0, DROPS_LIMIT)), frame_params(rng), f"grid {n_new}+{n_repl}")


# ------------------------------------------------------------------------------------------------
# real features: the golden model on photographs

PHOTO_W, PHOTO_H = 160, 120


def photo_frames(selection: str, budget: int, names: list[str]) -> list[tuple[str, list[int], FrameParams]]:
    """The feature stream golden_model makes of each photograph (2 scales, orb mode): in `all`
    selection every feature in canonical order; in `grid` selection every level's candidates in
    arrival order offered to golden_model.select.LevelSelector, each stored one a beat with
    sel_slot = the level's first slot + its slot and sel_replace = not new, the levels
    interleaved at random. Checked: decoding the stream gives golden_model's frame."""
    from golden_model.config import Config
    from golden_model.pipeline import candidates, extract
    from golden_model.select import CellGrid, LevelSelector, arrival_order, level_budgets
    from orbtb import images

    out = []
    rng = np.random.default_rng(5)
    for name in names:
        img = images.photo(name, PHOTO_W, PHOTO_H)
        cfg = Config(PHOTO_W, PHOTO_H, scales=2, threshold=20, mode="orb", selection=selection,
                     budget=budget if selection == "grid" else 0, threshold_lo=12, cols=4, rows=3)  # fmt: skip
        feats = candidates(img, cfg)

        def beat(i: int, sel_slot: int = 0, replace: bool = False, f=feats) -> int:
            return encode_feature(scale=int(f.scale[i]), x=int(f.x[i]), y=int(f.y[i]), score=int(f.score[i]),
                                  sector=int(f.sector[i]), descriptor=bytes(f.descriptor[i]),
                                  response=int(f.response[i]), low=int(f.low[i]), sel_slot=sel_slot,
                                  sel_replace=int(replace))  # fmt: skip

        if selection == "all":
            words = [beat(i) for i in range(len(feats))]
        else:
            levels: list[list[int]] = []
            first = 0
            for k, n in enumerate(level_budgets(cfg.budget, feats.step, cfg.scales)):
                w, h = cfg.scale_size(k)
                idx = np.flatnonzero(feats.scale == k)
                idx = idx[arrival_order(feats.x[idx], feats.y[idx], w, h)]
                sel = LevelSelector(n, CellGrid.of_level(cfg, k))
                ops = []
                for i in idx:
                    op = sel.offer(int(feats.x[i]), int(feats.y[i]), bool(feats.low[i]), int(feats.response[i]))
                    if op is not None:
                        ops.append(beat(int(i), first + op[0], not op[1]))
                levels.append(ops)
                first += n
            words = []
            heads = [0] * len(levels)
            while any(heads[k] < len(levels[k]) for k in range(len(levels))):
                live = [k for k in range(len(levels)) if heads[k] < len(levels[k])]
                k = live[int(rng.integers(0, len(live)))]
                words.append(levels[k][heads[k]])
                heads[k] += 1
        got = decode_stream_features(words, cfg.sectors, descriptors=True)
        assert got == extract(img, cfg), f"{name} {selection}: the stream does not decode to golden_model's frame"
        out.append((f"{name} {selection}", words, FrameParams.of(cfg)))
    return out


# ------------------------------------------------------------------------------------------------
# the DDR model


class ConstId:
    """Stands in for awid / bid, which the entity does not have (one ID): reads 0, ignores writes."""

    def __init__(self) -> None:
        self._v = LogicArray("0")

    @property
    def value(self) -> LogicArray:
        return self._v

    @value.setter
    def value(self, _v) -> None:
        pass

    def setimmediatevalue(self, _v) -> None:
        pass

    def __len__(self) -> int:
        return 1


def write_bus(dut) -> AxiWriteBus:
    bus = AxiWriteBus.from_prefix(dut, "m_axi_feat")
    for ch, name in ((bus.aw, "awid"), (bus.b, "bid")):
        if getattr(ch, name, None) is None:
            stand_in = ConstId()
            setattr(ch, name, stand_in)
            ch._signals[name] = stand_in
    return bus


class Ddr(AxiRamWrite):
    """AxiRamWrite over `mem`. With `errors`, bursts are taken by an own loop (the same channels)
    that stores every beat and answers a burst whose (address, 64 bytes) is in `error_of` with that
    response (SLVERR or DECERR), others OKAY."""

    def __init__(self, dut, mem: bytearray, errors: bool = False) -> None:
        self.errors = errors
        self.error_of: dict[tuple[int, bytes], int] = {}
        super().__init__(write_bus(dut), dut.clk, dut.bus_rst, reset_active_level=True, mem=mem)
        # deep queues (an interconnect with buffers): the slave never limits the bursts in flight,
        # so OUTSTANDING_g is the master's own limit (the monitor checks it)
        self.aw_channel.queue_occupancy_limit = 64
        self.w_channel.queue_occupancy_limit = 64 * BURST_BEATS
        self.b_channel.queue_occupancy_limit = 64

    async def _process_write(self) -> None:
        if not self.errors:
            await super()._process_write()
            return
        while True:
            aw = await self.aw_channel.recv()
            addr, n = int(aw.awaddr), int(aw.awlen) + 1
            data = bytearray()
            for k in range(n):
                w = await self.w_channel.recv()
                beat, strb = int(w.wdata).to_bytes(BEAT_BYTES, "little"), int(w.wstrb)
                for i in range(BEAT_BYTES):
                    if strb >> i & 1:
                        self.mem[(addr + k * BEAT_BYTES + i) % self.size] = beat[i]
                data += beat
            b = self.b_channel._transaction_obj()
            b.bid = 0
            b.bresp = self.error_of.get((addr, bytes(data)), OKAY)
            await self.b_channel.send(b)

    def pauses(self, aw: float = 0.0, w: float = 0.0, b: float = 0.0, seed: int = 1) -> None:
        """Random stalls of the three channels (probability per clock; 0: none)."""
        for i, (ch, p) in enumerate(((self.aw_channel, aw), (self.w_channel, w), (self.b_channel, b))):
            ch.set_pause_generator(pause_pattern(seed * 10 + i, p) if p > 0 else None)
            if p <= 0:
                ch.pause = False

    def hold(self, aw: bool | None = None, w: bool | None = None, b: bool | None = None) -> None:
        """Hold a channel stalled (True) or let it run (False); None leaves it."""
        for ch, v in ((self.aw_channel, aw), (self.w_channel, w), (self.b_channel, b)):
            if v is not None:
                ch.set_pause_generator(None)
                ch.pause = v


# ------------------------------------------------------------------------------------------------
# the protocol monitor


def edge_now() -> int:
    """The number of the rising edge just taken (the clock starts low: edges at 5, 15, .. ns)."""
    return int(get_sim_time("ns") // PERIOD_NS)


@dataclass
class Burst:
    j: int
    addr: int
    aw_edge: int
    beats: list[int] = field(default_factory=list)
    done_edge: int | None = None
    resp: int | None = None
    b_edge: int | None = None
    abandoned: bool = False  # cut by bus_rst

    def words(self) -> tuple[int, ...]:
        return tuple(w for d in self.beats for w in (d & M32, d >> 32))

    def data(self) -> bytes:
        return b"".join(d.to_bytes(BEAT_BYTES, "little") for d in self.beats)


def value(h) -> int | None:
    v = h.value
    return int(v) if v.is_resolvable else None


class AxiMonitor:
    """Checks the write master's AXI4 protocol at every clock (see the module docstring) and
    records every burst."""

    AW = ("awaddr", "awlen", "awsize", "awburst", "awcache", "awprot")
    W = ("wdata", "wstrb", "wlast")

    def __init__(self, dut, build: Build, allowed) -> None:
        self.dut = dut
        self.b = build
        self.allowed = allowed  # addr -> bool: inside a buffer of a configured ring
        self.h = {n: getattr(dut, f"m_axi_feat_{n}") for n in (*self.AW, *self.W, "awvalid", "awready", "wvalid",
                                                                  "wready", "bvalid", "bready", "bresp")}  # fmt: skip
        self.errors: list[str] = []
        self.bursts: list[Burst] = []
        self.aw_pend: tuple | None = None
        self.w_pend: tuple | None = None
        self.aw_shown = 0  # bursts whose AWVALID was raised
        self.aw_hs = 0  # AW handshakes
        self.w_burst = 0  # the burst the W beats belong to
        self.beat = 0  # its next beat
        self.b_hs = 0
        self.done = 0  # bursts whose 8 W beats are taken
        self.w_since_rst = 0  # W handshakes since the last rst / bus_rst
        self.err_since_rst = 0  # error responses since then
        self.errors_total = 0  # every error response
        self.dma_error_pulses = 0
        self.rst_seen = False  # rst (or bus_rst) sampled high since the bench last looked
        self.beats_at_rst = 0  # beats of the burst in progress taken before the last rst
        self.shown_at_rst = 0  # bursts whose AWVALID had risen at the first edge of the last reset
        self.in_rst = False
        self.in_bus_rst = 0
        self.max_outstanding = 0
        self.stalled_clocks = 0  # clocks with a valid up and its ready low

    def fail(self, edge: int, text: str) -> None:
        if not self.errors:
            self.errors.append(f"edge {edge}: {text}")

    async def run(self) -> None:
        while True:
            await RisingEdge(self.dut.clk)
            try:
                self.sample(edge_now())
            except Exception as exc:  # reported through the bench
                self.fail(edge_now(), f"monitor: {exc!r}")

    def sample(self, e: int) -> None:
        h, dut = self.h, self.dut
        if value(dut.bus_rst) == 1:
            if self.in_bus_rst and (value(h["awvalid"]) != 0 or value(h["wvalid"]) != 0):
                self.fail(e, "AWVALID or WVALID not 0 during bus_rst")
            if not self.in_bus_rst:
                self.shown_at_rst = len(self.bursts)
                for b in self.bursts[self.b_hs :]:
                    b.abandoned = True
                n = len(self.bursts)
                self.aw_shown = self.aw_hs = self.b_hs = self.w_burst = self.done = n
                self.beat = 0
                self.aw_pend = self.w_pend = None
            self.in_bus_rst += 1
            self.w_since_rst = self.err_since_rst = self.beats_at_rst = 0
            self.rst_seen = True
            return
        self.in_bus_rst = 0
        in_rst = value(dut.rst) == 1
        if in_rst:
            self.w_since_rst = self.err_since_rst = 0
            self.beats_at_rst = self.beat
            self.rst_seen = True
        awv, wv, bv = value(h["awvalid"]), value(h["wvalid"]), value(h["bvalid"])
        if awv is None or wv is None:
            self.fail(e, f"AWVALID {h['awvalid'].value} / WVALID {h['wvalid'].value} not 0 or 1")
            return
        if value(h["bready"]) != 1:
            self.fail(e, f"BREADY = {h['bready'].value}, must be 1")
        outstanding = self.aw_hs - self.b_hs
        if (awv or wv or outstanding) and value(dut.busy) != 1:
            self.fail(e, f"busy = {dut.busy.value} with AWVALID {awv}, WVALID {wv}, {outstanding} bursts unanswered")
        if value(dut.dma_error) == 1:
            self.dma_error_pulses += 1
        # write address
        if awv:
            aw = tuple(value(h[n]) for n in self.AW)
            if self.aw_pend is not None:
                if aw != self.aw_pend:
                    self.fail(e, f"AW payload changed while AWVALID waited for AWREADY: {self.aw_pend} -> {aw}")
            else:
                addr, alen, size, burst, cache, prot = aw
                j = self.aw_shown
                self.aw_shown += 1
                if (alen, size, burst, cache, prot) != (7, 3, 1, 0b0011, 0):
                    self.fail(e, f"burst {j}: AWLEN {alen} AWSIZE {size} AWBURST {burst} AWCACHE {cache} AWPROT "
                                 f"{prot}, expected 7, 3, 1 (INCR), 0b0011, 0")  # fmt: skip
                if addr is None or addr % SLOT_BYTES or (addr % 4096) + SLOT_BYTES > 4096:
                    self.fail(e, f"burst {j}: AWADDR {h['awaddr'].value} not 64-byte aligned (or crosses 4 KiB)")
                elif not self.allowed(addr):
                    self.fail(e, f"burst {j}: AWADDR {addr:#x} is not inside a buffer of a configured ring")
                self.bursts.append(Burst(j, addr or 0, e))
            if value(h["awready"]) == 1:
                self.aw_hs += 1
                self.aw_pend = None
                n_out = self.aw_hs - self.b_hs
                self.max_outstanding = max(self.max_outstanding, n_out)
                if n_out > self.b.outstanding:
                    self.fail(e, f"{n_out} bursts accepted and not answered, OUTSTANDING_g = {self.b.outstanding}")
            else:
                self.aw_pend = aw
                self.stalled_clocks += 1
        elif self.aw_pend is not None:
            self.fail(e, "AWVALID fell before AWREADY")
        if in_rst and not self.in_rst:
            self.shown_at_rst = self.aw_shown  # the bursts a soft reset lets finish
        self.in_rst = in_rst
        # write data
        if wv:
            wd = tuple(value(h[n]) for n in self.W)
            if self.w_pend is not None:
                if wd != self.w_pend:
                    self.fail(e, f"W payload changed while WVALID waited for WREADY (burst {self.w_burst} beat "
                                 f"{self.beat})")  # fmt: skip
            else:
                if self.beat == 0:
                    j = self.w_burst
                    if j >= self.aw_shown:
                        self.fail(e, f"W beats of burst {j} before its AWVALID ({self.aw_shown} raised)")
                    elif self.bursts[j].aw_edge != e:
                        self.fail(e, f"burst {j}: WVALID rose at edge {e}, AWVALID at edge {self.bursts[j].aw_edge}: "
                                     "they must rise together")  # fmt: skip
                data, strb, last = wd
                if strb != 0xFF:
                    self.fail(e, f"burst {self.w_burst} beat {self.beat}: WSTRB {h['wstrb'].value}, expected all ones")
                if last != int(self.beat == BURST_BEATS - 1):
                    self.fail(e, f"burst {self.w_burst} beat {self.beat}: WLAST = {last}")
                if data is None:
                    self.fail(e, f"burst {self.w_burst} beat {self.beat}: WDATA {h['wdata'].value}")
            if value(h["wready"]) == 1:
                self.w_pend = None
                if self.w_burst < len(self.bursts):
                    b = self.bursts[self.w_burst]
                    b.beats.append(wd[0] or 0)
                self.w_since_rst += 1
                self.beat += 1
                if self.beat == BURST_BEATS:
                    if self.w_burst < len(self.bursts):
                        self.bursts[self.w_burst].done_edge = e
                    self.done += 1
                    self.w_burst += 1
                    self.beat = 0
            else:
                self.w_pend = wd
                self.stalled_clocks += 1
        elif self.w_pend is not None:
            self.fail(e, f"WVALID fell before WREADY (burst {self.w_burst} beat {self.beat})")
        # write response
        if bv == 1:
            if self.b_hs >= self.aw_hs:
                self.fail(e, "a write response with no burst accepted")  # the slave model's fault
            else:
                b = self.bursts[self.b_hs]
                b.resp, b.b_edge = value(h["bresp"]), e
                self.b_hs += 1
                if b.resp:
                    self.err_since_rst += 1
                    self.errors_total += 1

    def idle(self) -> bool:
        return self.aw_pend is None and self.w_pend is None and self.aw_hs == self.b_hs == self.aw_shown


# ------------------------------------------------------------------------------------------------
# the bench


@dataclass
class Sent:
    """A frame as the reference sees it once sent."""

    tx: TxFrame
    seq: int
    start: int  # clock (edge) of its first beat
    fate: str  # "written", "overrun", "ring_error", "aborted"
    buffer: int | None = None
    base: int | None = None
    writer: SlotWriter | None = None
    writes: list[tuple[int, tuple[int, ...]]] = field(default_factory=list)
    closed: bool = False
    eof_clock: int = -1
    reset: bool = False  # a rst / bus_rst came before it was published
    burst_limit: int = 1 << 62  # reset: only bursts numbered below this (shown before the reset) are its
    fifo_drop: bool = False  # the scenario makes the full FIFO drop it
    matched: int = 0
    bursts: list[Burst] = field(default_factory=list)
    published: int | None = None
    final: str = ""  # "published", "error", "fifo", "overrun", "ring_error", "aborted", "reset"
    skipped_for: Sent | None = None

    @property
    def name(self) -> str:
        return f"frame {self.tx.number} ({self.tx.label or 'random'}, sent #{self.seq})"

    def complete(self) -> bool:
        return self.closed and self.fate == "written" and self.matched == len(self.writes)

    def record_b_edge(self) -> int | None:
        """The clock of its record's write response, once every write of the frame is answered."""
        if not self.complete() or not self.bursts or any(b.resp is None for b in self.bursts):
            return None
        return self.bursts[-1].b_edge

    def ok(self) -> bool:
        return all(b.resp == OKAY for b in self.bursts)


@dataclass
class PubEvent:
    edge: int
    ring_last: int
    ring_ready: int
    last_count: int
    last_frame: int
    mem: bytes


class DmaBench:
    """Drives orb_feat_dma one clock at a time (`cycle`), keeps the reference (see the module
    docstring) and checks every publication when it happens and everything else at `check`."""

    def __init__(self, dut, errors: bool = False, seed: int = 0) -> None:
        self.dut = dut
        self.b = Build.from_env()
        self.rng = np.random.default_rng(seed * 1000 + self.b.depth)
        idx = np.arange(RAM_BYTES, dtype=np.uint32)
        self.canary = ((idx * 73 + (idx >> 9) * 29 + 0x5A) & 0xFF).astype(np.uint8)
        self.mem = bytearray(self.canary.tobytes())
        self.errors = errors
        self.frames: list[Sent] = []
        self.frame_no = 0
        self.ring = Ring(0, 0, 0)
        self.active: Ring | None = None
        self.pos = 0
        self.ready = [0] * 16
        self.last_buffer = 0
        self.exp = {"overrun": 0, "aborted": 0, "dma_dropped": 0, "overflow": 0}
        self.fifo_drops = 0  # frames dropped by the full FIFO (the whole test)
        self.pubs: list[Sent] = []
        self.release_q: deque[tuple[int, int]] = deque()
        self.auto_release: tuple[int, int] | None = (1, 6)
        self.pending: list[PubEvent] = []
        self.slots_pushed = 0
        self.fifo_base = 0
        self.pace = True
        self.allow_fifo_drops = False
        self.abort_pending = False
        self.regions: list[tuple[int, int]] = []
        self.configured_at = -100  # the edge from which the ring registers hold self.ring
        self.changed_at = -100  # ... the last edge at which they changed value
        self.fresh_ring_ok = False  # a frame may start within RING_SETTLE clocks of a ring change
        self.hooks: list = []  # called after every clock (a scenario's reaction to the bus)
        self.clock = 0
        self.busy_low = 0
        self.last_beat_clock = -100
        self.last_frame_done = -100
        self.last_release = -100
        self.mf = 0  # matcher: the frame the next burst may belong to
        self.mi = 0  # matcher: the next burst to match
        self._driven: dict[str, int] = {}
        self.ddr: Ddr | None = None
        self.mon: AxiMonitor | None = None

    # ---- set-up ------------------------------------------------------------------------------
    async def start(self) -> None:
        dut = self.dut
        dut.bus_rst.value = 1
        dut.rst.value = 1
        for name in ("s_axis_feat_tvalid", "s_axis_feat_tlast", "frame_abort", "release_valid", "release_index",
                     "ring_base", "ring_stride", "ring_count"):  # fmt: skip
            getattr(dut, name).value = 0
            self._driven[name] = 0
        dut.s_axis_feat_tdata.value = 0
        cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
        self.ddr = Ddr(dut, self.mem, self.errors)
        self.mon = AxiMonitor(dut, self.b, self.allowed)
        cocotb.start_soon(self.mon.run())
        for _ in range(4):
            await RisingEdge(dut.clk)
        dut.bus_rst.value = 0
        dut.rst.value = 0
        for _ in range(3):
            await RisingEdge(dut.clk)
        self.clock = edge_now()
        self.mon.rst_seen = False

    def allowed(self, addr: int) -> bool:
        return any(lo <= addr and addr + SLOT_BYTES <= hi for lo, hi in self.regions)

    def configure(self, ring: Ring) -> None:
        """Drive RING_BASE / RING_STRIDE / RING_COUNT (from the next clock on)."""
        if ring != self.ring:
            self.changed_at = self.clock + 1
            if DEBUG:
                print(f"DEBUG edge {self.changed_at}: the ring registers change to {ring}")
        self.ring = ring
        self.configured_at = self.clock + 1
        self._drive("ring_base", ring.base & M32)
        self._drive("ring_stride", ring.stride & M32)
        self._drive("ring_count", ring.count)
        if ring_error(ring, self.b) == 0:
            self.regions += [r for r in ring.regions(self.b.depth) if r not in self.regions]

    def standard_ring(self, count: int, gap: int = 2 * SLOT_BYTES, offset: int = 0x1000) -> Ring:
        """A ring inside the window with `gap` bytes of canary between its buffers."""
        return Ring(self.b.win_lo + offset, self.b.buffer_bytes + gap, count)

    def frame(self, n: int, label: str = "") -> TxFrame:
        f = TxFrame(self.frame_no, [feature_beat(self.rng) for _ in range(n)], int(self.rng.integers(0, DROPS_LIMIT)),
                    frame_params(self.rng), label)  # fmt: skip
        self.frame_no = (self.frame_no + 1) & FRAME_MASK
        return f

    def next_number(self) -> int:
        n = self.frame_no
        self.frame_no = (self.frame_no + 1) & FRAME_MASK
        return n

    # ---- one clock -----------------------------------------------------------------------------
    def _drive(self, name: str, v: int) -> None:
        if self._driven.get(name) != v:
            getattr(self.dut, name).value = v
            self._driven[name] = v

    async def cycle(self, beat: tuple[int, int] | None = None, abort: int = 0, release: int | None = None,
                    rst: int = 0, bus_rst: int = 0) -> None:  # fmt: skip
        """One clock: these inputs are sampled at the next edge (edge self.clock + 1)."""
        edge = self.clock + 1
        if release is None and self.release_q and self.release_q[0][0] <= edge:
            release = self.release_q.popleft()[1]
        if release is not None:
            self.ready[release] = 0
            self.last_release = edge
            if DEBUG:
                print(f"DEBUG edge {edge}: release {release}, ring_ready {self.dut.ring_ready.value}")
        if beat is not None:
            self.dut.s_axis_feat_tdata.value = beat[0]
            self._drive("s_axis_feat_tlast", beat[1])
            self.last_beat_clock = edge
        self._drive("s_axis_feat_tvalid", int(beat is not None))
        self._drive("frame_abort", abort)
        self._drive("release_valid", int(release is not None))
        if release is not None:
            self._drive("release_index", release)
        self._drive("rst", rst)
        self._drive("bus_rst", bus_rst)
        await RisingEdge(self.dut.clk)
        self.clock = edge_now()
        if self.mon.errors:
            raise AssertionError(self.mon.errors[0])
        self._after_edge()

    async def idle(self, n: int) -> None:
        for _ in range(n):
            await self.cycle()

    def _after_edge(self) -> None:
        dut = self.dut
        if value(dut.s_axis_feat_tready) != 1:
            raise AssertionError(f"edge {self.clock}: s_axis_feat_tready = {dut.s_axis_feat_tready.value}")
        self._match_new()
        for ev in self.pending:
            self._publish(ev)
        self.pending = []
        if value(dut.frame_done) == 1:
            self.last_frame_done = self.clock
            self.pending.append(PubEvent(self.clock, value(dut.ring_last), value(dut.ring_ready),
                                         value(dut.last_count), value(dut.last_frame), bytes(self.mem)))  # fmt: skip
        self.busy_low = self.busy_low + 1 if value(dut.busy) == 0 else 0
        for hook in self.hooks:
            hook()

    # ---- matching bursts to frames -------------------------------------------------------------
    def _match_new(self) -> None:
        mon = self.mon
        while self.mi < len(mon.bursts) and mon.bursts[self.mi].done_edge is not None:
            self._match(mon.bursts[self.mi])
            self.mi += 1
        while self.mi < len(mon.bursts) and mon.bursts[self.mi].abandoned:
            self.mi += 1

    def _match(self, b: Burst) -> None:
        words = b.words()
        while True:
            if self.mf >= len(self.frames):
                raise AssertionError(f"burst {b.j} at {b.addr:#x} (edge {b.aw_edge}) belongs to no frame sent")
            f = self.frames[self.mf]
            if f.matched < len(f.writes) and f.writes[f.matched] == (b.addr, words) and b.j < f.burst_limit:
                f.matched += 1
                f.bursts.append(b)
                return
            if not f.closed:
                raise AssertionError(self._unexpected(b, f))
            if f.matched < len(f.writes) and not (f.reset or f.fifo_drop or f.fate == "aborted"
                                                   or self.allow_fifo_drops):  # fmt: skip
                raise AssertionError(self._unexpected(b, f))
            self.mf += 1

    def _unexpected(self, b: Burst, f: Sent) -> str:
        if f.matched >= len(f.writes):
            return f"burst {b.j} at {b.addr:#x} (edge {b.aw_edge}): {f.name} has no more writes ({len(f.writes)} done)"
        addr, want = f.writes[f.matched]
        where = self.describe(b.addr)
        if addr != b.addr:
            return (f"burst {b.j} (edge {b.aw_edge}): {f.name}'s write {f.matched} expected at {addr:#x} "
                    f"({self.describe(addr)}), the burst is at {b.addr:#x} ({where})")  # fmt: skip
        k = next(i for i in range(WORDS) if b.words()[i] != want[i])
        if DEBUG:
            print("DEBUG burst", [hex(x) for x in b.words()], "\nDEBUG want ", [hex(x) for x in want])
            for g in self.frames:
                print("DEBUG frame", g.tx.number, g.fate, [[hex(x) for x in w] for _, w in g.writes])
        return (f"burst {b.j} at {b.addr:#x} ({where}, edge {b.aw_edge}): {f.name}'s write {f.matched}, word {k} = "
                f"{b.words()[k]:#010x}, expected {want[k]:#010x}")  # fmt: skip

    def describe(self, addr: int) -> str:
        ring = self.active or self.ring
        for i in range(max(ring.count, 0)):
            lo = ring.buffer(i)
            if lo <= addr < lo + self.b.buffer_bytes:
                s, k = divmod(addr - lo, SLOT_BYTES)
                return f"buffer {i} slot {s} word {k // 4}"
        return "outside the active ring's buffers"

    # ---- publication ---------------------------------------------------------------------------
    def _publish(self, ev: PubEvent) -> None:
        cands = [f for f in self.frames if f.fate == "written" and f.published is None and not f.reset
                 and f.record_b_edge() is not None and f.record_b_edge() < ev.edge]  # fmt: skip
        good = [f for f in cands if f.ok()]
        if not good:
            raise AssertionError(f"edge {ev.edge}: frame_done (ring_last {ev.ring_last}, last_frame {ev.last_frame}) "
                                 "with no frame whose record has been answered OKAY and not yet published")  # fmt: skip
        f = good[0]
        later = [g for g in good[1:] if g.tx.number == ev.last_frame and g.buffer == ev.ring_last]
        if ev.last_frame != f.tx.number and later:
            raise AssertionError(
                f"edge {ev.edge}: frame_done for {later[0].name} (buffer {ev.ring_last}) while {f.name} (buffer "
                f"{f.buffer}, all {len(f.bursts)} bursts answered OKAY, its record at edge {f.record_b_edge()}) was "
                f"never published (dma_dropped {self.dut.dma_dropped.value.to_unsigned()})"
            )
        got = (ev.ring_last, (ev.ring_ready >> f.buffer) & 1, ev.last_count, ev.last_frame)
        want = (f.buffer, 1, f.writer.count, f.tx.number)
        assert got == want, (
            f"edge {ev.edge}: publication of {f.name}: ring_last, ring_ready bit, last_count, last_frame = {got}, "
            f"expected {want}"
        )
        n = f.writer.count + 1
        words = np.frombuffer(ev.mem, dtype="<u4", count=n * WORDS, offset=f.base).reshape(n, WORDS)
        mis = slot_mismatch(words, [f.writer.slots[s] for s in range(n)])
        assert mis is None, f"edge {ev.edge}: {f.name} in buffer {f.buffer} ({f.base:#x}) when published: {mis}"
        assert is_record(words[0]), f"{f.name}: slot 0 is not an end-of-frame record"
        lat = ev.edge - f.record_b_edge()
        assert lat <= PUB_LATENCY, f"{f.name}: published {lat} clocks after its record's write response"
        f.published = ev.edge
        f.final = "published"
        if DEBUG:
            print(f"DEBUG edge {ev.edge}: published {f.name} in buffer {f.buffer}, ring_ready {ev.ring_ready:#x}")
        self.pubs.append(f)
        self.ready[f.buffer] = 1
        self.last_buffer = f.buffer
        self.exp["overflow"] = (self.exp["overflow"] + f.writer.trunc) & M32
        if self.auto_release is not None:
            lo, hi = self.auto_release
            self.release_q.append((self.clock + int(self.rng.integers(lo, hi + 1)), f.buffer))

    # ---- sending frames ------------------------------------------------------------------------
    def _resolved_edge(self, g: Sent) -> int | None:
        """When frame g stopped holding its buffer in flight (None: still in flight)."""
        if g.reset or g.fate != "written" or g.published is not None:
            return -1 if g.published is None else g.published
        e = g.record_b_edge()
        if e is not None:
            if g.ok():
                return None  # answered OKAY: publication due (READY soon)
            return e
        low_since = self.clock - self.busy_low + 1
        if g.closed and g.matched < len(g.writes) and low_since > g.eof_clock + MARGIN and self.busy_low >= MARGIN:
            return low_since  # cut (dropped by the FIFO): free once the DUT is idle well after its end
        return None

    def _inflight(self, w: int) -> Sent | None:
        for g in self.frames:
            if g.fate == "written" and g.buffer == w and not g.reset and g.published is None:
                e = self._resolved_edge(g)
                if e is None:
                    return g
                if e > self.clock - MARGIN:
                    raise BenchError(f"{g.name} in buffer {w} resolved at edge {e}, too close to a frame start")
        return None

    def _next_buffer(self) -> int:
        ring = self.ring
        if ring_error(ring, self.b) == 0 and ring != self.active:
            return 0
        return self.pos

    def _free(self, w: int) -> bool:
        if self.clock + 1 - self.configured_at < RING_SETTLE:
            return False
        ring = self.ring
        if ring_error(ring, self.b) == 0 and ring != self.active:
            if self.busy_low < MARGIN or self.clock - self.last_beat_clock < MARGIN or not self.mon.idle():
                return False
        if self.ready[w] or any(r[1] == w for r in self.release_q):
            return False
        try:
            if self._inflight(w) is not None:
                return False
        except BenchError:
            return False
        if self.clock - self.last_frame_done < MARGIN or self.pending:
            return False
        return True

    async def wait_free(self) -> None:
        """Idle until the buffer the next frame goes to is free (not in flight, not READY)."""
        for _ in range(TIMEOUT):
            w = self._next_buffer()
            if self._free(w):
                return
            if self.ready[w] and self.auto_release is None and not any(r[1] == w for r in self.release_q):
                raise BenchError(f"waiting for buffer {w}, READY, with no release to come")
            await self.cycle()
        raise AssertionError(f"edge {self.clock}: buffer {self._next_buffer()} never became free: "
                             f"{self.state_text()}")  # fmt: skip

    async def wait_fifo(self) -> None:
        for _ in range(TIMEOUT):
            if self.slots_pushed - (self.mon.done - self.fifo_base) < self.b.fifo - 3:
                return
            await self.cycle()
        raise AssertionError(f"edge {self.clock}: the bursts stopped: {self.state_text()}")

    def _start(self, tx: TxFrame, release: int | None, abort: bool) -> Sent:
        edge = self.clock + 1
        s = Sent(tx, len(self.frames), edge, "")
        if DEBUG:
            print(f"DEBUG edge {edge}: first beat of {s.name}, release {release}, busy {self.dut.busy.value}")
        self.frames.append(s)
        if self.abort_pending or abort:
            self.abort_pending = False
            s.fate = "aborted"
            return s
        ring, err = self.ring, ring_error(self.ring, self.b)
        if 0 <= edge - self.changed_at <= SETTLE_DROP:
            s.fate = "ring_error"  # refused: the check of the changed registers has not settled
            return s
        if edge - self.configured_at < RING_SETTLE and not self.fresh_ring_ok:
            raise BenchError(f"{s.name} starts {edge - self.configured_at} clocks after a change of the ring")
        if err == 0 and ring != self.active:
            if self.busy_low < MARGIN or edge - self.last_beat_clock < MARGIN or not self.mon.idle():
                raise BenchError("a frame starts with a new ring while the DUT may be busy")
            self.active, self.pos = ring, 0
        w = self.pos
        held = self.ready[w] and release != w
        if held and self.clock - self.last_frame_done < MARGIN:
            raise BenchError(f"{s.name}: buffer {w} was published {self.clock - self.last_frame_done} clocks ago")
        g = None if held else self._inflight(w)
        if (held or g is not None) and err:
            raise BenchError(f"{s.name}: ring in error and buffer {w} held")
        if held or g is not None:
            s.fate, s.skipped_for = "overrun", g
        elif err:
            s.fate = "ring_error"
        else:
            s.fate, s.buffer, s.base, s.writer = "written", w, self.active.buffer(w), SlotWriter(self.b.depth)
        return s

    def _beat(self, s: Sent, word: int, last: int) -> None:
        if not last:
            if s.fate == "written":
                wr = s.writer.feature(word)
                if wr is not None:
                    s.writes.append((s.base + wr[0] * SLOT_BYTES, tuple(wr[1])))
                    self.slots_pushed += 1
            return
        s.closed, s.eof_clock = True, self.clock + 1
        if s.fate == "written":
            slot, words = s.writer.eof(word)
            s.writes.append((s.base + slot * SLOT_BYTES, tuple(words)))
            self.slots_pushed += 1
            if not s.fifo_drop:
                self.pos = (self.pos + 1) % self.active.count
        elif s.fate in ("overrun", "aborted"):
            self.exp[s.fate] += 1
            s.final = s.fate
        elif s.fate == "ring_error":
            self.exp["dma_dropped"] += 1
            s.final = "ring_error"

    async def send(self, tx: TxFrame, *, gap: tuple[float, int] = (0.0, 0), abort_at: int | None = None,
                   release_first: int | None = None, wait: bool = True, fifo_drop: bool = False) -> Sent:  # fmt: skip
        """Send frame tx: beat i after random idle clocks (probability gap[0], 1 .. gap[1] clocks);
        frame_abort in the clock of beat abort_at; a release of buffer release_first in the clock
        of the first beat. `wait`: first idle until its buffer is free."""
        beats = [(f, 0) for f in tx.features] + [(tx.eof_word(), 1)]
        if wait:
            await self.wait_free()
        s: Sent | None = None
        for i, (word, last) in enumerate(beats):
            if i and gap[0] > 0 and self.rng.random() < gap[0]:
                await self.idle(int(self.rng.integers(1, gap[1] + 1)))
            if self.pace and (s is None or s.fate == "written"):
                await self.wait_fifo()
            rel = None
            if i == 0:
                rel = release_first
                if rel is None and self.release_q and self.release_q[0][0] <= self.clock + 1:
                    rel = self.release_q.popleft()[1]  # an automatic release due in this clock
                s = self._start(tx, rel, abort_at == 0)
                s.fifo_drop = fifo_drop
            elif abort_at == i and s.fate != "aborted":
                s.fate = "aborted"
            self._beat(s, word, last)
            await self.cycle((word, last), int(abort_at == i), rel)
        return s

    async def abort_between(self) -> None:
        """A frame_abort pulse between frames: the next frame is aborted."""
        await self.cycle(abort=1)
        self.abort_pending = True

    # ---- resets --------------------------------------------------------------------------------
    def _reset_reference(self) -> None:
        for f in self.frames:
            if f.fate in ("written", "aborted") and f.published is None and f.final in ("", "aborted"):
                f.reset, f.burst_limit = True, self.mon.shown_at_rst
                f.final = f.final or "reset"
        self.ready = [0] * 16
        self.pos = 0
        self.active = None
        self.last_buffer = 0
        self.exp = dict.fromkeys(self.exp, 0)
        self.release_q.clear()
        self.abort_pending = False

    async def soft_reset(self, clocks: int = 2) -> None:
        for _ in range(clocks):
            await self.cycle(rst=1)
        self._reset_reference()
        await self.cycle()

    async def bus_reset(self, clocks: int = 3) -> None:
        for _ in range(clocks):
            await self.cycle(bus_rst=1)
        self._reset_reference()
        await self.cycle()

    # ---- checks --------------------------------------------------------------------------------
    async def drain(self) -> None:
        """Idle until the DUT is idle and every frame due has been published."""
        for _ in range(TIMEOUT):
            due = [f for f in self.frames if f.fate == "written" and not f.reset and f.published is None
                   and f.record_b_edge() is not None and f.ok()]  # fmt: skip
            quiet = (not self.release_q and self.clock - self.last_release >= MARGIN
                     and self.clock - self.last_beat_clock >= 8)  # fmt: skip
            if not due and self.busy_low >= 8 and self.mon.idle() and not self.pending and quiet:
                break
            if due and self.busy_low >= 8 and self.clock - due[0].record_b_edge() > 4 * PUB_LATENCY:
                break  # idle, and a frame due long ago was not published: fails below
            await self.cycle()
        else:
            due = due or [None]
        if due:
            f = due[0]
            if f is None:
                raise AssertionError(f"edge {self.clock}: the DUT did not drain: {self.state_text()}")
            raise AssertionError(
                f"edge {self.clock}: {f.name} (buffer {f.buffer}): every one of its {len(f.bursts)} bursts "
                f"answered OKAY, its record at edge {f.record_b_edge()}, not published "
                f"(dma_dropped {self.dut.dma_dropped.value.to_unsigned()}, bus_errors "
                f"{self.dut.bus_errors.value.to_unsigned()})"
            )
        self._finalize()
        self.slots_pushed, self.fifo_base = 0, self.mon.done

    def _finalize(self) -> None:
        for f in self.frames:
            if f.final or not f.closed:
                continue
            assert f.fate == "written", f.name
            if f.record_b_edge() is not None:
                assert not f.ok(), f"{f.name}: every burst answered OKAY, never published"
                f.final = "error"
                self.exp["dma_dropped"] += 1
            else:
                if not (f.fifo_drop or self.allow_fifo_drops):
                    raise AssertionError(f"{f.name}: {f.matched} of its {len(f.writes)} writes done, its record "
                                         f"never written (buffer {f.buffer}), with no reason to drop it")  # fmt: skip
                f.final = "fifo"
                self.exp["dma_dropped"] += 1
                self.fifo_drops += 1
                if not f.fifo_drop:  # the reference had moved the position on
                    self.pos = (self.pos - 1) % self.active.count
            if f.fifo_drop:
                assert f.final == "fifo", f"{f.name}: meant to be dropped by the full FIFO, but its record was written"

    def state_text(self) -> str:
        m = self.mon
        last = [(f.tx.number, f.fate, f.matched, len(f.writes), f.published) for f in self.frames[-4:]]
        counters = {n: value(getattr(self.dut, n)) for n in ("ring_error", "overrun", "aborted", "dma_dropped")}
        return (f"busy {self.dut.busy.value}, {counters}, AW shown {m.aw_shown} accepted {m.aw_hs}, W bursts {m.done}, "
                f"B {m.b_hs}, ring_ready {self.dut.ring_ready.value}, the last frames (number, fate, writes "
                f"done, writes, published) {last}")  # fmt: skip

    def check(self, canary_only: bool = False) -> None:
        """After drain: counters, status, the dma_error pulses and the whole DDR."""
        dut = self.dut
        m = self.mon
        names = ("overrun", "aborted", "dma_dropped", "overflow", "bus_errors", "beats", "ring_ready", "ring_last",
                 "busy", "ring_error")  # fmt: skip
        got = {n: value(getattr(dut, n)) for n in names}
        want = dict(self.exp)
        want |= {"bus_errors": m.err_since_rst, "beats": m.w_since_rst & M32,
                 "ring_ready": sum(r << i for i, r in enumerate(self.ready)), "ring_last": self.last_buffer, "busy": 0,
                 "ring_error": ring_error(self.ring, self.b)}  # fmt: skip
        got["ring_error"] = (got["ring_error"] or 0) & ring_error_mask(self.ring)
        bad = {n: (got[n], want[n]) for n in want if got[n] != want[n]}
        assert not bad, f"edge {self.clock}: (DUT, expected): {bad}"
        assert (m.w_since_rst + m.beats_at_rst) % BURST_BEATS == 0, (
            f"{m.w_since_rst} W beats since the reset ({m.beats_at_rst} of a burst before it): not whole bursts"
        )
        want_pulses = m.errors_total + self.fifo_drops
        assert m.dma_error_pulses == want_pulses, (
            f"dma_error high in {m.dma_error_pulses} clocks, expected {want_pulses} pulses "
            f"({m.errors_total} error responses, {self.fifo_drops} frames dropped by the FIFO)"
        )
        for f in self.frames:
            g = f.skipped_for
            if g is not None and g.record_b_edge() is not None:
                if g.record_b_edge() > f.start - MARGIN and g.record_b_edge() < f.start + MARGIN:
                    raise BenchError(f"{f.name} skipped for {g.name}, answered at {g.record_b_edge()}: too close")
        self.check_memory()

    def check_canary(self, regions: list[tuple[int, int]] | None = None) -> None:
        """Every byte outside `regions` (default: every buffer of a ring configured) is the canary."""
        regions = self.regions if regions is None else regions
        ram = np.frombuffer(bytes(self.mem), dtype=np.uint8)
        outside = np.ones(RAM_BYTES, dtype=bool)
        for lo, hi in regions:
            outside[lo:hi] = False
        bad = np.flatnonzero((ram != self.canary) & outside)
        assert len(bad) == 0, (
            f"{len(bad)} bytes outside the buffers written, the first at {int(bad[0]):#x}: "
            f"{int(ram[bad[0]]):#04x}, canary {int(self.canary[bad[0]]):#04x}"
        )

    def check_memory(self) -> None:
        """The DDR is the canary with exactly the monitored bursts applied (a burst cut by bus_rst:
        its slot not compared), and the canary outside every configured buffer."""
        self.check_canary()
        image = self.canary.copy()
        care = np.ones(RAM_BYTES, dtype=bool)
        for b in self.mon.bursts:
            if b.done_edge is not None:
                image[b.addr : b.addr + SLOT_BYTES] = np.frombuffer(b.data(), dtype=np.uint8)
            elif b.abandoned:
                care[b.addr : b.addr + SLOT_BYTES] = False
        ram = np.frombuffer(bytes(self.mem), dtype=np.uint8)
        bad = np.flatnonzero((ram != image) & care)
        assert len(bad) == 0, (
            f"DDR byte {int(bad[0]):#x} ({self.describe(int(bad[0]))}) = {int(ram[bad[0]]):#04x}, expected "
            f"{int(image[bad[0]]):#04x} from the bursts on the bus ({len(bad)} bytes differ)"
        )

    def published_numbers(self) -> list[int]:
        return [f.tx.number for f in self.pubs]


async def started(dut, errors: bool = False, seed: int = 0) -> DmaBench:
    b = DmaBench(dut, errors, seed)
    await b.start()
    return b


# ------------------------------------------------------------------------------------------------
# cocotb tests


@cocotb.test()
async def real_frames(dut) -> None:
    """Frames of golden_model features of photographs (all selection: every feature, truncated at
    DEPTH_g - 1; grid selection: its beats with sel_replace / sel_slot, the CPU view
    resolve_selection's) through random AW, W and B stalls into a ring of 4; each published buffer,
    decoded from the DDR when frame_done pulses, is the model's frame; frames published in order
    into buffers 0, 1, 2, 3, 0, ..."""
    b = await started(dut, seed=1)
    b.configure(b.standard_ring(4))
    b.ddr.pauses(aw=0.3, w=0.3, b=0.4, seed=3)
    d = b.b.depth
    names = ["astronaut", "camera", "coffee"]
    sent = []
    for sel in ("all", "grid"):
        for label, words, params in photo_frames(sel, min(40, d - 1), names):
            tx = TxFrame(b.next_number(), words, int(b.rng.integers(0, 50)), params, label)
            if sel == "grid":
                assert tx.slots(d)[1:] == [feature_slot(w) for w in resolve_selection(words)]
                assert any(SEL_REPLACE.get(w) for w in words), f"{label}: no replacement in the stream"
            sent.append(await b.send(tx, gap=(0.3, 6)))
    await b.drain()
    b.check()
    assert b.published_numbers() == [s.tx.number for s in sent]
    assert [f.buffer for f in b.pubs] == [k % 4 for k in range(len(sent))]
    trunc = [f.writer.trunc for f in b.pubs]
    assert any(trunc[:3]) == (d - 1 < max(len(s.tx.features) for s in sent[:3])), trunc
    for f in b.pubs:  # the CPU's decoding of the record
        rec = decode_record(f.writer.slots[0])
        assert (rec.count, rec.frame, rec.params) == (f.writer.count, f.tx.number, f.tx.params)
    dut._log.info("published %d frames (%s), truncated %s, %d bursts, max %d outstanding", len(b.pubs),
                  [f.tx.label for f in b.pubs], trunc, len(b.mon.bursts), b.mon.max_outstanding)  # fmt: skip


@cocotb.test()
async def empty_and_truncated_frames(dut) -> None:
    """Empty frames (the record alone, in slot 0, count 0); frames of DEPTH_g - 1 features (full),
    DEPTH_g (one truncated: count, truncated flag in the record, overflow) and 2 DEPTH_g + 3;
    frames at full rate and with gaps."""
    b = await started(dut, seed=2)
    b.configure(b.standard_ring(3))
    d = b.b.depth
    sizes = [0, 0, 0, d - 1, d, 2 * d + 3, 1, 0]
    for k, n in enumerate(sizes):
        await b.send(b.frame(n, f"{n} features"), gap=(0.0, 0) if k % 2 else (0.5, 3))
    await b.drain()
    b.check()
    assert len(b.pubs) == len(sizes)
    assert [f.writer.count for f in b.pubs] == [min(n, d - 1) for n in sizes]
    assert [f.writer.trunc for f in b.pubs] == [max(0, n - (d - 1)) for n in sizes]
    assert b.exp["overflow"] == 1 + d + 4
    assert [f.buffer for f in b.pubs] == [k % 3 for k in range(len(sizes))]
    rec = decode_record(b.pubs[4].writer.slots[0])
    assert rec.truncated == 1 and rec.truncated_flag, rec


@cocotb.test()
async def selection_replaces(dut) -> None:
    """Grid-selection frames: each buffer holds resolve_selection of its beats, in the order their
    places were taken; replacements right after their slot's first beat, two beats later, later,
    and with input gaps; a replacement is a second burst to the same address, after the first."""
    b = await started(dut, seed=3)
    b.configure(b.standard_ring(2))
    b.ddr.pauses(aw=0.2, w=0.2, b=0.2, seed=4)
    d = b.b.depth
    for n_new, n_repl, gaps in ((d - 1, 2 * d, 0.0), (d // 2, d, 0.5), (3, 9, 0.0), (1, 0, 0.0)):
        tx = selection_frame(b.rng, b.next_number(), n_new, n_repl)
        await b.send(tx, gap=(gaps, 3))
    await b.drain()
    b.check()
    assert len(b.pubs) == 4
    for f in b.pubs:
        assert f.tx.slots(d)[1:] == [feature_slot(w) for w in resolve_selection(f.tx.features)]
        first = {}
        for bu in f.bursts:
            first.setdefault(bu.addr, bu.j)
        assert len(f.bursts) == len(f.writes) > len(first), f"{f.name}: no address written twice"


@cocotb.test()
async def overrun_and_release(dut) -> None:
    """Ring of 2, the CPU holds both buffers: the next frames are skipped whole (overrun), the
    position does not move; a release in the very clock of a frame's first beat frees the buffer
    for it; a release of a buffer that is not READY does nothing. Ring of 1 with the record's write
    response held back: the next frame finds its buffer in flight and is skipped."""
    b = await started(dut, seed=4)
    b.auto_release = None
    b.configure(b.standard_ring(2))
    f = [b.frame(3 + k) for k in range(6)] + [b.frame(0), b.frame(4)]  # frame 6: its record is its only burst
    await b.send(f[0])
    await b.send(f[1])
    await b.drain()
    assert value(dut.ring_ready) == 3
    await b.idle(MARGIN)
    s2 = await b.send(f[2], wait=False)  # buffer 0 held: skipped
    s3 = await b.send(f[3], wait=False)
    await b.drain()
    assert (s2.fate, s3.fate) == ("overrun", "overrun") and value(dut.overrun) == 2
    await b.cycle(release=1)  # buffer 1 READY: released, but the position is at buffer 0
    await b.idle(2)
    assert value(dut.ring_ready) == 1
    s4 = await b.send(f[4], wait=False, release_first=0)  # released in the clock of its first beat
    assert s4.fate == "written" and s4.buffer == 0
    await b.drain()
    assert value(dut.ring_ready) == 1 and value(dut.ring_last) == 0
    await b.cycle(release=1)  # buffer 1 is not READY: nothing happens
    await b.idle(MARGIN)
    s5 = await b.send(f[5], wait=False)  # buffer 1 free: written
    await b.drain()
    b.check()
    assert s5.buffer == 1 and value(dut.ring_ready) == 3
    assert b.published_numbers() == [0, 1, 4, 5]
    # ring of 1, the record's response held: the next frame's buffer is still being written
    await b.cycle(release=0)
    await b.cycle(release=1)
    await b.idle(MARGIN)
    b.configure(b.standard_ring(1, offset=0x40000))
    await b.idle(MARGIN)
    b.auto_release = (1, 4)
    b.ddr.hold(b=True)
    s6 = await b.send(f[6])
    for _ in range(200):  # until its record's burst is on the bus (its response held)
        if s6.complete():
            break
        await b.cycle()
    assert s6.complete() and value(dut.busy) == 1
    s7 = await b.send(f[7], wait=False)
    assert s7.fate == "overrun"
    await b.idle(10)
    b.ddr.hold(b=False)
    await b.drain()
    b.check()
    assert b.published_numbers()[-1] == s6.tx.number and s6.buffer == 0
    assert value(dut.overrun) == 3


@cocotb.test()
async def abort(dut) -> None:
    """frame_abort mid-frame (the slots it had queued are still written into its buffer, which
    stays free: the next frame goes there), in the clock of the end-of-frame beat, between frames
    (aborts the next one), and during a frame that would have been skipped (counted as aborted)."""
    b = await started(dut, seed=5)
    b.configure(b.standard_ring(2))
    d = b.b.depth
    b.auto_release = None
    s0 = await b.send(b.frame(5))
    s1 = await b.send(b.frame(d + 4), abort_at=d // 2)  # truncation too: not in overflow
    await b.drain()
    assert s1.fate == "aborted" and s1.matched > 0 and value(dut.ring_ready) == 1
    assert value(dut.aborted) == 1 and value(dut.overflow) == 0
    f2 = b.frame(4)
    s2 = await b.send(f2, abort_at=len(f2.features))  # in the clock of its end-of-frame beat
    await b.drain()
    assert value(dut.aborted) == 2 and value(dut.ring_ready) == 1
    s3 = await b.send(b.frame(3))  # buffer 1, where frames 1 and 2 were going
    await b.drain()
    assert s3.buffer == 1 and value(dut.ring_ready) == 3 and value(dut.ring_last) == 1
    await b.idle(MARGIN)
    await b.send(b.frame(7), abort_at=2, wait=False)  # would be skipped: counted as aborted
    await b.send(b.frame(5), wait=False)  # skipped
    await b.drain()
    assert value(dut.aborted) == 3 and value(dut.overrun) == 1
    b.auto_release = (1, 3)
    await b.cycle(release=0)
    await b.cycle(release=1)
    await b.idle(MARGIN)
    await b.abort_between()
    await b.idle(2)
    s6 = await b.send(b.frame(2))  # aborted by the pulse before it
    s7 = await b.send(b.frame(9))
    await b.drain()
    b.check()
    assert s6.fate == "aborted" and s7.buffer == 0 and value(dut.aborted) == 4
    assert b.published_numbers() == [s0.tx.number, s3.tx.number, s7.tx.number]
    # the features the aborted frames had queued before the abort were written
    assert s1.matched == len(s1.writes) and s2.matched == len(s2.writes)


@cocotb.test()
async def ring_sizes(dut) -> None:
    """A ring of 1 buffer (every frame into buffer 0, after its release) and of 16 buffers
    (frames into 0 .. 15 and round again); a different ring, loaded while idle, restarts the
    position at 0; the same ring written again does not."""
    b = await started(dut, seed=6)
    b.configure(b.standard_ring(1))
    for n in (2, 0, 5):
        await b.send(b.frame(n))
    await b.drain()
    assert [f.buffer for f in b.pubs] == [0, 0, 0]
    b.configure(b.standard_ring(16, gap=SLOT_BYTES, offset=0x20000))
    for k in range(19):
        await b.send(b.frame(k % 3), gap=(0.2, 2))
    await b.drain()
    b.check()
    assert [f.buffer for f in b.pubs[3:]] == [k % 16 for k in range(19)]
    assert b.pos == 3
    same = b.ring
    b.configure(Ring(same.base, same.stride, same.count))  # the same values: the position stays
    await b.idle(MARGIN)
    s = await b.send(b.frame(1))
    b.configure(b.standard_ring(5, offset=0x60000))  # another ring: position 0
    await b.drain()
    s2 = await b.send(b.frame(1))
    await b.drain()
    b.check()
    assert (s.buffer, s2.buffer) == (3, 0)


@cocotb.test()
async def channels_and_outstanding(dut) -> None:
    """AWREADY held low: the W beats of the burst shown go on (they never wait for AWREADY), and
    the next burst waits (AWVALID and WVALID rise together); WREADY held low: the AW handshake goes
    on; the write responses held back: no more than OUTSTANDING_g bursts are accepted before their
    responses (the slave would take more); then everything is published bit-exact."""
    b = await started(dut, seed=16)
    b.configure(b.standard_ring(2))
    b.ddr.hold(aw=True)
    b.pace = False  # the frame fits the FIFO
    s0 = await b.send(b.frame(min(b.b.depth - 1, b.b.fifo - 4)))
    b.pace = True
    await b.idle(60)
    m = b.mon
    assert m.aw_hs == 0 and m.aw_pend is not None, "AWVALID not waiting for AWREADY"
    assert m.done == 1 and m.beat == 0, f"AWREADY low: {m.done} bursts and {m.beat} beats of W taken, expected 1 and 0"
    b.ddr.hold(aw=False, w=True)
    await b.idle(60)
    assert m.aw_hs == 2 and m.done == 1 and m.w_pend is not None, (
        f"WREADY low: {m.aw_hs} AW handshakes (expected 2: the waiting one, then the next burst's), {m.done} W bursts"
    )
    b.ddr.hold(w=False, b=True)
    await b.idle(150)
    held = m.aw_hs - m.b_hs
    assert 1 <= held <= b.b.outstanding, held
    b.ddr.hold(b=False)
    await b.drain()
    b.check()
    assert s0.final == "published"
    dut._log.info("responses held: %d bursts accepted and waiting (OUTSTANDING_g %d)", held, b.b.outstanding)


@cocotb.test()
async def fifo_overflow(dut) -> None:
    """AWREADY and WREADY held low (then WREADY alone) while frames stream in: the frame whose slot
    finds the burst FIFO full is dropped (its record never written, dma_dropped, one dma_error
    pulse), the earlier ones are published once the bus runs again, later frames bit-exact; the
    position does not move for the dropped frame. Its first slot, queued before the FIFO filled,
    is answered SLVERR: counted in bus_errors, the frame is not dropped twice, the next is
    published."""
    b = await started(dut, errors=True, seed=7)
    b.configure(b.standard_ring(8))
    d, fifo = b.b.depth, b.b.fifo
    for aw, w in ((True, True), (False, True)):
        b.pace = False
        b.ddr.hold(aw=aw, w=w)
        # frames filling the FIFO to FIFO_DEPTH_g - 2 slots, then one of at least 8 slots more
        room, fits = fifo - 2, []
        while room > 0:  # selection frames (replacements are slots too) cut to the room left
            tx = selection_frame(b.rng, b.next_number(), d - 1, 4 * d)
            tx.features = tx.features[: room - 1]
            fits.append(await b.send(tx))
            room -= len(tx.features) + 1
        x_tx = b.frame(min(d - 1, 12), "overflows")
        data = b"".join(w.to_bytes(4, "little") for w in x_tx.slots(d)[1])  # its first slot, queued: SLVERR
        for i in range(8):
            b.ddr.error_of[(b.ring.buffer(i) + SLOT_BYTES, data)] = SLVERR
        x = await b.send(x_tx, fifo_drop=True)
        await b.idle(50)
        assert value(dut.busy) == 1 and value(dut.frame_done) == 0
        b.ddr.hold(aw=False, w=False)
        b.pace = True
        await b.drain()
        b.check()
        assert x.final == "fifo" and all(f.final == "published" for f in fits), [f.final for f in fits]
        after = [await b.send(b.frame(n)) for n in (3, d - 1, 0)]
        await b.drain()
        b.check()
        assert after[0].buffer == x.buffer, "the position moved for the dropped frame"
        assert all(f.final == "published" for f in after)
    # each dropped frame once in dma_dropped; dma_error for each drop and each error response
    assert value(dut.dma_dropped) == 2 and value(dut.bus_errors) == 2 and b.mon.dma_error_pulses == 4


@cocotb.test()
async def error_responses(dut) -> None:
    """SLVERR on a feature burst, DECERR on a record, two errors in one frame: each such frame is not
    published (dma_dropped), its buffer is free again, bus_errors counts every error response and
    dma_error pulses for each; the frames between and after are published bit-exact. An error on
    a slot an aborted frame had queued counts in bus_errors only: the next frames (the first into the
    same buffer) are published, five of them (an error must not stay with a later frame)."""
    b = await started(dut, errors=True, seed=8)
    b.configure(b.standard_ring(3))
    b.ddr.pauses(aw=0.2, w=0.2, b=0.3, seed=9)
    frames = [b.frame(n) for n in (6, 5, 4, 7, 3, 2, 8, 6, 3, 1, 0, 2, 4, 1)]
    d = b.b.depth
    plan = {1: [(2, SLVERR)], 2: [(0, DECERR)], 4: [(1, SLVERR), (0, SLVERR)], 7: [(2, SLVERR)]}  # (slot, resp)
    for k, tx in enumerate(frames):
        for slot, resp in plan.get(k, []):  # the burst of that slot, in whichever buffer
            data = b"".join(w.to_bytes(4, "little") for w in tx.slots(d)[slot])
            for i in range(3):
                b.ddr.error_of[(b.ring.buffer(i) + slot * SLOT_BYTES, data)] = resp
        await b.send(tx, gap=(0.3, 3), abort_at=4 if k == 7 else None)  # frame 7: slots 1 .. 4 queued
    await b.drain()
    b.check()
    want = ["published", "error", "error", "published", "error", "published", "published", "aborted"]
    want += ["published"] * 6
    assert [f.final for f in b.frames] == want, [f.final for f in b.frames]
    assert value(dut.bus_errors) == 5 and value(dut.dma_dropped) == 3 and b.mon.dma_error_pulses == 5
    assert value(dut.aborted) == 1 and b.frames[7].matched == 4
    assert [f.buffer for f in b.frames] == [0, 1, 2, 0, 1, 2, 0, 1, 1, 2, 0, 1, 2, 0]


@cocotb.test()
async def bad_configurations(dut) -> None:
    """ring_error for aligned / unaligned base and stride, overlapping buffers, rings leaving the
    window (below, above, by one slot, and wrapping at 2^32 into it), count 0; frames started under
    a bad ring are dropped and counted, nothing is written (every byte of the DDR still the
    canary), the position does not move; the checkers themselves catch a planted byte."""
    b = await started(dut, seed=10)
    d, lo, hi = b.b.buffer_bytes, b.b.win_lo, b.b.win_hi
    cases = [
        (Ring(lo, d, 1), 0),
        (Ring(lo, 0, 1), 0),  # one buffer: the stride does not matter
        (Ring(lo, d, 16), 0 if lo + 16 * d <= hi else 4),
        (Ring(hi - 2 * d, d, 2), 0),  # exactly up to the window's end
        (Ring(lo + 32, d, 2), 1),
        (Ring(lo, d + 8, 2), 1),
        (Ring(lo, d - SLOT_BYTES, 2), 2),
        (Ring(lo, 0, 3), 2),
        (Ring(lo - SLOT_BYTES, d, 2), 4),
        (Ring(hi - 2 * d + SLOT_BYTES, d, 2), 4),
        (Ring(hi - d + SLOT_BYTES, d, 1), 4),
        (Ring(lo, 1 << 31, 3), 4),  # wraps at 2^32 back into the window
        (Ring(0xFFFF_F000, d, 2), 4),
        (Ring(lo + 4, d - 4, 3), 3),
        (Ring(lo, d, 0), 8),
        (Ring(lo + 4, d, 0), 9),
    ]
    latency = 0
    for ring, want in cases:
        assert ring_error(ring, b.b) == want, (ring, ring_error(ring, b.b), want)
        b.configure(ring)
        trace = []
        for _ in range(RING_SETTLE + 4):  # it settles within RING_SETTLE clocks, then holds
            await b.cycle()
            trace.append((value(dut.ring_error) or 0) & ring_error_mask(ring))
        assert trace[RING_SETTLE - 1 :] == [want] * 5, (
            f"ring_error {[f'{v:#06b}' for v in trace]} in the clocks after setting {ring}, expected {want:#06b} "
            f"from at most {RING_SETTLE} clocks on"
        )
        latency = max(latency, next(k for k, v in enumerate(trace) if trace[k:] == [want] * (len(trace) - k)) + 1)
    dut._log.info("ring_error follows the ring registers %d clocks after a change", latency)
    # frames under bad rings: dropped, nothing on the bus, nothing in the DDR
    b.regions = []
    for ring, want in cases:
        if want:
            b.configure(ring)
            await b.idle(3)
            s = await b.send(b.frame(int(b.rng.integers(0, 6))))
            assert s.fate == "ring_error"
    await b.drain()
    assert b.mon.aw_shown == 0 and value(dut.frame_done) == 0
    b.check()
    b.check_canary(regions=[])
    # the checkers catch a planted write (then the byte is restored)
    spot = lo + 3 * SLOT_BYTES + 5
    b.mem[spot] ^= 0x10
    for chk in (lambda: b.check_canary(regions=[]), b.check_memory):
        try:
            chk()
        except AssertionError:
            pass
        else:
            raise AssertionError("the canary check did not see a planted byte")
    b.mem[spot] ^= 0x10
    words = np.zeros((2, WORDS), dtype=np.uint32)
    want = "slot 1 (feature 0) word 9 = 0x00000000, expected 0x00000001"
    assert slot_mismatch(words, [[0] * WORDS, [0] * 9 + [1] + [0] * 6]) == want
    # a good ring after them: frames start at buffer 0 and are written
    ring = b.standard_ring(3)
    b.configure(ring)
    await b.idle(3)
    good = [await b.send(b.frame(n)) for n in (2, 3)]
    await b.drain()
    b.check()
    assert [f.buffer for f in good] == [0, 1]
    # a bad ring between frames of the same good ring: dropped, the position stays at 2
    b.configure(Ring(ring.base + 8, ring.stride, ring.count))
    await b.idle(3)
    s = await b.send(b.frame(2))
    b.configure(ring)
    await b.idle(MARGIN)
    s2 = await b.send(b.frame(2))
    await b.drain()
    b.check()
    assert s.fate == "ring_error" and s2.buffer == 2
    assert value(dut.dma_dropped) == sum(1 for _, w in cases if w) + 1


@cocotb.test()
async def ring_change_timing(dut) -> None:
    """The ring registers change from one good ring to another (ring_error 0 before and after); a
    frame whose first beat is sampled k edges after the edge that samples the change is dropped
    (dma_dropped) for k = 0 .. SETTLE_DROP, the check of the new values not yet settled, and written
    into buffer 0 of the new ring (the position restarts) from k = SETTLE_DROP + 1 on
    (docs/feature-dma.md, "The ring configuration and its checks"; the driver writes the ring only
    while the accelerator is stopped)."""
    b = await started(dut, seed=15)
    # three rings, so that each frame that is written meets a ring other than the active one
    rings = [b.standard_ring(2), b.standard_ring(3, offset=0x30000), b.standard_ring(2, offset=0x60000)]
    b.configure(rings[0])
    await b.send(b.frame(2))
    await b.drain()
    for n, k in enumerate((0, 1, SETTLE_DROP, SETTLE_DROP + 1, SETTLE_DROP + 2)):
        await b.idle(MARGIN + 2)
        b.configure(rings[(n + 1) % 3])
        for _ in range(k):  # send's first beat is sampled at the edge after the one configure's values are
            await b.cycle()
        b.fresh_ring_ok = True
        dropped = value(dut.dma_dropped)
        s = await b.send(b.frame(2), wait=False)
        b.fresh_ring_ok = False
        await b.drain()
        b.check()
        want = "ring_error" if k <= SETTLE_DROP else "published"
        assert s.final == want, f"k = {k}: {s.name} {s.final}, the contract says {want}"
        if k <= SETTLE_DROP:
            assert value(dut.dma_dropped) == dropped + 1, f"k = {k}: dma_dropped {dropped} -> {value(dut.dma_dropped)}"
        else:
            assert s.buffer == 0, f"k = {k}: {s.name} in buffer {s.buffer}, not 0 of the new ring"


@cocotb.test()
async def soft_reset_mid_burst(dut) -> None:
    """rst while AWVALID and WVALID wait for their readies (the first beat of a burst), and while
    WVALID waits in the middle of a burst with the responses held back (one of them SLVERR): the
    valids stay up with their payload, the burst ends with WLAST on its 8th beat, the responses are
    taken, nothing from before the reset is published (the error is counted after it), and the
    frames after it are published bit-exact from buffer 0."""
    b = await started(dut, errors=True, seed=11)
    b.configure(b.standard_ring(4))
    for case in ("first beat", "mid-burst"):
        for n in (2, 3):  # the position moves to 2
            await b.send(b.frame(n))
        await b.drain()
        await b.idle(10)
        if case == "first beat":
            b.ddr.hold(aw=True, w=True)
        else:
            b.ddr.hold(b=True)
        tx = b.frame(6)
        if case == "mid-burst":  # its first burst (slot 1), the one interrupted, is answered SLVERR
            words = tx.slots(b.b.depth)[1]
            addr = b.ring.buffer(b.pos) + SLOT_BYTES
            b.ddr.error_of[(addr, b"".join(w.to_bytes(4, "little") for w in words))] = SLVERR
        m = b.mon

        def stall_mid_burst(m=m) -> None:
            if m.beat >= 3 and not b.ddr.w_channel.pause:
                b.ddr.hold(w=True)

        if case == "mid-burst":
            b.hooks = [stall_mid_burst]
        b.pace = False
        await b.send(tx, wait=False)
        for _ in range(300):  # until a burst waits as the case wants
            if case == "first beat" and m.aw_pend is not None and m.w_pend is not None and m.beat == 0:
                break
            if case == "mid-burst" and m.w_pend is not None and 1 <= m.beat <= 6:
                break
            await b.cycle()
        else:
            raise AssertionError(f"{case}: no burst waiting for its ready: {b.state_text()}")
        b.hooks = []
        beat_at_reset = m.beat
        await b.soft_reset(2)
        assert b.mon.w_pend is not None, f"{case}: WVALID fell during rst"
        await b.idle(8)
        b.ddr.hold(aw=False, w=False, b=False)
        b.pace = True
        await b.drain()
        left = BURST_BEATS - beat_at_reset
        assert b.mon.w_since_rst == left, f"{case}: {b.mon.w_since_rst} W beats after rst, the burst had {left} left"
        b.check()
        if case == "mid-burst":
            assert value(dut.bus_errors) == 1, "the pre-reset SLVERR is not counted after the reset"
        assert all(f.final == "reset" for f in b.frames[-1:]), b.frames[-1].final
        after = [await b.send(b.frame(n)) for n in (4, 0, 2)]
        await b.drain()
        b.check()
        assert [f.buffer for f in after] == [0, 1, 2] and all(f.final == "published" for f in after)
        for i in range(4):
            await b.cycle(release=i)
        await b.idle(4)
        await b.soft_reset(1)


@cocotb.test()
async def bus_reset_mid_burst(dut) -> None:
    """bus_rst in the middle of a burst (W stalled): everything is reset at once, the valids fall
    during the reset, status and counters read 0, and the next frames are published bit-exact
    from buffer 0."""
    b = await started(dut, seed=12)
    b.configure(b.standard_ring(3))
    b.auto_release = None  # buffers 0 and 1 stay READY up to the reset
    for n in (3, 1):
        await b.send(b.frame(n))
    await b.drain()
    assert value(dut.ring_ready) == 3 and value(dut.ring_last) == 1
    b.pace = False
    m = b.mon
    b.hooks = [lambda: b.ddr.hold(w=True) if m.beat >= 2 and not b.ddr.w_channel.pause else None]
    await b.send(b.frame(9))
    for _ in range(500):
        if m.w_pend is not None and m.beat >= 2:
            break
        await b.cycle()
    else:
        raise AssertionError(f"no burst stalled: {b.state_text()}")
    b.hooks = []
    await b.bus_reset(3)
    names = ("ring_ready", "ring_last", "overrun", "overflow", "aborted", "dma_dropped", "bus_errors", "beats", "busy",
             "frame_done", "m_axi_feat_awvalid", "m_axi_feat_wvalid")  # fmt: skip
    left = {n: str(getattr(dut, n).value) for n in names if value(getattr(dut, n)) != 0}
    assert not left, f"not 0 in the clock after bus_rst (3 clocks, alone, rst 0): {left}"
    b.auto_release = (1, 6)
    b.ddr.hold(w=False)
    b.pace = True
    after = [await b.send(b.frame(n)) for n in (5, 2)]
    await b.drain()
    b.check()
    assert [f.buffer for f in after] == [0, 1] and all(f.final == "published" for f in after)


@cocotb.test()
async def random_soak(dut) -> None:
    """Random frame sizes, selection frames, gaps, stalls, late releases, aborts and skipped frames,
    all at once (ORB_DMA_FRAMES frames: a few by default, many in the slow run)."""
    b = await started(dut, seed=13)
    count = int(b.rng.integers(2, 6))
    b.configure(b.standard_ring(count))
    heavy = env_int("ORB_DMA_HEAVY", 0)
    b.ddr.pauses(aw=0.5 if heavy else 0.3, w=0.5 if heavy else 0.3, b=0.6 if heavy else 0.3, seed=14)
    b.auto_release = (1, 300 if heavy else 60)
    d = b.b.depth
    for _ in range(env_int("ORB_DMA_FRAMES", 40)):
        r = b.rng.random()
        if r < 0.25:
            tx = selection_frame(b.rng, b.next_number(), int(b.rng.integers(1, d)), int(b.rng.integers(0, d)))
        else:
            tx = b.frame(int(b.rng.integers(0, d + 3)))
        abort_at = int(b.rng.integers(0, len(tx.features) + 1)) if b.rng.random() < 0.1 else None
        await b.send(tx, gap=(float(b.rng.choice([0.0, 0.2, 0.6])), 4), abort_at=abort_at)
    await b.drain()
    b.check()
    dut._log.info("published %d of %d frames, %d bursts, max %d outstanding, %d stalled clocks", len(b.pubs),
                  len(b.frames), len(b.mon.bursts), b.mon.max_outstanding, b.mon.stalled_clocks)  # fmt: skip


# ------------------------------------------------------------------------------------------------
# pytest runners

BUILDS = {
    "d16_fifo16_out1": {"DEPTH_g": 16, "FIFO_DEPTH_g": 16, "OUTSTANDING_g": 1, "WIN_BASE_MB_g": 1, "WIN_SIZE_MB_g": 1},
    "d64_fifo256_out4": {"DEPTH_g": 64, "FIFO_DEPTH_g": 256, "OUTSTANDING_g": 4, "WIN_BASE_MB_g": 1,
                         "WIN_SIZE_MB_g": 1},
}  # fmt: skip


@pytest.mark.parametrize("build", list(BUILDS))
def test_feat_dma(build: str) -> None:
    run("orb_feat_dma", "test_orb_feat_dma", BUILDS[build], env=SIM_ENV)


@pytest.mark.slow
def test_feat_dma_soak() -> None:
    """Many random frames under heavy stalls, FIFO of 16 behind a ring of 16-slot buffers, 8 outstanding."""
    generics = {"DEPTH_g": 16, "FIFO_DEPTH_g": 16, "OUTSTANDING_g": 8, "WIN_BASE_MB_g": 1, "WIN_SIZE_MB_g": 2}
    run("orb_feat_dma", "test_orb_feat_dma", generics, testcase="random_soak",
        env={**SIM_ENV, "ORB_DMA_FRAMES": "400", "ORB_DMA_HEAVY": "1"})  # fmt: skip


# ------------------------------------------------------------------------------------------------
# the protocol monitor against scripted violations (no simulator): every rule it checks can fail


class _Sig:
    def __init__(self, width: int) -> None:
        self.width = width
        self.value = LogicArray(0, width)

    def set(self, v: int) -> None:
        self.value = LogicArray(v, self.width)


class _FakeDut:
    WIDTHS: ClassVar[dict[str, int]] = {"awaddr": 32, "awlen": 8, "awsize": 3, "awburst": 2, "awcache": 4,
                                        "awprot": 3, "wdata": 64, "wstrb": 8, "bresp": 2}  # fmt: skip

    def __init__(self) -> None:
        for n in (*AxiMonitor.AW, *AxiMonitor.W, "awvalid", "awready", "wvalid", "wready", "bvalid", "bready",
                  "bresp"):  # fmt: skip
            setattr(self, f"m_axi_feat_{n}", _Sig(self.WIDTHS.get(n, 1)))
        for n in ("bus_rst", "rst", "busy", "dma_error", "clk"):
            setattr(self, n, _Sig(1))
        self.m_axi_feat_bready.set(1)

    def drive(self, **values: int) -> None:
        for n, v in values.items():
            getattr(self, n if n in ("bus_rst", "rst", "busy") else f"m_axi_feat_{n}").set(v)


def _burst_clocks(addr: int, **over: int) -> list[dict[str, int]]:
    """The clocks of one legal burst with AW and W ready at once: AW with beat 0, then beats 1..7."""
    aw = {"awvalid": 1, "awready": 1, "awaddr": addr, "awlen": 7, "awsize": 3, "awburst": 1, "awcache": 3, "awprot": 0}
    clocks = []
    for k in range(BURST_BEATS):
        c = {"wvalid": 1, "wready": 1, "wdata": addr + k, "wstrb": 0xFF, "wlast": int(k == 7), "busy": 1}
        c |= aw if k == 0 else {"awvalid": 0}
        clocks.append(c | over)
    return clocks


def _run_monitor(clocks: list[dict[str, int]], outstanding: int = 4) -> list[str]:
    dut = _FakeDut()
    mon = AxiMonitor(dut, Build(16, 16, outstanding, 0, 1 << 30), lambda addr: addr < 0x10000)
    for e, c in enumerate(clocks):
        dut.drive(**({"awvalid": 0, "wvalid": 0, "bvalid": 0} | c))
        mon.sample(e)
    return mon.errors


def test_protocol_monitor_catches() -> None:
    """Each rule of the monitor, broken once in an otherwise legal script, is reported."""
    ok = [*_burst_clocks(0x40), {"bvalid": 1, "busy": 1}]
    assert _run_monitor(ok) == []
    stall = [dict(c) for c in _burst_clocks(0x80)]
    stall.insert(3, dict(stall[3], wready=0))  # beat 3 waits one clock
    assert _run_monitor(stall) == []

    def broken(clocks: list[dict[str, int]], outstanding: int = 4) -> str:
        errors = _run_monitor(clocks, outstanding)
        assert errors, "a broken script passed the monitor"
        return errors[0]

    assert "AWLEN 6" in broken(_burst_clocks(0x40, awlen=6)[:1])
    assert "not 64-byte aligned" in broken(_burst_clocks(0x48)[:1])
    assert "not inside a buffer" in broken(_burst_clocks(0x20000)[:1])
    assert "WLAST" in broken([dict(c, wlast=0) for c in _burst_clocks(0x40)])
    assert "WSTRB" in broken(_burst_clocks(0x40, wstrb=0x7F))
    b = _burst_clocks(0x40)
    assert "changed while WVALID waited" in broken([dict(b[0], wready=0), b[0] | {"wdata": 5, "awvalid": 0}])
    assert "WVALID fell" in broken([dict(b[0], wready=0), {"awvalid": 0, "busy": 1}])
    aw_wait = dict(b[0], awready=0, wvalid=0)
    assert "AW payload changed" in broken([aw_wait, dict(aw_wait, awaddr=0x80)])
    assert "AWVALID fell" in broken([aw_wait, {"busy": 1}])
    assert "W beats of burst 0 before its AWVALID" in broken([dict(b[0], awvalid=0)])
    assert "must rise together" in broken([aw_wait, dict(b[0], awvalid=1, awready=1)])
    two = _burst_clocks(0x40) + _burst_clocks(0x80)
    assert "OUTSTANDING_g = 1" in broken(two, 1)
    assert "busy = " in broken(_burst_clocks(0x40, busy=0))
    assert "BREADY" in broken(_burst_clocks(0x40, bready=0)[:1])
    assert "during bus_rst" in broken([{"bus_rst": 1}, {"bus_rst": 1, "awvalid": 1}])
