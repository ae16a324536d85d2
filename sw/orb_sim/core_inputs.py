# SPDX-License-Identifier: MIT
"""orb_core's run-time inputs of the selection (what orb_axil_regs drives in orb_accel_top), as the
core's tests and jobs set them: `selection` is "all" or "grid:BUDGET:COLSxROWS:LOW" (docs/spec.md
section 14), the spelling of orbtb's scoreboard."""

from __future__ import annotations

from golden_model.config import parse_cells
from golden_model.frameparams import FrameParams
from golden_model.latency import CORE_SPLIT
from golden_model.limits import SCALES_MAX

# idle clocks after a selection change before the next frame's first pixel: orb_core splits a new
# budget over the levels in CORE_SPLIT.at(scales) clocks (docs/latency.md), plus a margin for the
# registers before and after the split
SELECT_SETTLE = CORE_SPLIT.at(SCALES_MAX) + 15


def selection_text(mode: str, budget: int, cells: tuple[int, int], threshold_lo: int) -> str:
    """A selection ("all" or "grid" and its parameters: a model Config's or the driver's
    Selection's fields; cells = (columns, rows)) in this module's spelling."""
    return "all" if mode == "all" else f"grid:{budget}:{cells[0]}x{cells[1]}:{threshold_lo}"


def selection_params(selection: str, threshold: int, mode: str) -> FrameParams:
    """The parameters drive_selection (with `threshold` and `mode` on their inputs) gives orb_core:
    what a frame started under them carries in its end-of-frame beat (in `all`: budget 0, 8 x 6
    cells and threshold_lo = threshold, which the core ignores)."""
    kind, *arg = selection.split(":")
    if kind not in ("all", "grid") or (kind == "grid" and len(arg) != 3):
        raise ValueError(f"selection {selection!r}: expected all or grid:BUDGET:COLSxROWS:LOW")
    cols, rows = parse_cells(arg[1]) if arg else (8, 6)
    return FrameParams(threshold=threshold, threshold_lo=int(arg[2]) if arg else threshold, mode=mode,
                       selection=kind, budget=int(arg[0]) if arg else 0, cols=cols, rows=rows)  # fmt: skip


def drive_params(dut, params: FrameParams) -> None:
    """Set every run-time input of orb_core: threshold, mode_orb and the selection's."""
    dut.threshold.value = params.threshold
    dut.mode_orb.value = int(params.mode == "orb")
    dut.select_grid.value = int(params.selection == "grid")
    dut.budget.value = params.budget
    dut.grid_cols.value = params.cols
    dut.grid_rows.value = params.rows
    dut.threshold_lo.value = params.threshold_lo


def drive_selection(dut, selection: str, threshold: int) -> None:
    """Set orb_core's select_grid, budget, grid_cols, grid_rows and threshold_lo for `selection`
    (in `all`: budget 0, 8 x 6 cells and threshold_lo = threshold, which the core ignores)."""
    p = selection_params(selection, threshold, "orb")
    dut.select_grid.value = int(p.selection == "grid")
    dut.budget.value = p.budget
    dut.grid_cols.value = p.cols
    dut.grid_rows.value = p.rows
    dut.threshold_lo.value = p.threshold_lo
