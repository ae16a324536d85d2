# SPDX-License-Identifier: MIT
"""The whole model, frame in, features out: border rules, scales, errors, rotation and a naive reference."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from golden_model import Config, ConfigError, Features, extract
from golden_model.features import NO_SECTOR

PHOTOS = ("astronaut", "camera", "coffee", "chelsea")
NS = (4, 8, 16)
DOT = 200  # an isolated dot of DOT on 0 is a corner with all 16 ring pixels darker: score 16 * DOT
DOT_SCORE = 16 * DOT

Key = tuple[int, int, int]  # (scale, x, y)


def dots(w: int, h: int, points: dict[tuple[int, int], int]) -> np.ndarray:
    img = np.zeros((h, w), dtype=np.uint8)
    for (x, y), v in points.items():
        img[y, x] = v
    return img


def run(img: np.ndarray, **kw) -> Features:
    h, w = img.shape
    return extract(img, Config(width=w, height=h, **kw))


def positions(f: Features) -> list[tuple[int, int]]:
    """(x, y) of the features, in the list's order."""
    return list(zip(f.x.tolist(), f.y.tolist(), strict=True))


def in_orb_border(x: int, y: int, w: int, h: int) -> bool:
    return 18 <= x <= w - 19 and 18 <= y <= h - 19


def assert_matches_reference(ref, f: Features, img: np.ndarray, scales: int, n: int, t: int, mode: str) -> None:
    got = ref.rows(f)
    expected = ref.extract(img, scales, n, t, mode)
    assert got == expected, ref.rows_diff(got, expected)


# ---- border rules --------------------------------------------------------------------------------


def test_fast_mode_reports_corners_three_pixels_from_the_border() -> None:
    w, h = 64, 48
    corners = [(3, 3), (w - 4, 3), (3, h - 4), (w - 4, h - 4)]
    too_close = [(2, 20), (w - 3, 20), (20, 2), (30, h - 3)]
    img = dots(w, h, dict.fromkeys(corners + too_close, DOT))
    f = run(img, mode="fast", threshold=20)
    assert positions(f) == corners
    assert f.score.tolist() == [DOT_SCORE] * 4 and f.sector.tolist() == [NO_SECTOR] * 4
    assert f.descriptor.shape == (4, 0) and f.scale.tolist() == [0] * 4
    assert len(run(img, mode="orb", threshold=20)) == 0, "all of them are outside the orb border"


def test_orb_mode_reports_only_features_inside_the_descriptor_border() -> None:
    w, h = 96, 80  # orb border: 18 <= x <= 77, 18 <= y <= 61
    pts = {
        (17, 30): False, (18, 40): True,  # left
        (77, 30): True, (78, 40): False,  # right
        (30, 17): False, (40, 18): True,  # top
        (30, 61): True, (40, 62): False,  # bottom
        (18, 18): True, (77, 61): True, (62, 70): False, (50, 50): True,
    }  # fmt: skip
    img = dots(w, h, dict.fromkeys(pts, DOT))
    fast = run(img, mode="fast")
    orb = run(img, mode="orb")
    raster = sorted(pts, key=lambda p: (p[1], p[0]))
    assert positions(fast) == raster
    assert positions(orb) == [p for p in raster if pts[p]]
    assert all(in_orb_border(x, y, w, h) == pts[(x, y)] for x, y in pts), "the table above is the rule"
    assert orb.score.tolist() == [DOT_SCORE] * len(orb) and orb.descriptor.shape == (len(orb), 32)


@pytest.mark.parametrize("seed", range(3))
def test_orb_features_are_the_fast_survivors_inside_the_border(seed: int) -> None:
    img = np.random.default_rng(seed).integers(0, 256, (60, 80), dtype=np.uint8)
    fast, orb = run(img, mode="fast", threshold=30), run(img, mode="orb", threshold=30)
    fast_rows = zip(fast.x.tolist(), fast.y.tolist(), fast.score.tolist(), strict=True)
    expected = [(x, y, s) for x, y, s in fast_rows if in_orb_border(x, y, 80, 60)]
    assert list(zip(orb.x.tolist(), orb.y.tolist(), orb.score.tolist(), strict=True)) == expected
    assert len(expected) > 10


