"""The drift of a part under a planar table motion: its steady mean velocity vector and its limits
(docs/explanation/planar-alignment.md; the paper's Sect. 8, recommendation 4, on the objective of Sect. 4.3).

A point part on a table moving as Y(t) in the plane (:class:`~selfalign.model.planar.PlanarProfile`)
on a uniform surface: x'' = -Y''(t) - Sign2(x'), Sign2(v) = v/|v| for v != 0 and the unit disc at v = 0
(dimensionless, Sect. 3.2).  Its steady motion repeats the relative velocity from period to period
(the uniqueness argument of Sect. 6.2 carries over: V = |v1 - v2|^2 / 2 never grows, because the disc's
Sign2 is monotone) and advances by v_bar dt per period: v_bar is the planar objective of eq. (10).

* :func:`~selfalign.steady_drift` runs from rest until the period-boundary velocity repeats to a tolerance and
  returns v_bar = (x(t + dt) - x(t)) / dt over that period, and the periods it took;
* :func:`high_acceleration_drift` is the limit of large accelerations: the geometric median of the
  table's velocities Y'(t) over a period, the c that minimises ``<|c - Y'(t)|>`` (the derivation is in the
  docs page: friction changes the part's absolute velocity by at most dt per period, the table's by
  order max|Y''| dt, so the part moves at a nearly constant c, and periodicity asks
  <(c - Y')/|c - Y'|> = 0, the gradient of <|c - Y'|>);
* :func:`acceleration_limit` measures how v_bar approaches that limit as the table motion is scaled up;
* :func:`~selfalign.drift_map` maps v_bar over a phase offset and an amplitude of a family of table motions;
  :func:`three_phase_pair` and :func:`harmonic_orbit` are the two families of the planar stage.

Below max|Y''| <= 1 a part at rest never slips (the disc holds it): v_bar = 0 exactly.  A motion with
Y(t + dt/2) = -Y(t) (one harmonic: every ellipse, every straight line orbit) never drifts: the motion
shifted by half a period is the mirrored one, and the steady velocity is unique, so v_bar = -v_bar.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..model.errors import check_choice, check_finite, check_integer, check_positive
from ..model.planar import PlanarProfile
from ..model.profiles import FourierProfile, ThreePhaseProfile
from ..model.scene import METHODS, Record, Scene
from ..solvers.driver import simulate

#: Periods of the first run of :func:`~selfalign.steady_drift`; each further run doubles the periods simulated.
FIRST_PERIODS = 8
#: Time samples per period of :func:`high_acceleration_drift` (midpoints).  Where the velocities spread over the
#: plane the median moves smoothly with the samples; along one line it is the midpoint of the two middle samples
#: (5e-6 from the limit of many samples for the Fig. 18 profile), far below the asymptotic error it is compared
#: with (of order 1 in velocity).
MEDIAN_SAMPLES = 8192
#: Iterations of the geometric-median iteration (each halves the error at least once the points are spread).
MEDIAN_ITERATIONS = 2000


def _check_profile(profile) -> PlanarProfile:
    if not isinstance(profile, PlanarProfile):
        raise TypeError(f"profile must be a PlanarProfile, got {type(profile).__name__}")
    return profile


@dataclass(frozen=True)
class SteadyDrift:
    """The steady motion of a part under a planar table motion (:func:`~selfalign.steady_drift`).

    :func:`~selfalign.steady_drift` builds it; its constructor checks nothing.  The steady motion repeats the relative
    velocity from period to period and advances by ``v_bar`` dt per period (eq. 10 in the plane);
    ``speed`` and ``direction`` give v_bar in polar form.

    Parameters
    ----------
    v_bar : numpy.ndarray
        The mean velocity vector (Attributes).
    v_start : numpy.ndarray
        The relative velocity at the start of the steady period (Attributes).
    periods : int
        Periods simulated (Attributes).
    converged : bool
        Whether the steady state was reached (Attributes).
    residual : float
        The last change of the period-boundary velocity (Attributes).

    Attributes
    ----------
    v_bar : numpy.ndarray
        The mean velocity vector (2,) of the steady motion: the displacement over one steady period / dt.
    v_start : numpy.ndarray
        The relative velocity (2,) at the start of the steady period (phase 0 of the table motion).
    periods : int
        Periods simulated from rest until the period-boundary velocity repeated within the tolerance.
    converged : bool
        False if ``max_periods`` passed first (``v_bar`` is then that of the last period).
    residual : float
        ``|x'(t + dt) - x'(t)|`` over the last period, at the period boundaries.
    speed : float
        ``|v_bar|``.
    direction : float
        The angle of v_bar from the x axis in radians, in (-pi, pi] (0 for v_bar = 0).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.analysis.planar_drift import SteadyDrift
    >>> d = SteadyDrift(np.array([0.03, 0.04]), np.zeros(2), 3, True, 0.0)
    >>> d.speed, round(d.direction, 6)
    (0.05, 0.927295)
    """

    v_bar: np.ndarray
    v_start: np.ndarray
    periods: int
    converged: bool
    residual: float

    @property
    def speed(self) -> float:
        """``|v_bar|``."""
        return float(np.hypot(*self.v_bar))

    @property
    def direction(self) -> float:
        """The angle of v_bar from the x axis in radians, in (-pi, pi] (0 for v_bar = 0)."""
        return float(math.atan2(self.v_bar[1], self.v_bar[0]))


def _check_method(method) -> str:
    return check_choice("method", method, METHODS)


def steady_drift(profile: PlanarProfile, *, method: str = "exact", tol: float = 1e-10, max_periods: int = 20_000,
                 solver_options: dict | None = None) -> SteadyDrift:
    """The steady mean velocity vector v_bar of a part under a planar table motion on a uniform surface.

    The part starts at rest at phase 0; the runs are simulated in blocks (8 periods, then twice as many
    each time, each block from the last one's end state) with the period-boundary states recorded, until
    the boundary velocity repeats: ``|x'((k + 1) dt) - x'(k dt)|`` <= ``tol``.  Then
    v_bar = (x((k + 1) dt) - x(k dt)) / dt (eq. 10 in the plane) and ``periods`` = k + 1.

    Parameters
    ----------
    profile : PlanarProfile
        The table motion Y(t).
    method : str, optional
        "exact" (default), "moreau" or "ivp" (:func:`~selfalign.simulate`).
    tol : float, optional
        Largest change of the period-boundary velocity that counts as steady (velocity units of Sect.
        3.2); > 0.  Default 1e-10.
    max_periods : int, optional
        At most this many periods; >= 1.  Default 20,000.
    solver_options : dict, optional
        Options of ``method`` (e.g. ``{"steps_per_period": 4000}`` for Moreau).

    Returns
    -------
    SteadyDrift
        v_bar, the relative velocity at phase 0 of the steady period, the periods simulated, whether the
        steady state was reached within ``max_periods`` and the last change of the boundary velocity.

    Raises
    ------
    TypeError
        If ``profile`` is not a PlanarProfile, ``method`` is not a string or a number is not real.
    ValueError
        If ``method`` is unknown, ``tol`` <= 0 or ``max_periods`` < 1.
    RuntimeError
        If a run ends with an error of the solver (its message is kept): no number comes from a broken run.

    Examples
    --------
    The Fig. 18 profile along x: the 1-D steady state of Sect. 5.1 (case 1, vbar = 0.0623):

    >>> import selfalign as sa
    >>> from selfalign.model.planar import PlanarProfile
    >>> from selfalign.analysis.planar_drift import steady_drift
    >>> drift = steady_drift(PlanarProfile(x=sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)))
    >>> drift.v_bar.round(6).tolist(), drift.converged
    ([0.062297, 0.0], True)
    """
    profile = _check_profile(profile)
    method = _check_method(method)
    tol = check_positive("tol", tol)
    max_periods = check_integer("max_periods", max_periods)
    if solver_options is not None and not isinstance(solver_options, dict):
        raise TypeError(f"solver_options must be a dict of the method's options, got {type(solver_options).__name__}")
    x, v = np.zeros(2), np.zeros(2)
    done, block = 0, FIRST_PERIODS
    while True:
        block = min(block, max_periods - done)
        scene = Scene(profile, x0=tuple(x), v0=tuple(v), periods=block, method=method,
                      solver_options=dict(solver_options or {}), record=Record(series=("x", "v"), samples_per_period=2))
        run = simulate(scene)
        if not run.success:
            raise RuntimeError(f"steady_drift: the {method} solver stopped after {done} periods: {run.message}")
        xs, vs = np.asarray(run.series["x"], float)[::2], np.asarray(run.series["v"], float)[::2]
        change = np.hypot(*np.diff(vs, axis=0).T)
        steady = np.flatnonzero(change <= tol)
        k = int(steady[0]) if steady.size else change.size - 1
        if steady.size or done + block >= max_periods:
            return SteadyDrift(v_bar=(xs[k + 1] - xs[k]) / profile.dt, v_start=vs[k].copy(), periods=done + k + 1,
                               converged=bool(steady.size), residual=float(change[k]))
        done += block
        x, v = xs[-1], vs[-1]
        block *= 2


def _geometric_median(points: np.ndarray, weights: np.ndarray, tol: float) -> np.ndarray:
    """The c minimising sum_i w_i |c - p_i| (weights summing to 1): Weiszfeld's iteration with the step of
    Vardi & Zhang (PNAS 97, 2000, 1423-1426) at a point that carries weight, which converges to the median
    also when it is one of the points (a stick: equal velocities of a dwell of the table)."""
    points, index = np.unique(points, axis=0, return_inverse=True)
    weights = np.bincount(index.ravel(), weights=weights, minlength=points.shape[0])
    c = weights @ points
    scale = float(np.max(np.abs(points))) or 1.0
    _, spread, axes = np.linalg.svd(points - c, full_matrices=False)
    if spread.size < 2 or spread[1] <= 1e-12 * max(spread[0], 1e-300):
        # On one line the median is the weighted median along it (Weiszfeld's iteration crawls there).
        along = (points - c) @ axes[0]
        order = np.argsort(along, kind="stable")
        below = np.cumsum(weights[order])
        half = min(int(np.searchsorted(below, 0.5)), order.size - 1)
        # Where exactly half the weight lies on each side, every point between the two middle ones is a
        # median: the midpoint is the sampled continuous median to second order.
        tie = half + 1 < order.size and abs(below[half] - 0.5) <= 1e-12
        middle = 0.5 * (along[order][half] + along[order][half + 1]) if tie else along[order][half]
        return c + middle * axes[0]
    for _ in range(MEDIAN_ITERATIONS):
        d = np.hypot(*(points - c).T)
        on = d <= 1e-15 * scale
        q = np.where(on, 0.0, weights / np.where(on, 1.0, d))
        if not q.any():
            return c
        pull = q @ points / q.sum()
        resultant = float(np.hypot(*(q @ (points - c))))
        held = float(weights[on].sum())
        gamma = min(1.0, held / resultant) if held > 0.0 and resultant > 0.0 else 0.0
        new = (1.0 - gamma) * pull + gamma * c
        if np.hypot(*(new - c)) <= tol * scale:
            return new
        c = new
    return c


def high_acceleration_drift(profile: PlanarProfile, *, samples: int = MEDIAN_SAMPLES, tol: float = 1e-13) -> np.ndarray:
    """The limit of v_bar at large table accelerations: the geometric median of Y'(t) over a period.

    For max|Y''| >> 1 friction is a small perturbation: the part's absolute velocity stays within dt of a
    constant c (friction changes it at rate 1), and its periodicity asks ``<(c - Y'(t)) / |c - Y'(t)|>`` = 0,
    the gradient of ``<|c - Y'(t)|>``: c is its minimiser, the geometric (time-weighted L1) median of the table's
    velocities.  For a profile scaled by lambda, v_bar = lambda c_1 + O(1): the relative error falls as
    1 / max|Y''| (docs/explanation/planar-alignment.md).  A velocity the table keeps for at least half of
    the period (a dwell of both components) is the median: the part then sticks in the dwell.

    Parameters
    ----------
    profile : PlanarProfile
        The table motion.
    samples : int, optional
        Midpoint samples of Y' per period; >= 16.  Default 8192.
    tol : float, optional
        Relative step at which the median iteration stops; > 0.  Default 1e-13.

    Returns
    -------
    numpy.ndarray
        c, shape (2,).

    Raises
    ------
    TypeError
        If ``profile`` is not a PlanarProfile or a number is not real.
    ValueError
        If ``samples`` < 16 or ``tol`` <= 0.

    Examples
    --------
    A circle never drifts; along x the Fig. 18 profile's limit is the median of y'(t):

    >>> import selfalign as sa
    >>> from selfalign.model.planar import PlanarProfile
    >>> from selfalign.analysis.planar_drift import high_acceleration_drift
    >>> circle = PlanarProfile(x=sa.FourierProfile(1.0, [0.1], [0.0]), y=sa.FourierProfile(1.0, [0.0], [0.1]))
    >>> bool(abs(high_acceleration_drift(circle)).max() < 1e-12)
    True
    >>> fig18 = PlanarProfile(x=sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9))
    >>> high_acceleration_drift(fig18).round(5).tolist()
    [0.00775, 0.0]
    """
    profile = _check_profile(profile)
    samples = check_integer("samples", samples, low=16)
    tol = check_positive("tol", tol)
    t = (np.arange(samples) + 0.5) * (profile.dt / samples)
    velocity = np.asarray(profile.velocity(t), float)
    return _geometric_median(velocity, np.full(samples, 1.0 / samples), tol)


@dataclass(frozen=True)
class AccelerationLimit:
    """v_bar against the high-acceleration limit for one table motion scaled up (:func:`acceleration_limit`).

    Attributes
    ----------
    max_acceleration : numpy.ndarray
        max|Y''| of each profile, shape (n,).
    v_bar : numpy.ndarray
        The simulated steady v_bar, (n, 2).
    v_limit : numpy.ndarray
        The limit :func:`high_acceleration_drift`, (n, 2).
    error : numpy.ndarray
        ``|v_bar - v_limit|`` over max|Y'(t)| (the table's peak speed), (n,).
    slope, constant : float
        The least-squares fit error = constant * max_acceleration**slope (the asymptotic order says slope = -1).
    periods : numpy.ndarray
        Periods to the steady state of each profile, (n,).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.analysis.planar_drift import AccelerationLimit
    >>> a = np.array([10.0, 100.0])
    >>> fit = AccelerationLimit(a, np.zeros((2, 2)), np.zeros((2, 2)), 0.5 / a, -1.0, 0.5, np.array([3, 3]))
    >>> fit.slope
    -1.0
    """

    max_acceleration: np.ndarray
    v_bar: np.ndarray
    v_limit: np.ndarray
    error: np.ndarray
    slope: float
    constant: float
    periods: np.ndarray


def power_fit(x, y) -> tuple[float, float]:
    """(slope, constant) of the least-squares line log y = log constant + slope log x (x, y > 0).

    Parameters
    ----------
    x, y : array_like
        At least two positive numbers each, of equal length.

    Returns
    -------
    tuple of float
        The exponent and the factor of y ~ constant * x**slope.

    Raises
    ------
    ValueError
        If the arrays differ in length, hold fewer than two points or a number <= 0.

    Examples
    --------
    >>> from selfalign.analysis.planar_drift import power_fit
    >>> [round(v, 9) for v in power_fit([1.0, 10.0, 100.0], [2.0, 0.2, 0.02])]
    [-1.0, 2.0]
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.shape != y.shape or x.ndim != 1 or x.size < 2 or not (np.all(x > 0) and np.all(y > 0)):
        raise ValueError("power_fit needs two 1-D arrays of equal length >= 2 of numbers > 0")
    slope, intercept = np.polyfit(np.log(x), np.log(y), 1)
    return float(slope), float(np.exp(intercept))


