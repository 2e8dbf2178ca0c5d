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
import time
from dataclasses import dataclass, field, fields

import numpy as np

from ..model.profiles import FourierProfile, PolynomialProfile, ThreePhaseProfile, three_phase_times
from ..solvers.driver import simulate_batch
from ..solvers.outcomes import Reason, Status
from .classification import decision_quantities
from .steady_state import OBJECTIVE_SCALE, steady_state_grid

#: Bracket width at which the simulated steady state has converged, relative to the velocity swing.
RTOL = 1e-14
#: Probe offset of x'(0), relative to the velocity swing, for the slope of the period map.
PROBE = 1e-7
#: Period budget of one steady state in the Fourier optimisation (beyond it: time average).
OPTIMISER_PERIODS = 5000
#: Longest cycle of period-boundary states :func:`exact_steady_state` asks the driver to recognise,
#: in periods: smooth (Fourier) profiles can have long cycles where a backward slip grazes x' = 0.
MAX_CYCLE = 64
_EPS = np.finfo(float).eps


def objective(vbar):
    """f = 1 / (c vbar^2), c = 1e4 (eq. 11); inf where vbar = 0, NaN where vbar is NaN."""
    vbar = np.asarray(vbar, dtype=float)
    with np.errstate(divide="ignore"):
        return 1.0 / (OBJECTIVE_SCALE * vbar * vbar)


# --------------------------------------------------------------------------------------
# Steady state by simulation
# --------------------------------------------------------------------------------------

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
                            max_iter: int = 200) -> SimulatedSteadyState:
    """Limit of plain iteration of a batched period map from x'(0) = 0, by bisection (module docstring).

    ``period_map(index, v)`` simulates one period for each member ``index[k]``
    from x'(0) = ``v[k]`` at phase 0 and returns the end velocities and the
    displacements.  ``scale`` (the velocity swing s), ``dt`` and ``floor`` (|g|
    counted as zero) are per-member arrays or scalars.  RuntimeError if [-s, s]
    does not contain the fixed point.
    """
    if not (math.isfinite(rtol) and rtol > 0):
        raise ValueError(f"rtol must be finite and > 0 (bisection stops at a bracket of rtol * s), got {rtol!r}")
    scale = np.array(scale, dtype=float)
    dt, floor = (np.broadcast_to(np.asarray(a, dtype=float), scale.shape) for a in (dt, floor))
    members = np.arange(scale.size)
    end, dx = period_map(members, np.zeros(scale.size))
    # Search u = side * v in [0, s]: "reached" means side * g(side * u) <= floor.
    side = np.where(end > 0.0, 1.0, -1.0)
    lo, hi = np.zeros(scale.size), scale.copy()
    v_hi, dx_hi, g_hi = np.zeros(scale.size), dx.copy(), end.copy()
    at_zero = np.abs(end) <= floor
    hi[at_zero] = 0.0
    periods = np.ones(scale.size, dtype=np.int64)
    check = members[~at_zero]
    end, dx_hi[check] = period_map(check, side[check] * scale[check])
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


def velocity_swing(profile) -> float:
    """max y' - min y' of one profile (the velocity scale of the convergence test)."""
    return profile.velocity_swing


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


def _moreau_period_map(profiles, steps_per_period: int, iteration: str):
    """Period map from batched Moreau time-stepping with ``steps_per_period`` steps (h = dt / N)."""
    def period_map(index, v):
        res = simulate_batch(profiles, 0.0, v, profile_index=index, until="periods", periods=1, method="moreau",
                             steps_per_period=steps_per_period, iteration=iteration, fast_forward=False)
        return np.reshape(res.v_end, index.shape), np.reshape(res.records["xi"], index.shape)  # x0 = 0
    return period_map


def _three_phase_period_map(dt, dy, y2, y3):
    """Period map of three-phase profiles (flat feasible arrays) from the batched exact solver."""
    from .positioning import three_phase_table

    table = three_phase_table(dt, dy, y2, y3)

    def period_map(index, v):
        res = simulate_batch(table, 0.0, v, profile_index=index, until="periods", periods=1, fast_forward=False)
        if np.any(res.reason == Reason.MAX_EVENTS):
            raise RuntimeError("batched exact solver failed on a three-phase profile")
        return res.v_end, res.records["xi"]        # x0 = 0: the end position is the displacement
    return period_map


