# SPDX-License-Identifier: MIT
"""orb_axil_regs through a cocotbext-axi AxiLiteMaster, checked against golden_model/regs.py.

Every channel (AW, W, B, AR, R) runs under a random pause pattern unless a test says otherwise. A
per-clock monitor records the handshakes of the five channels and the soft_reset, release_valid and
mem_rd_en pulses, and plays orb_feat_mem: for every mem_rd_en it drives the addressed word (random,
fixed per address) on mem_rd_data for exactly the clock edge MEM_LATENCY_g edges later and random
garbage at every other edge, so a read taken one clock early or late returns a wrong word.

Checked: the reset value of every register (generics and status ports included) from
golden_model.regs; rw round trips and the control outputs; byte strobes; SLVERR without a state
change for unknown, misaligned and ro-write addresses, writes into the memory window, reads of the
wo registers and illegal values; W1C semantics and the irq level; the soft-reset, bank-release and
ring-release pulses; the DDR ring's registers (RING_BASE, RING_STRIDE, RING_COUNT up to its maximum
16 and their outputs, RING_RELEASE, the live RING_STATUS, RING_INFO and DMA_* inputs, CFG_DDR's
generics); memory reads; AW-before-W and W-before-AW with forced delays; back-to-back transactions;
a random mix of reads and writes against a Python model of the rules in docs/registers.md; and a
fuzz on raw channels (axil_fuzz: random addresses, strobes, AW/W orders, delays and B/R pauses,
5,000 transactions per generic set) against the same model (docs/axil-regs.md).
"""

from __future__ import annotations

import itertools
import warnings
from collections import Counter, deque
from dataclasses import dataclass, field

import cocotb
import numpy as np
import pytest
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge, with_timeout

from golden_model import regs
from orbtb.runner import run
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int, set_axil_pauses

warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotbext\..*")
warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotb_bus\..*")

from cocotbext.axi import AxiLiteBus, AxiLiteMaster  # noqa: E402

OKAY, SLVERR = 0, 2
GENERIC_NAMES = (
    "WIDTH",
    "HEIGHT",
    "SCALES",
    "STEP_NUM",
    "STEP_DEN",
    "SECTORS",
    "MEM_DEPTH",
    "MEM_LATENCY",
    "ADDR_BITS",
    "MEM_DDR",
    "WIN_BASE_MB",
    "WIN_SIZE_MB",
)
# every input port a ro field shows, and its width (the field's): driven with random values
STATUS_PORTS = {f.port: f.width for r in regs.REGISTERS for f in r.fields if f.port is not None}
# the DDR ring's configuration outputs: (port, register, field)
RING_OUTPUTS = (("ring_base", "RING_BASE", "base"), ("ring_stride", "RING_STRIDE", "stride"),
                ("ring_count", "RING_COUNT", "count"))  # fmt: skip
OP_TIMEOUT_NS = 2000 * PERIOD_NS  # "nothing hangs": every transaction must finish within this


@dataclass
class Monitor:
    """Per-clock observation of the DUT, and the feature-memory model."""

    latency: int
    seed: int = 0
    edge: int = 0
    hs: dict[str, list[int]] = field(default_factory=lambda: {c: [] for c in ("aw", "w", "b", "ar", "r")})
    soft_resets: list[int] = field(default_factory=list)
    releases: list[tuple[int, int]] = field(default_factory=list)
    ring_releases: list[tuple[int, int]] = field(default_factory=list)
    mem_reqs: list[int] = field(default_factory=list)
    mem: dict[int, int] = field(default_factory=dict)

    def word(self, offset: int) -> int:
        if offset not in self.mem:
            self.mem[offset] = int(np.random.default_rng((self.seed, offset)).integers(0, 1 << 32))
        return self.mem[offset]

    async def run(self, dut) -> None:
        rng = np.random.default_rng(self.seed + 1)
        due: dict[int, int] = {}  # edge -> word to present at that edge
        chans = {
            "aw": (dut.s_axil_awvalid, dut.s_axil_awready),
            "w": (dut.s_axil_wvalid, dut.s_axil_wready),
            "b": (dut.s_axil_bvalid, dut.s_axil_bready),
            "ar": (dut.s_axil_arvalid, dut.s_axil_arready),
            "r": (dut.s_axil_rvalid, dut.s_axil_rready),
        }
        while True:
            await RisingEdge(dut.clk)
            self.edge += 1
            n = self.edge
            for name, (valid, ready) in chans.items():
                if valid.value == 1 and ready.value == 1:
                    self.hs[name].append(n)
            if dut.soft_reset.value == 1:
                self.soft_resets.append(n)
            if dut.release_valid.value == 1:
                self.releases.append((n, int(dut.release_bank.value)))
            if dut.ring_release_valid.value == 1:
                self.ring_releases.append((n, int(dut.ring_release_index.value)))
            if dut.mem_rd_en.value == 1:
                addr = int(dut.mem_rd_addr.value)
                self.mem_reqs.append(addr)
                due[n + self.latency] = self.word(addr)
            # the value for the next edge: the due word, else garbage
            nxt = due.pop(n + 1, None)
            dut.mem_rd_data.value = nxt if nxt is not None else int(rng.integers(0, 1 << 32))


class Model:
    """The register bank's rules (docs/registers.md) over golden_model.regs, for the random test."""

    def __init__(self, generics: dict[str, int], ports: dict[str, int], mem_word, addr_bits: int) -> None:
        self.generics, self.ports, self.mem_word, self.addr_bits = generics, ports, mem_word, addr_bits
        self.values = {r.name: r.reset_value(generics, ports) for r in regs.REGISTERS if r.access in ("rw", "w1c")}
        self.releases: list[int] = []  # BANK_RELEASE.bank of each release pulse
        self.ring_releases: list[int] = []  # RING_RELEASE.index of each ring release pulse
        self.soft_resets = 0

    def read(self, addr: int) -> tuple[int, int]:
        if addr % 4:
            return SLVERR, 0
        if addr >= regs.MEM_BASE:
            return OKAY, self.mem_word(addr - regs.MEM_BASE)
        r = regs.BY_OFFSET.get(addr)
        if r is None or r.access == "wo":
            return SLVERR, 0
        if r.name in self.values:
            return OKAY, self.values[r.name]
        return OKAY, r.reset_value(self.generics, self.ports)

    def write(self, addr: int, data: int, strb: int) -> int:
        r = regs.BY_OFFSET.get(addr) if addr % 4 == 0 and addr < regs.MEM_BASE else None
        if r is None or r.access == "ro":
            return SLVERR
        bm = sum(0xFF << (8 * i) for i in range(4) if strb >> i & 1)
        cur = self.values.get(r.name, 0) if r.access == "rw" else 0
        merged = (cur & ~bm) | (data & bm)
        if r.access == "w1c":
            self.values[r.name] &= ~(merged & r.mask)
            return OKAY
        if not r.legal(merged, self.generics):
            return SLVERR
        if r.access == "wo":  # BANK_RELEASE, RING_RELEASE: a pulse if a strobed byte holds a defined bit
            if bm & r.mask:
                if r.name == "BANK_RELEASE":
                    self.releases.append(r.field("bank").get(merged))
                else:
                    self.ring_releases.append(regs.RING_RELEASE.field("index").get(merged))
            return OKAY
        pulse = [f for f in r.fields if f.pulse]
        for f in pulse:
            self.soft_resets += f.get(merged)
            merged = f.put(0, merged)
        self.values[r.name] = merged
        return OKAY


