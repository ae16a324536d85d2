# SPDX-License-Identifier: MIT
"""The fast simulation in Python (docs/fast-sim.md): the Verilated netlist of orb_accel_top with
its C++ harness (harness.cpp), loaded through ctypes, and the driver's bus over it.

    sim = FastSim(build_fast(cfg))                # orb_sim.fast.build: built once per configuration
    sim.reset()
    sim.push_frame(words)                         # a frame of tdata words, with blanking
    sim.set_live(Fraction(3, 4), 4096)            # optional: a source that cannot be held
    accel = OrbAccel(FastBus(sim), bank_read="slot")
    frame = accel.next_frame(timeout_s=0.01)      # simulated seconds: the video plays meanwhile

As with orb_sim.bus_server, the clock runs only inside the harness's calls (bus operations, waits,
run); Python sets up frames and reads results between them. 10 ns per clock.
"""

from __future__ import annotations

import ctypes
from fractions import Fraction
from pathlib import Path

import numpy as np

from orb_accel.bus import BusError

PERIOD_NS = 10
OP_TIMEOUT_CLOCKS = 5000
FLAG_USER, FLAG_LAST = 1, 2
_U32P = ctypes.POINTER(ctypes.c_uint32)
_U8P = ctypes.POINTER(ctypes.c_uint8)
_U64P = ctypes.POINTER(ctypes.c_uint64)
STATS = ("frames_started", "beats_sent", "last_beat_cycle", "longest_stall", "overlay_beats", "irq_rise_cycle",
         "irq_rises", "cycle", "fifo_dropped", "fifo_max")  # fmt: skip


class FastSimError(RuntimeError):
    """A bus operation got no answer (a lock-up), or the library cannot be loaded."""


def frame_program(words: np.ndarray, h_blank: int = 16, v_blank: int = 64) -> tuple[np.ndarray, ...]:
    """(data, flags, gaps) of a well-formed frame: tuser on the first beat, tlast on each line's
    last, h_blank idle clocks after each line, v_blank more after the frame."""
    h, w = words.shape[:2]
    data = np.ascontiguousarray(words, dtype=np.uint32).reshape(-1)
    flags = np.zeros(h * w, dtype=np.uint8)
    flags[0] |= FLAG_USER
    flags[w - 1 :: w] |= FLAG_LAST
    gaps = np.zeros(h * w, dtype=np.uint32)
    gaps[w - 1 :: w] = h_blank
    gaps[-1] += v_blank
    return data, flags, gaps