def simulated_steady_state(profiles, method: str = "exact", *, steps_per_period: int = 1000,
                           iteration: str = "exact", rtol: float = RTOL) -> SimulatedSteadyState:
    """Steady state of each profile on a uniform surface by simulation (module docstring).

    ``method="exact"``: :func:`exact_steady_state` for each profile;
    ``method="moreau"``: Moreau time-stepping with ``steps_per_period`` steps and
    the implicit step solved by ``iteration`` ("exact" soft threshold or the
    paper's "fixed_point"), all profiles in one batch, iterated to the steady
    state by :func:`iterate_to_steady_state`.
    """
    profiles = list(profiles)
    if not profiles:
        raise ValueError("profiles: give at least one profile")
    if method == "exact":
        parts = [exact_steady_state(p) for p in profiles]
        return SimulatedSteadyState(*(np.concatenate([getattr(r, f.name) for r in parts])
                                      for f in fields(SimulatedSteadyState)))
    if method != "moreau":
        raise ValueError(f"method must be 'exact' or 'moreau', got {method!r}")
    if isinstance(steps_per_period, bool) or not isinstance(steps_per_period, int) or steps_per_period < 2:
        raise ValueError(f"steps_per_period must be an integer >= 2, got {steps_per_period!r}")
    scale = np.array([velocity_swing(p) for p in profiles])
    return iterate_to_steady_state(_moreau_period_map(profiles, steps_per_period, iteration), scale,
                                   np.array([p.dt for p in profiles]), floor=steps_per_period * _EPS * scale,
                                   rtol=rtol)


def three_phase_simulated_steady_state(dt, dy, y2, y3, *, rtol: float = RTOL) -> SimulatedSteadyState:
    """Simulated steady state of three-phase profiles (broadcast arrays; NaN for case 0) with the
    batched exact solver and :func:`iterate_to_steady_state`, independent of the closed forms."""
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (dt, dy, y2, y3)))
    shape = arrays[0].shape
    dt, dy, y2, y3 = (a.ravel() for a in arrays)
    times = three_phase_times(dt, dy, y2, y3)
    ok = np.flatnonzero(times.feasible)
    out = {key: np.full(dt.size, np.nan) for key in ("vbar", "v0", "residual")}
    periods, cycle = np.zeros(dt.size, dtype=np.int64), np.ones(dt.size, dtype=np.int64)
    if ok.size:
        swing = y2[ok] * (times.t2[ok] - times.t1[ok])   # max y' - min y' (eq. 63)
        res = iterate_to_steady_state(_three_phase_period_map(dt[ok], dy[ok], y2[ok], y3[ok]),
                                      swing, dt[ok], rtol=rtol)
        for key in out:
            out[key][ok] = getattr(res, key)
        periods[ok] = res.periods
    return SimulatedSteadyState(*(out[k].reshape(shape) for k in ("vbar", "v0", "residual")),
                                periods.reshape(shape), cycle.reshape(shape))


# --------------------------------------------------------------------------------------
# Figs. 4 and 5: the polynomial profile
# --------------------------------------------------------------------------------------

def polynomial_sweep(dt, dy, *, forward_fraction: float = 0.8, steps_per_period: int = 1000,
                     iteration: str = "exact", rtol: float = RTOL) -> tuple[dict, dict]:
    """Figs. 4 and 5: steady state of the polynomial profile (Sect. 4.2) along a sweep.

    ``dt`` and ``dy`` broadcast to one dimension (one of them is the swept
    array).  Returns datasets ``dt``, ``dy``, and for ``exact`` and ``moreau``:
    ``vbar_*``, ``f_*`` (eq. 11), ``residual_*`` (|x'(dt) - x'(0)| over the
    steady period), ``periods_*`` (periods simulated); and attributes with
    the settings.
    """
    dt, dy = (np.atleast_1d(a).astype(float) for a in np.broadcast_arrays(dt, dy))
    if dt.ndim != 1:
        raise ValueError(f"dt and dy must broadcast to one dimension, got shape {dt.shape}")
    profiles = [PolynomialProfile(t, s, forward_fraction) for t, s in zip(dt.tolist(), dy.tolist())]
    data = {"dt": dt, "dy": dy}
    for method in ("exact", "moreau"):
        res = simulated_steady_state(profiles, method, steps_per_period=steps_per_period,
                                     iteration=iteration, rtol=rtol)
        data.update({f"vbar_{method}": res.vbar, f"f_{method}": res.f, f"residual_{method}": res.residual,
                     f"periods_{method}": res.periods})
    attrs = {"forward_fraction": float(forward_fraction), "moreau_steps_per_period": int(steps_per_period),
             "moreau_iteration": iteration, "rtol": float(rtol), "objective_scale": OBJECTIVE_SCALE}
    return data, attrs


