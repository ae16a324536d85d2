# SPDX-License-Identifier: MIT
"""The ROS 2 node of the accelerator (docs/ros2.md), rclpy from PyPI: one orb_accel_msgs/msg/Features
message per frame on ~/features (/orb_accel/features), the run-time parameters as ROS 2 parameters
(threshold, mode, enable; a callback refuses an illegal value with its range), ~/reset
(std_srvs/srv/Trigger) and diagnostics on /diagnostics. The loop is the ROS 1 node's
(orb_ros.loop.FrameLoop): a change is written right after the next frame-done interrupt and applies
from the first frame after that one; every message carries the parameters of its own frame.

Run in the ROS 2 venv (`make setup` makes .venv-ros2; rclpy is imported nowhere else):

    python -m orb_ros2.node --connect 127.0.0.1:5555 --ros-args -p threshold:=30
    python -m orb_ros2.node --uio orb-accel          # on a board with ROS 2

`orb-accel ros2` (the main venv's CLI) starts it, and with `--sim` a simulator for it. The frame
source is one function, open_source(): the driver on UIO, /dev/mem or the simulator's socket, or
the frames of an `orb-accel serve` on another machine (--remote; its parameters are the server's).
"""

from __future__ import annotations

import argparse
import array
import signal
import sys
import threading
from collections.abc import Iterator, Sequence
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from types import ModuleType

import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rcl_interfaces.msg import IntegerRange, ParameterDescriptor, SetParametersResult
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor, ShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import Trigger

from golden_model import limits
from golden_model.config import MODES
from golden_model.frameparams import FrameParams
from orb_accel.bus import BOARD_TIMEOUT_S, SIM_TIMEOUT_FRAMES
from orb_accel.ddr import memory_factory
from orb_accel.driver import Frame, OrbAccel
from orb_ros.loop import (
    NODE_NAME,
    AccelSource,
    FrameLoop,
    NodeSource,
    Params,
    RemoteSource,
    Report,
    Request,
    check_params,
    feature_arrays,
    frame_fields,
)

from . import interfaces

# The feature stream's QoS (docs/ros2.md, "QoS"): REP 2003's for a sensor driver, the system
# default's reliable and volatile, so that both a reliable subscriber (every frame, a recorder) and
# one with SensorDataQoS (best effort: a SLAM front end that wants the newest) connect; a history
# of a few frames bounds what a slow subscriber costs the node.
FEATURES_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=5, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.VOLATILE)  # fmt: skip
DIAGNOSTICS_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=4, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.VOLATILE)  # fmt: skip
ARRAY_CODES = {"float32": "f", "int32": "i", "uint16": "H", "uint8": "B"}  # array.array's codes of rosidl_generator_py
RECOMMENDED_BUDGET = -1  # ~budget's default: the recommended budget of the frame size (HwConfig.default_budget)


def build_message(msg_cls: type, frame: Frame, stamp: object, frame_id: str,
                  assumed: FrameParams | None = None) -> object:  # fmt: skip
    """An orb_accel_msgs/msg/Features of a frame (the fields as the ROS 1 node fills them,
    orb_ros.loop.frame_fields and feature_arrays); the arrays go in as array.array, which the
    generated class keeps and its C conversion copies whole."""
    msg = msg_cls(**frame_fields(frame, assumed))
    for name, values in feature_arrays(frame).items():
        setattr(msg, name, array.array(ARRAY_CODES[values.dtype.name], values.tobytes()))
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    return msg


@dataclass(frozen=True)
class Settings:
    """The node's start-up parameters (threshold, mode, enable change at run time; the others are
    read-only): budget RECOMMENDED_BUDGET = the recommended one, 0 every feature; timeout 0 = the
    source's default."""

    params: Params
    frame_id: str = NODE_NAME
    timeout_s: float = 0.0
    diag_period_s: float = 1.0
    budget: int = RECOMMENDED_BUDGET


