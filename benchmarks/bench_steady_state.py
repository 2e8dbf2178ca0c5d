"""Throughput of the closed-form steady state and the a-priori classification.

Run: python benchmarks/bench_steady_state.py [n]   (an n x n grid of y2'', y3''; default 1000)
Prints the best of three wall-clock timings as points per second.  Target: a
1000 x 1000 grid in under 1 s.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from selfalign.analysis.classification import classify_grid
from selfalign.analysis.steady_state import monodromy_grid, steady_state_grid

#: The Fig. 17 setting (dy = 0.084, dt = 1): its axes cover cases 0-4.
DY, DT = 0.084, 1.0


def best_time(func, *args, repeat: int = 3) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        func(*args)
        times.append(time.perf_counter() - start)
    return min(times)


def main(n: int = 1000) -> None:
    axis = np.linspace(0.3, 6.0, n)
    y2, y3 = np.meshgrid(axis, axis, indexing="ij")
    points = y2.size
    for name, func in (("classify_grid", classify_grid), ("steady_state_grid", steady_state_grid),
                       ("monodromy_grid", monodromy_grid)):
        seconds = best_time(func, DT, DY, y2, y3)
        print(f"{name:18s} {n}x{n}: {seconds:7.3f} s  {points / seconds:12.3e} points/s")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1000)