# --------------------------------------------------------------------------------------
# Figs. 10 and 11: (y2'', y3'') maps, computed in shards
# --------------------------------------------------------------------------------------

#: Target of :func:`map_verification`: closed-form and simulated vbar agree to this, relative.
VERIFY_RTOL = 1e-10
#: ... except within |vbar| < VERIFY_BAND * (velocity swing) of vbar = 0 (see map_verification).
VERIFY_BAND = 1e-3
#: 2-D datasets of a map, indexed [i_y2, i_y3].
MAP_FIELDS = ("case", "vbar", "f", "vbar_simulated")


def shard_rows(rows: int, shards: int, index: int, *, interleaved: bool = False) -> slice:
    """Rows (y2 indices) of shard ``index`` of ``shards``: contiguous, sizes differing by at most one;
    with ``interleaved`` every ``shards``-th row from ``index`` instead, which balances the jobs of a
    sweep whose cost is concentrated in part of the y2 range (Fig. 17)."""
    if isinstance(shards, bool) or not isinstance(shards, (int, np.integer)) or shards < 1:
        raise ValueError(f"shards must be an integer >= 1, got {shards!r}")
    if not 0 <= index < shards:
        raise ValueError(f"shard index must lie in [0, {shards}), got {index!r}")
    if interleaved:
        return slice(index, int(rows), int(shards))
    base, extra = divmod(int(rows), int(shards))
    start = index * base + min(index, extra)
    return slice(start, start + base + (index < extra))


def map_shard(dt: float, dy: float, y2, y3, rows: slice, *, simulate: bool = True, rtol: float = RTOL) -> dict:
    """The map rows ``y2[rows]`` x all of ``y3``: closed-form ``case``, ``vbar``, ``f``
    (Sect. 5.1, eq. 11) and, with ``simulate``, ``vbar_simulated`` (batched exact solver,
    module docstring).  Every entry depends only on its own (y2, y3), so shards
    concatenate to the whole map bit for bit."""
    y2 = np.asarray(y2, dtype=float)[rows]
    g2, g3 = np.meshgrid(y2, np.asarray(y3, dtype=float), indexing="ij")
    ss = steady_state_grid(dt, dy, g2, g3)
    out = {"case": ss.case.astype(np.int8), "vbar": ss.vbar, "f": ss.f}
    if simulate:
        out["vbar_simulated"] = three_phase_simulated_steady_state(dt, dy, g2, g3, rtol=rtol).vbar
    return out


def gather_map(dt: float, dy: float, y2, y3, shards: list[dict]) -> tuple[dict, dict]:
    """Datasets and attributes of ``results/classification/fig10.h5`` / ``fig11.h5`` from the
    shards in row order (README, "Steady state and classification")."""
    y2, y3 = np.asarray(y2, dtype=float), np.asarray(y3, dtype=float)
    data = {"y2": y2, "y3": y3}
    for name in (n for n in MAP_FIELDS if n in shards[0]):
        data[name] = np.concatenate([s[name] for s in shards], axis=0)
        if data[name].shape != (y2.size, y3.size):
            raise ValueError(f"gathered {name!r} has shape {data[name].shape}, expected {(y2.size, y3.size)}")
    return data, {"dt": float(dt), "dy": float(dy)}


