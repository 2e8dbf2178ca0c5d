"""Moreau midpoint time-stepping for x'' + y''(t) in -mu_bar(x) Sign(x') (Sect. 4.1, eqs. 6, 38).

One step of size h from (x_k, v_k) at time t_k (unit mass, dimensionless):

    x_M     = x_k + h/2 v_k                                   (midpoint)
    v_{k+1} = v_k - h y''(t_M) - h mu_bar(x_M) s,  s in Sign(v_{k+1})   (implicit friction impulse)
    x_{k+1} = x_M + h/2 v_{k+1}

The implicit equation has the exact one-dimensional solution (``iteration="exact"``)
v_{k+1} = v* - clip(v*, -h mu_bar, h mu_bar) with v* = v_k - h y''(t_M), a soft
threshold.  ``iteration="fixed_point"`` solves it the way the paper does, by a
fixed-point iteration on the friction multiplier (see :func:`fixed_point_impulse`).

Choices:

* Steps per period.  The step is adjusted down to h = dt / N with N = ceil(dt / h)
  (a ratio within 1e-9 of an integer counts as that integer), so every period holds
  exactly N steps, the midpoint accelerations y''(t_M) are one precomputed periodic
  array, and time is kept as (period index, step within period).  The h used is
  reported in ``Trajectory.options["h"]``.
* One step formula.  :func:`make_step` builds the step from a ``clip`` primitive and a
  friction function; with pure-Python ``clip`` it runs on floats (the scalar loop of
  :func:`solve`), with ``np.clip`` on arrays (:func:`solve_batch`).
* Stick skipping.  With v_k = 0 exactly and |y''(t_M)| <= mu_bar(x_k) the step is
  the identity (x_M = x_k, v* = -h y'', |v*| <= h mu_bar gives v_{k+1} = 0), so the
  scalar loop jumps straight to the next step whose |y''(t_M)| exceeds mu_bar: the
  result is bit-for-bit that of stepping through.
* Outcomes.  REST: v = 0 exactly at a position with mu_bar(x) >= max|y''| (the larger
  of the profile's max|y''| and the sampled midpoint values); the scheme then never
  moves again, so this is the state criterion "v = 0 for every later period", and the
  end time is the step at which the stick began.  Periodic motion: when the state at
  a period boundary repeats bit-for-bit the motion is periodic forever (NEVER_STOPS
  with until="rest"); when only v repeats and the whole period provably lies in a
  region of constant mu_bar (uniform surface, x <= x_mu or x >= x_mu + w, using the
  excursion bound dt (|v| + dt max|y''|)) every later period repeats the same
  velocities, so the run fast-forwards whole periods adding n * (net advance) —
  equal to stepping up to the rounding of the position sums — and with
  until="rest" reports NEVER_STOPS when the mass walks away for good.
  Accumulation (Sect. 7.3) cannot be reached by time-stepping (infinitely many ever
  shorter slips): with until="rest" the period-boundary positions in the transition
  region are watched; when their increments shrink (ratio q < 1) so that the
  geometric remainder d q / (1 - q) is <= ``accumulation_tol`` (option read with a
  default of 1e-12, as for the exact solver) and the extrapolated limit is where the
  scheme can stick for good (mu_bar = max|y''(t_M)|), the run ends with ACCUMULATION,
  x_end = the limit, ``info`` limit / contraction / periods, and a message with the
  caveat that this is the scheme's limit (for piecewise-constant profiles it is
  x_stick_min of eq. 41 for every h, as mu_bar(limit) = max|y''|).  Without a decision
  after max_periods the status is HORIZON and the message says that time-stepping
  could not resolve it.
* Dense output is sampled at the steps nearest a uniform grid of
  ``samples_per_period`` points per period (decimated steps, no interpolation);
  friction and mode follow the model (DESIGN) at the sampled state.  There is no
  event log (time-stepping locates no events): ``events`` is None and
  ``stats["events"]`` is 0; ``stats["steps"]`` counts evaluated steps (skipped stick
  steps and fast-forwarded periods are in ``info``).
"""

