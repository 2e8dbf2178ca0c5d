"""Throughput of Moreau's time-stepping of several parts (``selfalign.solvers.parts_moreau``).

Run: python benchmarks/parts_moreau.py [periods]   (default 20 periods of 1000 steps)

For 2, 10 and 100 parts 0.0625 wide on the Fig. 18 profile, on the uniform surface and entering a stop
zone, prints the steps per second (best of three, after a first call that compiles the stepper) and the
time per part and step, for three arrangements: parts far apart (no contact ever), a train 0.01 apart
with friction factors 0.7 ... 1.3 (the faster parts catch up: impacts and pushing clusters), and one
cluster of touching parts (every contact closed in every step).
"""

from __future__ import annotations

import sys
import time

import numpy as np

import selfalign as sa
from selfalign.model.parts import Part
from selfalign.solvers.parts_moreau import moreau_parts

PROFILE = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
W = 0.0625                 # a binary fraction: touching parts at i W touch exactly


def arrangement(name: str, n: int) -> list[Part]:
    """``n`` parts, the rear-most at x = 0: "apart" (1 apart), "train" (0.01 apart, friction factors
    0.7 ... 1.3 in a fixed shuffled order), "cluster" (touching)."""
    factors = 0.7 + 0.6 * np.random.default_rng(0).permutation(n) / max(n - 1, 1)
    spacing = {"apart": 1.0, "train": W + 0.01, "cluster": W}[name]
    return [Part(i * spacing, width=W, friction_factor=float(factors[i]) if name == "train" else 1.0)
            for i in range(n)]


def best_time(func, repeat: int = 3) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def main(periods: int = 20) -> None:
    moreau_parts(PROFILE, arrangement("train", 2), periods=1)       # compiles the stepper
    for surface in (sa.Uniform(), sa.StopZone(x_mu=0.5, w=W, c_mu=2.5)):
        for name in ("apart", "train", "cluster"):
            for n in (2, 10, 100):
                parts = arrangement(name, n)
                steps = periods * 1000
                seconds = best_time(lambda: moreau_parts(PROFILE, parts, surface=surface, periods=periods))
                print(f"{surface.kind:9s} {name:8s} N = {n:3d}: {steps / seconds:12.4g} steps/s "
                      f"{seconds / steps / n * 1e9:8.1f} ns per part and step")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:]))
