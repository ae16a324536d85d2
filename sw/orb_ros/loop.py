# SPDX-License-Identifier: MIT
"""The ROS nodes' loop, without ROS (docs/ros.md, docs/ros2.md): FrameLoop waits for a frame,
writes the parameter changes and resets the services queued right after its frame-done interrupt,
reads the frame, publishes it, and keeps running through faults, counting them for the
diagnostics. The ROS 1 node (orb_ros.node.FeatureNode) and the ROS 2 node (orb_ros2.node) are
FrameLoops that say how to publish, log and stamp; numpy, the model and the driver only.

The loop reads frames from a NodeSource: a driver's frame source (orb_accel.driver.FrameSource)
whose `next_frame(timeout_s, at_frame_done)` runs a hook after the frame-done interrupt and before
the bank is read (where the node writes queued changes, so that on a live stream they land in the
vertical blanking: the hardware samples the parameters at a frame's first pixel), plus configure,
soft reset and what was written. AccelSource is the driver on a bus (UIO, /dev/mem, the
simulator's socket); RemoteSource the frames of an `orb-accel serve` on another machine
(orb_accel.remote.RemoteAccel), whose parameters the server sets (`takes_changes` False).
"""

from __future__ import annotations

import functools
import threading
import time
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from golden_model import limits, regs
from golden_model.config import MODES, ConfigError
from golden_model.frameparams import FrameParams
from orb_accel.bus import BusError
from orb_accel.driver import AccelError, FaultCounts, Frame, FrameSource, HwConfig, OrbAccel

from .msgs import fields

NODE_NAME = "orb_accel"
# the accelerator's counters whose rise is a fault (FRAME_COUNT and DISCARDED are not)
HW_FAULTS = ("dropped", "overflow_count", "overrun", "proto_errors", "desc_lost")
NODE_FAULTS = ("bus_errors", "stale_banks", "stray_irqs", "errors", "frames_missed")
FRAME_MASK = 0xFFFF  # frame numbers are 16 bits
MAX_BACKOFF_S = 1.0  # the longest pause between tries while the bus keeps answering with errors


# the numpy type of each array type of the message definitions (orb_accel_msgs/msg/*.msg)
ARRAY_DTYPES = {"float32[]": np.float32, "int32[]": np.int32, "uint16[]": np.uint16, "uint8[]": np.uint8}


@functools.cache
def _array_types() -> dict[str, str]:
    """Features.msg's arrays, name -> type (read once)."""
    return {name: t for name, t in fields("Features").items() if t.endswith("[]")}


def feature_arrays(frame: Frame) -> dict[str, np.ndarray]:
    """The Features message's per-feature arrays of a frame, each in its field's type (from the
    definition): cv2.KeyPoint's fields (Frame.keypoint_arrays), the positions in the scale's
    pixels, the descriptors (N x 32 bytes, flat), the corner response codes and the low flags."""
    k = frame.keypoint_arrays()
    values = {**k, "scale_x": frame.scale_x, "scale_y": frame.scale_y, "descriptors": frame.descriptors,
              "corner_response": frame.response, "low": frame.low}  # fmt: skip
    types = _array_types()
    if set(types) != set(values):
        raise RuntimeError(f"Features.msg's arrays {sorted(types)} are not the node's {sorted(values)}")
    return {name: np.ascontiguousarray(values[name], dtype=ARRAY_DTYPES[t]).reshape(-1) for name, t in types.items()}


