# SPDX-License-Identifier: MIT
"""Faults the simulation server injects, for the CPU side's tests (docs/driver.md, "Faults and
recovery"). Each fault is a line of text, given to orb_sim.sim_server.SimServer(faults=...) or
`--sim-fault` / `orb-accel sim-server --fault`, and fixed when the server starts:

- `cut:EVERY:PERIODS`: a cable cut after every EVERY frames of the stream: the next frame stops
  half-way (its first half of lines, as sent), then no pixel comes for PERIODS frame periods; then
  the stream goes on from its first frame. The video is a program the fast engine plays
  (orb_sim.fast.sim), so this needs `engine="fast"`; the schedule (EVERY frames, the cut) repeats.
- `buserr:OP:WHERE:FIRST[:EVERY[:RESP]]`: the FIRST-th operation OP (`read`: a 32-bit read,
  `write`, `block`: a block read) at WHERE (a register name of golden_model.regs, or `mem`: the
  feature-memory window) since the server started is answered with RESP (`slverr`, the default, or
  `decerr`) instead of being done, as the register bank answers an illegal access (no state
  change); with EVERY > 0 also every EVERY-th such operation after it. Counted from the server's
  start, over every client.

The interconnect of a DDR build (MEM_KIND_g "DDR": the frames written through m_axi_feat into the
fast engine's memory model, docs/feature-dma.md, docs/fast-sim.md "The DDR model"); fast engine only
(apply_axi_faults sets them on the FastSim):

- `axistall:EVERY:CLOCKS[:WHAT]`: every EVERY clocks (from the server's start) the interconnect
  stops for CLOCKS clocks: WHAT `aww` (the default: AWREADY and WREADY low), `aw`, `w`, `b` (no
  write response) or `all`. Long enough (more than the burst FIFO's slots times 9 clocks) it drops
  the frames whose features find the FIFO full (DMA_DROPPED);
- `axierr:FIRST[:EVERY[:RESP]]`: the FIRST-th burst of m_axi_feat (from 1) is answered RESP
  (`slverr`, the default, or `decerr`) and not stored, with EVERY > 0 every EVERY-th after it too:
  the frame it belongs to is dropped (DMA_DROPPED, DMA_BUS_ERRORS);
- `axislow:READY:DELAY`: AWREADY and WREADY each high with probability READY (0 < READY <= 1) a
  clock, every write response DELAY clocks after the burst's last beat.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from golden_model import regs
from orb_accel.bus import Bus, BusError

if TYPE_CHECKING:
    from .fast.sim import FastSim

OPS = ("read", "write", "block")
RESPONSES = {"slverr": 2, "decerr": 3}
MAX_SCHEDULE_BEATS = 50_000_000  # the unrolled video of a cut schedule (12 bytes a beat in the harness)


@dataclass(frozen=True)
class Cut:
    every: int  # frames between cuts
    periods: int  # frame periods without a pixel

    @property
    def text(self) -> str:
        return f"cut:{self.every}:{self.periods}"


@dataclass(frozen=True)
class BusFault:
    op: str
    where: str  # a register name or "mem"
    first: int
    every: int = 0
    resp: int = 2

    @property
    def text(self) -> str:
        name = {v: k for k, v in RESPONSES.items()}[self.resp]
        return f"buserr:{self.op}:{self.where}:{self.first}:{self.every}:{name}"

    def covers(self, op: str, addr: int) -> bool:
        if op != self.op:
            return False
        if self.where == "mem":
            return addr >= regs.MEM_BASE
        return addr == getattr(regs, self.where).offset

    def hits(self, n: int) -> bool:
        """Whether the n-th covered operation (from 1) is answered with the error."""
        return n == self.first or (self.every > 0 and n > self.first and (n - self.first) % self.every == 0)


@dataclass(frozen=True)
class AxiStall:
    every: int  # clocks from one stall's start to the next
    clocks: int  # its length
    what: str = "aww"

    @property
    def text(self) -> str:
        return f"axistall:{self.every}:{self.clocks}:{self.what}"


@dataclass(frozen=True)
class AxiError:
    first: int  # the burst (from 1)
    every: int = 0
    resp: int = 2

    @property
    def text(self) -> str:
        name = {v: k for k, v in RESPONSES.items()}[self.resp]
        return f"axierr:{self.first}:{self.every}:{name}"


@dataclass(frozen=True)
class AxiSlow:
    ready: float  # AWREADY and WREADY: the probability a clock
    delay: int  # clocks from a burst's last beat to its response

    @property
    def text(self) -> str:
        return f"axislow:{self.ready}:{self.delay}"


STALL_HOLDS = {"aww": (True, True, False), "aw": (True, False, False), "w": (False, True, False),
               "b": (False, False, True), "all": (True, True, True)}  # fmt: skip
AxiFault = AxiStall | AxiError | AxiSlow
Fault = Cut | BusFault | AxiStall | AxiError | AxiSlow


def _int(text: str, what: str, spec: str, low: int) -> int:
    try:
        value = int(text)
    except ValueError:
        raise ValueError(f"fault {spec!r}: {what} {text!r} is not an integer") from None
    if value < low:
        raise ValueError(f"fault {spec!r}: {what} must be {low} or more, got {value}")
    return value


def parse(spec: str) -> Fault:
    """A fault of the module docstring's forms; ValueError naming the form otherwise."""
    kind, *parts = spec.split(":")
    if kind == "cut" and len(parts) == 2:
        return Cut(_int(parts[0], "EVERY", spec, 1), _int(parts[1], "PERIODS", spec, 1))
    if kind == "buserr" and 3 <= len(parts) <= 5:
        op, where = parts[0], parts[1]
        if op not in OPS:
            raise ValueError(f"fault {spec!r}: OP must be one of {', '.join(OPS)}")
        if where != "mem" and not isinstance(getattr(regs, where, None), regs.Register):
            raise ValueError(f"fault {spec!r}: WHERE must be a register name (docs/registers.md) or mem")
        every = _int(parts[3], "EVERY", spec, 0) if len(parts) > 3 else 0
        resp = parts[4] if len(parts) > 4 else "slverr"
        if resp not in RESPONSES:
            raise ValueError(f"fault {spec!r}: RESP must be slverr or decerr")
        return BusFault(op, where, _int(parts[2], "FIRST", spec, 1), every, RESPONSES[resp])
    if kind == "axistall" and 2 <= len(parts) <= 3:
        every, clocks = _int(parts[0], "EVERY", spec, 2), _int(parts[1], "CLOCKS", spec, 1)
        what = parts[2] if len(parts) > 2 else "aww"
        if what not in STALL_HOLDS:
            raise ValueError(f"fault {spec!r}: WHAT must be one of {', '.join(STALL_HOLDS)}")
        if clocks >= every:
            raise ValueError(f"fault {spec!r}: CLOCKS must be below EVERY (the interconnect must move at times)")
        return AxiStall(every, clocks, what)
    if kind == "axierr" and 1 <= len(parts) <= 3:
        every = _int(parts[1], "EVERY", spec, 0) if len(parts) > 1 else 0
        resp = parts[2] if len(parts) > 2 else "slverr"
        if resp not in RESPONSES:
            raise ValueError(f"fault {spec!r}: RESP must be slverr or decerr")
        return AxiError(_int(parts[0], "FIRST", spec, 1), every, RESPONSES[resp])
    if kind == "axislow" and len(parts) == 2:
        try:
            ready = float(parts[0])
        except ValueError:
            raise ValueError(f"fault {spec!r}: READY {parts[0]!r} is not a number") from None
        if not 0 < ready <= 1:
            raise ValueError(f"fault {spec!r}: READY must be in (0, 1], got {ready}")
        return AxiSlow(ready, _int(parts[1], "DELAY", spec, 0))
    raise ValueError(f"fault {spec!r} is not cut:EVERY:PERIODS, buserr:OP:WHERE:FIRST[:EVERY[:RESP]], "
                     "axistall:EVERY:CLOCKS[:WHAT], axierr:FIRST[:EVERY[:RESP]] or axislow:READY:DELAY")  # fmt: skip


