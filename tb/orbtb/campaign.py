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
and the OVERRUN counter as the reference says. A lock-up is any of: a bus operation without an
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
from golden_model.features import Features, first_difference
from golden_model.frameparams import FrameParams
from golden_model.luma import rgb_to_luma
from golden_model.pipeline import extract
from orb_accel.driver import Frame, OrbAccel
from orb_sim.fast.jobs import FastAccel, pack
from orb_sim.fast.sim import FLAG_LAST, FLAG_USER, FastSimError, frame_program

from .video_check import FrameEnd, VideoCheckModel

FAULTS = ("short_line", "long_line", "few_lines", "many_lines", "no_sof", "early_sof", "cable_cut", "reset",
          "soft_reset")  # fmt: skip
CHANGES = ("threshold", "mode", "selection", "backpressure", "hold")
KINDS = ("good", *FAULTS, *CHANGES)
WEIGHTS = {"good": 6, **{k: 1 for k in FAULTS}, "threshold": 1, "mode": 1, "selection": 2, "backpressure": 1,
           "hold": 1}  # fmt: skip
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

    def __init__(self, width: int, height: int) -> None:
        self.w, self.h = width, height
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
        self.next_bank = 1 - self.next_bank

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

    @property
    def faults(self) -> int:
        return sum(e.kind in FAULTS for e in self.events)

    def by_kind(self, kinds: Sequence[str]) -> dict[str, int]:
        n = Counter(e.kind for e in self.events)
        return {k: n[k] for k in kinds}

    @property
    def ok(self) -> bool:
        return not self.mismatches and not self.lockups

    def summary(self) -> str:
        mix = ", ".join(f"{k} {v}" for k, v in self.by_kind(KINDS).items() if v)
        return (f"seed {self.seed} (initial state {self.init_seed}): {len(self.events)} events ({mix}); "
                f"{self.frames_sent} frames sent, {self.frames_good} closed good, {self.frames_bad} bad; "
                f"{self.frames_published} published, {self.frames_skipped} skipped (bank held); "
                f"{self.features_checked} features checked; faults injected {self.faults}; "
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
        }


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
        fa = FastAccel.start(generics, seed=init_seed)
        self.sim, self.bus = fa.sim, fa.bus
        self.w, self.h = fa.width, fa.height
        self.scales, self.sectors = int(generics["SCALES_g"]), int(generics["SECTORS_g"])
        self.step_ratio = int(generics.get("STEP_NUM_g", 2)), int(generics.get("STEP_DEN_g", 1))
        self.period = frame_period(self.w, self.h)
        self.ref = Reference(self.w, self.h)
        self.capacity = int(generics["MEM_DEPTH_g"]) - 1
        self.setting = Setting(20, "orb", "grid", min(self.capacity, 1000), (8, 6), 7)
        self.held: set[int] = set()  # banks the CPU has read and not released
        self.hold_steps = 0  # services left in which the CPU keeps up to hold_banks banks
        self.hold_banks = 0
        self.kept: set[int] = set()
        self.res = CampaignResult(seed, init_seed, dict(generics))
        self.accel = self.fresh_driver()

    def fresh_driver(self) -> OrbAccel:
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
        data, flags, gaps, ev.detail, frames = fault_program(program, self.photos[photo], rng)
        if kind == "hold":
            ev.detail = f"the next {self.hold_banks} bank(s) read kept for {self.hold_steps} step(s)"
        self.res.frames_sent += frames
        skipped0 = self.ref.skipped
        try:
            self.play(kind, data, flags, gaps, ev)
            got, want = self.service(ev)
        except FastSimError as exc:
            raise Lockup(f"step {step} ({kind} {ev.detail}): {exc}") from None
        self.compare(ev, got, want)
        ev.published, ev.skipped = len(got), self.ref.skipped - skipped0
        ev.outcome = f"{len(got)} published" + (f", {ev.skipped} skipped" if ev.skipped else "")
        self.release()
        return ev

    def play(self, kind: str, data: np.ndarray, flags: np.ndarray, gaps: np.ndarray, ev: Event) -> None:
        """The step's video through the netlist and the reference."""
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
            cfg = Config(self.w, self.h, scales=self.scales, sectors=self.sectors, threshold=s.threshold,
                         mode=s.mode, step_num=self.step_ratio[0], step_den=self.step_ratio[1],
                         selection=s.selection, budget=s.budget, cols=s.cells[0], rows=s.cells[1],
                         threshold_lo=s.low)  # fmt: skip
            exp = extract(p.luma, cfg)
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
        names = list(WEIGHTS)
        p = np.array([WEIGHTS[k] for k in names], dtype=float)
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
        res.clocks = self.sim.cycle
        self.sim.close()
        res.wall_s = time.perf_counter() - t0
        return res


def run_campaign(photos: Sequence[np.ndarray], steps: int, seed: int, generics: Mapping[str, int | str],
                 init_seed: int = 0, on_event: Callable[[Event], None] | None = None) -> CampaignResult:  # fmt: skip
    """`steps` events on orb_accel_top with `generics` (RGB input), frames drawn from `photos`
    ((H, W, 3) RGB); `init_seed` the netlist's random initial state (0: zeros)."""
    return Campaign(photos, seed, generics, init_seed).run(steps, on_event)
