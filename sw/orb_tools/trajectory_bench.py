# SPDX-License-Identifier: MIT
"""`orb-accel trajectory-bench`: the trajectory a visual odometry gets from each extractor's
features, against exact ground truth (docs/evaluation.md, "Trajectory").

The sequence is rendered by the project (orb_tools.scene: the diver along a rock wall, textured
with the photographs given, a rectified stereo pair per frame, the camera poses exact), or read
from a TUM RGB-D sequence a user passes (rgb.txt, depth.txt, groundtruth.txt: its depth images
give the 3D points). Every extractor runs through the same tracker (orb_tools.vo) at the same
feature budget: ours (the golden model, bit-exact with the fabric, with its grid selection),
OpenCV ORB's defaults (8 levels of 1.2, Harris ranking, `nfeatures` = the budget) and the
ORB-SLAM-style extractor (orb_tools.orbslam_extractor). ATE (absolute trajectory error, RMSE of
the positions after an SE(3) alignment, Umeyama, no scale: stereo and RGB-D are metric) and RPE
(relative pose error between consecutive frames: translation RMSE in metres and rotation RMSE in
degrees) come from PyPI's evo; lost frames (too few PnP inliers) are counted.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from . import orbslam_extractor as ox
from . import scale_bench as sb
from . import scene, vo

FPS = 30.0
SPEED = 0.5  # metres a second along the wall
SIZE = (640, 480)
FOCAL = 500.0  # pixels at 640 wide (a 65-degree horizontal field of view)
BASELINE = 0.12  # metres
NOISE = 2.0  # grey levels, Gaussian
TUM_DEPTH_SCALE = 5000.0  # TUM's depth PNGs: 5000 per metre
TUM_FR1 = (517.3, 516.5, 318.6, 255.3)  # fx fy cx cy of TUM's freiburg1 camera (its calibration page)


@dataclass
class Sequence_:
    name: str
    frames: list[vo.Frame]
    k: np.ndarray
    baseline: float
    stamps: np.ndarray
    truth: list[np.ndarray] | None  # camera-to-world of each frame (rendered); None: from `truth_file`
    truth_file: Path | None = None


def render_wall(photos: Sequence[np.ndarray], frames: int = 300, size: tuple[int, int] = SIZE,
                noise: float = NOISE, seed: int = 1,
                progress: Callable[[str], None] | None = None) -> Sequence_:  # fmt: skip
    """The diver's swim along the wall: `frames` stereo pairs at 30 fps and their exact poses."""
    w, h = size
    cam = scene.Camera(w, h, FOCAL * w / SIZE[0])
    poses = scene.wall_path(frames, FPS, SPEED)
    length = SPEED * frames / FPS
    quads = scene.wall_scene(scene.tile_textures(photos, 48 + 16 * math.ceil(length), seed=seed + 6), length)
    right = np.eye(4)
    right[0, 3] = BASELINE
    out = []
    t0 = time.perf_counter()
    for i, p in enumerate(poses):
        left, _ = scene.render(quads, cam, p, noise=noise, seed=seed * 100_003 + 2 * i)
        rimg, _ = scene.render(quads, cam, p @ right, noise=noise, seed=seed * 100_003 + 2 * i + 1)
        out.append(vo.Frame(left, right=rimg))
        if progress and (i + 1) % 25 == 0:
            progress(f"rendered {i + 1} of {frames} stereo frames ({time.perf_counter() - t0:.0f} s)")
    stamps = np.arange(frames) / FPS
    return Sequence_("wall", out, cam.k, BASELINE, stamps, poses)


def _tum_list(path: Path) -> list[tuple[float, str]]:
    out = []
    for line in path.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            t, name = line.split()[:2]
            out.append((float(t), name))
    return out


def load_tum(root: Path, frames: int = 0, intrinsics: tuple[float, float, float, float] = TUM_FR1) -> Sequence_:
    """A TUM RGB-D sequence: rgb.txt and depth.txt (associated within 20 ms), groundtruth.txt."""
    for name in ("rgb.txt", "depth.txt", "groundtruth.txt"):
        if not (root / name).is_file():
            raise ValueError(f"{root}: not a TUM RGB-D sequence (no {name})")
    rgb, depth = _tum_list(root / "rgb.txt"), _tum_list(root / "depth.txt")
    dt = np.array([t for t, _ in depth])
    out, stamps = [], []
    for t, name in rgb:
        j = int(np.argmin(np.abs(dt - t))) if len(dt) else -1
        if j < 0 or abs(dt[j] - t) > 0.02:
            continue
        img = cv2.imread(str(root / name), cv2.IMREAD_GRAYSCALE)
        d = cv2.imread(str(root / depth[j][1]), cv2.IMREAD_UNCHANGED)
        if img is None or d is None:
            raise ValueError(f"{root}: cannot read {name} or {depth[j][1]}")
        out.append(vo.Frame(img, depth=d.astype(np.float64) / TUM_DEPTH_SCALE))
        stamps.append(t)
        if frames and len(out) >= frames:
            break
    if len(out) < 2:
        raise ValueError(f"{root}: fewer than two associated RGB and depth frames")
    fx, fy, cx, cy = intrinsics
    k = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1.0]])
    return Sequence_(root.name, out, k, 0.0, np.array(stamps), None, root / "groundtruth.txt")


