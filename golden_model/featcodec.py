# SPDX-License-Identifier: MIT
"""The one codec of the feature stream word and the feature-memory slot (docs/feature-word.md).

Every position comes from golden_model.featword, generated with hdl/common/orb_feat_pkg.vhd from
golden_model/data/featword.json; nothing here knows a bit number. Stream words (m_axis_feat_tdata,
320 bits) are Python ints as cocotb gives them; slots are arrays of the 32-bit words the CPU reads.
Many words are decoded at once as (N, words) arrays of 32-bit chunks, a field of up to 32 bits
as an integer column and a wider (whole-byte) field as a byte view. Shared by the testbenches, the
simulation support (orb_sim.feature_stream) and the on-target driver (through golden_model.featmem).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .features import NO_SECTOR, Features
from .featword import (
    EOF_BEAT,
    FEAT_BITS,
    FEATURE_BEAT,
    SLOT_BEAT,
    SLOT_BITS,
    SLOT_FEATURE,
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


def decode_record(words: Sequence[int] | np.ndarray) -> EndOfFrame:
    """The end-of-frame record from its slot's first words (at least SLOT_RECORD_WORDS); raises
    ValueError if the slot is not a record."""
    w = [int(v) for v in words][:SLOT_WORDS_USED]
    word = from_chunks(np.array(w + [0] * (SLOT_BITS // CHUNK - len(w)), dtype=np.uint32))
    flag = SLOT_RECORD.flag
    if flag.get(word) != SLOT_RECORD.flag_value:
        k = flag.lsb // CHUNK
        raise ValueError(f"not an end-of-frame record: {flag.name} flag 0 (word {k} = {w[k]:#010x})")
    v = unpack(SLOT_RECORD, word)
    return EndOfFrame(count=v["count"], frame=v["frame"], dropped=v["dropped"], truncated=v["truncated"],
                      truncated_flag=bool(v["truncated_flag"]), params=FrameParams.from_fields(v))  # fmt: skip


def decode_slot_features(words: np.ndarray, sectors_total: int, descriptors: bool = True) -> Features:
    """Features from an (N, SLOT_WORDS_USED) array of slot words, in canonical order. With
    `descriptors` false (fast mode) the sector and descriptor columns are left out. Raises
    ValueError if a slot is the end-of-frame record."""
    ch = np.asarray(words, dtype=np.uint32).reshape(-1, SLOT_WORDS_USED)
    if np.any(column(ch, SLOT_FEATURE.flag) != SLOT_FEATURE.flag_value):
        raise ValueError("an end-of-frame record among the feature slots")
    return _features(SLOT_FEATURE, ch, sectors_total, descriptors)