from __future__ import annotations

import math
import numbers
import time
from bisect import bisect_left
from dataclasses import dataclass

import numpy as np

from ..model.friction import StopZone
from .outcomes import BACKWARD_SLIP, FORWARD_SLIP, STICK, Status, Trajectory

#: Relaxation r of the fixed-point iteration, in units of the friction bound h mu_bar:
#: s <- proj_[-1,1](s + r v_{k+1}(s)) with r = FP_RELAXATION / (h mu_bar).  The map is a
#: contraction with factor |1 - FP_RELAXATION| = 1/2, so stopping when an update
#: changes v_{k+1} by <= fp_tol leaves an error <= fp_tol.  (FP_RELAXATION = 1 would
#: reach the soft threshold in one sweep, i.e. be the exact solution in disguise.)
FP_RELAXATION = 0.5

_ITERATIONS = ("exact", "fixed_point")


# --------------------------------------------------------------------------------------
# The step (shared by the scalar and the batched path)
# --------------------------------------------------------------------------------------

def _clip_float(z, lo, hi):
    """clip for Python floats (np.clip costs ~1 us on a scalar)."""
    return lo if z < lo else (hi if z > hi else z)


def _absmax_array(z):
    return float(np.max(np.abs(z)))


def friction_function(surface, clip=_clip_float):
    """mu_bar as a function of x relative to the reference origin (x_mu for a StopZone).

    Same formula as :meth:`StopZone.coefficient` (eqs. 7-8), built on ``clip`` so it
    works on floats or arrays.
    """
    if not isinstance(surface, StopZone):
        return lambda x_rel: 1.0
    w, rise = surface.w, surface.c_mu - 1.0
    return lambda x_rel: 1.0 + rise * clip(x_rel, 0.0, w) / w


def exact_impulse(clip=_clip_float):
    """Exact solution of v = v* - bound s, s in Sign(v): the soft threshold of v* by bound."""
    def solve(v_free, bound):
        return v_free - clip(v_free, -bound, bound)
    return solve


def fixed_point_impulse(tol, max_iter, tally, clip=_clip_float, absmax=abs):
    """The paper's fixed-point iteration for v = v* - bound s, s in Sign(v).

    Projected iteration on the multiplier s: s <- proj_[-1,1](s + r (v* - bound s)),
    r = FP_RELAXATION / bound, from s = 0; stop when an update changes v by <= ``tol``
    or after ``max_iter`` updates (counted in ``tally``).  The velocity is rebuilt
    from the converged contact status: |s| < 1 means stick, v = 0 exactly;
    |s| = 1 means slip, v = v* - bound s.  Works on floats or (with numpy ``clip``
    and ``absmax``) on arrays.
    """
    def solve(v_free, bound):
        s = 0.0 * v_free
        r = FP_RELAXATION / bound
        for iteration in range(1, max_iter + 1):
            s_new = clip(s + r * (v_free - bound * s), -1.0, 1.0)
            change = absmax(bound * (s_new - s))
            s = s_new
            if change <= tol:
                break
        else:
            tally["unconverged"] += 1
            tally["max_change"] = max(tally["max_change"], change)
        tally["iterations"] += iteration
        return (v_free - bound * s) * (abs(s) >= 1.0)
    return solve


def make_step(h, mu_bar, impulse):
    """The Moreau midpoint step (x_k, v_k, y''(t_M)) -> (x_{k+1}, v_{k+1}) (Sect. 4.1).

    ``h`` may be a float or an array (one step per trajectory); ``mu_bar`` and
    ``impulse`` come from :func:`friction_function` and :func:`exact_impulse` /
    :func:`fixed_point_impulse` built on the same ``clip``.
    """
    half = 0.5 * h

    def step(x, v, acc_mid):
        x_mid = x + half * v
        v_new = impulse(v - h * acc_mid, h * mu_bar(x_mid))
        return x_mid + half * v_new, v_new
    return step


