"""What the undecided entries of the Fig. 17 sweep do (docs/explanation/performance.md): a census.

Run: python benchmarks/fig17_undecided.py [n] [entries]   (default 41 32; about 1 minute)
On an n x n grid of (y2'', y3'') in [0.5, 2.5]^2 at the Fig. 17 settings, every entry that is
undecided after the sweep's 1000 periods (max_cycle 8) is run again with a 20x longer budget and
max_cycle 1024.  Printed: the share of the sweep's events that the undecided entries take, what
the longer budget makes of them (rest, periodic, still undecided: share of their events, periods
to the decision), and per setting the Lyapunov exponent of the stick map.

The stick map: in these runs the mass sticks once every period, in the dwell (y'' = 0), at a
position x_n < x_stick_min where the friction cannot hold max|y''|; it slips forward from rest at
the start t1 of the -y2'' phase, reverses in the y3'' phase and slips backward until the next
dwell.  The whole motion is therefore the 1-D map f: x_n -> x_{n+1} (the state at phase t1 is
(x_n, 0)), checked here at every iterate.  Its Lyapunov exponent, the mean of log|f'(x_n)| along
the orbit (f' by central differences), says whether the motion is chaotic (> 0) or converges to a
periodic orbit (< 0; exp(exponent) is the contraction per period).
"""

from __future__ import annotations

import sys
from collections import Counter

import numpy as np

from selfalign.analysis.positioning import positioning_grid
from selfalign.analysis.steady_state import steady_state_grid
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.solvers.driver import simulate_batch
from selfalign.solvers.outcomes import Reason
from selfalign.solvers.tables import three_phase_table

DT, DY, W, C_MU = 1.0, 0.084, 0.05, 2.5
BUDGET, LONG_FACTOR = 1000, 20
MAP_ITERATES, MAP_SKIP, MAP_STEP = 3000, 1000, 1e-9


def _entry_runs(y2, y3, entries, max_periods, max_cycle):
    """The sweep's runs of one setting (the entries of positioning_grid), absolute positions."""
    args = [np.array([a]) for a in (DT, DY, y2, y3)]
    steady, table = steady_state_grid(*args), three_phase_table(*args)
    one = np.zeros(1, dtype=int)
    x_mu = simulate_batch(table, 0.0, steady.v0, profile_index=one, until="periods", periods=1,
                          fast_forward=False).x_max[0]
    x0 = -steady.vbar[0] * DT * (np.arange(entries) + 0.5) / entries
    return simulate_batch(table, x0, steady.v0[0], profile_index=np.zeros(entries, dtype=int), x_mu=x_mu, w=W,
                          c_mu=C_MU, until="rest", max_periods=max_periods, max_cycle=max_cycle), x_mu


def _stick_map_orbit(y2, y3, x, v, x_mu):
    """Description of the stick map's orbit from the state (x, v) at a period boundary: its
    Lyapunov exponent and range (relative to x_mu), or where it comes to rest or leaves the map."""
    profile = ThreePhaseProfile(DT, DY, y2, y3)
    zone = {"x_mu": x_mu, "w": W, "c_mu": C_MU}
    stick = simulate_batch(profile, x, v, 0.0, **zone, until="stick", max_periods=10).x_end
    phase = profile.breaks[1] / DT

    def f(xs):
        run = simulate_batch(profile, xs, 0.0, phase, **zone, until="periods", periods=1, fast_forward=False)
        return run.x_end, np.all(run.records.mode == 0)

    orbit = np.empty(MAP_ITERATES)
    for k in range(MAP_ITERATES):
        previous = stick
        stick, stuck = f(stick)
        if not stuck:
            return f"not a stick map at iterate {k}"
        if stick[0] == previous[0]:
            return f"rests at x - x_mu = {stick[0] - x_mu:+.4f} after {k} iterates"
        orbit[k] = stick[0]
    tail = orbit[MAP_SKIP:]
    slope = (f(tail + MAP_STEP)[0] - f(tail - MAP_STEP)[0]) / (2 * MAP_STEP)
    return f"{np.mean(np.log(np.abs(slope))):+.3f}, [{tail.min() - x_mu:+.4f}, {tail.max() - x_mu:+.4f}]"


def main(n: int = 41, entries: int = 32) -> None:
    y = np.linspace(0.5, 2.5, n)
    y2, y3 = np.meshgrid(y, y, indexing="ij")
    grid = positioning_grid(DT, DY, y2, y3, w=W, c_mu=C_MU, n_entries=entries, max_periods=BUDGET,
                            progress="quiet")
    settings = np.argwhere(np.nan_to_num(grid.frac_undecided) > 0)
    undecided_events, later, later_events, later_periods = 0, Counter(), Counter(), {}
    print(f"{n} x {n} settings x {entries} entries, {grid.events} events; {len(settings)} settings have undecided "
          f"entries\n setting (y2'', y3''): undecided entries -> outcome at {LONG_FACTOR * BUDGET} periods; "
          "stick map: Lyapunov exponent per period, orbit range - x_mu, x_stick_min - x_mu")
    for i, j in settings:
        a2, a3 = y2[i, j], y3[i, j]
        short, x_mu = _entry_runs(a2, a3, entries, BUDGET, 8)
        long, _ = _entry_runs(a2, a3, entries, LONG_FACTOR * BUDGET, 1024)
        open_ = np.flatnonzero(short.records.reason == Reason.BOUNDED)
        undecided_events += int(short.records.events[open_].sum())
        outcome = Counter()
        for e in open_:
            name = Reason(int(long.records.reason[e])).name
            outcome[name] += 1
            later_events[name] += int(short.records.events[e])
            later_periods.setdefault(name, []).append(float(long.t_end_periods[e]))
        later.update(outcome)
        first = open_[0]
        orbit = _stick_map_orbit(a2, a3, short.x_end[first], short.v_end[first], x_mu)
        print(f" ({a2:.2f}, {a3:.2f}): {open_.size} -> {dict(outcome)}; {orbit}, "
              f"{W * (max(a2, a3) - 1) / (C_MU - 1):.4f}")
    print(f"undecided entries: {sum(later.values())}, {undecided_events / grid.events:.1%} of the events")
    for name, count in later.items():
        p = np.percentile(later_periods[name], [0, 50, 100])
        print(f" -> {name}: {count} entries, {later_events[name] / undecided_events:.1%} of their events, "
              f"end period min/median/max {p[0]:.0f}/{p[1]:.0f}/{p[2]:.0f}")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
