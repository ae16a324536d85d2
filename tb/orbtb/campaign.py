# SPDX-License-Identifier: MIT
"""Randomised fault campaign on the fast path (docs/fast-sim.md): frame after frame into the
Verilated netlist of orb_accel_top, good ones and faulty ones, with the CPU side played by the
shipped driver as it would run on the board, and every outcome checked against the reference:
the beats go through orbtb.video_check.VideoCheckModel (which frames the protocol checker closes
good, with which pixels: a frame with lines missing may be completed by the next frame's pixels
when that one has no start of frame, exactly as the hardware must do) and each good frame through
the golden model at the threshold, mode and selection in force at its first pixel.

Events (one per step, drawn from a seeded generator; the seed replays the campaign exactly):
good (random blanking), short_line, long_line, few_lines, many_lines, no_sof, early_sof (a start
of frame in mid-frame), reset (rst in mid-frame), soft_reset (CTRL.soft_reset in mid-frame),
threshold, mode and selection (changed between frames, then a good frame: the selection `all`
or `grid` with a random budget, cell grid and low threshold), backpressure (random tready on the
overlay output during a good frame).

Checked: the frames published are exactly the frames the reference closes good, in order, each
bit-exact; a frame closed bad or cut by a reset is never published; nothing locks up (every bus
operation is answered, the video source is never stalled for longer than a frame, every good
frame's interrupt comes). The result lists every event with its outcome.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from golden_model import regs
from golden_model.config import Config
from golden_model.features import Features, first_difference
from golden_model.luma import rgb_to_luma
from golden_model.pipeline import extract
from orb_accel.driver import OrbAccel
from orb_sim.fast.jobs import FastAccel, pack
from orb_sim.fast.sim import FLAG_LAST, FLAG_USER, FastSimError, frame_program

from .video_check import Beat, VideoCheckModel

FAULTS = ("short_line", "long_line", "few_lines", "many_lines", "no_sof", "early_sof", "reset", "soft_reset")
CHANGES = ("threshold", "mode", "selection", "backpressure")
KINDS = ("good", *FAULTS, *CHANGES)
WEIGHTS = {"good": 6, **{k: 1 for k in FAULTS}, "threshold": 1, "mode": 1, "selection": 2, "backpressure": 1}
IRQ_WAIT_CLOCKS = 20_000  # after the last beat: the pipeline's latency is tens of clocks


@dataclass
class Event:
    step: int
    kind: str
    photo: int
    threshold: int
    mode: str
    selection: tuple[str, int, tuple[int, int], int] = ("all", 0, (8, 6), 0)
    detail: str = ""
    published: int = 0
    expected: bool = False
    outcome: str = ""


@dataclass
class CampaignResult:
    seed: int
    events: list[Event] = field(default_factory=list)
    mismatches: list[str] = field(default_factory=list)
    lockups: list[str] = field(default_factory=list)
    frames_published: int = 0
    features_checked: int = 0
    counters: dict[str, int] = field(default_factory=dict)

    @property
    def faults(self) -> int:
        return sum(e.kind in FAULTS for e in self.events)

    @property
    def ok(self) -> bool:
        return not self.mismatches and not self.lockups

    def summary(self) -> str:
        kinds = {k: sum(e.kind == k for e in self.events) for k in KINDS}
        mix = ", ".join(f"{k} {v}" for k, v in kinds.items() if v)
        return (f"seed {self.seed}: {len(self.events)} frames ({mix}); "
                f"{self.frames_published} published, {self.features_checked} features checked; faults injected "
                f"{self.faults}; lock-ups {len(self.lockups)}; mismatches {len(self.mismatches)}")  # fmt: skip


def fault_program(kind: str, words: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    """(data, flags, gaps, detail) of a frame with the fault `kind` (or a good frame)."""
    h, w = words.shape
    data, flags, gaps = frame_program(words, int(rng.integers(0, 24)), int(rng.integers(0, 300)))
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
    return np.concatenate(lines_d), np.concatenate(lines_f), np.concatenate(lines_g), detail


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


def run_campaign(photos: Sequence[np.ndarray], steps: int, seed: int, generics: Mapping[str, int | str],
                 init_seed: int = 0, on_event: Callable[[Event], None] | None = None) -> CampaignResult:  # fmt: skip
    """`steps` events on orb_accel_top with `generics` (RGB input), frames drawn from `photos`
    ((H, W, 3) RGB); `init_seed` the netlist's random initial state (0: zeros)."""
    rng = np.random.default_rng(seed)
    fa = FastAccel.start(generics, seed=init_seed)
    sim, bus = fa.sim, fa.bus
    w, h = fa.width, fa.height
    scales, sectors = int(generics["SCALES_g"]), int(generics["SECTORS_g"])
    frame_bound = 40 * ((w + 24) * (h + 16) + 300)
    res = CampaignResult(seed)
    ref = VideoCheckModel(w, h)
    # threshold, mode and selection (mode, budget, (cols, rows), low threshold) of each frame the reference opened
    frame_params: list[tuple[int, str, tuple[str, int, tuple[int, int], int]]] = []
    ends_seen = 0
    threshold, mode = 20, "orb"
    capacity = int(generics["MEM_DEPTH_g"]) - 1
    selection: tuple[str, int, tuple[int, int], int] = ("grid", min(capacity, 1000), (8, 6), 7)
    irq_all = ("frame_done", "error")

    def feed(data: np.ndarray, flags: np.ndarray) -> None:
        luma = _luma_words(data)
        for d, f in zip(luma.tolist(), flags.tolist(), strict=True):
            n = len(ref.out)
            ref.beat(Beat(d, f & FLAG_USER, (f & FLAG_LAST) >> 1))
            for o in ref.out[n:]:
                if o.user:
                    frame_params.append((threshold, mode, selection))

    def expected_frames() -> list[tuple[Features, tuple[int, str, tuple[str, int, tuple[int, int], int]]]]:
        """The frames the reference closed good since the last call, with their expected features."""
        nonlocal ends_seen
        out = []
        for end in ref.ends[ends_seen:]:
            index = ref.ends.index(end)
            if not end.bad:
                pixels = np.array([b.data for b in ref.out[end.beat - w * h + 1 : end.beat + 1]], dtype=np.uint8)
                t, m, (sel, budget, cells, lo) = frame_params[index]
                cfg = Config(w, h, scales=scales, sectors=sectors, threshold=t, mode=m, selection=sel, budget=budget,
                             cols=cells[0], rows=cells[1], threshold_lo=lo)  # fmt: skip
                out.append((extract(pixels.reshape(h, w), cfg), frame_params[index]))
        ends_seen = len(ref.ends)
        return out

    def fresh_driver() -> OrbAccel:
        accel = OrbAccel(bus, bank_read="slot")
        accel.configure(threshold, mode, True, irq_all, *selection)
        return accel

    accel = fresh_driver()
    names = list(WEIGHTS)
    p = np.array([WEIGHTS[k] for k in names], dtype=float)
    p /= p.sum()
    for step in range(steps):
        kind = str(rng.choice(names, p=p))
        photo = int(rng.integers(0, len(photos)))
        if kind == "threshold":
            threshold = int(rng.integers(8, 45))
            accel.configure(threshold, mode, True, irq_all, *selection)
        elif kind == "mode":
            mode = "fast" if mode == "orb" else "orb"
            accel.configure(threshold, mode, True, irq_all, *selection)
        elif kind == "selection":
            # grid from tiny to full budgets, any grid from 1 x 1 to 15 x 15 cells, any low threshold
            budget = int(rng.choice([0, 1, int(rng.integers(2, capacity + 1)), capacity]))
            cells = (int(rng.integers(1, 16)), int(rng.integers(1, 16)))
            selection = (str(rng.choice(["all", "grid", "grid"])), budget, cells, int(rng.integers(0, 30)))
            accel.configure(threshold, mode, True, irq_all, *selection)
        sim.set_out_ready(float(rng.uniform(0.3, 0.95)) if kind == "backpressure" else 1.0, seed * 1000 + step + 1)
        ev = Event(step, kind, photo, threshold, mode, selection)
        data, flags, gaps, ev.detail = fault_program(kind if kind in FAULTS else "good", pack(photos[photo]), rng)
        got: list[tuple[Features, int, int]] = []
        try:
            base = sim.stats()["beats_sent"]
            sim.push(data, flags, gaps)
            if kind in ("reset", "soft_reset"):
                cut = int(rng.integers(1, max(2, len(data) - 64)))
                sim.run(cut)  # part of the frame, then the reset; the rest streams on
                before = sim.stats()["beats_sent"] - base
                if kind == "reset":
                    sim.reset(int(rng.integers(1, 12)))
                    accel = fresh_driver()  # rst clears the registers: the CPU sets them up again
                else:
                    accel.soft_reset()
                sent = sim.stats()["beats_sent"] - base
                ev.detail = f"after {cut} clocks"
            if not sim.run_video(frame_bound):
                raise FastSimError(f"the video source could not send the frame within {frame_bound} clocks")
            if sim.stats()["longest_stall"] > frame_bound // 2:
                raise FastSimError(f"the input stalled for {sim.stats()['longest_stall']} clocks")
            while sim.wait_irq(IRQ_WAIT_CLOCKS):
                status = accel.read(regs.IRQ_STATUS)
                accel.write(regs.IRQ_STATUS, status)
                if regs.IRQ_STATUS.field("frame_done").get(status):
                    st = accel.read(regs.STATUS)
                    bank = regs.STATUS.field("last_bank").get(st)
                    with accel.holding(bank):
                        f = accel.read_bank(bank, mode="orb", counters=False)
                    got.append((f.features, f.number, f.record.dropped + f.record.truncated))
        except (FastSimError, OSError) as exc:
            res.lockups.append(f"step {step} ({kind} {ev.detail}): {exc}")
            res.events.append(ev)
            break
        # the reference: the beats the source sent; a reset in mid-frame abandons the open frame
        # (the beats taken while the reset ran are lost to it: the checker was being reset)
        if kind in ("reset", "soft_reset"):
            feed(data[:before], flags[:before])
            if ref._open:  # abandoned without an end: its parameters go with it
                frame_params.pop()
            ref.reset()
            feed(data[sent:], flags[sent:])
        else:
            feed(data, flags)
        want = expected_frames()
        ev.expected = bool(want)
        ev.published = len(got)
        res.frames_published += len(got)
        if len(got) != len(want):
            res.mismatches.append(f"step {step} ({kind} {ev.detail}, photo {photo}): {len(got)} frames published, "
                                  f"the reference closed {len(want)} good")  # fmt: skip
        for (feats, number, lost), (exp, (t, m, sel)) in zip(got, want, strict=False):
            if m == "fast":  # read as orb: a fast frame carries sector 0 and no descriptor
                feats = Features(feats.scale, feats.x, feats.y, feats.score, np.full(len(feats), -1),
                                 np.zeros((len(feats), 0), np.uint8), feats.sectors_total, feats.step,
                                 feats.response, feats.low)  # fmt: skip
            if sel[0] == "grid" and lost:  # the grid selection never loses a feature of a legal frame
                diff = f"{lost} features lost in grid selection"
            else:
                diff = first_difference(feats, exp) if lost == 0 else subset_difference(feats, exp, lost)
            if diff is not None:
                res.mismatches.append(f"step {step} ({kind}, photo {photo}, frame {number}, t={t}, {m}, {sel}, "
                                      f"{lost} lost): {diff}")  # fmt: skip
            res.features_checked += len(feats)
        ev.outcome = f"{len(got)} published" if got else "not published"
        res.events.append(ev)
        if on_event is not None:
            on_event(ev)
    if not res.lockups:
        res.counters = accel.counters()
    sim.close()
    return res
