# SPDX-License-Identifier: MIT
"""Feature lists: canonical order, CSV form and round trip, and first_difference's messages."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from golden_model import Config, extract
from golden_model.features import CSV_COLUMNS, NO_SECTOR, Features, first_difference, read_csv, write_csv


def hand_features() -> Features:
    """Four features deliberately out of canonical order; 32 sectors."""
    return Features(
        scale=np.array([1, 0, 0, 2]),
        x=np.array([5, 10, 3, 7]),
        y=np.array([7, 3, 3, 1]),
        score=np.array([200, 100, 50, 9]),
        sector=np.array([5, 0, 31, 16]),
        descriptor=np.arange(4 * 32, dtype=np.uint8).reshape(4, 32),
        sectors_total=32,
    )


def fast_features() -> Features:
    return Features(np.array([0, 0]), np.array([4, 3]), np.array([9, 9]), np.array([3200, 17]),
                    np.full(2, NO_SECTOR), np.zeros((2, 0), dtype=np.uint8), 0)  # fmt: skip


def copy(f: Features) -> Features:
    return Features(f.scale.copy(), f.x.copy(), f.y.copy(), f.score.copy(), f.sector.copy(), f.descriptor.copy(),
                    f.sectors_total)  # fmt: skip


def keys(f: Features) -> list[tuple[int, int, int]]:
    """(scale, y, x) of each feature, in the list's order."""
    return list(zip(f.scale.tolist(), f.y.tolist(), f.x.tolist(), strict=True))


def test_sorted_is_scale_then_y_then_x() -> None:
    f = hand_features().sorted()
    assert keys(f) == [(0, 3, 3), (0, 3, 10), (1, 7, 5), (2, 1, 7)]
    assert f.score.tolist() == [50, 100, 200, 9], "other columns follow the sort"
    assert f.descriptor[0, 0] == 64 and f.descriptor[3, 0] == 96


def test_sorted_orders_by_row_before_column() -> None:
    f = Features(np.array([1, 0, 0, 0]), np.array([0, 3, 10, 1]), np.array([0, 5, 3, 5]), np.arange(4),
                 np.zeros(4, dtype=np.int64), np.zeros((4, 0), dtype=np.uint8), 0)  # fmt: skip
    s = f.sorted()
    assert keys(s) == [(0, 3, 10), (0, 5, 1), (0, 5, 3), (1, 0, 0)]


def test_full_res_and_angle_hand_values() -> None:
    f = hand_features()
    x0, y0 = f.full_res()
    # (x + 0.5) * 2^scale - 0.5: scale 1 (5, 7) -> (10.5, 14.5); scale 2 (7, 1) -> (29.5, 5.5).
    assert x0.tolist() == [10.5, 10.0, 3.0, 29.5] and y0.tolist() == [14.5, 3.0, 3.0, 5.5]
    assert f.angle_deg().tolist() == [56.25, 0.0, 348.75, 180.0]  # sector * 360 / 32
    assert all(math.isnan(a) for a in fast_features().angle_deg())
    mixed = hand_features()
    mixed.sector[0] = NO_SECTOR
    assert math.isnan(mixed.angle_deg()[0]) and mixed.angle_deg()[1] == 0.0


def test_len_and_has_descriptors() -> None:
    assert len(hand_features()) == 4 and hand_features().has_descriptors
    assert len(fast_features()) == 2 and not fast_features().has_descriptors
    assert len(Features()) == 0


def test_write_csv_hand_checked(tmp_path: Path) -> None:
    path = tmp_path / "f.csv"
    write_csv(hand_features(), path)
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    assert tuple(rows[0]) == CSV_COLUMNS
    d = np.arange(4 * 32, dtype=np.uint8).reshape(4, 32)
    assert rows[1:] == [
        ["0", "3", "3", "50", "31", d[2].tobytes().hex(), "3", "3", "348.75", "0", "0"],
        ["0", "10", "3", "100", "0", d[1].tobytes().hex(), "10", "3", "0", "0", "0"],
        ["1", "5", "7", "200", "5", d[0].tobytes().hex(), "10.5", "14.5", "56.25", "0", "0"],
        ["2", "7", "1", "9", "16", d[3].tobytes().hex(), "29.5", "5.5", "180", "0", "0"],
    ]


def test_write_csv_fast_mode_leaves_sector_descriptor_and_angle_empty(tmp_path: Path) -> None:
    path = tmp_path / "f.csv"
    write_csv(fast_features(), path)
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[1:] == [["0", "3", "9", "17", "", "", "3", "9", "", "0", "0"],
                        ["0", "4", "9", "3200", "", "", "4", "9", "", "0", "0"]]  # fmt: skip


