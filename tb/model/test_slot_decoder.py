# SPDX-License-Identifier: MIT
"""The feature-slot decoder the driver runs on every frame (golden_model.featcodec.decode_slot_features:
a handful of numpy operations over the frame's slots, its positions read from golden_model.featword)
against the column-by-column decoder it replaced (decode_slot_features_generic, the stream decoder's
path), bit for bit: every column's values, dtype and shape.

Random slots with every field at its extremes (0, its largest value, random), the reserved bits and
the unused words 10 .. 15 set, and features sharing (scale, y, x) (the canonical order's ties keep
the slots' order); slots encoded from the model's features of the bundled photograph (orb and fast
mode, every feature and grid selection with its low corners), shuffled; the shapes the decoder takes
(whole 16-word slots, as the driver passes a view of the memory, the 10 used words, flat, strided,
big-endian, read-only, lists); an end-of-frame record among the slots refused by both. And
decode_record, which reads each record field from its own word, against the record decoded through
the whole slot as one integer.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from golden_model import featcodec as fc
from golden_model import featword as fw
from golden_model.config import Config
from golden_model.features import CANONICAL_ORDER, Features
from golden_model.frameparams import FrameParams
from golden_model.images import DEFAULT_IMAGE
from golden_model.pipeline import extract
from orb_tools.images import load_luma

COLUMNS = ("scale", "x", "y", "score", "sector", "descriptor", "response", "low")
SLOT = fw.SLOT_FEATURE
NARROW = tuple(f for f in SLOT.fields if f.name != "descriptor")
WORD = (1 << fw.SLOT_WORD_BITS) - 1


def assert_same(got: Features, want: Features) -> None:
    """Column for column: dtype, shape and values (Features.__eq__ compares values only)."""
    for name in COLUMNS:
        a, b = getattr(got, name), getattr(want, name)
        assert a.dtype == b.dtype and a.shape == b.shape, (name, a.dtype, a.shape, b.dtype, b.shape)
        assert np.array_equal(a, b), name
    assert got.descriptor.flags.c_contiguous
    assert (got.sectors_total, got.step) == (want.sectors_total, want.step)


def slot_rows(words: list[int]) -> np.ndarray:
    """(N, SLOT_WORDS) uint32 rows of whole slots given as SLOT_WORDS * 32-bit integers."""
    data = b"".join(w.to_bytes(fw.SLOT_BYTES, "little") for w in words)
    return np.frombuffer(data, dtype="<u4").reshape(len(words), fw.SLOT_WORDS).astype(np.uint32)


def random_slots(rng: np.random.Generator, n: int) -> np.ndarray:
    """n feature slots: every bit random (reserved bits and unused words too), the flag 0, and each
    field 0, its largest value or random; slot 0 every field 0, slot 1 every field at its largest."""
    words = []
    for i in range(n):
        word = int.from_bytes(rng.bytes(fw.SLOT_BYTES), "little")
        word = SLOT.flag.put(SLOT.flag_value, word)
        for f in SLOT.fields:
            top = (1 << f.width) - 1
            pick = 0 if i == 0 else 1 if i == 1 else int(rng.integers(0, 3))
            value = (0, top, int.from_bytes(rng.bytes((f.width + 7) // 8), "little") & top)[pick]
            word = f.put(value, word)
        words.append(word)
    return slot_rows(words)


def with_ties(rng: np.random.Generator, rows: np.ndarray) -> np.ndarray:
    """rows with a third of them given the (scale, y, x) of another row (their other fields differ)."""
    out = rows.copy()
    key_words = sorted({SLOT.field(name).lsb // fw.SLOT_WORD_BITS for name in CANONICAL_ORDER})
    n = len(rows)
    for i in rng.choice(n, n // 3, replace=False) if n > 1 else []:
        j = int(rng.integers(0, n))
        for k in key_words:
            keep = 0
            for name in CANONICAL_ORDER:
                f = SLOT.field(name)
                if f.lsb // fw.SLOT_WORD_BITS == k:
                    keep |= ((1 << f.width) - 1) << (f.lsb % fw.SLOT_WORD_BITS)
            out[i, k] = (int(out[i, k]) & ~keep & WORD) | (int(rows[j, k]) & keep)
    return out


def reference(rows: np.ndarray, descriptors: bool = True) -> Features:
    return fc.decode_slot_features_generic(np.ascontiguousarray(rows[:, : fw.SLOT_WORDS_USED]), 64, descriptors)


@pytest.mark.parametrize("n", [0, 1, 2, 3, 57, 1000, 4095])
@pytest.mark.parametrize("descriptors", [True, False], ids=["orb", "fast"])
def test_random_slots_decode_alike(n: int, descriptors: bool) -> None:
    rng = np.random.default_rng(n)
    rows = with_ties(rng, random_slots(rng, n))
    want = reference(rows, descriptors)
    assert_same(fc.decode_slot_features(rows, 64, descriptors), want)  # whole slots
    assert_same(fc.decode_slot_features(np.ascontiguousarray(rows[:, : fw.SLOT_WORDS_USED]), 64, descriptors), want)
    assert_same(fc.decode_slot_features(rows[:, : fw.SLOT_WORDS_USED].ravel(), 64, descriptors), want)  # flat


def test_every_field_at_its_extremes() -> None:
    """Slots whose fields are all 0 but one, at its largest value (and all at their largest but
    one, at 0), against the generic decoder and against the field's own value."""
    words = []
    for f in SLOT.fields:
        top = (1 << f.width) - 1
        words.append(f.put(top))
        full = 0
        for g in SLOT.fields:
            full = g.put((1 << g.width) - 1 if g is not f else 0, full)
        words.append(full)
    rows = slot_rows(words)
    want = reference(rows)
    got = fc.decode_slot_features(rows, 64)
    assert_same(got, want)
    for name in ("score", "response", "sector", "x", "y", "scale"):
        top = (1 << SLOT.field(name).width) - 1
        assert set(getattr(got, name).tolist()) == {0, top}, name
    assert got.low.any() and not got.low.all()
    assert {bytes(d) for d in got.descriptor} == {bytes(32), b"\xff" * 32}