def declare(node: Node, defaults: Params) -> Settings:
    """Declare the parameters (their ranges in the descriptors, from golden_model.limits) and read
    the start-up values (`--ros-args -p NAME:=VALUE`); ValueError naming the allowed values for an
    illegal one, before any bus is opened."""
    ro = {"read_only": True}
    # the run-time ones take a value of any type, so that the callback (check_params), not rclpy's
    # type check, answers a wrong one with the allowed values
    any_type = {"dynamic_typing": True}
    specs = [
        ("threshold", defaults.threshold, ParameterDescriptor(
            description=f"FAST threshold {limits.THRESHOLD.text}; from the first frame after the next one",
            integer_range=[IntegerRange(from_value=limits.THRESHOLD.min, to_value=limits.THRESHOLD.max, step=1)],
            **any_type)),
        ("mode", defaults.mode, ParameterDescriptor(description=f"one of {', '.join(MODES)}", additional_constraints=
                                                    f"one of {', '.join(MODES)}", **any_type)),
        ("enable", defaults.enable, ParameterDescriptor(description="the accelerator processes frames", **any_type)),
        ("frame_id", NODE_NAME, ParameterDescriptor(description="header.frame_id of the messages", **ro)),
        ("budget", RECOMMENDED_BUDGET, ParameterDescriptor(
            description="the grid selection's budget: at most this many features a frame (-1: the recommended one "
                        "of the frame size; 0: every feature)", **ro)),
        ("timeout", 0.0, ParameterDescriptor(description="seconds to wait for a frame (0: 1 s on the board, three "
                                             "frame periods of simulated time in simulation)", **ro)),
        ("diagnostics_period", 1.0, ParameterDescriptor(description="seconds between diagnostics reports", **ro)),
    ]  # fmt: skip
    values = {}
    for name, default, descriptor in specs:
        try:
            values[name] = node.declare_parameter(name, default, descriptor).value
        except Exception as exc:  # rclpy's InvalidParameterValueException / InvalidParameterTypeException
            raise ValueError(f"{name}: {exc}") from None
    error = check_params(values["threshold"], values["mode"], values["enable"])
    for name in ("timeout", "diagnostics_period"):
        v = values[name]
        if not v >= 0 or (name == "diagnostics_period" and not v > 0):
            error = error or f"{name} must be a positive number of seconds, got {v!r}"
    if values["budget"] < RECOMMENDED_BUDGET:
        b = values["budget"]
        error = error or f"budget must be -1 (recommended), 0 (every feature) or a number of features, got {b}"
    if error is not None:
        raise ValueError(error)
    return Settings(Params(int(values["threshold"]), values["mode"], bool(values["enable"])), values["frame_id"],
                    float(values["timeout"]), float(values["diagnostics_period"]), int(values["budget"]))  # fmt: skip