# --------------------------------------------------------------------------------------
# Options and helpers shared with solvers/ivp.py
# --------------------------------------------------------------------------------------

def steps_per_period(dt: float, h) -> tuple[int, float]:
    """N = ceil(dt / h) steps per period and the h = dt / N actually used.

    ``h=None`` means dt / 1000.  Raises ValueError unless 0 < h <= dt and finite.
    """
    if h is None:
        return 1000, dt / 1000
    if isinstance(h, bool) or not isinstance(h, numbers.Real) or not math.isfinite(h) or h <= 0 or h > dt:
        raise ValueError(f"option h (time step) must be a finite number in (0, dt={dt!r}], got {h!r}")
    ratio = dt / h
    n = round(ratio)
    if abs(ratio - n) > 1e-9 * ratio:
        n = math.ceil(ratio)
    return max(int(n), 1), dt / max(int(n), 1)


def _check_fp_options(iteration, fp_tol, fp_max_iter):
    if iteration not in _ITERATIONS:
        raise ValueError(f"option iteration must be one of {list(_ITERATIONS)}, got {iteration!r}")
    if isinstance(fp_tol, bool) or not isinstance(fp_tol, numbers.Real) or not fp_tol > 0 or fp_tol == math.inf:
        raise ValueError(f"option fp_tol must be a finite number > 0, got {fp_tol!r}")
    if isinstance(fp_max_iter, bool) or not isinstance(fp_max_iter, numbers.Integral) or fp_max_iter < 1:
        raise ValueError(f"option fp_max_iter must be an integer >= 1, got {fp_max_iter!r}")


def midpoint_accelerations(profile, phase: float, n: int) -> np.ndarray:
    """y''(t_M) at the N step midpoints of one period starting at phase * dt."""
    h = profile.dt / n
    return np.asarray(profile.acceleration(phase * profile.dt + (np.arange(n) + 0.5) * h), dtype=float)


def reference_origin(scene) -> float:
    """Positions are kept relative to x_mu (StopZone) or x0, so a large x_mu loses nothing."""
    return scene.surface.x_mu if isinstance(scene.surface, StopZone) else scene.x0


def model_modes(v, ydd, mu):
    """Mode codes of the model (DESIGN) at states (v, y'', mu_bar), vectorised.

    Slip in the direction of v; at v = 0 stick iff |y''| <= mu_bar, else slip in
    the direction -sign(y'').
    """
    v, ydd, mu = np.broadcast_arrays(np.asarray(v, float), np.asarray(ydd, float), np.asarray(mu, float))
    at_zero = np.where(np.abs(ydd) <= mu, STICK, np.where(ydd > 0, BACKWARD_SLIP, FORWARD_SLIP))
    return np.where(v > 0, FORWARD_SLIP, np.where(v < 0, BACKWARD_SLIP, at_zero)).astype(np.int8)


def model_series(scene, names, period, tau, x_rel, v, x_ref) -> dict:
    """Dense series ``t`` + ``names`` at times (period, tau) and states (x_rel, v).

    Friction F = -(x'' + y'') (eq. 5): mu_bar * mode in slip, -y'' in stick.
    """
    profile = scene.profile
    period, tau = np.asarray(period, dtype=float), np.asarray(tau, dtype=float)
    x_rel, v = np.asarray(x_rel, dtype=float), np.asarray(v, dtype=float)
    ydd = np.asarray(profile.acceleration(tau), dtype=float)
    mu = friction_function(scene.surface, np.clip)(x_rel) + 0.0 * x_rel
    mode = model_modes(v, ydd, mu)
    out = {"t": period * profile.dt + tau}
    available = {
        "x": lambda: x_ref + x_rel,
        "v": lambda: v,
        "y": lambda: np.asarray(profile.position(tau), dtype=float),
        "yd": lambda: np.asarray(profile.velocity(tau), dtype=float),
        "ydd": lambda: ydd,
        "friction": lambda: np.where(mode == STICK, -ydd, mode * mu),
        "mode": lambda: mode,
    }
    out.update({name: available[name]() for name in names})
    return out