class Bench:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.g = {f"{k}_g": env_int(f"ORB_{k}") for k in GENERIC_NAMES}
        self.latency = self.g["MEM_LATENCY_g"]
        self.addr_bits = self.g["ADDR_BITS_g"]
        self.ports: dict[str, int] = {}

    async def start(self, pause_prob: float, seed: int = 1, master: bool = True) -> None:
        """Reset with random status inputs and the feature-memory model running; `master`: a
        cocotbext-axi AxiLiteMaster with random pauses (else the AXI inputs idle at 0, for a test
        that drives them itself)."""
        dut = self.dut
        rng = np.random.default_rng(seed)
        self.ports = {}
        dut.rst.value = 1
        self.drive_status(rng)
        dut.frame_done_pulse.value = 0
        dut.error_pulse.value = 0
        dut.mem_rd_data.value = 0
        cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
        # bus model only once reset is asserted and the clock starts low
        if master:
            self.axil = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), dut.clk, dut.rst)
            self.set_pauses(pause_prob, seed)
        else:
            for name in ("awvalid", "wvalid", "bready", "arvalid", "rready", "awaddr", "awprot", "wdata", "wstrb",
                         "araddr", "arprot"):  # fmt: skip
                getattr(dut, f"s_axil_{name}").value = 0
        self.mon = Monitor(self.latency, seed=seed)
        cocotb.start_soon(self.mon.run(dut))
        await ClockCycles(dut.clk, 4)
        dut.rst.value = 0
        await ClockCycles(dut.clk, 2)

    def drive_status(self, rng: np.random.Generator) -> None:
        """Drive every status input (STATUS_PORTS: the ports the ro fields show, the DDR ring's
        included) with a random value and record it in self.ports (which a Model shares)."""
        for name, width in STATUS_PORTS.items():
            self.ports[name] = int(rng.integers(0, 1 << width))
            getattr(self.dut, name).value = self.ports[name]

    def ring_outputs(self) -> dict[str, int]:
        """The ring configuration outputs, by register name."""
        return {reg: int(getattr(self.dut, port).value) for port, reg, _ in RING_OUTPUTS}

    def set_pauses(self, prob: float, seed: int = 1) -> None:
        set_axil_pauses(self.axil, prob, seed)

    async def write(self, addr: int, value: int, strb: int = 0xF) -> int:
        """One write of the strobed bytes (contiguous) of value to the word at addr: the master's
        AXI address is addr + the first strobed lane (misaligned unless that lane is 0)."""
        lanes = [i for i in range(4) if strb >> i & 1]
        assert lanes == list(range(lanes[0], lanes[-1] + 1)), "strobes must be contiguous"
        data = bytes((value >> (8 * i)) & 0xFF for i in lanes)
        resp = await with_timeout(self.axil.write(addr + lanes[0], data), OP_TIMEOUT_NS, "ns")
        return int(resp.resp)

    async def raw_write(self, addr: int, wdata: int, wstrb: int) -> int:
        """A write of one raw AW and W beat (any wstrb, unstrobed lanes as given) through the
        master's channel models, bypassing its command layer (which must be idle)."""
        w_if = self.axil.write_if
        assert w_if.idle()
        aw = w_if.aw_channel._transaction_obj()
        aw.awaddr, aw.awprot = addr, 0
        w = w_if.w_channel._transaction_obj()
        w.wdata, w.wstrb = wdata, wstrb
        await w_if.aw_channel.send(aw)
        await w_if.w_channel.send(w)
        resp = await with_timeout(w_if.b_channel.recv(), OP_TIMEOUT_NS, "ns")
        return int(resp.bresp)

    async def read(self, addr: int) -> tuple[int, int]:
        """(resp, 32-bit word) of a read at addr (a misaligned addr reads one byte: one transaction)."""
        length = 4 if addr % 4 == 0 else 1
        resp = await with_timeout(self.axil.read(addr, length), OP_TIMEOUT_NS, "ns")
        return int(resp.resp), int.from_bytes(resp.data, "little")

    async def read_ok(self, reg: regs.Register) -> int:
        resp, value = await self.read(reg.offset)
        assert resp == OKAY, f"read {reg.name}: resp {resp}"
        return value

    def reset_value(self, reg: regs.Register) -> int:
        return reg.reset_value(self.g, self.ports)


def all_ones(reg: regs.Register) -> int:
    return reg.mask


# ------------------------------------------------------------------------------------------------


@cocotb.test()
async def reset_values(dut) -> None:
    """Every readable register reads its golden_model.regs reset value; outputs at reset."""
    b = Bench(dut)
    await b.start(pause_prob=0.3, seed=2)
    assert int(dut.threshold.value) == regs.THRESHOLD.field("threshold").reset
    assert int(dut.threshold_lo.value) == regs.THRESHOLD.field("low").reset
    assert int(dut.select_grid.value) == regs.SELECT.field("mode").reset
    assert int(dut.grid_cols.value) == regs.SELECT.field("cols").reset
    assert int(dut.grid_rows.value) == regs.SELECT.field("rows").reset
    # the budget's reset value, at most the bank's capacity
    assert int(dut.budget.value) == min(regs.SELECT.field("budget").reset, b.g["MEM_DEPTH_g"] - 1)
    assert int(dut.mode_orb.value) == (regs.CTRL.field("mode").reset == 0)
    assert int(dut.enable.value) == regs.CTRL.field("enable").reset
    for name in ("irq", "soft_reset", "release_valid", "ring_release_valid", "mem_rd_en"):
        assert int(getattr(dut, name).value) == 0, f"{name} is not 0 after reset"
    for port, reg, fld in RING_OUTPUTS:
        want = regs.BY_NAME[reg].field(fld).reset
        assert int(getattr(dut, port).value) == want, f"{port} is not {reg}.{fld}'s reset value {want}"
    for reg in regs.REGISTERS:
        resp, value = await b.read(reg.offset)
        if reg.access == "wo":
            assert resp == SLVERR, f"read of wo {reg.name}: resp {resp}"
            continue
        assert resp == OKAY, f"read {reg.name}: resp {resp}"
        expected = b.reset_value(reg)
        assert value == expected, f"{reg.name} = {value:#010x} after reset, expected {expected:#010x}"
    assert (await b.read_ok(regs.ID)) == regs.ORB_ID == 0x4F524231
    # status ports are shown live
    dut.frame_count.value = 0xDEADBEEF
    dut.overflow.value = 1 - b.ports["overflow"]
    await ClockCycles(dut.clk, 1)
    assert (await b.read_ok(regs.FRAME_COUNT)) == 0xDEADBEEF
    st = await b.read_ok(regs.STATUS)
    assert regs.STATUS.field("overflow").get(st) == 1 - b.ports["overflow"]
    # every status input, new random values: each ro register with a port shows them
    rng = np.random.default_rng(22)
    live = [r for r in regs.REGISTERS if any(f.port is not None for f in r.fields)]
    for _ in range(4):
        b.drive_status(rng)
        await ClockCycles(dut.clk, 1)
        for reg in live:
            expected = b.reset_value(reg)
            assert await b.read_ok(reg) == expected, f"{reg.name}: not {expected:#010x}, its inputs {b.ports}"