def map_verification(data: dict, attrs: dict) -> dict:
    """Agreement of the closed-form vbar with the simulated one over a map (:func:`gather_map` output).

    The target is |vbar_sim - vbar| <= VERIFY_RTOL |vbar|.  Next to the vbar = 0 line
    (inside case 4 or 3) vbar is a small difference of the forward and backward
    areas, and x'(0) of the steady state is itself determined only to ~ulp / (1 - c4)
    (eq. 33) by either computation, so the check is made against
    VERIFY_RTOL max(|vbar|, VERIFY_BAND u), u the table velocity swing (eq. 63).
    Returns ``max_rel_error`` (plain |dv| / |vbar|, 0 where both are 0),
    ``max_scaled_error`` (the checked quantity), ``max_abs_error``,
    ``max_error_over_swing``, ``points`` (feasible points verified),
    ``band_points`` (points with |vbar| < VERIFY_BAND u) and ``passed``.
    """
    ok = data["case"] > 0
    va, vs = data["vbar"][ok], data["vbar_simulated"][ok]
    if np.isnan(vs).any() or np.isnan(va).any():
        raise ValueError("map_verification: a feasible point has no vbar")
    g2, g3 = np.meshgrid(data["y2"], data["y3"], indexing="ij")
    swing = decision_quantities(attrs["dt"], attrs["dy"], g2, g3)["swing"][ok]
    diff = np.abs(vs - va)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(diff == 0.0, 0.0, diff / np.abs(va))
    scaled = diff / np.maximum(np.abs(va), VERIFY_BAND * swing)
    return {"max_rel_error": float(rel.max()), "max_scaled_error": float(scaled.max()),
            "max_abs_error": float(diff.max()), "max_error_over_swing": float((diff / swing).max()),
            "points": int(ok.sum()), "band_points": int(np.count_nonzero(np.abs(va) < VERIFY_BAND * swing)),
            "target": VERIFY_RTOL, "band": VERIFY_BAND, "passed": bool(scaled.max() <= VERIFY_RTOL)}


# --------------------------------------------------------------------------------------
# Fig. 6: Fourier shape optimisation (Sect. 4.4.2)
# --------------------------------------------------------------------------------------

#: f reported in the caption of the paper's Fig. 6 (inconsistent with eq. 11, see the README).
PAPER_FIG6_F = 56.0

def fourier_projection(profile, order: int, samples: int = 4096) -> FourierProfile:
    """The first ``order`` harmonics of a periodic profile (FFT of ``samples`` samples)."""
    t = np.arange(samples) * profile.dt / samples
    spec = np.fft.rfft(profile.position(t)) * (2.0 / samples)
    return FourierProfile(profile.dt, spec.real[1:order + 1], -spec.imag[1:order + 1])


def fourier_start(dt: float, dy: float, order: int, forward_fraction: float = 0.8) -> FourierProfile:
    """Deterministic start of the optimisation: the polynomial profile of Sect. 4.2 (the
    paper's first table motion), truncated to ``order`` harmonics and scaled to stroke dy."""
    proj = fourier_projection(PolynomialProfile(dt, dy, forward_fraction), order)
    k = dy / proj.stroke
    return FourierProfile(dt, k * proj.cos_coeffs, k * proj.sin_coeffs)


@dataclass
class FourierOptimum:
    """Result of :func:`optimise_fourier`; ``history_f``: f at the start and after every iteration."""

    profile: FourierProfile
    start: FourierProfile
    vbar: float
    f: float
    v0: float
    history_f: np.ndarray
    iterations: int
    evaluations: int
    success: bool
    message: str
    seconds: float
    settings: dict = field(default_factory=dict)


def steady_vbar_gradient(profile_of, z, steady: SimulatedSteadyState, count: int, fd_step: float) -> np.ndarray:
    """d vbar / d z[:count] of the steady state ``steady`` of ``profile_of(z)`` by implicit
    differentiation (:func:`optimise_fourier`); entries from ``count`` on are 0."""
    k, v = max(int(steady.cycle[0]), 1), float(steady.v0[0])
    base = profile_of(z)
    p0, d0 = run_periods(base, v, k)
    delta = PROBE * velocity_swing(base)
    pd, dd = run_periods(base, v + delta, k)
    p_v, d_v = (pd - p0) / delta, (dd - d0) / delta
    grad = np.zeros_like(z)
    for i in range(count):
        zi = z.copy()
        zi[i] += fd_step
        pi, di = run_periods(profile_of(zi), v, k)
        p_z, d_z = (pi - p0) / fd_step, (di - d0) / fd_step
        grad[i] = (d_z + d_v * p_z / (1.0 - p_v)) / (k * base.dt)
    return grad