def period_time(scene, period: int, offset: float) -> tuple[int, float]:
    """(period_end, tau_end) of the time phase*dt + period*dt + offset, offset in [0, dt]."""
    dt = scene.profile.dt
    tau = scene.phase * dt + offset
    if tau >= dt:
        return period + 1, tau - dt
    return period, tau


# --------------------------------------------------------------------------------------
# Batched path
# --------------------------------------------------------------------------------------

@dataclass
class BatchResult:
    """End states and states at every period boundary of :func:`solve_batch`.

    ``x_periods[p]``, ``v_periods[p]`` hold the states at time phase*dt + p*dt
    (p = 0..periods); ``h`` is the step used per trajectory, ``steps_per_period``
    the common N.
    """

    x_end: np.ndarray
    v_end: np.ndarray
    x_periods: np.ndarray
    v_periods: np.ndarray
    h: np.ndarray
    steps_per_period: int
    fp_unconverged_steps: int = 0


def solve_batch(profile, surface, x0, v0, periods: int, h=None, phase: float = 0.0, *,
                iteration: str = "exact", fp_tol: float = 1e-14, fp_max_iter: int = 200) -> BatchResult:
    """Advance many trajectories at once with the Moreau step of :func:`make_step` (numpy).

    ``profile`` is one profile or a sequence of profiles (one per trajectory, e.g. the
    sweeps of Figs. 4-5); ``x0``, ``v0`` broadcast against it.  ``h`` (float, array or
    None = dt/1000) is adjusted down so that all trajectories take the same number
    N = max ceil(dt_i / h_i) of steps per period, h_i = dt_i / N.  ``phase`` is the
    fraction of the period at which (x0, v0) hold.  Positions are returned absolute
    but computed relative to x_mu (StopZone) or x0.
    """
    profiles = [profile] if not isinstance(profile, (list, tuple)) else list(profile)
    if not profiles:
        raise ValueError("profile: give a profile or a non-empty sequence of profiles")
    if isinstance(periods, bool) or not isinstance(periods, (int, np.integer)) or periods < 0:
        raise ValueError(f"periods must be an integer >= 0, got {periods!r}")
    if not (isinstance(phase, (int, float)) and 0.0 <= phase < 1.0):
        raise ValueError(f"phase must lie in [0, 1) (fraction of the period), got {phase!r}")
    _check_fp_options(iteration, fp_tol, fp_max_iter)
    dts = np.array([p.dt for p in profiles])
    x0, v0 = (np.asarray(a, dtype=float) for a in (x0, v0))
    shape = np.broadcast_shapes(x0.shape, v0.shape, (len(profiles),) if len(profiles) > 1 else ())
    if len(shape) > 1:
        raise ValueError(f"x0, v0 and profile must broadcast to one dimension, got shape {shape}")
    if not (np.all(np.isfinite(x0)) and np.all(np.isfinite(v0))):
        raise ValueError("x0 and v0 must be finite")
    h_req = np.broadcast_to(np.asarray(dts / 1000 if h is None else h, dtype=float), dts.shape)
    n = max(steps_per_period(float(dt), None if h is None else float(hi))[0] for dt, hi in zip(dts, h_req))
    h_used = dts / n

    acc = np.stack([midpoint_accelerations(p, phase, n) for p in profiles], axis=1)  # (N, profiles)
    x_ref = surface.x_mu if isinstance(surface, StopZone) else x0
    x = np.broadcast_to(x0 - x_ref, shape).astype(float)
    v = np.broadcast_to(v0, shape).astype(float)
    x_ref = np.broadcast_to(x_ref, shape)
    step_h = h_used if len(profiles) > 1 else float(h_used[0])
    acc = acc if len(profiles) > 1 else acc[:, 0]
    tally = {"iterations": 0, "unconverged": 0, "max_change": 0.0}
    impulse = (exact_impulse(np.clip) if iteration == "exact"
               else fixed_point_impulse(fp_tol, fp_max_iter, tally, np.clip, _absmax_array))
    step = make_step(step_h, friction_function(surface, np.clip), impulse)

    xs, vs = [x + x_ref], [v]
    for _ in range(periods):
        for a in acc:
            x, v = step(x, v, a)
        xs.append(x + x_ref)
        vs.append(v)
    return BatchResult(x_end=xs[-1], v_end=vs[-1], x_periods=np.array(xs), v_periods=np.array(vs),
                       h=np.broadcast_to(h_used, shape).copy(), steps_per_period=n,
                       fp_unconverged_steps=tally["unconverged"])