def acceleration_limit(profiles, *, method: str = "exact", tol: float = 1e-10, max_periods: int = 20_000,
                       solver_options: dict | None = None) -> AccelerationLimit:
    """How the steady v_bar of a table motion approaches :func:`high_acceleration_drift` as it is scaled up.

    Parameters
    ----------
    profiles : sequence of PlanarProfile
        The same motion at growing amplitude (at least two), e.g. :func:`three_phase_pair` with growing
        ``scale``.
    method, tol, max_periods, solver_options
        As :func:`~selfalign.steady_drift`.

    Returns
    -------
    AccelerationLimit
        The error ``|v_bar - c|`` / max|Y'| against max|Y''| and its power-law fit (slope -1 by the
        derivation: the error of the limit is of order 1 in velocity while the table's speed grows).

    Raises
    ------
    TypeError
        If a profile is not a PlanarProfile.
    ValueError
        If fewer than two profiles are given, or a limit is met exactly (a zero error has no power law),
        or as :func:`~selfalign.steady_drift`.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.analysis.planar_drift import acceleration_limit, three_phase_pair
    >>> pairs = [three_phase_pair(1.0, 0.064, 3.0, 1.5, ratio=0.5, offset=0.3, scale=s) for s in (8.0, 16.0)]
    >>> fit = acceleration_limit(pairs)
    >>> bool(-1.3 < fit.slope < -0.7)
    True
    """
    profiles = [_check_profile(p) for p in profiles]
    if len(profiles) < 2:
        raise ValueError(f"acceleration_limit needs at least two profiles, got {len(profiles)}")
    drifts = [steady_drift(p, method=method, tol=tol, max_periods=max_periods, solver_options=solver_options)
              for p in profiles]
    limits = np.array([high_acceleration_drift(p) for p in profiles])
    v_bar = np.array([d.v_bar for d in drifts])
    peak = np.array([p.max_abs_acceleration for p in profiles])
    speed = np.array([np.max(np.hypot(*np.asarray(p.velocity(np.linspace(0.0, p.dt, 2049)), float).T))
                      for p in profiles])
    error = np.hypot(*(v_bar - limits).T) / speed
    slope, constant = power_fit(peak, error)
    return AccelerationLimit(peak, v_bar, limits, error, slope, constant, np.array([d.periods for d in drifts]))


