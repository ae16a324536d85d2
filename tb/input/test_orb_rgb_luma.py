# SPDX-License-Identifier: MIT
"""orb_rgb_luma through independent AXI4-Stream bus models (cocotbext-axi), bit-exact with
golden_model.luma.rgb_to_luma.

Every input beat must come out as exactly one luma beat, in order, with its tuser and tlast. The
inputs: crops of real colour photographs (scikit-image's astronaut, coffee, chelsea) sent as video
(one AXI frame per line, tuser on each frame's first pixel); a structured sweep of every (R, G, B)
on a grid of step 17 (0, 17, ..., 255) plus every rounding tie (77 R + 150 G + 29 B = 128 mod 256:
one B per (R, G), 65536 in all, or an evenly spread part of them) and their neighbours one below
and above, with random tuser bits and random line lengths. The source idles at random and the sink
stalls at random (pause generators). Both 24-bit packings (INPUT_g "RGB" and "RBG", Digilent
dvi2rgb's red/blue/green) and the 8-bit luma passthrough ("LUMA") are run. A run without pauses
checks the rate (one beat per clock) and the latency (3 clocks from the edge accepting a beat to
the edge where the sink can take its luma).
"""

from __future__ import annotations

import warnings

import cocotb
import numpy as np
import skimage.data
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge, with_timeout
from cocotb.utils import get_sim_time, get_time_from_sim_steps

from golden_model.latency import RGB_LUMA_LAT
from golden_model.luma import rgb_to_luma
from orbtb.runner import run
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int, env_str, pause_pattern

warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotbext\..*")
warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotb_bus\..*")

from cocotbext.axi import AxiStreamBus, AxiStreamFrame, AxiStreamSink, AxiStreamSource  # noqa: E402


def pack(rgb: np.ndarray, packing: str) -> np.ndarray:
    """(..., 3) uint8 RGB as the tdata words of `packing` ("RGB", "RBG"; "LUMA": the luma byte)."""
    c = rgb.astype(np.int64)
    r, g, b = c[..., 0], c[..., 1], c[..., 2]
    if packing == "RGB":
        return (r << 16) | (g << 8) | b
    if packing == "RBG":
        return (r << 16) | (b << 8) | g
    if packing == "LUMA":
        return rgb_to_luma(rgb.reshape(1, -1, 3)).reshape(rgb.shape[:-1]).astype(np.int64)
    raise ValueError(packing)


def sweep_pixels(tie_stride: int) -> np.ndarray:
    """(N, 3) uint8: a grid of step 17 on every channel, then every tie_stride-th (R, G) pair's
    rounding tie (77 R + 150 G + 29 B = 128 mod 256) and the sums one below and one above it."""
    steps = np.arange(0, 256, 17)
    grid = np.stack(np.meshgrid(steps, steps, steps, indexing="ij"), axis=-1).reshape(-1, 3)
    inv29 = pow(29, -1, 256)
    rg = np.stack(np.meshgrid(np.arange(256), np.arange(256), indexing="ij"), axis=-1).reshape(-1, 2)
    rg = rg[::tie_stride]
    out = [grid]
    for target in (128, 127, 129):
        b = ((target - 77 * rg[:, 0] - 150 * rg[:, 1]) * inv29) % 256
        out.append(np.column_stack([rg, b]))
    pixels = np.concatenate(out).astype(np.uint8)
    ties = pixels[len(grid) : len(grid) + len(rg)].astype(np.int64)
    assert np.all((77 * ties[:, 0] + 150 * ties[:, 1] + 29 * ties[:, 2]) % 256 == 128)
    return pixels


def photo_crop(name: str, width: int, height: int) -> np.ndarray:
    img = getattr(skimage.data, name)()[..., :3]
    h, w = img.shape[:2]
    y0, x0 = (h - height) // 2, (w - width) // 2
    return np.ascontiguousarray(img[y0 : y0 + height, x0 : x0 + width])


