# SPDX-License-Identifier: MIT
"""The run-time parameters a frame was processed with (docs/feature-memory.md, "Every frame says how
it was made").

orb_core samples the thresholds, the mode and the selection's parameters with each frame's first
pixel and carries them on the frame's end-of-frame beat into the end-of-frame record
(docs/feature-word.md: the beat's and the record's fields threshold, threshold_lo, mode_orb,
select_grid, budget, cols, rows). FrameParams is that set with the model's spellings (``mode``
"orb"/"fast", ``selection`` "grid"/"all"), the values as written: ``threshold_lo`` is
THRESHOLD.low even in ``all`` selection (which ignores it), ``budget``, ``cols`` and ``rows`` are
SELECT's fields in either selection. golden_model.featcodec packs and unpacks it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass

from .config import Config


@dataclass(frozen=True)
class FrameParams:
    """A frame's parameters as the hardware sampled them."""

    threshold: int
    threshold_lo: int
    mode: str  # "orb" (detect and describe) or "fast" (detection only)
    selection: str  # "grid" or "all"
    budget: int
    cols: int
    rows: int

    @classmethod
    def of(cls, cfg: Config) -> FrameParams:
        """The parameters a frame processed under the model configuration `cfg` carries, when
        they were written as `cfg` says (the driver's configure_as(cfg))."""
        return cls(cfg.threshold, int(cfg.threshold_lo or 0), cfg.mode, cfg.selection, cfg.budget, cfg.cols,
                   cfg.rows)  # fmt: skip

    def fields(self) -> dict[str, int]:
        """The end-of-frame beat's and record's field values (docs/feature-word.md)."""
        return {"threshold": self.threshold, "threshold_lo": self.threshold_lo, "mode_orb": int(self.mode == "orb"),
                "select_grid": int(self.selection == "grid"), "budget": self.budget, "cols": self.cols,
                "rows": self.rows}  # fmt: skip

    @classmethod
    def from_fields(cls, values: Mapping[str, int]) -> FrameParams:
        """From the fields of an end-of-frame beat or record (as golden_model.featcodec.unpack gives them)."""
        return cls(threshold=int(values["threshold"]), threshold_lo=int(values["threshold_lo"]),
                   mode="orb" if values["mode_orb"] else "fast", selection="grid" if values["select_grid"] else "all",
                   budget=int(values["budget"]), cols=int(values["cols"]), rows=int(values["rows"]))  # fmt: skip

    def text(self) -> str:
        """One line: "threshold 20, orb, grid 300 in 8x6 cells, low threshold 14" or "threshold 35, fast, all"."""
        sel = (f"grid {self.budget} in {self.cols}x{self.rows} cells, low threshold {self.threshold_lo}"
               if self.selection == "grid" else "all")  # fmt: skip
        return f"threshold {self.threshold}, {self.mode}, {sel}"

    def config(self, base: Config) -> Config:
        """`base` (the bitstream's shape) with this frame's parameters: the model configuration that
        reproduces the frame."""
        return dataclasses.replace(base, threshold=self.threshold, threshold_lo=self.threshold_lo, mode=self.mode,
                                   selection=self.selection, budget=self.budget, cols=self.cols,
                                   rows=self.rows)  # fmt: skip
