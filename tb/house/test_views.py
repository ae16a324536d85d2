# SPDX-License-Identifier: MIT
"""The registry of generated views (orb_flow.gen.views, `make views`): every module of orb_flow.gen
but its helpers is a generator with render(root), the model's Python views are generated first,
each view has one generator and names it in its header, and every committed view is byte for byte
what its generator renders from the committed data."""

from __future__ import annotations

import pkgutil
from pathlib import Path

import orb_flow.gen
from orb_flow.gen import views
from orb_sim.hdl import ROOT


def test_registry_names_every_generator() -> None:
    found = {m.name for m in pkgutil.iter_modules(orb_flow.gen.__path__)} - set(views.HELPERS)
    order = views.generators()
    assert set(order) == found and len(order) == len(found)
    for name in order:
        assert callable(getattr(views.module(name), "render", None)), f"orb_flow.gen.{name} has no render(root)"
    # the generators of the Python views the model imports come first (pattern_vhdl reads pattern_data.py)
    assert order.index("pattern") < order.index("pattern_vhdl")
    firsts = [n for n in order if n in views.FIRST]
    assert list(order[: len(firsts)]) == firsts


def test_each_view_has_one_generator_and_says_so() -> None:
    seen: dict[Path, str] = {}
    for name in views.generators():
        for view in views.module(name).render(ROOT):
            assert view not in seen, f"{view} is written by orb_flow.gen.{seen[view]} and orb_flow.gen.{name}"
            seen[view] = name
            # in the header, or for a generated section of a page (orb_flow.gen.results) in its marker
            text = (ROOT / view).read_text()
            named = f"sw/orb_flow/gen/{name}.py" in text or f"orb_flow.gen.{name}" in text
            assert named, f"{view}'s header does not name its generator (sw/orb_flow/gen/{name}.py)"


def test_every_view_is_fresh() -> None:
    stale = [str(v) for v, text in views.render_all(ROOT).items() if (ROOT / v).read_bytes() != text.encode()]
    assert not stale, f"stale views (run `make views`): {stale}"
