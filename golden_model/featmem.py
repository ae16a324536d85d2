# SPDX-License-Identifier: MIT
"""The feature memory as the CPU reads it: decode a bank's 32-bit words into Features and its
end-of-frame record. Shared by the testbenches and the on-target driver, so both read the memory
the same way.

A bank holds SLOT_BYTES-byte slots (words 0 .. SLOT_WORDS_USED - 1 used): slots 0..count-1 are
features, slot `count` is the end-of-frame record. The layout is golden_model/data/featword.json
(docs/feature-word.md); this module names the parts of the one codec, golden_model.featcodec,
that the driver uses.
"""

from __future__ import annotations

from .featcodec import EndOfFrame, decode_record
from .featcodec import decode_slot_features as decode_features
from .featword import SLOT_BYTES, SLOT_RECORD_WORDS, SLOT_WORDS_USED

__all__ = ["SLOT_BYTES", "SLOT_RECORD_WORDS", "SLOT_WORDS_USED", "EndOfFrame", "decode_features", "decode_record"]
