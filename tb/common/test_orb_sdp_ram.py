# SPDX-License-Identifier: MIT
"""orb_sdp_ram against a cycle-exact Python model of the documented behaviour.

The model: at each clock edge, rd_en loads the word at rd_addr into the read register as it was
before this edge's write (read-first), wr_en then writes wr_data at wr_addr, and with LATENCY_g = 2
out_en loads the read register's previous value into the output register. Both registers start
at 0; words start at 0 with INIT_ZERO_g, else unknown ('U' until written). Inputs change and
rd_data is compared on falling edges, every clock, whether or not anything was read.

Scenarios, in one run: reads of unwritten words, every word filled and read back, random traffic
over the whole address range with random enables, reads and writes of the same address in the
same clock (read-first) and in consecutive clocks, and enables held low. The run counts what it
exercised and fails if a case never occurred. Runners: depths 2 to 640 (one not a power of two),
widths 1 to 48, both latencies, with and without initial value.
"""

from __future__ import annotations

import cocotb
import numpy as np
import pytest
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, FallingEdge

from orbtb.runner import run
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int, env_str, to_int


class SdpRamModel:
    """The RAM as documented; None stands for an unknown ('U') word."""

    def __init__(self, depth: int, latency: int, init_zero: bool) -> None:
        self.mem: list[int | None] = [0 if init_zero else None] * depth
        self.latency = latency
        self.q: int | None = 0
        self.q2: int | None = 0

    def edge(self, we: int, wa: int, wd: int, re: int, ra: int, oe: int) -> None:
        q_before = self.q
        if re:
            self.q = self.mem[ra]  # read-first: before this edge's write
        if we:
            self.mem[wa] = wd
        if self.latency == 2 and oe:
            self.q2 = q_before

    @property
    def out(self) -> int | None:
        return self.q if self.latency == 1 else self.q2


Op = tuple[int, int, int, int, int, int]  # we, wa, wd, re, ra, oe


def schedule(depth: int, width: int, init_zero: bool, rng: np.random.Generator) -> list[tuple[str, Op]]:
    """The stimulus, one (scenario, inputs) pair per clock."""
    ops: list[tuple[str, Op]] = []

    def data() -> int:
        return int.from_bytes(rng.bytes((width + 7) // 8), "little") & ((1 << width) - 1)

    ops += [("unwritten", (0, 0, 0, 1, a, 1)) for a in range(min(depth, 8))]
    ops += [("fill", (1, a, data(), 0, 0, 1)) for a in range(depth)]
    ops += [("read back", (0, 0, 0, 1, a, 1)) for a in range(depth)]
    for _ in range(4 * depth + 200):
        we, re, oe = (int(b) for b in rng.random(3) < (0.6, 0.7, 0.8))
        ops.append(("random", (we, int(rng.integers(depth)), data(), re, int(rng.integers(depth)), oe)))
    hot = [int(a) for a in rng.integers(depth, size=min(depth, 3))]  # few addresses: many collisions
    for _ in range(300):
        a = hot[int(rng.integers(len(hot)))]
        kind = rng.random()
        if kind < 0.5:
            ops.append(("same clock", (1, a, data(), 1, a, 1)))
        else:
            ops.append(("next clock", (1, a, data(), 0, 0, 1)))
            ops.append(("next clock", (0, 0, 0, 1, a, 1)))
    for _ in range(20):  # hold: enables low around a read
        a = int(rng.integers(depth))
        ops += [("hold", (0, 0, 0, 1, a, 1)), ("hold", (1, a, data(), 0, a, 0)), ("hold", (0, 0, 0, 0, 0, 0))]
        ops += [("hold", (0, 0, 0, 0, a, 1))] * 2
    return ops


@cocotb.test()
async def sdp_ram_model(dut) -> None:
    depth, width, latency = env_int("ORB_DEPTH"), env_int("ORB_DATA_WIDTH"), env_int("ORB_LATENCY")
    init_zero = env_str("ORB_INIT_ZERO").lower() == "true"
    rng = np.random.default_rng(depth * 7 + width + 1000 * latency + init_zero)
    ops = schedule(depth, width, init_zero, rng)
    model = SdpRamModel(depth, latency, init_zero)
    ports = (dut.wr_en, dut.wr_addr, dut.wr_data, dut.rd_en, dut.rd_addr, dut.out_en)

    for p in ports:
        p.value = 0
    cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
    await ClockCycles(dut.clk, 2)  # nothing enabled: the registers keep their initial 0
    seen = dict.fromkeys(("same clock collision", "next clock", "unwritten word read", "hold"), 0)
    prev: Op | None = None
    for n, (scenario, op) in enumerate(ops):
        await FallingEdge(dut.clk)
        got = dut.rd_data.value
        exp = model.out
        where = f"clock {n} ({scenario}; inputs at the last edge: {prev})"
        if exp is None:
            assert set(str(got)) == {"U"}, f"{where}: rd_data {got}, expected an unwritten word (all U)"
        else:
            assert to_int(got) == exp, f"{where}: rd_data {got}, expected {exp:#x}"
        for p, v in zip(ports, op, strict=True):
            p.value = v
        we, wa, _, re, ra, oe = op
        if we and re and wa == ra:
            seen["same clock collision"] += 1
        if scenario == "unwritten" and re:
            seen["unwritten word read"] += 1
        if prev is not None and prev[0] and re and prev[1] == ra:
            seen["next clock"] += 1
        if not re or not oe:
            seen["hold"] += 1
        model.edge(*op)
        prev = op
    await FallingEdge(dut.clk)
    assert to_int(dut.rd_data.value) == model.out, f"after the last clock: rd_data {dut.rd_data.value}"
    missing = [k for k, v in seen.items() if v == 0]
    assert not missing, f"cases never exercised: {missing}"
    dut._log.info("%d clocks checked; %s", len(ops), seen)


# ------------------------------------------------------------------------------------------------
# pytest runners


@pytest.mark.parametrize(
    ("depth", "width", "latency", "init_zero"),
    [
        (16, 8, 1, True),
        (48, 13, 2, False),  # depth not a power of two, no initial value
        (2, 1, 2, True),  # the smallest RAM
        (32, 36, 1, False),  # orb_feat_fifo's default shape (LUT RAM)
        (640, 48, 2, True),  # a line buffer's shape (block RAM)
    ],
)
def test_sdp_ram(depth: int, width: int, latency: int, init_zero: bool) -> None:
    run(
        "orb_sdp_ram",
        "test_orb_sdp_ram",
        {"DATA_WIDTH_g": width, "DEPTH_g": depth, "LATENCY_g": latency, "INIT_ZERO_g": init_zero},
        env=SIM_ENV,
    )
