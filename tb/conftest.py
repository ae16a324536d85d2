# SPDX-License-Identifier: MIT
"""Test order for `make test`: the long simulations first, so that two workers (pytest-xdist
`--dist load --maxschedchunk 1`, the Makefile's) finish together instead of one of them starting a
ten-minute simulation when the other has nothing left. The order changes nothing else: every test
is independent of the others (a simulation's build is shared only by the tests of its own worker,
which run one after the other, and is rebuilt when a source changes: docs/conventions.md).
"""

from __future__ import annotations

import pytest

# Node-id prefixes, longest simulations first (measured with `pytest --durations` on a fresh clone
# and with warm caches); everything else keeps pytest's order after them.
LONG_FIRST = (
    # two Verilator builds when the cache is cold (a fresh clone: 220 s), 20 s when warm
    "tb/fast/test_fast_sim.py::test_make_sim_fast_and_cli",
    "tb/top/test_orb_accel_top.py",
    "tb/fast/test_fast_sim.py::test_against_ghdl",
    "tb/top/test_orb_accel_zynq.py",
    "tb/fast/test_fast_ddr.py::test_ddr_frames",
    "tb/core/test_orb_core.py::test_recommended_configuration_densest_input",
    "tb/core/test_orb_core.py::test_grid_selection",
    "tb/core/test_orb_core.py",
    "tb/tools/test_sim_accel.py",
    "tb/driver/test_socket_bus.py",
    "tb/tools/test_cli_rtl.py",
    "tb/core/test_orb_core_axis.py",
    "tb/describe/test_orb_desc_path.py",
    "tb/tools/test_core_job.py",
    "tb/fast/test_fast_sim.py",
    "tb/fast/test_fast_ddr.py",
)


def _rank(nodeid: str) -> int:
    return next((i for i, prefix in enumerate(LONG_FIRST) if nodeid.startswith(prefix)), len(LONG_FIRST))


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    items.sort(key=lambda item: _rank(item.nodeid))  # stable: pytest's order within a rank