# --------------------------------------------------------------------------------------
# Scalar path: simulate(scene, method="moreau")
# --------------------------------------------------------------------------------------

class _Loop:
    """The scalar stepping loop of one scene: floats, time as (period, step)."""

    def __init__(self, step, acc: np.ndarray, mu_bar, rest_acc: float):
        self.step = step
        self.acc = acc.tolist()
        self.abs_acc = np.abs(acc)
        self.n = acc.size
        self.mu_bar = mu_bar
        self.rest_acc = rest_acc
        self.steps = 0
        self.skipped = 0
        self._candidates_mu = None
        self._candidates = []

    def _next_candidate(self, k: int, mu: float) -> int:
        """First step >= k whose |y''(t_M)| exceeds mu (N if none): stick may end there."""
        if mu != self._candidates_mu:
            self._candidates_mu = mu
            self._candidates = np.flatnonzero(self.abs_acc > mu).tolist()
        i = bisect_left(self._candidates, k)
        return self._candidates[i] if i < len(self._candidates) else self.n

    def advance(self, x: float, v: float, k: int, k_to: int):
        """Steps k..k_to-1 of the current period -> (x, v, k, at_rest)."""
        step, acc = self.step, self.acc
        while k < k_to:
            if v == 0.0:
                mu = self.mu_bar(x)
                if mu >= self.rest_acc:
                    return x, v, k, True
                k_next = self._next_candidate(k, mu)
                if k_next >= k_to:
                    self.skipped += k_to - k
                    return x, v, k_to, False
                self.skipped += k_next - k
                k = k_next
            start = k
            for k in range(start, k_to):
                x, v = step(x, v, acc[k])
                if v == 0.0:
                    break
            k += 1
            self.steps += k - start
        return x, v, k, False


def _validated(scene, options):
    dt = scene.profile.dt
    n, h = steps_per_period(dt, options.get("h"))
    iteration = options.get("iteration", "exact")
    fp_tol, fp_max_iter = options.get("fp_tol", 1e-14), options.get("fp_max_iter", 200)
    _check_fp_options(iteration, fp_tol, fp_max_iter)
    acc_tol = options.get("accumulation_tol", 1e-12)
    if isinstance(acc_tol, bool) or not isinstance(acc_tol, numbers.Real) or not 0 < acc_tol < math.inf:
        raise ValueError(f"option accumulation_tol must be a finite number > 0, got {acc_tol!r}")
    return n, h, iteration, fp_tol, fp_max_iter, acc_tol


