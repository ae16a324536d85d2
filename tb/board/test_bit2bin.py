# SPDX-License-Identifier: MIT
"""Checks of sw/orb_flow/board/bit2bin.py, the .bit -> byte-swapped .bit.bin converter for the Zynq
fpga_manager, on a synthetic .bit (orbtb.bitfile): header parsing, the word swap, the sync word, the CLI
and the error messages on bad input."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from orb_flow.board import bit2bin as b2b
from orbtb.bitfile import DESIGN, RAW, SYNC_AT, WORDS, make_bit

ROOT = Path(__file__).resolve().parents[2]

# --- the conversion ----------------------------------------------------------------------------


def test_parse_bit_reads_the_header_fields() -> None:
    hdr = b2b.parse_bit(make_bit())
    assert (hdr.design, hdr.part, hdr.date, hdr.time) == (DESIGN, "7z020clg400", "2026/11/24", "12:34:56")
    assert hdr.data == RAW


def test_every_word_is_byte_swapped_and_the_length_kept() -> None:
    out = b2b.bit_to_bin(make_bit())
    assert len(out) == len(RAW) == 72
    assert [int.from_bytes(out[i : i + 4], "little") for i in range(0, len(out), 4)] == WORDS
    assert out[32:40] == bytes.fromhex("bb000000 44002211")  # bus-width words
    assert out[SYNC_AT : SYNC_AT + 4] == bytes([0x66, 0x55, 0x99, 0xAA])
    assert out[-4:] == bytes.fromhex("78563412")


def test_check_bin_finds_the_swapped_sync_word() -> None:
    assert b2b.check_bin(b2b.bit_to_bin(make_bit())) == SYNC_AT


def test_check_bin_refuses_unswapped_data_and_a_bit_file() -> None:
    with pytest.raises(ValueError, match="unswapped"):
        b2b.check_bin(RAW)
    with pytest.raises(ValueError, match=r"\.bit file"):
        b2b.check_bin(make_bit())


# --- bad input ---------------------------------------------------------------------------------


def _cut_header() -> bytes:
    return make_bit()[:40]


def _cut_data() -> bytes:
    return make_bit()[:-4]


def _wrong_magic() -> bytes:
    bit = bytearray(make_bit())
    bit[2] = 0x0E
    return bytes(bit)


def _no_sync() -> bytes:
    return make_bit(RAW.replace(bytes.fromhex("aa995566"), bytes.fromhex("ffffffff")))


def _odd_length() -> bytes:
    return make_bit(RAW + b"\0\0")


def _extra_bytes() -> bytes:
    return make_bit(RAW + b"\0" * 4, declared=len(RAW))


BAD = {
    "truncated header": (_cut_header, r"^truncated \.bit: field 'a' \(design\) needs"),
    "truncated data": (_cut_data, r"^truncated \.bit: header declares 72 bytes of raw data, file has 68$"),
    "wrong magic": (_wrong_magic, r"^not a \.bit file: the 13-byte preamble"),
    "missing sync": (_no_sync, r"^sync word 0xAA995566 not found in the raw data$"),
    "length not multiple of 4": (_odd_length, r"^raw data length 74 is not a multiple of 4$"),
    "length mismatch": (_extra_bytes, r"^length mismatch: header declares 72 bytes of raw data, file has 76$"),
}


@pytest.mark.parametrize("case", BAD)
def test_bad_input_raises_a_clear_error(case: str) -> None:
    make, message = BAD[case]
    with pytest.raises(ValueError, match=message):
        b2b.bit_to_bin(make())


def test_too_short_for_the_preamble() -> None:
    with pytest.raises(ValueError, match=r"^truncated \.bit: 5 bytes"):
        b2b.parse_bit(b"\x00\x09\x0f\xf0\x0f")


# --- the command line --------------------------------------------------------------------------


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "orb_flow.board.bit2bin", *args], capture_output=True, text=True, timeout=60
    )


def test_cli_converts_and_prints_one_line(tmp_path: Path) -> None:
    src, dst = tmp_path / "top.bit", tmp_path / "top.bit.bin"
    src.write_bytes(make_bit())
    r = run(str(src), str(dst))
    assert r.returncode == 0, r.stderr
    assert r.stdout == f"{dst}: design {DESIGN}, part 7z020clg400, 72 bytes\n"
    assert dst.read_bytes() == b2b.bit_to_bin(make_bit())

    r = run("--check", str(dst))
    assert (r.returncode, r.stdout) == (0, f"{dst}: ok, swapped sync word at offset 48, 72 bytes\n")


@pytest.mark.parametrize("case", BAD)
def test_cli_bad_input_exits_1_with_one_error_line(tmp_path: Path, case: str) -> None:
    src, dst = tmp_path / "bad.bit", tmp_path / "bad.bit.bin"
    src.write_bytes(BAD[case][0]())
    r = run(str(src), str(dst))
    assert r.returncode == 1
    assert r.stdout == ""
    assert r.stderr.startswith("error: ") and r.stderr.count("\n") == 1
    assert not dst.exists()


def test_cli_check_rejects_an_unswapped_bin(tmp_path: Path) -> None:
    plain = tmp_path / "plain.bin"
    plain.write_bytes(RAW)
    r = run("--check", str(plain))
    assert r.returncode == 1
    assert r.stderr == "error: sync word found unswapped (AA 99 55 66): a plain .bin, not the byte-swapped .bit.bin\n"


def test_cli_missing_file_exits_1(tmp_path: Path) -> None:
    r = run(str(tmp_path / "nope.bit"), str(tmp_path / "out.bin"))
    assert r.returncode == 1
    assert r.stderr.startswith("error: ") and "nope.bit" in r.stderr
