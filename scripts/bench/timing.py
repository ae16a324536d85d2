# SPDX-License-Identifier: MIT
"""The benchmarks' one timing rule: a warm-up call, then the median of `repeat` timed calls, in
milliseconds (scripts/bench/bench_driver.py, bench_stream.py, bench_ros2.py import it as a sibling)."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable


def median_ms(fn: Callable[[], object], repeat: int) -> float:
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times) * 1e3
