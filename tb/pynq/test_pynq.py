# SPDX-License-Identifier: MIT
"""The PYNQ backend (docs/pynq.md): orb_accel.pynq_bus and the UIO lookup here, in .venv; the
checks under PyPI's pynq in .venv-pynq.

- tb/pynq/pynq_checks.py runs in .venv-pynq (pynq 4.0.0 pins numpy below 2; `make setup` and
  `make test` make the venv from tb/pynq/requirements.txt): every check in it runs and passes, none
  is skipped (about 4 s);
- the interrupt number and the VLNV the driver binds to follow vivado/board.json;
- find_uio_irq finds the UIO device of an interrupt line the way PYNQ does (/proc/interrupts, then
  sysfs), and says what is missing;
- PynqBus over a fake MMIO: one MMIO access per register access, both block modes, every bad
  address or value a ValueError before any access, the UIO interrupt when it has one, polling
  IRQ_STATUS & IRQ_ENABLE when it has none.
"""

from __future__ import annotations

import ast
import json
import os
import socket
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from golden_model import regs
from orb_accel.pynq_bus import ACCEL_IRQ, VLNV, PynqBus
from orb_accel.uio import UioInterrupt, find_uio_irq

ROOT = Path(__file__).resolve().parents[2]
BOARD = json.loads((ROOT / "vivado" / "board.json").read_text())
VENV = ROOT / ".venv-pynq"
CHECKS = ROOT / "tb" / "pynq" / "pynq_checks.py"
SIZE = 0x100000


# --- the checks in .venv-pynq --------------------------------------------------------------------


