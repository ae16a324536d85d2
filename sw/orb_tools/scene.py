# SPDX-License-Identifier: MIT
"""A textured 3D scene rendered by the project, with exact camera poses: the sequence of
`orb-accel trajectory-bench` (docs/evaluation.md, "Trajectory").

The scene is a set of textured rectangles (`Quad`: a corner, two edge vectors in metres, a
greyscale photograph stretched over it). A pinhole camera (`Camera`: fx = fy, the principal point
at the image centre, no distortion) renders it by inverse mapping: for every pixel the ray's
intersection with each quad's plane, the nearest one in front of the camera whose texture
coordinates fall inside it wins (a depth buffer). Each frame is rendered at `SUPERSAMPLE` times the
resolution and reduced by area averaging (no aliasing where a wall recedes), then gets Gaussian
noise of `noise` grey levels (seeded per frame). A stereo rig is two such cameras `baseline` metres
apart along the camera's x axis, both looking along its z axis (rectified, as a stereo SLAM's
input).

The canned scene `wall` is a diver swimming along a rock wall: the wall (the photographs, tiled),
the sea floor below, boulders between the two (boxes, each face a photograph), and a camera path
along the wall at half a metre a second with a slow sway in height and distance, yaw up to 25
degrees towards and away from the wall, pitch and some roll. Poses are camera-to-world (x right,
y down, z forward at the start), written in the TUM format (timestamp tx ty tz qx qy qz qw).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

SUPERSAMPLE = 2


@dataclass(frozen=True)
class Quad:
    """A textured rectangle: texture pixel (u, v) is at origin + u / w * edge_u + v / h * edge_v."""

    origin: np.ndarray
    edge_u: np.ndarray
    edge_v: np.ndarray
    texture: np.ndarray  # greyscale uint8


@dataclass(frozen=True)
class Camera:
    width: int
    height: int
    focal: float  # pixels

    @property
    def k(self) -> np.ndarray:
        return np.array([[self.focal, 0, (self.width - 1) / 2], [0, self.focal, (self.height - 1) / 2], [0, 0, 1.0]])


def rot_xyz(rx: float, ry: float, rz: float) -> np.ndarray:
    """Rotation matrix of angles in radians: R = Rz Ry Rx."""
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    r_x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    r_y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    r_z = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return r_z @ r_y @ r_x


def pose(r: np.ndarray, t: Sequence[float]) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = r
    m[:3, 3] = t
    return m


def render(quads: Sequence[Quad], cam: Camera, t_wc: np.ndarray, noise: float = 0.0, seed: int = 0,
           background: int = 40) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """(image uint8, depth in metres, inf where no quad) of the scene seen from camera-to-world pose t_wc."""
    s = SUPERSAMPLE
    w, h = cam.width * s, cam.height * s
    f = cam.focal * s
    img = np.full((h, w), float(background), dtype=np.float32)
    zbuf = np.full((h, w), np.inf, dtype=np.float32)
    r_wc, c = t_wc[:3, :3], t_wc[:3, 3]
    for q in quads:
        box = _window(q, cam, t_wc)
        if box is None:
            continue
        x0, x1, y0, y1 = (v * s for v in box)
        xs = (np.arange(x0, x1, dtype=np.float32) - (w - 1) / 2) / f
        ys = (np.arange(y0, y1, dtype=np.float32) - (h - 1) / 2) / f
        gx, gy = np.meshgrid(xs, ys)
        # the world direction of each pixel's ray R (x, y, 1), its depth along the optical axis lam
        n = np.cross(q.edge_u, q.edge_v)
        rn = (r_wc.T @ n).astype(np.float32)  # the plane's normal in camera coordinates
        denom = gx * rn[0] + gy * rn[1] + rn[2]
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = np.float32((q.origin - c) @ n) / denom
        # the hit point relative to the quad's origin, projected on its edges
        oc = c - q.origin
        eu = (r_wc.T @ q.edge_u / (q.edge_u @ q.edge_u)).astype(np.float32)
        ev = (r_wc.T @ q.edge_v / (q.edge_v @ q.edge_v)).astype(np.float32)
        a = np.float32(oc @ q.edge_u / (q.edge_u @ q.edge_u)) + lam * (gx * eu[0] + gy * eu[1] + eu[2])
        b = np.float32(oc @ q.edge_v / (q.edge_v @ q.edge_v)) + lam * (gx * ev[0] + gy * ev[1] + ev[2])
        zb = zbuf[y0:y1, x0:x1]
        ok = np.isfinite(lam) & (lam > 0.05) & (lam < zb) & (a >= 0) & (a < 1) & (b >= 0) & (b < 1)
        if not ok.any():
            continue
        th, tw = q.texture.shape
        sample = cv2.remap(
            q.texture,
            (a * tw - 0.5).astype(np.float32),
            (b * th - 0.5).astype(np.float32),
            cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REFLECT,
        )
        img[y0:y1, x0:x1][ok] = sample[ok]
        zb[ok] = lam[ok]
    small = cv2.resize(img, (cam.width, cam.height), interpolation=cv2.INTER_AREA)
    depth = zbuf[s // 2 :: s, s // 2 :: s][: cam.height, : cam.width].astype(np.float64)
    if noise > 0:
        small = small + np.random.default_rng(seed).normal(0.0, noise, small.shape).astype(np.float32)
    return np.clip(np.rint(small), 0, 255).astype(np.uint8), depth


def _window(q: Quad, cam: Camera, t_wc: np.ndarray) -> tuple[int, int, int, int] | None:
    """The image window (x0, x1, y0, y1) the quad may cover, None when it is certainly out of view
    (all behind the camera, or all its corners beyond one side of the image); the whole image when
    a corner is behind the camera."""
    corners = np.array([q.origin, q.origin + q.edge_u, q.origin + q.edge_v, q.origin + q.edge_u + q.edge_v])
    pc = (corners - t_wc[:3, 3]) @ t_wc[:3, :3]  # camera coordinates: R^T (X - c)
    z = pc[:, 2]
    if (z <= 0.05).all():
        return None
    if (z <= 0.05).any():
        return 0, cam.width, 0, cam.height
    u = cam.focal * pc[:, 0] / z + (cam.width - 1) / 2
    v = cam.focal * pc[:, 1] / z + (cam.height - 1) / 2
    x0, x1 = max(math.floor(u.min()) - 1, 0), min(math.ceil(u.max()) + 2, cam.width)
    y0, y1 = max(math.floor(v.min()) - 1, 0), min(math.ceil(v.max()) + 2, cam.height)
    if x0 >= x1 or y0 >= y1:
        return None
    return x0, x1, y0, y1


def tile_textures(photos: Sequence[np.ndarray], count: int, seed: int = 7, size: tuple[int, int] = (512, 384),
                  ) -> list[np.ndarray]:  # fmt: skip
    """`count` distinct textures from the photographs: random crops (half to nine tenths of a side),
    turned by a multiple of 90 degrees and maybe mirrored, resized to `size` (no two tiles alike, so
    that a repeated photograph does not make matches ambiguous)."""
    if not photos:
        raise ValueError("the scene needs at least one photograph for its textures")
    rng = np.random.default_rng(seed)
    out = []
    for i in range(count):
        img = photos[i % len(photos)]
        h, w = img.shape
        cw, ch = int(w * rng.uniform(0.5, 0.9)), int(h * rng.uniform(0.5, 0.9))
        x0, y0 = int(rng.integers(0, w - cw + 1)), int(rng.integers(0, h - ch + 1))
        crop = np.rot90(img[y0 : y0 + ch, x0 : x0 + cw], int(rng.integers(0, 4)))
        if rng.integers(0, 2):
            crop = crop[:, ::-1]
        out.append(cv2.resize(np.ascontiguousarray(crop), size, interpolation=cv2.INTER_AREA))
    return out


def _tile(textures: Sequence[np.ndarray], i: int) -> np.ndarray:
    return textures[i % len(textures)]


def wall_scene(textures: Sequence[np.ndarray], length: float = 12.0, seed: int = 3) -> list[Quad]:
    """The diver's wall: a wall at z = 4 m (tiles of 2 x 1.5 m), a floor at y = 1.6 m, boulders between."""
    if not textures:
        raise ValueError("the wall scene needs at least one texture (a photograph)")
    quads: list[Quad] = []
    tile_w, tile_h = 2.0, 1.5
    i = 0
    cols = math.ceil((length + 12) / tile_w)  # 6 m past either end: the view's width at the wall, turned
    for col in range(cols):
        for row in range(3):
            x0, y0 = -6.0 + col * tile_w, -2.9 + row * tile_h
            quads.append(Quad(np.array([x0, y0, 4.0]), np.array([tile_w, 0, 0]), np.array([0, tile_h, 0]),
                              _tile(textures, i)))  # fmt: skip
            i += 1
    for col in range(cols):
        for row in range(3):
            x0, z0 = -6.0 + col * tile_w, -0.5 + row * tile_w * 0.75
            quads.append(Quad(np.array([x0, 1.6, z0]), np.array([tile_w, 0, 0]), np.array([0, 0, tile_w * 0.75]),
                              _tile(textures, i)))  # fmt: skip
            i += 1
    rng = np.random.default_rng(seed)
    for k in range(int((length + 6) / 1.5)):
        x, z = -3.0 + k * 1.5 + rng.uniform(-0.3, 0.3), rng.uniform(2.6, 3.4)
        sx, sy, sz = rng.uniform(0.4, 0.8), rng.uniform(0.5, 1.1), rng.uniform(0.3, 0.6)
        y1 = 1.6  # standing on the floor
        y0 = y1 - sy
        # the front face (towards the camera), the top, and the two sides
        quads.append(Quad(np.array([x, y0, z]), np.array([sx, 0, 0]), np.array([0, sy, 0]), _tile(textures, i)))
        quads.append(Quad(np.array([x, y0, z]), np.array([sx, 0, 0]), np.array([0, 0, sz]), _tile(textures, i + 1)))
        quads.append(Quad(np.array([x, y0, z]), np.array([0, 0, sz]), np.array([0, sy, 0]), _tile(textures, i + 2)))
        quads.append(
            Quad(np.array([x + sx, y0, z]), np.array([0, 0, sz]), np.array([0, sy, 0]), _tile(textures, i + 3))
        )
        i += 4
    return quads