def three_phase_pair(dt: float, dy: float, y2: float, y3: float, *, ratio: float, offset: float,
                     scale: float = 1.0) -> PlanarProfile:
    """Two three-phase profiles of one shape (Sect. 4.4.3), along x and y, the y one ``ratio`` times as large
    and lagging by ``offset`` periods, all scaled by ``scale``.

    Y(t) = scale (P(t), ratio P(t - offset dt)), P = ThreePhaseProfile(dt, dy, y2, y3); ``scale`` and
    ``ratio`` multiply dy, y2'' and y3'' together, which keeps the shape (the switch times depend on
    their ratios only).  At ``offset`` = 0 the motion is a line at atan(ratio) with the 1-D profile
    sqrt(1 + ratio^2) scale P.

    Parameters
    ----------
    dt, dy, y2, y3 : float
        The three-phase profile (:class:`~selfalign.ThreePhaseProfile`).
    ratio : float
        Amplitude of the y motion over that of the x motion; >= 0 (0: the x motion alone).
    offset : float
        Lag of the y motion in periods, in [0, 1).
    scale : float, optional
        Factor on both; > 0.  Default 1.

    Returns
    -------
    PlanarProfile

    Raises
    ------
    TypeError
        If a number is not real.
    ValueError
        If ``ratio`` < 0, ``scale`` <= 0, ``offset`` is outside [0, 1), or as ThreePhaseProfile.

    Examples
    --------
    >>> from selfalign.analysis.planar_drift import three_phase_pair
    >>> pair = three_phase_pair(1.05, 0.084, 2.2, 0.9, ratio=0.5, offset=0.25)
    >>> pair.acceleration(0.3).round(6).tolist()
    [-2.2, 0.0]
    """
    ratio, scale = check_finite("ratio", ratio), check_positive("scale", scale)
    offset = check_finite("offset", offset)
    if ratio < 0.0:
        raise ValueError(f"ratio must be >= 0 (the y amplitude over the x one), got {ratio!r}")
    if not 0.0 <= offset < 1.0:
        raise ValueError(f"offset must lie in [0, 1) (the lag of the y motion in periods), got {offset!r}")
    x = ThreePhaseProfile(dt, scale * dy, scale * y2, scale * y3)
    y = ThreePhaseProfile(dt, ratio * scale * dy, ratio * scale * y2, ratio * scale * y3) if ratio > 0 else None
    return PlanarProfile(x, y, offset=offset if y is not None else 0.0)