def assert_same_columns(a: Features, b: Features) -> None:
    a, b = a.sorted(), b.sorted()
    for name in ("scale", "x", "y", "score", "sector", "descriptor", "response", "low"):
        va, vb = getattr(a, name), getattr(b, name)
        assert va.shape == vb.shape, f"{name}: shape {va.shape} != {vb.shape}"
        if len(va) == 0:
            continue
        bad = np.nonzero((va != vb).reshape(len(va), -1).any(axis=1))[0]
        assert len(bad) == 0, f"{name} differs at scale {a.scale[bad[0]]} (x={a.x[bad[0]]}, y={a.y[bad[0]]})"


@pytest.mark.parametrize("make", [hand_features, fast_features, Features], ids=["orb", "fast", "empty"])
def test_csv_round_trip_of_hand_lists(tmp_path: Path, make) -> None:
    f = make()
    path = tmp_path / "f.csv"
    write_csv(f, path)
    back = read_csv(path, sectors_total=f.sectors_total)
    assert back == f, first_difference(back, f)
    assert_same_columns(back, f)


@pytest.mark.parametrize("mode", ["orb", "fast"])
def test_csv_round_trip_of_an_extracted_photograph(ref, photographs, tmp_path: Path, mode: str) -> None:
    img = ref.center_crop(photographs["coffee"], 200, 160)
    f = extract(img, Config(200, 160, scales=2, sectors=64, threshold=20, mode=mode))
    assert len(f) > 50
    path = tmp_path / "f.csv"
    write_csv(f, path)
    back = read_csv(path, sectors_total=64)
    assert back == f, first_difference(back, f)
    assert_same_columns(back, f)


def test_read_csv_ignores_extra_columns_and_rejects_missing_ones(tmp_path: Path) -> None:
    path = tmp_path / "extra.csv"
    path.write_text("y,x,scale,score,sector,descriptor,comment\n4,3,1,77,,,hello\n")
    f = read_csv(path)
    assert (f.scale.tolist(), f.x.tolist(), f.y.tolist(), f.score.tolist(), f.sector.tolist()) == (
        [1], [3], [4], [77], [NO_SECTOR]
    )  # fmt: skip
    bad = tmp_path / "missing.csv"
    bad.write_text("scale,x,y,sector,descriptor\n0,1,2,,\n")
    with pytest.raises(ValueError, match="score"):
        read_csv(bad)


def test_first_difference_none_when_equal_in_any_order() -> None:
    a = hand_features()
    assert first_difference(a, a.sorted()) is None
    assert a == a.sorted()
    assert (a == 3) is False


@pytest.mark.parametrize(
    ("column", "index", "value", "where", "what"),
    [
        ("score", 1, 101, "scale 0 (x=10, y=3)", "score 100 != 101"),
        ("sector", 0, 6, "scale 1 (x=5, y=7)", "sector 5 != 6"),
        ("sector", 3, 0, "scale 2 (x=7, y=1)", "sector 16 != 0"),
    ],
)
def test_first_difference_names_the_feature(column: str, index: int, value: int, where: str, what: str) -> None:
    a = hand_features()
    b = copy(a)
    getattr(b, column)[index] = value
    msg = first_difference(a, b)
    assert msg is not None and where in msg and what in msg, msg
    assert a != b


def test_first_difference_descriptor_message() -> None:
    a = hand_features()
    b = copy(a)
    b.descriptor[2, 31] ^= 0x80
    msg = first_difference(a, b)
    assert msg is not None and "scale 0 (x=3, y=3)" in msg and "descriptor" in msg, msg
    assert a.descriptor[2].tobytes().hex() in msg and b.descriptor[2].tobytes().hex() in msg


def test_first_difference_missing_and_extra_features() -> None:
    a = hand_features()
    without = a.take(np.array([0, 2, 3]))  # drops scale 0 (x=10, y=3)
    msg = first_difference(a, without)
    assert msg is not None and "scale 0 (x=10, y=3)" in msg and "missing from the second list" in msg, msg
    msg = first_difference(without, a)
    assert msg is not None and "scale 0 (x=10, y=3)" in msg and "missing from the first list" in msg, msg
    shorter = a.take(np.array([0, 1, 2]))  # drops the last in canonical order: scale 2 (x=7, y=1)
    msg = first_difference(a, shorter)
    assert msg is not None and "first list has 1 more features" in msg and "scale 2 (x=7, y=1)" in msg, msg
    msg = first_difference(Features(), a)
    assert msg is not None and "second list has 4 more features" in msg and "scale 0 (x=3, y=3)" in msg, msg


def test_concat_keeps_columns_and_empty_concat_has_the_descriptor_width() -> None:
    a, b = hand_features(), hand_features()
    c = Features.concat([a, b], 32, 32)
    assert len(c) == 8 and c.descriptor.shape == (8, 32) and c.sectors_total == 32
    e = Features.concat([], 64, 32)
    assert len(e) == 0 and e.descriptor.shape == (0, 32) and e.sectors_total == 64
