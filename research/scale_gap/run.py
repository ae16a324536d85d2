"""Run named variants: .venv/bin/python -m research.scale_gap.run [--screen] NAME... (from the repository root)."""
import argparse, sys
from . import lib
from .variants import VARIANTS

ap = argparse.ArgumentParser()
ap.add_argument("--screen", action="store_true", help="perspective 0 only")
ap.add_argument("--no-cv", action="store_true")
ap.add_argument("names", nargs="+")
a = ap.parse_args()
sel = {}
for n in a.names:
    hits = {k: v for k, v in VARIANTS.items() if k == n or (n.endswith("*") and k.startswith(n[:-1]))}
    if not hits:
        sys.exit(f"unknown variant {n}")
    sel.update(hits)
lib.bench(sel, screen=a.screen, with_cv=not a.no_cv, out=lib.HERE / "results.jsonl", log=lambda s: print(s, flush=True))