def harmonic_orbit(dt: float, a: float, b: float, *, offset: float = 0.25, second: float = 0.0,
                   angle: float = 0.0) -> PlanarProfile:
    """A harmonic table orbit: X = a (sin wt + second sin 2wt), Y = b sin(w (t - offset dt)), w = 2 pi / dt,
    rotated by ``angle``.

    ``second`` = 0 gives the ellipses (``offset`` = 0.25: (a sin wt, -b cos wt), a circle for a = b) and,
    with b = 0 or ``offset`` = 0, straight line orbits; these never drift (Y(t + dt/2) = -Y(t)).  A second
    harmonic (the sawtooth-like motion of vibratory feeders) breaks that symmetry.

    Parameters
    ----------
    dt : float
        Period; > 0.
    a, b : float
        Amplitudes of the x and y motion; a > 0, b >= 0.
    offset : float, optional
        Lag of the y motion in periods, in [0, 1).  Default 0.25.
    second : float, optional
        Amplitude of the second harmonic of the x motion relative to a; finite.  Default 0.
    angle : float, optional
        Rotation of the orbit in radians.  Default 0.

    Returns
    -------
    PlanarProfile

    Raises
    ------
    TypeError
        If a number is not real.
    ValueError
        If ``dt`` or ``a`` is not > 0, ``b`` < 0, ``offset`` is outside [0, 1) or a number is not finite.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.analysis.planar_drift import harmonic_orbit
    >>> circle = harmonic_orbit(1.0, 0.1, 0.1)
    >>> np.hypot(*circle.position(np.array([0.0, 0.1, 0.3])).T).round(12).tolist()
    [0.1, 0.1, 0.1]
    """
    dt, a = check_positive("dt", dt), check_positive("a", a)
    b, offset = check_finite("b", b), check_finite("offset", offset)
    second, angle = check_finite("second", second), check_finite("angle", angle)
    if b < 0.0:
        raise ValueError(f"b must be >= 0 (the y amplitude), got {b!r}")
    if not 0.0 <= offset < 1.0:
        raise ValueError(f"offset must lie in [0, 1) (the lag of the y motion in periods), got {offset!r}")
    x = FourierProfile(dt, [0.0, 0.0], [a, a * second]) if second else FourierProfile(dt, [0.0], [a])
    y = FourierProfile(dt, [0.0], [b]) if b > 0.0 else None
    return PlanarProfile(x, y, offset=offset if y is not None else 0.0, angle=angle)


