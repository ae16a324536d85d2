# SPDX-License-Identifier: MIT
"""A synthetic Xilinx .bit file for the tests of the board build (tb/board/test_bit2bin.py, the
packaging of `make bitstream` in tb/board/test_board_dryrun.py, the PYNQ checks in tb/pynq): the
header fields and a few words of raw configuration data with the sync word, the layout
sw/orb_flow/board/bit2bin.py documents. Standard library only (it also runs in .venv-pynq)."""

from __future__ import annotations

import struct

# raw configuration data as Vivado writes it (big-endian words)
WORDS = [
    *[0xFFFFFFFF] * 8,  # dummy pad
    0x000000BB,  # bus width detection
    0x11220044,
    0xFFFFFFFF,
    0xFFFFFFFF,
    0xAA995566,  # sync word, at byte 48
    0x20000000,  # NOOP
    0x30022001,  # write TIMER
    0x00000000,
    0x30020001,  # write WBSTAR
    0x12345678,
]
RAW = b"".join(w.to_bytes(4, "big") for w in WORDS)
SYNC_AT = 48
DESIGN = "orb_accel_zynq_wrapper;UserID=0XFFFFFFFF;Version=2023.2"


def field(key: str, text: str) -> bytes:
    s = text.encode() + b"\0"
    return key.encode() + struct.pack(">H", len(s)) + s


def make_bit(raw: bytes = RAW, declared: int | None = None, design: str = DESIGN) -> bytes:
    head = bytes.fromhex("0009 0ff00ff00ff00ff000 0001")
    head += field("a", design) + field("b", "7z020clg400") + field("c", "2026/11/24") + field("d", "12:34:56")
    return head + b"e" + struct.pack(">I", len(raw) if declared is None else declared) + raw
