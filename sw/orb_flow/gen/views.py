# SPDX-License-Identifier: MIT
"""The registry of the generators of the generated views (docs/conventions.md): `make views`
(python -m orb_flow.gen.views) runs each, in this order, in a process of its own, so a generator
that reads another's view through the model (pattern_vhdl reads golden_model/pattern_data.py)
sees it fresh. Each generator module has render(root) -> {repository-relative path: text} and a
main() that writes them."""

from __future__ import annotations

import argparse
import importlib
import subprocess
import sys
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parents[3]

# orb_flow.gen.<name>, in the order they run (pattern before pattern_vhdl)
GENERATORS = ("regmap", "featword", "limits", "pattern", "pattern_vhdl", "board", "core")


def module(name: str) -> ModuleType:
    return importlib.import_module(f"orb_flow.gen.{name}")


def render_all(root: Path = ROOT) -> dict[Path, str]:
    """Every generated view of root's data, keyed by its repository-relative path."""
    views: dict[Path, str] = {}
    for name in GENERATORS:
        views |= module(name).render(root)
    return views


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--list", action="store_true", help="print each generator and its views, write nothing")
    args = ap.parse_args(argv)
    if args.list:
        for name in GENERATORS:
            print(f"orb_flow.gen.{name}: " + " ".join(str(p) for p in module(name).render(ROOT)))
        return 0
    for name in GENERATORS:
        subprocess.run([sys.executable, "-m", f"orb_flow.gen.{name}"], check=True, cwd=ROOT)
    return 0


if __name__ == "__main__":
    sys.exit(main())
