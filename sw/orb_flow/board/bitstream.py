#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""`make bitstream`: the Zybo Z7-20 build of one configuration (docs/board.md).

1. Checks before anything starts, all reported in one line, exit 2: Vivado on PATH (or VIVADO=),
   Digilent's vivado-library at VIVADO_LIBRARY (with the exact commands to fetch the pinned commit),
   dtc, a known configuration.
2. vivado -mode batch -source vivado/build.tcl (log: build/vivado/<config>/vivado.log): the .bit,
   the .hwh beside it, the .xsa and the reports.
3. package(): beside them, with the same stem, the byte-swapped .bit.bin that Linux's fpga_manager
   loads (sw/orb_flow/board/bit2bin.py) and the .dtbo that pynq.Overlay applies (the compiled
   vivado/linux/orb-accel-<config>-pynq.dtso; docs/pynq.md).
4. The yosys estimate of the same orb_accel_zynq (build/vivado/estimate/report.json, from
   `make board-estimate`) beside Vivado's figures, if it has been run.
5. sw/orb_flow/board/vivado_summary.py: summary.json, printed; exit 1 when timing is not met.

Usage: python3 -m orb_flow.board.bitstream [--config NAME] [--vivado-library DIR] [--board-repo DIR]
       [--vivado PATH] [--jobs N]   (plain python3)
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

from orb_flow.board import bit2bin, config_key

ROOT = Path(__file__).resolve().parents[3]
BOARD = ROOT / "vivado" / "board.json"
OUT = ROOT / "build" / "vivado"
ESTIMATE = OUT / "estimate" / "report.json"
HERE = Path(__file__).resolve().parent


def board() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(BOARD.read_text())
    return data


def fetch_hint(lib: dict[str, str], where: str) -> str:
    return f"git clone {lib['url']} {where} && git -C {where} checkout {lib['commit']} (then VIVADO_LIBRARY={where})"


def missing(config: str, vivado: str, library: str, dtc: str = "dtc") -> list[str]:
    """What stops the build before Vivado starts (empty: nothing)."""
    b = board()
    out = []
    if config not in b["configs"]:
        out.append(f"configuration {config!r} (known: {', '.join(b['configs'])})")
    if shutil.which(vivado) is None:
        out.append(f"Vivado ({vivado!r} not on PATH; Vivado {b['vivado_version']} ML Standard, or set VIVADO=)")
    if shutil.which(dtc) is None:
        out.append(f"the device-tree compiler ({dtc!r} not on PATH: apt-get install device-tree-compiler)")
    lib = b["vivado_library"]
    where = library or "../vivado-library"
    if not library:
        out.append(f"Digilent's vivado-library: VIVADO_LIBRARY is not set; fetch it: {fetch_hint(lib, where)}")
    elif not all((Path(library) / p).exists() for p in ("ip/dvi2rgb/component.xml", "ip/rgb2dvi/component.xml")):
        out.append(f"Digilent's vivado-library at {library} (no ip/dvi2rgb or ip/rgb2dvi): {fetch_hint(lib, where)}")
    return out


def stem(config: str) -> str:
    """The file stem every output of a configuration shares: orb_board_<config>."""
    return f"{board()['design_name']}_{config}"


def package(out: Path, config: str, dtc: str = "dtc") -> dict[str, Path]:
    """Beside the <stem>.bit and <stem>.hwh that vivado/build.tcl wrote into `out`, write <stem>.bit.bin
    (the .bit byte-swapped for the Zynq fpga_manager) and <stem>.dtbo (vivado/linux/orb-accel-<config>-pynq.dtso
    compiled): the files pynq.Overlay("<stem>.bit") reads (docs/pynq.md) and those of the plain UIO flow
    (docs/board.md). Returns them by suffix. FileNotFoundError naming a missing input, ValueError for a
    bad .bit, RuntimeError with dtc's message."""
    base = stem(config)
    files = {ext: out / f"{base}{ext}" for ext in (".bit", ".hwh", ".bit.bin", ".dtbo")}
    for ext in (".bit", ".hwh"):
        if not files[ext].is_file():
            raise FileNotFoundError(f"{files[ext]}: Vivado wrote no {ext} (vivado/build.tcl; see {out / 'vivado.log'})")
    files[".bit.bin"].write_bytes(bit2bin.bit_to_bin(files[".bit"].read_bytes()))
    src = ROOT / "vivado" / "linux" / f"orb-accel-{config}-pynq.dtso"
    proc = subprocess.run([dtc, "-@", "-I", "dts", "-O", "dtb", "-o", str(files[".dtbo"]), str(src)],
                          capture_output=True, text=True, check=False)  # fmt: skip
    if proc.returncode != 0:
        raise RuntimeError(f"dtc failed on {src}: {proc.stderr.strip()}")
    return files


