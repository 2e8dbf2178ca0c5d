"""Wall-clock time of the Fig. 17 sweep with the batched exact solver (Sect. 7.2).

Run: python benchmarks/bench_fig17.py [n] [entries] [processes]   (default 101 64 2)
An n x n grid of (y2'', y3'') in [0.5, 2.5]^2 (dy = 0.084, dt = 1, w = 0.05,
c_mu = 2.5), every setting with entries steady-state entries run to their
outcome (at most 1000 periods), split over `processes` worker processes, plus
the accumulation-speed levels p = 0.99, 0.999.  Prints the machine, the
settings, the entries, the seconds and the trajectory events per second.
Target: 101 x 101 x 64 in under 60 s on 2 cores.
"""

from __future__ import annotations

import os
import platform
import sys
import time

import numpy as np

from selfalign.analysis.positioning import positioning_grid

DT, DY, W, C_MU = 1.0, 0.084, 0.05, 2.5


def main(n: int = 101, entries: int = 64, processes: int = 2) -> None:
    y = np.linspace(0.5, 2.5, n)
    y2, y3 = np.meshgrid(y, y, indexing="ij")
    start = time.perf_counter()
    grid = positioning_grid(DT, DY, y2, y3, w=W, c_mu=C_MU, n_entries=entries, levels=(0.99, 0.999),
                            processes=processes)
    seconds = time.perf_counter() - start
    moving = int(grid.moving.sum())
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
          f"Python {platform.python_version()}, {processes} process(es)")
    print(f"settings: {n} x {n} = {n * n} ({moving} move forward and are simulated), "
          f"entries per setting: {entries}, trajectories: {moving * entries}")
    print(f"time: {seconds:.2f} s wall clock, {grid.events} trajectory events, "
          f"{grid.events / seconds:.3e} events/s")
    print(f"settings where all / some / no entries accumulate: {int(np.sum(grid.frac_accumulate == 1))} / "
          f"{int(np.sum((grid.frac_accumulate > 0) & (grid.frac_accumulate < 1)))} / "
          f"{int(np.sum(grid.frac_accumulate[grid.moving] == 0))}")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:4]))
