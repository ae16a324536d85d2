# SPDX-License-Identifier: MIT
"""The fast simulation in Python (docs/fast-sim.md): the Verilated netlist of orb_accel_top with
its C++ harness (harness.cpp), loaded through ctypes, and the driver's bus over it.

    sim = FastSim(build_fast(cfg))                # orb_sim.fast.build: built once per configuration
    sim.reset()
    sim.push_frame(words)                         # a frame of tdata words, with blanking
    sim.set_live(Fraction(3, 4), 4096)            # optional: a source that cannot be held
    accel = OrbAccel(FastBus(sim), bank_read="slot")
    frame = accel.next_frame(timeout_s=0.01)      # simulated seconds: the video plays meanwhile

A "DDR" build (MEM_KIND_g, docs/feature-dma.md) writes its frames through m_axi_feat into the
harness's memory (a region, default DDR_BASE and DDR_SIZE): FastMemory(sim) is the driver's
FrameMemory over it (orb_accel.ddr), FastBus.read_mem reads it for a client in another process;
set_axi_timing, axi_stall and axi_error make the interconnect slow or failing, axi_stats and
axi_log say what it did (docs/fast-sim.md, "The DDR model").

    accel = OrbAccel(FastBus(sim), memory=FastMemory(sim))

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
# The DDR (harness.cpp, m_axi_feat's slave): the memory region a new model starts with
DDR_BASE, DDR_SIZE = 0x1000_0000, 4 << 20
CACHE_LINE = 32  # bytes: FastMemory's model of the CPU's data cache (the Cortex-A9's L1 and L2 lines)
RESPONSES = {"okay": 0, "slverr": 2, "decerr": 3}
RESP_FORGOTTEN = 255  # a burst an AXI reset (rst) forgot before its response (the log's resp)
# fs_axi_stats: harness.cpp's AxiStat counters, then the channels' contents now
AXI_STATS = ("bursts", "beats", "responses", "okay", "slverr", "decerr", "injected", "refused", "refused_beats",
             "error_beats", "bytes", "protocol_errors", "aw_stall_clocks", "w_stall_clocks", "b_wait_clocks",
             "max_outstanding", "max_w_ahead", "reset_dropped", "first_protocol_cycle", "open_bursts", "unanswered",
             "w_ahead")  # fmt: skip
# fs_axi_log_take's entries (harness.cpp AxiLogEntry): a finished burst, its first four beats
AXI_LOG_DTYPE = np.dtype([("index", "<u8"), ("aw_cycle", "<u8"), ("done_cycle", "<u8"), ("b_cycle", "<u8"),
                          ("addr", "<u4"), ("resp", "<u4"), ("data", "<u8", (4,)), ("beats", "<u8")])  # fmt: skip


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
            "fs_mem_region": ([vp, u64, u64], i32), "fs_mem_info": ([vp, _U64P, _U64P], None),
            "fs_mem_read": ([vp, u64, _U8P, u64], i32), "fs_mem_write": ([vp, u64, _U8P, u64], i32),
            "fs_axi_timing": ([vp, u32, u32, u64, u64, u64, u64, u64], None),
            "fs_axi_window": ([vp, u64, u64, u32], None), "fs_axi_period": ([vp, u64, u64, u64, u32], None),
            "fs_axi_clear_windows": ([vp], None), "fs_axi_error_every": ([vp, u64, u64, u32], None),
            "fs_axi_error": ([vp, u64, u32], None), "fs_axi_error_addr": ([vp, u32, u32], None),
            "fs_axi_error_rate": ([vp, u32, u32], None),
            "fs_axi_clear_errors": ([vp], None), "fs_axi_stats": ([vp, _U64P, u64], u64),
            "fs_axi_log": ([vp, i32], None), "fs_axi_log_take": ([vp, ctypes.c_void_p, u64], u64),
            "fs_axi_log_entry_bytes": ([], u64), "fs_coverage_zero": ([vp], i32),
            "fs_coverage_write": ([vp, ctypes.c_char_p], i32),
        }  # fmt: skip
        for name, (args, res) in sigs.items():
            fn = getattr(lib, name)
            fn.argtypes, fn.restype = args, res
        if lib.fs_axi_log_entry_bytes() != AXI_LOG_DTYPE.itemsize:
            raise FastSimError(f"{library}: the harness's AXI log entry is {lib.fs_axi_log_entry_bytes()} bytes, "
                               f"sim.py reads {AXI_LOG_DTYPE.itemsize}")  # fmt: skip
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

    # ---- the DDR: m_axi_feat's slave and its memory (harness.cpp) -------------------------------------
    def set_mem_region(self, base: int, size: int) -> None:
        """The memory m_axi_feat writes: [base, base + size) bytes, zeroed (a write outside it is
        answered DECERR and not stored). A new model has DDR_BASE, DDR_SIZE."""
        if base < 0 or self.lib.fs_mem_region(self.h, base, size) != 0:
            raise ValueError(f"memory region {base:#x} + {size:#x}: not empty, within 32 bits and 1 GiB at most")

    @property
    def memory_region(self) -> tuple[int, int]:
        """(base, size) of the memory, bytes."""
        base, size = ctypes.c_uint64(), ctypes.c_uint64()
        self.lib.fs_mem_info(self.h, ctypes.byref(base), ctypes.byref(size))
        return int(base.value), int(size.value)

    def read_mem(self, addr: int, nbytes: int) -> bytes:
        """`nbytes` bytes of the memory at byte address `addr` (BusError DECERR outside the region)."""
        out = np.empty(max(0, nbytes), dtype=np.uint8)
        if nbytes < 0 or addr < 0 or self.lib.fs_mem_read(self.h, addr, out.ctypes.data_as(_U8P), len(out)) != 0:
            raise BusError("read", addr, RESPONSES["decerr"])
        return out.tobytes()

    def write_mem(self, addr: int, data: bytes | np.ndarray) -> None:
        """Store bytes into the memory (a canary, a stale pattern); BusError DECERR outside it."""
        buf = np.ascontiguousarray(np.frombuffer(bytes(data), dtype=np.uint8))
        if addr < 0 or self.lib.fs_mem_write(self.h, addr, buf.ctypes.data_as(_U8P), len(buf)) != 0:
            raise BusError("write", addr, RESPONSES["decerr"])

    def set_axi_timing(self, aw_ready: float = 1.0, w_ready: float = 1.0, b_delay: int = 0, b_jitter: int = 0,
                       outstanding: int = 8, w_ahead: int = 64, seed: int = 0) -> None:  # fmt: skip
        """The interconnect's pace: AWREADY and WREADY each high with these probabilities per clock,
        every write response `b_delay` clocks after the burst's last beat plus 0..b_jitter more (in
        order), at most `outstanding` bursts accepted and unanswered (AWREADY low beyond), at most
        `w_ahead` W beats taken before their AW; `seed` (not 0) restarts the draws."""
        permille = lambda p: max(0, min(1000, round(p * 1000)))  # noqa: E731
        self.lib.fs_axi_timing(self.h, permille(aw_ready), permille(w_ready), b_delay, b_jitter, outstanding, w_ahead,
                               seed)  # fmt: skip

    def axi_stall(self, clocks: int, start: int = 0, aw: bool = True, w: bool = True,
                  b: bool = False) -> tuple[int, int]:  # fmt: skip
        """A stall of the interconnect `start` clocks from now for `clocks` clocks: AWREADY low (aw),
        WREADY low (w), no new write response (b). Returns its cycles [start, end)."""
        first = self.cycle + start
        self.lib.fs_axi_window(self.h, first, first + clocks, int(aw) | int(w) << 1 | int(b) << 2)
        return first, first + clocks

    def axi_stall_every(self, period: int, clocks: int, phase: int = 0, aw: bool = True, w: bool = True,
                        b: bool = False) -> None:  # fmt: skip
        """A stall that repeats: clocks [phase, phase + clocks) of every `period` clocks of the
        model's cycle count (clocks < period), holding what axi_stall holds."""
        self.lib.fs_axi_period(self.h, period, phase, clocks, int(aw) | int(w) << 1 | int(b) << 2)

    def clear_axi_stalls(self) -> None:
        """Forget every stall (axi_stall, axi_stall_every)."""
        self.lib.fs_axi_clear_windows(self.h)

    def axi_error(self, burst: int, resp: str = "slverr") -> None:
        """Answer the burst of index `burst` (AW handshakes counted from 0: axi_stats()["bursts"] is
        the next one's) with SLVERR or DECERR; its data is not stored."""
        self.lib.fs_axi_error(self.h, burst, RESPONSES[resp])

    def axi_error_every(self, first: int, every: int = 0, resp: str = "slverr") -> None:
        """Answer bursts first, first + every, first + 2 every, .. (indices as axi_error's; every 0:
        `first` only) with SLVERR or DECERR."""
        self.lib.fs_axi_error_every(self.h, first, every, RESPONSES[resp])

    def axi_error_at(self, addr: int, resp: str = "slverr") -> None:
        """Answer the next burst whose AWADDR is `addr` with SLVERR or DECERR (once)."""
        self.lib.fs_axi_error_addr(self.h, addr, RESPONSES[resp])

    def axi_error_rate(self, prob: float, resp: str = "slverr") -> None:
        """Answer each burst with the error with probability `prob` (0: none)."""
        self.lib.fs_axi_error_rate(self.h, max(0, min(1000, round(prob * 1000))), RESPONSES[resp])

    def clear_axi_errors(self) -> None:
        """Forget the errors not given yet (axi_error, axi_error_every, axi_error_at) and the rate."""
        self.lib.fs_axi_clear_errors(self.h)

    def axi_stats(self) -> dict[str, int]:
        """The slave's counters (AXI_STATS): bursts, beats and responses (okay, slverr, decerr),
        bursts answered with an injected error and bursts refused (outside the region: DECERR) with
        their beats, bytes stored, the master's AXI rule violations (protocol_errors, the cycle of
        the first), stall clocks, the most bursts outstanding and W beats ahead, bursts an AXI
        reset forgot, the channels now (open_bursts: data missing; unanswered; w_ahead)."""
        out = (ctypes.c_uint64 * len(AXI_STATS))()
        if self.lib.fs_axi_stats(self.h, out, len(AXI_STATS)) != len(AXI_STATS):
            raise FastSimError("the harness's AXI counters are not sim.py's AXI_STATS")
        return dict(zip(AXI_STATS, (int(v) for v in out), strict=True))

    def axi_log(self, on: bool) -> None:
        """Log every finished burst from now on (AXI_LOG_DTYPE; off: stop and forget the log)."""
        self.lib.fs_axi_log(self.h, int(on))

    def axi_log_take(self) -> np.ndarray:
        """The bursts logged since the last take, oldest first: index, AW, last-W and B cycles,
        address, response (RESP_FORGOTTEN: lost to an AXI reset), the first four 64-bit beats."""
        n = int(self.lib.fs_axi_log_take(self.h, None, 0))
        out = np.zeros(n, dtype=AXI_LOG_DTYPE)
        if n:
            self.lib.fs_axi_log_take(self.h, out.ctypes.data, n)
        return out

    # ---- toggle coverage (a build with toggle_coverage: orb_sim.fast.activity) -------------------
    def coverage_zero(self) -> None:
        """Zero every toggle counter (the activity window starts here)."""
        if not self.lib.fs_coverage_zero(self.h):
            raise FastSimError("this library was built without toggle coverage (build_fast(..., toggle_coverage=True))")

    def coverage_write(self, path: Path) -> None:
        """Write the toggle counters since the last zero to `path` (Verilator's coverage.dat)."""
        if not self.lib.fs_coverage_write(self.h, str(path).encode()):
            raise FastSimError("this library was built without toggle coverage (build_fast(..., toggle_coverage=True))")