def apply_axi_faults(sim: FastSim, faults: list[Fault]) -> list[AxiFault]:
    """Set the interconnect faults (AxiStall, AxiError, AxiSlow) on the fast engine's model of a DDR
    build's interconnect (orb_sim.fast.sim.FastSim); returns those set. Stalls count clocks from the
    model's start, errors the bursts since it."""
    names = {v: k for k, v in RESPONSES.items()}
    done: list[AxiFault] = []
    for f in faults:
        if isinstance(f, AxiStall):
            aw, w, b = STALL_HOLDS[f.what]
            sim.axi_stall_every(f.every, f.clocks, 0, aw=aw, w=w, b=b)
        elif isinstance(f, AxiError):
            sim.axi_error_every(f.first - 1, f.every, names[f.resp])
        elif isinstance(f, AxiSlow):
            sim.set_axi_timing(aw_ready=f.ready, w_ready=f.ready, b_delay=f.delay)
        else:
            continue
        done.append(f)
    return done


class FaultyBus:
    """A Bus whose operations answer the BusFaults' errors instead of being done; `injected`
    counts them, `log` lists (op, address) of each."""

    def __init__(self, bus: Bus, faults: list[Fault]) -> None:
        self.bus = bus
        self.faults = [f for f in faults if isinstance(f, BusFault)]
        self.seen = [0] * len(self.faults)
        self.injected = 0
        self.log: list[tuple[str, int]] = []

    def _inject(self, op: str, addr: int, value: int | None = None) -> None:
        for i, f in enumerate(self.faults):
            if f.covers(op, addr):
                self.seen[i] += 1
                if f.hits(self.seen[i]):
                    self.injected += 1
                    self.log.append((op, addr))
                    raise BusError("write" if op == "write" else "read", addr, f.resp, value)

    def read32(self, addr: int) -> int:
        self._inject("read", addr)
        return self.bus.read32(addr)

    def write32(self, addr: int, value: int) -> None:
        self._inject("write", addr, value)
        self.bus.write32(addr, value)

    def read_block(self, addr: int, count: int) -> np.ndarray:
        self._inject("block", addr)
        return self.bus.read_block(addr, count)

    def wait_irq(self, timeout_s: float) -> bool:
        return self.bus.wait_irq(timeout_s)

    # a DDR build's memory (the socket bus's MEM_READ), passed through: no fault is injected there
    @property
    def memory_region(self) -> tuple[int, int] | None:
        return getattr(self.bus, "memory_region", None)

    def read_mem(self, addr: int, nbytes: int) -> bytes:
        return self.bus.read_mem(addr, nbytes)  # type: ignore[attr-defined]


