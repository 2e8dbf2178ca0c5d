"""Moreau midpoint time-stepping (``method="moreau"``, Sect. 4.1, eqs. 6, 38).

One step of size h from (x_k, v_k) at time t_k (unit mass, dimensionless):

    x_M     = x_k + h/2 v_k                                        (midpoint)
    v_{k+1} = v_k - (y'(t_k + h) - y'(t_k)) - h mu_bar(x_M) s,  s in Sign(v_{k+1})
    x_{k+1} = x_M + h/2 v_{k+1}

The table's impulse over the step, y'(t_k + h) - y'(t_k) = int y'' dt, is integrated
exactly (closed form for every profile), so no phase of the profile is missed however
short it is, and the table velocity the mass sees is periodic: the scheme is first order
in h with an error constant that does not grow with the horizon beyond the motion's own
sensitivity.  (Sampling y'' at the step midpoints instead, as an earlier version did,
misses phases shorter than h and leaves a net table impulse of up to h |jump| per
period, so the mass drifts like N^2 h max|y''| over N periods; docs/explanation/solvers.md.)

The implicit friction equation has the exact one-dimensional solution
(``iteration="exact"``) v_{k+1} = v* - clip(v*, -h mu_bar, h mu_bar) with
v* = v_k - impulse, a soft threshold; ``iteration="fixed_point"`` solves it the way
the paper does, by a projected fixed-point iteration on the friction multiplier.

The step is adjusted down to h = dt / N (:func:`steps_per_period`),
so every period holds exactly N steps from the start phase; their impulses are one
precomputed periodic array (the profile row, :func:`profile_row`).  While v = 0 the
step is the identity as long as |impulse| <= h mu_bar (v* lies in the stick window),
so the kernel jumps to the next step that can start a slip, bit for bit the result of
stepping through.  Outcomes are those of every method (the driver,
:mod:`selfalign.solvers.engine.timestepping`): REST is v = 0 where the scheme can stick for good,
h mu_bar >= max |impulse|, i.e. mu_bar >= max|impulse| / h (the scheme's own
max|y''|); an ACCUMULATION ends at the scheme's limit, x_stick_min of eq. (41) for that
acceleration.  Dense output is the state at the steps nearest a uniform grid of
``samples_per_period`` points per period; there is no event log.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from . import records as R

#: Most Moreau steps per period: the table impulses of one period are kept in memory
#: (8 bytes each), and more steps than this would take hours per period anyway.
MAX_STEPS_PER_PERIOD = 10_000_000

#: Least fraction of the table's velocity swing (max y' - min y') that the velocities at the step
#: times must span (:func:`profile_row`).
MIN_SWING_SEEN = 0.5


def table_impulses(profile, phase: float, n: int, h: float) -> np.ndarray:
    """The table's impulse y'(t_k + h) - y'(t_k) = int y'' dt of each of the N steps of one
    period from t_0 = phase dt, in closed form.

    Piecewise-constant y'': a y'' h for a step inside one piece (one rounding, so a tie
    |y''| = mu_bar stays a tie in the step's test) and the sum of y'' times the overlap for
    the few steps across a break; smooth profiles: the difference of y' (closed form).
    """
    t = phase * profile.dt + np.arange(n + 1) * h
    if not profile.piecewise_constant:
        yd = np.asarray(profile.velocity(t), dtype=float)
        yd[-1] = yd[0]                   # y' is periodic: the period's impulses telescope to 0
        return np.diff(yd)
    dt, breaks, accels = profile.dt, profile.breaks, profile.accels
    lo, hi = t[:-1], t[1:]
    first = profile.piece_index(np.mod(lo, dt))
    impulse = accels[first] * h
    # Steps that reach past the end of their first piece (or past the period end).
    end_of_first = np.floor(lo / dt) * dt + breaks[first + 1]
    m = accels.size
    for k in np.flatnonzero(hi > end_of_first).tolist():
        period, i = float(np.floor(lo[k] / dt)), int(first[k])
        total, a = 0.0, float(lo[k])
        while a < hi[k]:                 # piece i of the period starting at period * dt
            b = min(float(hi[k]), period * dt + float(breaks[i + 1]))
            total += float(accels[i]) * (b - a)
            a = b
            i += 1
            if i == m:
                i, period = 0, period + 1
        impulse[k] = total
    return impulse


def steps_per_period(dt: float, h) -> tuple[int, float]:
    """N = ceil(dt / h) Moreau steps per period (a ratio within 1e-9 of an integer counts
    as that integer) and the step h = dt / N used; ``h=None`` means dt / 1000.

    ValueError unless 0 < h <= dt and N <= :data:`MAX_STEPS_PER_PERIOD`.
    """
    if h is None:
        return 1000, dt / 1000
    if not (isinstance(h, numbers.Real) and not isinstance(h, bool) and math.isfinite(h) and 0 < h <= dt):
        raise ValueError(f"option h (time step) must be a finite number in (0, dt = {dt!r}], got {h!r}")
    ratio = dt / h
    n = round(ratio)
    if abs(ratio - n) > 1e-9 * ratio:
        n = math.ceil(ratio)
    n = max(int(n), 1)
    if n > MAX_STEPS_PER_PERIOD:
        raise ValueError(f"option h = {h!r} needs {n:.3g} Moreau steps per period; at most "
                         f"{MAX_STEPS_PER_PERIOD:,} are allowed (the table impulses of one period are kept in "
                         f"memory, {8 * n / 1e9:.2g} GB here)")
    return n, dt / n


def moreau_step(dt: float, options: dict) -> tuple[int, float]:
    """(N, h) of the Moreau options ``h`` or ``steps_per_period`` for a period ``dt``."""
    if options.get("steps_per_period") is not None:
        if options.get("h") is not None:
            raise ValueError("options h and steps_per_period exclude each other; give one")
        return steps_per_period(dt, dt / options["steps_per_period"])
    return steps_per_period(dt, options.get("h"))


def profile_row(profile, phase: float, options: dict) -> np.ndarray:
    """The Moreau profile row: N, h (options ``h`` or ``steps_per_period``), the largest
    |impulse| and the exact table impulse of each step of one period from the start phase
    (module docstring).  The rest acceleration in the header is largest / h; whether the
    scheme holds a stuck mass is decided as the step decides it, h mu_bar >= largest.
    ValueError if the N steps cannot resolve the table motion (:func:`check_swing_seen`)."""
    n, h = moreau_step(profile.dt, options)
    impulse = table_impulses(profile, phase, n, h)
    check_swing_seen(profile, n, impulse)
    largest = float(np.max(np.abs(impulse)))
    head = R.profile_header(profile.dt, profile.max_abs_acceleration, profile.velocity_swing, largest / h)
    return R.moreau_row(head, h, impulse)


def check_swing_seen(profile, n: int, impulse: np.ndarray) -> None:
    """ValueError unless the table velocities at the N step times of a period span at least
    :data:`MIN_SWING_SEEN` of the table's velocity swing.

    Why: the scheme sees the table only through the impulses y'(t_k + h) - y'(t_k), i.e. through
    y' at the step times (however short a phase between them is, its impulse is exact).  Steps
    that see less than half the swing simulate another, slower table; at h = dt every impulse is 0
    and the scheme reports "at rest for good" at the start position.  The share seen depends on
    the start phase; for the workflow's profiles 10 steps per period see at least 0.58 of it.
    """
    seen = float(np.ptp(np.concatenate([[0.0], np.cumsum(impulse[:-1])])))
    swing = profile.velocity_swing
    if not seen >= MIN_SWING_SEEN * swing:
        raise ValueError(f"option h = dt / {n:,} is too coarse for {profile!r}: the table velocities at the step "
                         f"times span {seen:.6g}, a share {seen / swing:.3f} of its velocity swing {swing:.6g} (at "
                         f"least {MIN_SWING_SEEN:g} needed), so Moreau would simulate a slower table (h = dt: a "
                         f"table at rest); take more steps per period")


def sample_steps(steps: int, samples_per_period: int) -> np.ndarray:
    """The steps (0 .. N-1) nearest a uniform grid of ``samples_per_period`` points per period."""
    return np.unique(np.minimum(np.round(np.arange(samples_per_period) * steps / samples_per_period),
                                steps - 1)).astype(np.int64)