def extractor(name: str, budget: int) -> vo.Extract:
    """`orbslam`, `cv-default`, or one of ours (scale-bench's names, e.g. 5:4x5s32/g1000)."""
    if name == "orbslam":
        params = ox.OrbSlamParams(budget=budget)
        return lambda img: ox.extract(img, params)
    if name == "cv-default":
        orb = cv2.ORB_create(nfeatures=budget)

        def cv_default(img: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            kps, desc = orb.detectAndCompute(img, None)
            xy = np.array([k.pt for k in kps], dtype=np.float64).reshape(-1, 2)
            return xy[:, 0], xy[:, 1], desc if desc is not None else np.zeros((0, 32), np.uint8)

        return cv_default
    ext = sb.parse_extractor(name)
    if ext.kind != "ours":
        raise ValueError(f"extractor {name!r}: expected orbslam, cv-default or one of ours (NUM:DENxLEVELS...)")

    def ours(img: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        p = sb.extract_ours(img, ext)
        return p.x, p.y, p.desc

    return ours


def metrics(seq: Sequence_, track: vo.Track) -> dict[str, float]:
    """ATE RMSE (m), RPE translation RMSE (m) and rotation RMSE (degrees) per frame, by evo."""
    from evo.core import metrics as em
    from evo.core import sync
    from evo.core.trajectory import PoseTrajectory3D
    from evo.tools import file_interface

    est = PoseTrajectory3D(poses_se3=track.poses, timestamps=seq.stamps[: len(track.poses)])
    if seq.truth is not None:
        ref = PoseTrajectory3D(poses_se3=seq.truth[: len(track.poses)], timestamps=seq.stamps[: len(track.poses)])
    else:
        ref = file_interface.read_tum_trajectory_file(str(seq.truth_file))
    ref, est = sync.associate_trajectories(ref, est, max_diff=0.02)
    est.align(ref, correct_scale=False)
    ape = em.APE(em.PoseRelation.translation_part)
    ape.process_data((ref, est))
    out = {"ate_m": float(ape.get_statistic(em.StatisticsType.rmse))}
    for key, rel in (("rpe_m", em.PoseRelation.translation_part), ("rpe_deg", em.PoseRelation.rotation_angle_deg)):
        rpe = em.RPE(rel, delta=1, delta_unit=em.Unit.frames, all_pairs=False)
        rpe.process_data((ref, est))
        out[key] = float(rpe.get_statistic(em.StatisticsType.rmse))
    return out


def run(seq: Sequence_, names: Sequence[str], budget: int, out_dir: Path | None = None,
        progress: Callable[[str], None] | None = None) -> list[dict]:  # fmt: skip
    """One summary row per extractor; with out_dir, each one's trajectory (TUM) and the truth."""
    rows = []
    start = seq.truth[0] if seq.truth is not None else None
    if out_dir is not None and seq.truth is not None:
        scene.write_tum(out_dir / "truth.tum", seq.stamps, seq.truth)
    for name in names:
        t0 = time.perf_counter()
        track = vo.run(seq.frames, extractor(name, budget), seq.k, seq.baseline, start)
        m = metrics(seq, track)
        row = {"sequence": seq.name, "extractor": name, "budget": budget, "frames": len(seq.frames),
               "lost": len(track.lost), "ate_m": round(m["ate_m"], 4), "rpe_m": round(m["rpe_m"], 4),
               "rpe_deg": round(m["rpe_deg"], 3),
               "inliers": round(float(np.mean(track.inliers)) if track.inliers else 0.0, 1),
               "features": round(float(np.mean(track.features)), 1),
               "points": round(float(np.mean(track.points)), 1)}  # fmt: skip
        rows.append(row)
        if out_dir is not None:
            scene.write_tum(out_dir / f"{_file_name(name)}.tum", seq.stamps[: len(track.poses)], track.poses)
        if progress:
            progress(f"{seq.name} {name}: ATE {row['ate_m']} m, lost {row['lost']} ({time.perf_counter() - t0:.0f} s)")
    return rows


def _file_name(name: str) -> str:
    return name.replace("/", "_").replace(":", "-").replace("@", "_at_")


def plot(seq: Sequence_, out_dir: Path, names: Sequence[str], path: Path) -> None:
    """Top view (x, z) of the truth and of each extractor's trajectory (the TUM files in out_dir)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5))
    if seq.truth is not None:
        t = np.array([p[:3, 3] for p in seq.truth])
        ax.plot(t[:, 0], t[:, 2], "k-", lw=2, label="truth")
    for name in names:
        data = np.loadtxt(out_dir / f"{_file_name(name)}.tum", ndmin=2)
        ax.plot(data[:, 1], data[:, 3], label=name)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Visual odometry on {seq.name} (orb-accel trajectory-bench; not aligned)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
