# SPDX-License-Identifier: MIT
"""The cases of sw/orb_flow/netlist_sim.py (`make netlist-sim`) name pytest nodes that exist and
entities of the manifest: a renamed test or parameter fails here, not in a 15-minute run."""

from __future__ import annotations

import subprocess
import sys

from orb_flow import netlist_sim
from orb_sim.hdl import ROOT, entities


def test_netlist_cases_name_real_tests_and_entities() -> None:
    cases = list(netlist_sim.CASES)
    assert cases, "no netlist cases"
    unknown = sorted({c.entity for c in cases} - set(entities()))
    assert not unknown, f"netlist cases of entities not in the manifest: {unknown}"
    nodes = [f"tb/{c.test}" for c in cases]
    r = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider", *nodes],
                       cwd=ROOT, capture_output=True, text=True, check=False)  # fmt: skip
    assert r.returncode == 0, f"a netlist case names no test:\n{r.stdout[-3000:]}\n{r.stderr[-2000:]}"
    collected = {line.strip() for line in r.stdout.splitlines() if "::" in line}
    missing = [n for n in nodes if n not in collected]
    assert not missing, f"netlist cases not collected: {missing}"