def wall_path(frames: int, fps: float = 30.0, speed: float = 0.5) -> list[np.ndarray]:
    """Camera-to-world poses of the swim along the wall at `speed` m/s, sampled at `fps`: x along the
    wall, a sway in height (0.25 m, a 6 s period) and in distance (0.3 m, 8 s), yaw towards and away
    from the wall up to 25 degrees (7 s), pitch 0 to 16 degrees down (5 s), roll up to 6 degrees (4 s)."""
    out = []
    tau = 2 * math.pi
    for i in range(frames):
        t = i / fps
        x = speed * t
        y = -0.3 + 0.25 * math.sin(tau * t / 6.0)
        z = 0.3 * math.sin(tau * t / 8.0 + 0.5)
        yaw = math.radians(25.0) * math.sin(tau * t / 7.0)
        pitch = math.radians(8.0) * math.sin(tau * t / 5.0 + 1.0) - math.radians(8.0)  # looking down
        roll = math.radians(6.0) * math.sin(tau * t / 4.0)
        out.append(pose(rot_xyz(pitch, yaw, roll), (x, y, z)))
    return out


def quaternion_wxyz(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix."""
    tr = np.trace(r)
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2]) * 2
        q = [(r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif r[1, 1] > r[2, 2]:
        s = math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2]) * 2
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s]
    else:
        s = math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1]) * 2
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q)


def write_tum(path: Path, stamps: Sequence[float], poses: Sequence[np.ndarray]) -> None:
    """TUM trajectory file: `timestamp tx ty tz qx qy qz qw` per line."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as fh:
        for t, m in zip(stamps, poses, strict=True):
            w, x, y, z = quaternion_wxyz(m[:3, :3])
            fh.write(f"{t:.6f} {m[0, 3]:.6f} {m[1, 3]:.6f} {m[2, 3]:.6f} {x:.9f} {y:.9f} {z:.9f} {w:.9f}\n")
