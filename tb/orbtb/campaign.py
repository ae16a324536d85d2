# SPDX-License-Identifier: MIT
"""Randomised fault campaign on the fast path (docs/fast-sim.md, "The fault campaign"): frame after
frame into the Verilated netlist of orb_accel_top, good ones and faulty ones, with the CPU side
played by the shipped driver as it would run on the board, and every outcome checked against a
reference.

Events (one per step, drawn from a seeded generator; the seed replays the campaign exactly):

- good: a frame with random blanking;
- faults: short_line, long_line, few_lines, many_lines, no_sof, early_sof (a start of frame in
  mid-frame), cable_cut (the frame stops at a random beat, no pixel for half a frame period to three,
  then the video comes back in the middle of a frame, without its start, and the next frame
  follows), reset (rst in mid-frame), soft_reset (CTRL.soft_reset in mid-frame);
- changes, each followed by a good frame: threshold, mode, selection (`all` or `grid` with a random
  budget, cell grid and low threshold), backpressure (random tready on the overlay output during the
  frame), hold (the CPU keeps the next one or two banks it reads for one to four steps instead of
  releasing them, so the accelerator must skip the frames that find their bank held).

The reference (`Reference`): orbtb.video_check.VideoCheckModel says which frames the protocol
checker closes good, with which pixels (a frame with lines missing may be completed by the next
frame's pixels when that one has no start of frame, or by the rest of a frame after a cable cut,
exactly as the hardware must do), and orb_feat_mem's bank rules (docs/feature-memory.md, Protocol)
say which of those are published, in which bank and with which frame number, and which are skipped
because their bank is still held; each published frame must be the golden model's at the threshold,
mode and selection in force at its first pixel, and its end-of-frame record must carry them.

The CPU: after each step's video it waits for the interrupts, reads every bank newly READY (the
older first), and releases them, except the banks a hold keeps and, while the checker has a frame
open, the bank that frame goes to (whether the frame saw that bank held or free would depend on the
time its first feature reached the memory: a slow CPU, and a campaign whose reference is exact).

Checked per step: the frames published are exactly the frames the reference publishes, in order,
in their banks, with their numbers, parameters and features bit-exact (a frame whose record counts
features lost to a full FIFO or bank: the model's list less exactly that many); STATUS.bank_ready
and the OVERRUN counter as the reference says.

A DDR build (MEM_KIND_g "DDR": orb_feat_dma, docs/feature-dma.md) runs the same campaign on a ring
of DDR_RING buffers in the harness's memory (the reference's banks become ring buffers, taken in
turn), with three more events, each on a good frame: ddr_stall (the interconnect stops for an
eighth of a frame period to two: AWREADY, WREADY, both, or the write responses held back, long
enough to fill the burst FIFO; a quarter of them with an error response to one of the frame's
first bursts too), ddr_error (one burst of the frame answered SLVERR or DECERR: its record or one
of its first 64 feature slots; a quarter of the time one of the first bursts of a frame the
checker rejects instead, which must cost no frame) and ddr_slow (random AWREADY and WREADY,
delayed write responses, 1 to 8 bursts outstanding, for the frame). A DDR fault is injected only
in a step whose video closes exactly one frame (published, or for ddr_error rejected) with none
open before or after it (so each burst of the step is that frame's). The harness logs every
burst; per step the frames the reference expects and the ones published must be reconciled: a
frame missing is legal only after a stall or slowness with its record never written (dropped at
a full burst FIFO: its ring position is not used) or after an error response with its record
written (dropped at its record's response: its position is used); DMA_DROPPED must rise by
exactly the frames so explained, DMA_BUS_ERRORS must equal the error responses the harness gave
since the last reset, and no frame with an error response is published. At the end: no AXI rule
broken by the master, no write outside the memory, and the memory outside the ring as it was (a
canary). A lock-up is any of: a bus operation without an
answer, the video source unable to send its frame within 40 frame periods or stalled for 20, and
the watchdog: no frame for WATCHDOG_FRAMES frame periods after the last beat while the reference
expects one. The campaign stops at the first lock-up (what follows it would not mean anything).
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from golden_model import regs
from golden_model.config import Config
from golden_model.featmem import SLOT_BYTES, SLOT_RECORD_WORDS, decode_record
from golden_model.features import Features, first_difference
from golden_model.frameparams import FrameParams
from golden_model.luma import rgb_to_luma
from golden_model.pipeline import extract
from orb_accel.driver import Frame, OrbAccel
from orb_sim.fast.jobs import FastAccel, is_ddr, pack
from orb_sim.fast.sim import FLAG_LAST, FLAG_USER, RESP_FORGOTTEN, FastSimError, frame_program

from .video_check import FrameEnd, VideoCheckModel

FAULTS = ("short_line", "long_line", "few_lines", "many_lines", "no_sof", "early_sof", "cable_cut", "reset",
          "soft_reset")  # fmt: skip
CHANGES = ("threshold", "mode", "selection", "backpressure", "hold")
KINDS = ("good", *FAULTS, *CHANGES)
WEIGHTS = {"good": 6, **{k: 1 for k in FAULTS}, "threshold": 1, "mode": 1, "selection": 2, "backpressure": 1,
           "hold": 1}  # fmt: skip
# a DDR build's events (the module docstring), drawn besides those
DDR_FAULTS = ("ddr_stall", "ddr_error")
DDR_CHANGES = ("ddr_slow",)
DDR_KINDS = (*DDR_FAULTS, *DDR_CHANGES)
DDR_WEIGHTS = {"ddr_stall": 2, "ddr_error": 2, "ddr_slow": 1}
DDR_RING = 3  # ring buffers of a DDR campaign (not a power of two: the wrap is exercised)
DDR_ERROR_SLOTS = 64  # ddr_error hits the record or one of the frame's first this many feature slots
DDR_ERROR_BAD = 0.25  # ... or, this often, one of the first DDR_ERROR_SLOTS bursts of a frame the checker rejects
DDR_STALL_ERROR = 0.25  # a ddr_stall with an error to one of the frame's first DDR_ERROR_SLOTS bursts too
CANARY = 0xA5  # the memory outside the ring, checked at the end
QUIET_CLOCKS = 2_000  # no interrupt for this long after the video: the step's frames are in (latency: tens of clocks)
WATCHDOG_FRAMES = 4  # a lock-up: no frame for this many frame periods after the last beat while one is expected
SOURCE_FRAMES = 40  # a lock-up: the video source cannot send a step's video within this many frame periods
KEEP_MESSAGES = 20  # the first mismatches and lock-ups a report keeps


@dataclass(frozen=True)
class Setting:
    """What the CPU has written: threshold, mode and selection (THRESHOLD, CTRL.mode, SELECT)."""

    threshold: int
    mode: str
    selection: str
    budget: int
    cells: tuple[int, int]
    low: int

    def params(self) -> FrameParams:
        """The parameters the end-of-frame record of a frame started under this setting carries."""
        return FrameParams(self.threshold, self.low, self.mode, self.selection, self.budget, *self.cells)

    def text(self) -> str:
        return self.params().text()


@dataclass(frozen=True)
class Published:
    """A frame the reference publishes: its number, bank, setting and pixels (luma)."""

    number: int
    bank: int
    setting: Setting
    luma: np.ndarray


class Reference:
    """What the accelerator must make of the beats the source sent: the checker's model closes the
    frames, good or bad; orb_feat_mem's rules (docs/feature-memory.md) publish a good frame in the
    bank the next frame goes to unless that bank is still READY (then the frame is skipped and
    counted in OVERRUN); every frame the checker closes, good or bad, takes a frame number."""

    def __init__(self, width: int, height: int, buffers: int = regs.BANKS) -> None:
        self.w, self.h = width, height
        self.buffers = buffers  # the banks, or a DDR build's ring buffers (taken in turn)
        self.check = VideoCheckModel(width, height)
        self.ready: set[int] = set()  # READY banks: published and not released
        self.next_bank = 0  # the bank the next frame goes to
        self.number = 0  # the next frame's number
        self.overrun = 0  # frames skipped whole since the last reset (OVERRUN)
        self.open_setting: Setting | None = None  # the setting at the open frame's first pixel
        self.closed_good = self.closed_bad = self.skipped = 0  # over the whole campaign
        self.published: list[Published] = []  # since the CPU last took them

    def reset(self) -> None:
        """rst or CTRL.soft_reset: the open frame is abandoned, both banks are free, the counters restart."""
        self.check.reset()
        self.check.forget()
        self.ready.clear()
        self.next_bank = self.number = self.overrun = 0
        self.open_setting = None

    @property
    def frame_open(self) -> bool:
        return self.check._open

    def feed(self, data: np.ndarray, flags: np.ndarray, setting: Setting) -> None:
        """The beats the checker took, with the setting written while they streamed: every frame that
        opens among them has it, a frame open before them keeps its own."""
        chk = self.check
        was_open, n_ends = chk._open, len(chk.ends)
        chk.feed_arrays(_luma_words(data), flags & FLAG_USER, (flags & FLAG_LAST) >> 1)
        for i, end in enumerate(chk.ends[n_ends:]):
            self._close(end, self.open_setting if i == 0 and was_open else setting)
        if not chk._open:
            self.open_setting = None
        elif not was_open or len(chk.ends) > n_ends:
            self.open_setting = setting
        chk.forget()

    def _close(self, end: FrameEnd, setting: Setting | None) -> None:
        assert setting is not None, "a frame closed that the reference never saw open"
        number, self.number = self.number, (self.number + 1) & 0xFFFF
        if end.bad:
            self.closed_bad += 1  # aborted: never published, not an overrun, its bank stays free
            return
        self.closed_good += 1
        if self.next_bank in self.ready:
            self.overrun += 1
            self.skipped += 1
            return
        n = self.w * self.h
        pixels = np.fromiter((b.data for b in self.check.out[end.beat - n + 1 : end.beat + 1]), np.uint8, n)
        self.published.append(Published(number, self.next_bank, setting, pixels.reshape(self.h, self.w)))
        self.ready.add(self.next_bank)
        self.next_bank = (self.next_bank + 1) % self.buffers

    def unpublish(self, p: Published, position_used: bool) -> None:
        """A DDR build dropped p, the last frame published (docs/feature-dma.md): at its record's
        error response (its ring position was used: the next frame goes to the next buffer), or
        at a full burst FIFO (position_used False: the next frame goes to p's buffer)."""
        assert self.next_bank == (p.bank + 1) % self.buffers, "only the last frame published can be dropped"
        self.ready.discard(p.bank)
        if not position_used:
            self.next_bank = p.bank

    def take(self) -> list[Published]:
        out, self.published = self.published, []
        return out


@dataclass
class Event:
    step: int
    kind: str
    photo: int
    setting: Setting
    detail: str = ""
    published: int = 0
    skipped: int = 0
    outcome: str = ""


@dataclass
class CampaignResult:
    seed: int
    init_seed: int = 0
    generics: dict[str, int | str] = field(default_factory=dict)
    events: list[Event] = field(default_factory=list)
    mismatches: list[str] = field(default_factory=list)
    lockups: list[str] = field(default_factory=list)
    frames_sent: int = 0  # whole or cut; a cable cut sends three (the frame cut, the rest it resumes in, the next)
    frames_good: int = 0  # closed good by the checker
    frames_bad: int = 0  # closed bad (padded, aborted)
    frames_published: int = 0
    frames_skipped: int = 0  # good, but their bank was held
    late_steps: int = 0  # steps whose frames came after QUIET_CLOCKS (not a lock-up)
    deferred_releases: int = 0  # releases the CPU put off while a frame was open
    features_checked: int = 0
    counters: dict[str, int] = field(default_factory=dict)
    clocks: int = 0
    wall_s: float = 0.0
    # a DDR build's (the module docstring)
    ddr: bool = False
    ddr_injected: int = 0  # DDR events whose fault was injected (a step with exactly one frame)
    ddr_not_injected: int = 0  # ... not (the step had another number of frames, or one open before it)
    frames_dropped_fifo: int = 0  # expected, not published: dropped at a full burst FIFO (ddr_stall, ddr_slow)
    frames_dropped_error: int = 0  # ... dropped at an error response (ddr_error)
    error_responses: int = 0  # SLVERR and DECERR responses the harness gave
    dma: dict[str, int] = field(default_factory=dict)  # DMA_DROPPED, DMA_BUS_ERRORS, DMA_BEATS at the end
    axi: dict[str, int] = field(default_factory=dict)  # the harness's DDR counters at the end

    @property
    def faults(self) -> int:
        return sum(e.kind in FAULTS or e.kind in DDR_FAULTS for e in self.events)

    def by_kind(self, kinds: Sequence[str]) -> dict[str, int]:
        n = Counter(e.kind for e in self.events)
        return {k: n[k] for k in kinds}

    @property
    def ok(self) -> bool:
        return not self.mismatches and not self.lockups

    def summary(self) -> str:
        mix = ", ".join(f"{k} {v}" for k, v in self.by_kind(KINDS + DDR_KINDS).items() if v)
        ddr = ""
        if self.ddr:
            ddr = (f"DDR: {self.ddr_injected} faults injected ({self.ddr_not_injected} events not), "
                   f"{self.frames_dropped_fifo} frames dropped at the full burst FIFO, {self.frames_dropped_error} "
                   f"at an error response ({self.error_responses} error responses), DMA {self.dma}; ")  # fmt: skip
        return (f"seed {self.seed} (initial state {self.init_seed}): {len(self.events)} events ({mix}); "
                f"{self.frames_sent} frames sent, {self.frames_good} closed good, {self.frames_bad} bad; "
                f"{self.frames_published} published, {self.frames_skipped} skipped (bank held); "
                f"{self.features_checked} features checked; faults injected {self.faults}; {ddr}"
                f"lock-ups {len(self.lockups)}; mismatches {len(self.mismatches)}; "
                f"{self.clocks:,} clocks in {self.wall_s:.0f} s")  # fmt: skip

    def report(self) -> dict[str, Any]:
        """The figures as JSON (python -m orb_flow.record campaign reads it)."""
        return {
            "seed": self.seed,
            "init_seed": self.init_seed,
            "generics": dict(self.generics),
            "events": len(self.events),
            "faults_injected": self.faults,
            "faults_by_kind": self.by_kind(FAULTS),
            "changes_by_kind": self.by_kind(CHANGES),
            "good_events": self.by_kind(("good",))["good"],
            "frames_sent": self.frames_sent,
            "frames_closed_good": self.frames_good,
            "frames_closed_bad": self.frames_bad,
            "frames_published": self.frames_published,
            "frames_skipped_bank_held": self.frames_skipped,
            "features_checked": self.features_checked,
            "late_steps": self.late_steps,
            "deferred_releases": self.deferred_releases,
            "lockups": len(self.lockups),
            "mismatches": len(self.mismatches),
            "first_lockups": self.lockups[:KEEP_MESSAGES],
            "first_mismatches": self.mismatches[:KEEP_MESSAGES],
            "counters": self.counters,
            "sim_clocks": self.clocks,
            "wall_s": round(self.wall_s, 1),
            **(self.ddr_report() if self.ddr else {}),
        }

    def ddr_report(self) -> dict[str, Any]:
        return {"ddr": {
            "ring_buffers": DDR_RING, "faults_by_kind": self.by_kind(DDR_FAULTS), "changes_by_kind":
            self.by_kind(DDR_CHANGES), "injected": self.ddr_injected, "not_injected": self.ddr_not_injected,
            "frames_dropped_fifo": self.frames_dropped_fifo, "frames_dropped_error": self.frames_dropped_error,
            "error_responses": self.error_responses, "dma": self.dma, "axi": self.axi,
        }}  # fmt: skip


def frame_period(w: int, h: int) -> int:
    """Clocks of the longest frame fault_program draws (blanking 23 clocks a line, 299 a frame)."""
    return (w + 24) * h + 300


def fault_program(kind: str, words: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray,
                                                                                   np.ndarray, str, int]:  # fmt: skip
    """(data, flags, gaps, detail, frames) of a frame with the fault `kind` (or a good frame);
    `frames`: how many frames it sends, whole or cut."""
    h, w = words.shape
    data, flags, gaps = frame_program(words, int(rng.integers(0, 24)), int(rng.integers(0, 300)))
    if kind == "cable_cut":
        return _cable_cut(words, data, flags, gaps, rng)
    lines_d = [data[y * w : (y + 1) * w] for y in range(h)]
    lines_f = [flags[y * w : (y + 1) * w] for y in range(h)]
    lines_g = [gaps[y * w : (y + 1) * w] for y in range(h)]
    detail = ""
    if kind == "short_line":
        y, k = int(rng.integers(0, h)), int(rng.integers(1, w // 2))
        lines_d[y], lines_f[y], lines_g[y] = lines_d[y][:-k], lines_f[y][:-k].copy(), lines_g[y][:-k].copy()
        lines_f[y][-1] |= FLAG_LAST
        lines_g[y][-1] = lines_g[y][-1] or 16
        detail = f"line {y} short by {k}"
    elif kind == "long_line":
        y, k = int(rng.integers(0, h)), int(rng.integers(1, w // 2))
        extra = rng.integers(0, 1 << 24, k).astype(np.uint32)
        lines_d[y] = np.concatenate([lines_d[y], extra])
        f = np.concatenate([lines_f[y], np.zeros(k, np.uint8)])
        f[w - 1] &= ~FLAG_LAST & 0xFF
        f[-1] |= FLAG_LAST
        lines_f[y] = f
        g = np.concatenate([lines_g[y], np.zeros(k, np.uint32)])
        g[-1], g[w - 1] = g[w - 1], 0
        lines_g[y] = g
        detail = f"line {y} long by {k}"
    elif kind == "few_lines":
        k = int(rng.integers(1, h // 2))
        lines_d, lines_f, lines_g = lines_d[:-k], lines_f[:-k], lines_g[:-k]
        detail = f"{k} lines missing"
    elif kind == "many_lines":
        k = int(rng.integers(1, 8))
        for _ in range(k):
            lines_d.append(rng.integers(0, 1 << 24, w).astype(np.uint32))
            f = np.zeros(w, np.uint8)
            f[-1] = FLAG_LAST
            lines_f.append(f)
            g = np.zeros(w, np.uint32)
            g[-1] = 16
            lines_g.append(g)
        detail = f"{k} extra lines"
    elif kind == "no_sof":
        lines_f[0] = lines_f[0].copy()
        lines_f[0][0] &= ~FLAG_USER & 0xFF
        detail = "no tuser"
    elif kind == "early_sof":
        y, x = int(rng.integers(1, h)), int(rng.integers(0, w))
        lines_f[y] = lines_f[y].copy()
        lines_f[y][x] |= FLAG_USER
        detail = f"tuser at ({x}, {y})"
    return np.concatenate(lines_d), np.concatenate(lines_f), np.concatenate(lines_g), detail, 1


def _cable_cut(words: np.ndarray, data: np.ndarray, flags: np.ndarray, gaps: np.ndarray,
               rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray, str, int]:  # fmt: skip
    """The frame stops after a random beat; no pixel for half a frame period to three; the video
    comes back at a random beat of a frame, without its start of frame (at the very beat of the cut,
    in the column of the cut, or anywhere), and the next frame follows whole."""
    h, w = words.shape
    n = h * w
    cut = int(rng.integers(1, n))
    outage = int(rng.integers(frame_period(w, h) // 2, 3 * frame_period(w, h)))
    where = rng.random()
    if where < 0.25:
        back, how = cut, "at the beat of the cut"
    elif where < 0.5:
        back, how = max(1, cut % w + w * int(rng.integers(0, h))), "in the column of the cut"
    else:
        back, how = int(rng.integers(1, n)), "anywhere"
    gaps = gaps.copy()
    gaps[cut - 1] = outage
    d2, f2, g2 = frame_program(words, int(rng.integers(0, 24)), int(rng.integers(0, 300)))
    d3, f3, g3 = frame_program(words, int(rng.integers(0, 24)), int(rng.integers(0, 300)))
    detail = f"cut after beat {cut}, {outage} clocks without video, back at beat {back} ({how})"
    return (np.concatenate([data[:cut], d2[back:], d3]), np.concatenate([flags[:cut], f2[back:], f3]),
            np.concatenate([gaps[:cut], g2[back:], g3]), detail, 3)  # fmt: skip


def subset_difference(got: Features, want: Features, lost: int) -> str | None:
    """For a frame whose record says `lost` features were dropped (a full FIFO) or cut (a full
    bank): None when `got` is `want` less exactly `lost` features, the others bit-exact."""
    if len(want) - len(got) != lost:
        return f"{len(got)} features for the model's {len(want)} with {lost} lost"
    keys = {(int(s), int(y), int(x)): i for i, (s, y, x) in enumerate(zip(want.scale, want.y, want.x, strict=True))}
    picked = []
    for s, y, x in zip(got.scale, got.y, got.x, strict=True):
        i = keys.get((int(s), int(y), int(x)))
        if i is None:
            return f"feature at scale {s} (x={x}, y={y}) is not in the model's list"
        picked.append(i)
    return first_difference(got, want.take(np.array(picked, dtype=np.int64)))


def _luma_words(words: np.ndarray) -> np.ndarray:
    """The luma the accelerator computes of 24-bit RGB words (as the checker sees it)."""
    w = words.astype(np.uint32)
    rgb = np.stack(((w >> 16) & 255, (w >> 8) & 255, w & 255), axis=-1).astype(np.uint8)
    return rgb_to_luma(rgb.reshape(-1, 1, 3)).reshape(-1)


class Lockup(Exception):
    """The accelerator stopped answering or publishing: the campaign ends."""


class Campaign:
    """One campaign: the netlist, the driver, the reference, the CPU's banks."""

    def __init__(self, photos: Sequence[np.ndarray], seed: int, generics: Mapping[str, int | str],
                 init_seed: int = 0) -> None:  # fmt: skip
        self.photos = [pack(p) for p in photos]
        self.rng = np.random.default_rng(seed)
        self.ddr = is_ddr(generics)
        fa = FastAccel.start(generics, seed=init_seed, ring_count=DDR_RING if self.ddr else None)
        self.fa = fa
        self.sim, self.bus = fa.sim, fa.bus
        self.w, self.h = fa.width, fa.height
        self.scales, self.sectors = int(generics["SCALES_g"]), int(generics["SECTORS_g"])
        self.step_ratio = int(generics.get("STEP_NUM_g", 2)), int(generics.get("STEP_DEN_g", 1))
        self.period = frame_period(self.w, self.h)
        self.ref = Reference(self.w, self.h, DDR_RING if self.ddr else regs.BANKS)
        self.fifo_depth = int(generics.get("DMA_FIFO_g", 256))  # a DDR build's burst FIFO, slots
        self._expected: tuple[Published, Features] | None = None  # the model's features of a frame
        self.capacity = int(generics["MEM_DEPTH_g"]) - 1
        self.setting = Setting(20, "orb", "grid", min(self.capacity, 1000), (8, 6), 7)
        self.held: set[int] = set()  # banks the CPU has read and not released
        self.hold_steps = 0  # services left in which the CPU keeps up to hold_banks banks
        self.hold_banks = 0
        self.kept: set[int] = set()
        self.res = CampaignResult(seed, init_seed, dict(generics), ddr=self.ddr)
        self.accel = self.fresh_driver()
        if self.ddr:
            self.ring = self.accel.ring
            assert self.ring is not None and self.ring.count == DDR_RING
            base, size = self.sim.memory_region
            lo, hi = self.ring.offset, self.ring.offset + self.ring.extent
            self.sim.write_mem(base, bytes([CANARY]) * lo)
            self.sim.write_mem(base + hi, bytes([CANARY]) * (size - hi))
            self.sim.axi_log(True)
            self.errors_seen = 0  # error responses the harness gave, up to the last step
            self.errors_base = 0  # ... up to the last reset (DMA_BUS_ERRORS restarts there)
            self.dropped_seen = 0  # DMA_DROPPED after the last step

    def fresh_driver(self) -> OrbAccel:
        if self.ddr:  # the driver lays the ring out in the memory, writes it and soft-resets the accelerator
            accel = OrbAccel(self.bus, bank_read="slot", memory=self.fa.memory, ring_count=DDR_RING)
        else:
            accel = OrbAccel(self.bus, bank_read="slot")
        self.write_setting(accel, self.setting)
        return accel

    def configure(self, **changes: Any) -> None:
        self.setting = replace(self.setting, **changes)
        self.write_setting(self.accel, self.setting)

    def write_setting(self, accel: OrbAccel, s: Setting) -> None:
        accel.configure(s.threshold, s.mode, True, ("frame_done", "error"), s.selection, s.budget, s.cells, s.low)

    # ---- one step --------------------------------------------------------------------------------
    def step(self, step: int, kind: str) -> Event:
        rng, sim = self.rng, self.sim
        photo = int(rng.integers(0, len(self.photos)))
        if kind == "threshold":
            self.configure(threshold=int(rng.integers(8, 45)))
        elif kind == "mode":
            self.configure(mode="fast" if self.setting.mode == "orb" else "orb")
        elif kind == "selection":
            # the grid from tiny to full budgets, any grid from 1 x 1 to 15 x 15 cells, any low threshold
            cap = self.capacity
            budget = int(rng.choice([0, 1, int(rng.integers(2, cap + 1)), cap]))
            cells = (int(rng.integers(1, 16)), int(rng.integers(1, 16)))
            self.configure(selection=str(rng.choice(["all", "grid", "grid"])), budget=budget, cells=cells,
                           low=int(rng.integers(0, 30)))  # fmt: skip
        elif kind == "hold":
            self.hold_steps, self.hold_banks = int(rng.integers(1, 5)), int(rng.integers(1, 3))
        ready = float(rng.uniform(0.3, 0.95)) if kind == "backpressure" else 1.0
        sim.set_out_ready(ready, self.res.seed * 1000 + step + 1)
        ev = Event(step, kind, photo, self.setting)
        program = kind if kind in FAULTS else "good"
        if kind == "ddr_error" and rng.random() < DDR_ERROR_BAD:  # the error to a frame the checker rejects
            program = str(rng.choice(["short_line", "long_line"]))
        data, flags, gaps, ev.detail, frames = fault_program(program, self.photos[photo], rng)
        if kind == "hold":
            ev.detail = f"the next {self.hold_banks} bank(s) read kept for {self.hold_steps} step(s)"
        self.res.frames_sent += frames
        skipped0 = self.ref.skipped
        armed = False
        if kind in DDR_KINDS:
            # the reference first (it needs no timing): the fault goes in only if the step closes one
            # frame, published, and none was open before it (each burst of the step is then that frame's)
            was_open, good, bad = self.ref.frame_open, self.ref.closed_good, self.ref.closed_bad
            self.ref.feed(data, flags, self.setting)
            good, bad = self.ref.closed_good - good, self.ref.closed_bad - bad
            one = not was_open and not self.ref.frame_open and good + bad == 1
            # a good frame the reference publishes (not skipped), or a bad one (ddr_error only)
            one = one and (len(self.ref.published) == 1 or (bad == 1 and kind == "ddr_error"))
            detail, ev.detail = ev.detail, ""
            armed = self.arm_ddr(kind, len(data), ev, one)
            ev.detail = f"{program} ({detail}): {ev.detail}" if program != "good" else ev.detail
        try:
            self.play(kind, data, flags, gaps, ev, fed=kind in DDR_KINDS)
            got, want = self.service_ddr(ev, armed) if self.ddr else self.service(ev)
        except FastSimError as exc:
            raise Lockup(f"step {step} ({kind} {ev.detail}): {exc}") from None
        finally:
            if kind in DDR_KINDS:
                self.disarm_ddr()
        self.compare(ev, got, want)
        ev.published, ev.skipped = len(got), self.ref.skipped - skipped0
        ev.outcome = f"{len(got)} published" + (f", {ev.skipped} skipped" if ev.skipped else "")
        self.release()
        return ev

    def play(self, kind: str, data: np.ndarray, flags: np.ndarray, gaps: np.ndarray, ev: Event,
             fed: bool = False) -> None:  # fmt: skip
        """The step's video through the netlist and the reference (unless `fed` already)."""
        sim, rng = self.sim, self.rng
        base = sim.stats()["beats_sent"]
        sim.push(data, flags, gaps)
        before = sent = len(data)
        if kind in ("reset", "soft_reset"):
            cut = int(rng.integers(1, max(2, len(data) - 64)))
            sim.run(cut)  # part of the frame, then the reset; the rest streams on
            before = sim.stats()["beats_sent"] - base
            if kind == "reset":
                sim.reset(int(rng.integers(1, 12)))
                self.accel = self.fresh_driver()  # rst clears the registers: the CPU sets them up again
            else:
                self.accel.soft_reset()
            sent = sim.stats()["beats_sent"] - base
            ev.detail = f"after {cut} clocks"
        bound = SOURCE_FRAMES * self.period + int(gaps.sum())
        if not sim.run_video(bound):
            raise FastSimError(f"the video source could not send the step's video within {bound} clocks")
        if sim.stats()["longest_stall"] > SOURCE_FRAMES // 2 * self.period:
            raise FastSimError(f"the input stalled for {sim.stats()['longest_stall']} clocks")
        # the reference: the beats the source sent; a reset in mid-frame abandons the open frame
        # and frees the banks (the beats taken while it ran are lost to it: the checker was being reset)
        if fed:
            return
        self.ref.feed(data[:before], flags[:before], self.setting)
        if kind in ("reset", "soft_reset"):
            if self.ref.published:
                raise AssertionError("a frame published in the step of a reset: the campaign cannot tell its fate")
            self.ref.reset()
            self.held.clear()
            self.kept.clear()
            self.hold_steps = 0
            self.ref.feed(data[sent:], flags[sent:], self.setting)

    def service(self, ev: Event) -> tuple[list[Frame], list[Published]]:
        """Wait for the step's frames (the watchdog), read every bank newly READY, older first."""
        sim, accel = self.sim, self.accel
        want = self.ref.take()
        last_beat = sim.stats()["last_beat_cycle"]
        limit = WATCHDOG_FRAMES * self.period
        late = False
        while True:
            if sim.wait_irq(QUIET_CLOCKS):
                accel.write(regs.IRQ_STATUS, accel.read(regs.IRQ_STATUS))
                continue
            status = accel.read(regs.STATUS)
            ready = regs.STATUS.field("bank_ready").get(status)
            new = [b for b in range(regs.BANKS) if ready >> b & 1 and b not in self.held]
            if len(new) >= len(want):
                break
            if sim.cycle - last_beat > limit:
                raise Lockup(f"step {ev.step} ({ev.kind} {ev.detail}): no frame for {WATCHDOG_FRAMES} frame periods "
                             f"({limit} clocks) after the last beat, {len(new)} of the {len(want)} expected "
                             f"published; {accel.status_text()}")  # fmt: skip
            late = True
        self.res.late_steps += late
        last = regs.STATUS.field("last_bank").get(status)
        got = []
        for b in sorted(new, key=lambda b: b == last):  # the older first
            got.append(accel.read_bank(b, mode="orb", counters=False))
            self.held.add(b)
        want_ready = sum(1 << b for b in self.ref.ready)
        if ready != want_ready:
            self.mismatch(ev, f"STATUS.bank_ready {ready:02b}, the reference {want_ready:02b}")
        overrun = accel.read(regs.OVERRUN)
        if overrun != self.ref.overrun:
            self.mismatch(ev, f"OVERRUN {overrun}, the reference {self.ref.overrun}")
        return got, want

    # ---- a DDR build (the module docstring) --------------------------------------------------------
    def arm_ddr(self, kind: str, beats: int, ev: Event, one: bool) -> bool:
        """The DDR event's fault for this step's frame if `one` (the step closes exactly one frame,
        which the reference publishes, and none was open before it); the detail says what was done."""
        rng, sim = self.rng, self.sim
        closing = self.ref.published
        if not one:
            self.res.ddr_not_injected += 1
            ev.detail = f"not injected: {len(closing)} frame(s) to publish, a frame open before or after"
            return False
        self.res.ddr_injected += 1
        first = sim.axi_stats()["bursts"]  # the DMA is idle: the step's bursts are its frame's, from this one
        resp = "decerr" if rng.random() < 0.25 else "slverr"
        if kind == "ddr_error" and not closing:  # a frame the checker rejects: one of its first bursts
            k = int(rng.integers(0, DDR_ERROR_SLOTS))
            sim.axi_error(first + k, resp)
            ev.detail = f"{resp.upper()} to its burst {k}"
        elif kind == "ddr_error":
            buf = self.ring.base + closing[0].bank * self.ring.stride
            # the record, or a feature slot the frame writes (its count: the model's, at most a buffer's)
            count = min(len(self.expected(closing[0])), self.capacity, DDR_ERROR_SLOTS)
            slot = 0 if count == 0 or rng.random() < 1 / 3 else int(rng.integers(1, count + 1))
            sim.axi_error_at(buf + slot * SLOT_BYTES, resp)
            ev.detail = f"{resp.upper()} to the burst of " + ("its record" if slot == 0 else f"slot {slot}")
        elif kind == "ddr_stall":
            start = int(rng.integers(0, beats))
            clocks = int(rng.integers(self.period // 8, 2 * self.period))
            aw, w, b = [(1, 1, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)][int(rng.integers(0, 5))]
            sim.axi_stall(clocks, start, aw=bool(aw), w=bool(w), b=bool(b))
            held = "+".join(n for n, on in (("AWREADY", aw), ("WREADY", w), ("BVALID", b)) if on)
            ev.detail = f"{held} low for {clocks} clocks from clock {start} of the frame"
            if rng.random() < DDR_STALL_ERROR:
                k = int(rng.integers(0, DDR_ERROR_SLOTS))
                sim.axi_error(first + k, resp)
                ev.detail += f", {resp.upper()} to its burst {k}"
        else:
            # slow, not stalled: a full burst FIFO drains within two frame periods (the watchdog's margin)
            per_slot = 2 * self.period // self.fifo_depth
            aw_p, w_p = (float(rng.uniform(max(0.2, 8 / per_slot), 1.0)) for _ in range(2))
            outstanding, ahead = int(rng.integers(1, 9)), int(rng.choice([0, 8, 64]))
            latency = min(600, per_slot * outstanding)
            delay = int(rng.integers(0, latency // 2 + 1))
            jitter = int(rng.integers(0, latency // 2 + 1))
            sim.set_axi_timing(aw_p, w_p, delay, jitter, outstanding, ahead, seed=self.res.seed * 7919 + ev.step + 1)
            ev.detail = (f"AWREADY {aw_p:.2f}, WREADY {w_p:.2f}, responses after {delay}+0..{jitter} clocks, "
                         f"{outstanding} outstanding, {ahead} W beats ahead")  # fmt: skip
        return True

    def disarm_ddr(self) -> None:
        """The interconnect back to an ideal one after a DDR event's step."""
        self.sim.clear_axi_errors()
        self.sim.clear_axi_stalls()
        self.sim.set_axi_timing()

    def service_ddr(self, ev: Event, armed: bool) -> tuple[list[Frame], list[Published]]:
        """service() on the DDR ring: wait until every frame the reference expects is published or
        dropped (DMA_DROPPED) and the DMA is idle (RING_STATUS.busy), read the ring buffers newly
        READY (the older first), reconcile the frames missing with the DDR faults (the module
        docstring), then check RING_STATUS.ready and OVERRUN."""
        sim, accel = self.sim, self.accel
        want = self.ref.take()
        last_beat = sim.stats()["last_beat_cycle"]
        limit = WATCHDOG_FRAMES * self.period
        reset = ev.kind in ("reset", "soft_reset")
        if reset:
            self.dropped_seen = 0  # both resets restart DMA_DROPPED and DMA_BUS_ERRORS
        late = False
        rs = regs.RING_STATUS.field
        while True:
            if sim.wait_irq(QUIET_CLOCKS):
                accel.write(regs.IRQ_STATUS, accel.read(regs.IRQ_STATUS))
                continue
            status = accel.read(regs.RING_STATUS)
            ready = rs("ready").get(status)
            new = [b for b in range(DDR_RING) if ready >> b & 1 and b not in self.held]
            dropped = accel.read(regs.DMA_DROPPED) - self.dropped_seen
            if len(new) + dropped >= len(want) and not rs("busy").get(status):
                break
            if sim.cycle - last_beat > limit:
                raise Lockup(f"step {ev.step} ({ev.kind} {ev.detail}): no frame for {WATCHDOG_FRAMES} frame periods "
                             f"({limit} clocks) after the last beat, {len(new)} of the {len(want)} expected "
                             f"published, {dropped} dropped; {accel.status_text()}")  # fmt: skip
            late = True
        self.res.late_steps += late
        last = rs("last").get(status)
        got = []
        for b in sorted(new, key=lambda b: (b - last - 1) % DDR_RING):  # the older first, the newest last
            got.append(accel.read_bank(b, mode="orb", counters=False))
            self.held.add(b)
        want = self.reconcile(ev, armed, got, want, dropped, reset)
        want_ready = sum(1 << b for b in self.ref.ready)
        if ready != want_ready:
            self.mismatch(ev, f"RING_STATUS.ready {ready:0{DDR_RING}b}, the reference {want_ready:0{DDR_RING}b}")
        overrun = accel.read(regs.OVERRUN)
        if overrun != self.ref.overrun:
            self.mismatch(ev, f"OVERRUN {overrun}, the reference {self.ref.overrun}")
        return got, want

    def reconcile(self, ev: Event, armed: bool, got: list[Frame], want: list[Published], dropped: int,
                  reset: bool) -> list[Published]:  # fmt: skip
        """The frames the reference expects that were not published, explained by the step's DDR
        fault from the harness's log of bursts, or mismatches; DMA_DROPPED and DMA_BUS_ERRORS
        against what was explained and injected. Returns the frames that must have been published."""
        sim, accel, ring = self.sim, self.accel, self.ring
        log = sim.axi_log_take()
        axi = sim.axi_stats()
        errors_now = axi["slverr"] + axi["decerr"]
        errors, self.errors_seen = errors_now - self.errors_seen, errors_now
        self.res.error_responses += errors
        if reset:
            self.errors_base = errors_now - errors  # the errors of the step before the reset are not counted
        dma_errors = accel.read(regs.DMA_BUS_ERRORS)
        self.dropped_seen += dropped
        # the records written in the step: the frame numbers of the bursts to a buffer's slot 0
        records: dict[int, int] = {}
        for e in log:
            at = int(e["addr"]) - ring.base
            if at % ring.stride or not 0 <= at // ring.stride < ring.count or e["resp"] == RESP_FORGOTTEN:
                continue
            words = np.asarray(e["data"], dtype="<u8").view("<u4")[:SLOT_RECORD_WORDS]
            try:
                records[decode_record(words).frame] = int(e["resp"])
            except ValueError:
                self.mismatch(ev, f"burst {e['index']} to slot 0 of buffer {at // ring.stride} is not a record")
        numbers = {f.number for f in got}
        explained: list[Published] = []
        for p in want:
            if p.number in numbers:
                continue
            where = f"frame {p.number} (buffer {p.bank}) not published"
            if not armed or p is not want[-1]:
                self.mismatch(ev, f"{where} in a step without a DDR fault")
            elif p.number in records:  # written: only an error response drops it
                if errors == 0:
                    self.mismatch(ev, f"{where}: its record was written and no burst was answered with an error")
                    continue
                self.ref.unpublish(p, position_used=True)
                self.res.frames_dropped_error += 1
                explained.append(p)
            elif ev.kind in ("ddr_stall", "ddr_slow"):  # its record never written: the burst FIFO was full
                self.ref.unpublish(p, position_used=False)
                self.res.frames_dropped_fifo += 1
                explained.append(p)
            else:
                self.mismatch(ev, f"{where}: its record was never written ({ev.kind})")
        if errors and any(p.number in numbers for p in want) and armed:
            self.mismatch(ev, f"{errors} error response(s) in the step, and its frame was published")
        if not reset:
            if dropped != len(explained):
                self.mismatch(ev, f"DMA_DROPPED rose by {dropped}, {len(explained)} frame(s) dropped by the DDR faults")
            if dma_errors != errors_now - self.errors_base:
                self.mismatch(ev, f"DMA_BUS_ERRORS {dma_errors}, the harness answered {errors_now - self.errors_base} "
                              "error(s) since the last reset")  # fmt: skip
        elif dropped:
            self.mismatch(ev, f"DMA_DROPPED {dropped} after a reset, in a step without a DDR fault")
        return [p for p in want if p not in explained]

    def check_ddr_end(self) -> None:
        """A DDR campaign's last checks: the master kept the AXI rules, wrote nothing outside the
        memory, and left the memory outside the ring as it was."""
        axi = self.sim.axi_stats()
        self.res.axi = axi
        end = Event(len(self.res.events), "end", -1, self.setting, "the campaign's end")
        if axi["protocol_errors"]:
            self.mismatch(end, f"{axi['protocol_errors']} AXI rule violations by the master, the first at cycle "
                          f"{axi['first_protocol_cycle']}")  # fmt: skip
        if axi["refused_beats"]:
            self.mismatch(end, f"{axi['refused_beats']} beats written outside the memory (DECERR)")
        base, size = self.sim.memory_region
        lo, hi = self.ring.offset, self.ring.offset + self.ring.extent
        outside = np.frombuffer(self.sim.read_mem(base, lo) + self.sim.read_mem(base + hi, size - hi), np.uint8)
        if np.any(outside != CANARY):
            self.mismatch(end, f"{int(np.count_nonzero(outside != CANARY))} bytes outside the ring were written")

    def expected(self, p: Published) -> Features:
        """The golden model's features of a published frame (kept for the step: arm_ddr asks first)."""
        if self._expected is not None and self._expected[0] is p:
            return self._expected[1]
        s = p.setting
        cfg = Config(self.w, self.h, scales=self.scales, sectors=self.sectors, threshold=s.threshold,
                     mode=s.mode, step_num=self.step_ratio[0], step_den=self.step_ratio[1],
                     selection=s.selection, budget=s.budget, cols=s.cells[0], rows=s.cells[1],
                     threshold_lo=s.low)  # fmt: skip
        exp = extract(p.luma, cfg)
        self._expected = (p, exp)
        return exp

    def compare(self, ev: Event, got: list[Frame], want: list[Published]) -> None:
        if len(got) != len(want):
            self.mismatch(ev, f"{len(got)} frames published, the reference {len(want)}")
        for f, p in zip(got, want, strict=False):
            s = p.setting
            where = f"frame {f.number} in bank {f.bank} ({s.text()})"
            if (f.number, f.bank) != (p.number, p.bank):
                self.mismatch(ev, f"{where}: the reference's is frame {p.number} in bank {p.bank}")
            if f.params != s.params():
                self.mismatch(ev, f"{where}: its record says {f.params}")
            exp = self.expected(p)
            feats, lost = f.features, f.record.dropped + f.record.truncated
            if s.mode == "fast":  # read as orb: a fast frame carries sector 0 and no descriptor
                feats = Features(feats.scale, feats.x, feats.y, feats.score, np.full(len(feats), -1),
                                 np.zeros((len(feats), 0), np.uint8), feats.sectors_total, feats.step,
                                 feats.response, feats.low)  # fmt: skip
            if s.selection == "grid" and lost:  # the grid selection never loses a feature of a legal frame
                diff: str | None = f"{lost} features lost in grid selection"
            else:
                diff = first_difference(feats, exp) if lost == 0 else subset_difference(feats, exp, lost)
            if diff is not None:
                self.mismatch(ev, f"{where}, {lost} lost: {diff}")
            self.res.features_checked += len(feats)
        self.res.frames_published += len(got)

    def release(self) -> None:
        """Give the banks back, but those a hold keeps, and while the checker has a frame open the
        one that frame goes to."""
        if self.hold_steps > 0:
            for b in sorted(self.held):
                if len(self.kept) < self.hold_banks:
                    self.kept.add(b)
            self.hold_steps -= 1
        else:
            self.kept.clear()
        for b in sorted(self.held - self.kept):
            if self.ref.frame_open and b == self.ref.next_bank:
                self.res.deferred_releases += 1
                continue
            self.accel.release(b)
            self.held.discard(b)
            self.ref.ready.discard(b)

    def mismatch(self, ev: Event, text: str) -> None:
        self.res.mismatches.append(f"step {ev.step} ({ev.kind} {ev.detail}, photo {ev.photo}): {text}")

    # ---- the campaign ----------------------------------------------------------------------------
    def run(self, steps: int, on_event: Callable[[Event], None] | None = None) -> CampaignResult:
        t0 = time.perf_counter()
        weights = {**WEIGHTS, **DDR_WEIGHTS} if self.ddr else WEIGHTS
        names = list(weights)
        p = np.array([weights[k] for k in names], dtype=float)
        p /= p.sum()
        res = self.res
        for step in range(steps):
            kind = str(self.rng.choice(names, p=p))
            try:
                ev = self.step(step, kind)
            except Lockup as exc:
                res.lockups.append(str(exc))
                res.events.append(Event(step, kind, -1, self.setting, outcome="lock-up"))
                break
            res.events.append(ev)
            if on_event is not None:
                on_event(ev)
        res.frames_good, res.frames_bad = self.ref.closed_good, self.ref.closed_bad
        res.frames_skipped = self.ref.skipped
        if not res.lockups:
            res.counters = self.accel.counters()
            if self.ddr:
                res.dma = self.accel.dma_counters()
                self.check_ddr_end()
        res.clocks = self.sim.cycle
        self.sim.close()
        res.wall_s = time.perf_counter() - t0
        return res


def run_campaign(photos: Sequence[np.ndarray], steps: int, seed: int, generics: Mapping[str, int | str],
                 init_seed: int = 0, on_event: Callable[[Event], None] | None = None) -> CampaignResult:  # fmt: skip
    """`steps` events on orb_accel_top with `generics` (RGB input), frames drawn from `photos`
    ((H, W, 3) RGB); `init_seed` the netlist's random initial state (0: zeros)."""
    return Campaign(photos, seed, generics, init_seed).run(steps, on_event)