def write_estimate(config: str, path: Path) -> Path | None:
    """The yosys record of this configuration's orb_accel_zynq, if `make board-estimate` ran."""
    if not ESTIMATE.exists():
        return None
    cfg = board()["configs"][config]
    for rec in json.loads(ESTIMATE.read_text()):
        g = rec.get("generics", {})
        key = (rec.get("top"), rec.get("width"), rec.get("height"), rec.get("scales"),
               int(g.get("STEP_NUM_g", 2)), int(g.get("STEP_DEN_g", 1)))  # fmt: skip
        if key == ("orb_accel_zynq", cfg["width"], cfg["height"], cfg["scales"], cfg["step_num"], cfg["step_den"]):
            path.write_text(json.dumps(rec, indent=1) + "\n")
            return path
    return None


def main(argv: list[str] | None = None) -> int:
    b = board()
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    names = ", ".join(f"{k} ({c['config']})" for k, c in b["configs"].items())
    ap.add_argument("--config", default=b["default_config"], help=f"one of {names}: a size or its named configuration")
    ap.add_argument("--vivado-library", default=os.environ.get("VIVADO_LIBRARY", ""))
    ap.add_argument(
        "--board-repo", default=os.environ.get("BOARD_REPO", ""), help="Digilent vivado-boards/new/board_files"
    )
    ap.add_argument("--vivado", default=os.environ.get("VIVADO", "vivado"))
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args(argv)
    try:
        args.config = config_key(b, args.config)
    except ValueError:
        pass  # missing() names the known ones

    stop = missing(args.config, args.vivado, args.vivado_library)
    if stop:
        print("make bitstream: missing " + "; ".join(stop), file=sys.stderr)
        return 2
    out = OUT / args.config
    out.mkdir(parents=True, exist_ok=True)
    cmd = [
        args.vivado, "-mode", "batch", "-notrace", "-log", str(out / "vivado.log"), "-journal", str(out / "vivado.jou"),
        "-source", str(ROOT / "vivado" / "build.tcl"), "-tclargs",
        "--config", args.config, "--vivado-library", str(Path(args.vivado_library).resolve()),
        "--out", str(out), "--jobs", str(args.jobs),
        *(["--board-repo", args.board_repo] if args.board_repo else []),
    ]  # fmt: skip
    print(" ".join(cmd))
    if subprocess.run(cmd, check=False).returncode != 0:
        print(f"make bitstream: Vivado failed, see {out / 'vivado.log'}", file=sys.stderr)
        return 1
    try:
        files = package(out, args.config)
    except (OSError, ValueError, RuntimeError) as exc:
        print(f"make bitstream: {exc}", file=sys.stderr)
        return 1
    print("beside each other: " + ", ".join(p.name for p in files.values()))
    summary = [sys.executable, "-m", "orb_flow.board.vivado_summary", str(out / "reports"), "--config", args.config]
    summary += ["--out", str(out / "summary.json")]
    est = write_estimate(args.config, out / "estimate.json")
    if est is not None:
        summary += ["--estimate", str(est)]
    else:
        print("(no yosys estimate beside it: run `make board-estimate` first)")
    return subprocess.run(summary, check=False).returncode


if __name__ == "__main__":
    sys.exit(main())