class Ros2FeatureNode(FrameLoop):
    """The loop (orb_ros.loop.FrameLoop) with rclpy's publishers, parameters, service and log. The
    loop runs in the caller's thread (run()); the parameter callback and ~/reset run in the
    executor's threads and wait until the loop has written their change."""

    def __init__(self, node: Node, msgs: ModuleType, source: NodeSource, settings: Settings, timeout_s: float,
                 hardware_id: str) -> None:  # fmt: skip
        budget = None if settings.budget == RECOMMENDED_BUDGET else settings.budget
        super().__init__(source, settings.params, timeout_s, settings.diag_period_s, budget=budget)
        self.node, self.frame_id, self.hardware_id = node, settings.frame_id, hardware_id
        self.msg_cls = msgs.Features
        self.log = node.get_logger()
        self.pub = node.create_publisher(msgs.Features, "~/features", FEATURES_QOS)
        self.diag_pub = node.create_publisher(DiagnosticArray, "/diagnostics", DIAGNOSTICS_QOS)
        self.start()
        group = ReentrantCallbackGroup()
        node.add_on_set_parameters_callback(self._on_set_parameters)
        node.create_service(Trigger, "~/reset", self._on_reset, callback_group=group)
        self.stopping = threading.Event()

    # ---- what the loop needs of ROS ------------------------------------------------------------
    def now(self) -> object:
        return self.node.get_clock().now().to_msg()

    def publish(self, frame: Frame, stamp: object, assumed: FrameParams) -> None:
        self.pub.publish(build_message(self.msg_cls, frame, stamp, self.frame_id, assumed))

    def publish_report(self, report: Report) -> None:
        status = DiagnosticStatus(
            level=DiagnosticStatus.WARN if report.warn else DiagnosticStatus.OK, name=f"{NODE_NAME}: accelerator",
            hardware_id=self.hardware_id, message=report.message,
            values=[KeyValue(key=k, value=v) for k, v in report.values.items()],
        )  # fmt: skip
        arr = DiagnosticArray(status=[status])
        arr.header.stamp = self.now()
        self.diag_pub.publish(arr)

    def logwarn(self, text: str) -> None:
        self.log.warning(text)

    def loginfo(self, text: str) -> None:
        self.log.info(text)

    # ---- parameters and services (the executor's threads) -------------------------------------
    def _on_set_parameters(self, changes: list[Parameter]) -> SetParametersResult:
        """Refuse an illegal value with the allowed ones (the descriptors' ranges and types are
        checked by rclpy before); queue a legal change and answer once the loop has written it."""
        base = self.queued_params()
        values = {"threshold": base.threshold, "mode": base.mode, "enable": base.enable}
        for p in changes:
            if p.name in values:
                values[p.name] = p.value
        error = check_params(values["threshold"], values["mode"], values["enable"])
        if error is not None:
            self.logwarn(f"parameter refused: {error}")
            return SetParametersResult(successful=False, reason=error)
        new = Params(int(values["threshold"]), str(values["mode"]), bool(values["enable"]))
        if new == base:
            return SetParametersResult(successful=True)
        if isinstance(self.source, RemoteSource):
            return SetParametersResult(successful=False, reason=self.source.refusal())
        if self.stopping.is_set():
            return SetParametersResult(successful=False, reason="the node is shutting down")
        r = self.submit(Request(params=new))
        if r.success:
            self.loginfo(r.message)
        return SetParametersResult(successful=r.success, reason=r.message)

    def _on_reset(self, _request: object, response: object) -> object:
        if isinstance(self.source, RemoteSource):
            response.success, response.message = False, self.source.refusal()  # type: ignore[attr-defined]
            return response
        r = self.submit(Request(reset=True))
        response.success, response.message = r.success, r.message  # type: ignore[attr-defined]
        if r.success:
            self.loginfo(r.message)
        return response

    def run(self) -> None:
        while not self.stopping.is_set() and rclpy.ok():
            self.step()


@contextmanager
def open_source(args: argparse.Namespace) -> Iterator[tuple[NodeSource, str, float]]:
    """(frame source, what it is, the default frame timeout) of the command line: the driver on the
    board (--uio, the default; --devmem) or on a simulator's socket (--connect), or the frames of
    an `orb-accel serve` on another machine (--remote). A DDR build's frame memory: --ddr-memory
    (orb_accel.ddr.memory_factory; u-dma-buf's udmabuf0 on the board, an array on a simulator)."""
    with ExitStack() as stack:
        if args.remote:
            from orb_accel.remote import RemoteAccel

            remote = stack.enter_context(RemoteAccel(args.remote, name=f"{NODE_NAME} (ROS 2)"))
            what = f"orb-accel serve at {args.remote}"
            yield RemoteSource(remote, what), what, remote.frame_wait_s
            return
        if args.connect:
            from orb_accel.socket_bus import SocketBus

            bus = stack.enter_context(SocketBus(args.connect))
            what = f"simulator {args.connect} ({bus.info['toplevel']})"
            timeout = SIM_TIMEOUT_FRAMES * bus.frame_period_s()
        elif args.devmem is not None:
            from orb_accel.devmem import DevMemBus

            bus = stack.enter_context(DevMemBus(args.devmem))
            what, timeout = f"/dev/mem at {args.devmem:#x}", BOARD_TIMEOUT_S
        else:
            from orb_accel.uio import UioBus

            name = args.uio or "orb-accel"
            bus, what, timeout = stack.enter_context(UioBus.open(name)), f"UIO device {name!r}", BOARD_TIMEOUT_S
        memory = memory_factory(args.ddr_memory, board=not args.connect, bus=bus)
        yield AccelSource(OrbAccel(bus, memory=memory)), what, timeout


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m orb_ros2.node", description=__doc__.split("\n\n")[0])
    g = p.add_mutually_exclusive_group()
    g.add_argument("--uio", metavar="NAME", nargs="?", const="orb-accel", help="UIO device NAME (the default)")
    g.add_argument("--devmem", metavar="BASE", type=lambda t: int(t, 0), help="/dev/mem at physical address BASE")
    g.add_argument("--connect", metavar="HOST:PORT", help="a running simulator (orb-accel sim-server)")
    g.add_argument("--remote", metavar="HOST:PORT", help="the frames of an orb-accel serve (its parameters)")
    p.add_argument("--threshold", type=int, default=20, help="start-up threshold (parameter threshold wins)")
    p.add_argument("--mode", default="orb", help="start-up mode (parameter mode wins)")
    p.add_argument("--ddr-memory", metavar="SPEC",
                   help="a DDR build's frame memory (CFG_DDR.ddr = 1 only): udmabuf[:NAME] (default on the board: "
                        "udmabuf0), array[:PHYS] (default with --connect), pynq (docs/driver.md)")  # fmt: skip
    return p