def cut_program(words: np.ndarray, h_blank: int, v_blank: int, periods: int) -> tuple[np.ndarray, ...]:
    """(data, flags, gaps) of a frame cut half-way: its first half of lines as a camera sends them
    (tuser on the first beat, tlast on each line's last), then no pixel for `periods` frame
    periods (of this frame's size and blanking)."""
    from .fast.sim import frame_program

    h, w = words.shape[:2]
    data, flags, gaps = frame_program(words[: max(1, h // 2)], h_blank, 0)
    gaps = gaps.copy()
    gaps[-1] = h_blank + periods * ((w + h_blank) * h + v_blank)
    return data, flags, gaps


def video_schedule(frames: list[np.ndarray], faults: list[Fault], h_blank: int,
                   v_blank: int) -> list[tuple[np.ndarray, ...]]:  # fmt: skip
    """The fast engine's video programs for `frames` (packed tdata words), played round and round:
    the frames, or with a Cut the frames up to EVERY of them, then the cut frame."""
    from .fast.sim import frame_program

    cuts = [f for f in faults if isinstance(f, Cut)]
    if len(cuts) > 1:
        raise ValueError(f"one cut schedule at most, got {[c.text for c in cuts]}")
    if not cuts:
        return [frame_program(f, h_blank, v_blank) for f in frames]
    cut = cuts[0]
    beats = sum(f.size for f in frames) // len(frames) * (cut.every + 1)
    if beats > MAX_SCHEDULE_BEATS:
        raise ValueError(f"fault {cut.text}: {cut.every} frames between cuts are {beats} beats of video, "
                         f"more than {MAX_SCHEDULE_BEATS}: cut more often")  # fmt: skip
    programs = [frame_program(frames[i % len(frames)], h_blank, v_blank) for i in range(cut.every)]
    programs.append(cut_program(frames[cut.every % len(frames)], h_blank, v_blank, cut.periods))
    return programs