@cocotb.test()
async def rw_round_trip(dut) -> None:
    """rw registers keep what was written (byte strobes honoured) and drive their outputs."""
    b = Bench(dut)
    await b.start(pause_prob=0.4, seed=3)
    rng = np.random.default_rng(3)
    ctrl, thr, ien = regs.CTRL, regs.THRESHOLD, regs.IRQ_ENABLE
    for _ in range(12):
        t = int(rng.integers(0, 256))
        assert await b.write(thr.offset, t) == OKAY
        assert await b.read_ok(thr) == t
        assert int(dut.threshold.value) == t
        en, mode = int(rng.integers(0, 2)), int(rng.integers(0, 2))
        word = ctrl.field("mode").put(mode, ctrl.field("enable").put(en))
        assert await b.write(ctrl.offset, word) == OKAY
        assert await b.read_ok(ctrl) == word
        assert int(dut.enable.value) == en and int(dut.mode_orb.value) == (mode == 0)
        e = int(rng.integers(0, 4))
        assert await b.write(ien.offset, e) == OKAY
        assert await b.read_ok(ien) == e
    # byte strobes (aligned address, lanes 0..k): unstrobed lanes are not written, so their
    # reserved bits do not count; strobed reserved bits do
    assert await b.write(thr.offset, 0x0000_77A5, strb=0x1) == OKAY
    assert await b.read_ok(thr) == 0xA5
    assert await b.raw_write(thr.offset, 0x0077_0033, 0x5) == SLVERR  # byte 2 is reserved
    assert await b.read_ok(thr) == 0xA5
    word = ctrl.field("mode").put(1, ctrl.field("enable").put(1))
    assert await b.write(ctrl.offset, word) == OKAY
    assert await b.write(ctrl.offset, 0xFFFF_FF10, strb=0x1) == OKAY  # enable 0, mode 1
    assert await b.read_ok(ctrl) == ctrl.field("mode").put(1)
    assert await b.write(ien.offset, 0xFFFF_FF00, strb=0x1) == OKAY
    assert await b.read_ok(ien) == 0
    # raw W beats with garbage in the unstrobed lanes (the master always zero-fills them)
    assert await b.raw_write(thr.offset, 0xDEAD_BE3C, 0x1) == OKAY
    assert await b.read_ok(thr) == 0x3C
    assert await b.raw_write(thr.offset, 0xFFFF_FF00, 0xE) == SLVERR, "strobed reserved bytes accepted"
    assert await b.raw_write(thr.offset, 0x1234_5678, 0x0) == OKAY
    assert await b.read_ok(thr) == 0x3C, "a write without strobes changed THRESHOLD"
    assert await b.raw_write(thr.offset, 0x1234_5600, 0xE) == SLVERR
    assert await b.raw_write(thr.offset, 0x0000_00C3, 0xE) == OKAY
    assert await b.read_ok(thr) == 0x3C, "an unstrobed byte 0 was written"
    assert await b.raw_write(ctrl.offset, 0xFFFF_FF11, 0x1) == OKAY
    assert await b.read_ok(ctrl) == ctrl.field("mode").put(1, ctrl.field("enable").put(1))
    assert await b.raw_write(regs.BANK_RELEASE.offset, 0x0000_0001, 0x0) == OKAY
    assert await b.raw_write(regs.BANK_RELEASE.offset, 0xFFFF_FF01, 0x1) == OKAY
    await ClockCycles(dut.clk, 2)
    assert [bank for _, bank in b.mon.releases] == [1], "BANK_RELEASE without byte 0 strobed pulsed"


@cocotb.test()
async def illegal_values(dut) -> None:
    """Reserved bits and out-of-range fields of rw/wo writes: SLVERR and no state change."""
    b = Bench(dut)
    await b.start(pause_prob=0.3, seed=4)
    ctrl, thr, ien = regs.CTRL, regs.THRESHOLD, regs.IRQ_ENABLE
    good = ctrl.field("enable").put(1, ctrl.field("mode").put(1))
    assert await b.write(ctrl.offset, good) == OKAY
    assert await b.write(thr.offset, 77) == OKAY
    assert await b.write(ien.offset, 2) == OKAY
    for mode in (2, 3):
        word = ctrl.field("mode").put(mode, ctrl.field("soft_reset").put(1))
        assert await b.write(ctrl.offset, word) == SLVERR, f"CTRL.mode = {mode} accepted"
    assert await b.write(ctrl.offset, good | 1 << 8) == SLVERR, "CTRL reserved bit 8 accepted"
    assert await b.write(thr.offset, 0x10000) == SLVERR, "THRESHOLD 0x10000 accepted"
    assert await b.write(thr.offset, 0xFFFFFFFF) == SLVERR
    assert await b.write(ien.offset, 0x4) == SLVERR
    for bank in (regs.BANKS, 7, 15):
        assert await b.write(regs.BANK_RELEASE.offset, bank) == SLVERR, f"BANK_RELEASE {bank} accepted"
    assert await b.write(regs.BANK_RELEASE.offset, 0x10) == SLVERR
    ring_max = regs.RING_COUNT.field("count").max
    assert await b.write(regs.RING_COUNT.offset, 5) == OKAY
    for count in (ring_max + 1, 31, 0x20, 0x25, 1 << 31):
        assert await b.write(regs.RING_COUNT.offset, count) == SLVERR, f"RING_COUNT {count:#x} accepted"
    for index in (0x10, 0x1F, 1 << 8):
        assert await b.write(regs.RING_RELEASE.offset, index) == SLVERR, f"RING_RELEASE {index:#x} accepted"
    await ClockCycles(dut.clk, 3)
    assert await b.read_ok(regs.RING_COUNT) == 5 and int(dut.ring_count.value) == 5
    assert await b.read_ok(ctrl) == good
    assert await b.read_ok(thr) == 77 and int(dut.threshold.value) == 77
    assert await b.read_ok(ien) == 2
    assert int(dut.mode_orb.value) == 0 and int(dut.enable.value) == 1
    assert b.mon.soft_resets == [], "a refused CTRL write pulsed soft_reset"
    assert b.mon.releases == [], "a refused BANK_RELEASE write pulsed release_valid"
    assert b.mon.ring_releases == [], "a refused RING_RELEASE write pulsed ring_release_valid"


@cocotb.test()
async def select_limits(dut) -> None:
    """SELECT: the grid's minimum (1 x 1) and the budget's maximum (the bank's capacity, MEM_DEPTH_g - 1) answer
    SLVERR just outside and OKAY just inside; outputs follow; byte strobes merge before the check."""
    b = Bench(dut)
    await b.start(pause_prob=0.3, seed=13)
    sel = regs.SELECT
    cap = min(b.g["MEM_DEPTH_g"] - 1, (1 << sel.field("budget").width) - 1)

    def word(mode: int, cols: int, rows: int, budget: int) -> int:
        cells = sel.field("cols").put(cols, sel.field("rows").put(rows, sel.field("budget").put(budget)))
        return sel.field("mode").put(mode, cells)

    def grid_out() -> tuple[int, int]:
        return int(dut.grid_cols.value), int(dut.grid_rows.value)

    good = word(1, 1, 1, cap)
    assert await b.write(sel.offset, good) == OKAY
    assert await b.read_ok(sel) == good
    assert grid_out() == (1, 1) and int(dut.budget.value) == cap and int(dut.select_grid.value) == 1
    assert await b.write(sel.offset, word(1, 0, 6, cap)) == SLVERR, "0 columns accepted"
    assert await b.write(sel.offset, word(1, 8, 0, 0)) == SLVERR, "0 rows accepted"
    if cap < (1 << sel.field("budget").width) - 1:
        assert await b.write(sel.offset, word(1, 8, 6, cap + 1)) == SLVERR, f"budget {cap + 1} accepted"
    assert await b.write(sel.offset, word(2, 8, 6, 0)) == SLVERR, "mode 2 accepted"
    assert await b.write(sel.offset, good | 1 << 30) == SLVERR, "reserved bit 30 accepted"
    assert await b.read_ok(sel) == good, "a refused write changed SELECT"
    # byte lane 1 alone: the grid, checked after the merge
    assert await b.raw_write(sel.offset, 0x0000_F000, 0x2) == SLVERR
    assert await b.raw_write(sel.offset, 0x0000_FF00, 0x2) == OKAY
    assert await b.read_ok(sel) == word(1, 15, 15, cap) and grid_out() == (15, 15)
    assert await b.write(sel.offset, word(0, 7, 3, 0)) == OKAY
    await ClockCycles(dut.clk, 1)  # the budget output is registered (held at the capacity)
    assert int(dut.select_grid.value) == 0 and int(dut.budget.value) == 0 and grid_out() == (7, 3)
    thr = regs.THRESHOLD
    t = thr.field("threshold").put(40, thr.field("low").put(9))
    assert await b.write(thr.offset, t) == OKAY
    assert int(dut.threshold.value) == 40 and int(dut.threshold_lo.value) == 9


