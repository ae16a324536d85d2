# SPDX-License-Identifier: MIT
"""The driver under faults (docs/driver.md, "Faults and recovery") against a scripted accelerator
(orbtb.scripted_accel: the feature memory's bank protocol, which skips every frame whose bank is
still READY, with faults on demand). The same faults against the simulated netlist, through the
socket, are tb/driver/test_socket_faults.py.

- interrupts stop (a cable cut): TimeoutError with the status registers, counted; the driver stays
  usable and frames flow again when the video comes back;
- a frame-done interrupt lost with its bank READY (the accelerator then skips every frame): the
  timeout releases the bank and frames flow again;
- an error response (SLVERR) to the STATUS read after an interrupt, to a feature-memory read, to
  the release: BusError, counted; the next wait releases whatever bank was lost track of, without
  waiting for a timeout, and frames flow again;
- a previous process died holding a bank: the next driver releases it at open (counted), keeps the
  frame whose interrupt is still pending, and frames flow;
- a frame that finishes while a recovery releases its bank: its interrupt is waited past.
"""

from __future__ import annotations

import pytest

from golden_model import regs
from orb_accel import BusError, OrbAccel
from orbtb.scripted_accel import ScriptedAccel

CUT_TEXT = r"no interrupt within 0.01 s: STATUS = 0x\w+, IRQ_STATUS = 0x0, .*overrun = 0"


def started() -> tuple[ScriptedAccel, OrbAccel]:
    bus = ScriptedAccel()
    accel = OrbAccel(bus)
    accel.configure(threshold=20, mode="orb")
    return bus, accel


def flowing(accel: OrbAccel, bus: ScriptedAccel, n: int = 4) -> list[int]:
    """n frames in a row, none skipped by the accelerator meanwhile; their frame numbers."""
    overruns = bus.overruns
    numbers = [accel.next_frame(0.01).number for _ in range(n)]
    assert numbers == list(range(numbers[0], numbers[0] + n)), f"frames {numbers} not consecutive"
    assert bus.overruns == overruns, "the accelerator skipped frames: a bank was held"
    assert bus.ready == [0, 0], f"banks left held: {bus.ready}"
    return numbers


def test_interrupts_stop_then_frames_come_back() -> None:
    bus, accel = started()
    before = flowing(accel, bus, 2)
    bus.video = False  # the cable is cut
    for k in range(3):
        with pytest.raises(TimeoutError, match=CUT_TEXT):
            accel.next_frame(0.01)
        assert accel.faults.timeouts == k + 1
    bus.video = True
    after = flowing(accel, bus)
    assert after[0] > before[-1]
    assert (accel.faults.stale_banks, accel.faults.bus_errors) == (0, 0)


def test_a_lost_interrupt_is_recovered_at_the_timeout() -> None:
    bus, accel = started()
    flowing(accel, bus, 2)
    bus.finish_frame()  # published ...
    bus.lose_irq()  # ... but its interrupt never reaches the CPU: the bank stays READY, the next frame skips
    lost = bus.last_bank
    with pytest.raises(TimeoutError, match=rf"released bank\(s\) \[{lost}\] that nobody held"):
        for _ in range(3):  # one frame may still come (the other bank), then nothing
            accel.next_frame(0.01)
    assert accel.faults.stale_banks == 1
    flowing(accel, bus)


@pytest.mark.parametrize(
    ("op", "reg", "where"),
    [
        ("read", regs.STATUS, "the STATUS read after the interrupt"),
        ("block", None, "the bank's read"),
        ("write", regs.BANK_RELEASE, "the release"),
    ],
)
def test_a_bus_error_is_raised_counted_and_recovered(op: str, reg: regs.Register | None, where: str) -> None:
    bus, accel = started()
    flowing(accel, bus, 2)
    bus.fail(op, reg)
    with pytest.raises(BusError, match="SLVERR"):
        accel.next_frame(0.01)
    assert bus.injected == 1, where
    flowing(accel, bus)  # at once: no timeout needed to find the bank the error left READY
    assert accel.faults.timeouts == 0, f"after an error in {where} frames came only after a timeout"
    assert accel.faults.bus_errors == 1, where
    # a bank left READY by the error (STATUS read, release) is released unread; one released by
    # frame()'s own clean-up (the bank's read) is not stale
    assert accel.faults.stale_banks == (0 if op == "block" else 1), where


def test_a_dead_predecessors_bank_is_released_at_open() -> None:
    bus, dead = started()
    flowing(dead, bus, 2)
    held = dead.wait_frame(0.01)  # ... and the process dies holding it
    bus.finish_frame()  # the next frame goes to the other bank; its interrupt stays pending
    pending = bus.last_bank
    assert pending != held and bus.ready == [1, 1]
    accel = OrbAccel(bus)
    accel.configure(threshold=20, mode="orb")
    first = accel.next_frame(0.01)
    assert first.bank == pending, "the frame whose interrupt was pending is kept"
    flowing(accel, bus)
    assert accel.released_at_open == [held] and accel.faults.stale_banks == 1


def test_no_release_at_open_when_asked() -> None:
    bus, dead = started()
    held = dead.wait_frame(0.01)
    look = OrbAccel(bus, release_stale=False)
    assert look.released_at_open == [] and bus.ready[held] == 1


def test_a_frame_finishing_during_a_recovery_is_waited_past() -> None:
    bus, accel = started()
    flowing(accel, bus, 2)
    bus.fail("write", regs.BANK_RELEASE)
    with pytest.raises(BusError):
        accel.next_frame(0.01)  # the bank stays READY
    # the recovery reads IRQ_STATUS (nothing pending), then STATUS, at which a frame finishes: its
    # bank looks stale and is released, its interrupt comes anyway
    bus.finish_on_status_read = bus.status_reads + 1
    flowing(accel, bus)
    assert accel.faults.stray_irqs == 1 and accel.faults.stale_banks == 2
