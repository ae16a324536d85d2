#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Convert a Vivado .bit file into the byte-swapped .bit.bin that Linux's Zynq fpga_manager loads.

A .bit file is a small header followed by the raw configuration data:

    00 09  0F F0 0F F0 0F F0 0F F0 00  00 01     13-byte preamble field
    'a' len16 "design name\\0"                    (Vivado appends ";UserID=...;Version=...")
    'b' len16 "part\\0"   'c' len16 "date\\0"   'd' len16 "time\\0"
    'e' len32  <raw configuration data, len32 bytes>

(lengths big-endian). The raw data starts with dummy words 0xFFFFFFFF, the bus-width detection
words 0x000000BB 0x11220044, more dummy words and the sync word 0xAA995566, all big-endian.
drivers/fpga/zynq-fpga.c (zynq_fpga_has_sync) wants the data with every 32-bit word byte-swapped,
so that the bytes 66 55 99 AA appear at a 4-byte aligned offset, and a length that is a multiple
of 4. This script checks the header and the raw data, swaps the words and writes the result.

Usage:
    python3 sw/orb_flow/board/bit2bin.py IN.bit OUT.bit.bin
    python3 sw/orb_flow/board/bit2bin.py --check FILE.bit.bin

Prints one line (design, part, byte count, or the sync word's offset for --check); on bad input
prints one line `error: ...` to stderr and exits 1.
"""

from __future__ import annotations

import argparse
import struct
import sys
from dataclasses import dataclass
from pathlib import Path

PREAMBLE = bytes.fromhex("0009 0ff00ff00ff00ff000 0001")  # the first field (length 9) and the next length (1)
SYNC_WORD = 0xAA995566
SYNC_BE = SYNC_WORD.to_bytes(4, "big")  # as it stands in a .bit
SYNC_SWAPPED = SYNC_WORD.to_bytes(4, "little")  # as zynq-fpga.c looks for it: 66 55 99 AA
STRING_FIELDS = (("a", "design"), ("b", "part"), ("c", "date"), ("d", "time"))


@dataclass(frozen=True)
class BitHeader:
    """The header fields of a .bit file and its raw configuration data."""

    design: str
    part: str
    date: str
    time: str
    data: bytes


class _Reader:
    """Sequential reader over the .bit bytes; every short read is a `truncated` ValueError."""

    def __init__(self, data: bytes) -> None:
        self.data = data
        self.pos = 0

    def take(self, n: int, what: str) -> bytes:
        if self.pos + n > len(self.data):
            raise ValueError(
                f"truncated .bit: {what} needs {n} bytes at offset {self.pos}, file has {len(self.data)} bytes"
            )
        chunk = self.data[self.pos : self.pos + n]
        self.pos += n
        return chunk

    def u16(self, what: str) -> int:
        return int(struct.unpack(">H", self.take(2, what))[0])

    def u32(self, what: str) -> int:
        return int(struct.unpack(">I", self.take(4, what))[0])


def _string_field(rd: _Reader, key: str, name: str) -> str:
    at = rd.pos
    tag = rd.take(1, f"field '{key}' ({name}) tag")
    if tag != key.encode():
        raise ValueError(f"not a .bit file: expected field '{key}' ({name}) at offset {at}, found {tag!r}")
    raw = rd.take(rd.u16(f"field '{key}' length"), f"field '{key}' ({name})")
    if not raw.endswith(b"\0"):
        raise ValueError(f"not a .bit file: field '{key}' ({name}) is not NUL-terminated")
    return raw[:-1].decode("latin-1")


def find_sync(data: bytes, word: bytes) -> int:
    """Offset of the first 4-byte aligned occurrence of `word` in `data`, or -1."""
    for off in range(0, len(data) - 3, 4):
        if data[off : off + 4] == word:
            return off
    return -1


def parse_bit(data: bytes) -> BitHeader:
    """Parse and check a .bit file: header, declared length, word alignment, sync word."""
    if len(data) < len(PREAMBLE):
        raise ValueError(f"truncated .bit: {len(data)} bytes, shorter than the {len(PREAMBLE)}-byte preamble")
    rd = _Reader(data)
    if rd.take(len(PREAMBLE), "preamble") != PREAMBLE:
        raise ValueError("not a .bit file: the 13-byte preamble (00 09 0F F0 ... 00 00 01) does not match")
    fields = {name: _string_field(rd, key, name) for key, name in STRING_FIELDS}
    at = rd.pos
    if rd.take(1, "field 'e' tag") != b"e":
        raise ValueError(f"not a .bit file: expected field 'e' (raw data length) at offset {at}")
    length = rd.u32("field 'e' length")
    rest = len(data) - rd.pos
    if rest < length:
        raise ValueError(f"truncated .bit: header declares {length} bytes of raw data, file has {rest}")
    if rest > length:
        raise ValueError(f"length mismatch: header declares {length} bytes of raw data, file has {rest}")
    raw = data[rd.pos :]
    if length % 4:
        raise ValueError(f"raw data length {length} is not a multiple of 4")
    if find_sync(raw, SYNC_BE) < 0:
        raise ValueError("sync word 0xAA995566 not found in the raw data")
    return BitHeader(data=raw, **fields)


def swap32(data: bytes) -> bytes:
    """Every 32-bit word of `data` (length a multiple of 4) with its bytes reversed."""
    out = bytearray(data)
    out[0::4], out[1::4], out[2::4], out[3::4] = data[3::4], data[2::4], data[1::4], data[0::4]
    return bytes(out)


def bit_to_bin(data: bytes) -> bytes:
    """The byte-swapped .bit.bin for the .bit file `data` (checked by parse_bit)."""
    return swap32(parse_bit(data).data)


def check_bin(data: bytes) -> int:
    """Check a .bit.bin the way zynq-fpga.c does; return the offset of the swapped sync word."""
    if data.startswith(PREAMBLE):
        raise ValueError("this is a .bit file (it has the .bit preamble), not a .bit.bin: convert it first")
    if len(data) % 4:
        raise ValueError(f".bin length {len(data)} is not a multiple of 4")
    off = find_sync(data, SYNC_SWAPPED)
    if off < 0:
        if find_sync(data, SYNC_BE) >= 0:
            raise ValueError("sync word found unswapped (AA 99 55 66): a plain .bin, not the byte-swapped .bit.bin")
        raise ValueError("swapped sync word 66 55 99 AA not found at any 4-byte aligned offset")
    return off


def _convert(src: Path, dst: Path) -> str:
    hdr = parse_bit(src.read_bytes())
    dst.write_bytes(swap32(hdr.data))
    return f"{dst}: design {hdr.design}, part {hdr.part}, {len(hdr.data)} bytes"


def _check(path: Path) -> str:
    data = path.read_bytes()
    off = check_bin(data)
    return f"{path}: ok, swapped sync word at offset {off}, {len(data)} bytes"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Convert a Xilinx .bit into the byte-swapped .bit.bin for fpga_manager.")
    ap.add_argument("--check", metavar="FILE.bit.bin", type=Path, help="verify a .bit.bin instead of converting")
    ap.add_argument("files", nargs="*", type=Path, metavar="IN.bit OUT.bit.bin")
    args = ap.parse_args(argv)
    if not (len(args.files) == 2 if args.check is None else not args.files):
        ap.error("give IN.bit OUT.bit.bin, or --check FILE.bit.bin")
    try:
        print(_check(args.check) if args.check is not None else _convert(*args.files))
    except (OSError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