def test_pynq_checks_in_their_venv(tmp_path: Path) -> None:
    python = VENV / "bin" / "python"
    assert python.exists(), f"{VENV} is missing: `make setup` makes it (pip install -r tb/pynq/requirements.txt)"
    report = tmp_path / "junit.xml"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(str(ROOT / p) for p in ("sw", ".", "tb"))}
    proc = subprocess.run(
        [str(python), "-m", "pytest", "-q", "-p", "no:cacheprovider", f"--junitxml={report}",
         "--basetemp", str(tmp_path / "base"), str(CHECKS)],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout[-6000:] + proc.stderr[-2000:]
    suite = ET.parse(report).getroot()
    suite = suite if suite.tag == "testsuite" else suite.find("testsuite")
    assert suite is not None
    tree = ast.parse(CHECKS.read_text())
    defined = sum(isinstance(n, ast.FunctionDef) and n.name.startswith("test_") for n in tree.body)
    counts = {k: int(suite.get(k, "0")) for k in ("tests", "failures", "errors", "skipped")}
    assert counts == {"tests": defined, "failures": 0, "errors": 0, "skipped": 0}, (counts, proc.stdout[-3000:])


# --- facts ---------------------------------------------------------------------------------------


def test_interrupt_and_vlnv_follow_board_json() -> None:
    acc = BOARD["accel"]
    assert ACCEL_IRQ == 32 + acc["gic_spi"] == 61 + acc["irq_f2p"], "IRQ_F2P[n] is GIC interrupt 61 + n (SPI 29 + n)"
    assert VLNV == f"xilinx.com:module_ref:{acc['entity']}:1.0"


# --- finding the interrupt's UIO device ---------------------------------------------------------


def fake_proc_and_sysfs(root: Path, lines: list[str], devices: dict[str, str]) -> tuple[Path, Path]:
    (root / "interrupts").write_text("\n".join(["           CPU0       CPU1", *lines]) + "\n")
    for dev, name in devices.items():
        (root / "uio" / dev / "maps" / "map0").mkdir(parents=True)
        (root / "uio" / dev / "name").write_text(name + "\n")
        (root / "uio" / dev / "maps" / "map0" / "size").write_text("0x00010000\n")
    (root / "uio").mkdir(exist_ok=True)
    return root / "interrupts", root / "uio"


FABRIC = f" 47:          5          0     GIC-0  {ACCEL_IRQ} Level     fabric"
OTHER = " 48:          0          0     GIC-0  62 Level     axi-gpio"


def test_find_uio_irq_as_pynq_does(tmp_path: Path) -> None:
    proc, sysfs = fake_proc_and_sysfs(tmp_path, [OTHER, FABRIC], {"uio0": "axi-gpio", "uio1": "fabric"})
    assert find_uio_irq(ACCEL_IRQ, proc, sysfs) == ("uio1", "fabric")
    assert find_uio_irq(62, proc, sysfs) == ("uio0", "axi-gpio")


def test_find_uio_irq_says_what_is_missing(tmp_path: Path) -> None:
    proc, sysfs = fake_proc_and_sysfs(tmp_path, [OTHER], {"uio0": "axi-gpio"})
    with pytest.raises(FileNotFoundError, match=f"no interrupt with hardware number {ACCEL_IRQ} in .*`fabric`"):
        find_uio_irq(ACCEL_IRQ, proc, sysfs)
    proc.write_text(proc.read_text() + FABRIC + "\n")
    with pytest.raises(FileNotFoundError, match=r"no UIO device named 'fabric'.*uio0 \('axi-gpio'\)"):
        find_uio_irq(ACCEL_IRQ, proc, sysfs)
    proc.write_text(proc.read_text() + FABRIC.replace("47:", "49:") + "\n")
    with pytest.raises(RuntimeError, match=f"2 lines of .* have hardware interrupt {ACCEL_IRQ}: fabric, fabric"):
        find_uio_irq(ACCEL_IRQ, proc, sysfs)
    with pytest.raises(FileNotFoundError, match="cannot read"):
        find_uio_irq(ACCEL_IRQ, tmp_path / "nope", sysfs)


# --- PynqBus over a fake MMIO -------------------------------------------------------------------


class FakeMmio:
    """pynq.MMIO's interface on a numpy array; counts calls (a block copy is one slice)."""

    def __init__(self, length: int = SIZE) -> None:
        self.length = length
        self.array = np.arange(length // 4, dtype=np.uint32) * np.uint32(3)
        self.calls: list[tuple[str, int]] = []

    def read(self, offset: int = 0, length: int = 4) -> int:
        self.calls.append(("read", offset))
        return int(self.array[offset // 4])

    def write(self, offset: int, data: int) -> None:
        assert type(data) is int, "pynq.MMIO.write takes int or bytes"
        self.calls.append(("write", offset))
        self.array[offset // 4] = np.uint32(data)


def test_register_access_is_one_mmio_access() -> None:
    mmio = FakeMmio()
    bus = PynqBus(mmio)
    assert bus.read32(0x40) == 3 * 0x10
    bus.write32(0x44, 0xFFFFFFFF)
    bus.write32(0x48, np.uint32(7))
    assert mmio.calls == [("read", 0x40), ("write", 0x44), ("write", 0x48)]
    assert (bus.read32(0x44), bus.read32(0x48)) == (0xFFFFFFFF, 7)
    assert (bus.reads, bus.writes) == (3, 2)


def test_block_modes_agree() -> None:
    mmio = FakeMmio()
    copy, words = PynqBus(mmio).read_block(0x8000, 40), PynqBus(mmio, block_mode="words").read_block(0x8000, 40)
    assert copy.dtype == words.dtype == np.uint32 and np.array_equal(copy, words)
    assert np.array_equal(copy, mmio.array[0x2000:0x2028])
    assert [c for c in mmio.calls if c[0] == "read"] == [("read", 0x8000 + 4 * k) for k in range(40)]
    copy[0] = 1
    assert mmio.array[0x2000] == 0x6000, "a copy, not a view of the mapping"


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda b: b.read32(2), "not 32-bit aligned"),
        (lambda b: b.read32(SIZE), "outside the map"),
        (lambda b: b.read32(-4), "outside the map"),
        (lambda b: b.write32(0x10, 1 << 32), "not a 32-bit value"),
        (lambda b: b.write32(0x10, -1), "not a 32-bit value"),
        (lambda b: b.read_block(SIZE - 8, 3), "block of 3 words at .* outside the map"),
        (lambda b: b.read_block(0, -1), "block of -1 words"),
    ],
)
def test_bad_access_is_refused_before_the_mmio(call, message: str) -> None:
    mmio = FakeMmio()
    with pytest.raises(ValueError, match=message):
        call(PynqBus(mmio))
    assert mmio.calls == []


def test_bad_construction() -> None:
    with pytest.raises(ValueError, match="block_mode 'dma'"):
        PynqBus(FakeMmio(), block_mode="dma")
    with pytest.raises(ValueError, match="poll_s 0"):
        PynqBus(FakeMmio(), poll_s=0)
    with pytest.raises(ValueError, match="MMIO length 0x6"):
        PynqBus(FakeMmio(6))


def test_wait_irq_polls_without_an_interrupt() -> None:
    mmio = FakeMmio()
    bus = PynqBus(mmio, poll_s=0.001)
    mmio.array[regs.IRQ_STATUS.offset // 4] = 1
    mmio.array[regs.IRQ_ENABLE.offset // 4] = 0
    assert not bus.wait_irq(0.01)
    mmio.array[regs.IRQ_ENABLE.offset // 4] = 1
    assert bus.wait_irq(0.01)
    assert ("read", regs.IRQ_STATUS.offset) in mmio.calls and ("read", regs.IRQ_ENABLE.offset) in mmio.calls


def test_wait_irq_takes_the_uio_interrupt_and_close_closes_it(tmp_path: Path) -> None:
    ours, kernel = socket.socketpair()
    with ours, kernel:
        irq = UioInterrupt(os.dup(ours.fileno()), tmp_path / "uio1", owns_fd=True)
        mmio = FakeMmio()
        with PynqBus(mmio, irq) as bus:
            kernel.sendall((41).to_bytes(4, sys.byteorder))
            assert bus.wait_irq(1.0) and irq.count == 41
            assert kernel.recv(4) == (1).to_bytes(4, sys.byteorder), "the enable write"
            assert not bus.wait_irq(0)
            assert mmio.calls == [], "no register polled when the interrupt is there"
        assert irq.fd is None
        with pytest.raises(ValueError, match="is closed"):
            irq.wait(0)
