# SPDX-License-Identifier: MIT
"""Shared support of the per-entity cocotb tests: clock and reset, a lean valid-stream driver that
samples the outputs at every clock edge, input-gap patterns and test frames.

Timing convention: edges are counted from the start of `Stream.run`. An input item is sampled at
the edge it is listed with (`in_edges`); an output of an entity with latency L for that item is
read at edge `in_edge + L` (values read right after a rising edge are those sampled by it).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge

from orb_sim.cocotb_bus import PERIOD_NS, pause_pattern, set_axil_pauses

__all__ = ["PERIOD_NS", "pause_pattern", "set_axil_pauses"]  # re-exported for the unit tests


# Extra environment for orbtb.runner.run: cocotb applies pytest's assertion rewriting to every
# module the simulation imports unless told otherwise, and rewriting scikit-image and SciPy on
# each start costs seconds per test. Only the test modules need it.
SIM_ENV = {"COCOTB_REWRITE_ASSERTION_FILES": "test_*.py"}


def env_int(name: str, default: int | None = None) -> int:
    value = os.environ.get(name)
    if value is None:
        if default is None:
            raise KeyError(f"environment variable {name} is not set")
        return default
    return int(value)


def env_str(name: str, default: str = "") -> str:
    return os.environ.get(name, default)


async def reset(dut, inputs: dict[str, int], cycles: int = 3) -> None:
    """Drive every input (and rst = 1) before the first edge, start the clock low, release reset."""
    dut.rst.value = 1
    for name, value in inputs.items():
        getattr(dut, name).value = value
    cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
    await ClockCycles(dut.clk, cycles)
    dut.rst.value = 0
    await RisingEdge(dut.clk)


def random_gaps(n: int, seed: int, prob: float = 0.25, max_gap: int = 3, long_every: int = 0) -> list[int]:
    """Idle clocks before each of n items: 0 mostly, 1..max_gap with probability prob, and (when
    long_every > 0) a long gap of 20..60 clocks before about every long_every-th item."""
    if prob <= 0 and long_every <= 0:
        return [0] * n
    rng = np.random.default_rng(seed)
    gaps = np.where(rng.random(n) < prob, rng.integers(1, max_gap + 1, n), 0)
    if long_every > 0:
        longs = rng.random(n) < 1.0 / long_every
        gaps = np.where(longs, rng.integers(20, 61, n), gaps)
    return [int(g) for g in gaps]


def window_word(win: np.ndarray) -> int:
    """A flat window port value: element (r, c) of a (n, n) uint8 window at bits (r * n + c) * 8 and up."""
    return int.from_bytes(np.ascontiguousarray(win, dtype=np.uint8).tobytes(), "little")


def to_int(value) -> int | None:
    """A sampled LogicArray as an int, or None when it holds a non-0/1 bit (U, X, ...)."""
    try:
        return int(value)
    except ValueError:
        return None


def field_of(value, lo: int, bits: int) -> int | None:
    """Bits lo .. lo+bits-1 of a sampled LogicArray (None if any of them is not 0/1)."""
    text = str(value)  # MSB first
    n = len(text)
    part = text[n - lo - bits : n - lo]
    if any(c not in "01" for c in part):
        return None
    return int(part, 2)


@dataclass
class Stream:
    """Drives `valid` plus `ports` from precomputed items (one tuple of port values per item),
    with `gaps[i]` idle clocks before item i, and records the watched outputs at every edge where
    any of the `when` signals is 1. Only changing signals are written."""

    clk: object
    valid: object
    ports: Sequence[object]
    watch: Sequence[object]
    when: Sequence[object]
    in_edges: list[int] = field(default_factory=list)
    samples: list[tuple[int, list]] = field(default_factory=list)  # (edge, [watched values])
    edge: int = 0

    def _sample(self) -> None:
        for w in self.when:
            if w.value == 1:
                self.samples.append((self.edge, [h.value for h in self.watch]))
                return

    async def run(self, items: Sequence[Sequence[int]], gaps: Sequence[int] | None = None, tail: int = 0) -> None:
        clk, valid, ports = self.clk, self.valid, self.ports
        current: list[int | None] = [None] * len(ports)
        valid_on = False
        sample = self._sample
        for i, item in enumerate(items):
            gap = gaps[i] if gaps is not None else 0
            if gap:
                if valid_on:
                    valid.value = 0
                    valid_on = False
                for _ in range(gap):
                    await RisingEdge(clk)
                    self.edge += 1
                    sample()
            for k, v in enumerate(item):
                if current[k] != v:
                    ports[k].value = v
                    current[k] = v
            if not valid_on:
                valid.value = 1
                valid_on = True
            await RisingEdge(clk)
            self.edge += 1
            self.in_edges.append(self.edge)
            sample()
        if valid_on:
            valid.value = 0
        await self.idle(tail)

    async def idle(self, cycles: int) -> None:
        for _ in range(cycles):
            await RisingEdge(self.clk)
            self.edge += 1
            self._sample()


def make_frame(kind: str, width: int, height: int, bits: int = 8, seed: int = 0) -> np.ndarray:
    """A (height, width) int64 frame of `bits`-bit values: `photo:<name>` (a real photograph; for
    bits > 8 its pixels fill the top 8 bits and random bits the rest), `random`, or anything
    orbtb.images.make knows."""
    from orbtb import images

    rng = np.random.default_rng(seed)
    if kind == "random":
        return rng.integers(0, 1 << bits, (height, width), dtype=np.int64)
    img = images.make(kind, width, height).astype(np.int64)
    if bits > 8:
        img = (img << (bits - 8)) | rng.integers(0, 1 << (bits - 8), (height, width), dtype=np.int64)
    elif bits < 8:
        img >>= 8 - bits
    return img


def parse_frames(spec: str) -> list[tuple[str, int]]:
    """`kind@height,kind@height,...` (kind as in make_frame) into (kind, height) pairs."""
    out = []
    for part in spec.split(","):
        kind, _, height = part.rpartition("@")
        out.append((kind, int(height)))
    return out