def frame_fields(frame: Frame, assumed: FrameParams | None = None) -> dict[str, int | str]:
    """The Features message's other fields (but the header) of a frame, labelled with the
    parameters its end-of-frame record says it was processed with (Frame.params); `assumed`, the
    parameters written before the frame started, labels a frame of an accelerator whose records
    carry none (a register map before 3.1)."""
    hw = frame.hw
    assert hw is not None, "a frame read by OrbAccel.read_bank carries its configuration"
    p = frame.params or assumed
    if p is None:
        raise ValueError("the frame's record carries no parameters and none were assumed")
    c = frame.counters
    return {
        "width": hw.width, "height": hw.height, "frame": frame.number, "threshold": p.threshold, "mode": frame.mode,
        "scales": hw.scales, "sectors": hw.sectors, "step_num": hw.step_num, "step_den": hw.step_den,
        "budget": p.budget if p.selection == "grid" else 0, "selection": p.selection,
        "threshold_lo": p.threshold_lo, "cols": p.cols, "rows": p.rows,
        "dropped": frame.dropped, "truncated": frame.truncated,
        "frames_total": c.get("frame_count", 0), "dropped_total": c.get("dropped", 0),
        "overflow_total": c.get("overflow_count", 0), "overrun_total": c.get("overrun", 0),
        "protocol_errors_total": c.get("proto_errors", 0), "desc_lost_total": c.get("desc_lost", 0),
        "discarded_total": c.get("discarded", 0),
    }  # fmt: skip


@dataclass(frozen=True)
class Params:
    threshold: int = 20
    mode: str = "orb"
    enable: bool = True


def check_params(threshold: object, mode: object, enable: object) -> str | None:
    """None when legal, else a sentence naming the allowed values."""
    if (
        isinstance(threshold, bool)
        or not isinstance(threshold, (int, np.integer))
        or not limits.THRESHOLD.legal(int(threshold))
    ):
        return f"threshold must be an integer {limits.THRESHOLD.text}, got {threshold!r}"
    if mode not in MODES:
        return f"mode must be one of {', '.join(MODES)}, got {mode!r}"
    if not isinstance(enable, (bool, np.bool_)):
        return f"enable must be true or false, got {enable!r}"
    return None


class NodeSource(Protocol):
    """Where the loop's frames come from (AccelSource: the driver on a bus; RemoteSource: a stream)."""

    hw: HwConfig
    faults: FaultCounts
    released_at_open: list[int]
    takes_changes: bool  # False: configure and soft_reset are not this node's to call (the server's)

    def next_frame(self, timeout_s: float, at_frame_done: Callable[[], None]) -> Frame: ...

    def configure(self, params: Params, budget: int) -> None: ...

    def soft_reset(self) -> None: ...

    def written(self) -> FrameParams: ...


class AccelSource:
    """The driver (OrbAccel) as a FrameSource: wait for the frame-done interrupt, run the hook, read
    the bank, release it (also when the hook or the read fails)."""

    takes_changes = True

    def __init__(self, accel: OrbAccel) -> None:
        self.accel = accel
        self.hw, self.faults, self.released_at_open = accel.hw, accel.faults, accel.released_at_open

    def next_frame(self, timeout_s: float, at_frame_done: Callable[[], None]) -> Frame:
        bank = self.accel.wait_frame(timeout_s)
        with self.accel.holding(bank):
            before = self.accel.written()  # an old map's frame is decoded in the mode of its start
            at_frame_done()
            return self.accel.read_bank(bank, mode=None if self.accel.records_params else before.mode)

    def configure(self, params: Params, budget: int) -> None:
        """The parameters and the selection (grid with `budget`, 0: every feature)."""
        self.accel.configure(params.threshold, params.mode, params.enable, selection="grid" if budget else "all",
                             budget=budget or None)  # fmt: skip

    def soft_reset(self) -> None:
        self.accel.soft_reset()

    def written(self) -> FrameParams:
        return self.accel.written()

    def start(self) -> None:
        """A clean start: frame numbers from 0, the frame in flight (older values) cut, stale
        interrupts acknowledged."""
        self.accel.soft_reset()
        self.accel.write(regs.IRQ_STATUS, 0xFFFFFFFF)