def _accumulation(history, tol, surface, mu_bar, sampled_max):
    """Accumulation test on the last three period-boundary positions (relative).

    Increments d1 > 0, d2 >= 0 with ratio q = d2 / d1 < 1 extrapolate to the limit
    x + d2 q / (1 - q); it is an accumulation (Sect. 7.3) when that remaining distance
    is <= ``tol`` and the limit lies in the transition region where the scheme can
    stick for good, mu_bar(limit) = max|y''(t_M)| up to b1 * tol (a periodic motion
    without progress converges too, but to a point where mu_bar is smaller).
    """
    if not isinstance(surface, StopZone) or len(history) < 3:
        return None
    d1, d2 = history[1] - history[0], history[2] - history[1]
    if not (d1 > 0.0 and 0.0 <= d2 < d1):
        return None
    q = d2 / d1
    limit = history[2] + d2 * q / (1.0 - q)
    slack = surface.b1 * (tol + 8 * np.finfo(float).eps * (abs(limit) + surface.w))
    if limit - history[2] > tol or not 0.0 <= limit <= surface.w or abs(mu_bar(limit) - sampled_max) > slack:
        return None
    return {"limit": surface.x_mu + limit, "contraction": q}


def _constant_friction_periods(surface, x_start, dx, excursion):
    """How many more periods a motion repeating with advance dx per period stays where
    mu_bar is constant (inf: for ever; 0: not provably), given that the last period
    started at x_start (relative) and moved at most ``excursion`` away from it."""
    if dx == 0.0 or not isinstance(surface, StopZone):
        return math.inf
    if x_start + excursion <= 0.0:           # below x_mu: mu_bar = 1
        return math.inf if dx < 0.0 else max(0, math.floor((-excursion - x_start) / dx) - 1)
    if x_start - excursion >= surface.w:     # beyond x_mu + w: mu_bar = c_mu
        return math.inf if dx > 0.0 else max(0, math.floor((x_start - excursion - surface.w) / -dx) - 1)
    return 0


