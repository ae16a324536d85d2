# SPDX-License-Identifier: MIT
"""Reference models of hdl/input/orb_video_check.vhd: which pixels come out (the input's, padding
zeros), with which tuser/tlast, which frames end bad with which faults, and the counters.

VideoCheckModel (IDLE_TIMEOUT_g = 0, a source that can wait) works at beat level: it takes the
beats the checker accepts, in order (a source that honours tready loses nothing, so timing does not
change the result), and `reset()` between beats (the checker idle: no padding under way).
LiveVideoCheckModel (IDLE_TIMEOUT_g > 0, a live source) works clock by clock, since there timing
decides: tready stays high, a pixel arriving while a frame is padded is discarded, and an open
frame idle for IDLE_TIMEOUT_g clocks is padded at once. Output tuser/tlast follow the checker's own
position in a WIDTH x HEIGHT frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

SHORT_LINE = 1  # frame_fault bit 0: tlast before x = WIDTH - 1
LONG_LINE = 2  # bit 1: no tlast at x = WIDTH - 1
FEW_LINES = 4  # bit 2: tuser at a line start before the frame is complete
EARLY_SOF = 8  # bit 3: tuser in mid-line
IDLE = 16  # bit 4: the open frame's input idle for IDLE_TIMEOUT_g clocks (live source only)


@dataclass(frozen=True)
class Beat:
    data: int
    user: int = 0
    last: int = 0


@dataclass(frozen=True)
class OutBeat:
    data: int
    user: int
    last: int
    pad: bool  # a padding pixel (not from the input)


@dataclass(frozen=True)
class FrameEnd:
    bad: bool
    faults: int
    beat: int  # index in `out` of the frame's last pixel (frame_end comes with it)


@dataclass
class VideoCheckModel:
    width: int
    height: int
    out: list[OutBeat] = field(default_factory=list)
    ends: list[FrameEnd] = field(default_factory=list)
    protocol_errors: int = 0
    discarded_pixels: int = 0
    _open: bool = False
    _x: int = 0
    _y: int = 0
    _faults: int = 0

    def reset(self) -> None:
        """rst: an open frame is abandoned without frame_end; the counters restart from 0."""
        self._open, self._x, self._y, self._faults = False, 0, 0, 0
        self.protocol_errors = 0
        self.discarded_pixels = 0

    def forget(self) -> None:
        """Drop the closed frames' output beats and ends, keeping the open frame's beats (a long run
        stays small): `out` then starts at the open frame's first beat, and later ends index it so."""
        keep = self._y * self.width + self._x if self._open else 0
        del self.out[: len(self.out) - keep]
        self.ends.clear()

    def feed(self, beats: list[Beat]) -> None:
        for b in beats:
            self.beat(b)

    def feed_arrays(self, data: np.ndarray, user: np.ndarray, last: np.ndarray) -> None:
        """beat() for every (data, user, last) of the arrays, in bulk where nothing can happen: the
        beats that carry an open frame on as expected (no tuser, tlast exactly at each line's end; the
        frame's last pixel goes through beat()) and the beats without tuser while no frame is open."""
        w, size, n, i = self.width, self.width * self.height, len(data), 0
        while i < n:
            if not self._open:
                run = int(np.argmax(user[i:] != 0)) if user[i:].any() else n - i
                self.discarded_pixels += run
                i += run
                if i == n:
                    break
            elif not self._faults:
                pos = self._y * w + self._x
                p = pos + np.arange(min(n - i, size - pos - 1))  # up to, not including, the frame's last pixel
                ok = (user[i : i + len(p)] == 0) & ((last[i : i + len(p)] != 0) == (p % w == w - 1))
                run = len(p) if ok.all() else int(np.argmin(ok))
                if run:
                    xs = (p[:run] % w).tolist()
                    self.out.extend(OutBeat(d, 0, int(x == w - 1), False)
                                    for d, x in zip(data[i : i + run].tolist(), xs, strict=True))  # fmt: skip
                    self._y, self._x = divmod(pos + run, w)
                    i += run
                    if i == n:
                        break
            self.beat(Beat(int(data[i]), int(user[i]), int(last[i])))
            i += 1

    def beat(self, b: Beat) -> None:
        if not self._open:
            if not b.user:
                self.discarded_pixels += 1
                return
            self._open, self._faults = True, 0
        elif b.user:
            # the next frame starts early: this one is padded and ends bad, then b opens the next
            self._faults |= FEW_LINES if self._x == 0 else EARLY_SOF
            self._pad()
            self.beat(b)
            return
        if b.last and self._x != self.width - 1:
            self._faults |= SHORT_LINE
        elif not b.last and self._x == self.width - 1:
            self._faults |= LONG_LINE
        self._emit(b.data, pad=False)
        if self._open and self._faults:
            self._pad()

    def _pad(self) -> None:
        while self._open:
            self._emit(0, pad=True)

    def _emit(self, data: int, pad: bool) -> None:
        x, y = self._x, self._y
        self.out.append(OutBeat(data, int(x == 0 and y == 0), int(x == self.width - 1), pad))
        if x == self.width - 1 and y == self.height - 1:
            self.ends.append(FrameEnd(bool(self._faults), self._faults, len(self.out) - 1))
            self.protocol_errors += bool(self._faults)
            self._open, self._x, self._y = False, 0, 0
        elif x == self.width - 1:
            self._x, self._y = 0, y + 1
        else:
            self._x = x + 1