class RemoteSource:
    """The frames of an `orb-accel serve` (orb_accel.remote.RemoteAccel, or anything with the driver's
    FrameSource interface) as a NodeSource: the hook runs once a frame has come; the accelerator's
    parameters are the server's (set there: `orb-accel serve --threshold ...`), so a node refuses
    changes and resets, and every frame is labelled with its own record's parameters."""

    takes_changes = False

    def __init__(self, remote: FrameSource, what: str) -> None:
        self.remote, self.what = remote, what
        self.hw, self.faults, self.released_at_open = remote.hw, FaultCounts(), []
        self._params: FrameParams | None = None

    def next_frame(self, timeout_s: float, at_frame_done: Callable[[], None]) -> Frame:
        frame = self.remote.next_frame(timeout_s)
        self._params = frame.params
        at_frame_done()
        return frame

    def refusal(self) -> str:
        return f"the frames come from {self.what}, which sets the accelerator's parameters: change them there"

    def configure(self, params: Params, budget: int) -> None:
        raise ValueError(self.refusal())

    def soft_reset(self) -> None:
        raise ValueError(self.refusal())

    def written(self) -> FrameParams:
        if self._params is None:
            raise ValueError(f"{self.what}'s frame carries no parameters (a register map before 3.1)")
        return self._params


@dataclass
class Request:
    """A change queued by a service or a parameter callback for the loop: new parameters, or a soft reset."""

    params: Params | None = None
    reset: bool = False
    done: threading.Event = field(default_factory=threading.Event)
    success: bool = False
    message: str = ""
    after_frame: int = 0


@dataclass(frozen=True)
class Report:
    """One diagnostics report: WARN or OK, one line, the values (strings)."""

    warn: bool
    message: str
    values: dict[str, str]


