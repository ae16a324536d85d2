# SPDX-License-Identifier: MIT
"""The record of one published latency (docs/latency.md); the generated golden_model.latency holds the data."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Latency:
    """One block's latency in clocks, from `meaning`'s input to its output. A fixed latency has
    `clocks`; one that depends on the generic `generic` (a count n of levels) is
    `per_level * n + plus`, and `clocks` is None. `parts` names the blocks a sum is made of, `page`
    the doc page (docs/<page>), `test` the test that measures it (None: not measured as a whole)."""

    name: str
    entity: str
    meaning: str
    page: str
    clocks: int | None = None
    parts: tuple[str, ...] = ()
    per_level: int = 0
    plus: int = 0
    generic: str | None = None
    test: str | None = None

    def at(self, n: int) -> int:
        """The latency for the generic's value n (a fixed latency ignores n)."""
        if self.clocks is not None:
            return self.clocks
        return self.per_level * n + self.plus
