# SPDX-License-Identifier: MIT
"""orb_sim.runner's build reuse (docs/conventions.md, "Tests"): one build directory per toplevel,
back end and worker, built again when the stamp of the sources' contents changes; the generics go to
`ghdl -r`, so two generic sets share a build. The stamp and the directory key are checked here; the
cocotb tests of tb/ run every generic set on such shared builds (a wrong generic would fail them)."""

from __future__ import annotations

from pathlib import Path

from orb_sim import runner


def test_the_stamp_follows_contents_toplevel_back_end_and_waves(tmp_path: Path) -> None:
    a, b = tmp_path / "a.vhd", tmp_path / "b.vhd"
    a.write_text("entity a is end;\n")
    b.write_text("entity b is end;\n")
    base = runner.build_stamp("a", "llvm", [a, b], False)
    assert base == runner.build_stamp("a", "llvm", [a, b], False), "the stamp is not reproducible"
    others = {
        "toplevel": runner.build_stamp("b", "llvm", [a, b], False),
        "back end": runner.build_stamp("a", "mcode", [a, b], False),
        "waves": runner.build_stamp("a", "llvm", [a, b], True),
        "file order": runner.build_stamp("a", "llvm", [b, a], False),
        "file set": runner.build_stamp("a", "llvm", [a], False),
    }
    for what, stamp in others.items():
        assert stamp != base, f"the stamp does not change with the {what}"
    b.write_text("entity b is end; -- edited\n")
    assert runner.build_stamp("a", "llvm", [a, b], False) != base, "an edited source keeps the old stamp"


def test_the_stamp_covers_every_source_of_the_manifest() -> None:
    files = runner.sources()
    assert files and all(Path(f).is_file() for f in files)
    assert len(runner.build_stamp("orb_core", "llvm", files, False)) == 40