class FrameLoop(ABC):
    """The loop, its queue of changes and its fault bookkeeping; a subclass publishes (publish,
    publish_report), stamps (now) and logs (logwarn, loginfo)."""

    def __init__(self, source: NodeSource, params: Params, timeout_s: float, diag_period_s: float = 1.0,
                 service_timeout_s: float = 600.0, budget: int | None = None) -> None:  # fmt: skip
        self.source = source
        self.params, self.timeout_s = params, timeout_s
        # the accelerator's selection (docs/selection.md): the grid with this budget (None: the
        # recommended one of the frame size), 0: every feature (selection all)
        self.budget = source.hw.default_budget() if budget is None else int(budget)
        if not 0 <= self.budget <= source.hw.capacity:
            cap = source.hw.capacity
            raise ConfigError(f"budget {self.budget}: a bank of this accelerator holds 0..{cap} features")
        self.diag_period_s, self.service_timeout_s = diag_period_s, service_timeout_s
        self.lock = threading.Lock()
        self.requests: list[Request] = []
        self.last_frame = 0
        self.published = 0
        self.timeouts = 0
        self.last_counters: dict[str, int] = {}
        # faults (docs/ros.md, "Faults and recovery")
        self.stalls = 0  # episodes without frames (each starts with a timeout while enabled)
        self.stalled_since: float | None = None  # monotonic time of the last frame before the stall in progress
        self.errors = 0  # inconsistent answers (AccelError) the loop recovered from
        self.frames_missed = 0  # frame numbers skipped between two published frames (lost anywhere)
        self.last_error = ""
        self._next_number: int | None = None  # the frame number expected next (None: unknown, after a reset)
        self._last_frame_t = time.monotonic()
        self._backoff_s = 0.0
        self._diag_base: dict[str, int] = {}
        self._stats = {"t": time.monotonic(), "published": 0, "features": 0}
        self._next_diag = time.monotonic() + diag_period_s

    def start(self) -> None:
        """Take the accelerator: say which banks a killed predecessor left held (the driver released
        them), a clean start (AccelSource.start), the parameters written."""
        if self.source.released_at_open:
            self.logwarn(f"{NODE_NAME}: released bank(s) {self.source.released_at_open} a previous process left held")
        if not self.source.takes_changes:  # the server's parameters
            return
        start = getattr(self.source, "start", None)
        if start is not None:
            start()
        self.source.configure(self.params, self.budget)

    # ---- what a ROS binding provides ----------------------------------------------------------
    @abstractmethod
    def now(self) -> object:
        """The binding's time stamp for a frame's message."""

    @abstractmethod
    def publish(self, frame: Frame, stamp: object, assumed: FrameParams) -> None:
        """Publish one frame's message."""

    @abstractmethod
    def publish_report(self, report: Report) -> None:
        """Publish the diagnostics of a report."""

    @abstractmethod
    def logwarn(self, text: str) -> None:
        """Log a warning through the binding's logger."""

    @abstractmethod
    def loginfo(self, text: str) -> None:
        """Log information through the binding's logger."""

    # ---- changes (called from the bindings' service threads): queue, wait until written -------
    def queued_params(self) -> Params:
        """The parameters the node will have once the queue is written (a change builds on them)."""
        with self.lock:
            queued = [r.params for r in self.requests if r.params is not None]
        return queued[-1] if queued else self.params

    def submit(self, request: Request) -> Request:
        """Queue a change and wait until the loop has written it (at most service_timeout_s)."""
        with self.lock:
            self.requests.append(request)
        if not request.done.wait(self.service_timeout_s):
            with self.lock:
                if request in self.requests:
                    self.requests.remove(request)
                    request.message = f"not applied: no frame boundary within {self.service_timeout_s:g} s"
                    request.done.set()
            request.done.wait()
        return request

    def _take(self) -> list[Request]:
        with self.lock:
            taken, self.requests = self.requests, []
        return taken

    def _apply_params(self, requests: list[Request]) -> Params:
        """Write the newest queued parameters (the frame in flight keeps the old ones)."""
        new = [r.params for r in requests if r.params is not None]
        if new and new[-1] != self.params:
            p = new[-1]
            self.source.configure(p, self.budget)
            self.params = p
        return self.params

    def _finish(self, requests: list[Request], after_frame: int) -> None:
        for r in requests:
            r.success, r.after_frame = True, after_frame
            if r.reset:
                r.message = f"soft reset after frame {after_frame}: frame numbers and counters restart at 0"
            else:
                p = r.params
                assert p is not None
                r.message = (f"threshold {p.threshold}, mode {p.mode}, enable {str(p.enable).lower()}: "
                             f"applied from the first frame after frame {after_frame}")  # fmt: skip
            r.done.set()

    # ---- the loop ------------------------------------------------------------------------------
    def step(self) -> Frame | None:
        """Wait for one frame and publish it (None after a timeout or a fault). Queued changes are
        written. A bus error or an inconsistent answer is counted and logged, and the loop goes on:
        the driver releases any bank it left held before the next wait."""
        requests: list[Request] = []
        done: list[Request] = []  # requests whose change is written
        got: dict[str, object] = {}

        def at_frame_done() -> None:  # right after the interrupt: from the next frame on
            got["stamp"], got["assumed"] = self.now(), self.source.written()  # before this frame started
            requests[:] = self._take()
            self._apply_params(requests)
            done[:] = [r for r in requests if not r.reset]

        try:
            try:
                frame = self.source.next_frame(self.timeout_s, at_frame_done)
            except TimeoutError:
                self._no_frame()
                requests[:] = self._take()  # no frame in flight that could see half of a change
                self._apply(requests, done, self.last_frame)
                self._diagnostics(force=False)
                return None
            self._apply(requests, done, frame.number)
        except (BusError, AccelError) as exc:
            self._fault(exc, requests, done)
            return None
        self._frame_came(frame)
        assumed = got["assumed"]
        assert isinstance(assumed, FrameParams)
        self.publish(frame, got["stamp"], assumed)
        self.published += 1
        self._stats["published"] += 1
        self._stats["features"] += len(frame)
        self.last_counters = frame.counters
        self._diagnostics(force=False)
        return frame

    def _apply(self, requests: list[Request], done: list[Request], after_frame: int) -> None:
        """Write the queued changes not yet written (the parameters, then a reset) and answer them."""
        if not requests:
            return
        if not done:
            self._apply_params(requests)
            done[:] = [r for r in requests if not r.reset]
        if any(r.reset for r in requests):
            self.source.soft_reset()
            self._next_number = None
            done[:] = requests
        self._finish(requests, after_frame)

    def _fault(self, exc: Exception, requests: list[Request], done: list[Request]) -> None:
        """A bus error (counted by the driver) or an inconsistent answer: log it, give the changes
        not yet written back to the queue, answer those written, pause a little if it repeats."""
        if isinstance(exc, AccelError):
            self.errors += 1
        self.last_error = str(exc)
        self.logwarn(f"{NODE_NAME}: {exc} (frames go on; docs/ros.md, Faults and recovery)")
        self._finish(done, self.last_frame)  # written: every frame published from now on has it
        left = [r for r in requests if r not in done]
        if left:
            with self.lock:
                self.requests[:0] = left
        self._diagnostics(force=self._backoff_s == 0.0)
        self._backoff_s = min(max(2 * self._backoff_s, 0.01), MAX_BACKOFF_S)
        time.sleep(self._backoff_s)  # a bus that fails every operation is not polled flat out

    def _no_frame(self) -> None:
        self.timeouts += 1
        self._backoff_s = 0.0
        if not self.params.enable:  # disabled: no frame is expected
            self.stalled_since = None
        elif self.stalled_since is None:
            self.stalled_since = self._last_frame_t
            self.stalls += 1
            self.logwarn(f"{NODE_NAME}: no frame within {self.timeout_s:g} s (no video, or the interrupt is lost); "
                         "waiting for frames")  # fmt: skip
            self._diagnostics(force=True)

    def _frame_came(self, frame: Frame) -> None:
        now = time.monotonic()
        self._backoff_s = 0.0
        if self._next_number is not None:
            self.frames_missed += (frame.number - self._next_number) & FRAME_MASK
        self._next_number = (frame.number + 1) & FRAME_MASK
        self.last_frame = frame.number
        self._last_frame_t = now
        if self.stalled_since is not None:
            self.loginfo(f"{NODE_NAME}: frames again (frame {frame.number}) after "
                         f"{now - self.stalled_since:.1f} s without")  # fmt: skip
            self.stalled_since = None
            self._next_diag = now  # report the recovery with this frame

    def shutdown(self) -> None:
        """Answer any waiting service call (the loop has stopped)."""
        for r in self._take():
            r.message = "the node is shutting down"
            r.done.set()

    # ---- diagnostics ---------------------------------------------------------------------------
    def fault_counts(self) -> dict[str, int]:
        """The counters whose rise is a fault: the accelerator's (read with the last frame), the
        driver's and the node's."""
        c, f = self.last_counters, self.source.faults
        return {**{k: c.get(k, 0) for k in HW_FAULTS}, "bus_errors": f.bus_errors, "stale_banks": f.stale_banks,
                "stray_irqs": f.stray_irqs, "errors": self.errors, "frames_missed": self.frames_missed}  # fmt: skip

    def _diagnostics(self, force: bool) -> None:
        now = time.monotonic()
        if not force and now < self._next_diag:
            return
        span = max(now - self._stats["t"], 1e-9)
        fps = self._stats["published"] / span
        per_frame = self._stats["features"] / max(self._stats["published"], 1)
        faults = self.fault_counts()
        # WARN for a rise since the previous report (a counter that falls restarted: a reset)
        rose = {k: v - self._diag_base.get(k, 0) for k, v in faults.items() if v > self._diag_base.get(k, 0)}
        problems = []
        if self.stalled_since is not None:
            problems.append(f"no frame for {now - self.stalled_since:.1f} s (no video, or the interrupt is lost)")
        elif self.published == 0 and self.timeouts:
            problems.append("no frames")
        if rose:
            problems.append("since the last report " + ", ".join(f"{k} +{v}" for k, v in rose.items()))
        p = self.params
        values = {"frames_per_second": f"{fps:.2f}", "features_per_frame": f"{per_frame:.1f}",
                  "published": self.published, "timeouts": self.timeouts, "last_frame": self.last_frame,
                  "threshold": p.threshold, "mode": p.mode, "enable": str(p.enable).lower(), **self.last_counters,
                  "stalls": self.stalls, "stalled": str(self.stalled_since is not None).lower(),
                  **{k: faults[k] for k in NODE_FAULTS}, "last_error": self.last_error}  # fmt: skip
        message = f"{fps:.1f} fps, {per_frame:.0f} features per frame" + "".join(f"; {t}" for t in problems)
        self.publish_report(Report(bool(problems), message, {str(k): str(v) for k, v in values.items()}))
        self._diag_base = faults
        self._stats = {"t": now, "published": 0, "features": 0}
        self._next_diag = now + self.diag_period_s
