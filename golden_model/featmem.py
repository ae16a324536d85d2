# SPDX-License-Identifier: MIT
"""The feature memory as the CPU reads it (docs/feature-memory.md, record layout): decode a bank's
32-bit words into Features and its end-of-frame record. Shared by the testbenches and the
on-target driver, so both read the memory the same way.

A bank holds 64-byte slots (16 words; words 0..9 used): slots 0..count-1 are features, slot
`count` is the end-of-frame record. Feature slot: word 0 = x [15:0], y [31:16]; word 1 = score
[11:0], scale [17:16], sector [29:24], bit 31 = 0; words 2..9 = descriptor bytes 0..31
(little-endian). Record: word 0 = count, word 1 bit 31 = 1 and bit 30 = truncated, word 2 =
frame number, word 3 = features dropped upstream, word 4 = truncated count.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .features import NO_SECTOR, Features

SLOT_BYTES = 64
SLOT_WORDS_USED = 10  # words 0..9 of a slot carry data; 10..15 read 0
DESC_WORDS = 8
RECORD_BIT = 31
TRUNCATED_BIT = 30


@dataclass(frozen=True)
class EndOfFrame:
    count: int
    frame: int
    dropped: int
    truncated: int
    truncated_flag: bool


def decode_record(words: np.ndarray | list[int]) -> EndOfFrame:
    """The end-of-frame record from its slot's words 0..4; raises if the slot is not a record."""
    w = [int(v) for v in words]
    if not w[1] >> RECORD_BIT & 1:
        raise ValueError(f"not an end-of-frame record: word 1 = {w[1]:#010x}")
    return EndOfFrame(count=w[0], frame=w[2] & 0xFFFF, dropped=w[3] & 0xFFFF, truncated=w[4],
                      truncated_flag=bool(w[1] >> TRUNCATED_BIT & 1))  # fmt: skip


def decode_features(words: np.ndarray, sectors_total: int, descriptors: bool = True) -> Features:
    """Features from an (N, 10) array of slot words 0..9, in canonical order. With
    `descriptors` false (fast mode) the sector and descriptor columns are left out."""
    w = np.asarray(words, dtype=np.uint32).reshape(-1, SLOT_WORDS_USED).astype(np.int64)
    if np.any(w[:, 1] >> RECORD_BIT & 1):
        raise ValueError("an end-of-frame record among the feature slots")
    x, y = w[:, 0] & 0xFFFF, w[:, 0] >> 16
    score, scale = w[:, 1] & 0xFFF, (w[:, 1] >> 16) & 3
    if descriptors:
        sector = (w[:, 1] >> 24) & 0x3F
        desc = np.ascontiguousarray(w[:, 2 : 2 + DESC_WORDS].astype("<u4")).view(np.uint8).reshape(-1, 4 * DESC_WORDS)
    else:
        sector = np.full(len(w), NO_SECTOR, dtype=np.int64)
        desc = np.zeros((len(w), 0), dtype=np.uint8)
    return Features(scale, x, y, score, sector, desc, sectors_total).sorted()
