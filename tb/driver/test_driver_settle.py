# SPDX-License-Identifier: MIT
"""OrbAccel.settle() against a scripted accelerator: the frame-end races around its acknowledgement.

The bus here is orbtb.scripted_accel.ScriptedAccel, a small register-level model of the feature
memory's bank protocol (docs/feature-memory.md): a finished frame goes to the next bank unless that
bank is still READY, in which case it is skipped (an overrun) and the next frame tries the same
bank again. Frames finish when the driver waits for the interrupt, or at a chosen read.

- A frame that finished before settle() acknowledged the interrupts must have its bank released,
  or every later frame is skipped and the driver waits for an interrupt that never comes.
- A frame that finishes between the acknowledgement and that release raises the interrupt with a
  bank that is gone: settle() waits on for the next frame instead of failing.
"""

from __future__ import annotations

import pytest

from golden_model import regs
from orb_accel import OrbAccel
from orbtb.scripted_accel import ScriptedAccel


def started() -> tuple[ScriptedAccel, OrbAccel]:
    bus = ScriptedAccel()
    accel = OrbAccel(bus)
    accel.configure(threshold=20, mode="orb")
    return bus, accel


def test_a_frame_finished_before_settle_has_its_bank_released() -> None:
    bus, accel = started()
    bus.finish_frame()  # bank 0 READY, its interrupt pending
    accel.configure(threshold=30, mode="fast")
    accel.settle(0.01)
    assert bus.ready == [0, 0], f"banks still held after settle: {bus.ready}"
    for _ in range(3):  # and frames keep coming
        accel.next_frame(0.01)
    assert bus.overruns == 0


def test_a_frame_finished_between_acknowledgement_and_release_is_waited_past() -> None:
    bus, accel = started()
    bus.finish_frame()  # bank 0
    # the next frame (bank 1) finishes just as settle() reads STATUS to release what is ready
    bus.finish_on_status_read = bus.status_reads + 1
    frames_before = bus.frames
    frame = accel.settle(0.01)
    assert bus.frames >= frames_before + 2, "settle returned a frame that finished before it"
    assert frame.bank == bus.last_bank and bus.ready == [0, 0]
    accel.next_frame(0.01)


def test_next_frame_without_settle_still_needs_the_release() -> None:
    """The scripted model is strict: a bank never released stops the frames (the failure the
    first test guards against)."""
    bus, accel = started()
    bus.finish_frame()
    accel.write(regs.IRQ_STATUS, 0xFFFFFFFF)  # acknowledged, bank 0 left READY
    accel.next_frame(0.01)  # bank 1
    with pytest.raises(TimeoutError, match="no interrupt"):
        accel.next_frame(0.01)
