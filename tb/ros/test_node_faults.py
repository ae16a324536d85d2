# SPDX-License-Identifier: MIT
"""The ROS node's loop under faults, in process (docs/ros.md, "Faults and recovery"): FeatureNode
with Debian's message classes, a stand-in for rospy (publishers that keep what they get, no
master) and the driver on the scripted accelerator (orbtb.scripted_accel). The end-to-end run
through a roscore and the simulated netlist is test_ros_node.py's test_node_under_faults.

- a stall (no video) is one WARN report at its start, "no frame for" while it lasts, and an OK
  report with the next frame;
- an error response while a parameter change is written: the change goes back to the queue, the
  service call is answered once it is written (no call left hanging), the node goes on;
- an error response to the bank's read after the change was written: the call is answered with the
  last published frame, the frame is lost and counted in frames_missed when the next one comes.
"""

from __future__ import annotations

import dataclasses
import threading
from types import SimpleNamespace

import pytest

from golden_model import regs
from orb_accel import OrbAccel
from orb_ros import msgs as rosmsgs
from orb_ros.node import FeatureNode, Params
from orbtb.scripted_accel import ScriptedAccel

rospy_real = rosmsgs.import_rospy()
msg_mod, srv_mod = rosmsgs.load()
OK, WARN = 0, 1


class FakeRospy:
    """What FeatureNode uses of rospy, without a master."""

    def __init__(self) -> None:
        self.topics: dict[str, list] = {}
        self.log: list[str] = []
        self.Time = SimpleNamespace(now=lambda: rospy_real.Time(0))

    def Publisher(self, name: str, _cls: type, queue_size: int) -> SimpleNamespace:
        return SimpleNamespace(publish=self.topics.setdefault(name, []).append)

    def Service(self, *_args: object) -> None:
        pass

    def logwarn(self, text: str) -> None:
        self.log.append("WARN " + text)

    def loginfo(self, text: str) -> None:
        self.log.append("INFO " + text)


@pytest.fixture
def node() -> tuple[FeatureNode, ScriptedAccel, FakeRospy]:
    bus, fake = ScriptedAccel(), FakeRospy()
    n = FeatureNode(fake, msg_mod, srv_mod, OrbAccel(bus), Params(20, "orb", True), "test", 0.01, diag_period_s=0.0)
    return n, bus, fake


def reports(fake: FakeRospy) -> list:
    return [a.status[0] for a in fake.topics["/diagnostics"]]


def call_set_params(n: FeatureNode, threshold: int) -> tuple[threading.Thread, list]:
    out: list = []
    req = SimpleNamespace(threshold=threshold, mode="", enable=-1)
    t = threading.Thread(target=lambda: out.append(n._on_set_params(req)), daemon=True)
    t.start()
    while not n.requests:  # queued
        t.join(0.001)
    return t, out


def test_a_stall_warns_and_recovers(node: tuple[FeatureNode, ScriptedAccel, FakeRospy]) -> None:
    n, bus, fake = node
    assert n.step() is not None and n.step() is not None
    bus.video = False
    for _ in range(3):
        assert n.step() is None
    bus.video = True
    assert n.step() is not None
    r = reports(fake)
    stall = [s for s in r if "no frame for" in s.message]
    assert stall and all(s.level == WARN for s in stall), [s.message for s in r]
    assert r[-1].level == OK and {kv.key: kv.value for kv in r[-1].values}["stalls"] == "1", r[-1]
    assert n.stalls == 1 and n.timeouts == 3 and n.stalled_since is None
    assert sum("no frame within" in line for line in fake.log) == 1 and any("frames again" in x for x in fake.log)


def test_a_change_cut_by_an_error_response_is_written_later(node: tuple[FeatureNode, ScriptedAccel, FakeRospy]) -> None:
    n, bus, fake = node
    n.step()
    bus.fail("write", regs.SELECT)  # configure()'s first write
    t, out = call_set_params(n, 35)
    assert n.step() is None  # the error: the frame lost, the change back in the queue
    assert not out and n.requests, "the change was dropped"
    frame = n.step()
    t.join(5.0)
    assert frame is not None and out and out[0].success, out
    assert regs.THRESHOLD.field("threshold").get(bus.threshold) == 35 and n.params.threshold == 35
    assert out[0].after_frame == frame.number
    assert any("bus_errors +1" in s.message and s.level == WARN for s in reports(fake))
    assert n.accel.faults.bus_errors == 1
    for _ in range(3):  # and the frames flow: the bank of the frame the error cut was given back
        assert n.step() is not None
    assert bus.overruns == 0 and bus.ready == [0, 0]


def test_an_error_response_after_the_change_answers_the_call(
    node: tuple[FeatureNode, ScriptedAccel, FakeRospy],
) -> None:
    n, bus, fake = node
    first = n.step()
    assert first is not None
    bus.fail("block", None)  # the bank's read, after the change is written
    t, out = call_set_params(n, 30)
    assert n.step() is None
    t.join(5.0)
    assert out and out[0].success and out[0].after_frame == first.number, out
    after = n.step()
    assert after is not None and after.number == first.number + 2 and n.frames_missed == 1
    assert "frames_missed +1" in reports(fake)[-1].message


@pytest.mark.parametrize("late", [False, True], ids=["in the blanking", "missed the blanking"])
def test_each_message_carries_its_frames_parameters(node: tuple[FeatureNode, ScriptedAccel, FakeRospy],
                                                    late: bool) -> None:  # fmt: skip
    """The message's threshold and mode (and selection) are the frame's record's (docs/ros.md): a
    change written after a frame-done interrupt that misses the vertical blanking (late) leaves the
    frame in flight with the old values, and its message says so, while the node's own record (and
    every register) already holds the new ones; the message after it says the new ones."""
    n, bus, fake = node
    bus.late_writes = late
    n.step()
    t, out = call_set_params(n, 35)
    first = n.step()  # the change is written right after this frame's interrupt
    t.join(5.0)
    assert first is not None and out and out[0].success and out[0].after_frame == first.number, out
    n.params = dataclasses.replace(n.params, mode="fast")  # the node's record now disagrees in mode too
    second, third = n.step(), n.step()
    assert second is not None and third is not None
    by_frame = {m.frame: m for m in fake.topics["~features"]}
    sel = n.accel.selection
    for frame, threshold in ((first, 20), (second, 20 if late else 35), (third, 35)):
        m = by_frame[frame.number]
        assert (m.threshold, m.mode) == (threshold, "orb"), (frame.number, m.threshold, m.mode)
        assert (m.selection, m.budget, m.cols, m.rows, m.threshold_lo) == (
            sel.mode, sel.budget if sel.mode == "grid" else 0, *sel.cells, sel.threshold_lo)  # fmt: skip
        assert frame.params is not None and frame.params.threshold == threshold
    if late:  # the label the node's own record gives the frame in flight would be wrong
        assert by_frame[second.number].threshold != n.params.threshold
