# SPDX-License-Identifier: MIT
"""orb_desc_rotate: the shared orbit rotation of rBRIEF on the merged feature stream.

A feature word carries the sector-0 table's 256 tests and its sector s; out comes the sector-s
descriptor: bit i is input bit golden_model.pattern.orbit_permutation(S, s)[i], every other field
unchanged; an end-of-frame word (tlast) passes unchanged. Stimulus, through cocotbext-axi with
idle cycles on the source and back-pressure on the sink: the model's features of photographs (the
input is describe() with sector 0, the output must equal describe() with the feature's sector,
which is what orb_core reports), every sector with random tests and random bits in every other
field, and end-of-frame words with random bits. Per parameter set: 16, 32 and 64 sectors, with and
without pauses.
"""

from __future__ import annotations

import warnings

import cocotb
import numpy as np
import pytest
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, with_timeout

from golden_model.brief import describe
from golden_model.config import Config
from golden_model.featcodec import encode_eof, encode_feature
from golden_model.featword import FEAT_BITS, FEATURE_BEAT
from golden_model.pattern import orbit_permutation
from golden_model.pipeline import extract
from golden_model.smooth import smooth
from orbtb import images
from orbtb.runner import run
from orbtb.unit import PERIOD_NS, SIM_ENV, env_int, pause_pattern

warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotbext\..*")
warnings.filterwarnings("ignore", category=DeprecationWarning, module=r"cocotb_bus\..*")

from cocotbext.axi import AxiStreamBus, AxiStreamFrame, AxiStreamSink, AxiStreamSource  # noqa: E402

DESC = FEATURE_BEAT.field("descriptor")
SECTOR = FEATURE_BEAT.field("sector")


def rotated(word: int, sectors: int) -> int:
    """The model's rule on one feature word (independent of the RTL's rotate_right)."""
    bits = np.array([(DESC.get(word) >> i) & 1 for i in range(DESC.width)], dtype=np.int64)
    out = bits[orbit_permutation(sectors, SECTOR.get(word))]
    return DESC.put(int(sum(int(b) << i for i, b in enumerate(out))), word)


def photo_words(sectors: int) -> tuple[list[int], list[int]]:
    """(input, expected) feature words of photographs: sector-0 tests in, the model's descriptor out."""
    words_in: list[int] = []
    words_out: list[int] = []
    for name in ("astronaut", "coffee", "camera"):
        img = images.photo(name, 160, 120)
        feats = extract(img, Config(160, 120, scales=1, sectors=sectors, threshold=10, mode="orb"))
        d0 = describe(smooth(img), feats.x, feats.y, np.zeros_like(feats.sector), sectors // 4)
        for k in range(len(feats)):
            fields = {"scale": 0, "x": int(feats.x[k]), "y": int(feats.y[k]), "score": int(feats.score[k]),
                      "sector": int(feats.sector[k])}  # fmt: skip
            words_in.append(encode_feature(**fields, descriptor=bytes(d0[k])))
            words_out.append(encode_feature(**fields, descriptor=bytes(feats.descriptor[k])))
            assert rotated(words_in[-1], sectors) == words_out[-1]  # the rule and describe() agree
    seen = {SECTOR.get(w) for w in words_in}
    assert len(words_in) > 100 and len(seen) > sectors // 2, f"{len(words_in)} features, {len(seen)} sectors"
    return words_in, words_out


def random_frames(sectors: int, rng: np.random.Generator) -> list[list[int]]:
    """Every sector several times with random tests and random bits in every field, then an
    end-of-frame word of random bits."""
    frames = []
    for _ in range(3):
        words = [SECTOR.put(int(s), int.from_bytes(rng.bytes(FEAT_BITS // 8), "little"))
                 for s in rng.permutation(np.repeat(np.arange(sectors), 2))]  # fmt: skip
        words.append(int.from_bytes(rng.bytes(FEAT_BITS // 8), "little"))
        frames.append(words)
    return frames


@cocotb.test()
async def rotation(dut) -> None:
    sectors = env_int("ORB_SECTORS")
    pauses = env_int("ORB_PAUSES")
    dut.rst.value = 1
    dut.s_axis_feat_tvalid.value = 0
    dut.s_axis_feat_tlast.value = 0
    dut.s_axis_feat_tdata.value = 0
    dut.m_axis_feat_tready.value = 0
    cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start(start_high=False))
    source = AxiStreamSource(AxiStreamBus.from_prefix(dut, "s_axis_feat"), dut.clk, dut.rst, byte_size=FEAT_BITS)
    sink = AxiStreamSink(AxiStreamBus.from_prefix(dut, "m_axis_feat"), dut.clk, dut.rst, byte_size=FEAT_BITS)
    if pauses:
        source.set_pause_generator(pause_pattern(3, 0.3))
        sink.set_pause_generator(pause_pattern(4, 0.4))
    await ClockCycles(dut.clk, 4)
    dut.rst.value = 0
    await ClockCycles(dut.clk, 2)

    rng = np.random.default_rng(sectors)
    words_in, words_out = photo_words(sectors)
    frames_in = [[*words_in, encode_eof(0)]]
    frames_out = [[*words_out, encode_eof(0)]]
    for words in random_frames(sectors, rng):
        frames_in.append(words)
        frames_out.append([rotated(w, sectors) for w in words[:-1]] + [words[-1]])
    for words in frames_in:
        await source.send(AxiStreamFrame(words))
    for f, want in enumerate(frames_out):
        rx = await with_timeout(sink.recv(), 40 * len(want) * PERIOD_NS + 10_000, "ns")
        got = list(rx.tdata)
        assert len(got) == len(want), f"frame {f}: {len(got)} words out, {len(want)} in (tlast misplaced)"
        for i, (g, e) in enumerate(zip(got, want, strict=True)):
            assert g == e, (
                f"frame {f}, word {i} (sector {SECTOR.get(e)}, last {i == len(want) - 1}): out {g:#x}, expected {e:#x}"
            )
    assert sink.empty()


@pytest.mark.parametrize(("sectors", "pauses"), [(16, 1), (32, 0), (32, 1), (64, 1)])
def test_desc_rotate(sectors: int, pauses: int) -> None:
    run("orb_desc_rotate", "test_orb_desc_rotate", {"SECTORS_g": sectors}, env={**SIM_ENV, "ORB_PAUSES": str(pauses)})