@dataclass(frozen=True)
class DriftMap:
    """v_bar over a phase offset and an amplitude of a family of table motions (:func:`~selfalign.drift_map`).

    :func:`~selfalign.drift_map` builds it; its constructor checks nothing.  Row i, column j holds the steady drift
    (:func:`~selfalign.steady_drift`) of the motion at ``offsets[i]`` and ``amplitudes[j]``; ``speed`` and ``direction``
    give v_bar in polar form.

    Parameters
    ----------
    offsets : numpy.ndarray
        The phase offsets (Attributes).
    amplitudes : numpy.ndarray
        The amplitudes (Attributes).
    v_bar : numpy.ndarray
        The mean velocity vectors (Attributes).
    periods : numpy.ndarray
        Periods to the steady state (Attributes).
    converged : numpy.ndarray
        Whether the steady state was reached (Attributes).
    max_acceleration : numpy.ndarray
        max|Y''| of each motion (Attributes).

    Attributes
    ----------
    offsets : numpy.ndarray
        The phase offsets of the y motion (periods), (p,).
    amplitudes : numpy.ndarray
        The amplitudes, (a,).
    v_bar : numpy.ndarray
        Steady mean velocity vector of each pair, (p, a, 2).
    periods : numpy.ndarray
        Periods to the steady state, (p, a).
    converged : numpy.ndarray
        The steady state was reached, (p, a).
    max_acceleration : numpy.ndarray
        max|Y''| of each motion, (p, a).
    speed : numpy.ndarray
        ``|v_bar|``, (p, a).
    direction : numpy.ndarray
        Angle of v_bar from the x axis in radians, (p, a).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.analysis.planar_drift import DriftMap
    >>> m = DriftMap(np.array([0.0]), np.array([1.0]), np.array([[[0.0, 2.0]]]), np.ones((1, 1), int),
    ...              np.ones((1, 1), bool), np.ones((1, 1)))
    >>> m.speed.tolist(), m.direction.round(6).tolist()
    ([[2.0]], [[1.570796]])
    """

    offsets: np.ndarray
    amplitudes: np.ndarray
    v_bar: np.ndarray
    periods: np.ndarray
    converged: np.ndarray
    max_acceleration: np.ndarray

    @property
    def speed(self) -> np.ndarray:
        """``|v_bar|``, (p, a)."""
        return np.hypot(self.v_bar[..., 0], self.v_bar[..., 1])

    @property
    def direction(self) -> np.ndarray:
        """Angle of v_bar from the x axis in radians, (p, a)."""
        return np.arctan2(self.v_bar[..., 1], self.v_bar[..., 0])