def solve(scene, options: dict) -> Trajectory:
    """Simulate ``scene`` with Moreau midpoint time-stepping (see the module docstring)."""
    n, h, iteration, fp_tol, fp_max_iter, acc_tol = _validated(scene, options)
    cpu0 = time.process_time()
    profile, surface = scene.profile, scene.surface
    dt = profile.dt
    acc = midpoint_accelerations(profile, scene.phase, n)
    rest_acc = max(float(profile.max_abs_acceleration), float(np.max(np.abs(acc))))
    mu_bar = friction_function(surface)
    tally = {"iterations": 0, "unconverged": 0, "max_change": 0.0}
    impulse = (exact_impulse() if iteration == "exact"
               else fixed_point_impulse(fp_tol, fp_max_iter, tally))
    loop = _Loop(make_step(h, mu_bar, impulse), acc, mu_bar, rest_acc)

    x_ref = reference_origin(scene)
    x, v = scene.x0 - x_ref, scene.v0
    total = scene.horizon_periods
    until_rest = scene.until == "rest"
    dense = scene.record.dense
    spp = int(scene.record.samples_per_period)
    sample_steps = np.unique(np.minimum(np.round(np.arange(spp) * n / spp).astype(int), n - 1)).tolist()
    targets = (sample_steps if dense else []) + [n]
    samples = []                      # (period, step, x_rel, v)
    ff_periods = 0
    sampled_max = float(np.max(np.abs(acc)))
    status, message, period, k = Status.HORIZON, "", 0, 0
    boundary, history = (x, v), [x]
    info = {"steps_per_period": n, "h_requested": options.get("h")}
    if isinstance(surface, StopZone):
        info["x_stick_min"] = surface.x_stick_min(float(profile.max_abs_acceleration))

    while period < total:
        for target in targets:
            x, v, k, at_rest = loop.advance(x, v, k, target)
            if at_rest:
                break
            if target < n:
                samples.append((period, k, x, v))
        if at_rest:
            if until_rest:
                status = Status.REST
                message = (f"at rest for good: stuck at x = {x_ref + x!r} where mu_bar = {mu_bar(x)!r} "
                           f">= max|y''| = {rest_acc!r}")
                break
            # Stuck for good inside a horizon run: nothing moves any more.
            if dense:
                samples.extend((period, kk, x, 0.0) for kk in sample_steps if kk > k)
                samples.extend((p, kk, x, 0.0) for p in range(period + 1, total) for kk in sample_steps)
            ff_periods += total - period - 1
            period, k = total, 0
            break
        period, k = period + 1, 0
        prev_x, prev_v = boundary
        boundary = (x, v)
        history = history[-2:] + [x]
        if period == total:
            break
        if until_rest:
            found = _accumulation(history, acc_tol, surface, mu_bar, sampled_max)
            if found:
                status, (x, v) = Status.ACCUMULATION, (found["limit"] - x_ref, 0.0)
                info.update(found, periods=period)
                message = (f"accumulation: stick positions converge geometrically "
                           f"(ratio {found['contraction']:.6g}) to x = {found['limit']!r}, remaining distance <= accumulation_tol = {acc_tol!r}; "
                           f"caveat: the limit is that of the time-stepping scheme (the paper's x_stick_min, "
                           f"eq. 41, is {info.get('x_stick_min')!r})")
                break
        if v != prev_v:
            continue
        dx = x - prev_x
        stays = _constant_friction_periods(surface, prev_x, dx, dt * (abs(prev_v) + dt * sampled_max))
        if until_rest and stays == math.inf:
            status = Status.NEVER_STOPS
            message = ("never stops: periodic motion without net progress (the state at the period "
                       "boundary repeats)" if dx == 0.0 else
                       f"never stops: periodic motion in a region of constant friction, "
                       f"net advance {dx!r} per period")
            info["net_advance"] = dx
            break
        more = min(stays, total - period)
        if more > 0:
            # Every later period repeats the last one's velocities: add whole periods.
            if dense:
                last = [s for s in samples if s[0] == period - 1]
                samples.extend((p, kk, xx + (p - period + 1) * dx, vv)
                               for p in range(period, period + more) for (_, kk, xx, vv) in last)
            x = x + more * dx
            period += more
            ff_periods += more
            boundary = (x, v)
            history = [x]

    p_end, tau_end = period_time(scene, period, k * h)
    if status is Status.HORIZON:
        message = f"simulated {period} periods (Moreau, h = {h!r}, {n} steps per period)"
        if until_rest:
            message = (f"not at rest after max_periods = {total} periods; time-stepping cannot resolve an "
                       f"accumulation (Sect. 7.3) nor prove that the motion never stops")
    info.update(skipped_stick_steps=loop.skipped, fast_forward_periods=ff_periods)
    if iteration == "fixed_point":
        info.update(fp_iterations=tally["iterations"], fp_unconverged_steps=tally["unconverged"])
        if tally["unconverged"]:
            message += (f"; WARNING: the fixed-point iteration missed fp_tol = {fp_tol!r} within "
                        f"fp_max_iter = {fp_max_iter} on {tally['unconverged']} steps "
                        f"(largest last change {tally['max_change']!r})")
    series = {}
    if dense:
        if samples and samples[-1][:2] == (period, k):
            samples.pop()                       # the end state replaces a grid sample at the same step
        samples.append((period, k, x, v))
        arr = np.array(samples, dtype=float).reshape(-1, 4)
        offsets = scene.phase * dt + arr[:, 1] * h
        wrap = offsets >= dt
        series = model_series(scene, scene.record.series, arr[:, 0] + wrap, offsets - wrap * dt,
                              arr[:, 2], arr[:, 3], x_ref)
    return Trajectory(
        x_end=float(x_ref + x), v_end=float(v), period_end=int(p_end), tau_end=float(tau_end),
        status=status, message=message, method="moreau", options={**options, "h": h}, series=series,
        events=None, stats={"events": 0, "steps": loop.steps, "cpu_time": time.process_time() - cpu0},
        info=info,
    )