class Bench:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.packing = env_str("ORB_INPUT", "RGB")
        self.in_bits = 8 if self.packing == "LUMA" else 24

    async def start(self, idle_prob: float, stall_prob: float) -> None:
        dut = self.dut
        dut.rst.value = 1
        for name in ("tvalid", "tuser", "tlast", "tdata"):
            getattr(dut, f"s_axis_video_{name}").value = 0
        dut.m_axis_video_tready.value = 0
        cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
        self.source = AxiStreamSource(
            AxiStreamBus.from_prefix(dut, "s_axis_video"), dut.clk, dut.rst, byte_size=self.in_bits
        )
        self.sink = AxiStreamSink(AxiStreamBus.from_prefix(dut, "m_axis_video"), dut.clk, dut.rst, byte_size=8)
        self.source.log.setLevel("WARNING")
        self.sink.log.setLevel("WARNING")
        if idle_prob > 0:
            self.source.set_pause_generator(pause_pattern(1, idle_prob))
        if stall_prob > 0:
            self.sink.set_pause_generator(pause_pattern(2, stall_prob))
        await ClockCycles(dut.clk, 4)
        assert int(dut.s_axis_video_tready.value) == 0, "tready high in reset"
        dut.rst.value = 0
        await RisingEdge(dut.clk)
        await RisingEdge(dut.clk)
        assert int(dut.s_axis_video_tready.value) == 1, "tready not high after reset"

    async def check(self, rgb: np.ndarray, tuser: list[int], line_ends: list[int], what: str) -> list:
        """Send the (N, 3) pixels as AXI frames ending (tlast) after the indices in line_ends, with
        tuser per beat; receive and compare every beat. Returns the received frames."""
        words = pack(rgb, self.packing).ravel().tolist()
        expected = rgb_to_luma(rgb.reshape(1, -1, 3)).ravel().tolist()
        assert line_ends[-1] == len(words) - 1
        start = 0
        for end in line_ends:
            await self.source.send(
                AxiStreamFrame(
                    words[start : end + 1] if self.in_bits == 24 else bytes(words[start : end + 1]),
                    tuser=tuser[start : end + 1],
                )
            )
            start = end + 1
        got_data: list[int] = []
        got_user: list[int] = []
        got_ends: list[int] = []
        frames = []
        timeout = 20 * len(words) * PERIOD_NS + 10_000
        for _ in line_ends:
            rx = await with_timeout(self.sink.recv(compact=False), timeout, "ns")
            frames.append(rx)
            got_data += list(rx.tdata)
            got_user += [int(u) for u in rx.tuser]
            got_ends.append(len(got_data) - 1)
        assert got_ends == line_ends, f"{what}: tlast after beats {got_ends[:8]}..., expected {line_ends[:8]}..."
        for i, (g, e) in enumerate(zip(got_data, expected, strict=True)):
            if g != e:
                r, gg, b = (int(v) for v in rgb[i])
                raise AssertionError(
                    f"{what}: beat {i} (R={r}, G={gg}, B={b}, tdata={words[i]:#x}) gave luma {g}, expected {e}"
                )
        if got_user != tuser:
            first = next(i for i, (a, b) in enumerate(zip(got_user, tuser, strict=True)) if a != b)
            raise AssertionError(f"{what}: tuser of beat {first} is {got_user[first]}, expected {tuser[first]}")
        assert self.sink.empty(), f"{what}: extra beats after the expected ones"
        self.dut._log.info("%s: %d beats bit-exact, tuser/tlast passed", what, len(words))
        return frames


def video_framing(width: int, height: int) -> tuple[list[int], list[int]]:
    n = width * height
    return [1] + [0] * (n - 1), list(range(width - 1, n, width))


@cocotb.test()
async def photographs(dut) -> None:
    """Crops of three colour photographs as video frames, source idles and sink stalls."""
    b = Bench(dut)
    await b.start(idle_prob=0.3, stall_prob=0.4)
    w, h = env_int("ORB_PHOTO_W", 64), env_int("ORB_PHOTO_H", 48)
    for name in ("astronaut", "coffee", "chelsea"):
        img = photo_crop(name, w, h)
        tuser, ends = video_framing(w, h)
        await b.check(img.reshape(-1, 3), tuser, ends, f"{name} {w}x{h}")


@cocotb.test()
async def sweep(dut) -> None:
    """The structured sweep with random tuser bits and line lengths, idles and stalls."""
    b = Bench(dut)
    await b.start(idle_prob=0.25, stall_prob=0.35)
    pixels = sweep_pixels(env_int("ORB_TIE_STRIDE", 1))
    if b.packing == "LUMA":
        pixels = np.stack([np.arange(256)] * 3, axis=-1).astype(np.uint8)  # luma = value: every byte
    rng = np.random.default_rng(5)
    n = len(pixels)
    tuser = (rng.random(n) < 0.02).astype(int).tolist()
    ends = [*sorted(set(np.cumsum(rng.integers(1, 60, n)).tolist()) & set(range(n - 1))), n - 1]
    await b.check(pixels, tuser, ends, f"sweep ({n} pixels)")


@cocotb.test()
async def full_rate(dut) -> None:
    """No idles, no stalls: one beat per clock, first output RGB_LUMA_LAT clocks after the first input."""
    b = Bench(dut)
    await b.start(idle_prob=0.0, stall_prob=0.0)
    dut.m_axis_video_tready.value = 1
    img = photo_crop("coffee", 32, 8).reshape(-1, 3)
    tuser, ends = video_framing(32, 8)
    first_in = [0.0]

    async def first_accept() -> None:
        while True:
            await RisingEdge(dut.clk)
            if dut.s_axis_video_tvalid.value == 1 and dut.s_axis_video_tready.value == 1:
                first_in[0] = get_sim_time("ns")
                return

    cocotb.start_soon(first_accept())
    frames = await b.check(img, tuser, ends, "full rate")
    t_first = get_time_from_sim_steps(frames[0].sim_time_start, "ns")
    t_last = get_time_from_sim_steps(frames[-1].sim_time_end, "ns")
    span = (t_last - t_first) / PERIOD_NS
    assert span == len(img) - 1, f"{len(img)} beats took {span + 1} clocks at the output, expected {len(img)}"
    latency = (t_first - first_in[0]) / PERIOD_NS
    assert latency == RGB_LUMA_LAT, f"latency {latency} clocks, expected {RGB_LUMA_LAT}"


# ------------------------------------------------------------------------------------------------
# pytest runners


def run_luma(packing: str, env: dict[str, str] | None = None) -> None:
    run(
        "orb_rgb_luma",
        "test_orb_rgb_luma",
        {"INPUT_g": packing},
        env={**SIM_ENV, **(env or {})},
    )


def test_rgb_luma_rgb() -> None:
    run_luma("RGB")


def test_rgb_luma_rbg() -> None:
    run_luma("RBG", {"ORB_TIE_STRIDE": "7"})


def test_rgb_luma_luma() -> None:
    run_luma("LUMA")
