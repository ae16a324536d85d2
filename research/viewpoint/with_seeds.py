"""Run any `orb-accel` command with the model's orbit seeds replaced by a seed file's (README.md).

    .venv/bin/python -m research.viewpoint.with_seeds FILE scale-bench build/eval/held/640x480/*.png ...

The model's descriptor (golden_model.brief) then uses the file's seeds for every sector count in it,
exactly as `make pattern` would make it after the file replaced golden_model/data/orbit_seeds.json.
"""

from __future__ import annotations

import sys
from pathlib import Path

from orb_tools.cli import main

from .bench import use_seeds

if __name__ == "__main__":
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    use_seeds(Path(sys.argv[1]))
    raise SystemExit(main(sys.argv[2:]))
