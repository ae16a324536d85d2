# SPDX-License-Identifier: MIT
"""`orb-accel eval-photos` (orb_tools.eval_photos) without a network: the centre crop and resize, the
control-field parsing, a whole run on two tiny .deb files built with `dpkg-deb --build`, its
idempotence, and the one-line errors when apt-get download fails or --deb lacks a package."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from orb_tools import eval_photos as ep

needs_dpkg = pytest.mark.skipif(shutil.which("dpkg-deb") is None, reason="dpkg-deb (Debian's dpkg) not installed")
HELD = (("opencv-doc", ep.OPENCV_DATA + "tiny.jpg"), ("mate-backgrounds", ep.MATE_NATURE + "Wide.png"))
SIZES = ((64, 48), (32, 18))


def _gradient(w: int, h: int) -> np.ndarray:
    """A colour image whose pixel tells its column and row (B = x, G = y, R = 7)."""
    yy, xx = np.mgrid[0:h, 0:w]
    return np.dstack([xx % 256, yy % 256, np.full((h, w), 7)]).astype(np.uint8)


def test_crop_to_aspect_takes_the_centre() -> None:
    wide = _gradient(200, 100)
    c = ep.crop_to_aspect(wide, 4, 3)  # 133 x 100, columns 33..165
    assert c.shape[:2] == (100, 133)
    assert int(c[0, 0, 0]) == 33 and int(c[0, -1, 0]) == 165
    tall = _gradient(90, 200)
    c = ep.crop_to_aspect(tall, 16, 9)  # 90 x 50, rows 75..124
    assert c.shape[:2] == (50, 90)
    assert int(c[0, 0, 1]) == 75 and int(c[-1, 0, 1]) == 124


def test_fit_interpolation_shrinks_by_area_and_enlarges_cubically() -> None:
    rng = np.random.default_rng(3)
    big = rng.integers(0, 256, (300, 400, 3), dtype=np.uint8)
    assert np.array_equal(ep.fit(big, 160, 120), cv2.resize(big, (160, 120), interpolation=cv2.INTER_AREA))
    assert not np.array_equal(ep.fit(big, 160, 120), cv2.resize(big, (160, 120), interpolation=cv2.INTER_LINEAR))
    small = rng.integers(0, 256, (30, 40), dtype=np.uint8)
    assert np.array_equal(ep.fit(small, 160, 120), cv2.resize(small, (160, 120), interpolation=cv2.INTER_CUBIC))
    assert not np.array_equal(ep.fit(small, 160, 120), cv2.resize(small, (160, 120), interpolation=cv2.INTER_AREA))
    assert ep.fit(big, 400, 300) is not big and np.array_equal(ep.fit(big, 400, 300), big), "same size: unchanged"
    wide = _gradient(200, 100)
    assert ep.fit(wide, 16, 9).shape == (9, 16, 3)


def test_parse_control() -> None:
    text = "Package: opencv-doc\nVersion: 4.6.0+dfsg-12\nDescription: docs\n more text: here\n\tand: more\n"
    assert ep.parse_control(text) == {"Package": "opencv-doc", "Version": "4.6.0+dfsg-12", "Description": "docs"}
    assert ep.parse_control("") == {}


def _fake_deb(tmp: Path, package: str, version: str, files: dict[str, np.ndarray]) -> Path:
    root = tmp / f"src-{package}"
    (root / "DEBIAN").mkdir(parents=True)
    (root / "DEBIAN" / "control").write_text(
        f"Package: {package}\nVersion: {version}\nArchitecture: all\nMaintainer: test <t@example.org>\n"
        f"Description: a test package\n"
    )
    for rel, img in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        assert cv2.imwrite(str(root / rel), img)
    debs = tmp / "debs"
    debs.mkdir(exist_ok=True)
    out = debs / f"{package}_{version}_all.deb"
    subprocess.run(["dpkg-deb", "-Znone", "--root-owner-group", "--build", str(root), str(out)], check=True,
                   capture_output=True)  # fmt: skip
    return out


@pytest.fixture()
def debs(tmp_path: Path) -> Path:
    _fake_deb(tmp_path, "opencv-doc", "1.0", {HELD[0][1]: _gradient(80, 60)})
    grey = cv2.cvtColor(_gradient(100, 40), cv2.COLOR_BGR2GRAY)
    _fake_deb(tmp_path, "mate-backgrounds", "2.1", {HELD[1][1]: grey})
    return tmp_path / "debs"


@needs_dpkg
def test_run_on_fake_debs_is_idempotent(tmp_path: Path, debs: Path) -> None:
    found = ep.find_debs(debs)
    assert {p: d.version for p, d in found.items()} == {"opencv-doc": "1.0", "mate-backgrounds": "2.1"}
    out, cache = tmp_path / "out", tmp_path / "cache"
    records = ep.make(out, cache, debs, SIZES, HELD)
    assert [(r["name"], r["package"], r["version"], r["path"], r["width"], r["height"], r["channels"])
            for r in records] == [("tiny", "opencv-doc", "1.0", "/" + HELD[0][1], 80, 60, 3),
                                  ("Wide", "mate-backgrounds", "2.1", "/" + HELD[1][1], 100, 40, 1)]  # fmt: skip
    index = json.loads((out / "photos.json").read_text())
    assert [r["name"] for r in index["photos"]] == ["tiny", "Wide"] and index["sizes"] == ["64x48", "32x18"]
    jpeg = cv2.imread(str(cache / "opencv-doc" / HELD[0][1]), cv2.IMREAD_UNCHANGED)  # as unpacked (lossy)
    assert jpeg.shape == (60, 80, 3) and np.abs(jpeg.astype(int) - _gradient(80, 60)).max() < 16
    native = cv2.imread(str(out / "native" / "tiny.png"), cv2.IMREAD_UNCHANGED)
    assert np.array_equal(native, jpeg), "native: as it is, colour kept"
    assert cv2.imread(str(out / "native" / "Wide.png"), cv2.IMREAD_UNCHANGED).ndim == 2, "grey stays grey"
    fitted = cv2.imread(str(out / "64x48" / "tiny.png"), cv2.IMREAD_UNCHANGED)
    assert np.array_equal(fitted, ep.fit(jpeg, 64, 48))
    assert cv2.imread(str(out / "32x18" / "Wide.png"), cv2.IMREAD_UNCHANGED).shape == (18, 32)
    stamp = cache / "opencv-doc" / ".unpacked"
    assert stamp.read_text() == "1.0"
    before = {p: p.stat().st_mtime_ns for p in [*out.rglob("*.png"), out / "photos.json", stamp]}
    ep.make(out, cache, debs, SIZES, HELD)
    assert {p: p.stat().st_mtime_ns for p in before} == before, "a second run rewrites nothing"
    (out / "32x18" / "tiny.png").unlink()
    ep.make(out, cache, debs, SIZES, HELD)
    assert (out / "32x18" / "tiny.png").is_file(), "what is missing is made again"


@needs_dpkg
def test_deb_dir_missing_a_package(tmp_path: Path, debs: Path) -> None:
    (next(debs.glob("mate-backgrounds_*.deb"))).unlink()
    with pytest.raises(ep.PhotoSourceError, match=r"no \.deb of mate-backgrounds"):
        ep.make(tmp_path / "out", tmp_path / "cache", debs, SIZES, HELD)


def _failing_apt(tmp_path: Path) -> dict[str, str]:
    """An environment whose apt-get fails as it does without package lists."""
    bindir = tmp_path / "bin"
    bindir.mkdir()
    apt = bindir / "apt-get"
    apt.write_text("#!/bin/sh\necho 'E: Unable to locate package opencv-doc' >&2\nexit 100\n")
    apt.chmod(0o755)
    return {**os.environ, "PATH": f"{bindir}{os.pathsep}{os.environ['PATH']}"}


@needs_dpkg
def test_download_failure_is_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    env = _failing_apt(tmp_path)
    monkeypatch.setenv("PATH", env["PATH"])
    with pytest.raises(ep.PhotoSourceError) as exc:
        ep.make(tmp_path / "out", tmp_path / "cache")
    msg = str(exc.value)
    assert "opencv-doc" in msg and "mate-backgrounds" in msg and "apt-get update" in msg and "--deb" in msg
    assert "Unable to locate package" in msg and "\n" not in msg
    r = subprocess.run([sys.executable, "-m", "orb_tools.cli", "eval-photos", str(tmp_path / "out"), "--cache",
                        str(tmp_path / "cache")], capture_output=True, text=True, env=env, timeout=120)  # fmt: skip
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "apt-get update" in r.stderr, r.stderr
    assert not (tmp_path / "out" / "photos.json").exists()
