# SPDX-License-Identifier: MIT
"""Configuration validation: every illegal value raises ConfigError, every legal extreme is accepted."""

from __future__ import annotations

import dataclasses
from typing import Any

import pytest

from golden_model.config import Config, ConfigError, sectors_to_per_quadrant

LEGAL: dict[str, Any] = {"width": 640, "height": 480, "scales": 2, "sectors": 32, "threshold": 20,
                         "mode": "orb"}  # fmt: skip


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("width", 63),
        ("width", 1921),
        ("width", 0),
        ("width", -640),
        ("height", 47),
        ("height", 1081),
        ("scales", 0),
        ("scales", 9),
        ("scales", -1),
        ("step_num", 1),
        ("step_num", 17),
        ("step_num", 5),  # 5:1, more than 2:1
        ("step_den", 3),  # not a power of two
        ("step_den", 16),
        ("step_den", 2),  # 2:2, no reduction
        ("step_num", 2.0),
        ("sectors", 24),
        ("sectors", 0),
        ("sectors", 8),  # N, not the total
        ("sectors", 128),
        ("threshold", -1),
        ("threshold", 256),
        ("mode", "x"),
        ("mode", "ORB"),
        ("mode", ""),
        ("width", True),
        ("width", 640.0),
        ("height", 480.0),
        ("height", "480"),
        ("scales", True),
        ("scales", 2.0),
        ("sectors", 32.0),
        ("sectors", False),
        ("threshold", 20.0),
        ("threshold", False),
        ("threshold", None),
    ],
)
def test_illegal_values_raise_config_error(field: str, value: Any) -> None:
    with pytest.raises(ConfigError) as exc:
        Config(**{**LEGAL, field: value})
    assert isinstance(exc.value, ValueError), "ConfigError must be a ValueError"
    assert field.split("_")[0] in str(exc.value), f"{field}={value!r}: {exc.value} does not name the parameter"


@pytest.mark.parametrize(
    ("field", "value"),
    [("width", 64), ("width", 1920), ("height", 48), ("height", 1080), ("scales", 1), ("scales", 7),
     ("sectors", 16), ("sectors", 64), ("threshold", 0), ("threshold", 255),
     ("mode", "fast")],
)  # fmt: skip
def test_legal_extremes_are_accepted(field: str, value: Any) -> None:
    cfg = Config(**{**LEGAL, field: value})
    assert getattr(cfg, field) == value


def test_defaults() -> None:
    cfg = Config(width=64, height=48)
    assert (cfg.scales, cfg.sectors, cfg.threshold, cfg.mode, cfg.step) == (1, 32, 20, "orb", (2, 1))


@pytest.mark.parametrize(
    ("w", "h", "step", "sizes"),
    [(640, 480, (5, 4), [(640, 480), (512, 384), (409, 307), (327, 245), (261, 196), (208, 156), (166, 124),
                         (132, 99)]),
     (1920, 1080, (3, 2), [(1920, 1080), (1280, 720), (853, 480), (568, 320), (378, 213), (252, 142), (168, 94),
                           (112, 62)]),
     (1920, 1080, (2, 1), [(1920 >> s, 1080 >> s) for s in range(8)])],
)  # fmt: skip
def test_level_sizes_floor_each_step(w: int, h: int, step: tuple[int, int], sizes: list[tuple[int, int]]) -> None:
    cfg = Config(width=w, height=h, scales=8, step_num=step[0], step_den=step[1])
    assert [cfg.scale_size(s) for s in range(8)] == sizes
    assert cfg.factor == step[0] / step[1]


@pytest.mark.parametrize(
    ("w", "h", "scales", "step"), [(64, 48, 5, (2, 1)), (640, 480, 8, (2, 1)), (64, 48, 7, (3, 2))]
)
def test_a_smallest_level_below_8x6_is_refused(w: int, h: int, scales: int, step: tuple[int, int]) -> None:
    with pytest.raises(ConfigError, match="smallest level"):
        Config(width=w, height=h, scales=scales, step_num=step[0], step_den=step[1])


@pytest.mark.parametrize(("n", "total"), [(4, 16), (8, 32), (16, 64)])
def test_sectors_is_the_total_and_n_is_derived(n: int, total: int) -> None:
    assert Config(**{**LEGAL, "sectors": total}).sectors_per_quadrant == n
    assert sectors_to_per_quadrant(total) == n


@pytest.mark.parametrize("total", [0, 4, 8, 12, 17, 48, 128, -16])
def test_illegal_total_sectors_raise(total: Any) -> None:
    with pytest.raises(ConfigError, match="sectors"):
        sectors_to_per_quadrant(total)


@pytest.mark.parametrize(
    ("w", "h", "sizes"),
    [(1920, 1080, [(1920, 1080), (960, 540), (480, 270), (240, 135)]),
     (641, 481, [(641, 481), (320, 240), (160, 120), (80, 60)]),
     (64, 48, [(64, 48), (32, 24), (16, 12), (8, 6)])],
)  # fmt: skip
def test_scale_size_halves_rounding_down(w: int, h: int, sizes: list[tuple[int, int]]) -> None:
    cfg = Config(width=w, height=h, scales=4)
    assert [cfg.scale_size(s) for s in range(4)] == sizes


def test_config_is_frozen() -> None:
    cfg = Config(**LEGAL)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.width = 100  # type: ignore[misc]


RANGES = {"width": "64..1920", "height": "48..1080", "scales": "1..8", "sectors": "16, 32 or 64",
          "threshold": "0..255", "mode": "'orb', 'fast'"}  # fmt: skip


@pytest.mark.parametrize(
    ("field", "value"),
    [("width", 63), ("height", 1081), ("scales", 9), ("sectors", 24), ("threshold", 256), ("mode", "x"),
     ("width", True), ("height", 480.0), ("scales", 2.0), ("sectors", 32.0), ("threshold", False)],
)  # fmt: skip
def test_every_refusal_names_the_value_and_the_legal_range(field: str, value: Any) -> None:
    # docs/spec.md section 1: "An illegal value is refused with a message naming the value and the legal range".
    with pytest.raises(ConfigError) as exc:
        Config(**{**LEGAL, field: value})
    msg = str(exc.value)
    assert repr(value) in msg or str(value) in msg, f"{field}={value!r}: {msg!r} does not name the value"
    assert RANGES[field] in msg, f"{field}={value!r}: {msg!r} does not name the legal range {RANGES[field]}"
