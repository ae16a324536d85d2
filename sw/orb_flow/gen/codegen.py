# SPDX-License-Identifier: MIT
"""Shared helpers of the generators in orb_flow.gen (one source per shared fact, several views):
text formatting for the VHDL and Python views, and the common command line that writes every
view of a source under a root folder (the repository, or a temporary folder for the byte checks
of the tests)."""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TypeVar

T = TypeVar("T")


def align_colons(lines: list[str]) -> list[str]:
    """Pad the names of consecutive constant declarations so their colons line up (vsg's rule)."""
    out: list[str] = []
    group: list[tuple[str, str]] = []

    def flush() -> None:
        width = max((len(n) for n, _ in group), default=0)
        out.extend(f"  constant {n.ljust(width)} :{rest}" for n, rest in group)
        group.clear()

    for line in lines:
        if line.startswith("  constant "):
            name, _, rest = line.removeprefix("  constant ").partition(" :")
            group.append((name, rest))
        else:
            flush()
            out.append(line)
    flush()
    return out


def pystr(s: str) -> str:
    """A string literal the way ruff format writes it (double quotes unless that needs escapes)."""
    if '"' in s and "'" not in s:
        return "'" + s.replace("\\", "\\\\") + "'"
    return json.dumps(s, ensure_ascii=False)


def write_views(views: Mapping[Path, str], root: Path) -> None:
    """Write each view (text keyed by its repository-relative path) under root, byte for byte, UTF-8."""
    for rel, text in views.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(text.encode())
        print(f"wrote {path}")


def views_main(doc: str | None, render: Callable[[Path], Mapping[Path, str]], root: Path,
               argv: Sequence[str] | None = None) -> None:  # fmt: skip
    """The command line of a generator that reads its source from the repository: --root (the
    repository holding the data) and --out (where the views go, default --root)."""
    ap = argparse.ArgumentParser(description=(doc or "").split("\n\n")[0])
    ap.add_argument("--root", type=Path, default=root, help="repository holding the data (default: this one)")
    ap.add_argument("--out", type=Path, default=None, help="root directory of the views (default: --root)")
    args = ap.parse_args(argv)
    write_views(render(args.root), args.out or args.root)


def render_views(data: T, outputs: Mapping[str, Path], renderers: Mapping[str, Callable[[T], str]]) -> dict[Path, str]:
    """The views of one source's loaded data: outputs[key] (a repository-relative path) gets
    renderers[key](data)."""
    return {outputs[key]: render(data) for key, render in renderers.items()}


def file_main(doc: str, out: Path, text: Callable[[], str]) -> None:
    """The command line of a generator of one file: --out FILE (default: the view in the repository)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=out, help="the file to write (default: the view in the repository)")
    args = ap.parse_args()
    args.out.write_text(text())
    print(f"wrote {args.out}")


def generator_main(doc: str, what: str, data: Path, root: Path,
                   render: Callable[[Path], Mapping[Path, str]]) -> None:  # fmt: skip
    """The command line of a generator: --data (the source) and --out (root of the views);
    render(data) gives the views keyed by their repository-relative paths."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--data", type=Path, default=data, help=f"{what} data (JSON)")
    ap.add_argument("--out", type=Path, default=root, help="root directory of the outputs (default: the repository)")
    args = ap.parse_args()
    write_views(render(args.data), args.out)