# (points, fast survivors, orb features): a corner outside the orb border suppresses one inside.
W, H, Y0, X0 = 96, 80, 40, 50
SUPPRESSION_CASES = {
    "left-equal": ({(17, Y0): DOT, (18, Y0): DOT}, [(17, Y0)], []),
    "left-weaker-inside": ({(17, Y0): DOT, (18, Y0): DOT // 2}, [(17, Y0)], []),
    "left-control": ({(18, Y0): DOT}, [(18, Y0)], [(18, Y0)]),
    "top-equal": ({(X0, 17): DOT, (X0, 18): DOT}, [(X0, 17)], []),
    "top-left-diagonal": ({(17, 17): DOT, (18, 18): DOT}, [(17, 17)], []),
    "top-right-diagonal": ({(X0 + 1, 17): DOT, (X0, 18): DOT}, [(X0 + 1, 17)], []),
    "right-stronger-outside": ({(W - 19, Y0): DOT // 2, (W - 18, Y0): DOT}, [(W - 18, Y0)], []),
    "right-equal": ({(W - 19, Y0): DOT, (W - 18, Y0): DOT}, [(W - 19, Y0)], [(W - 19, Y0)]),
    "bottom-stronger-outside": ({(X0, H - 19): DOT // 2, (X0, H - 18): DOT}, [(X0, H - 18)], []),
    "bottom-equal": ({(X0, H - 19): DOT, (X0, H - 18): DOT}, [(X0, H - 19)], [(X0, H - 19)]),
}


@pytest.mark.parametrize("case", list(SUPPRESSION_CASES))
def test_corner_outside_the_orb_border_still_suppresses_inside(case: str) -> None:
    pts, fast_expected, orb_expected = SUPPRESSION_CASES[case]
    img = dots(W, H, pts)
    assert positions(run(img, mode="fast")) == fast_expected, f"{case}: fast-mode survivors"
    assert positions(run(img, mode="orb")) == orb_expected, f"{case}: orb-mode features"


# ---- special images ------------------------------------------------------------------------------


@pytest.mark.parametrize("mode", ["orb", "fast"])
@pytest.mark.parametrize("t", [0, 20, 255])
@pytest.mark.parametrize("value", [0, 128, 255])
def test_flat_image_has_no_features(mode: str, t: int, value: int) -> None:
    f = run(np.full((48, 64), value, dtype=np.uint8), mode=mode, threshold=t, scales=4)
    assert len(f) == 0
    assert f.descriptor.shape == (0, 32 if mode == "orb" else 0)


@pytest.mark.parametrize(
    ("mode", "t", "n", "lo", "hi", "seed"),
    [("orb", 20, 8, 0, 256, 0), ("fast", 20, 8, 0, 256, 1), ("orb", 0, 4, 0, 4, 2), ("orb", 0, 16, 0, 3, 3),
     ("fast", 1, 8, 0, 6, 6), ("orb", 60, 16, 0, 256, 4)],
)  # fmt: skip
def test_smallest_legal_frame_against_naive_reference(ref, mode: str, t: int, n: int, lo: int, hi: int, seed: int):
    img = np.random.default_rng(seed).integers(lo, hi, (48, 64), dtype=np.uint8)
    f = run(img, mode=mode, threshold=t, sectors=4 * n)
    assert len(f) > 0
    assert_matches_reference(ref, f, img, 1, n, t, mode)


@pytest.mark.parametrize("mode", ["orb", "fast"])
def test_four_scales_of_the_smallest_frame_against_naive_reference(ref, mode: str) -> None:
    # Scales 1..3 are 32x24, 16x12 and 8x6: too small for the orb border, and 8x6 even for FAST.
    rng = np.random.default_rng(5)
    img = np.kron(rng.integers(0, 256, (12, 16)), np.ones((4, 4), dtype=np.int64)).astype(np.uint8)
    img = (img.astype(np.int64) + rng.integers(0, 30, img.shape)).clip(0, 255).astype(np.uint8)
    f = run(img, mode=mode, threshold=15, scales=4)
    assert_matches_reference(ref, f, img, 4, 8, 15, mode)
    if mode == "fast":
        assert set(f.scale.tolist()) >= {0, 1, 2}, "FAST finds corners on scales 1 and 2 too"
        assert 3 not in f.scale.tolist()
    else:
        assert set(f.scale.tolist()) == {0}


@pytest.mark.parametrize("n", NS)
def test_photograph_crop_with_two_scales_against_naive_reference(ref, photographs, n: int) -> None:
    name = {4: "astronaut", 8: "camera", 16: "chelsea"}[n]
    img = ref.center_crop(photographs[name], 128, 96)
    f = run(img, scales=2, sectors=4 * n, threshold=10)
    assert (f.scale == 1).any() and (f.scale == 0).any()
    assert_matches_reference(ref, f, img, 2, n, 10, "orb")


def test_one_pixel_checkerboard_against_naive_reference(ref) -> None:
    # Only 4 of 16 ring pixels (dx + dy odd) differ from the centre: no corner anywhere.
    img = (np.indices((48, 64)).sum(axis=0) % 2 * 255).astype(np.uint8)
    for mode in ("fast", "orb"):
        f = run(img, mode=mode, threshold=0, scales=2)
        assert_matches_reference(ref, f, img, 2, 8, 0, mode)
        assert len(f) == 0


@pytest.mark.parametrize("block", [2, 3, 4, 5])
def test_block_checkerboards_against_naive_reference(ref, block: int) -> None:
    cells = np.indices((48 // block + 1, 64 // block + 1)).sum(axis=0) % 2
    img = (np.kron(cells, np.ones((block, block), dtype=np.int64))[:48, :64] * 200 + 20).astype(np.uint8)
    for mode in ("fast", "orb"):
        f = run(img, mode=mode, threshold=10, sectors=16)
        assert_matches_reference(ref, f, img, 1, 4, 10, mode)


def test_dot_grid_every_dot_is_a_feature(ref) -> None:
    # Dots every 4 pixels: no dot lies on another's ring (the ring has |dx| or |dy| = 3 or (2, 2) offsets
    # not both multiples of 4), so each dot is a corner with score 16 * DOT and nothing else is.
    w, h = 64, 48
    grid = [(x, y) for y in range(4, h - 3, 4) for x in range(4, w - 3, 4)]
    img = dots(w, h, dict.fromkeys(grid, DOT))
    fast = run(img, mode="fast", threshold=20)
    assert positions(fast) == grid and len(grid) == 15 * 11
    assert fast.score.tolist() == [DOT_SCORE] * len(grid)
    orb = run(img, mode="orb", threshold=20)
    # Inside 18 <= x <= 45, 18 <= y <= 29: x in 20..44 (7 columns), y in 20, 24, 28 (3 rows).
    assert positions(orb) == [(x, y) for y in (20, 24, 28) for x in range(20, 45, 4)]
    assert_matches_reference(ref, orb, img, 1, 8, 20, "orb")


# ---- scales --------------------------------------------------------------------------------------


def test_scale_1_coordinates_are_in_scale_1_pixels() -> None:
    # A 2x2 block at (60..61, 40..41): at scale 0 the top-left pixel wins the tie of 4 equal corners,
    # at scale 1 the block is the single pixel (30, 20), whose full-resolution centre is (60.5, 40.5).
    img = dots(128, 96, dict.fromkeys([(60, 40), (61, 40), (60, 41), (61, 41)], DOT))
    f = run(img, scales=2, threshold=20)
    assert list(zip(f.scale.tolist(), f.x.tolist(), f.y.tolist(), strict=True)) == [(0, 60, 40), (1, 30, 20)]
    assert f.score.tolist() == [DOT_SCORE, DOT_SCORE]
    x0, y0 = f.full_res()
    assert (x0.tolist(), y0.tolist()) == ([60.0, 60.5], [40.0, 40.5])


@pytest.mark.parametrize(("name", "scales"), [("astronaut", 4), ("coffee", 3), ("chelsea", 2)])
def test_each_scale_equals_the_model_run_on_the_naively_downscaled_image(ref, photographs, name: str, scales: int):
    img = photographs[name]
    f = run(img, scales=scales, threshold=20, sectors=32)
    level = img
    for s in range(scales):
        if s:
            level = ref.downscale(level)
        h, w = level.shape
        direct = extract(level, Config(width=w, height=h, scales=1, sectors=32, threshold=20))
        got = ref.rows(f.take(np.nonzero(f.scale == s)[0]))
        expected = [(s, *row[1:]) for row in ref.rows(direct)]
        assert len(expected) > 0, f"{name}: no features at scale {s}"
        assert got == expected, f"{name} scale {s} ({w}x{h}): " + ref.rows_diff(got, expected)


@pytest.mark.parametrize(("scales", "mode"), [(3, "orb"), (4, "fast")])
def test_output_is_in_canonical_order(photographs, scales: int, mode: str) -> None:
    f = run(photographs["camera"], scales=scales, mode=mode, threshold=25)
    keys = list(zip(f.scale.tolist(), f.y.tolist(), f.x.tolist(), strict=True))
    assert len(set(f.scale.tolist())) == scales
    for i in range(1, len(keys)):
        assert keys[i - 1] < keys[i], f"features {i - 1} and {i} out of order: {keys[i - 1]} then {keys[i]}"


@pytest.mark.parametrize("n", NS)
def test_output_columns(photographs, n: int) -> None:
    img = photographs["chelsea"]
    orb = run(img, scales=2, sectors=4 * n)
    assert orb.descriptor.shape == (len(orb), 32) and orb.descriptor.dtype == np.uint8
    assert orb.sectors_total == 4 * n
    assert orb.sector.min() >= 0 and orb.sector.max() < 4 * n
    assert orb.score.min() >= 9 and orb.score.max() <= 4080
    fast = run(img, scales=2, sectors=4 * n, mode="fast")
    assert fast.descriptor.shape == (len(fast), 0) and (fast.sector == NO_SECTOR).all()
    assert len(fast) > len(orb)


# ---- errors --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("shape", "expected"), [((48, 65), ("65x48", "64x48")), ((47, 64), ("64x47", "64x48")), ((64, 48), ("48x64",))]
)
def test_wrong_sized_frame_raises_value_error_naming_both_sizes(shape: tuple[int, int], expected: tuple[str, ...]):
    with pytest.raises(ValueError) as exc:
        extract(np.zeros(shape, dtype=np.uint8), Config(width=64, height=48))
    msg = str(exc.value)
    assert not isinstance(exc.value, ConfigError)
    for text in (*expected, "64x48"):
        assert text in msg, f"{text!r} not in {msg!r}"


@pytest.mark.parametrize(
    "img",
    [np.zeros((48, 64), dtype=np.float32), np.zeros((48, 64), dtype=np.uint16), np.zeros((48, 64), dtype=np.int64),
     np.zeros((48, 64, 3), dtype=np.uint8), np.zeros((48 * 64,), dtype=np.uint8)],
    ids=["float32", "uint16", "int64", "rgb", "1-d"],
)  # fmt: skip
def test_non_uint8_or_non_2d_frame_raises_value_error(img: np.ndarray) -> None:
    with pytest.raises(ValueError, match="2-D uint8"):
        extract(img, Config(width=64, height=48))


# ---- rotation by 90 degrees ----------------------------------------------------------------------


def rotated_position(k: int, x: int, y: int, w: int, h: int) -> tuple[int, int]:
    """Where pixel (x, y) of a w x h image lands in np.rot90(img, k).

    np.rot90(img, 1)[i, j] = img[j, w-1-i]: (x, y) -> (y, w-1-x), counter-clockwise on screen; patch
    offsets (u, v) -> (v, -u), so (m10, m01) -> (m01, -m10), the inverse of the quadrant step
    (m10, m01) -> (-m01, m10) that adds N: the sector moves by -N. np.rot90(img, -1) is the reverse
    ((x, y) -> (h-1-y, x), sector +N) and np.rot90(img, 2) is (x, y) -> (w-1-x, h-1-y), sector +2N.
    """
    if k == 1:
        return y, w - 1 - x
    if k == -1:
        return h - 1 - y, x
    return w - 1 - x, h - 1 - y


SECTOR_SHIFT = {1: -1, -1: 1, 2: 2}  # in units of N


def zero_moments(ref, img: np.ndarray, scale: int, x: int, y: int) -> bool:
    """True when the naive m10 and m01 of the feature are both 0 (the only exemption)."""
    level = img
    for _ in range(scale):
        level = ref.downscale(level)
    px = level.astype(int).tolist()
    patch = [[ref.smooth_at(px, x + u, y + v) for u in range(-15, 16)] for v in range(-15, 16)]
    return ref.moments(patch, 15, 15) == (0, 0)


@pytest.mark.parametrize("k", [1, -1, 2])
@pytest.mark.parametrize("n", NS)
@pytest.mark.parametrize("name", PHOTOS)
def test_rotation_by_90_degrees_moves_sectors_by_n_and_keeps_descriptors(ref, photographs, name: str, n: int, k: int):
    img = photographs[name]
    h, w = img.shape
    img = np.ascontiguousarray(img[: h - h % 4, : w - w % 4])  # even sizes: the pyramid commutes with rot90
    h, w = img.shape
    rot = np.ascontiguousarray(np.rot90(img, k))
    a = run(img, scales=2, sectors=4 * n, threshold=20)
    b = run(rot, scales=2, sectors=4 * n, threshold=20)
    in_b = {(int(s), int(x), int(y)): i for i, (s, x, y) in enumerate(zip(b.scale, b.x, b.y, strict=True))}
    both = 0
    exempt: list[Key] = []
    for i in range(len(a)):
        s, x, y = int(a.scale[i]), int(a.x[i]), int(a.y[i])
        key = (s, *rotated_position(k, x, y, w >> s, h >> s))
        j = in_b.get(key)
        if j is None:
            continue
        both += 1
        where = f"{name} N={n} rot90 k={k}: scale {s} (x={x}, y={y}) -> (x={key[1]}, y={key[2]})"
        assert int(b.score[j]) == int(a.score[i]), f"{where}: score {a.score[i]} -> {b.score[j]}"
        sector_ok = int(b.sector[j]) == (int(a.sector[i]) + SECTOR_SHIFT[k] * n) % (4 * n)
        desc_ok = np.array_equal(a.descriptor[i], b.descriptor[j])
        if not (sector_ok and desc_ok):
            if zero_moments(ref, img, s, x, y):
                exempt.append((s, x, y))
                continue
            assert sector_ok, f"{where}: sector {a.sector[i]} -> {b.sector[j]}, expected shift {SECTOR_SHIFT[k]}N"
            assert desc_ok, (
                f"{where}: descriptor {a.descriptor[i].tobytes().hex()} -> {b.descriptor[j].tobytes().hex()}"
            )
    assert len(a) > 300 and len(b) > 300
    assert both >= 0.95 * len(a) and both >= 0.95 * len(b), f"{name}: only {both} of {len(a)} / {len(b)} in both"
    if exempt:
        warnings.warn(f"{name} N={n} k={k}: features with m10 = m01 = 0 exempted: {exempt}", stacklevel=1)
