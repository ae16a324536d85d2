# SPDX-License-Identifier: MIT
"""`orb-accel eval-photos OUT_DIR`: the held-out photographs of the selection evaluation.

32 photographs that are not in the project and were not used to choose any parameter (the list of
research/selection/photos.py, `held`): 20 of OpenCV's sample images (Debian package `opencv-doc`,
/usr/share/doc/opencv-doc/examples/data/) and 12 nature photographs of `mate-backgrounds`
(/usr/share/backgrounds/mate/nature/). Without root: `apt-get download opencv-doc
mate-backgrounds` into a cache directory (default build/eval/debian-cache; `--deb DIR` takes the two
.deb files from DIR instead), `dpkg-deb -x` of each into CACHE/<package>/, then

- OUT_DIR/native/<name>.png: each photograph as it is (colour kept, grey ones stay grey);
- OUT_DIR/<W>x<H>/<name>.png for 640x480, 1280x720 and 1920x1080: centre-cropped to the aspect
  ratio W:H, then resized with cv2.INTER_AREA when shrinking and cv2.INTER_CUBIC when enlarging
  (`fit`);
- OUT_DIR/photos.json: per photograph its package, version, path in the package and native size.

Idempotent: a .deb already in the cache is not downloaded again, a package already extracted is
not extracted again, a PNG that exists is not written again.

Dense and sparse scenes, as measured (2026-11-25): the model's candidates at 640x480, full contrast,
thresholds 20 and 7, 5 levels of 5:4 (the `candidates` column of `orb-accel density-bench`; main: those
at threshold 20, counted with golden_model.pipeline.candidates on the same frames). The densest
are board (37,385 candidates, 25,358 main), baboon (39,263 / 18,790), aloeL (34,684 / 13,890), the
aerial views aero1 and aero3 (28,000 to 32,000 / 9,700 to 12,500) and butterfly; the sparsest are
Storm (a sky: 24 candidates, none main), Blinds (3,987 candidates but 26 main: nearly all its corners
are low-contrast ones), stuff (1,117 / 218), FreshFlower (1,808 / 264), smarties (1,356 / 395) and
LadyBird (1,569 / 502). The textured nature photographs (Wood, RainDrops, GreenMeadow, Dune) hold
4,300 to 17,900 candidates, 750 to 4,050 of them main.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

PACKAGES = ("opencv-doc", "mate-backgrounds")
SIZES = ((640, 480), (1280, 720), (1920, 1080))
DEFAULT_CACHE = Path("build/eval/debian-cache")
OPENCV_DATA = "usr/share/doc/opencv-doc/examples/data/"
MATE_NATURE = "usr/share/backgrounds/mate/nature/"
HELD: tuple[tuple[str, str], ...] = tuple(("opencv-doc", OPENCV_DATA + f) for f in (
    "aero1.jpg", "aero3.jpg", "aloeL.jpg", "baboon.jpg", "basketball1.png", "board.jpg", "box_in_scene.png",
    "building.jpg", "butterfly.jpg", "fruits.jpg", "graf1.png", "home.jpg", "leuvenA.jpg", "messi5.jpg",
    "rubberwhale1.png", "smarties.png", "squirrel_cls.jpg", "stuff.jpg", "sudoku.png", "left.jpg",
)) + tuple(("mate-backgrounds", MATE_NATURE + f) for f in (
    "Aqua.jpg", "Blinds.jpg", "Dune.jpg", "FreshFlower.jpg", "Garden.jpg", "GreenMeadow.jpg", "LadyBird.jpg",
    "RainDrops.jpg", "Storm.jpg", "TwoWings.jpg", "Wood.jpg", "YellowFlower.jpg",
))  # fmt: skip


class PhotoSourceError(Exception):
    """The packages could not be fetched or read (one line for the user)."""


@dataclass(frozen=True)
class Deb:
    package: str
    version: str
    path: Path


def parse_control(text: str) -> dict[str, str]:
    """The fields of a Debian control paragraph (`dpkg-deb -f` output), continuation lines dropped."""
    fields: dict[str, str] = {}
    for line in text.splitlines():
        if line[:1] in (" ", "\t") or ":" not in line:
            continue
        key, _, value = line.partition(":")
        fields[key.strip()] = value.strip()
    return fields


def read_deb(path: Path) -> Deb:
    """Package name and version of a .deb (`dpkg-deb -f`)."""
    try:
        out = subprocess.run(["dpkg-deb", "-f", str(path), "Package", "Version"], capture_output=True, text=True,
                             check=True).stdout  # fmt: skip
    except FileNotFoundError:
        raise PhotoSourceError("dpkg-deb not found: it reads the .deb files (Debian package dpkg)") from None
    except subprocess.CalledProcessError as exc:
        raise PhotoSourceError(f"{path}: not a .deb dpkg-deb can read ({_last_line(exc.stderr)})") from None
    fields = parse_control(out)
    if "Package" not in fields:
        raise PhotoSourceError(f"{path}: no Package field")
    return Deb(fields["Package"], fields.get("Version", ""), path)


def _last_line(text: str | None) -> str:
    lines = [ln.strip() for ln in (text or "").splitlines() if ln.strip()]
    return lines[-1] if lines else "no message"


def find_debs(directory: Path, packages: tuple[str, ...] = PACKAGES) -> dict[str, Deb]:
    """The .deb of each wanted package in `directory` (the newest file when there are several)."""
    found: dict[str, Deb] = {}
    for path in sorted(directory.glob("*.deb"), key=lambda p: p.stat().st_mtime):
        deb = read_deb(path)
        if deb.package in packages:
            found[deb.package] = deb
    return found


def _how_to_provide(packages: tuple[str, ...]) -> str:
    files = " and ".join(f"{p}_*.deb" for p in packages)
    return (
        f"run `apt-get update` and retry, or pass --deb DIR with {files} (from `apt-get download {' '.join(packages)}`)"
    )


def download(cache: Path, packages: tuple[str, ...] = PACKAGES) -> None:
    """`apt-get download PACKAGES` into `cache` (no root needed)."""
    cache.mkdir(parents=True, exist_ok=True)
    try:
        r = subprocess.run(["apt-get", "download", *packages], cwd=cache, capture_output=True, text=True)
    except FileNotFoundError:
        raise PhotoSourceError(f"apt-get not found, cannot download {', '.join(packages)}: "
                               f"{_how_to_provide(packages)}") from None  # fmt: skip
    if r.returncode != 0:
        raise PhotoSourceError(f"`apt-get download {' '.join(packages)}` failed ({_last_line(r.stderr)}): "
                               f"{_how_to_provide(packages)}")  # fmt: skip


def get_debs(cache: Path, deb_dir: Path | None, packages: tuple[str, ...] = PACKAGES) -> dict[str, Deb]:
    """The packages' .deb files: from `deb_dir` when given, else from the cache, downloading what is missing."""
    if deb_dir is not None:
        if not deb_dir.is_dir():
            raise PhotoSourceError(f"--deb {deb_dir}: not a directory")
        found = find_debs(deb_dir, packages)
        missing = [p for p in packages if p not in found]
        if missing:
            raise PhotoSourceError(f"--deb {deb_dir}: no .deb of {', '.join(missing)} there "
                                   f"(`apt-get download {' '.join(missing)}` makes them)")  # fmt: skip
        return found
    found = find_debs(cache, packages) if cache.is_dir() else {}
    missing = tuple(p for p in packages if p not in found)
    if missing:
        download(cache, missing)
        found = find_debs(cache, packages)
        missing = tuple(p for p in packages if p not in found)
        if missing:
            raise PhotoSourceError(f"apt-get download left no .deb of {', '.join(missing)} in {cache}: "
                                   f"{_how_to_provide(missing)}")  # fmt: skip
    return found


