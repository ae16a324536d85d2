# SPDX-License-Identifier: MIT
"""The registry of the generators of the generated views (docs/conventions.md): every module of
orb_flow.gen but the helpers below is a generator, with render(root) -> {repository-relative path:
text} and a main() that writes them. `make views` (python -m orb_flow.gen.views) runs each in a
process of its own, the generators of the model's Python views first, so a generator that reads
another's view through the model (pattern_vhdl reads golden_model/pattern_data.py) sees it fresh."""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parents[3]

HELPERS = ("codegen", "views")  # modules of orb_flow.gen that are no generators
# run first, in this order: the generators of Python views the model imports
FIRST = ("regmap", "featword", "limits", "configs", "pattern")


def module(name: str) -> ModuleType:
    return importlib.import_module(f"orb_flow.gen.{name}")


def generators() -> tuple[str, ...]:
    """Every generator of orb_flow.gen, in the order `make views` runs them."""
    names = {m.name for m in pkgutil.iter_modules([str(Path(__file__).parent)])} - set(HELPERS)
    return tuple(sorted(names, key=lambda n: (FIRST.index(n) if n in FIRST else len(FIRST), n)))


def render_all(root: Path = ROOT) -> dict[Path, str]:
    """Every generated view of root's data, keyed by its repository-relative path."""
    views: dict[Path, str] = {}
    for name in generators():
        views |= module(name).render(root)
    return views


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--list", action="store_true", help="print each generator and its views, write nothing")
    args = ap.parse_args(argv)
    if args.list:
        for name in generators():
            print(f"orb_flow.gen.{name}: " + " ".join(str(p) for p in module(name).render(ROOT)))
        return 0
    for name in generators():
        subprocess.run([sys.executable, "-m", f"orb_flow.gen.{name}"], check=True, cwd=ROOT)
    return 0


if __name__ == "__main__":
    sys.exit(main())
