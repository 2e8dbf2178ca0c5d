"""Events per second of the exact solver on single trajectories (no fast-forward).

Run: python benchmarks/bench_exact.py [periods]   (default 20000 periods per case)
Each case is advanced with ExactSolver.advance (the solver's own event loop, nothing
recorded, no steady-state fast-forward); prints the best of three process-time
timings.  Target: >= 1e5 events/s.  Also times a 1e6-period uniform run through
sa.simulate, which fast-forwards the steady state (target: well under 1 s).
"""

from __future__ import annotations

import os
import platform
import sys
import time

import selfalign as sa
from selfalign.solvers.exact import ExactSolver

CASE1 = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
CASES = {
    "case 1 stick-slip, uniform": (CASE1, sa.Uniform()),
    "case 4 slip-slip, uniform": (sa.ThreePhaseProfile(1.0, 0.02, 3.0, 2.5), sa.Uniform()),
    "polynomial profile, uniform": (sa.PolynomialProfile(0.05, 0.02), sa.Uniform()),
    # x0 = 0 lies deep inside a wide transition zone: harmonic arcs every period.
    "transition zone, harmonic arcs": (CASE1, sa.StopZone(-1000.0, 1e4, 2.0)),
    "Fourier profile (brentq events)": (sa.FourierProfile(1.0, [0.02, 0.0], [0.0, 0.006]), sa.Uniform()),
}


def events_per_second(profile, surface, periods: int, repeat: int = 3) -> tuple[int, float]:
    best = float("inf")
    for _ in range(repeat):
        solver = ExactSolver(profile, surface, record=False)
        start = time.process_time()
        events = solver.advance(periods)
        best = min(best, time.process_time() - start)
    return events, best


def main(periods: int = 20000) -> None:
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
          f"Python {platform.python_version()}")
    for name, (profile, surface) in CASES.items():
        n = periods if not isinstance(profile, sa.FourierProfile) else max(1, periods // 20)
        events, seconds = events_per_second(profile, surface, n)
        print(f"{name:34s} {events:9d} events {seconds:7.3f} s  {events / seconds:12.3e} events/s")
    start = time.process_time()
    traj = sa.simulate(sa.Scene(CASE1, periods=1_000_000))
    print(f"{'1e6 periods via simulate (fast-forward)':34s} {traj.stats['events']:9d} events "
          f"{time.process_time() - start:7.3f} s  x_end = {traj.x_end!r}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20000)
