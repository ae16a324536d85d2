# SPDX-License-Identifier: MIT
"""Accelerator configuration, validated exactly like the hardware generics and registers.

The legal values come from golden_model.limits (generated from golden_model/data/limits.json, the
one definition the HDL's orb_limits_pkg and docs/limits.md are generated from too).
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

from . import limits
from .configs import CONFIGS, TOPS_DEFAULT

MODES = ("orb", "fast")
SELECTIONS = ("all", "grid")

# The recommended configuration for 640x480 on the XC7Z020 (docs/pyramid.md: the best measured on
# the scale benchmark within 80% of the device's LUTs and block RAM), the named configuration
# "recommended-vga" (docs/configurations.md): what `make sim` and `orb-accel extract` use unless
# told. The selection (docs/selection.md): the grid mode with a budget of RECOMMENDED_BUDGET
# features per 640x480 frame (recommended_budget for other sizes), a grid of 8 x 6 cells over the
# frame at every level and the low threshold 14, chosen by measurement against 7 (ORB-SLAM's
# minThFAST), 12 and 16 (research/selection/README.md, "Low corners in the rest").
RECOMMENDED_NAME = "recommended-vga"
_REC = CONFIGS[RECOMMENDED_NAME]
RECOMMENDED_SCALES = int(_REC["scales"])
RECOMMENDED_STEP = (int(_REC["step_num"]), int(_REC["step_den"]))
RECOMMENDED_SECTORS = int(_REC["sectors"])
RECOMMENDED_BUDGET = 1000  # per 640x480 frame: the budget rule below ("recommended-vga" has it)
RECOMMENDED_THRESHOLD_LO = int(_REC["threshold_lo"])
RECOMMENDED_COLS = int(_REC["cols"])
RECOMMENDED_ROWS = int(_REC["rows"])
# the budgets of the board's resolutions (docs/board-configs.md): each fits its bank
RECOMMENDED_BUDGETS = {(640, 480): 1000, (1280, 720): 1500, (1920, 1080): 2000}


def recommended_budget(width: int, height: int) -> int:
    """The grid selection's budget for a frame: RECOMMENDED_BUDGETS for the board's resolutions,
    otherwise RECOMMENDED_BUDGET per 640x480 scaled by the square root of the area (features of a
    SLAM front end grow slower than the pixel count), at least 1 and at most 2000."""
    if (width, height) in RECOMMENDED_BUDGETS:
        return RECOMMENDED_BUDGETS[(width, height)]
    return max(1, min(2000, round(RECOMMENDED_BUDGET * (width * height / (640 * 480)) ** 0.5)))


# The Config fields checked against golden_model.limits, in the order they are checked.
_LIMITED = tuple(lim for lim in limits.LIMITS if lim.config)


class ConfigError(ValueError):
    """An illegal configuration value (the hardware would refuse it too)."""


@dataclass(frozen=True)
class Config:
    """One accelerator configuration.

    ``sectors`` is the total number of orientation sectors (16, 32 or 64; generic SECTORS_g);
    the thesis's N, the sectors per quadrant, is the derived ``sectors_per_quadrant``.
    ``threshold`` is the run-time FAST threshold; ``mode`` is ``orb`` (detect and describe) or
    ``fast`` (detection only, the thesis's isolated-FAST mode). ``step_num``:``step_den`` is the
    pyramid step (generics STEP_NUM_g, STEP_DEN_g): each of the ``scales`` levels is that much
    smaller than the one before; 2:1 is the thesis's 2x2 box, any other step the fixed-phase
    bilinear resampler (docs/spec.md section 3). The step needs step_den < step_num <= 2 step_den,
    and the smallest level at least scale_width x scale_height pixels.

    ``selection`` is ``all`` (every feature at the threshold, the feature memory stores them in
    arrival order) or ``grid`` (each level's share of ``budget`` features: every cell of a ``cols`` x
    ``rows`` grid over the frame keeps its best corner of the level, a corner at ``threshold_lo``
    when it has none at ``threshold``, then the strongest of the rest; docs/spec.md section 14). ``threshold_lo``
    defaults to ``threshold`` (no low corners); a value above it acts as equal to it.
    """

    width: int
    height: int
    scales: int = 1
    sectors: int = 32
    threshold: int = 20
    mode: str = "orb"
    step_num: int = 2
    step_den: int = 1
    threshold_lo: int | None = None
    selection: str = "all"
    budget: int = 0
    cols: int = RECOMMENDED_COLS
    rows: int = RECOMMENDED_ROWS

    def __post_init__(self) -> None:
        if self.threshold_lo is None:
            object.__setattr__(self, "threshold_lo", self.threshold)
        for lim in _LIMITED:
            value = getattr(self, lim.name)
            if isinstance(value, bool) or not isinstance(value, numbers.Integral):
                raise ConfigError(f"{lim.name} must be an integer ({lim.text}), got {value!r}")
            object.__setattr__(self, lim.name, int(value))  # numpy integers become plain ints
        for lim in _LIMITED:
            value = getattr(self, lim.name)
            if not lim.legal(value):
                raise ConfigError(f"{lim.name} must be {lim.text}, got {value}")
        if self.mode not in MODES:
            raise ConfigError(f"mode {self.mode!r} not one of {MODES}")
        if self.selection not in SELECTIONS:
            raise ConfigError(f"selection {self.selection!r} not one of {SELECTIONS}")
        check_step(self.step_num, self.step_den)
        w, h = self.scale_size(self.scales - 1)
        if not (limits.SCALE_WIDTH.legal(w) and limits.SCALE_HEIGHT.legal(h)):
            raise ConfigError(
                f"{self.scales} levels of {self.step_num}:{self.step_den} leave a {w}x{h} smallest level; it must "
                f"be at least {limits.SCALE_WIDTH.min}x{limits.SCALE_HEIGHT.min} (fewer scales or a larger frame)"
            )

    @classmethod
    def named(cls, name: str, **overrides: object) -> Config:
        """The model configuration of the named configuration ``name`` (docs/configurations.md),
        with ``overrides`` (any Config field) applied: ``Config.named("board-720p", threshold=30)``."""
        return named(name).config(**overrides)

    @property
    def low_threshold(self) -> int:
        """The low threshold in effect: threshold_lo, or the threshold when threshold_lo is above it."""
        return min(int(self.threshold_lo or 0), self.threshold)

    @property
    def sectors_per_quadrant(self) -> int:
        """N = sectors / 4, the sectors per quadrant of the orientation and pattern rules (spec §9, §10)."""
        return self.sectors // 4

    @property
    def step(self) -> tuple[int, int]:
        """The pyramid step (num, den)."""
        return self.step_num, self.step_den

    @property
    def factor(self) -> float:
        """The pyramid step as a number, num / den (2.0 for the thesis's pyramid)."""
        return self.step_num / self.step_den

    def scale_size(self, scale: int) -> tuple[int, int]:
        """(width, height) of scale ``scale``: level_size applied ``scale`` times."""
        return level_size(self.width, self.height, scale, self.step)


def check_step(num: int, den: int) -> None:
    """ConfigError unless num:den is a legal pyramid step: each part inside its limit (den a power of
    two) and den < num <= 2 den (the one rule; Config, the CLI and the bag converter call it)."""
    for lim, value in ((limits.STEP_NUM, num), (limits.STEP_DEN, den)):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lim.legal(int(value)):
            raise ConfigError(f"{lim.name} must be {lim.text}, got {value!r}")
    if not den < num <= 2 * den:
        raise ConfigError(f"pyramid step {num}:{den}: need step_den < step_num <= 2 step_den")


def parse_step(text: str) -> tuple[int, int]:
    """ "5:4" -> (5, 4): the pyramid step as the CLI and the benches write it (legality: Config)."""
    num, sep, den = text.partition(":")
    if not sep or not num.strip().isdigit() or not den.strip().isdigit():
        raise ConfigError(f"pyramid step {text!r}: expected NUM:DEN, e.g. 5:4 or 2:1")
    return int(num), int(den)


def parse_cells(text: str) -> tuple[int, int]:
    """ "8x6" -> (8, 6): the grid selection's cells across and down, as the CLI and the simulation
    jobs write them (legality: Config)."""
    cols, sep, rows = text.lower().partition("x")
    if not sep or not cols.strip().isdigit() or not rows.strip().isdigit():
        raise ConfigError(f"cells {text!r}: expected COLSxROWS, e.g. 8x6")
    return int(cols), int(rows)


def level_size(width: int, height: int, scale: int, step: tuple[int, int] = (2, 1)) -> tuple[int, int]:
    """(width, height) of pyramid level ``scale``: each level is floor(size * den / num) of the one
    before (2:1: halved, rounding down) -- the rule of docs/spec.md section 3 and of orb_util_pkg's
    level_size."""
    num, den = step
    for _ in range(scale):
        width, height = width * den // num, height * den // num
    return width, height


def sectors_to_per_quadrant(sectors: int) -> int:
    """Total sectors (16, 32 or 64) to the per-quadrant N (4, 8 or 16)."""
    if isinstance(sectors, bool) or not isinstance(sectors, numbers.Integral) or not limits.SECTORS.legal(int(sectors)):
        raise ConfigError(f"sectors must be {limits.SECTORS.text}, got {sectors!r}")
    return int(sectors) // 4


NAMES = tuple(CONFIGS)


@dataclass(frozen=True)
class NamedConfig:
    """A named configuration (golden_model/data/configs.json, docs/configurations.md): the generics of
    a bitstream or simulation (width .. block_log2) and the selection the driver starts it with."""

    name: str
    about: str
    width: int
    height: int
    scales: int
    step_num: int
    step_den: int
    sectors: int
    mem_depth: int
    block_log2: int
    mem_kind: str  # "bram": orb_feat_mem's two banks; "ddr": orb_feat_dma's ring (docs/feature-dma.md)
    threshold: int
    threshold_lo: int
    selection: str
    budget: int
    cols: int
    rows: int
    used_by: tuple[str, ...]
    verified_by: tuple[str, ...]

    def config(self, **overrides: object) -> Config:
        """The model's Config of this device (Config fields in ``overrides`` replace its values)."""
        fields = {k: getattr(self, k) for k in _CONFIG_FIELDS}
        unknown = set(overrides) - set(fields) - {"mode"}
        if unknown:
            raise ConfigError(f"not Config fields: {sorted(unknown)}")
        return Config(**{**fields, **overrides})  # type: ignore[arg-type]

    def generics(self, input_format: str = "RGB") -> dict[str, int | str]:
        """The VHDL generics of orb_accel_top / orb_accel_zynq for this configuration."""
        return {"WIDTH_g": self.width, "HEIGHT_g": self.height, "SCALES_g": self.scales,
                "STEP_NUM_g": self.step_num, "STEP_DEN_g": self.step_den, "SECTORS_g": self.sectors,
                "MEM_DEPTH_g": self.mem_depth, "BLOCK_LOG2_g": self.block_log2, "INPUT_g": input_format,
                "MEM_KIND_g": self.mem_kind.upper()}  # fmt: skip

    @property
    def capacity(self) -> int:
        """Features a bank holds (one slot is the end-of-frame record)."""
        return self.mem_depth - 1


_CONFIG_FIELDS = ("width", "height", "scales", "step_num", "step_den", "sectors", "threshold", "threshold_lo",
                  "selection", "budget", "cols", "rows")  # fmt: skip


def named(name: str) -> NamedConfig:
    """The named configuration ``name``; ConfigError naming the known ones otherwise."""
    try:
        entry = CONFIGS[name]
    except KeyError:
        raise ConfigError(f"no configuration named {name!r}; known: {', '.join(NAMES)}") from None
    return NamedConfig(name=name, **entry)  # type: ignore[arg-type]


def tops_default() -> NamedConfig:
    """The configuration of the HDL tops' generic defaults."""
    return named(TOPS_DEFAULT)