def test_shapes_and_dtypes_the_decoder_takes() -> None:
    rng = np.random.default_rng(5)
    rows = with_ties(rng, random_slots(rng, 300))
    want = reference(rows)
    twice = np.repeat(rows, 2, axis=0)
    view = rows.view()
    view.flags.writeable = False
    for words in (
        twice[::2],  # strided rows
        rows.astype(">u4"),  # big-endian words
        rows.astype(np.int64),  # wider integers (as the generic decoder takes them)
        view,  # a read-only view, as of the DDR ring's memory
        rows[:, : fw.SLOT_WORDS_USED + 1],  # an odd number of words per row
        rows[:, : fw.SLOT_WORDS_USED].tolist(),
        np.asfortranarray(rows[:, : fw.SLOT_WORDS_USED]),
    ):
        assert_same(fc.decode_slot_features(words, 64), want)
    got = fc.decode_slot_features(view, 64)
    for name in COLUMNS:
        assert not np.shares_memory(getattr(got, name), rows), f"{name} must not be a view of the slots"


@cache
def model_features(cfg: Config) -> Features:
    return extract(load_luma(DEFAULT_IMAGE), cfg)


BASE = {"width": 640, "height": 480, "scales": 2, "sectors": 32, "threshold": 20}
CONFIGS = {
    "orb-all": Config(**BASE, mode="orb"),
    "orb-grid": Config(**BASE, mode="orb", threshold_lo=10, selection="grid", budget=1000),
    "fast-all": Config(**BASE, mode="fast"),
}


