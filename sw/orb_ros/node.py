# SPDX-License-Identifier: MIT
"""The ROS 1 node of the accelerator (docs/ros.md): one orb_accel_msgs/Features message per frame
on ~features (/orb_accel/features), parameters, a reset service and diagnostics.

The node owns the bus: one loop waits for the frame-done interrupt, stamps the frame, applies the
parameter changes that services queued (written right after the interrupt, so that on a live
stream they land in the vertical blanking and the next frame to start is the first one to use
them; the hardware samples threshold and mode at a frame's first pixel), reads the bank, releases
it, publishes. A service call returns once its change is written, with the number of the last
frame published under the old values (`after_frame`). Runs on the board (UioBus) and against the
simulator (SocketBus) unchanged; needs numpy and Debian's ROS packages only.

Faults (docs/ros.md, "Faults and recovery"): the loop keeps running through a stall (no frame
within the timeout: a cable cut, the video or the interrupt lost), error responses of the bus and
inconsistent answers; it counts them, says so in the log and in /diagnostics (WARN while a stall
lasts or when a fault counter rose since the previous report, OK again once frames flow), and the
driver releases what a fault left held.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from types import ModuleType

import numpy as np

from golden_model import limits, regs
from golden_model.config import MODES, ConfigError
from golden_model.frameparams import FrameParams
from orb_accel.bus import Bus, BusError
from orb_accel.driver import AccelError, Frame, OrbAccel

NODE_NAME = "orb_accel"
KEEP_THRESHOLD, KEEP_MODE, KEEP_ENABLE = -1, "", -1
FLOAT_FIELDS = ("x", "y", "size", "angle", "response")
# the accelerator's counters whose rise is a fault (FRAME_COUNT and DISCARDED are not)
HW_FAULTS = ("dropped", "overflow_count", "overrun", "proto_errors", "desc_lost")
NODE_FAULTS = ("bus_errors", "stale_banks", "stray_irqs", "errors", "frames_missed")
FRAME_MASK = 0xFFFF  # frame numbers are 16 bits
MAX_BACKOFF_S = 1.0  # the longest pause between tries while the bus keeps answering with errors


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


class WireArray(np.ndarray):
    """A numpy array as rospy.numpy_msg serialises it: genpy's generated serialize_numpy calls
    `tostring()`, which numpy 2 removed (numpy 1.x deprecates it); here it is `tobytes()`."""

    def tostring(self) -> bytes:
        return self.tobytes()


def _wire(values: np.ndarray, dtype: type) -> WireArray:
    return np.ascontiguousarray(values, dtype=dtype).view(WireArray)


def message_arrays(frame: Frame) -> dict[str, np.ndarray | bytes]:
    """The Features message's per-feature arrays of a frame (numpy, the message's types)."""
    k = frame.keypoint_arrays()
    arrays: dict[str, np.ndarray | bytes] = {name: _wire(k[name], np.float32) for name in FLOAT_FIELDS}
    arrays["octave"] = _wire(k["octave"], np.int32)
    arrays["scale_x"] = _wire(frame.scale_x, np.uint16)
    arrays["scale_y"] = _wire(frame.scale_y, np.uint16)
    arrays["descriptors"] = np.ascontiguousarray(frame.descriptors, dtype=np.uint8).tobytes()
    arrays["corner_response"] = np.ascontiguousarray(frame.response, dtype=np.uint8).tobytes()
    arrays["low"] = np.ascontiguousarray(frame.low, dtype=np.uint8).tobytes()
    return arrays


def build_message(msg_cls: type, frame: Frame, stamp: object, frame_id: str,
                  assumed: FrameParams | None = None) -> object:  # fmt: skip
    """An orb_accel_msgs/Features message (`msg_cls`: the generated class, or its numpy_msg form)
    of a frame, labelled with the parameters its end-of-frame record says it was processed with
    (Frame.params); `assumed`, the parameters written before the frame started, labels a frame of
    an accelerator whose records carry none (a register map before 3.1)."""
    hw = frame.hw
    assert hw is not None, "a frame read by OrbAccel.read_bank carries its configuration"
    p = frame.params or assumed
    if p is None:
        raise ValueError("the frame's record carries no parameters and none were assumed")
    msg = msg_cls(**message_arrays(frame))
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.width, msg.height, msg.frame = hw.width, hw.height, frame.number
    msg.threshold, msg.mode, msg.scales, msg.sectors = p.threshold, frame.mode, hw.scales, hw.sectors
    msg.step_num, msg.step_den = hw.step_num, hw.step_den
    msg.budget = p.budget if p.selection == "grid" else 0
    msg.selection, msg.threshold_lo, msg.cols, msg.rows = p.selection, p.threshold_lo, p.cols, p.rows
    msg.dropped, msg.truncated = frame.dropped, frame.truncated
    c = frame.counters
    msg.frames_total, msg.dropped_total = c.get("frame_count", 0), c.get("dropped", 0)
    msg.overflow_total, msg.overrun_total = c.get("overflow_count", 0), c.get("overrun", 0)
    msg.protocol_errors_total, msg.desc_lost_total = c.get("proto_errors", 0), c.get("desc_lost", 0)
    msg.discarded_total = c.get("discarded", 0)
    return msg


@dataclass
class Request:
    """A change queued by a service for the loop: new parameters, or a soft reset."""

    params: Params | None = None
    reset: bool = False
    done: threading.Event = field(default_factory=threading.Event)
    success: bool = False
    message: str = ""
    after_frame: int = 0


class FeatureNode:
    """The node's loop and services (rospy initialised by the caller)."""

    def __init__(self, rospy: ModuleType, msgs: ModuleType, srvs: ModuleType, accel: OrbAccel, params: Params,
                 frame_id: str, timeout_s: float, diag_period_s: float = 1.0, hardware_id: str = "orb-accel",
                 service_timeout_s: float = 600.0, budget: int | None = None) -> None:  # fmt: skip
        from diagnostic_msgs.msg import DiagnosticArray  # Debian's python3-diagnostic-msgs
        from rospy.numpy_msg import numpy_msg
        from std_srvs.srv import Trigger, TriggerResponse

        self.rospy, self.srvs, self.accel = rospy, srvs, accel
        self.params, self.frame_id, self.timeout_s = params, frame_id, timeout_s
        # the accelerator's selection (docs/selection.md): the grid with this budget (None: the
        # recommended one of the frame size), 0: every feature (selection all)
        self.budget = accel.hw.default_budget() if budget is None else int(budget)
        if not 0 <= self.budget <= accel.hw.capacity:
            raise ConfigError(f"budget {self.budget}: a bank of this accelerator holds 0..{accel.hw.capacity} features")
        self.selection = {"selection": "grid" if self.budget else "all", "budget": self.budget or None}
        self.diag_period_s, self.hardware_id, self.service_timeout_s = diag_period_s, hardware_id, service_timeout_s
        self._trigger_response = TriggerResponse
        self._diag_array = DiagnosticArray
        self.msg_cls = numpy_msg(msgs.Features)
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
        self.pub = rospy.Publisher("~features", self.msg_cls, queue_size=16)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=4)
        self._stats = {"t": time.monotonic(), "published": 0, "features": 0}
        self._next_diag = time.monotonic() + diag_period_s
        if accel.released_at_open:  # the driver found banks a killed predecessor held, and released them
            rospy.logwarn(f"{NODE_NAME}: released bank(s) {accel.released_at_open} a previous process left held")
        accel.soft_reset()  # a clean start: frame numbers from 0, the frame in flight (older values) cut
        accel.write(regs.IRQ_STATUS, 0xFFFFFFFF)
        accel.configure(params.threshold, params.mode, params.enable, **self.selection)
        rospy.Service("~set_params", srvs.SetParams, self._on_set_params)
        rospy.Service("~reset", Trigger, self._on_reset)

    # ---- services (rospy's threads): queue, wait until the loop has written the change ---------
    def _submit(self, request: Request) -> Request:
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

    def _on_set_params(self, req: object) -> object:
        p = self.params
        with self.lock:
            queued = [r.params for r in self.requests if r.params is not None]
        base = queued[-1] if queued else p
        threshold = base.threshold if req.threshold == KEEP_THRESHOLD else int(req.threshold)  # type: ignore[attr-defined]
        mode = base.mode if req.mode == KEEP_MODE else req.mode  # type: ignore[attr-defined]
        if req.enable not in (KEEP_ENABLE, 0, 1):  # type: ignore[attr-defined]
            return self.srvs.SetParamsResponse(False, f"enable must be 1, 0 or -1 (keep), got {req.enable}", 0)  # type: ignore[attr-defined]
        enable = base.enable if req.enable == KEEP_ENABLE else bool(req.enable)  # type: ignore[attr-defined]
        error = check_params(threshold, mode, enable)
        if error is not None:
            self.rospy.logwarn(f"set_params refused: {error}")
            return self.srvs.SetParamsResponse(False, error, self.last_frame)
        r = self._submit(Request(params=Params(threshold, mode, enable)))
        return self.srvs.SetParamsResponse(r.success, r.message, r.after_frame)

    def _on_reset(self, _req: object) -> object:
        r = self._submit(Request(reset=True))
        return self._trigger_response(r.success, r.message)

    def _take(self) -> list[Request]:
        with self.lock:
            taken, self.requests = self.requests, []
        return taken

    def _apply_params(self, requests: list[Request]) -> Params:
        """Write the newest queued parameters (the frame in flight keeps the old ones)."""
        new = [r.params for r in requests if r.params is not None]
        if new and new[-1] != self.params:
            p = new[-1]
            self.accel.configure(p.threshold, p.mode, p.enable, **self.selection)
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
        try:
            try:
                bank = self.accel.wait_frame(self.timeout_s)
            except TimeoutError:
                self._no_frame()
                requests = self._take()  # no frame in flight that could see half of a change
                self._apply(requests, done, self.last_frame)
                self._diagnostics(force=False)
                return None
            with self.accel.holding(bank):  # released on the way out, also when a write below fails
                stamp = self.rospy.Time.now()
                assumed = self.accel.written()  # before this frame started (if the write made the blanking)
                requests = self._take()
                self._apply_params(requests)  # right after the interrupt: from the next frame on
                done = [r for r in requests if not r.reset]
                # decoded and labelled as its record says (an old map: as written before it started)
                frame = self.accel.read_bank(bank, mode=None if self.accel.records_params else assumed.mode)
            self._apply(requests, done, frame.number)
        except (BusError, AccelError) as exc:
            self._fault(exc, requests, done)
            return None
        self._frame_came(frame)
        self.pub.publish(build_message(self.msg_cls, frame, stamp, self.frame_id, assumed))
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
            self.accel.soft_reset()
            self._next_number = None
            done[:] = requests
        self._finish(requests, after_frame)

    def _fault(self, exc: Exception, requests: list[Request], done: list[Request]) -> None:
        """A bus error (counted by the driver) or an inconsistent answer: log it, give the changes
        not yet written back to the queue, answer those written, pause a little if it repeats."""
        if isinstance(exc, AccelError):
            self.errors += 1
        self.last_error = str(exc)
        self.rospy.logwarn(f"{NODE_NAME}: {exc} (frames go on; docs/ros.md, Faults and recovery)")
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
            self.rospy.logwarn(f"{NODE_NAME}: no frame within {self.timeout_s:g} s (no video, or the interrupt is "
                               "lost); waiting for frames")  # fmt: skip
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
            self.rospy.loginfo(f"{NODE_NAME}: frames again (frame {frame.number}) after "
                               f"{now - self.stalled_since:.1f} s without")  # fmt: skip
            self.stalled_since = None
            self._next_diag = now  # report the recovery with this frame

    def run(self) -> None:
        while not self.rospy.is_shutdown():
            self.step()

    def shutdown(self) -> None:
        """Answer any waiting service call (the loop has stopped)."""
        for r in self._take():
            r.message = "the node is shutting down"
            r.done.set()

    # ---- diagnostics ---------------------------------------------------------------------------
    def fault_counts(self) -> dict[str, int]:
        """The counters whose rise is a fault: the accelerator's (read with the last frame), the
        driver's and the node's."""
        c, f = self.last_counters, self.accel.faults
        return {**{k: c.get(k, 0) for k in HW_FAULTS}, "bus_errors": f.bus_errors, "stale_banks": f.stale_banks,
                "stray_irqs": f.stray_irqs, "errors": self.errors, "frames_missed": self.frames_missed}  # fmt: skip

    def _diagnostics(self, force: bool) -> None:
        now = time.monotonic()
        if not force and now < self._next_diag:
            return
        from diagnostic_msgs.msg import DiagnosticStatus, KeyValue

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
        level = DiagnosticStatus.WARN if problems else DiagnosticStatus.OK
        p = self.params
        values = {"frames_per_second": f"{fps:.2f}", "features_per_frame": f"{per_frame:.1f}",
                  "published": self.published, "timeouts": self.timeouts, "last_frame": self.last_frame,
                  "threshold": p.threshold, "mode": p.mode, "enable": str(p.enable).lower(), **self.last_counters,
                  "stalls": self.stalls, "stalled": str(self.stalled_since is not None).lower(),
                  **{k: faults[k] for k in NODE_FAULTS}, "last_error": self.last_error}  # fmt: skip
        status = DiagnosticStatus(
            level=level, name=f"{NODE_NAME}: accelerator", hardware_id=self.hardware_id,
            message=f"{fps:.1f} fps, {per_frame:.0f} features per frame" + "".join(f"; {t}" for t in problems),
            values=[KeyValue(str(k), str(v)) for k, v in values.items()],
        )  # fmt: skip
        arr = self._diag_array()
        arr.header.stamp = self.rospy.Time.now()
        arr.status = [status]
        self.diag_pub.publish(arr)
        self._diag_base = faults
        self._stats = {"t": now, "published": 0, "features": 0}
        self._next_diag = now + self.diag_period_s