class FastSim:
    """One instance of the Verilated accelerator. `seed` 0: every register starts at 0; else
    Verilator's random initial values from that seed (docs/fast-sim.md, 2-state)."""

    def __init__(self, library: Path, seed: int = 0) -> None:
        try:
            lib = ctypes.CDLL(str(library), mode=ctypes.RTLD_LOCAL)
        except OSError as exc:
            raise FastSimError(f"cannot load {library}: {exc}") from None
        self.lib = lib
        vp, u64, u32, i32 = ctypes.c_void_p, ctypes.c_uint64, ctypes.c_uint32, ctypes.c_int
        sigs = {
            "fs_new": ([u32], vp), "fs_free": ([vp], None), "fs_cycle": ([vp], u64), "fs_set_rst": ([vp, i32], None),
            "fs_run": ([vp, u64], None), "fs_push": ([vp, _U32P, _U8P, _U32P, u64], None),
            "fs_set_loop": ([vp, i32], None), "fs_live": ([vp, u64, u64, u64], None),
            "fs_run_video": ([vp, u64], i32), "fs_stats": ([vp, _U64P], None),
            "fs_frame_start": ([vp, u64, _U64P], ctypes.c_int64), "fs_set_out_ready": ([vp, u32, u64], None),
            "fs_capture": ([vp, i32], None), "fs_captured": ([vp, _U32P, _U8P, u64], u64),
            "fs_read": ([vp, u32, _U32P, u64], i32), "fs_read_block": ([vp, u32, _U32P, u64, u64], i32),
            "fs_write": ([vp, u32, u32, u64], i32), "fs_wait_irq": ([vp, u64], i32),
        }  # fmt: skip
        for name, (args, res) in sigs.items():
            fn = getattr(lib, name)
            fn.argtypes, fn.restype = args, res
        self.h = lib.fs_new(seed)
        self.seed = seed

    def close(self) -> None:
        if self.h:
            self.lib.fs_free(self.h)
            self.h = None

    def __del__(self) -> None:
        self.close()

    # ---- clock, reset, video ---------------------------------------------------------------------
    @property
    def cycle(self) -> int:
        return int(self.lib.fs_cycle(self.h))

    def run(self, clocks: int) -> None:
        self.lib.fs_run(self.h, clocks)

    def reset(self, clocks: int = 4) -> None:
        """rst high for `clocks` clocks (the video source keeps playing), then low."""
        self.lib.fs_set_rst(self.h, 1)
        self.run(clocks)
        self.lib.fs_set_rst(self.h, 0)

    def push(self, data: np.ndarray, flags: np.ndarray, gaps: np.ndarray) -> None:
        """Queue a beat program: tdata words, flags (FLAG_USER, FLAG_LAST), idle clocks after each."""
        d = np.ascontiguousarray(data, dtype=np.uint32)
        f = np.ascontiguousarray(flags, dtype=np.uint8)
        g = np.ascontiguousarray(gaps, dtype=np.uint32)
        if not len(d) == len(f) == len(g):
            raise ValueError(f"beat program arrays of lengths {len(d)}, {len(f)}, {len(g)}")
        self.lib.fs_push(self.h, d.ctypes.data_as(_U32P), f.ctypes.data_as(_U8P), g.ctypes.data_as(_U32P), len(d))

    def push_frame(self, words: np.ndarray, h_blank: int = 16, v_blank: int = 64) -> None:
        self.push(*frame_program(words, h_blank, v_blank))

    def set_loop(self, loop: bool) -> None:
        """Play the queued programs round and round. Set it before the first of them is sent:
        without it, a program's beats are freed once sent."""
        self.lib.fs_set_loop(self.h, int(loop))

    def set_live(self, pixel_clock: Fraction, fifo_depth: int) -> None:
        """Make the source live (harness.cpp): the queued programs play at `pixel_clock` (of the
        clock, at most 1) beats or blanking clocks per clock, whatever tready does, into a FIFO of
        `fifo_depth` beats in front of s_axis_video that drops what arrives while it is full (the
        board's HDMI input bridge); a program's gaps count pixel clocks. The stats' fifo_dropped and
        fifo_max say what it lost and how full it got."""
        if not 0 < pixel_clock <= 1 or fifo_depth < 1:
            raise ValueError(f"a live source needs 0 < pixel clock <= 1 and a FIFO, got {pixel_clock}, {fifo_depth}")
        self.lib.fs_live(self.h, pixel_clock.numerator, pixel_clock.denominator, fifo_depth)

    def run_video(self, timeout_clocks: int) -> bool:
        """Run until every queued beat is sent; False when `timeout_clocks` passed first."""
        return bool(self.lib.fs_run_video(self.h, timeout_clocks))

    def stats(self) -> dict[str, int]:
        out = (ctypes.c_uint64 * len(STATS))()
        self.lib.fs_stats(self.h, out)
        return dict(zip(STATS, (int(v) for v in out), strict=True))

    def frame_starts(self) -> list[tuple[int, int]]:
        """(program index, cycle) of every frame start so far."""
        out, i, cycle = [], 0, ctypes.c_uint64()
        while (prog := self.lib.fs_frame_start(self.h, i, ctypes.byref(cycle))) >= 0:
            out.append((int(prog), int(cycle.value)))
            i += 1
        return out

    # ---- overlay output --------------------------------------------------------------------------
    def set_out_ready(self, prob: float, seed: int = 1) -> None:
        """m_axis_video_tready high with probability `prob` per clock (1: always)."""
        self.lib.fs_set_out_ready(self.h, max(0, min(1000, round(prob * 1000))), seed)

    def capture(self, on: bool) -> None:
        """Collect overlay output beats from now on (off: stop and forget them)."""
        self.lib.fs_capture(self.h, int(on))

    def captured(self) -> tuple[np.ndarray, np.ndarray]:
        n = int(self.lib.fs_captured(self.h, None, None, 0))
        data, flags = np.empty(n, dtype=np.uint32), np.empty(n, dtype=np.uint8)
        self.lib.fs_captured(self.h, data.ctypes.data_as(_U32P), flags.ctypes.data_as(_U8P), n)
        return data, flags

    # ---- AXI4-Lite and the interrupt (raw: the response code; FastBus raises) ----------------------
    def read(self, addr: int, timeout: int = OP_TIMEOUT_CLOCKS) -> tuple[int, int]:
        value = ctypes.c_uint32()
        resp = self.lib.fs_read(self.h, addr, ctypes.byref(value), timeout)
        return int(resp), int(value.value)

    def read_block(self, addr: int, count: int, timeout: int = OP_TIMEOUT_CLOCKS) -> tuple[int, np.ndarray]:
        out = np.zeros(count, dtype=np.uint32)
        resp = self.lib.fs_read_block(self.h, addr, out.ctypes.data_as(_U32P), count, timeout)
        return int(resp), out

    def write(self, addr: int, value: int, timeout: int = OP_TIMEOUT_CLOCKS) -> int:
        return int(self.lib.fs_write(self.h, addr, value, timeout))

    def wait_irq(self, timeout_clocks: int) -> bool:
        return bool(self.lib.fs_wait_irq(self.h, timeout_clocks))


class FastBus:
    """orb_accel.bus.Bus on a FastSim: the shipped driver drives the Verilated netlist. An AXI
    transaction that gets no answer within OP_TIMEOUT_CLOCKS raises FastSimError (a lock-up)."""

    def __init__(self, sim: FastSim) -> None:
        self.sim = sim
        self.reads = self.writes = 0

    def _check(self, op: str, addr: int, resp: int, value: int | None = None) -> None:
        if resp < 0:
            raise FastSimError(f"{op} at {addr:#x}: no AXI4-Lite answer within {OP_TIMEOUT_CLOCKS} clocks "
                               f"(cycle {self.sim.cycle})")  # fmt: skip
        if resp != 0:
            raise BusError(op, addr, resp, value)

    def read32(self, addr: int) -> int:
        resp, value = self.sim.read(addr)
        self.reads += 1
        self._check("read", addr, resp)
        return value

    def write32(self, addr: int, value: int) -> None:
        resp = self.sim.write(addr, value)
        self.writes += 1
        self._check("write", addr, resp, value)

    def read_block(self, addr: int, count: int) -> np.ndarray:
        resp, out = self.sim.read_block(addr, count)
        self.reads += count
        self._check("read", addr, resp)
        return out

    def wait_irq(self, timeout_s: float) -> bool:
        return self.sim.wait_irq(max(0, round(timeout_s * 1e9 / PERIOD_NS)))