def _raise_interrupt(_sig: int, _frame: object) -> None:
    raise KeyboardInterrupt


def _spin(executor: MultiThreadedExecutor) -> None:
    """The executor's thread: spins until the executor or the context is shut down."""
    try:
        executor.spin()
    except (ExternalShutdownException, ShutdownException):
        pass


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    ros_args = argv[argv.index("--ros-args") :] if "--ros-args" in argv else []
    args = _parser().parse_args(argv[: len(argv) - len(ros_args)])
    msgs, _ = interfaces.load()
    # SIGINT and SIGTERM stop the loop at once (rclpy's own handlers are off: the loop is ours)
    rclpy.init(args=[sys.argv[0], *ros_args], signal_handler_options=SignalHandlerOptions.NO)
    signal.signal(signal.SIGTERM, _raise_interrupt)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    node = Node(NODE_NAME)
    executor = MultiThreadedExecutor(num_threads=2)
    ros2: Ros2FeatureNode | None = None
    spin: threading.Thread | None = None
    try:
        try:
            settings = declare(node, Params(args.threshold, args.mode, True))
        except ValueError as exc:
            node.get_logger().fatal(f"illegal start-up parameter: {exc}")
            print(f"orb-accel ros2: error: illegal start-up parameter: {exc}", file=sys.stderr)
            return 2
        with open_source(args) as (source, what, default_timeout):
            timeout_s = settings.timeout_s or default_timeout
            ros2 = Ros2FeatureNode(node, msgs, source, settings, timeout_s, what)
            executor.add_node(node)
            spin = threading.Thread(target=_spin, args=(executor,), name="executor", daemon=True)
            spin.start()
            hw, p = source.hw, settings.params
            node.get_logger().info(
                f"{NODE_NAME} on {what}: {hw.width}x{hw.height}, {hw.scales} scales of {hw.step_num}:{hw.step_den}, "
                f"{hw.sectors} sectors; threshold {p.threshold}, mode {p.mode}, budget {ros2.budget}; frame timeout "
                f"{timeout_s:g} s; publishing on {ros2.pub.topic_name}")  # fmt: skip
            try:
                ros2.run()
            except KeyboardInterrupt:
                node.get_logger().info(f"{NODE_NAME}: interrupted after {ros2.published} frames, shutting down")
        return 0
    except KeyboardInterrupt:
        return 0
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):  # a second signal does not cut the shutdown short
            signal.signal(sig, signal.SIG_IGN)
        if ros2 is not None:
            ros2.stopping.set()
            ros2.shutdown()
        # the executor's thread is joined before the node and the context go: a thread still inside
        # rclpy's wait when the interpreter exits aborts the process ("terminate called without an
        # active exception", seen under load); a context shutdown wakes a wait that outlives the
        # executor's own shutdown
        executor.shutdown(timeout_sec=5.0)
        if spin is not None:
            spin.join(timeout=5.0)
            if spin.is_alive():
                rclpy.try_shutdown()
                spin.join(timeout=5.0)
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (OSError, RuntimeError, ValueError) as exc:  # a bus that does not open, not an accelerator, ...
        print(f"orb-accel ros2: error: {exc}", file=sys.stderr)
        sys.exit(2)