def optimise_fourier(dt: float, dy: float, yd_max: float, ydd_max: float, *, order: int = 12,
                     max_iter: int = 40, samples: int | None = None, fd_step: float = 1e-9,
                     first_step: float = 0.02, forward_fraction: float = 0.8) -> FourierOptimum:
    """Fig. 6 (Sect. 4.4.2): maximise vbar (i.e. minimise f, eq. 11) over the Fourier
    coefficients of y, with SLSQP.

    Variables z: the coefficients a_k, b_k (k = 1..order) in units of dy, and the
    bounds m, M of y / dy.  Constraints, on ``samples`` equally spaced times
    (default 64 (order + 1), the exact solver's event grid): m <= y / dy <= M
    with M - m = 1, i.e. stroke <= dy, |y'| <= yd_max, |y''| <= ydd_max.  All
    are linear in z, so SLSQP meets them exactly on the samples (between
    samples a peak may exceed its bound by ~(pi / samples per shortest
    period)^2 / 2 relative).  The stroke bound is an inequality: a dithering
    profile (README) may do better with a slightly smaller stroke.  The true
    stroke and peaks are reported in ``settings``.

    Objective: -vbar of the steady state the exact solver reaches from rest, x'(0) = 0
    at t = 0 (:func:`exact_steady_state`; the same start for every profile, as
    dithering profiles can have several steady motions), scaled so that SLSQP's
    first step (identity Hessian) has length ``first_step`` in z.  Gradient: implicit
    differentiation of the steady state.  With P(v; z), D(v; z) the velocity and
    displacement after the k periods of the steady cycle from x'(0) = v, the fixed
    point v* = P(v*; z) moves by dv*/dz = P_z / (1 - P_v), so
    dvbar/dz = (D_z + D_v dv*/dz) / (k dt); P_z, D_z are forward differences of
    step ``fd_step`` and P_v, D_v of step PROBE * (velocity swing), each a
    k-period run from v* — 2 (order + 1) short runs instead of 2 order steady
    states.  A trial profile whose motion does not settle within
    OPTIMISER_PERIODS periods gets its time-averaged vbar, and, should SLSQP ask
    for a gradient there, the one-period linearisation at its last state.
    Start: :func:`fourier_start`.

    The path of the iterates is sensitive to rounding (the objective is not smooth
    where a slip grazes x' = 0, and SciPy's SLSQP sums differently with the BLAS
    thread count), so it is reproducible for a fixed thread count and machine;
    the workflow runs it single-threaded.
    """
    from scipy.optimize import minimize

    for name, value in (("dt", dt), ("dy", dy), ("yd_max", yd_max), ("ydd_max", ydd_max),
                        ("fd_step", fd_step), ("first_step", first_step)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    if isinstance(order, bool) or not isinstance(order, int) or order < 1:
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    samples = 64 * (order + 1) if samples is None else int(samples)
    start_time = time.perf_counter()
    start = fourier_start(dt, dy, order, forward_fraction)
    n_coef = 2 * order
    w = 2.0 * np.pi * np.arange(1, order + 1) / dt
    t = np.arange(samples) * dt / samples
    cos, sin = np.cos(np.outer(t, w)), np.sin(np.outer(t, w))
    # Rows map z to y / dy, y' and y'' at the samples.
    zeros = np.zeros((samples, 2))
    pos = np.hstack([cos, sin, zeros])
    vel = dy * np.hstack([-sin * w, cos * w, zeros])
    acc = dy * np.hstack([-cos * w**2, -sin * w**2, zeros])
    lower, upper = np.zeros((samples, n_coef + 2)), np.zeros((samples, n_coef + 2))
    lower[:, -2] = upper[:, -1] = 1.0
    # Inequalities G z + g >= 0: y - m, M - y, yd_max -+ y', ydd_max -+ y''.
    G = np.vstack([pos - lower, upper - pos, -vel, vel, -acc, acc])
    g = np.concatenate([np.zeros(2 * samples), np.full(2 * samples, yd_max), np.full(2 * samples, ydd_max)])
    E = np.zeros((1, n_coef + 2))
    E[0, -1], E[0, -2] = 1.0, -1.0

    def profile_of(z):
        return FourierProfile(dt, dy * z[:order], dy * z[order:n_coef])

    cache: dict[bytes, SimulatedSteadyState] = {}

    def steady(z):
        key = z.tobytes()
        if key not in cache:
            cache[key] = exact_steady_state(profile_of(z), max_periods=OPTIMISER_PERIODS, aperiodic="average")
        return cache[key]

    def vbar_gradient(z):
        return steady_vbar_gradient(profile_of, z, steady(z), n_coef, fd_step)
    z0 = np.concatenate([start.cos_coeffs / dy, start.sin_coeffs / dy, [0.0, 0.0]])
    y0 = pos @ z0
    z0[-2], z0[-1] = y0.min(), y0.min() + 1.0
    scale = first_step / np.linalg.norm(vbar_gradient(z0))
    history = [float(steady(z0).f[0])]
    res = minimize(lambda z: -scale * float(steady(z).vbar[0]), z0, jac=lambda z: -scale * vbar_gradient(z),
                   method="SLSQP", callback=lambda z: history.append(float(steady(z).f[0])),
                   constraints=[{"type": "ineq", "fun": lambda z: G @ z + g, "jac": lambda z: G},
                                {"type": "eq", "fun": lambda z: E @ z - 1.0, "jac": lambda z: E}],
                   options={"maxiter": max_iter, "ftol": 1e-12})
    best = profile_of(res.x)
    final = steady(res.x)
    vbar = float(final.vbar[0])
    settings = {"dt": float(dt), "dy": float(dy), "yd_max": float(yd_max), "ydd_max": float(ydd_max),
                "order": order, "max_iter": max_iter, "samples": samples, "fd_step": fd_step,
                "first_step": first_step, "forward_fraction": float(forward_fraction), "stroke": best.stroke,
                "peak_velocity": best.peak_velocity, "peak_acceleration": best.peak_acceleration,
                "cycle": int(final.cycle[0])}
    return FourierOptimum(profile=best, start=start, vbar=vbar, f=float(objective(vbar)),
                          v0=float(final.v0[0]), history_f=np.array(history, dtype=float),
                          iterations=int(res.nit), evaluations=len(cache), success=bool(res.success),
                          message=str(res.message), seconds=time.perf_counter() - start_time,
                          settings=settings)


def best_three_phase(dt: float, dy: float, ydd_max: float, yd_max: float, *, num: int = 401,
                     zooms: int = 3) -> ThreePhaseProfile:
    """The three-phase profile (Sect. 4.4.3) with the smallest f (closed form, eq. 11) among
    y2'', y3'' <= ydd_max and peak table speed max|y'| <= yd_max, by a grid search over
    (y2'', y3'') refined ``zooms`` times around the best point."""
    lo2 = lo3 = ydd_max / num
    hi2 = hi3 = ydd_max
    best = None
    for _ in range(zooms + 1):
        a2, a3 = np.linspace(lo2, hi2, num), np.linspace(lo3, hi3, num)
        y2, y3 = np.meshgrid(a2, a3, indexing="ij")
        ss = steady_state_grid(dt, dy, y2, y3)
        qty = decision_quantities(dt, dy, y2, y3)
        times = three_phase_times(dt, dy, y2, y3)
        peak = np.maximum(times.yd_ini, qty["swing"] - times.yd_ini)
        vbar = np.where((ss.case > 0) & (peak <= yd_max), ss.vbar, -np.inf)
        i, j = np.unravel_index(np.argmax(vbar), vbar.shape)
        if not np.isfinite(vbar[i, j]):
            raise ValueError(f"no feasible three-phase profile with dt={dt}, dy={dy}, y'' <= {ydd_max}")
        best = (a2[i], a3[j])
        d2, d3 = 2 * (hi2 - lo2) / (num - 1), 2 * (hi3 - lo3) / (num - 1)
        lo2, hi2 = max(a2[i] - d2, lo2), min(a2[i] + d2, ydd_max)
        lo3, hi3 = max(a3[j] - d3, lo3), min(a3[j] + d3, ydd_max)
    return ThreePhaseProfile(dt, dy, *best)


def time_shift(profile: FourierProfile, shift: float) -> FourierProfile:
    """The Fourier profile t -> y(t + shift) (same steady state, other phase)."""
    arg = profile.omega * shift
    c, s = np.cos(arg), np.sin(arg)
    a, b = profile.cos_coeffs, profile.sin_coeffs
    return FourierProfile(profile.dt, a * c + b * s, b * c - a * s)


def align_to(profile: FourierProfile, reference, samples: int = 4096) -> FourierProfile:
    """``profile`` shifted in time (by a multiple of dt / samples) so that its table velocity
    y' best matches that of ``reference`` (largest circular cross-correlation)."""
    t = np.arange(samples) * profile.dt / samples
    corr = np.fft.ifft(np.fft.fft(profile.velocity(t)) * np.conj(np.fft.fft(reference.velocity(t)))).real
    return time_shift(profile, float(np.argmax(corr)) * profile.dt / samples)


def steady_motion(profile, v0: float, periods: int = 3, samples_per_period: int = 400) -> dict:
    """Mass and table over ``periods`` periods from the steady state x'(0) = v0, x(0) = 0
    (exact solver): ``t``, ``v`` (x', relative), ``y`` (table), ``x_abs`` = x + y."""
    from ..model.scene import Record, Scene
    from ..solvers.driver import simulate

    scene = Scene(profile, x0=0.0, v0=float(v0), periods=int(periods), method="exact",
                  record=Record(series=("x", "v", "y"), samples_per_period=samples_per_period))
    traj = simulate(scene)
    t, x, v, y = (np.asarray(traj.series[k], dtype=float) for k in ("t", "x", "v", "y"))
    return {"t": t, "v": v, "y": y, "x_abs": x + y}


def fig06_results(dt: float, dy: float, yd_max: float, ydd_max: float, *, order: int = 12,
                  max_iter: int = 130, samples_per_period: int = 1000,
                  motion_periods: int = 3) -> tuple[dict, dict, FourierOptimum]:
    """Datasets and attributes of ``results/classification/fig06.h5`` (README), and the
    optimisation result itself.

    The optimised profile is time-shifted to match the best three-phase profile
    (:func:`align_to`; the steady state does not depend on the phase).  Profile
    samples cover one period, with y shifted to zero mean (the three-phase y has
    min y = 0); the mass motion covers ``motion_periods`` steady periods.
    """
    opt = optimise_fourier(dt, dy, yd_max, ydd_max, order=order, max_iter=max_iter)
    three = best_three_phase(dt, dy, ydd_max, yd_max)
    ss3 = steady_state_grid(dt, dy, three.y2, three.y3)
    best = align_to(opt.profile, three)
    t = np.arange(samples_per_period + 1) * dt / samples_per_period
    data = {"t": t, "history_f": opt.history_f, "cos_coeffs": best.cos_coeffs, "sin_coeffs": best.sin_coeffs,
            "start_cos_coeffs": opt.start.cos_coeffs, "start_sin_coeffs": opt.start.sin_coeffs}
    for name, profile in (("fourier", best), ("start", opt.start), ("three_phase", three)):
        y = profile.position(t)
        data.update({f"{name}_y": y - y[:-1].mean(), f"{name}_yd": profile.velocity(t),
                     f"{name}_ydd": profile.acceleration(t)})
    steady_best = exact_steady_state(best, max_periods=4 * OPTIMISER_PERIODS, aperiodic="average")
    for name, profile, v0 in (("fourier", best, float(steady_best.v0[0])), ("three_phase", three, float(ss3.v0))):
        for key, values in steady_motion(profile, v0, motion_periods, samples_per_period // 4).items():
            data[f"{name}_motion_{key}"] = values
    attrs = {f"fourier_{k}": v for k, v in opt.settings.items() if k not in ("dt", "dy", "yd_max", "ydd_max")}
    attrs.update(dt=float(dt), dy=float(dy), yd_max=float(yd_max), ydd_max=float(ydd_max),
                 fourier_vbar=opt.vbar, fourier_f=opt.f, start_f=float(opt.history_f[0]),
                 iterations=opt.iterations, evaluations=opt.evaluations, success=opt.success,
                 message=opt.message, three_phase_y2=three.y2, three_phase_y3=three.y3,
                 three_phase_case=int(ss3.case), three_phase_vbar=float(ss3.vbar), three_phase_f=float(ss3.f),
                 three_phase_peak_velocity=float(np.max(np.abs(three.piece_velocity))),
                 paper_f=PAPER_FIG6_F, paper_vbar=float(1.0 / math.sqrt(OBJECTIVE_SCALE * PAPER_FIG6_F)))
    return data, attrs, opt
