"""Throughput of the exact planar solver on piecewise-constant table accelerations (``selfalign.solvers.planar_exact``).

Run: python benchmarks/planar_exact.py [periods]   (default 100000 periods)

For the Fig. 18 profile along one axis (every slip collinear: quadratic arcs), and for two three-phase profiles a
quarter period apart (curved slips: the closed form and its Newton inversion at every piece end), prints the events
and the closed-form arcs per second (best of three, after a first call that compiles the stepper).
"""

from __future__ import annotations

import sys

from parts_moreau import best_time

import selfalign as sa
from selfalign.solvers import planar_exact

PROFILE = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
SECOND = sa.ThreePhaseProfile(dt=1.05, dy=0.05, y2=1.8, y3=1.1)
OPTIONS = {"max_events": 50_000_000}


def throughput(profile, periods: int) -> dict:
    """Events, arcs and their rates per second of one run of ``periods`` periods of ``profile`` from rest."""
    scene = sa.Scene(profile, x0=(0.0, 0.0), periods=periods)
    planar_exact.run(scene.replace(periods=1), OPTIONS)               # compile
    result = planar_exact.run(scene, OPTIONS)
    events = result.sticks + result.slips + result.breaks
    raw = planar_exact.run_pieces(*profile.pieces(), profile.dt, periods=periods)
    seconds = best_time(lambda: planar_exact.run(scene, OPTIONS))
    return {"events": events, "arcs": raw["arcs"], "seconds": seconds, "events_per_s": events / seconds,
            "arcs_per_s": raw["arcs"] / seconds}


def main(periods: int = 100_000) -> dict:
    """Print and return the throughput of the two planar cases."""
    out = {"collinear": throughput(sa.PlanarProfile(x=PROFILE), periods),
           "curved": throughput(sa.PlanarProfile(x=PROFILE, y=SECOND, offset=0.25), periods)}
    for name, row in out.items():
        print(name, {key: (round(value, 4) if isinstance(value, float) else value) for key, value in row.items()})
    return out


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100_000)