@pytest.mark.parametrize("name", CONFIGS)
def test_slots_of_real_features_decode_alike(name: str) -> None:
    """The model's features of the bundled photograph, encoded as the feature memory stores them,
    in a shuffled order (the memory's is the selection's, not the canonical one)."""
    cfg = CONFIGS[name]
    feats = model_features(cfg)
    orb = cfg.mode == "orb"
    assert len(feats) > 500 and (not orb or feats.has_descriptors)
    slots = []
    for i in range(len(feats)):
        beat = fc.encode_feature(scale=int(feats.scale[i]), x=int(feats.x[i]), y=int(feats.y[i]),
                                 score=int(feats.score[i]), sector=int(feats.sector[i]) if orb else 0,
                                 descriptor=feats.descriptor[i].tobytes() if orb else 0,
                                 response=int(feats.response[i]), low=int(feats.low[i]))  # fmt: skip
        slots.append(fc.feature_slot(beat))
    rows = np.array(slots, dtype=np.uint32)[np.random.default_rng(1).permutation(len(slots))]
    got = fc.decode_slot_features(rows, cfg.sectors, descriptors=orb)
    assert_same(got, fc.decode_slot_features_generic(rows[:, : fw.SLOT_WORDS_USED], cfg.sectors, orb))
    assert got == feats
    if cfg.selection == "grid":
        assert got.low.any(), "grid selection's low corners are among the features"


def test_a_record_among_the_slots_is_refused() -> None:
    rng = np.random.default_rng(9)
    rows = random_slots(rng, 20)
    rows[7] = fc.record_slot(fc.encode_eof(3, 0, None), 20, 0)
    for decode in (fc.decode_slot_features, fc.decode_slot_features_generic):
        with pytest.raises(ValueError, match="end-of-frame record"):
            decode(rows[:, : fw.SLOT_WORDS_USED], 64)
    with pytest.raises(ValueError, match="end-of-frame record"):
        fc.decode_slot_features(rows, 64)


def record_reference(words: list[int]) -> fc.EndOfFrame:
    """decode_record through the whole slot as one integer (its implementation before the fast one)."""
    w = [int(v) for v in words][: fw.SLOT_WORDS_USED]
    word = fc.from_chunks(np.array(w + [0] * (fw.SLOT_WORDS_USED - len(w)), dtype=np.uint32))
    flag = fw.SLOT_RECORD.flag
    if flag.get(word) != fw.SLOT_RECORD.flag_value:
        k = flag.lsb // fw.SLOT_WORD_BITS
        raise ValueError(f"not an end-of-frame record: {flag.name} flag 0 (word {k} = {w[k]:#010x})")
    v = fc.unpack(fw.SLOT_RECORD, word)
    return fc.EndOfFrame(count=v["count"], frame=v["frame"], dropped=v["dropped"], truncated=v["truncated"],
                         truncated_flag=bool(v["truncated_flag"]), params=FrameParams.from_fields(v))  # fmt: skip


def test_records_decode_alike() -> None:
    rng = np.random.default_rng(11)
    layout = fw.SLOT_RECORD
    for i in range(400):
        word = int.from_bytes(rng.bytes(fw.SLOT_BYTES), "little")  # reserved bits set too
        word = layout.flag.put(layout.flag_value, word)
        for f in layout.fields:
            top = (1 << f.width) - 1
            pick = i % 3 if i < 3 else int(rng.integers(0, 3))
            word = f.put((0, top, int(rng.integers(0, top + 1)))[pick], word)
        words = slot_rows([word])[0]
        want = record_reference(words.tolist())
        for given in (words, words[: fw.SLOT_RECORD_WORDS], words.tolist(), words[: fw.SLOT_RECORD_WORDS].tolist()):
            assert fc.decode_record(given) == want
    feature = fc.feature_slot(fc.encode_feature(scale=0, x=1, y=2, score=3))
    with pytest.raises(ValueError) as fast:
        fc.decode_record(feature)
    with pytest.raises(ValueError) as ref:
        record_reference(feature)
    assert str(fast.value) == str(ref.value)