def unpack(deb: Deb, cache: Path) -> Path:
    """`dpkg-deb -x` of the package into CACHE/<package>/ (once per version); the directory."""
    root = cache / deb.package
    stamp = root / ".unpacked"
    if stamp.is_file() and stamp.read_text() == deb.version:
        return root
    if root.exists():
        shutil.rmtree(root)
    tmp = cache / f".{deb.package}.partial"
    if tmp.exists():
        shutil.rmtree(tmp)
    tmp.mkdir(parents=True)
    r = subprocess.run(["dpkg-deb", "-x", str(deb.path), str(tmp)], capture_output=True, text=True)
    if r.returncode != 0:
        raise PhotoSourceError(f"dpkg-deb -x {deb.path} failed: {_last_line(r.stderr)}")
    tmp.rename(root)
    stamp.write_text(deb.version)
    return root


def crop_to_aspect(img: np.ndarray, width: int, height: int) -> np.ndarray:
    """The largest centred crop with the aspect ratio width:height (rounding down)."""
    ih, iw = img.shape[:2]
    if iw * height > ih * width:  # too wide
        cw = ih * width // height
        x0 = (iw - cw) // 2
        return img[:, x0 : x0 + cw]
    ch = iw * height // width
    y0 = (ih - ch) // 2
    return img[y0 : y0 + ch]


