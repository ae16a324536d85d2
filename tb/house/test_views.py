# SPDX-License-Identifier: MIT
"""The registry of generated views (orb_flow.gen.views, `make views`): it names every generator of
orb_flow.gen, each view has one generator and names it in its header, and every committed view is
byte for byte what its generator renders from the committed data."""

from __future__ import annotations

import pkgutil
from pathlib import Path

import orb_flow.gen
from orb_flow.gen import views
from orb_sim.hdl import ROOT

HELPERS = {"codegen", "views"}  # modules of orb_flow.gen that are not generators


def test_registry_names_every_generator() -> None:
    found = {m.name for m in pkgutil.iter_modules(orb_flow.gen.__path__)} - HELPERS
    assert found == set(views.GENERATORS), "orb_flow.gen.views.GENERATORS must list every generator module"
    for name in views.GENERATORS:
        assert callable(getattr(views.module(name), "render", None)), f"orb_flow.gen.{name} has no render(root)"


def test_each_view_has_one_generator_and_says_so() -> None:
    seen: dict[Path, str] = {}
    for name in views.GENERATORS:
        for view in views.module(name).render(ROOT):
            assert view not in seen, f"{view} is written by orb_flow.gen.{seen[view]} and orb_flow.gen.{name}"
            seen[view] = name
            head = (ROOT / view).read_text()[:2000]
            assert f"sw/orb_flow/gen/{name}.py" in head, f"{view}'s header does not name sw/orb_flow/gen/{name}.py"


def test_every_view_is_fresh() -> None:
    stale = [str(v) for v, text in views.render_all(ROOT).items() if (ROOT / v).read_bytes() != text.encode()]
    assert not stale, f"stale views (run `make views`): {stale}"