@dataclass
class LiveVideoCheckModel:
    """The checker with IDLE_TIMEOUT_g = idle_timeout > 0, one call of `edge` per clock edge with the
    input pixel taken at that edge (tready is high but in reset and the edge after it) or None, or
    rst. A pixel emitted at edge k is on m_axis_video after edge k (`edges` holds k per `out` beat;
    a FrameEnd's `beat` indexes `out`)."""

    width: int
    height: int
    idle_timeout: int
    out: list[OutBeat] = field(default_factory=list)
    edges: list[int] = field(default_factory=list)
    ends: list[FrameEnd] = field(default_factory=list)
    protocol_errors: int = 0
    discarded_pixels: int = 0
    clock: int = 0
    _open: bool = False
    _padding: bool = False
    _x: int = 0
    _y: int = 0
    _faults: int = 0
    _idle: int = 0

    def __post_init__(self) -> None:
        if self.idle_timeout < 1:
            raise ValueError("LiveVideoCheckModel models IDLE_TIMEOUT_g > 0; VideoCheckModel models 0")

    def edge(self, beat: Beat | None, rst: bool = False) -> None:
        k, self.clock = self.clock, self.clock + 1
        if rst:
            self._open = self._padding = False
            self._x = self._y = self._idle = 0
            self.protocol_errors = self.discarded_pixels = 0
            return
        idle = False
        if self._padding:
            self._emit(0, True, k)
            self.discarded_pixels += beat is not None
        elif beat is not None:
            if not self._open:
                if beat.user:
                    self._open, self._faults = True, 0
                    self._pixel(beat, k)
                else:
                    self.discarded_pixels += 1
            elif beat.user:
                # the next frame starts before this one is complete: pad this one, its frame is lost
                self._faults |= FEW_LINES if self._x == 0 else EARLY_SOF
                self.discarded_pixels += 1
                self._padding = True
            else:
                self._pixel(beat, k)
        elif self._open:
            idle = True
            if self._idle == self.idle_timeout - 1:
                self._faults |= IDLE
                self._padding, idle = True, False
        self._idle = self._idle + 1 if idle else 0

    def _pixel(self, b: Beat, k: int) -> None:
        if b.last and self._x != self.width - 1:
            self._faults |= SHORT_LINE
        elif not b.last and self._x == self.width - 1:
            self._faults |= LONG_LINE
        self._emit(b.data, False, k)
        if self._open and self._faults:
            self._padding = True

    def _emit(self, data: int, pad: bool, k: int) -> None:
        x, y = self._x, self._y
        self.out.append(OutBeat(data, int(x == 0 and y == 0), int(x == self.width - 1), pad))
        self.edges.append(k)
        if x == self.width - 1 and y == self.height - 1:
            self.ends.append(FrameEnd(bool(self._faults), self._faults, len(self.out) - 1))
            self.protocol_errors += bool(self._faults)
            self._open = self._padding = False
            self._x, self._y = 0, 0
        elif x == self.width - 1:
            self._x, self._y = 0, y + 1
        else:
            self._x = x + 1


def lines_to_beats(lines: list[list[int]], sof: bool = True, last_tlast: bool = True) -> list[Beat]:
    """A frame as beats: tuser on the first pixel (if sof), tlast on every line's last pixel (on the
    final line only if last_tlast)."""
    beats = []
    for i, line in enumerate(lines):
        for j, v in enumerate(line):
            user = int(sof and i == 0 and j == 0)
            last = int(j == len(line) - 1 and (last_tlast or i < len(lines) - 1))
            beats.append(Beat(int(v), user, last))
    return beats