def fit(img: np.ndarray, width: int, height: int) -> np.ndarray:
    """Centre crop to the aspect ratio, then resize to width x height: INTER_AREA when shrinking,
    INTER_CUBIC when enlarging (a crop already of that size is returned as it is)."""
    crop = crop_to_aspect(img, width, height)
    if crop.shape[1] == width and crop.shape[0] == height:
        return np.ascontiguousarray(crop)
    interp = cv2.INTER_AREA if crop.shape[1] > width else cv2.INTER_CUBIC
    return cv2.resize(crop, (width, height), interpolation=interp)


def _write_png(path: Path, img: np.ndarray) -> None:
    """Write atomically (a partial file never looks done)."""
    tmp = path.with_name(f".{path.stem}.partial.png")
    if not cv2.imwrite(str(tmp), img):
        raise OSError(f"{path}: could not write the PNG")
    os.replace(tmp, path)


def photo_name(path: str) -> str:
    return Path(path).stem


def write_photos(roots: dict[str, Path], versions: dict[str, str], out_dir: Path,
                 sizes: tuple[tuple[int, int], ...] = SIZES,
                 held: tuple[tuple[str, str], ...] = HELD) -> list[dict]:  # fmt: skip
    """The native and fitted PNGs of every photograph and OUT_DIR/photos.json; the records."""
    dirs = {"native": out_dir / "native", **{f"{w}x{h}": out_dir / f"{w}x{h}" for w, h in sizes}}
    for d in dirs.values():
        d.mkdir(parents=True, exist_ok=True)
    records = []
    for package, rel in held:
        src = roots[package] / rel
        name = photo_name(rel)
        targets = {key: d / f"{name}.png" for key, d in dirs.items()}
        img = cv2.imread(str(src), cv2.IMREAD_UNCHANGED)
        if img is None:
            raise PhotoSourceError(f"{src}: missing or unreadable in package {package}")
        if not targets["native"].is_file():
            _write_png(targets["native"], img)
        for w, h in sizes:
            if not targets[f"{w}x{h}"].is_file():
                _write_png(targets[f"{w}x{h}"], fit(img, w, h))
        records.append({"name": name, "package": package, "version": versions.get(package, ""), "path": "/" + rel,
                        "width": int(img.shape[1]), "height": int(img.shape[0]),
                        "channels": 1 if img.ndim == 2 else int(img.shape[2])})  # fmt: skip
    text = json.dumps({"photos": records, "sizes": [f"{w}x{h}" for w, h in sizes]}, indent=1) + "\n"
    index = out_dir / "photos.json"
    if not index.is_file() or index.read_text() != text:
        index.write_text(text)
    return records


Sizes = tuple[tuple[int, int], ...]
Held = tuple[tuple[str, str], ...]


def make(out_dir: Path, cache: Path = DEFAULT_CACHE, deb_dir: Path | None = None, sizes: Sizes = SIZES,
         held: Held = HELD) -> list[dict]:  # fmt: skip
    """Everything `orb-accel eval-photos` does; the photo records."""
    packages = tuple(dict.fromkeys(p for p, _ in held))
    debs = get_debs(cache, deb_dir, packages)
    cache.mkdir(parents=True, exist_ok=True)
    roots = {p: unpack(d, cache) for p, d in debs.items()}
    return write_photos(roots, {p: d.version for p, d in debs.items()}, out_dir, sizes, held)
