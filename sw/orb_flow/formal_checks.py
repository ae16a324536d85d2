# SPDX-License-Identifier: MIT
"""The formal checks as data (docs/formal.md): which entity with which generics, the mode (prove or bmc) and its
depth, the file of its own properties (hdl/formal/props/), the planted bugs with their textual change and the
property each must fail. sw/orb_flow/formal.py runs them.

A check's property file is SystemVerilog inserted into the wrapper `orb_formal_top` after the bound checkers: its
header (the comment lines up to the first empty line) is left out, a line `` `include "<name>.svh" `` is replaced
by that file of hdl/formal/props/ (blocks several checks share), and each `@NAME@` by the check's value NAME
(Check.values) or else its generic NAME: values the code owns (a window from the generics, a bit from the
register map) are not copied into the file.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from golden_model import regs


@dataclass(frozen=True)
class Mutation:
    """A planted bug: `pattern` (a regex, exactly one match) replaced by `repl` in `target`, either
    "wrapper" or a source path relative to hdl/; the run must FAIL in the property `expect` (an
    instance name of a checker, or a label of the check's property file)."""

    name: str
    what: str
    target: str
    pattern: str
    repl: str
    expect: str
    more: tuple[tuple[str, str], ...] = ()  # further (pattern, repl) patches of the same target


@dataclass(frozen=True)
class Check:
    entity: str
    generics: Mapping[str, int | str]
    mode: str = "prove"  # "prove" (k-induction) or "bmc"
    depth: int = 10  # prove: the induction length; bmc: the bound
    quick: bool = True  # a few seconds: in make test; else marked slow
    # the check's own properties: a file of hdl/formal/props/ (labelled asserts inside orb_formal_top), or none
    props: str = ""
    values: Mapping[str, int] = field(default_factory=dict)  # the property file's @NAME@ placeholders
    extra_props: Mapping[str, str] = field(default_factory=dict)  # label -> what it says
    mutations: tuple[Mutation, ...] = ()
    axil: Mapping[str, int] = field(default_factory=dict)  # orb_axil_chk parameters
    # orb_axi4w_chk parameters (MAX_OUTSTANDING, MAX_AHEAD): given, the checker is bound to every m_axi_<name> write
    # master port (its rst: the entity's bus_rst where it has one, the AXI reset); not given, those ports are unbound
    axi4w: Mapping[str, int] = field(default_factory=dict)
    # planted bugs of another check that fail these properties on the same RTL (property prefix -> check)
    bugs_of: Mapping[str, str] = field(default_factory=dict)
    name: str = ""  # the check's name where an entity has several checks (default: the entity)
    # internal nets of the entity's module made outputs `probe_<net>` of it in GHDL's Verilog (add_probes), for
    # properties about state the ports do not show (e.g. a RAM's write port)
    probes: tuple[str, ...] = ()
    # the sby engine line: smtbmc's --nopresat skips the check that the assumptions alone are satisfiable before each
    # step's assertion check (orb_feat_dma: boolector spends minutes on that check at depth 24; the planted bugs show
    # the assumptions are satisfiable to their steps)
    engine: str = "smtbmc boolector"

    @property
    def key(self) -> str:
        return self.name or self.entity


# The checks, quick ones first. Generics: narrow data, the smallest legal sizes (the test-tiny configuration's
# where a size matters). Planted bugs are patches of the entity's VHDL (a copy in the run's folder).
_FG = "input/orb_frame_gate.vhd"


def _stall_bug(path: str, pattern: str, repl: str, port: str) -> Mutation:
    """The common planted bug of a pipeline: its stage loads whatever m_axis_<port>_tready says."""
    return Mutation(
        "ignores_tready",
        "the output stage loads a new beat although the stalled one was not taken (tready ignored)",
        path,
        pattern,
        repl,
        f"chk_m_axis_{port}",
    )


# the nets of orb_feat_mem the bank protocol's check reads: the RAM's write port, the control state
_FEAT_MEM_PROBES = ("wr_en", "wr_addr", "wr_data", "wbank", "in_frame", "storing", "abort_f", "cnt", "in_rel",
                    "in_relb", "in_beat", "in_last", "in_abort")  # fmt: skip

LIVE_GAP = 3  # the idle timeout property's bound for IDLE_TIMEOUT_g = 3 (IDLE_TIMEOUT_g clocks; 2 fails)

# orb_video_check's planted bugs of the output's shape and the sink's contract, run with and without
# IDLE_TIMEOUT_g
_VIDEO_CHECK_SHAPE_BUGS = (
    Mutation(
        "sink_stalls",
        "the documented contract broken: the sink stalls m_axis_video (no longer assumed ready); "
        "orb_video_check then changes a waiting beat (the contract is needed, not vacuous)",
        "wrapper",
        r"^  always @\(\*\) if \(!init\) assume \(m_axis_video_tready\);",
        "",
        "chk_m_axis_video",
    ),
    Mutation(
        "tlast_copied",
        "m_axis_video_tlast copied from the input's tlast instead of the position",
        "input/orb_video_check.vhd",
        r"o_last  <= '1' when x = WIDTH_g - 1 else '0';",
        "o_last  <= placed.last;",
        "frame_shape",
    ),
    Mutation(
        "frame_end_early",
        "frame_end one position early (at x = WIDTH_g - 2 of the last line)",
        "input/orb_video_check.vhd",
        r"frame_last  <= emit_v and x = WIDTH_g - 1 and y = HEIGHT_g - 1;",
        "frame_last  <= emit_v and x = WIDTH_g - 2 and y = HEIGHT_g - 1;",
        "frame_end_last",
    ),
)

# orb_feat_dma (docs/feature-dma.md): its generics (a small window: [1 MiB, 2 MiB)), the AXI4 write checker's
# parameters (at most OUTSTANDING_g bursts unanswered; the next burst's address waits for the last beat of the one
# before), and the property files' window (orb_feat_dma.window.svh: the registers' contract, RING_COUNT 0 .. 16, the
# register map's maximum) and, for the .ring and .off checks, a ring constant from the first clock, legal or not by
# the four checks of docs/feature-dma.md computed there
_DMA_GENERICS = {"DEPTH_g": 16, "SEL_SLOTS_g": 2, "FIFO_DEPTH_g": 16, "OUTSTANDING_g": 2, "WIN_BASE_MB_g": 1,
                 "WIN_SIZE_MB_g": 1}  # fmt: skip
_DMA_AXI4W = {"MAX_OUTSTANDING": 2, "MAX_AHEAD": 1}
_DMA_ADDR_PROPS = {
    "aw_aligned": "every AWADDR 64-byte aligned (the ring registers, the stream, frame_abort, the release, rst and "
    "bus_rst free)",
    "aw_in_window": "every burst (64 bytes at AWADDR) inside the DDR window [WIN_BASE_MB_g, + WIN_SIZE_MB_g) MiB, "
    "whatever the ring registers do (RING_COUNT at most 16)",
}


def _dma_window(generics: Mapping[str, int | str]) -> dict[str, int]:
    """orb_feat_dma.window.svh's values: the DDR window [WIN_LO, WIN_HI) and one buffer (BUF), in bytes."""
    lo = int(generics["WIN_BASE_MB_g"]) << 20
    return {"WIN_LO": lo, "WIN_HI": lo + (int(generics["WIN_SIZE_MB_g"]) << 20), "BUF": int(generics["DEPTH_g"]) * 64}


_DMA = "host/orb_feat_dma.vhd"
DMA_DEPTH = 26  # the second burst's AWVALID at step 25 at the earliest
DMA_OUT1_DEPTH = 27  # with OUTSTANDING_g 1 a second burst waits for the first's response: step 26 at the earliest
_DMA_ENGINE = "smtbmc --nopresat boolector"

# the tops' checks: orb_accel_zynq's generics (orb_accel_top's but the address width) and the AXI4-Lite
# checker's parameters of both
_ZYNQ_GENERICS = {
    "WIDTH_g": 64,
    "HEIGHT_g": 48,
    "SCALES_g": 1,
    "SECTORS_g": 16,
    "MEM_DEPTH_g": 16,
    "INPUT_g": "LUMA",
    "BLOCK_LOG2_g": 2,
    "C_S_AXI_CTRL_ADDR_WIDTH": 18,
}
_TOP_AXIL = {"MAXW": 2, "MAXR": 1, "BOUND": 4, "RBOUND": 6, "REGMAP": 1, "MEM_DEPTH": 16}

# orb_accel_zynq's video path with the sink always ready and no soft reset (CTRL.soft_reset empties the
# overlay's pipeline; other writes, CTRL.enable among them, are free): the live input (IDLE_TIMEOUT_g
# 4,096) is never held, and every beat taken leaves OVERLAY_VIDEO_LAT_c = 3 clocks later (the top's video
# path is the overlay's); the top and then its core leave reset a clock after the interface each, so the
# rate counts from the third edge out of reset
ZYNQ_RATE_FROM = 3  # s_axis_video_tready is 1 from the clock 3 edges after the last that sampled aresetn low (2 fails)
_SOFT_BIT = regs.CTRL.field("soft_reset").lsb
# orb_accel_zynq.timing.sv's values: CTRL.soft_reset's bit (and its byte lane) in the register map
_ZYNQ_TIMING = {"SOFT_BYTE": _SOFT_BIT // 8, "SOFT_BIT": _SOFT_BIT, "RATE_FROM": ZYNQ_RATE_FROM}

CHECKS: dict[str, Check] = {
    c.key: c
    for c in (
        Check(
            "orb_frame_gate",
            {"DATA_WIDTH_g": 4},
            props="orb_frame_gate.sv",
            extra_props={
                "no_invention": "combinational (FRAME_GATE_LAT_c = 0), nothing invented: a beat on m_axis_video is "
                "the one on s_axis_video in the same clock (data, tuser, tlast), s_axis_video_tready = "
                "m_axis_video_tready then"
            },
            mutations=(
                Mutation(
                    "tvalid_without_input",
                    "m_axis_video_tvalid raised by the open gate alone, without a beat on s_axis_video",
                    _FG,
                    r"m_axis_video_tvalid <= s_axis_video_tvalid and gate_pass;",
                    "m_axis_video_tvalid <= gate_pass;",
                    "no_invention",
                ),
                Mutation(
                    "sof_dropped_on_stall",
                    "the old gate: a start-of-frame beat passes by enable alone, so enable falling while it "
                    "waits on a stalled output drops m_axis tvalid",
                    _FG,
                    r"\(enable or sof_hold\) when",
                    "enable when",
                    "chk_m_axis_video",
                ),
                Mutation(
                    "data_follows_enable",
                    "m_axis_video_tdata inverted while enable is 1: the data changes while a beat waits",
                    _FG,
                    r"^  m_axis_video_tdata  <= s_axis_video_tdata;",
                    "  m_axis_video_tdata  <= s_axis_video_tdata xor (s_axis_video_tdata'range => enable);",
                    "chk_m_axis_video",
                ),
            ),
        ),
        Check(
            "orb_frame_gate",
            {"DATA_WIDTH_g": 4},
            name="orb_frame_gate.rate",
            bugs_of={"chk_m_axis_video": "orb_frame_gate"},
            props="orb_frame_gate.rate.sv",
            extra_props={"rate": "with the sink always ready, s_axis_video_tready is 1 in every clock out of reset"},
            mutations=(
                Mutation(
                    "sof_stalls",
                    "a start-of-frame beat waits a clock (tready low while tuser is offered and no decision held)",
                    _FG,
                    r"ready     <= m_axis_video_tready when gate_pass = '1' else",
                    "ready     <= m_axis_video_tready and (sof_hold or not s_axis_video_tuser) "
                    "when gate_pass = '1' else",
                    "rate",
                ),
            ),
        ),
        Check(
            "orb_rgb_luma",
            {"INPUT_g": "RGB"},
            mutations=(
                _stall_bug(
                    "input/orb_rgb_luma.vhd",
                    r"adv    := o_valid = '0' or m_axis_video_tready = '1';",
                    "adv    := true;",
                    "video",
                ),
            ),
        ),
        Check(
            "orb_rgb_luma",
            {"INPUT_g": "RGB"},
            name="orb_rgb_luma.conserve",
            probes=("a_valid", "b_valid", "p_valid"),
            props="orb_rgb_luma.conserve.sv",
            extra_props={
                "no_invention": "nothing out that did not go in, nothing lost: the beats taken and not given are "
                "exactly those its 4 registers hold (skid a, b, stage 1, output; valid bits probed)"
            },
            bugs_of={"chk_m_axis_video": "orb_rgb_luma"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "the output stage offers the beat of an empty stage when its tuser bit is set",
                    "input/orb_rgb_luma.vhd",
                    r"o_valid <= p_valid;",
                    "o_valid <= p_valid or p_user;",
                    "no_invention",
                ),
            ),
        ),
        Check(
            "orb_rgb_luma",
            {"INPUT_g": "RGB"},
            name="orb_rgb_luma.timing",
            bugs_of={"chk_m_axis_video": "orb_rgb_luma"},
            props="orb_rgb_luma.timing.sv",
            extra_props={
                "rate": "with the sink always ready, s_axis_video_tready is 1 in every clock out of reset",
                "latency": "with the sink always ready, every beat taken is on m_axis_video RGB_LUMA_LAT_c = 3 "
                "clocks later, in order, nothing else, with its tuser and tlast (Y itself: the golden model's "
                "simulations)",
            },
            mutations=(
                Mutation(
                    "half_rate",
                    "tready low in the clock after every beat taken: half rate",
                    "input/orb_rgb_luma.vhd",
                    r"ready   <= not b_next;",
                    "if take then ready <= '0'; else ready <= not b_next; end if;",
                    "rate",
                ),
                Mutation(
                    "tlast_early",
                    "the output's tlast taken from the skid register instead of stage 1 (a clock early)",
                    "input/orb_rgb_luma.vhd",
                    r"o_last  <= p_last;",
                    "o_last  <= a_beat(IN_BITS_c);",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_desc_rotate",
            {"SECTORS_g": 16},
            props="orb_desc_rotate.sv",
            extra_props={"no_invention": "nothing out that did not go in: the beat inside is the one on the output"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "the stage offers a beat whenever it may load, whether one came in or not",
                    "describe/orb_desc_rotate.vhd",
                    r"q_valid <= s_axis_feat_tvalid;",
                    "q_valid <= '1';",
                    "no_invention",
                ),
                _stall_bug(
                    "describe/orb_desc_rotate.vhd",
                    r"take <= not q_valid or m_axis_feat_tready;",
                    "take <= '1';",
                    "feat",
                ),
            ),
        ),
        Check(
            "orb_desc_rotate",
            {"SECTORS_g": 16},
            name="orb_desc_rotate.timing",
            bugs_of={"chk_m_axis_feat": "orb_desc_rotate"},
            quick=False,  # 13-27 s (the rotation of the 256-bit descriptor); its planted bugs 3 s each
            props="orb_desc_rotate.timing.sv",
            extra_props={
                "rate": "with the sink always ready, s_axis_feat_tready is 1 in every clock out of reset",
                "latency": "with the sink always ready, every beat taken is on m_axis_feat DESC_ROTATE_LAT_c = 1 "
                "clock later, nothing else: its tlast, every field but the descriptor unchanged, the descriptor's "
                "orbits rotated by the sector (an end-of-frame word unchanged)",
            },
            mutations=(
                Mutation(
                    "bubble",
                    "the stage takes a beat only when empty: a bubble after every beat",
                    "describe/orb_desc_rotate.vhd",
                    r"take <= not q_valid or m_axis_feat_tready;",
                    "take <= not q_valid;",
                    "rate",
                ),
                Mutation(
                    "rotates_left",
                    "the orbits rotated the other way (test k takes test k - s)",
                    "describe/orb_desc_rotate.vhd",
                    r"orbit := orbit\(2 \*\* k - 1 downto 0\) & orbit\(ORBIT_c - 1 downto 2 \*\* k\);",
                    "orbit := orbit(ORBIT_c - 2 ** k - 1 downto 0) & orbit(ORBIT_c - 1 downto ORBIT_c - 2 ** k);",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_video_check",
            {"WIDTH_g": 4, "HEIGHT_g": 2},
            mode="bmc",
            depth=24,
            props="orb_video_check.sv",
            values={"LOW_MAX": 2 * 4 * 2 - 1},  # 2 WIDTH_g HEIGHT_g - 1
            extra_props={
                "frame_shape": "every output frame is WIDTH_g x HEIGHT_g: tuser at (0, 0), tlast at x = WIDTH_g - 1",
                "frame_end_last": "frame_end exactly with the frame's last output beat",
                "rate": "s_axis_video_tready low for at most 2 WIDTH_g HEIGHT_g - 1 = 15 clocks in a row (padding a "
                "bad frame, then the next one when the start of frame held meanwhile is bad itself; 14 fails)",
                "latency": "a pixel taken is on m_axis_video VIDEO_CHECK_LAT_c = 1 clock later (the same value), or "
                "counted in discarded_pixels, or held (tready falls)",
            },
            mutations=(
                Mutation(
                    "padding_forever",
                    "padding does not stop at the padded frame's last position",
                    "input/orb_video_check.vhd",
                    r"open_v    := '0';\n(\s*)padding_v := '0';",
                    "open_v    := '0';",
                    "rate",
                ),
                Mutation(
                    "discard_uncounted",
                    "a pixel outside any frame is dropped without being counted",
                    "input/orb_video_check.vhd",
                    r"disc_cnt <= disc_cnt \+ 1;",
                    "disc_cnt <= disc_cnt;",
                    "latency",
                ),
                *_VIDEO_CHECK_SHAPE_BUGS,
            ),
        ),
        Check(
            "orb_video_check",
            {"WIDTH_g": 4, "HEIGHT_g": 2, "IDLE_TIMEOUT_g": 3},
            name="orb_video_check.live",
            mode="bmc",
            depth=24,
            props="orb_video_check.live.sv",
            values={"GAP_MAX": LIVE_GAP},
            extra_props={
                "frame_shape": "every output frame is WIDTH_g x HEIGHT_g: tuser at (0, 0), tlast at x = WIDTH_g - 1",
                "frame_end_last": "frame_end exactly with the frame's last output beat",
                "never_held": "s_axis_video_tready is 1 from the second clock out of reset on (a live source is "
                "never held)",
                "latency": "a pixel taken is on m_axis_video VIDEO_CHECK_LAT_c = 1 clock later (the same value), or "
                "counted in discarded_pixels",
                "idle_timeout": f"inside an output frame at most {LIVE_GAP} clocks in a row without an output beat "
                f"(IDLE_TIMEOUT_g = 3: the open frame is padded; {LIVE_GAP - 1} fails)",
            },
            mutations=(
                Mutation(
                    "live_held",
                    "a live source held like one that can wait: tready low while a frame is padded",
                    "input/orb_video_check.vhd",
                    r"^      if LIVE_c then\n        ready <= '1';\n      end if;\n",
                    "",
                    "never_held",
                ),
                Mutation(
                    "no_idle_timeout",
                    "the idle timeout never fires: a cut frame stays open until the next start of frame",
                    "input/orb_video_check.vhd",
                    r"elsif LIVE_c and is_open = '1' and padding = '0' and idle = IDLE_TIMEOUT_g - 1 then",
                    "elsif false then",
                    "idle_timeout",
                ),
                Mutation(
                    "live_discard_uncounted",
                    "a live pixel arriving while a frame is padded is dropped without being counted",
                    "input/orb_video_check.vhd",
                    r"(if LIVE_c and s_axis_video_tvalid = '1' and ready = '1' then\n\s*)discard <= true;",
                    r"\1null;",
                    "latency",
                ),
                *_VIDEO_CHECK_SHAPE_BUGS,
            ),
        ),
        Check(
            "orb_feat_merge",
            {"SCALES_g": 2, "FIFO_DEPTH_g": 2, "DESC_g": "false"},
            mutations=(
                _stall_bug(
                    "core/orb_feat_merge.vhd",
                    r"go_v    := o_valid = '0' or m_axis_feat_tready = '1';",
                    "go_v    := true;",
                    "feat",
                ),
            ),
        ),
        Check(
            "orb_feat_merge",
            {"SCALES_g": 2, "FIFO_DEPTH_g": 2, "DESC_g": "false"},
            name="orb_feat_merge.conserve",
            mode="bmc",
            depth=12,
            quick=False,  # 23 s at depth 12 (3 s at depth 10); its planted bug 3 s
            props="orb_feat_merge.conserve.sv",
            extra_props={
                "no_invention": "nothing out that did not go in: features out plus those counted dropped never "
                "exceed those given; end-of-frame beats never exceed any scale's frame ends",
            },
            bugs_of={"chk_m_axis_feat": "orb_feat_merge"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "the output register loads whenever it may, whether a FIFO offers a feature or not",
                    "core/orb_feat_merge.vhd",
                    r"pop_any <= go_v and request_v /= \(request_v'range => '0'\);",
                    "pop_any <= go_v;",
                    "no_invention",
                ),
            ),
        ),
        Check(
            "orb_feat_merge",
            {"SCALES_g": 2, "FIFO_DEPTH_g": 2, "DESC_g": "false"},
            name="orb_feat_merge.timing",
            bugs_of={"chk_m_axis_feat": "orb_feat_merge"},
            mode="bmc",
            depth=12,
            props="orb_feat_merge.timing.sv",
            extra_props={
                "rate": "with the sink always ready and at most one feature a clock in all (no frame end), no "
                "feature is lost",
                "latency": "with the sink always ready, a lone feature given when nothing waits is on m_axis_feat "
                "FEAT_MERGE_LAT_c = 3 clocks later with its x, y, score and scale",
            },
            mutations=(
                Mutation(
                    "loss_miscounted",
                    "a write into a full FIFO counted as lost although a feature leaves it in that clock",
                    "core/orb_feat_merge.vhd",
                    r"fifo_room\(k\)  <= '1' when fifo_level\(k\) < FIFO_DEPTH_g or grant\(k\) = '1' else",
                    "fifo_room(k)  <= '1' when fifo_level(k) < FIFO_DEPTH_g else",
                    "rate",
                ),
                Mutation(
                    "served_in_turn",
                    "a scale is served only when the round-robin pointer is at it (which moves only on a grant)",
                    "core/orb_feat_merge.vhd",
                    r"request_v\(k\) := fifo_valid\(k\);",
                    "if rr = k then request_v(k) := fifo_valid(k); end if;",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_overlay",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "BLOCK_LOG2_g": 2},
            props="orb_overlay.sv",
            extra_props={"feat_ready": "s_axis_feat_tready is 1 in every clock out of reset (documented)"},
            mutations=(
                _stall_bug(
                    "output/orb_overlay.vhd", r"ce    <= m_axis_video_tready or not m_valid;", "ce    <= '1';", "video"
                ),
                Mutation(
                    "feat_stalls",
                    "s_axis_feat_tready low while a video beat waits",
                    "output/orb_overlay.vhd",
                    r"s_axis_feat_tready <= '1';",
                    "s_axis_feat_tready <= ce;",
                    "feat_ready",
                ),
            ),
        ),
        Check(
            "orb_overlay",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "BLOCK_LOG2_g": 2},
            name="orb_overlay.conserve",
            probes=("d1_valid", "d2_valid"),
            props="orb_overlay.conserve.sv",
            extra_props={
                "no_invention": "nothing out that did not go in, nothing lost: the video beats taken and not given "
                "are exactly those its 3 stages hold (valid bits probed)"
            },
            bugs_of={"chk_m_axis_video": "orb_overlay"},
            mutations=(
                Mutation(
                    "invents_beats",
                    "stage 2 offers the beat of an empty stage 1 when its tuser bit is set",
                    "output/orb_overlay.vhd",
                    r"d2_valid <= d1_valid;",
                    "d2_valid <= d1_valid or d1_user;",
                    "no_invention",
                ),
            ),
        ),
        Check(
            "orb_overlay",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "BLOCK_LOG2_g": 2},
            name="orb_overlay.timing",
            bugs_of={"chk_m_axis_video": "orb_overlay"},
            props="orb_overlay.timing.sv",
            extra_props={
                "rate": "with the sink always ready, s_axis_video_tready is 1 in every clock out of reset",
                "latency": "with the sink always ready, every video beat taken is on m_axis_video "
                "OVERLAY_VIDEO_LAT_c = 3 clocks later, in order, nothing else, with its tuser and tlast",
            },
            mutations=(
                Mutation(
                    "ready_waits_empty",
                    "s_axis_video_tready only while the output register is empty (back-pressure without the sink)",
                    "output/orb_overlay.vhd",
                    r"ce    <= m_axis_video_tready or not m_valid;",
                    "ce    <= not m_valid;",
                    "rate",
                ),
                Mutation(
                    "tlast_early",
                    "the output's tlast taken from stage 1 instead of stage 2 (a clock early)",
                    "output/orb_overlay.vhd",
                    r"m_last  <= d2_last;",
                    "m_last  <= d1_last;",
                    "latency",
                ),
            ),
        ),
        Check(
            "orb_feat_mem",
            {"DEPTH_g": 16, "SEL_SLOTS_g": 2},
            props="orb_feat_mem.sv",
            extra_props={"feat_ready": "s_axis_feat_tready is 1 in every clock out of reset (documented)"},
            mutations=(
                Mutation(
                    "feat_stalls",
                    "s_axis_feat_tready low while a bank is released",
                    "host/orb_feat_mem.vhd",
                    r"s_axis_feat_tready <= '1';",
                    "s_axis_feat_tready <= not release_valid;",
                    "feat_ready",
                ),
            ),
        ),
        Check(
            "orb_feat_mem",
            {"DEPTH_g": 16, "SEL_SLOTS_g": 2},
            name="orb_feat_mem.banks",
            probes=_FEAT_MEM_PROBES,
            props="orb_feat_mem.banks.sv",
            extra_props={
                "held_header_stable": "a READY bank's header (count, frame, truncated, dropped) does not change "
                "until the CPU releases it",
                "ready_until_release": "a READY bank stays READY until the CPU releases it (or rst)",
                "held_not_written": "the RAM's write port never writes a held bank (READY and not being released)",
                "count_record": "the count and the end-of-frame record agree: in a READY bank (the RAM's writes "
                "followed) slot count holds the record last written, with the header's count, truncated flag, "
                "frame, dropped and truncated counts, and no slot below count holds a record",
                "banks_alternate": "frames are published into bank 0, 1, 0, ... from reset (frame_done, last_bank)",
                "bank_choice": "a frame is published iff its bank was free at its first beat (not READY, or "
                "released in that clock) and no frame_abort came; else counted once in overrun or aborted",
            },
            mutations=(
                Mutation(
                    "header_overwritten",
                    "every end of frame writes both banks' headers (the held one's too)",
                    "host/orb_feat_mem.vhd",
                    r"^            if wbank = BANK_c\(k\) then",
                    "            if true then",
                    "held_header_stable",
                ),
                Mutation(
                    "ready_dropped_on_abort",
                    "a frame_abort pulse also frees the READY banks",
                    "host/orb_feat_mem.vhd",
                    r"if in_rel = '1' and in_relb = BANK_c\(k\) then",
                    "if (in_rel = '1' and in_relb = BANK_c(k)) or in_abort = '1' then",
                    "ready_until_release",
                ),
                Mutation(
                    "record_other_bank",
                    "the end-of-frame record written into the other bank (the held one)",
                    "host/orb_feat_mem.vhd",
                    r"wr_addr  <= wbank & cnt when",
                    "wr_addr  <= (not wbank) & cnt when",
                    "held_not_written",
                ),
                Mutation(
                    "count_plus_one",
                    "the header's count one more than the features stored (the record's slot)",
                    "host/orb_feat_mem.vhd",
                    r"h_count\(k\) <= resize\(cnt, 16\);",
                    "h_count(k) <= resize(cnt + 1, 16);",
                    "count_record",
                ),
                Mutation(
                    "bank_not_toggled",
                    "the write bank does not change at a publication: a released bank 0 takes every frame",
                    "host/orb_feat_mem.vhd",
                    r"wbank      <= not wbank;",
                    "wbank      <= wbank;",
                    "banks_alternate",
                ),
                Mutation(
                    "release_same_clock_ignored",
                    "a release in the clock of a frame's first beat does not free the bank for it (the frame is "
                    "skipped although its bank is released)",
                    "host/orb_feat_mem.vhd",
                    r"if ready\(bank_index\(wbank\)\) = '0' or \(in_rel = '1' and in_relb = wbank\) then",
                    "if ready(bank_index(wbank)) = '0' then",
                    "bank_choice",
                ),
            ),
        ),
        Check(
            "orb_feat_mem",
            {"DEPTH_g": 16, "SEL_SLOTS_g": 2},
            name="orb_feat_mem.read",
            mode="bmc",
            depth=12,
            props="orb_feat_mem.read.sv",
            extra_props={
                "published_stable": "a published bank never changes, seen at the CPU port: reads of one address "
                "(any) while the bank stays held return the same word",
            },
            mutations=(
                Mutation(
                    "skipped_frame_written",
                    "a skipped frame's beats written into its (held) bank: the write enable ignores the bank choice",
                    "host/orb_feat_mem.vhd",
                    r"wr_en    <= beat and store_nw and not abort_nw",
                    "wr_en    <= beat and not abort_nw",
                    "published_stable",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            _DMA_GENERICS,
            mode="bmc",
            depth=DMA_DEPTH,
            quick=False,  # about a minute (2 cores shared), each planted bug 10-30 s
            axi4w=_DMA_AXI4W,
            engine=_DMA_ENGINE,
            props="orb_feat_dma.sv",
            values=_dma_window(_DMA_GENERICS),
            extra_props=_DMA_ADDR_PROPS,
            bugs_of={"chk_m_axi_feat.outstanding": "orb_feat_dma.out1"},
            mutations=(
                Mutation(
                    "wlast_early",
                    "WLAST one beat early (on beat 7 of 8)",
                    _DMA,
                    r"m_axi_feat_wlast   <= '1' when wbeat = BEATS_c - 1 else",
                    "m_axi_feat_wlast   <= '1' when wbeat = BEATS_c - 2 else",
                    "chk_m_axi_feat.w_last",
                ),
                Mutation(
                    "soft_reset_cuts_burst",
                    "the rule that finishes a launched burst removed: rst drops AWVALID and WVALID at once",
                    _DMA,
                    r"if state = addr1_s or state = addr2_s or state = addr3_s then\n\s*state <= idle_s;\n\s*end if;",
                    "state     <= idle_s;\n        awvalid_r <= '0';\n        wvalid_r  <= '0';",
                    "chk_m_axi_feat.aw_hold",
                ),
                Mutation(
                    "soft_reset_drops_wvalid",
                    "rst drops WVALID in the middle of a burst (AWVALID kept)",
                    _DMA,
                    r"stale    <= inflight_v;",
                    "stale    <= inflight_v;\n        wvalid_r <= '0';",
                    "chk_m_axi_feat.w_hold",
                ),
                Mutation(
                    "bus_reset_keeps_awvalid",
                    "bus_rst does not clear AWVALID",
                    _DMA,
                    r"(if bus_rst = '1' then\n\s*state     <= idle_s;\n)\s*awvalid_r <= '0';\n",
                    r"\1",
                    "chk_m_axi_feat.reset_low",
                ),
                Mutation(
                    "awsize_32bit",
                    "AWSIZE of a 32-bit port (010) on the 64-bit bus",
                    _DMA,
                    r'm_axi_feat_awsize  <= "011";',
                    'm_axi_feat_awsize  <= "010";',
                    "chk_m_axi_feat.aw_burst",
                ),
                Mutation(
                    "slot_not_shifted",
                    "the slot's address not shifted by 6 (base + slot instead of base + 64 slot): bursts cross 4 KiB",
                    _DMA,
                    r"b_start <= act_base \+ shift_left\(resize\(b_slot, 32\), 6\);",
                    "b_start <= act_base + resize(b_slot, 32);",
                    "chk_m_axi_feat.aw_4k",
                ),
                Mutation(
                    "w_before_aw",
                    "WVALID raised in the last address stage, a clock before AWVALID: a W beat without an address",
                    _DMA,
                    r"b_prod <= resize\(b_lo \+ b_hi, 32\);",
                    "b_prod <= resize(b_lo + b_hi, 32);\n        wvalid_r <= '1';",
                    "chk_m_axi_feat.w_after_aw",
                ),
                Mutation(
                    "wvalid_never",
                    "WVALID not raised with AWVALID: the next burst's address without the data of the one before",
                    _DMA,
                    r"wvalid_r  <= '1';",
                    "wvalid_r  <= '0';",
                    "chk_m_axi_feat.aw_ahead",
                ),
                Mutation(
                    "base_unchecked",
                    "RING_BASE's alignment not checked (only the stride's)",
                    _DMA,
                    r"if cfg_base\(5 downto 0\) /= 0 or cfg_stride\(5 downto 0\) /= 0 then",
                    "if cfg_stride(5 downto 0) /= 0 then",
                    "aw_aligned",
                ),
                Mutation(
                    "live_ring_address",
                    "the address computed with the live ring registers (cfg_base) instead of the active ring",
                    _DMA,
                    r"b_start <= act_base \+",
                    "b_start <= cfg_base +",
                    "aw_in_window",
                ),
                Mutation(
                    "ring_count_above_16",
                    "the registers' contract dropped: RING_COUNT 17 .. 31 (which the register map refuses) passes the "
                    "checks as count - 1 mod 16, and a frame goes past the checked ring (the contract is needed)",
                    "wrapper",
                    r"^  always @\(\*\) assume \(ring_count <= 16\);\n",
                    "",
                    "aw_in_window",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            {**_DMA_GENERICS, "OUTSTANDING_g": 1},
            name="orb_feat_dma.out1",
            mode="bmc",
            depth=DMA_OUT1_DEPTH,
            quick=False,  # about a minute
            axi4w={**_DMA_AXI4W, "MAX_OUTSTANDING": 1},
            engine=_DMA_ENGINE,
            props="orb_feat_dma.sv",
            values=_dma_window(_DMA_GENERICS),
            extra_props=_DMA_ADDR_PROPS,
            bugs_of={"chk_m_axi_feat": "orb_feat_dma", "aw_aligned": "orb_feat_dma", "aw_in_window": "orb_feat_dma"},
            mutations=(
                Mutation(
                    "outstanding_off_by_one",
                    "the master takes a slot while OUTSTANDING_g bursts are unanswered (<= for <)",
                    _DMA,
                    r"inflight < OUTSTANDING_g and rst = '0'",
                    "inflight <= OUTSTANDING_g and rst = '0'",
                    "chk_m_axi_feat.outstanding",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            _DMA_GENERICS,
            name="orb_feat_dma.ring",
            mode="bmc",
            depth=DMA_DEPTH,
            quick=False,  # 2-3 minutes: the buffers' starts against the master's address arithmetic
            engine=_DMA_ENGINE,
            props="orb_feat_dma.ring.sv",
            values=_dma_window(_DMA_GENERICS),
            extra_props={
                "aw_in_ring": "with the ring registers constant and legal, every burst (64 bytes at AWADDR) inside a "
                "buffer of the ring: [base + i stride, + DEPTH_g 64) for some i < count (the slave unconstrained)",
            },
            mutations=(
                Mutation(
                    "pos_wraps_late",
                    "the ring position wraps after buffer count instead of count - 1: a frame written past the ring",
                    _DMA,
                    r"if resize\(cur_buf, 5\) \+ 1 >= eff_count then",
                    "if resize(cur_buf, 5) + 1 > eff_count then",
                    "aw_in_ring",
                ),
            ),
        ),
        Check(
            "orb_feat_dma",
            _DMA_GENERICS,
            name="orb_feat_dma.off",
            mode="bmc",
            depth=DMA_DEPTH,
            quick=False,  # 20-40 s
            engine=_DMA_ENGINE,
            props="orb_feat_dma.off.sv",
            values=_dma_window(_DMA_GENERICS),
            extra_props={
                "no_write": "with the ring registers constant and in error (unaligned, overlapping, outside the "
                "window or off), no AWVALID, ever",
            },
            mutations=(
                Mutation(
                    "window_end_unchecked",
                    "the ring's end not checked against the window (only its start)",
                    _DMA,
                    r"if chk_err2\(2\) = '1' or chk_top > WIN_HI_c then",
                    "if chk_err2(2) = '1' then",
                    "no_write",
                ),
            ),
        ),
        Check(
            "orb_core",
            {"WIDTH_g": 64, "HEIGHT_g": 48, "SCALES_g": 1, "SECTORS_g": 16, "FIFO_DEPTH_g": 2, "BUDGET_MAX_g": 15},
            quick=False,  # 20 s, its planted bugs 10-25 s each
            props="orb_core.sv",
            extra_props={"video_ready": "s_axis_video_tready is 1 in every clock out of reset (documented)"},
            mutations=(
                Mutation(
                    "ignores_tready",
                    "the output stage (orb_desc_rotate's) loads whatever tready says and offers a beat every "
                    "other clock by itself (reachable right after reset: no feature reaches the output that soon)",
                    "describe/orb_desc_rotate.vhd",
                    r"take <= not q_valid or m_axis_feat_tready;",
                    "take <= '1';",
                    "chk_m_axis_feat",
                    more=((r"q_valid <= s_axis_feat_tvalid;", "q_valid <= s_axis_feat_tvalid or not q_valid;"),),
                ),
                Mutation(
                    "video_stalls",
                    "s_axis_video_tready low in the clock after a start of frame",
                    "core/orb_core.vhd",
                    r"^      ready       <= '1';",
                    "      ready       <= not s_axis_video_tuser;",
                    "video_ready",
                ),
            ),
        ),
        Check(
            "orb_axil_regs",
            {"WIDTH_g": 128, "HEIGHT_g": 96, "SCALES_g": 2, "SECTORS_g": 32, "MEM_DEPTH_g": 512, "MEM_LATENCY_g": 2},
            mode="bmc",
            depth=12,
            axil={"MAXW": 2, "MAXR": 1, "BOUND": 4, "RBOUND": 4, "REGMAP": 1, "MEM_DEPTH": 512},
            mutations=(
                Mutation(
                    "bresp_always_okay",
                    "every write answered OKAY",
                    "host/orb_axil_regs.vhd",
                    r"bresp_r       <= OKAY_c when decoded.ok = '1' else SLVERR_c;",
                    "bresp_r       <= OKAY_c;",
                    "chk_s_axil.b_slverr",
                ),
                Mutation(
                    "rresp_unknown_okay",
                    "a read of an unknown register answered OKAY",
                    "host/orb_axil_regs.vhd",
                    r"rresp_r <= OKAY_c;\n(\s*)else\n(\s*)rresp_r <= SLVERR_c;",
                    "rresp_r <= OKAY_c;\n\\1else\n\\2rresp_r <= OKAY_c;",
                    "chk_s_axil.r_slverr",
                ),
                Mutation(
                    "b_dropped",
                    "bvalid cleared without bready",
                    "host/orb_axil_regs.vhd",
                    r"if bvalid_r = '1' and s_axil_bready = '1' then",
                    "if bvalid_r = '1' then",
                    "chk_s_axil.b_held",
                ),
                Mutation(
                    "r_dropped",
                    "rvalid cleared without rready",
                    "host/orb_axil_regs.vhd",
                    r"if rvalid_r = '1' and s_axil_rready = '1' then",
                    "if rvalid_r = '1' then",
                    "chk_s_axil.r_held",
                ),
                Mutation(
                    "b_without_w",
                    "a write decoded without waiting for its W (executed with the last W's data and strobes)",
                    "host/orb_axil_regs.vhd",
                    r"write_take <= aw_full = '1' and w_full = '1' and",
                    "write_take <= aw_full = '1' and",
                    "chk_s_axil.b_slverr",
                ),
                Mutation(
                    "b_on_read",
                    "a B response raised by a read request",
                    "host/orb_axil_regs.vhd",
                    r"if decoded_valid = '1' then\n(\s*)decoded_valid <= '0';",
                    "if decoded_valid = '1' or s_axil_arvalid = '1' then\n\\1decoded_valid <= '0';",
                    "chk_s_axil.b_no_req",
                ),
                Mutation(
                    "r_on_write",
                    "an R response raised by a write request",
                    "host/orb_axil_regs.vhd",
                    r"if mem_pipe\(mem_pipe'high\) = '1' then",
                    "if mem_pipe(mem_pipe'high) = '1' or s_axil_awvalid = '1' then",
                    "chk_s_axil.r_no_req",
                ),
                Mutation(
                    "ar_while_busy",
                    "arready 1 while a read is answered (a second read taken)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_arready <= not ar_busy;",
                    "s_axil_arready <= '1';",
                    "chk_s_axil.r_outstanding",
                    more=((r"if s_axil_arvalid = '1' and ar_busy = '0' then", "if s_axil_arvalid = '1' then"),),
                ),
                Mutation(
                    "write_waits_rready",
                    "a write decoded only while rready is 1 (the master may hold it low)",
                    "host/orb_axil_regs.vhd",
                    r"and decoded_valid = '0';",
                    "and decoded_valid = '0' and s_axil_rready = '1';",
                    "chk_s_axil.b_bound",
                ),
                Mutation(
                    "aw_waits_w",
                    "awready only while wvalid is 1 (the documented AW-before-W order refused)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_awready <= not aw_full;",
                    "s_axil_awready <= not aw_full and s_axil_wvalid;",
                    "chk_s_axil.aw_live",
                    more=(
                        (
                            r"if s_axil_awvalid = '1' and aw_full = '0' then",
                            "if s_axil_awvalid = '1' and aw_full = '0' and s_axil_wvalid = '1' then",
                        ),
                    ),
                ),
                Mutation(
                    "w_waits_aw",
                    "wready only while awvalid is 1 (the documented W-before-AW order refused)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_wready  <= not w_full;",
                    "s_axil_wready  <= not w_full and s_axil_awvalid;",
                    "chk_s_axil.w_live",
                    more=(
                        (
                            r"if s_axil_wvalid = '1' and w_full = '0' then",
                            "if s_axil_wvalid = '1' and w_full = '0' and s_axil_awvalid = '1' then",
                        ),
                    ),
                ),
                Mutation(
                    "ar_waits_aw",
                    "arready low while awvalid is 1 (reads starved by a waiting write)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_arready <= not ar_busy;",
                    "s_axil_arready <= not ar_busy and not s_axil_awvalid;",
                    "chk_s_axil.ar_live",
                    more=(
                        (
                            r"if s_axil_arvalid = '1' and ar_busy = '0' then",
                            "if s_axil_arvalid = '1' and ar_busy = '0' and s_axil_awvalid = '0' then",
                        ),
                    ),
                ),
                Mutation(
                    "aw_while_full",
                    "awready 1 while the AW buffer is full (a request overwritten)",
                    "host/orb_axil_regs.vhd",
                    r"s_axil_awready <= not aw_full;",
                    "s_axil_awready <= '1';",
                    "chk_s_axil.w_outstanding",
                ),
                Mutation(
                    "ar_stuck",
                    "arready held low after a read of the memory window",
                    "host/orb_axil_regs.vhd",
                    r"elsif addr_v >= MEM_BASE_c then\n(\s*)mem_en_r <= '1';",
                    "elsif addr_v >= MEM_BASE_c then\n\\1mem_en_r <= '0';",
                    "chk_s_axil.r_bound",
                ),
            ),
        ),
        Check(
            "orb_accel_top",
            {k: v for k, v in _ZYNQ_GENERICS.items() if k != "C_S_AXI_CTRL_ADDR_WIDTH"},
            mode="bmc",
            depth=10,
            quick=False,
            axil=_TOP_AXIL,
            bugs_of={"chk_s_axil": "orb_axil_regs"},
            mutations=(
                Mutation(
                    "soft_reset_drops_video",
                    "the old top: CTRL.soft_reset resets the overlay at once, withdrawing a beat that waits on "
                    "m_axis_video",
                    "top/orb_accel_top.vhd",
                    r"^  ov_rst <= rst or hard_rst or .*$",
                    "  ov_rst <= core_rst;",
                    "chk_m_axis_video",
                ),
            ),
        ),
        Check(
            "orb_accel_zynq",
            _ZYNQ_GENERICS,
            mode="bmc",
            depth=10,
            quick=False,
            axil=_TOP_AXIL,
            props="orb_accel_zynq.sv",
            bugs_of={"chk_s_axil": "orb_axil_regs"},
            mutations=(
                Mutation(
                    "reset_late",
                    "the wrapper before this check: aresetn only registered into orb_accel_top's rst, so a one-clock "
                    "pulse resets the top a clock late, and it answers after the pulse a read it took before",
                    "top/orb_accel_zynq.vhd",
                    r"^  rst <= \(not aresetn\) or rst_q;$",
                    "  rst <= rst_q;",
                    "chk_s_axil.r_no_req",
                ),
                Mutation(
                    "master_early",
                    "AXI's reset rule dropped: the master raises arvalid in the clock after aresetn rises, while "
                    "orb_accel_top is still in reset and takes the read without answering (the rule is needed)",
                    "wrapper",
                    r"assume \(!s_axi_ctrl_awvalid && !s_axi_ctrl_wvalid && !s_axi_ctrl_arvalid && "
                    r"!s_axis_video_tvalid\);",
                    "assume (!s_axi_ctrl_awvalid && !s_axi_ctrl_wvalid && (!s_axi_ctrl_arvalid || aresetn) && "
                    "!s_axis_video_tvalid);",
                    "chk_s_axil.r_outstanding",
                ),
                Mutation(
                    "sink_ready_tied",
                    "the wrapper ties orb_accel_top's m_axis_video_tready to 1 (the sink's tready not passed on)",
                    "top/orb_accel_zynq.vhd",
                    r"m_axis_video_tready => m_axis_video_tready,",
                    "m_axis_video_tready => '1',",
                    "chk_m_axis_video",
                ),
                Mutation(
                    "bready_tied",
                    "the wrapper ties orb_accel_top's s_axil_bready to 1 (the master's bready not passed on)",
                    "top/orb_accel_zynq.vhd",
                    r"s_axil_bready       => s_axi_ctrl_bready,",
                    "s_axil_bready       => '1',",
                    "chk_s_axil.b_held",
                ),
            ),
        ),
        Check(
            "orb_accel_zynq",
            _ZYNQ_GENERICS,
            name="orb_accel_zynq.timing",
            mode="bmc",
            depth=14,
            quick=False,
            axil=_TOP_AXIL,
            props="orb_accel_zynq.timing.sv",
            values=_ZYNQ_TIMING,
            bugs_of={"chk_s_axil": "orb_axil_regs", "chk_m_axis_video": "orb_accel_zynq"},
            extra_props={
                "rate": "with the sink always ready and no soft reset, s_axis_video_tready is 1 from the clock after "
                "the third edge that samples aresetn high on (the wrapper's live video checker never holds the "
                "input; a clock earlier fails: the top and its core leave reset a clock apart)",
                "latency": "with the sink always ready and no soft reset, every video beat taken is on m_axis_video "
                "OVERLAY_VIDEO_LAT_c = 3 clocks later, in order, nothing else, with its tuser and tlast",
            },
            mutations=(
                Mutation(
                    "wrapper_not_live",
                    "the wrapper's video checker not live (IDLE_TIMEOUT_g 0, orb_accel_top's default): it holds "
                    "the input while it pads a bad frame",
                    "top/orb_accel_zynq.vhd",
                    r"IDLE_TIMEOUT_g => IDLE_TIMEOUT_g",
                    "IDLE_TIMEOUT_g => 0",
                    "rate",
                ),
                Mutation(
                    "overlay_tlast_early",
                    "the overlay's tlast taken from stage 1 instead of stage 2 (a clock early)",
                    "output/orb_overlay.vhd",
                    r"m_last  <= d2_last;",
                    "m_last  <= d1_last;",
                    "latency",
                ),
            ),
        ),
    )
}
