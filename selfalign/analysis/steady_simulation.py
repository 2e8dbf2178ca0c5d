"""Parameter studies of Sects. 4.4 and 5.2: the objective function f of eq. (11) over table profiles.

* :func:`polynomial_sweep` — Figs. 4 and 5: f against dt and against dy for the
  polynomial profile of Sect. 4.2, from time-stepping (Moreau, as in the paper)
  and from the exact solver.
* :func:`optimise_fourier` — Fig. 6: the shape of a Fourier profile optimised for f
  under the actuator constraints of Sect. 4.4.2, and :func:`best_three_phase`, the
  three-phase profile it is compared with.
* :func:`map_shard`, :func:`gather_map` — Figs. 10 and 11: f and the case of Table 1
  over a (y2'', y3'') grid from the closed-form steady state
  (:mod:`selfalign.analysis.steady_state`), each point verified by simulation.

Steady state by simulation
--------------------------
vbar (eq. 10) is the mean velocity over one period of the steady state.  On a
uniform surface x does not enter the dynamics, so the steady state is a fixed
point v* of the period map P: x'(0) -> x'(dt), and vbar = (x(n+1) - x(n)) / dt over
a period that starts at v*.

* With the exact solver (one trajectory at a time) the driver simulates periods
  from x'(0) = v0 until the period-boundary state repeats (bit for bit, or to its
  near-repeat tolerance, :data:`selfalign.solvers.outcomes.NEAR_ULPS` ulp of
  |x'| + s, s the table velocity swing max y' - min y') after a cycle of
  k <= MAX_CYCLE periods; vbar is then the net advance over those k periods.
  k > 1 occurs for smooth (Fourier) profiles: where a backward slip grazes x' = 0
  at |y''| < 1 the period map jumps (a slightly deeper graze sticks), and the
  steady motion can be a cycle of many periods.
* For batches (Moreau time-stepping, the batched exact solver) plain iteration is
  too slow: P contracts by only c4 of eq. (33) per period in slip-slip (0.998 on
  the Fig. 10 grid, 0.9968 for the polynomial profile at dt = 0.01), i.e.
  thousands of periods.  P is continuous and non-decreasing (slopes are products
  of positive slope ratios at reversals, or 0 after a stick), so plain iteration
  from x'(0) = 0 moves monotonically toward the fixed point nearest to 0 on the
  side of g(0), g(v) = P(v) - v, and converges to it.
  :func:`iterate_to_steady_state` computes that limit directly by bisection on
  the sign of g (one simulated period per member and step), in [0, s] or [-s, 0]:
  in steady state |x'| <= s, the table velocity swing max y' - min y' (the
  absolute mass velocity stays between min y' and max y'), so the interval
  brackets it.  Bisection stops when the bracket is narrower than rtol * s; its
  width bounds |v - v*| (up to rounding of g near the root) and so the error of
  vbar (the displacement over a period changes by at most dt |dv|).
* Moreau's fixed point is not unique: while the mass slips throughout a period
  the Moreau map is a translation, P(v) = v + h (N_b - N_f) (N_f, N_b the
  forward and backward slip steps; y' is periodic), so every v with N_f = N_b
  is a fixed point (an interval of width O(h)).  The bisection then uses the
  rounding floor ``floor`` (N eps s for N steps per period) as zero and returns
  the end of that interval nearest to 0, the limit of time-stepping from rest.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ..model.friction import FrictionLaw, Uniform
from ..model.profiles import finite_jerk_times, three_phase_times
from ..progress import Progress, resolve_mode
from ..solvers.driver import simulate_batch
from ..solvers.outcomes import Reason, Status
from ..solvers.tables import setting_method, setting_table
from .steady_state import OBJECTIVE_SCALE

#: Bracket width at which the simulated steady state has converged, relative to the velocity swing.
RTOL = 1e-14
#: Longest cycle of period-boundary states :func:`exact_steady_state` asks the driver to recognise,
#: in periods: smooth (Fourier) profiles can have long cycles where a backward slip grazes x' = 0.
MAX_CYCLE = 64
_EPS = np.finfo(float).eps


def objective(vbar):
    """f = 1 / (c vbar^2), c = 1e4 (eq. 11); inf where vbar = 0, NaN where vbar is NaN."""
    vbar = np.asarray(vbar, dtype=float)
    with np.errstate(divide="ignore"):
        return 1.0 / (OBJECTIVE_SCALE * vbar * vbar)


@dataclass(frozen=True)
class SimulatedSteadyState:
    """Steady state found by simulation (module docstring), one entry per member.

    ``vbar``: mean velocity of the steady motion (eq. 10); ``v0``: x'(0) at the
    start of a steady period (or cycle of periods); ``residual``: how much x'(0)
    still changed over it; ``periods``: periods simulated; ``cycle``: periods
    per repeat of the steady motion (1 unless :func:`exact_steady_state` found
    a longer cycle).
    """

    vbar: np.ndarray
    v0: np.ndarray
    residual: np.ndarray
    periods: np.ndarray
    cycle: np.ndarray

    @property
    def f(self) -> np.ndarray:
        return objective(self.vbar)


def iterate_to_steady_state(period_map, scale, dt, *, floor=0.0, rtol: float = RTOL,
                            max_iter: int = 200, progress: str = "auto") -> SimulatedSteadyState:
    """Limit of plain iteration of a batched period map from x'(0) = 0, by bisection (module docstring).

    ``period_map(index, v)`` simulates one period for each member ``index[k]``
    from x'(0) = ``v[k]`` at phase 0 and returns the end velocities and the
    displacements.  ``scale`` (the velocity swing s), ``dt`` and ``floor`` (|g|
    counted as zero) are per-member arrays or scalars.  RuntimeError if [-s, s]
    does not contain the fixed point.  ``progress`` reports the period-map calls
    (:mod:`selfalign.progress`); the bracket halves with each, so there are about
    2 + log2(1 / rtol) of them.
    """
    if not (math.isfinite(rtol) and rtol > 0):
        raise ValueError(f"rtol must be finite and > 0 (bisection stops at a bracket of rtol * s), got {rtol!r}")
    with Progress(2 + min(max_iter, math.ceil(-math.log2(rtol))), "steady state by bisection",
                  unit="period maps", mode=progress) as bar:
        return _bisect(period_map, scale, dt, floor, rtol, max_iter, bar)


def _bisect(period_map, scale, dt, floor, rtol, max_iter, bar):
    """:func:`iterate_to_steady_state` (its docstring), counting every period-map call on ``bar``."""
    scale = np.array(scale, dtype=float)
    dt, floor = (np.broadcast_to(np.asarray(a, dtype=float), scale.shape) for a in (dt, floor))
    members = np.arange(scale.size)
    end, dx = period_map(members, np.zeros(scale.size))
    bar.advance()
    # Search u = side * v in [0, s]: "reached" means side * g(side * u) <= floor.
    side = np.where(end > 0.0, 1.0, -1.0)
    lo, hi = np.zeros(scale.size), scale.copy()
    v_hi, dx_hi, g_hi = np.zeros(scale.size), dx.copy(), end.copy()
    at_zero = np.abs(end) <= floor
    hi[at_zero] = 0.0
    periods = np.ones(scale.size, dtype=np.int64)
    check = members[~at_zero]
    if check.size:      # none where every member's steady period starts at rest (Moreau refuses empty batches)
        end, dx_hi[check] = period_map(check, side[check] * scale[check])
        bar.advance()
        periods[check] += 1
        v_hi[check] = side[check] * scale[check]
        g_hi[check] = end - v_hi[check]
        bad = side[check] * g_hi[check] > floor[check]
        if bad.any():
            raise RuntimeError(f"steady state: x'(0) in [-s, s] (s = velocity swing) does not contain the "
                               f"fixed point of the period map for member {int(check[bad][0])}")
    active = check[hi[check] - lo[check] > rtol * scale[check]]
    for _ in range(max_iter):
        if active.size == 0:
            break
        mid = 0.5 * (lo[active] + hi[active])
        v = side[active] * mid
        end, dx = period_map(active, v)
        bar.advance(note=f"{active.size} of {scale.size} members bracketing")
        periods[active] += 1
        reached = side[active] * (end - v) <= floor[active]
        lo[active] = np.where(reached, lo[active], mid)
        hi[active] = np.where(reached, mid, hi[active])
        v_hi[active] = np.where(reached, v, v_hi[active])
        dx_hi[active] = np.where(reached, dx, dx_hi[active])
        g_hi[active] = np.where(reached, end - v, g_hi[active])
        active = active[hi[active] - lo[active] > rtol * scale[active]]
    else:
        if active.size:
            raise RuntimeError(f"steady state: {active.size} of {scale.size} members did not converge in "
                               f"{max_iter} bisection steps (first: member {active[0]})")
    return SimulatedSteadyState(dx_hi / dt, v_hi, np.abs(g_hi), periods, np.ones(scale.size, dtype=np.int64))


def run_periods(profile, v0: float, periods: int = 1) -> tuple[float, float]:
    """(x'(periods dt), x(periods dt) - x(0)) from x'(0) = v0, exact solver, uniform surface
    (every period simulated: no fast-forward, so perturbed runs share their arithmetic)."""
    res = simulate_batch(profile, 0.0, float(v0), until="periods", periods=int(periods), fast_forward=False)
    return float(res.v_end[0]), float(res.records["xi"][0])


def exact_steady_state(profile, v0: float = 0.0, max_periods: int = 200_000,
                       aperiodic: str = "raise") -> SimulatedSteadyState:
    """Steady state of one profile (piecewise constant or Fourier) with the exact solver:
    the driver runs from x'(0) = v0 on a uniform surface until the period-boundary state
    repeats, possibly after a cycle of up to MAX_CYCLE periods (module docstring), and
    vbar is the net advance per period of that cycle over dt.  ``residual`` is 0 for a
    bit-exact repeat and the driver's near-repeat tolerance otherwise (an upper bound).

    No repeat within ``max_periods``: RuntimeError, or with ``aperiodic="average"`` the time
    average of the second half of the run as vbar (eq. 10 as a limit), with ``cycle`` 0 and
    ``residual`` NaN.
    """
    if aperiodic not in ("raise", "average"):
        raise ValueError(f"aperiodic must be 'raise' or 'average', got {aperiodic!r}")
    res = simulate_batch(profile, 0.0, float(v0), until="rest", max_periods=int(max_periods), max_cycle=MAX_CYCLE)
    reason = Reason(int(res.reason[0]))
    if reason is Reason.REST:          # pure stick: no relative motion
        return SimulatedSteadyState(np.array([0.0]), np.array([0.0]), np.array([0.0]),
                                    np.array([int(res.period_end[0])]), np.array([1]))
    if reason.status is Status.NEVER_STOPS:
        r = res.records[0]
        return SimulatedSteadyState(np.array([float(r["advance"]) / profile.dt]), np.array([float(r["v"])]),
                                    np.array([0.0]), np.array([int(r["n_end"])]), np.array([int(r["cycle"])]))
    if aperiodic == "average":
        half = int(max_periods) // 2
        first = simulate_batch(profile, 0.0, float(v0), until="periods", periods=half, fast_forward=False)
        rest = simulate_batch(profile, 0.0, float(first.v_end[0]), until="periods", periods=int(max_periods) - half,
                              fast_forward=False)
        return SimulatedSteadyState(np.array([float(rest.records["xi"][0]) / (int(max_periods) - half) / profile.dt]),
                                    np.array([float(rest.v_end[0])]), np.array([np.nan]),
                                    np.array([int(max_periods)]), np.array([0]))
    raise RuntimeError(f"exact steady state of {profile!r}: x'(0) has not converged (nor cycled with "
                       f"<= {MAX_CYCLE} periods) in {max_periods} periods ({res.message(0)})")


def _moreau_period_map(profiles, steps_per_period: int, iteration: str, friction=None):
    """Period map from batched Moreau time-stepping with ``steps_per_period`` steps (h = dt / N)
    under the :class:`~selfalign.model.friction.FrictionLaw` ``friction`` (default Coulomb)."""
    def period_map(index, v):
        res = simulate_batch(profiles, 0.0, v, profile_index=index, until="periods", periods=1, method="moreau",
                             steps_per_period=steps_per_period, iteration=iteration, fast_forward=False,
                             friction=friction)
        return np.reshape(res.v_end, index.shape), np.reshape(res.records["xi"], index.shape)  # x0 = 0
    return period_map


def _three_phase_period_map(dt, dy, y2, y3, friction, ramp):
    """Period map of three-phase profiles (flat arrays whose profiles exist) with y'' ramps of time
    ``ramp`` (0: the paper's) from the batched solver the settings allow on a uniform surface
    (:func:`~selfalign.solvers.tables.setting_method`: exact, or Moreau for Stribeck friction)."""
    choice = setting_method(dt, dy, y2, y3, ramp, Uniform(), friction)
    table = setting_table(dt, dy, y2, y3, ramp, choice)

    def period_map(index, v):
        res = simulate_batch(table, 0.0, v, profile_index=index, until="periods", periods=1, fast_forward=False,
                             friction=friction, method=choice.method, **choice.options)
        if np.any(res.reason == Reason.MAX_EVENTS):
            raise RuntimeError("batched exact solver failed on a three-phase profile")
        return res.v_end, res.records["xi"]        # x0 = 0: the end position is the displacement
    return period_map


def simulated_steady_state(profiles, method: str = "exact", *, steps_per_period: int = 1000,
                           iteration: str = "exact", rtol: float = RTOL, progress: str = "auto",
                           friction=None) -> SimulatedSteadyState:
    """Steady state of each profile on a uniform surface by simulation (module docstring).

    ``method="exact"``: :func:`exact_steady_state` for each profile;
    ``method="moreau"``: Moreau time-stepping with ``steps_per_period`` steps and
    the implicit step solved by ``iteration`` ("exact" soft threshold or the
    paper's "fixed_point"), all profiles in one batch, iterated to the steady
    state by :func:`iterate_to_steady_state`.  ``progress``: :mod:`selfalign.progress` mode
    (profiles done with "exact", bisection steps with "moreau").  ``friction``: a
    :class:`~selfalign.model.friction.FrictionLaw` (default Coulomb), with ``method="moreau"``
    only (the Stribeck law has no exact arcs; static/kinetic three-phase profiles:
    :func:`three_phase_simulated_steady_state`).
    """
    profiles = list(profiles)
    if not profiles:
        raise ValueError("profiles: give at least one profile")
    if friction is not None and method != "moreau":
        raise ValueError(f"friction is simulated here with method 'moreau' only, got method {method!r}")
    resolve_mode(progress)
    if method == "exact":
        parts = []
        with Progress(len(profiles), "exact steady states", unit="profiles", mode=progress) as bar:
            for profile in profiles:
                parts.append(exact_steady_state(profile))
                bar.advance()
        return SimulatedSteadyState(*(np.concatenate([getattr(r, f.name) for r in parts])
                                      for f in fields(SimulatedSteadyState)))
    if method != "moreau":
        raise ValueError(f"method must be 'exact' or 'moreau', got {method!r}")
    if isinstance(steps_per_period, bool) or not isinstance(steps_per_period, int) or steps_per_period < 2:
        raise ValueError(f"steps_per_period must be an integer >= 2, got {steps_per_period!r}")
    scale = np.array([p.velocity_swing for p in profiles])
    return iterate_to_steady_state(_moreau_period_map(profiles, steps_per_period, iteration, friction), scale,
                                   np.array([p.dt for p in profiles]), floor=steps_per_period * _EPS * scale,
                                   rtol=rtol, progress=progress)


def three_phase_simulated_steady_state(dt, dy, y2, y3, *, rtol: float = RTOL, progress: str = "auto",
                                       friction=None, ramp: float = 0.0) -> SimulatedSteadyState:
    """Simulated steady state of three-phase profiles (broadcast arrays; NaN for case 0 and where
    ramps of time ``ramp`` do not fit) with the batched exact solver (Moreau where it cannot:
    Stribeck friction) and :func:`iterate_to_steady_state` (reporting to ``progress``),
    independent of the closed forms.  ``friction``: a :class:`~selfalign.model.friction.FrictionLaw`
    (default Coulomb), for which no closed form exists: a stick lasts while |y''| <= mu_s / mu_k,
    which moves every phase of Sect. 5; ``ramp``: the finite-jerk profile's y'' ramp time."""
    resolve_mode(progress)
    friction = FrictionLaw() if friction is None else friction
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (dt, dy, y2, y3)))
    shape = arrays[0].shape
    dt, dy, y2, y3 = (a.ravel() for a in arrays)
    times = three_phase_times(dt, dy, y2, y3)
    exists = times.feasible if ramp == 0.0 else finite_jerk_times(dt, dy, y2, y3, ramp, ramp, ramp).valid
    ok = np.flatnonzero(exists)
    out = {key: np.full(dt.size, np.nan) for key in ("vbar", "v0", "residual")}
    periods, cycle = np.zeros(dt.size, dtype=np.int64), np.ones(dt.size, dtype=np.int64)
    if ok.size:
        swing = y2[ok] * (times.t2[ok] - times.t1[ok])   # max y' - min y' (eq. 63)
        res = iterate_to_steady_state(_three_phase_period_map(dt[ok], dy[ok], y2[ok], y3[ok], friction, ramp),
                                      swing, dt[ok], rtol=rtol, progress=progress)
        for key in out:
            out[key][ok] = getattr(res, key)
        periods[ok] = res.periods
    return SimulatedSteadyState(*(out[k].reshape(shape) for k in ("vbar", "v0", "residual")),
                                periods.reshape(shape), cycle.reshape(shape))
