# SPDX-License-Identifier: MIT
"""Processes of the ROS nodes' end-to-end tests (tb/ros, tb/ros2): stop a process group, wait for
a condition while the processes live, read a listener's JSON lines, find processes left behind."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

WAIT_S = 600.0  # wall-clock bound of any wait (a frame takes milliseconds on the fast engine, seconds in GHDL)


def stop(proc: subprocess.Popen, sig: int = signal.SIGINT, wait_s: float = 60.0) -> int | None:
    """Signal the process group; when it does not end within wait_s, SIGABRT the process (a Python
    started with PYTHONFAULTHANDLER=1 writes every thread's stack to its log: where it hung), then
    SIGKILL the group. The exit status, None when it had to be killed."""
    if proc.poll() is None:
        try:
            os.killpg(proc.pid, sig)
            proc.wait(wait_s)
        except subprocess.TimeoutExpired:
            os.kill(proc.pid, signal.SIGABRT)
            try:
                proc.wait(5.0)
            except subprocess.TimeoutExpired:
                pass
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:  # the SIGABRT ended the whole group
                pass
            proc.wait()
            return None
        except ProcessLookupError:
            pass
    return proc.returncode


def records(path: Path, topic: str) -> list[dict]:
    """A listener's JSON lines of one topic (a line still being written is left out)."""
    if not path.exists():
        return []
    lines = path.read_text().splitlines()
    return [r for r in (json.loads(line) for line in lines if line.endswith("}")) if r["topic"] == topic]


def wait(what: str, ok: Callable[[], bool], procs: dict[str, subprocess.Popen], log: Path,
         wait_s: float = WAIT_S) -> None:  # fmt: skip
    """Poll `ok` until it holds; fail with the log's tail when a process exits or time runs out."""
    deadline = time.monotonic() + wait_s
    while not ok():
        for name, p in procs.items():
            assert p.poll() is None, f"{name} exited ({p.returncode}) waiting for {what}:\n{log.read_text()[-3000:]}"
        assert time.monotonic() < deadline, f"timeout waiting for {what}:\n{log.read_text()[-3000:]}"
        time.sleep(0.2)


def alive(marker: str) -> list[str]:
    """Processes whose command line or environment mention `marker`."""
    found = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit() or int(proc.name) == os.getpid():
            continue
        try:
            text = (proc / "cmdline").read_bytes() + (proc / "environ").read_bytes()
            state = (proc / "stat").read_text().split(") ")[1][0]
        except OSError:
            continue
        if marker.encode() in text and state != "Z":
            cmdline = (proc / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            found.append(f"{proc.name}: {cmdline[:200]}")
    return found