class FastMemory:
    """orb_accel.ddr's FrameMemory over the harness's memory (the region m_axi_feat writes): the
    driver's DDR path in the same process, `OrbAccel(FastBus(sim), memory=FastMemory(sim))`.
    phys_addr and size are the region's (the driver places its ring in it: orb_accel.ring);
    view(offset, length) returns the bytes as the CPU sees them.

    With `coherent` False (the default) the CPU's data cache is modelled strictly: the CPU sees
    the memory as it was when it last invalidated the bytes' cache lines (CACHE_LINE bytes), so a
    reader that does not invalidate before reading what the accelerator wrote sees stale data
    (zeros, or an older frame), as it may on the board. `invalidations` counts the calls."""

    def __init__(self, sim: FastSim, coherent: bool = False) -> None:
        self.sim = sim
        self.phys_addr, self.size = sim.memory_region
        self.coherent = coherent
        self._seen = None if coherent else np.frombuffer(bytearray(sim.read_mem(self.phys_addr, self.size)), np.uint8)
        self.invalidations = 0

    def _check(self, offset: int, length: int) -> None:
        if offset < 0 or length < 0 or offset + length > self.size:
            raise ValueError(f"bytes {offset:#x} + {length:#x} outside the memory of {self.size:#x} bytes")

    def invalidate(self, offset: int, length: int) -> None:
        """Drop the cache lines over [offset, offset + length): the next view reads the memory."""
        self._check(offset, length)
        self.invalidations += 1
        if self._seen is None or length == 0:
            return
        lo = offset // CACHE_LINE * CACHE_LINE
        hi = min(self.size, -(-(offset + length) // CACHE_LINE) * CACHE_LINE)
        self._seen[lo:hi] = np.frombuffer(self.sim.read_mem(self.phys_addr + lo, hi - lo), np.uint8)

    def view(self, offset: int, length: int) -> np.ndarray:
        """The bytes [offset, offset + length) as the CPU reads them (uint8, read-only; a copy, where
        the board's mapping gives a view: the same bytes while the buffer is held)."""
        self._check(offset, length)
        if self._seen is None:
            out = np.frombuffer(self.sim.read_mem(self.phys_addr + offset, length), np.uint8)
        else:
            out = self._seen[offset : offset + length].copy()
        out.flags.writeable = False
        return out


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

    # the DDR's memory, for a client in another process (the socket protocol's memory operation)
    def read_mem(self, addr: int, nbytes: int) -> bytes:
        """`nbytes` bytes of the DDR model's memory at byte address `addr` (a physical address, as
        RING_BASE holds it); BusError (DECERR) outside memory_region."""
        return self.sim.read_mem(addr, nbytes)

    @property
    def memory_region(self) -> tuple[int, int]:
        """(base, size) of the DDR model's memory, bytes."""
        return self.sim.memory_region
