# SPDX-License-Identifier: MIT
"""The one codec of the feature stream word and the feature-memory slot (docs/feature-word.md).

Every position comes from golden_model.featword, generated with hdl/common/orb_feat_pkg.vhd from
golden_model/data/featword.json; nothing here knows a bit number. Stream words (m_axis_feat_tdata,
320 bits) are Python ints as cocotb gives them; slots are arrays of the 32-bit words the CPU reads.
Many words are decoded at once as (N, words) arrays of 32-bit chunks, a field of up to 32 bits
as an integer column and a wider (whole-byte) field as a byte view. A frame's feature slots, which
the driver decodes every frame, go faster (decode_slot_features: the slot's narrow fields from its
first 64 bits at once, one sort, one gather of the descriptors; the positions still from
golden_model.featword), held bit for bit to the column-by-column decoder
(decode_slot_features_generic) by tb/model/test_slot_decoder.py. Shared by the testbenches, the
simulation support (orb_sim.feature_stream) and the on-target driver (through golden_model.featmem).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .features import CANONICAL_ORDER, NO_SECTOR, Features
from .featword import (
    EOF_BEAT,
    FEAT_BITS,
    FEATURE_BEAT,
    SLOT_BEAT,
    SLOT_BITS,
    SLOT_FEATURE,
    SLOT_FEATURE_WORDS,
    SLOT_RECORD,
    SLOT_WORD_BITS,
    SLOT_WORDS,
    SLOT_WORDS_USED,
    Field,
    Layout,
)
from .frameparams import FrameParams

CHUNK = SLOT_WORD_BITS  # bits of one column of a chunk array (a CPU word)
DESC_BYTES = FEATURE_BEAT.field("descriptor").width // 8


class LayoutError(ValueError):
    """A word that breaks its layout: the wrong flag, or a reserved bit set."""


# ------------------------------------------------------------------------------------------------
# any layout


def pack(layout: Layout, values: Mapping[str, int]) -> int:
    """The word of `layout` with its flag and the given fields (others 0); raises on an unknown
    name or a value that does not fit its field."""
    names = {f.name for f in layout.fields}
    if unknown := set(values) - names:
        raise KeyError(f"{layout.name} has no field {sorted(unknown)}")
    word = layout.flag.put(layout.flag_value)
    for f in layout.fields:
        word = f.put(int(values.get(f.name, 0)), word)
    return word


def unpack(layout: Layout, word: int) -> dict[str, int]:
    """Every field of `layout` in `word`, by name."""
    return {f.name: f.get(word) for f in layout.fields}


def layout_error(layout: Layout, word: int) -> str | None:
    """None when `word` is a well-formed `layout` word; else a sentence saying what is wrong."""
    flag = layout.flag
    if word >> layout.bits or word < 0:
        return f"{layout.name} word wider than {layout.bits} bits: {word:#x}"
    if flag.get(word) != layout.flag_value:
        return f"{layout.name} word with {flag.name} flag (bit {flag.lsb}) {flag.get(word)}: {word:#x}"
    if word & layout.reserved:
        return f"{layout.name} word with reserved bits {word & layout.reserved:#x} set: {word:#x}"
    return None


def to_chunks(words: Sequence[int], bits: int) -> np.ndarray:
    """(N, bits / 32) uint32 array of the words' 32-bit chunks, least significant first."""
    n = len(words)
    data = b"".join(int(w).to_bytes(bits // 8, "little") for w in words)
    return np.frombuffer(data, dtype="<u4").reshape(n, bits // CHUNK).astype(np.uint32)


def from_chunks(row: np.ndarray) -> int:
    """One word from its 32-bit chunks (least significant first)."""
    return int.from_bytes(np.ascontiguousarray(row, dtype="<u4").tobytes(), "little")


def column(chunks: np.ndarray, f: Field) -> np.ndarray:
    """Field `f` (at most 32 bits) of every row of a chunk array, as int64."""
    if f.width > CHUNK:
        raise ValueError(f"{f.name}: {f.width} bits, use byte_column")
    k, off = divmod(f.lsb, CHUNK)
    v = chunks[:, k].astype(np.uint64)
    if off + f.width > CHUNK:
        v |= chunks[:, k + 1].astype(np.uint64) << np.uint64(CHUNK)
    return ((v >> np.uint64(off)) & np.uint64((1 << f.width) - 1)).astype(np.int64)


def byte_column(chunks: np.ndarray, f: Field) -> np.ndarray:
    """Field `f` (whole bytes) of every row of a chunk array as (N, width / 8) uint8, little-endian."""
    if f.lsb % 8 or f.width % 8:
        raise ValueError(f"{f.name}: not whole bytes")
    b = np.ascontiguousarray(chunks, dtype="<u4").view(np.uint8).reshape(chunks.shape[0], 4 * chunks.shape[1])
    return b[:, f.lsb // 8 : (f.lsb + f.width) // 8].copy()


def check_rows(layout: Layout, chunks: np.ndarray) -> None:
    """Raise LayoutError naming the first row of `chunks` that is not a well-formed `layout` word."""
    nch = layout.bits // CHUNK
    reserved = np.frombuffer(layout.reserved.to_bytes(nch * 4, "little"), dtype="<u4")
    bad = (column(chunks, layout.flag) != layout.flag_value) | np.any(chunks[:, :nch] & reserved, axis=1)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise LayoutError(f"word {i}: {layout_error(layout, from_chunks(chunks[i, :nch]))}")


# ------------------------------------------------------------------------------------------------
# stream words (m_axis_feat_tdata)


@dataclass(frozen=True)
class FeatureBeat:
    """One decoded feature word. ``sector`` and ``descriptor`` are 0 when the merge carries no
    descriptors; ``descriptor`` is the 256 bits as an int (bit i = test i); ``descriptor_bytes``
    gives golden_model's byte form."""

    scale: int
    x: int
    y: int
    score: int
    sector: int
    descriptor: int
    response: int = 0
    low: int = 0
    sel_slot: int = 0
    sel_replace: int = 0

    @property
    def descriptor_bytes(self) -> bytes:
        return self.descriptor.to_bytes(DESC_BYTES, "little")


@dataclass(frozen=True)
class EofBeat:
    """One decoded end-of-frame word: the frame number, the features it lost upstream and the
    parameters the frame was processed with."""

    frame: int
    drops: int
    params: FrameParams


def is_eof(word: int) -> bool:
    """Whether the stream word carries the end-of-frame flag."""
    return EOF_BEAT.flag.get(word) == EOF_BEAT.flag_value


def feature_error(word: int) -> str | None:
    """None for a well-formed feature word (flag 0, reserved bits 0); else what is wrong."""
    return layout_error(FEATURE_BEAT, word)


def eof_error(word: int) -> str | None:
    """None for a well-formed end-of-frame word (flag 1, reserved bits 0); else what is wrong."""
    return layout_error(EOF_BEAT, word)


def encode_feature(*, scale: int, x: int, y: int, score: int, sector: int = 0, descriptor: int | bytes = 0,
                   response: int = 0, low: int = 0, sel_slot: int = 0, sel_replace: int = 0) -> int:  # fmt: skip
    """A feature word; `descriptor` as an int (bit i = test i) or golden_model's bytes."""
    if isinstance(descriptor, bytes | bytearray):
        descriptor = int.from_bytes(descriptor, "little")
    return pack(FEATURE_BEAT, {"scale": scale, "x": x, "y": y, "score": score, "sector": sector,
                               "descriptor": descriptor, "response": response, "low": low, "sel_slot": sel_slot,
                               "sel_replace": sel_replace})  # fmt: skip


def encode_eof(frame: int, drops: int = 0, params: FrameParams | None = None) -> int:
    """An end-of-frame word (frame and drops must fit their fields) carrying the frame's `params`
    (None: every parameter field 0, as in a word no core wrote)."""
    return pack(EOF_BEAT, {"frame": frame, "drops": drops} | (params.fields() if params else {}))


def decode_feature(word: int, check: bool = True) -> FeatureBeat:
    """Decode a feature word; with `check`, raise LayoutError unless it is well-formed."""
    if check and (err := feature_error(word)):
        raise LayoutError(err)
    return FeatureBeat(**unpack(FEATURE_BEAT, word))


def decode_eof(word: int, check: bool = True) -> EofBeat:
    """Decode an end-of-frame word; with `check`, raise LayoutError unless it is well-formed."""
    if check and (err := eof_error(word)):
        raise LayoutError(err)
    v = unpack(EOF_BEAT, word)
    return EofBeat(frame=v["frame"], drops=v["drops"], params=FrameParams.from_fields(v))


def resolve_selection(words: Sequence[int]) -> list[int]:
    """A frame's feature words as the feature memory keeps them (docs/selection.md): a word with
    sel_replace = 0 takes the next place, one with sel_replace = 1 replaces the word that took the
    place for its sel_slot. In `all` mode every word takes a place (arrival order). Raises
    LayoutError for a replacing word whose sel_slot no earlier word of the frame took."""
    slot_f, repl_f = FEATURE_BEAT.field("sel_slot"), FEATURE_BEAT.field("sel_replace")
    kept: list[int] = []
    place: dict[int, int] = {}
    for i, w in enumerate(words):
        slot = slot_f.get(w)
        if repl_f.get(w):
            if slot not in place:
                raise LayoutError(f"feature word {i} replaces sel_slot {slot}, which no earlier word took")
            kept[place[slot]] = w
        else:
            place[slot] = len(kept)
            kept.append(w)
    return kept


def decode_stream_features(
    words: Sequence[int], sectors_total: int = 0, descriptors: bool = False, check: bool = True, resolve: bool = True
) -> Features:
    """A frame's feature words as Features in canonical order, after resolve_selection (unless not
    `resolve`: every word, as the overlay marks them): fast mode (no sector, no descriptor) unless
    `descriptors`. With `check`, raise LayoutError at the first word that is not a well-formed
    feature word."""
    ch = to_chunks(resolve_selection(words) if resolve else list(words), FEAT_BITS)
    if check:
        check_rows(FEATURE_BEAT, ch)
    return _features(FEATURE_BEAT, ch, sectors_total, descriptors)


def _features(layout: Layout, ch: np.ndarray, sectors_total: int, descriptors: bool) -> Features:
    def col(name: str) -> np.ndarray:
        return column(ch, layout.field(name))

    n = len(ch)
    if descriptors:
        sector, desc = col("sector"), byte_column(ch, layout.field("descriptor"))
    else:
        sector, desc = np.full(n, NO_SECTOR, dtype=np.int64), np.zeros((n, 0), dtype=np.uint8)
    return Features(col("scale"), col("x"), col("y"), col("score"), sector, desc, sectors_total, (2, 1),
                    col("response"), col("low").astype(bool)).sorted()  # fmt: skip


# ------------------------------------------------------------------------------------------------
# feature-memory slots (32-bit words as the CPU reads them)


@dataclass(frozen=True)
class EndOfFrame:
    """The end-of-frame record of a bank; `params`: the parameters the frame was processed with (as
    orb_core sampled them with its first pixel)."""

    count: int
    frame: int
    dropped: int
    truncated: int
    truncated_flag: bool
    params: FrameParams


def slot_words(layout: Layout, values: Mapping[str, int]) -> list[int]:
    """The SLOT_WORDS words of a slot of `layout` with the given fields (unused words 0)."""
    word = pack(layout, values)
    return [(word >> (CHUNK * k)) & ((1 << CHUNK) - 1) for k in range(SLOT_WORDS)]


def fill_slot(layout: Layout, beat_word: int, **own: int) -> list[int]:
    """The slot words orb_feat_mem writes for a stream beat: each field with a source takes that
    field of the beat (SLOT_BEAT names the beat's layout), the others come from `own`."""
    beat = SLOT_BEAT[layout.name]
    values = {f.name: beat.field(f.source).get(beat_word) for f in layout.fields if f.source is not None}
    return slot_words(layout, values | own)


def feature_slot(beat_word: int) -> list[int]:
    """The words of the slot that stores feature word `beat_word`."""
    return fill_slot(SLOT_FEATURE, beat_word)


def record_slot(eof_word: int, count: int, truncated: int) -> list[int]:
    """The words of the end-of-frame record for end-of-frame word `eof_word`, `count` features
    stored and `truncated` cut."""
    return fill_slot(SLOT_RECORD, eof_word, count=count, truncated=truncated, truncated_flag=int(truncated != 0))


def is_record(words: Sequence[int] | np.ndarray) -> bool:
    """Whether a slot (its words from word 0 on) is the end-of-frame record."""
    flag = SLOT_RECORD.flag
    return (int(words[flag.lsb // CHUNK]) >> (flag.lsb % CHUNK)) & 1 == SLOT_RECORD.flag_value


def _word_fields(layout: Layout) -> tuple[tuple[str, int, int, int], ...] | None:
    """(name, CPU word, shift, mask) of every field of `layout`; None if a field spans two words."""
    out = []
    for f in layout.fields:
        k, off = divmod(f.lsb, CHUNK)
        if off + f.width > CHUNK:
            return None
        out.append((f.name, k, off, (1 << f.width) - 1))
    return tuple(out)


_RECORD_FIELDS = _word_fields(SLOT_RECORD)
# the record's fields FrameParams is made of, and the rest; the parameters' words (masked) as the key
# of the FrameParams already made (frames in a row carry the same parameters: one object for them)
_PARAM_NAMES = frozenset(FrameParams(0, 0, "orb", "grid", 0, 0, 0).fields())
_RECORD_OWN = tuple(f for f in _RECORD_FIELDS or () if f[0] not in _PARAM_NAMES)
_RECORD_PARAMS = tuple(f for f in _RECORD_FIELDS or () if f[0] in _PARAM_NAMES)
_PARAM_KEY = tuple(
    (k, sum(mask << off for _, kk, off, mask in _RECORD_PARAMS if kk == k))
    for k in sorted({f[1] for f in _RECORD_PARAMS})
)
_PARAMS: dict[tuple[int, ...], FrameParams] = {}


def decode_record(words: Sequence[int] | np.ndarray) -> EndOfFrame:
    """The end-of-frame record from its slot's first words (at least SLOT_RECORD_WORDS); raises
    ValueError if the slot is not a record."""
    w = (words.tolist() if isinstance(words, np.ndarray) and words.ndim == 1 else [int(v) for v in words])[
        :SLOT_WORDS_USED
    ]
    w += [0] * (SLOT_BITS // CHUNK - len(w))
    flag = SLOT_RECORD.flag
    if _RECORD_FIELDS is None or min(w) < 0 or max(w) >> CHUNK:  # the layout, or values beyond 32-bit words
        word = from_chunks(np.array(w, dtype=np.uint32))
        v = unpack(SLOT_RECORD, word)
        if flag.get(word) != SLOT_RECORD.flag_value:
            k = flag.lsb // CHUNK
            raise ValueError(f"not an end-of-frame record: {flag.name} flag 0 (word {k} = {w[k]:#010x})")
        params = FrameParams.from_fields(v)
    else:  # each field from its own word (the driver's path, once a frame)
        if (w[flag.lsb // CHUNK] >> (flag.lsb % CHUNK)) & 1 != SLOT_RECORD.flag_value:
            k = flag.lsb // CHUNK
            raise ValueError(f"not an end-of-frame record: {flag.name} flag 0 (word {k} = {w[k]:#010x})")
        v = {name: (w[k] >> off) & mask for name, k, off, mask in _RECORD_OWN}
        key = tuple(w[k] & mask for k, mask in _PARAM_KEY)
        params = _PARAMS.get(key)
        if params is None:
            params = FrameParams.from_fields({name: (w[k] >> off) & mask for name, k, off, mask in _RECORD_PARAMS})
            if len(_PARAMS) >= 64:
                _PARAMS.clear()
            _PARAMS[key] = params
    return EndOfFrame(v["count"], v["frame"], v["dropped"], v["truncated"], bool(v["truncated_flag"]), params)


def decode_slot_features_generic(words: np.ndarray, sectors_total: int, descriptors: bool = True) -> Features:
    """decode_slot_features column by column (column, byte_column, Features.sorted: the stream
    decoder's path), for an (N, SLOT_WORDS_USED) array of slot words or a flat one of N *
    SLOT_WORDS_USED: the reference the fast decoder is tested against, and what it falls back to
    for a layout it cannot read at speed."""
    ch = np.asarray(words, dtype=np.uint32).reshape(-1, SLOT_WORDS_USED)
    if np.any(column(ch, SLOT_FEATURE.flag) != SLOT_FEATURE.flag_value):
        raise ValueError("an end-of-frame record among the feature slots")
    return _features(SLOT_FEATURE, ch, sectors_total, descriptors)


# The fast decoder's plan, from SLOT_FEATURE (None when the layout does not allow it): every field
# but the descriptor, and the flag, lies in the slot's first 64 bits (two CPU words), read as one
# 64-bit integer per slot; the descriptor is whole 64-bit words, gathered as such; the canonical
# order's fields (scale, y, x) packed side by side above the slot's index make a sort key whose
# values are all distinct, so an unstable sort gives the stable lexsort's order.
_LANE = 2 * CHUNK  # bits of the 64-bit integer (CPU words 2 k and 2 k + 1)
_INDEX_BITS = 28  # the sort key's low bits: the slot's index (frames of up to 2^28 slots)


@dataclass(frozen=True)
class _SlotPlan:
    names: tuple[str, ...]  # the fields of the field block's rows ("sector" last)
    shifts: tuple[np.ndarray, np.ndarray]  # (rows, 1) uint64: each field's lsb; without and with the sector
    masks: tuple[np.ndarray, np.ndarray]  # (rows, 1) uint64: each field's value mask; idem
    flag_mask: np.uint64
    flag_value: np.uint64
    key: tuple[tuple[bool, np.uint64, np.uint64], ...]  # per run of key fields: (left?, shift, mask at its place)
    index_mask: np.uint64
    desc: tuple[int, int]  # the descriptor's 64-bit words (first, end) in a slot


def _slot_plan(layout: Layout) -> _SlotPlan | None:
    desc = layout.field("descriptor")
    narrow = [f for f in layout.fields if f is not desc]
    if any(f.lsb + f.width > _LANE for f in [*narrow, layout.flag]) or desc.lsb % _LANE or desc.width % _LANE:
        return None
    narrow.sort(key=lambda f: f.name == "sector")
    if narrow[-1].name != "sector":
        return None
    runs: list[list[int]] = []  # [lsb, width, place] of runs of key fields adjacent in the slot and in the key
    place = _INDEX_BITS
    for name in reversed(CANONICAL_ORDER):  # least significant first
        f = layout.field(name)
        if runs and runs[-1][0] + runs[-1][1] == f.lsb and runs[-1][2] + runs[-1][1] == place:
            runs[-1][1] += f.width
        else:
            runs.append([f.lsb, f.width, place])
        place += f.width
    if place > _LANE:
        return None
    u64 = np.uint64
    shifts = np.array([[f.lsb] for f in narrow], dtype=np.uint64)
    masks = np.array([[(1 << f.width) - 1] for f in narrow], dtype=np.uint64)
    return _SlotPlan(
        names=tuple(f.name for f in narrow),
        shifts=(shifts[:-1], shifts), masks=(masks[:-1], masks),
        flag_mask=u64(layout.flag.mask), flag_value=u64(layout.flag_value << layout.flag.lsb),
        key=tuple((lsb < at, u64(abs(at - lsb)), u64(((1 << width) - 1) << at)) for lsb, width, at in runs),
        index_mask=u64((1 << _INDEX_BITS) - 1),
        desc=(desc.lsb // _LANE, (desc.lsb + desc.width) // _LANE),
    )  # fmt: skip


_PLAN = _slot_plan(SLOT_FEATURE)


def _lanes(words: np.ndarray | Sequence[int]) -> np.ndarray:
    """The slots as an (N, lanes) little-endian 64-bit array: no copy for uint32 rows of an even
    number of contiguous words (a memory's view of whole slots)."""
    a = np.asarray(words, dtype="<u4")
    if a.ndim != 2 or a.shape[1] < SLOT_FEATURE_WORDS:
        a = a.reshape(-1, SLOT_WORDS_USED)
    if a.shape[1] % 2:
        a = a[:, :-1]
    try:
        return a.view("<u8")
    except ValueError:  # the words of a row not contiguous
        return np.ascontiguousarray(a).view("<u8")


def _gather(lanes: np.ndarray, span: tuple[int, int], index: np.ndarray) -> np.ndarray:
    """Lanes span[0] .. span[1] - 1 of rows `index` of `lanes`, as a new contiguous (len(index),
    span width) array. For contiguous rows whose width is a multiple of the span's (whole slots)
    the memory from lane span[0] on is taken as rows of the span's width, of which row i's span is
    row i * (width / span): one gather of contiguous chunks, without the copy of the strided
    columns np.take would make first."""
    first, end = span
    width, d = lanes.shape[1], end - first
    if len(index) and width % d == 0 and lanes.strides == (8 * width, 8):
        flat = lanes.reshape(-1)
        chunks = flat[first : first + (flat.size - first) // d * d].reshape(-1, d)
        return chunks.take(index * (width // d), axis=0)
    return lanes[:, first:end].take(index, axis=0)


def decode_slot_features(words: np.ndarray, sectors_total: int, descriptors: bool = True) -> Features:
    """Features from an array of slot words, in canonical order: (N, SLOT_WORDS) whole slots (a
    view of the memory, read in place), (N, SLOT_WORDS_USED), or a flat N * SLOT_WORDS_USED. With
    `descriptors` false (fast mode) the sector and descriptor columns are left out. Raises
    ValueError if a slot is the end-of-frame record. The result shares no memory with `words`.

    One pass of a few numpy operations over the frame (the driver's decoder, every frame): the
    slots' first 64 bits as one integer each, the sort key of the canonical order with each slot's
    index below it, one sort, every narrow field of the sorted slots by one shift and one mask, the
    descriptors by one gather of their 64-bit words. Equal, column for column and dtype for dtype,
    to decode_slot_features_generic."""
    plan = _PLAN
    lanes = _lanes(words)
    n = lanes.shape[0]
    if plan is None or n > 1 << _INDEX_BITS:
        return decode_slot_features_generic(lanes.view("<u4")[:, :SLOT_WORDS_USED], sectors_total, descriptors)
    v = lanes[:, 0].astype(np.uint64)  # native, contiguous: the one read of the slots' first words
    flags = v & plan.flag_mask
    if flags.any() if plan.flag_value == 0 else (flags != plan.flag_value).any():
        raise ValueError("an end-of-frame record among the feature slots")
    key = np.arange(n, dtype=np.uint64)
    for left, shift, mask in plan.key:
        key |= ((v << shift) if left else (v >> shift)) & mask
    key.sort()  # distinct values: the order of a stable sort by (scale, y, x)
    index = (key & plan.index_mask).astype(np.intp)
    rows = 1 if descriptors else 0  # the sector's row with the descriptors only
    block = ((v.take(index) >> plan.shifts[rows]) & plan.masks[rows]).view(np.int64)
    col = dict(zip(plan.names, block, strict=False))
    if descriptors:
        sector = col["sector"]
        desc = _gather(lanes, plan.desc, index).view(np.uint8)
    else:
        sector, desc = np.full(n, NO_SECTOR, dtype=np.int64), np.zeros((n, 0), dtype=np.uint8)
    return Features(col["scale"], col["x"], col["y"], col["score"], sector, desc, sectors_total, (2, 1),
                    col["response"], col["low"].astype(bool))  # fmt: skip
