# SPDX-License-Identifier: MIT
"""Every frame says how it was made (docs/driver.md, "The frame's own parameters"): the driver's
Frame.params against the simulated accelerator in another process (orb_sim.sim_server on the fast
engine: orb_accel_top's netlist in Verilator, the 128x96 colour photographs of test_socket_bus.py).

Each change of the parameters (threshold, low threshold, mode, selection, budget, cells) is written
half-way through a frame: after a frame-done interrupt (its bank released unread) the test waits
half a frame period (the simulated time runs while the bus waits) before configure(). The frame in
flight was started with the old values, so its record must say the old ones while every register already holds the new
ones (the label the driver's own state would give is wrong), and its features must be the model's
under the old ones; the next frame must say, and be, the new ones.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from golden_model import regs
from golden_model.config import named
from golden_model.features import Features, first_difference
from golden_model.frameparams import FrameParams
from golden_model.luma import rgb_to_luma
from orb_accel import OrbAccel
from orb_accel.driver import Frame
from orb_accel.socket_bus import SocketBus
from orb_sim.core_inputs import selection_text
from orb_sim.sim_server import SimServer
from orbtb.images import colour_photo
from orbtb.scoreboard import expected_features

TINY = named("test-tiny")
W, H, SCALES, SECTORS = TINY.width, TINY.height, TINY.scales, TINY.sectors
PHOTOS = ("astronaut", "coffee", "chelsea")
# the parameter sets, in the order written; neighbours differ in every field the driver sets (small
# budgets and high thresholds: a frame's bank is read in fewer simulated clocks)
STEPS = (
    FrameParams(threshold=20, threshold_lo=14, mode="orb", selection="grid", budget=60, cols=8, rows=6),
    FrameParams(threshold=45, threshold_lo=9, mode="fast", selection="all", budget=0, cols=4, rows=3),
    FrameParams(threshold=12, threshold_lo=5, mode="orb", selection="grid", budget=40, cols=5, rows=4),
    FrameParams(threshold=40, threshold_lo=40, mode="orb", selection="all", budget=0, cols=2, rows=2),
)


@pytest.fixture(scope="module")
def lumas() -> list[np.ndarray]:
    return [rgb_to_luma(colour_photo(name, W, H)) for name in PHOTOS]


def model(luma: np.ndarray, p: FrameParams) -> Features:
    sel = selection_text(p.selection, p.budget, (p.cols, p.rows), p.threshold_lo)
    return expected_features(luma, SCALES, p.threshold, p.mode, SECTORS, (TINY.step_num, TINY.step_den), sel)


def configure(accel: OrbAccel, p: FrameParams) -> None:
    accel.configure(p.threshold, p.mode, selection=p.selection, budget=p.budget, cells=(p.cols, p.rows),
                    threshold_lo=p.threshold_lo)  # fmt: skip


def check_made_with(frame: Frame, p: FrameParams, lumas: list[np.ndarray], what: str) -> None:
    assert frame.params == p, f"{what}: frame {frame.number}'s record says {frame.params}, it was made with {p}"
    assert frame.mode == p.mode, f"{what}: decoded in {frame.mode} mode"
    diffs = [first_difference(frame.features, model(luma, p)) for luma in lumas]
    assert diffs.count(None) == 1, f"{what}: frame {frame.number} is no photograph under {p}: {diffs}"


def sync(accel: OrbAccel, timeout: float) -> int:
    """Return right after a fresh frame-done interrupt, every bank released; the number of the
    frame that raised it. Its bank is released unread: reading a bank costs the simulation more
    than a frame period, and time must stand near the interrupt."""
    accel.write(regs.IRQ_STATUS, 0xFFFFFFFF)
    ready = regs.STATUS.field("bank_ready").get(accel.read(regs.STATUS))
    for b in range(regs.BANKS):
        if ready >> b & 1:
            accel.release(b)
    bank = accel.wait_frame(timeout)
    info = accel.read(regs.BANK0_INFO if bank == 0 else regs.BANK1_INFO)
    accel.release(bank)
    return regs.BANK0_INFO.field("frame").get(info)


def test_a_change_written_mid_frame_labels_each_frame_right(lumas: list[np.ndarray], tmp_path) -> None:
    frames = np.stack([colour_photo(name, W, H) for name in PHOTOS])
    with SimServer(frames, TINY.name, engine="fast", job_dir=tmp_path / "job") as srv, SocketBus(srv.address) as bus:
        g = bus.info["generics"]
        period = ((g["WIDTH_g"] + bus.info["h_blank"]) * g["HEIGHT_g"] + bus.info["v_blank"]) * bus.info["period_ns"]
        timeout = 3 * period * 1e-9
        accel = OrbAccel(bus)
        assert accel.records_params, "the simulated accelerator's register map predates the frames' parameters"
        configure(accel, STEPS[0])
        check_made_with(accel.settle(timeout), STEPS[0], lumas, "after settle")
        for old, new in itertools.pairwise(STEPS):
            number = sync(accel, timeout)
            # half a frame period on: the next frame has started with the old values
            assert not bus.wait_irq(0.5 * period * 1e-9), "a frame ended within half a period of the last"
            configure(accel, new)
            assert accel.written() == new
            in_flight = accel.next_frame(timeout)
            assert in_flight.number == (number + 1) & 0xFFFF, (number, in_flight.number)
            check_made_with(in_flight, old, lumas, "written mid-frame")
            assert in_flight.params != accel.written(), "the test proves nothing: the last write labels it alike"
            check_made_with(accel.next_frame(timeout), new, lumas, "the frames after the change")
