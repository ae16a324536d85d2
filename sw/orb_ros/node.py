# SPDX-License-Identifier: MIT
"""The ROS 1 node of the accelerator (docs/ros.md): one orb_accel_msgs/Features message per frame
on ~features (/orb_accel/features), parameters, a reset service and diagnostics.

The node owns the bus: one loop (orb_ros.loop.FrameLoop, shared with the ROS 2 node) waits for
the frame-done interrupt, stamps the frame, applies the parameter changes that services queued
(written right after the interrupt, so that on a live stream they land in the vertical blanking
and the next frame to start is the first one to use them; the hardware samples threshold and mode
at a frame's first pixel), reads the bank, releases it, publishes. A service call returns once its
change is written, with the number of the last frame published under the old values
(`after_frame`). Runs on the board (UioBus) and against the simulator (SocketBus) unchanged; needs
numpy and Debian's ROS packages only.

Faults (docs/ros.md, "Faults and recovery"): the loop keeps running through a stall (no frame
within the timeout: a cable cut, the video or the interrupt lost), error responses of the bus and
inconsistent answers; it counts them, says so in the log and in /diagnostics (WARN while a stall
lasts or when a fault counter rose since the previous report, OK again once frames flow), and the
driver releases what a fault left held.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import ModuleType

import numpy as np

from golden_model.frameparams import FrameParams
from orb_accel.bus import Bus
from orb_accel.ddr import FrameMemory, MemoryFactory
from orb_accel.driver import Frame, OrbAccel

from .loop import NODE_NAME, AccelSource, FrameLoop, Params, Report, Request, check_params, feature_arrays, frame_fields

__all__ = ["NODE_NAME", "FeatureNode", "Params", "Settings", "build_message", "check_params", "init_node",
           "message_arrays", "run_node"]  # fmt: skip

KEEP_THRESHOLD, KEEP_MODE, KEEP_ENABLE = -1, "", -1


class WireArray(np.ndarray):
    """A numpy array as rospy.numpy_msg serialises it: genpy's generated serialize_numpy calls
    `tostring()`, which numpy 2 removed (numpy 1.x deprecates it); here it is `tobytes()`."""

    def tostring(self) -> bytes:
        return self.tobytes()


def message_arrays(frame: Frame) -> dict[str, np.ndarray | bytes]:
    """The Features message's per-feature arrays of a frame (orb_ros.loop.feature_arrays) as
    genpy serialises them: uint8[] as bytes, the others as numpy arrays (numpy_msg)."""
    arrays = feature_arrays(frame)
    return {name: a.tobytes() if a.dtype == np.uint8 else a.view(WireArray) for name, a in arrays.items()}


def build_message(msg_cls: type, frame: Frame, stamp: object, frame_id: str,
                  assumed: FrameParams | None = None) -> object:  # fmt: skip
    """An orb_accel_msgs/Features message (`msg_cls`: the generated class, or its numpy_msg form)
    of a frame, labelled with the parameters its end-of-frame record says it was processed with
    (orb_ros.loop.frame_fields)."""
    msg = msg_cls(**message_arrays(frame), **frame_fields(frame, assumed))
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    return msg


class FeatureNode(FrameLoop):
    """The ROS 1 node: the loop (orb_ros.loop.FrameLoop) with rospy's publishers, services and
    log (rospy initialised by the caller)."""

    def __init__(self, rospy: ModuleType, msgs: ModuleType, srvs: ModuleType, accel: OrbAccel, params: Params,
                 frame_id: str, timeout_s: float, diag_period_s: float = 1.0, hardware_id: str = "orb-accel",
                 service_timeout_s: float = 600.0, budget: int | None = None) -> None:  # fmt: skip
        from diagnostic_msgs.msg import DiagnosticArray  # Debian's python3-diagnostic-msgs
        from rospy.numpy_msg import numpy_msg
        from std_srvs.srv import Trigger, TriggerResponse

        super().__init__(AccelSource(accel), params, timeout_s, diag_period_s, service_timeout_s, budget)
        self.rospy, self.srvs, self.accel = rospy, srvs, accel
        self.frame_id, self.hardware_id = frame_id, hardware_id
        self._trigger_response = TriggerResponse
        self._diag_array = DiagnosticArray
        self.msg_cls = numpy_msg(msgs.Features)
        self.pub = rospy.Publisher("~features", self.msg_cls, queue_size=16)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=4)
        self.start()
        rospy.Service("~set_params", srvs.SetParams, self._on_set_params)
        rospy.Service("~reset", Trigger, self._on_reset)

    # ---- what the loop needs of ROS ------------------------------------------------------------
    def now(self) -> object:
        return self.rospy.Time.now()

    def publish(self, frame: Frame, stamp: object, assumed: FrameParams) -> None:
        self.pub.publish(build_message(self.msg_cls, frame, stamp, self.frame_id, assumed))

    def publish_report(self, report: Report) -> None:
        from diagnostic_msgs.msg import DiagnosticStatus, KeyValue

        status = DiagnosticStatus(
            level=DiagnosticStatus.WARN if report.warn else DiagnosticStatus.OK, name=f"{NODE_NAME}: accelerator",
            hardware_id=self.hardware_id, message=report.message,
            values=[KeyValue(k, v) for k, v in report.values.items()],
        )  # fmt: skip
        arr = self._diag_array()
        arr.header.stamp = self.rospy.Time.now()
        arr.status = [status]
        self.diag_pub.publish(arr)

    def logwarn(self, text: str) -> None:
        self.rospy.logwarn(text)

    def loginfo(self, text: str) -> None:
        self.rospy.loginfo(text)

    # ---- services (rospy's threads): queue, wait until the loop has written the change ---------
    def _on_set_params(self, req: object) -> object:
        base = self.queued_params()
        threshold = base.threshold if req.threshold == KEEP_THRESHOLD else int(req.threshold)  # type: ignore[attr-defined]
        mode = base.mode if req.mode == KEEP_MODE else req.mode  # type: ignore[attr-defined]
        if req.enable not in (KEEP_ENABLE, 0, 1):  # type: ignore[attr-defined]
            return self.srvs.SetParamsResponse(False, f"enable must be 1, 0 or -1 (keep), got {req.enable}", 0)  # type: ignore[attr-defined]
        enable = base.enable if req.enable == KEEP_ENABLE else bool(req.enable)  # type: ignore[attr-defined]
        error = check_params(threshold, mode, enable)
        if error is not None:
            self.rospy.logwarn(f"set_params refused: {error}")
            return self.srvs.SetParamsResponse(False, error, self.last_frame)
        r = self.submit(Request(params=Params(threshold, mode, enable)))
        return self.srvs.SetParamsResponse(r.success, r.message, r.after_frame)

    def _on_reset(self, _req: object) -> object:
        r = self.submit(Request(reset=True))
        return self._trigger_response(r.success, r.message)

    def run(self) -> None:
        while not self.rospy.is_shutdown():
            self.step()


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
             default_timeout_s: float, hardware_id: str,
             memory: FrameMemory | MemoryFactory | None = None) -> int:  # fmt: skip
    """Run the initialised node on `bus` until it is shut down; `memory`: a DDR build's frame
    memory (OrbAccel(memory=); orb_accel.ddr), unused by a build with block-RAM banks."""
    accel = OrbAccel(bus, memory=memory)
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