@cocotb.test()
async def slverr_addresses(dut) -> None:
    """Unknown and misaligned addresses, ro writes, memory-window writes: SLVERR, nothing changes."""
    b = Bench(dut)
    await b.start(pause_prob=0.3, seed=5)
    known = {r.offset for r in regs.REGISTERS}
    rng = np.random.default_rng(5)
    unknown = sorted(
        {0x3C, 0x40, 0x58, max(known) + 4, max(known) + 8, regs.MEM_BASE - 4}
        | {int(a) * 4 for a in rng.integers(0, regs.MEM_BASE // 4, 8)}
    )
    unknown = [a for a in unknown if a not in known]
    for a in unknown:
        assert (await b.read(a))[0] == SLVERR, f"read of unknown {a:#x} answered OKAY"
        assert await b.write(a, 0) == SLVERR, f"write to unknown {a:#x} answered OKAY"
    for reg in regs.REGISTERS:
        for off in (1, 2, 3):
            assert (await b.read(reg.offset + off))[0] == SLVERR, f"misaligned read {reg.offset + off:#x}"
            assert await b.write(reg.offset, 0xFF << (8 * off), strb=1 << off) == SLVERR, (
                f"misaligned write {reg.offset + off:#x}"
            )
    for reg in regs.REGISTERS:
        if reg.access == "ro":
            assert await b.write(reg.offset, 0xFFFFFFFF) == SLVERR, f"write to ro {reg.name} answered OKAY"
            assert await b.write(reg.offset, 0) == SLVERR
    n_mem = len(b.mon.mem_reqs)
    top = (1 << b.addr_bits) - 4
    for a in (regs.MEM_BASE, regs.MEM_BASE + 0x40, top):
        assert await b.write(a, 0x12345678) == SLVERR, f"write into the memory window at {a:#x} answered OKAY"
    assert (await b.read(regs.MEM_BASE + 2))[0] == SLVERR, "misaligned memory read answered OKAY"
    assert len(b.mon.mem_reqs) == n_mem, "a refused access reached the memory port"
    for reg in regs.REGISTERS:
        if reg.access != "wo":
            assert (await b.read(reg.offset))[1] == b.reset_value(reg), f"{reg.name} changed by refused writes"
    assert b.mon.soft_resets == [] and b.mon.releases == [] and b.mon.ring_releases == []


@cocotb.test()
async def w1c_and_irq(dut) -> None:
    """IRQ_STATUS set by pulses, cleared by writing 1 (a pulse during the clear wins); irq level."""
    b = Bench(dut)
    await b.start(pause_prob=0.3, seed=6)
    st, en = regs.IRQ_STATUS, regs.IRQ_ENABLE
    fd, er = st.field("frame_done"), st.field("error")

    async def pulse(sig) -> None:
        sig.value = 1
        await RisingEdge(dut.clk)
        sig.value = 0
        await ClockCycles(dut.clk, 2)

    await pulse(dut.frame_done_pulse)
    assert await b.read_ok(st) == fd.mask
    assert int(dut.irq.value) == 0, "irq without enable"
    assert await b.write(en.offset, er.mask) == OKAY
    await ClockCycles(dut.clk, 2)
    assert int(dut.irq.value) == 0, "irq from a disabled source"
    await pulse(dut.error_pulse)
    assert await b.read_ok(st) == fd.mask | er.mask
    assert int(dut.irq.value) == 1, "no irq from an enabled, set source"
    # writing 0 clears nothing; writing 1 to frame_done clears only it
    assert await b.write(st.offset, 0) == OKAY
    assert await b.read_ok(st) == fd.mask | er.mask
    assert await b.write(st.offset, fd.mask) == OKAY
    assert await b.read_ok(st) == er.mask
    assert int(dut.irq.value) == 1
    # the irq is a level: it stays until cleared
    await ClockCycles(dut.clk, 20)
    assert int(dut.irq.value) == 1
    assert await b.write(st.offset, er.mask) == OKAY
    await ClockCycles(dut.clk, 2)
    assert await b.read_ok(st) == 0
    assert int(dut.irq.value) == 0, "irq still high after clearing"
    # a disabled-then-enabled set source raises irq; disabling drops it with the status kept
    await pulse(dut.frame_done_pulse)
    assert int(dut.irq.value) == 0
    assert await b.write(en.offset, fd.mask | er.mask) == OKAY
    await ClockCycles(dut.clk, 2)
    assert int(dut.irq.value) == 1
    assert await b.write(en.offset, 0) == OKAY
    await ClockCycles(dut.clk, 2)
    assert int(dut.irq.value) == 0 and await b.read_ok(st) == fd.mask
    # W1C with reserved bits set is accepted and clears every flag
    await pulse(dut.error_pulse)
    assert await b.write(st.offset, 0xFFFFFFFF) == OKAY
    assert await b.read_ok(st) == 0
    # a pulse in the very clock that executes the clearing write wins: without pauses AW and W
    # hand over at one edge E, the write is decoded at E + 1 and executes at E + 2, so the pulse is
    # driven right after E + 1
    b.set_pauses(0.0)
    for bit, sig in ((fd, dut.frame_done_pulse), (er, dut.error_pulse)):
        await pulse(sig)
        assert await b.read_ok(st) == bit.mask

        async def pulse_at_execute(sig=sig) -> None:
            while True:
                await RisingEdge(dut.clk)
                if dut.s_axil_awvalid.value == 1 and dut.s_axil_awready.value == 1:
                    assert dut.s_axil_wvalid.value == 1 and dut.s_axil_wready.value == 1
                    break
            await RisingEdge(dut.clk)
            sig.value = 1
            await RisingEdge(dut.clk)
            sig.value = 0

        driver = cocotb.start_soon(pulse_at_execute())
        assert await b.write(st.offset, bit.mask) == OKAY
        await driver
        assert await b.read_ok(st) == bit.mask, f"a {bit.name} pulse in the clock of its clear was lost"
        assert await b.write(st.offset, bit.mask) == OKAY
        assert await b.read_ok(st) == 0


@cocotb.test()
async def soft_reset_and_bank_release(dut) -> None:
    """CTRL.soft_reset: one one-clock pulse per write of 1, reads 0; BANK_RELEASE pulses release_valid."""
    b = Bench(dut)
    await b.start(pause_prob=0.4, seed=7)
    ctrl = regs.CTRL
    word = ctrl.field("enable").put(1, ctrl.field("soft_reset").put(1))
    assert await b.write(ctrl.offset, word) == OKAY
    await ClockCycles(dut.clk, 3)
    assert len(b.mon.soft_resets) == 1, f"soft_reset pulses at edges {b.mon.soft_resets}"
    assert await b.read_ok(ctrl) == ctrl.field("enable").put(1), "soft_reset does not read 0"
    assert int(dut.enable.value) == 1
    assert await b.write(ctrl.offset, ctrl.field("enable").put(1)) == OKAY
    await ClockCycles(dut.clk, 3)
    assert len(b.mon.soft_resets) == 1, "a write of soft_reset = 0 pulsed"
    for _ in range(3):
        assert await b.write(ctrl.offset, word) == OKAY
    await ClockCycles(dut.clk, 3)
    e = b.mon.soft_resets
    assert len(e) == 4 and all(y - x > 1 for x, y in itertools.pairwise(e)), f"soft_reset pulses at edges {e}"

    banks = [0, 1, 1, 0, 1]
    for bank in banks:
        assert await b.write(regs.BANK_RELEASE.offset, bank) == OKAY
    await ClockCycles(dut.clk, 3)
    got = [bank for _, bank in b.mon.releases]
    assert got == banks, f"release_bank sequence {got}, expected {banks}"
    edges = [n for n, _ in b.mon.releases]
    assert all(y - x > 1 for x, y in itertools.pairwise(edges)), f"release_valid longer than one clock: {edges}"
    assert b.mon.ring_releases == [], "BANK_RELEASE pulsed ring_release_valid"


@cocotb.test()
async def ring_registers(dut) -> None:
    """The DDR ring's registers (docs/feature-dma.md): RING_BASE and RING_STRIDE round trips (any 32-bit value,
    byte strobes merged) on ring_base and ring_stride; RING_COUNT 0 .. 16 on ring_count, 17 .. 31 refused
    (also when a byte-lane merge makes it); RING_RELEASE pulses ring_release_valid for one clock with every
    index, reads SLVERR, acts only with byte 0 strobed, and never pulses release_valid (nor BANK_RELEASE
    ring_release_valid); RING_STATUS, RING_INFO and DMA_* show their inputs live, CFG_DDR the generics."""
    b = Bench(dut)
    await b.start(pause_prob=0.3, seed=14)
    rng = np.random.default_rng(14)
    base, stride, count = regs.RING_BASE, regs.RING_STRIDE, regs.RING_COUNT
    for _ in range(8):
        vb, vs = int(rng.integers(0, 1 << 32)), int(rng.integers(0, 1 << 32)) & ~63
        assert await b.write(base.offset, vb) == OKAY and await b.write(stride.offset, vs) == OKAY
        assert (await b.read_ok(base), await b.read_ok(stride)) == (vb, vs)
        assert b.ring_outputs()["RING_BASE"] == vb and b.ring_outputs()["RING_STRIDE"] == vs
    assert await b.raw_write(base.offset, 0xA5A5_C3A5, 0x2) == OKAY  # byte 1 only
    vb = (vb & ~0xFF00) | 0xC300
    assert await b.read_ok(base) == vb and int(dut.ring_base.value) == vb
    top = count.field("count").max
    assert top == 16 == len(dut.ring_ready) == 1 << len(dut.ring_release_index)
    for n in [*range(top + 1), 0, top]:
        assert await b.write(count.offset, n) == OKAY, f"RING_COUNT {n} refused"
        assert await b.read_ok(count) == n and int(dut.ring_count.value) == n
    for n in range(top + 1, 32):
        assert await b.write(count.offset, n) == SLVERR, f"RING_COUNT {n} accepted"
    assert await b.raw_write(count.offset, 0xFFFF_FF00 | (top + 1), 0x1) == SLVERR
    assert await b.raw_write(count.offset, 0x0000_0100, 0x2) == SLVERR, "a reserved bit of byte 1 accepted"
    assert await b.raw_write(count.offset, 0xFFFF_FF03, 0x1) == OKAY  # garbage in the unstrobed lanes
    assert await b.read_ok(count) == 3 and int(dut.ring_count.value) == 3
    # RING_RELEASE: every index, in random order, then a few back to back
    rel = regs.RING_RELEASE
    order = [int(i) for i in rng.permutation(16)] + [5, 5, 0, 15]
    for i in order:
        assert await b.write(rel.offset, i) == OKAY
    assert await b.raw_write(rel.offset, 0x0000_0007, 0x0) == OKAY  # no strobe: no pulse
    assert await b.raw_write(rel.offset, 0x0000_0009, 0xE) == OKAY  # byte 0 not strobed: no pulse
    assert await b.raw_write(rel.offset, 0xFFFF_FF0C, 0x1) == OKAY
    order.append(12)
    assert (await b.read(rel.offset))[0] == SLVERR, "RING_RELEASE readable"
    await ClockCycles(dut.clk, 3)
    got = [i for _, i in b.mon.ring_releases]
    assert got == order, f"ring_release_index sequence {got}, expected {order}"
    edges = [n for n, _ in b.mon.ring_releases]
    assert all(y - x > 1 for x, y in itertools.pairwise(edges)), f"ring_release_valid longer than a clock: {edges}"
    assert b.mon.releases == [], "RING_RELEASE pulsed release_valid"
    assert await b.write(regs.BANK_RELEASE.offset, 1) == OKAY
    await ClockCycles(dut.clk, 3)
    assert len(b.mon.ring_releases) == len(order) and [k for _, k in b.mon.releases] == [1]
    assert (await b.read_ok(base), await b.read_ok(stride), await b.read_ok(count)) == (vb, vs, 3)
    # the live inputs, changed under the bus: each read shows the present values
    status, info = regs.RING_STATUS, regs.RING_INFO
    for k in range(12):
        b.drive_status(rng)
        if k % 3 == 0:  # the edges of the fields
            for port in ("ring_ready", "ring_last", "ring_error", "ring_busy", "dma_beats"):
                b.ports[port] = (1 << STATUS_PORTS[port]) - 1 if k % 2 else 0
                getattr(dut, port).value = b.ports[port]
        await ClockCycles(dut.clk, 1)
        st = await b.read_ok(status)
        assert [status.field(f).get(st) for f in ("ready", "last", "error", "busy")] == [
            b.ports[p] for p in ("ring_ready", "ring_last", "ring_error", "ring_busy")
        ], f"RING_STATUS {st:#010x}, inputs {b.ports}"
        assert st & ~status.mask == 0, f"RING_STATUS {st:#010x}: a reserved bit set"
        word = await b.read_ok(info)
        assert (info.field("count").get(word), info.field("frame").get(word)) == (
            b.ports["ring_last_count"], b.ports["ring_last_frame"]), f"RING_INFO {word:#010x}"  # fmt: skip
        for reg, port in ((regs.DMA_DROPPED, "dma_dropped"), (regs.DMA_BUS_ERRORS, "dma_bus_errors"),
                          (regs.DMA_BEATS, "dma_beats")):  # fmt: skip
            assert await b.read_ok(reg) == b.ports[port], f"{reg.name} is not input {port}"
    # CFG_DDR: the generics
    cfg = await b.read_ok(regs.CFG_DDR)
    got_g = {f.generic: f.get(cfg) for f in regs.CFG_DDR.fields}
    assert got_g == {k: b.g[k] for k in ("MEM_DDR_g", "WIN_BASE_MB_g", "WIN_SIZE_MB_g")}, f"CFG_DDR {cfg:#010x}"
    assert cfg & ~regs.CFG_DDR.mask == 0


@cocotb.test()
async def memory_reads(dut) -> None:
    """Reads at MEM_BASE and above return the memory model's word after exactly MEM_LATENCY_g clocks."""
    b = Bench(dut)
    await b.start(pause_prob=0.4, seed=8)
    rng = np.random.default_rng(8)
    span = (1 << b.addr_bits) - regs.MEM_BASE
    offsets = [0, 4, span - 4] + [int(x) * 4 for x in rng.integers(0, span // 4, 40)]
    for i, off in enumerate(offsets):
        resp, value = await b.read(regs.MEM_BASE + off)
        assert resp == OKAY, f"memory read at offset {off:#x}: resp {resp}"
        assert value == b.mon.word(off), (
            f"memory offset {off:#x}: read {value:#010x}, memory holds {b.mon.word(off):#010x}"
        )
        if i % 5 == 0:
            assert await b.read_ok(regs.ID) == regs.ORB_ID
    assert b.mon.mem_reqs == offsets, "mem_rd_addr sequence differs (or a mem_rd_en longer than one clock)"


@cocotb.test()
async def channel_orders(dut) -> None:
    """AW before W and W before AW, each by 1 to 6 clocks, and both together: every write executes once."""
    b = Bench(dut)
    await b.start(pause_prob=0.0, seed=9)
    thr = regs.THRESHOLD
    w, aw = b.axil.write_if.w_channel, b.axil.write_if.aw_channel
    value = 1
    for first in ("aw", "w", "both"):
        for delay in range(1, 7) if first != "both" else (0,):
            late = w if first == "aw" else aw
            if first != "both":
                # the source sees a pause one clock after it is set: delay + 1 paused clocks
                late.set_pause_generator(itertools.chain([True] * (delay + 1), itertools.repeat(False)))
            n_aw, n_w = len(b.mon.hs["aw"]), len(b.mon.hs["w"])
            value = (value * 37 + 11) % 256
            assert await b.write(thr.offset, value) == OKAY
            late.set_pause_generator(None)
            e_aw, e_w = b.mon.hs["aw"][n_aw], b.mon.hs["w"][n_w]
            what = f"{first} first by {delay}"
            if first == "aw":
                assert e_w - e_aw >= delay, f"{what}: AW at edge {e_aw}, W at {e_w}"
            elif first == "w":
                assert e_aw - e_w >= delay, f"{what}: W at edge {e_w}, AW at {e_aw}"
            else:
                assert e_aw == e_w, f"{what}: AW at edge {e_aw}, W at {e_w}"
            assert len(b.mon.hs["aw"]) == n_aw + 1 and len(b.mon.hs["w"]) == n_w + 1
            assert await b.read_ok(thr) == value, what
            assert int(dut.threshold.value) == value


@cocotb.test()
async def back_to_back(dut) -> None:
    """Many reads and writes issued at once (no pauses): all complete, in order, at full rate."""
    b = Bench(dut)
    await b.start(pause_prob=0.0, seed=10)
    n = 32
    vals = [(i * 53 + 7) % 256 for i in range(n)]
    start = b.mon.edge
    writes = [cocotb.start_soon(b.write(regs.THRESHOLD.offset, v)) for v in vals]
    reads = [cocotb.start_soon(b.read(regs.ID.offset)) for _ in range(n)]
    for t in writes:
        assert await t == OKAY
    for t in reads:
        assert await t == (OKAY, regs.ORB_ID)
    clocks = b.mon.edge - start
    hs = b.mon.hs
    w_gap = max(y - x for x, y in itertools.pairwise(hs["b"][-n:]))
    r_gap = max(y - x for x, y in itertools.pairwise(hs["r"][-n:]))
    assert await b.read_ok(regs.THRESHOLD) == vals[-1]
    dut._log.info(
        "%d writes and %d reads back to back in %d clocks (B every <= %d, R every <= %d)", n, n, clocks, w_gap, r_gap
    )
    assert w_gap <= 2 and r_gap <= 2, f"slower than one write and one read per 2 clocks: {w_gap}, {r_gap}"
    # memory reads back to back
    offs = [i * 4 for i in range(16)]
    tasks = [cocotb.start_soon(b.read(regs.MEM_BASE + o)) for o in offs]
    for o, t in zip(offs, tasks, strict=True):
        assert await t == (OKAY, b.mon.word(o)), f"memory offset {o:#x}"
    # queued writes and reads with pauses (B and R backpressure while the next AW/W/AR waits):
    # OKAY and SLVERR alternate irregularly, so a lost or merged response shows
    b.set_pauses(0.5, seed=12)
    rng = np.random.default_rng(12)
    legal = rng.random(40) < 0.6
    vals = [int(v) if ok else 0x10000 | int(v) for v, ok in zip(rng.integers(0, 256, 40), legal, strict=True)]
    addrs = [int(rng.choice([regs.ID.offset, regs.BANK_RELEASE.offset, 0x3C, regs.MEM_BASE + 8])) for _ in range(40)]
    writes = [cocotb.start_soon(b.write(regs.THRESHOLD.offset, v)) for v in vals]
    reads = [cocotb.start_soon(b.read(a)) for a in addrs]
    for i, (t, ok) in enumerate(zip(writes, legal, strict=True)):
        assert await t == (OKAY if ok else SLVERR), f"queued write {i} ({vals[i]:#x})"
    for i, (t, a) in enumerate(zip(reads, addrs, strict=True)):
        expected = {regs.ID.offset: (OKAY, regs.ORB_ID), regs.MEM_BASE + 8: (OKAY, b.mon.word(8))}.get(a, (SLVERR, 0))
        assert await t == expected, f"queued read {i} at {a:#x}"
    last_legal = [v for v, ok in zip(vals, legal, strict=True) if ok][-1]
    assert await b.read_ok(regs.THRESHOLD) == last_legal


@cocotb.test()
async def random_mix(dut) -> None:
    """Random reads and writes (legal, illegal, unknown, misaligned, memory) against the Python model."""
    b = Bench(dut)
    await b.start(pause_prob=0.5, seed=11)
    model = Model(b.g, b.ports, b.mon.word, b.addr_bits)
    rng = np.random.default_rng(11)
    offsets = [r.offset for r in regs.REGISTERS]
    for i in range(300):
        kind = rng.random()
        if kind < 0.7:
            addr = int(rng.choice(offsets))
        elif kind < 0.8:
            addr = int(rng.integers(0, 0x100)) & ~3
        elif kind < 0.9:
            addr = regs.MEM_BASE + int(rng.integers(0, ((1 << b.addr_bits) - regs.MEM_BASE) // 4)) * 4
        else:
            addr = int(rng.choice(offsets)) + int(rng.integers(1, 4))
        if rng.random() < 0.5:
            expected = model.read(addr)
            got = await b.read(addr)
            assert got == expected, f"op {i}: read {addr:#x} gave {got}, model {expected}"
        else:
            r = regs.BY_OFFSET.get(addr)
            mask = r.mask if r is not None else 0xFFFFFFFF
            data = int(rng.integers(0, 1 << 32)) & (mask if rng.random() < 0.7 else 0xFFFFFFFF)
            strb = 0xF if rng.random() < 0.8 else (0x1, 0x3, 0x7)[int(rng.integers(0, 3))]
            if addr % 4:  # one byte at a misaligned address
                strb = 1 << (addr % 4)
            expected_resp = model.write(addr, data, strb)
            resp = await b.write(addr & ~3, data, strb)
            assert resp == expected_resp, (
                f"op {i}: write {data:#x} strb {strb:#x} to {addr:#x}: resp {resp}, model {expected_resp}"
            )
        if int(rng.integers(0, 40)) == 0:
            dut.frame_done_pulse.value = 1
            await RisingEdge(dut.clk)
            dut.frame_done_pulse.value = 0
            await ClockCycles(dut.clk, 2)
            model.values["IRQ_STATUS"] |= regs.IRQ_STATUS.field("frame_done").mask
    await ClockCycles(dut.clk, 3)
    assert [bank for _, bank in b.mon.releases] == model.releases
    assert [i for _, i in b.mon.ring_releases] == model.ring_releases
    assert b.ring_outputs() == {reg: model.values[reg] for _, reg, _ in RING_OUTPUTS}
    assert len(b.mon.soft_resets) == model.soft_resets
    ctrl = model.values["CTRL"]
    assert int(dut.enable.value) == regs.CTRL.field("enable").get(ctrl)
    assert int(dut.mode_orb.value) == (regs.CTRL.field("mode").get(ctrl) == 0)
    thr, sel = model.values["THRESHOLD"], model.values["SELECT"]
    assert int(dut.threshold.value) == regs.THRESHOLD.field("threshold").get(thr)
    assert int(dut.threshold_lo.value) == regs.THRESHOLD.field("low").get(thr)
    assert int(dut.select_grid.value) == regs.SELECT.field("mode").get(sel)
    assert int(dut.grid_cols.value) == regs.SELECT.field("cols").get(sel)
    assert int(dut.grid_rows.value) == regs.SELECT.field("rows").get(sel)
    assert int(dut.budget.value) == min(regs.SELECT.field("budget").get(sel), b.g["MEM_DEPTH_g"] - 1)
    irq = bool(model.values["IRQ_STATUS"] & model.values["IRQ_ENABLE"])
    assert int(dut.irq.value) == irq
    dut._log.info(
        "random mix: %d handshakes AW, %d AR, %d releases, %d ring releases, %d soft resets",
        len(b.mon.hs["aw"]),
        len(b.mon.hs["ar"]),
        len(model.releases),
        len(model.ring_releases),
        model.soft_resets,
    )


# ------------------------------------------------------------------------------------------------
# AXI4-Lite fuzz: raw channels driven clock by clock

FUZZ_TRANSACTIONS = 5000  # per generic set: 15,000 over the three sets of make test (about 2 s each)
VOLATILE = frozenset(r.offset for r in regs.REGISTERS if r.access in ("rw", "w1c"))  # what a write can change


@dataclass
class Txn:
    """One fuzz transaction: a write (addr, data, strb) or a read (addr), the channel delays before
    its valid rises (AW and W each their own: either may come first) and what the model expects."""

    index: int
    write: bool
    addr: int
    data: int = 0
    strb: int = 0
    aw_delay: int = 0
    w_delay: int = 0
    expect: tuple[int, int] | int = 0  # (resp, rdata) of a read, resp of a write


@dataclass
class Channel:
    """A valid/ready source on one channel: a queue of transactions, each offered after its delay and
    held (with its payload) until the handshake."""

    name: str
    queue: deque = field(default_factory=deque)
    current: Txn | None = None
    wait: int = 0
    done: int = 0  # handshakes so far

    def next_valid(self, delay_of) -> Txn | None:
        """The transaction to offer at the next edge (None: valid low)."""
        if self.current is None and self.queue:
            self.current = self.queue.popleft()
            self.wait = delay_of(self.current)
        if self.current is None:
            return None
        if self.wait > 0:
            self.wait -= 1
            return None
        return self.current


def fuzz_address(rng: np.random.Generator, addr_bits: int) -> int:
    """Registers of the map (the writable ones more often), their misaligned neighbours, unmapped
    and misaligned addresses below MEM_BASE, the memory window, and the edges of the two."""
    top = 1 << addr_bits
    k = rng.random()
    if k < 0.30:
        return int(rng.choice(OFFSETS))
    if k < 0.50:
        return int(rng.choice(WRITABLE))
    if k < 0.58:
        return int(rng.choice(OFFSETS)) + int(rng.integers(1, 4))
    if k < 0.70:
        return int(rng.integers(0, regs.MEM_BASE)) & (~3 if rng.random() < 0.7 else ~0)
    if k < 0.92:
        return int(rng.integers(regs.MEM_BASE, top)) & (~3 if rng.random() < 0.8 else ~0)
    edges = [0, regs.MEM_BASE - 4, regs.MEM_BASE - 1, regs.MEM_BASE, regs.MEM_BASE + 2, top - 4, top - 1]
    return int(rng.choice(edges))


def fuzz_write_data(rng: np.random.Generator, addr: int) -> tuple[int, int]:
    """(wdata, wstrb): often a value inside the register's fields, else any; any strobe, 0 and
    non-contiguous ones included. Unstrobed lanes carry garbage."""
    r = regs.BY_OFFSET.get(addr)
    k = rng.random()
    data = int(rng.integers(0, 1 << 32))
    if r is not None and k < 0.7:
        data &= r.mask
        if r.name == "CTRL":  # mode 0 or 1 mostly (2 and 3 are refused)
            data = regs.CTRL.field("mode").put(int(rng.integers(0, 2)) if rng.random() < 0.8 else 2, data)
        if r.name == "SELECT" and rng.random() < 0.7:  # the grid at least 1 x 1: mostly legal
            data = regs.SELECT.field("cols").put(int(rng.integers(1, 16)), data)
            data = regs.SELECT.field("rows").put(int(rng.integers(1, 16)), data)
            data = regs.SELECT.field("budget").put(int(rng.integers(0, 64)), data)
        if r.name == "RING_COUNT":  # 0 .. 16 mostly, at and above the maximum sometimes
            top = regs.RING_COUNT.field("count").max
            data = int(rng.integers(0, top + 1)) if rng.random() < 0.7 else int(rng.integers(top, 32))
    elif k < 0.8:
        data = int(rng.integers(0, 4))
    strb = 0xF if rng.random() < 0.6 else int(rng.integers(0, 16))
    return data, strb


OFFSETS = [r.offset for r in regs.REGISTERS]
WRITABLE = [r.offset for r in regs.REGISTERS if r.access != "ro"]


@cocotb.test()
async def axil_fuzz(dut) -> None:
    """FUZZ_TRANSACTIONS random transactions on raw channels against the model of the map (class
    Model, from golden_model.regs, the map's one source): addresses in and out of the map (unmapped,
    misaligned, the memory window), any WSTRB, AW before, with or after W, random delays before each
    valid, several writes queued, reads beside writes, random BREADY and RREADY pauses in phases.
    Checked: every response (OKAY or SLVERR as the map says), every read's data (SLVERR reads 0),
    exactly one response per request in order, no BVALID or RVALID without a request, the pulses
    (BANK_RELEASE, RING_RELEASE, CTRL.soft_reset) and the control and ring outputs. The status inputs
    (the DDR ring's included) change to new random values while the bus is drained. A read of a
    register a write can change is issued once every earlier write has its response, and a later
    write waits for that read's address handshake, so the model's order is the bus's; the other
    reads overlap the writes."""
    b = Bench(dut)
    await b.start(pause_prob=0.0, seed=21, master=False)
    seed = 21 + b.latency
    rng = np.random.default_rng(seed)
    model = Model(b.g, b.ports, b.mon.word, b.addr_bits)
    aw, w, ar = Channel("aw"), Channel("w"), Channel("ar")
    b_due: deque[Txn] = deque()  # writes whose B response is due, in order
    r_due: deque[Txn] = deque()
    pending: Txn | None = None  # generated, waiting for its turn
    issued = writes = reads = 0
    b_done = r_done = 0
    volatile_ar = 0  # volatile reads issued whose AR handshake has not happened
    order = {"aw first": 0, "w first": 0, "together": 0}
    aw_edge: dict[int, int] = {}
    w_edge: dict[int, int] = {}
    stalls = {"b": 0, "r": 0}
    answers: Counter[tuple[str, int]] = Counter()
    ready_p = {"b": 1.0, "r": 1.0}
    quiet = 0  # clocks without new transactions (after a frame-done or error pulse)
    pulses = 0
    status_changes = 0
    drain = False
    edge = 0
    sig = {n: getattr(dut, f"s_axil_{n}") for n in ("awvalid", "awready", "wvalid", "wready", "bvalid", "bready",
                                                     "bresp", "arvalid", "arready", "rvalid", "rready", "rresp",
                                                     "rdata", "awaddr", "awprot", "wdata", "wstrb", "araddr",
                                                     "arprot")}  # fmt: skip

    def delay(r: np.random.Generator) -> int:
        return 0 if r.random() < 0.5 else int(r.integers(1, 7))

    def generate() -> Txn:
        if rng.random() < 0.5:  # a write: to a writable register half of the time
            addr = int(rng.choice(WRITABLE)) if rng.random() < 0.5 else fuzz_address(rng, b.addr_bits)
            data, strb = fuzz_write_data(rng, addr)
            return Txn(issued, True, addr, data, strb, delay(rng), delay(rng))
        return Txn(issued, False, fuzz_address(rng, b.addr_bits), aw_delay=delay(rng))

    def volatile(t: Txn) -> bool:
        return not t.write and t.addr in VOLATILE

    while b_done < writes or r_done < reads or issued < FUZZ_TRANSACTIONS:
        await RisingEdge(dut.clk)
        edge += 1
        # what the last edge took (values read after an edge are those it sampled)
        bvalid, rvalid = int(sig["bvalid"].value), int(sig["rvalid"].value)
        if int(sig["awvalid"].value) and int(sig["awready"].value):
            aw_edge[aw.current.index] = edge
            aw.current, aw.done = None, aw.done + 1
        if int(sig["wvalid"].value) and int(sig["wready"].value):
            w_edge[w.current.index] = edge
            w.current, w.done = None, w.done + 1
        if int(sig["arvalid"].value) and int(sig["arready"].value):
            volatile_ar -= volatile(ar.current)
            ar.current, ar.done = None, ar.done + 1
        assert not bvalid or b_done < min(aw.done, w.done), f"edge {edge}: BVALID without a write in flight"
        assert not rvalid or r_done < ar.done, f"edge {edge}: RVALID without a read in flight"
        if bvalid and int(sig["bready"].value):
            t = b_due.popleft()
            got = int(sig["bresp"].value)
            assert got == t.expect, (f"transaction {t.index}: write {t.data:#010x} strb {t.strb:#x} to {t.addr:#x}: "
                                     f"BRESP {got}, the model {t.expect}")  # fmt: skip
            b_done += 1
            answers["write", got] += 1
            i = t.index
            order["together" if aw_edge[i] == w_edge[i] else "aw first" if aw_edge[i] < w_edge[i] else "w first"] += 1
        elif bvalid:
            stalls["b"] += 1
        if rvalid and int(sig["rready"].value):
            t = r_due.popleft()
            got = (int(sig["rresp"].value), int(sig["rdata"].value))
            assert got == t.expect, f"transaction {t.index}: read {t.addr:#x}: (RRESP, RDATA) {got}, model {t.expect}"
            answers["read", got[0]] += 1
            r_done += 1
        elif rvalid:
            stalls["r"] += 1
        # new transactions: a few in flight, in the order the model applies them
        if quiet:
            quiet -= 1
            dut.frame_done_pulse.value = 0
            dut.error_pulse.value = 0
        elif drain and not (b_due or r_due or aw.queue or w.queue or ar.queue):
            # the bus drained: an interrupt source fires (IRQ_STATUS is set; a write to it is w1c)
            drain = False
            bit = regs.IRQ_STATUS.field("frame_done" if rng.random() < 0.5 else "error")
            (dut.frame_done_pulse if bit.name == "frame_done" else dut.error_pulse).value = 1
            model.values["IRQ_STATUS"] |= bit.mask
            quiet = 3
            pulses += 1
            if rng.random() < 0.5:  # and the status inputs change (the model shares b.ports)
                b.drive_status(rng)
                status_changes += 1
        elif not drain and issued < FUZZ_TRANSACTIONS and len(b_due) + len(r_due) < 4:
            if pending is None:
                pending = generate()
            t = pending
            if (t.write and volatile_ar == 0) or (not t.write and (not volatile(t) or b_done == writes)):
                if t.write:
                    t.expect = model.write(t.addr, t.data, t.strb)
                    aw.queue.append(t)
                    w.queue.append(t)
                    b_due.append(t)
                    writes += 1
                else:
                    t.expect = model.read(t.addr)
                    ar.queue.append(t)
                    r_due.append(t)
                    reads += 1
                    volatile_ar += volatile(t)
                issued += 1
                pending = None
                drain = rng.random() < 0.015  # let the bus drain, then pulse an interrupt source
                if issued % 250 == 0:  # a new phase of B and R back-pressure
                    ready_p = {c: float(rng.choice([1.0, 0.8, 0.5, 0.2])) for c in ready_p}
        # drive the next edge
        t = aw.next_valid(lambda t: t.aw_delay)
        sig["awvalid"].value = int(t is not None)
        if t is not None:
            sig["awaddr"].value = t.addr
            sig["awprot"].value = int(rng.integers(0, 8))
        t = w.next_valid(lambda t: t.w_delay)
        sig["wvalid"].value = int(t is not None)
        if t is not None:
            sig["wdata"].value = t.data
            sig["wstrb"].value = t.strb
        t = ar.next_valid(lambda t: t.aw_delay)
        sig["arvalid"].value = int(t is not None)
        if t is not None:
            sig["araddr"].value = t.addr
            sig["arprot"].value = int(rng.integers(0, 8))
        sig["bready"].value = int(rng.random() < ready_p["b"])
        sig["rready"].value = int(rng.random() < ready_p["r"])
    # nothing more may come
    sig["bready"].value = sig["rready"].value = 1
    for _ in range(20):
        await RisingEdge(dut.clk)
        assert not int(sig["bvalid"].value) and not int(sig["rvalid"].value), "a response without a request"
    assert (aw.done, w.done, ar.done) == (writes, writes, reads)
    assert [bank for _, bank in b.mon.releases] == model.releases
    assert [i for _, i in b.mon.ring_releases] == model.ring_releases
    assert b.ring_outputs() == {reg: model.values[reg] for _, reg, _ in RING_OUTPUTS}
    assert len(b.mon.soft_resets) == model.soft_resets
    ctrl, thr, sel = model.values["CTRL"], model.values["THRESHOLD"], model.values["SELECT"]
    assert int(dut.enable.value) == regs.CTRL.field("enable").get(ctrl)
    assert int(dut.mode_orb.value) == (regs.CTRL.field("mode").get(ctrl) == 0)
    assert int(dut.threshold.value) == regs.THRESHOLD.field("threshold").get(thr)
    assert int(dut.threshold_lo.value) == regs.THRESHOLD.field("low").get(thr)
    assert int(dut.select_grid.value) == regs.SELECT.field("mode").get(sel)
    assert (int(dut.grid_cols.value), int(dut.grid_rows.value)) == (regs.SELECT.field("cols").get(sel),
                                                                    regs.SELECT.field("rows").get(sel))  # fmt: skip
    assert int(dut.budget.value) == min(regs.SELECT.field("budget").get(sel), b.g["MEM_DEPTH_g"] - 1)
    assert int(dut.irq.value) == bool(model.values["IRQ_STATUS"] & model.values["IRQ_ENABLE"])
    # every ordering, both back-pressures, OKAY and SLVERR to reads and writes, and the pulses happened
    kinds = [answers[op, resp] for op in ("write", "read") for resp in (OKAY, SLVERR)]
    assert min(order.values()) >= 100 and min(stalls.values()) >= 100 and min(kinds) >= 100, (order, stalls, answers)
    assert len(model.releases) >= 10 and len(model.ring_releases) >= 10 and model.soft_resets >= 10
    assert pulses >= 10 and status_changes >= 5
    dut._log.info("fuzz (seed %d): %d transactions (%d writes, %d reads) in %d clocks; writes OKAY %d, SLVERR %d; "
                  "reads OKAY %d, SLVERR %d; AW/W %s; B stalled %d clocks, R %d; %d releases, %d ring releases, "
                  "%d soft resets, %d interrupt pulses, %d status changes", seed, issued, writes, reads, edge, *kinds,
                  order, stalls["b"], stalls["r"], len(model.releases), len(model.ring_releases), model.soft_resets,
                  pulses, status_changes)  # fmt: skip


# ------------------------------------------------------------------------------------------------
# pytest runners: three generic sets (memory latency 1, 2 and 5, both address widths' extremes; CFG_DDR's
# generics at their defaults (the block RAM), at their extremes and in between (the DDR ring))

GENERIC_SETS = {
    "lat1": {
        "WIDTH_g": 640,
        "HEIGHT_g": 480,
        "SCALES_g": 1,
        "STEP_NUM_g": 2,
        "STEP_DEN_g": 1,
        "SECTORS_g": 32,
        "MEM_DEPTH_g": 4096,
        "MEM_LATENCY_g": 1,
        "ADDR_BITS_g": 18,
        "MEM_DDR_g": 0,
        "WIN_BASE_MB_g": 0,
        "WIN_SIZE_MB_g": 4096,
    },
    "lat2": {
        "WIDTH_g": 1920,
        "HEIGHT_g": 1080,
        "SCALES_g": 8,
        "STEP_NUM_g": 16,
        "STEP_DEN_g": 8,
        "SECTORS_g": 64,
        "MEM_DEPTH_g": 12345,
        "MEM_LATENCY_g": 2,
        "ADDR_BITS_g": 20,
        "MEM_DDR_g": 1,
        "WIN_BASE_MB_g": 4095,
        "WIN_SIZE_MB_g": 1,
    },
    "lat5": {
        "WIDTH_g": 64,
        "HEIGHT_g": 48,
        "SCALES_g": 2,
        "STEP_NUM_g": 5,
        "STEP_DEN_g": 4,
        "SECTORS_g": 16,
        "MEM_DEPTH_g": 1,
        "MEM_LATENCY_g": 5,
        "ADDR_BITS_g": 19,
        "MEM_DDR_g": 1,
        "WIN_BASE_MB_g": 512,
        "WIN_SIZE_MB_g": 1024,
    },
}


@pytest.mark.parametrize("name", sorted(GENERIC_SETS))
def test_orb_axil_regs(name: str) -> None:
    run("orb_axil_regs", "test_orb_axil_regs", GENERIC_SETS[name], env=SIM_ENV)