@dataclass(frozen=True)
class Settings:
    """The node's start-up parameters (private: ~threshold, ~mode, ~enable, ~frame_id, ~timeout,
    ~diagnostics_period, ~budget); timeout_s None: the caller's default for its bus; budget None:
    the recommended one (HwConfig.default_budget), 0: every feature."""

    params: Params
    frame_id: str = "orb_accel"
    timeout_s: float | None = None
    diag_period_s: float = 1.0
    budget: int | None = None


def init_node(rospy: ModuleType, defaults: Params, argv: list[str] | None = None) -> Settings:
    """Initialise rospy as node `orb_accel` and read its private parameters; ValueError (after a
    logfatal) for an illegal one, before any bus is opened."""
    rospy.init_node(NODE_NAME, argv=argv, disable_signals=True)
    threshold = rospy.get_param("~threshold", defaults.threshold)
    mode = rospy.get_param("~mode", defaults.mode)
    enable = rospy.get_param("~enable", defaults.enable)
    error = check_params(threshold, mode, enable)
    timeout = rospy.get_param("~timeout", None)
    period = rospy.get_param("~diagnostics_period", 1.0)
    for name, value in (("timeout", timeout), ("diagnostics_period", period)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0):
            error = error or f"{name} must be a positive number of seconds, got {value!r}"
    budget = rospy.get_param("~budget", None)
    if budget is not None and (isinstance(budget, bool) or not isinstance(budget, int) or budget < 0):
        error = error or f"budget must be a non-negative integer (0: every feature), got {budget!r}"
    if error is not None:
        rospy.logfatal(f"illegal start-up parameter: {error}")
        rospy.signal_shutdown("illegal parameter")
        raise ValueError(error)
    frame_id = str(rospy.get_param("~frame_id", "orb_accel"))
    return Settings(Params(int(threshold), mode, bool(enable)), frame_id,
                    None if timeout is None else float(timeout), float(period),
                    None if budget is None else int(budget))  # fmt: skip