def drift_map(family: Callable[[float, float], PlanarProfile], offsets, amplitudes, *, method: str = "exact",
              tol: float = 1e-10, max_periods: int = 20_000, solver_options: dict | None = None) -> DriftMap:
    """The steady v_bar of ``family(offset, amplitude)`` over a grid of phase offsets and amplitudes.

    Each motion of the grid runs :func:`~selfalign.steady_drift` from rest, one after the other; the map holds its
    v_bar, the periods it took, whether it converged and the motion's largest table acceleration.

    Parameters
    ----------
    family : callable
        (offset, amplitude) -> PlanarProfile, e.g.
        ``lambda p, r: three_phase_pair(1.05, 0.084, 2.2, 0.9, ratio=r, offset=p)``.
    offsets, amplitudes : array_like
        The grid axes, 1-D and finite.
    method : str, optional
        "exact" (default), "moreau" or "ivp", as :func:`~selfalign.steady_drift`.
    tol : float, optional
        Steady-state tolerance of :func:`~selfalign.steady_drift`; > 0.  Default 1e-10.
    max_periods : int, optional
        At most this many periods per motion; >= 1.  Default 20,000.
    solver_options : dict, optional
        Options of ``method``.

    Returns
    -------
    DriftMap
        v_bar, periods, convergence and max|Y''| over the grid, shaped (len(offsets), len(amplitudes)).

    Raises
    ------
    TypeError
        If ``family`` is not callable or does not return a PlanarProfile, or as :func:`~selfalign.steady_drift`.
    ValueError
        If an axis is empty, not 1-D or not finite, or as :func:`~selfalign.steady_drift`.
    RuntimeError
        If a run ends with an error of the solver, as :func:`~selfalign.steady_drift`.

    Examples
    --------
    >>> from selfalign.analysis.planar_drift import drift_map, three_phase_pair
    >>> m = drift_map(lambda p, r: three_phase_pair(1.05, 0.084, 2.2, 0.9, ratio=r, offset=p), [0.0], [0.0, 1.0])
    >>> m.speed.round(6).tolist()
    [[0.062297, 0.104206]]
    """
    if not callable(family):
        raise TypeError(f"family must be a callable (offset, amplitude) -> PlanarProfile, got {type(family).__name__}")
    axes = []
    for name, values in (("offsets", offsets), ("amplitudes", amplitudes)):
        values = np.asarray(values, dtype=float)
        if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values)):
            raise ValueError(f"{name} must be a non-empty 1-D array of finite numbers, got {values!r}")
        axes.append(values)
    offsets, amplitudes = axes
    shape = (offsets.size, amplitudes.size)
    v_bar, periods = np.zeros(shape + (2,)), np.zeros(shape, np.int64)
    converged, peak = np.zeros(shape, bool), np.zeros(shape)
    for i, p in enumerate(offsets):
        for j, r in enumerate(amplitudes):
            profile = _check_profile(family(float(p), float(r)))
            d = steady_drift(profile, method=method, tol=tol, max_periods=max_periods, solver_options=solver_options)
            v_bar[i, j], periods[i, j], converged[i, j] = d.v_bar, d.periods, d.converged
            peak[i, j] = profile.max_abs_acceleration
    return DriftMap(offsets, amplitudes, v_bar, periods, converged, peak)