def run_node(rospy: ModuleType, msgs: ModuleType, srvs: ModuleType, bus: Bus, settings: Settings,
             default_timeout_s: float, hardware_id: str) -> int:  # fmt: skip
    """Run the initialised node on `bus` until it is shut down."""
    accel = OrbAccel(bus)
    timeout_s = settings.timeout_s or default_timeout_s
    node = FeatureNode(rospy, msgs, srvs, accel, settings.params, settings.frame_id, timeout_s,
                       settings.diag_period_s, hardware_id, budget=settings.budget)  # fmt: skip
    hw, p = accel.hw, settings.params
    rospy.loginfo(f"{NODE_NAME}: {hw.width}x{hw.height}, {hw.scales} scales of {hw.step_num}:{hw.step_den}, "
                  f"{hw.sectors} sectors; threshold "
                  f"{p.threshold}, mode {p.mode}; frame timeout {timeout_s:g} s; publishing on "
                  f"{rospy.resolve_name('~features')}")  # fmt: skip
    try:
        node.run()
    except KeyboardInterrupt:  # SIGINT or SIGTERM: the usual way to stop a node
        rospy.loginfo(f"{NODE_NAME}: interrupted after {node.published} frames, shutting down")
    finally:
        node.shutdown()
        rospy.signal_shutdown("done")
    return 0
