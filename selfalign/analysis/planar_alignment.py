"""Self-alignment in the plane: where a drifting part stops at a strip of high friction and at the corner of
two strips (docs/explanation/planar-alignment.md; the paper's Sect. 8, recommendation 4, on the stop zone of
Sects. 3.3 and 7).

A :class:`~selfalign.model.planar.Strip` is the paper's stop zone along its unit normal n: mu_bar rises from
1 at n.x = x_mu to c_mu at n.x = x_mu + w (eqs. 7-9).  A part held at rest by the disc of friction stays
at rest for good where mu_bar(x) >= max|Y''| (the planar eq. 40): along n that is the depth
x_stick_min - x_mu = w (max|Y''| - 1) / (c_mu - 1) of eq. (41), whatever the direction of Y''.

* :func:`~selfalign.line_alignment`: entries drifting in steady state onto a strip whose normal makes an angle with the
  drift.  Where along n and along the strip do they stop, and do their normal depths accumulate to
  x_stick_min (Sect. 7.3)?  The spread Delta x_d of eq. (39) is taken along n and along the strip.
* :func:`~selfalign.corner_alignment`: entries from a band across the drift onto a corner of two strips (friction the
  larger of the two): do they all end at one point?

The entries follow Sect. 7.1: each starts in the steady motion (the period-boundary velocity of
:func:`~selfalign.analysis.planar_drift.steady_drift` at phase 0), ``distance`` plus a fraction s in [0, 1)
of one period's advance ``|v_bar|`` dt behind the strip's edge along the drift (every way of entering), and
at a lateral offset along the strip (a band of entry lines).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.errors import check_finite, check_integer, check_positive
from ..model.planar import PlanarProfile, Strip
from ..model.scene import Scene
from ..solvers.driver import simulate
from ..solvers.outcomes import Reason
from .planar_drift import SteadyDrift, _check_method, _check_profile, steady_drift

#: A part counts as at x_stick_min (accumulated) within this many body widths along n.
AT_LIMIT_WIDTHS = 1e-6
#: A steady drift slower than this counts as none (velocity units of Sect. 3.2): the steady state is declared
#: when the period-boundary velocity repeats within 1e-10, and a symmetric orbit's v_bar keeps that order.
MIN_DRIFT = 1e-8


def _rotate(vector: np.ndarray, angle: float) -> np.ndarray:
    """``vector`` turned by ``angle`` and normalised to unit length."""
    c, s = math.cos(angle), math.sin(angle)
    turned = np.array([c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]])
    return turned / np.hypot(*turned)


def strip_at(direction, angle: float, *, x_mu: float, w: float, c_mu: float) -> Strip:
    """The strip whose unit normal is ``direction`` turned by ``angle`` (radians, counter-clockwise).

    Parameters
    ----------
    direction : array_like
        A vector (2,), e.g. the drift v_bar; not zero.
    angle : float
        Angle between ``direction`` and the normal.
    x_mu, w, c_mu : float
        The strip's edge n.x = x_mu, width and friction ratio (:class:`~selfalign.model.planar.Strip`).

    Returns
    -------
    Strip

    Raises
    ------
    TypeError
        If a number is not real.
    ValueError
        If ``direction`` is zero or not finite, or as Strip.

    Examples
    --------
    >>> import math
    >>> from selfalign.analysis.planar_alignment import strip_at
    >>> [round(v, 12) for v in strip_at([2.0, 0.0], math.pi / 2, x_mu=0.0, w=0.05, c_mu=2.5).normal]
    [0.0, 1.0]
    """
    direction = np.asarray(direction, dtype=float)
    if direction.shape != (2,) or not np.all(np.isfinite(direction)) or not np.any(direction):
        raise ValueError(f"direction must be a finite non-zero vector (2,), got {direction!r}")
    return Strip(normal=tuple(_rotate(direction, check_finite("angle", angle)).tolist()), x_mu=x_mu, w=w, c_mu=c_mu)


def _axis(name: str, values, low: float, high: float) -> np.ndarray:
    values = np.asarray(values, dtype=float)
    if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values)):
        raise ValueError(f"{name} must be a non-empty 1-D array of finite numbers, got {values!r}")
    if np.any(values < low) or np.any(values > high):
        raise ValueError(f"{name} must lie in [{low:g}, {high:g}], got {values!r}")
    return values


def stick_depth(max_acceleration: float, w: float, c_mu: float) -> float:
    """x_stick_min - x_mu along a strip's normal (eq. 41): w (max|Y''| - 1) / (c_mu - 1), the depth from
    which the disc of friction holds the part for good.

    Parameters
    ----------
    max_acceleration : float
        max|Y''| of the table motion; 1 < it <= c_mu.
    w, c_mu : float
        The strip's width (the body width) and friction ratio; w > 0, c_mu > 1.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If a number is not real.
    ValueError
        Unless w > 0 and 1 < max_acceleration <= c_mu.

    Examples
    --------
    >>> from selfalign.analysis.planar_alignment import stick_depth
    >>> round(stick_depth(2.2, 0.05, 2.5), 12)
    0.04
    """
    a, w, c_mu = check_finite("max_acceleration", max_acceleration), check_positive("w", w), check_finite("c_mu", c_mu)
    if not 1.0 < a <= c_mu:
        raise ValueError(f"a strip can stop a drifting part only for 1 < max|Y''| <= c_mu (eq. 41), got max|Y''| = "
                         f"{a!r}, c_mu = {c_mu!r}")
    return w * (a - 1.0) / (c_mu - 1.0)


@dataclass(frozen=True)
class Entries:
    """End states of a set of entries onto a surface of strips (``line_alignment``, ``corner_alignment``).

    Attributes
    ----------
    start : numpy.ndarray
        Start positions, (k, 2).
    x_end : numpy.ndarray
        End positions, (k, 2).
    reason : numpy.ndarray
        :class:`~selfalign.Reason` code of each run, (k,).
    stopped : numpy.ndarray
        The part came to rest or accumulated within ``AT_LIMIT_WIDTHS`` w of x_stick_min, (k,).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.analysis.planar_alignment import Entries
    >>> e = Entries(np.zeros((2, 2)), np.array([[0.0, 0.1], [0.0, 0.3]]), np.array([4, 4]), np.ones(2, bool))
    >>> e.spread().round(6).tolist()
    [0.0, 0.1]
    """

    start: np.ndarray
    x_end: np.ndarray
    reason: np.ndarray
    stopped: np.ndarray

    def spread(self, axes=None) -> np.ndarray:
        """Delta x_d of eq. (39) along each axis: half the range of the end positions of the entries that
        stop, projected on the rows of ``axes`` (default the x and y axes); NaN where none stops."""
        axes = np.eye(2) if axes is None else np.asarray(axes, float)
        ends = self.x_end[self.stopped] @ axes.T
        if not ends.size:
            return np.full(axes.shape[0], np.nan)
        return (ends.max(axis=0) - ends.min(axis=0)) / 2.0


def _entries(profile, drift: SteadyDrift, surface, starts, method, max_periods, solver_options, limit):
    """Run every start with the steady velocity at phase 0 until rest; ``limit(x)`` says whether an end
    position lies at x_stick_min of the strips."""
    ends, reasons, stopped = np.zeros_like(starts), np.zeros(len(starts), np.int64), np.zeros(len(starts), bool)
    for i, start in enumerate(starts):
        run = simulate(Scene(profile, surface=surface, x0=tuple(start), v0=tuple(drift.v_start), until="rest",
                             max_periods=max_periods, method=method, solver_options=dict(solver_options or {})))
        if not run.success:
            raise RuntimeError(f"the {method} solver stopped on the entry from {tuple(start)}: {run.message}")
        ends[i], reasons[i] = run.x_end, int(run.reason)
        stopped[i] = Reason(run.reason) in (Reason.REST, Reason.ACCUMULATION) or limit(ends[i])
    return Entries(np.asarray(starts, float), ends, reasons, stopped)


@dataclass(frozen=True)
class LineAlignment:
    """Entries onto one strip at each angle between the drift and the strip's normal (``line_alignment``).

    :func:`~selfalign.line_alignment` builds it; its constructor checks nothing.  Row i holds the k entries onto the
    strip at ``angles[i]``, in the order of ``entry_starts``.  The properties ``dx_d_normal``,
    ``dx_d_along`` and ``dx_d_slide`` give the spreads (half ranges, as Delta x_d of eq. 39) of the entries
    that stop, and ``at_limit`` the fraction of the entries accumulated at x_stick_min (Sect. 7.3).

    Parameters
    ----------
    angles : numpy.ndarray
        The angles (Attributes).
    normals : numpy.ndarray
        The strip's normals (Attributes).
    drift : SteadyDrift
        The steady drift (Attributes).
    depth, along, lateral : numpy.ndarray
        The end positions relative to the strip (Attributes).
    stopped, reason : numpy.ndarray
        The outcome of every entry (Attributes).
    start, x_end : numpy.ndarray
        Start and end positions (Attributes).
    stick_depth : float
        x_stick_min - x_mu (Attributes).
    x_mu, w, c_mu : float
        The strip (Attributes).

    Attributes
    ----------
    angles : numpy.ndarray
        Angle between the drift direction and the strip's normal (radians), (m,).
    normals : numpy.ndarray
        The strip's unit normal at each angle, (m, 2).
    drift : SteadyDrift
        The steady drift on the uniform surface.
    depth : numpy.ndarray
        n.x_end - x_mu of every entry, (m, k).
    along : numpy.ndarray
        t.x_end - lateral of every entry, t the strip's direction (n turned by +90 degrees): how far along
        the strip the part ends from the point where its drift line meets the strip's edge, (m, k).  A
        motion along the drift alone ends at -depth tan(angle) from it.
    lateral : numpy.ndarray
        t.p of the point p where the entry's drift line (through its start along v_bar) meets the strip's
        edge n.x = x_mu, (m, k).
    stopped : numpy.ndarray
        The part came to rest or accumulated within ``AT_LIMIT_WIDTHS`` w of x_stick_min, (m, k).
    reason : numpy.ndarray
        :class:`~selfalign.Reason` code of each run, (m, k).
    start : numpy.ndarray
        Start positions, (m, k, 2).
    x_end : numpy.ndarray
        End positions, (m, k, 2).
    stick_depth : float
        x_stick_min - x_mu of eq. (41).
    x_mu : float
        The strip's edge n.x = x_mu.
    w : float
        The strip's width (the body width, eq. 7).
    c_mu : float
        The strip's friction ratio.
    dx_d_normal : numpy.ndarray
        Delta x_d (eq. 39) along n at each angle, over the entries that stop, (m,).
    dx_d_along : numpy.ndarray
        Delta x_d along the strip at each angle: half the range of t.x_end over the entries that stop, (m,).
    dx_d_slide : numpy.ndarray
        Half the range of ``along`` over the entries that stop, (m,).
    at_limit : numpy.ndarray
        Fraction of the entries whose depth is x_stick_min within ``AT_LIMIT_WIDTHS`` w (accumulated), (m,).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.analysis.planar_alignment import LineAlignment
    >>> z = np.zeros((1, 2))
    >>> a = LineAlignment(np.zeros(1), np.array([[1.0, 0.0]]), None, np.array([[0.04, 0.05]]), z, z,
    ...                   np.ones((1, 2), bool), np.full((1, 2), 4), np.zeros((1, 2, 2)), np.zeros((1, 2, 2)),
    ...                   0.04, 0.0, 0.05, 2.5)
    >>> a.dx_d_normal.round(6).tolist(), a.at_limit.tolist()
    ([0.005], [0.5])
    """

    angles: np.ndarray
    normals: np.ndarray
    drift: SteadyDrift
    depth: np.ndarray
    along: np.ndarray
    lateral: np.ndarray
    stopped: np.ndarray
    reason: np.ndarray
    start: np.ndarray
    x_end: np.ndarray
    stick_depth: float
    x_mu: float
    w: float
    c_mu: float

    def _half_range(self, values) -> np.ndarray:
        out = np.full(self.angles.size, np.nan)
        for i, (row, stopped) in enumerate(zip(values, self.stopped)):
            if stopped.any():
                out[i] = (row[stopped].max() - row[stopped].min()) / 2.0
        return out

    @property
    def dx_d_normal(self) -> np.ndarray:
        """Delta x_d (eq. 39) along n at each angle, over the entries that stop, (m,)."""
        return self._half_range(self.depth)

    @property
    def dx_d_along(self) -> np.ndarray:
        """The positioning error along the strip at each angle, half the range of t.x_end over the stopped entries."""
        return self._half_range(np.einsum("mkj,mj->mk", self.x_end, np.stack([-self.normals[:, 1],
                                                                                self.normals[:, 0]], axis=1)))

    @property
    def dx_d_slide(self) -> np.ndarray:
        """Half the range of ``along`` over the entries that stop, (m,): the spread along the strip that the
        dynamics adds to that of the entry lines (0 for a motion along the drift alone)."""
        return self._half_range(self.along)

    @property
    def at_limit(self) -> np.ndarray:
        """Fraction of the entries whose depth is x_stick_min within ``AT_LIMIT_WIDTHS`` w (accumulated), (m,)."""
        return np.mean(np.abs(self.depth - self.stick_depth) <= AT_LIMIT_WIDTHS * self.w, axis=1)


def entry_starts(direction: np.ndarray, normal: np.ndarray, advance: float, *, distance: float, offsets,
                 lateral) -> np.ndarray:
    """Start positions of entries onto the strip n.x >= 0: ``distance`` + s ``advance`` behind the strip's edge
    along ``direction`` (the drift), shifted by each lateral offset along the strip t = (-n_y, n_x).

    Parameters
    ----------
    direction, normal : array_like
        Unit vectors (2,) of the drift and of the strip's normal, with direction.normal > 0.
    advance : float
        One period's advance ``|v_bar|`` dt; > 0.
    distance : float
        Distance behind the edge along the drift; > 0.
    offsets : array_like
        The fractions s in [0, 1) of one period's advance.
    lateral : array_like
        Offsets along the strip.

    Returns
    -------
    numpy.ndarray
        (len(lateral) * len(offsets), 2), the lateral offset varying slowest.

    Raises
    ------
    ValueError
        If the drift does not point into the strip, or an axis is empty or out of range.

    Examples
    --------
    >>> from selfalign.analysis.planar_alignment import entry_starts
    >>> entry_starts([1.0, 0.0], [1.0, 0.0], 0.1, distance=0.2, offsets=[0.0, 0.5], lateral=[0.0]).tolist()
    [[-0.2, 0.0], [-0.25, 0.0]]
    """
    direction, normal = np.asarray(direction, float), np.asarray(normal, float)
    cos = float(direction @ normal)
    if cos <= 0.0:
        raise ValueError(f"the drift must point into the strip (direction . normal > 0), got {cos!r}")
    advance, distance = check_positive("advance", advance), check_positive("distance", distance)
    offsets = _axis("offsets", offsets, 0.0, 1.0)
    lateral = _axis("lateral", lateral, -np.inf, np.inf)
    tangent = np.array([-normal[1], normal[0]])
    back = (distance + offsets * advance)[None, :, None] * direction
    return (lateral[:, None, None] * tangent - back).reshape(-1, 2)


def line_alignment(profile: PlanarProfile, *, w: float, c_mu: float, angles, distance: float, offsets, lateral,
                   x_mu: float = 0.0, method: str = "exact", max_periods: int = 2000,
                   solver_options: dict | None = None) -> LineAlignment:
    """Entries in steady drift onto one strip whose normal makes each of ``angles`` with the drift.

    The strip's normal is the drift direction turned by the angle; each entry starts as
    ``entry_starts`` with the steady velocity at phase 0 and runs until rest (at most ``max_periods``).

    Parameters
    ----------
    profile : PlanarProfile
        The table motion; it must drift (v_bar != 0) and 1 < max|Y''| <= c_mu.
    w, c_mu : float
        Strip width (the body width, eq. 7) and friction ratio.
    angles : array_like
        Angles between the drift and the normal in radians, in [0, 1.5] (the drift must reach the strip).
    distance : float
        Start distance behind the strip's edge along the drift; > 0.
    offsets : array_like
        Fractions s in [0, 1) of one period's advance ``|v_bar|`` dt added to ``distance``.
    lateral : array_like
        Offsets of the entry lines along the strip.
    x_mu : float, optional
        The strip's edge n.x = x_mu.  Default 0.
    method : str, optional
        "exact" (default), "moreau" or "ivp".
    max_periods : int, optional
        Horizon of each entry.  Default 2000.
    solver_options : dict, optional
        Options of ``method``.

    Returns
    -------
    LineAlignment
        The end of every entry at every angle (depth along n, position along the strip, outcome), the steady
        drift and x_stick_min - x_mu of eq. (41).

    Raises
    ------
    TypeError
        If ``profile`` is not a PlanarProfile or a number is not real.
    ValueError
        If the profile does not drift or cannot be stopped (max|Y''| outside (1, c_mu]), or an axis is out
        of range.
    RuntimeError
        If a run ends with an error of the solver.

    Examples
    --------
    The Fig. 18 motion along x onto a strip at 30 degrees: every entry accumulates to x_stick_min along n:

    >>> import math
    >>> import selfalign as sa
    >>> from selfalign.model.planar import PlanarProfile
    >>> from selfalign.analysis.planar_alignment import line_alignment
    >>> fig18 = PlanarProfile(x=sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9))
    >>> a = line_alignment(fig18, w=0.05, c_mu=2.5, angles=[math.radians(30)], distance=0.1, offsets=[0.0, 0.5],
    ...                    lateral=[0.0])
    >>> a.at_limit.tolist(), round(a.stick_depth, 6)
    ([1.0], 0.04)
    """
    profile = _check_profile(profile)
    method = _check_method(method)
    depth_min = stick_depth(profile.max_abs_acceleration, w, c_mu)
    x_mu = check_finite("x_mu", x_mu)
    max_periods = check_integer("max_periods", max_periods)
    angles = _axis("angles", angles, 0.0, 1.5)
    drift = steady_drift(profile, method=method, solver_options=solver_options)
    if drift.speed <= MIN_DRIFT:
        raise ValueError(f"the table motion does not drift (|v_bar| = {drift.speed:.3g}): no entry reaches a strip")
    direction = drift.v_bar / drift.speed
    normals, runs = [], []
    for angle in angles:
        strip = strip_at(direction, float(angle), x_mu=x_mu, w=w, c_mu=c_mu)
        normal = np.array(strip.normal)
        starts = entry_starts(direction, normal, drift.speed * profile.dt, distance=distance, offsets=offsets,
                              lateral=lateral) + x_mu * normal
        runs.append(_entries(profile, drift, strip, starts, method, max_periods, solver_options,
                             lambda x, n=normal: abs(n @ x - x_mu - depth_min) <= AT_LIMIT_WIDTHS * w))
        normals.append(normal)
    normals = np.array(normals)
    tangents = np.stack([-normals[:, 1], normals[:, 0]], axis=1)
    x_end = np.array([r.x_end for r in runs])
    start = np.array([r.start for r in runs])
    # Where each start's drift line meets the edge: start + lam direction with n.(...) = x_mu.
    lam = (x_mu - np.einsum("mkj,mj->mk", start, normals)) / (normals @ direction)[:, None]
    lateral = np.einsum("mkj,mj->mk", start + lam[..., None] * direction, tangents)
    return LineAlignment(
        angles=angles, normals=normals, drift=drift, depth=np.einsum("mkj,mj->mk", x_end, normals) - x_mu,
        along=np.einsum("mkj,mj->mk", x_end, tangents) - lateral, lateral=lateral,
        stopped=np.array([r.stopped for r in runs]), reason=np.array([r.reason for r in runs]), start=start,
        x_end=x_end, stick_depth=depth_min, x_mu=x_mu, w=float(w), c_mu=float(c_mu))


@dataclass(frozen=True)
class CornerAlignment:
    """Entries onto the corner of two strips (:func:`~selfalign.corner_alignment`).

    :func:`~selfalign.corner_alignment` builds it; its constructor checks nothing.  Each part ends where one of the
    strips holds it (``first``); the entries end at one point only if they all reach ``corner``, and
    ``spread_radius`` measures how far the stopped entries end from it.

    Parameters
    ----------
    strips : tuple of Strip
        The two strips (Attributes).
    corner : numpy.ndarray
        The corner point (Attributes).
    entries : selfalign.analysis.planar_alignment.Entries
        Start and end states (Attributes).
    first : numpy.ndarray
        The strip that holds each part (Attributes).
    distance_to_corner : numpy.ndarray
        Distance of each end from the corner (Attributes).
    stick_depth : float
        x_stick_min - x_mu (Attributes).

    Attributes
    ----------
    strips : tuple of Strip
        The two strips; their edges meet at the origin.
    corner : numpy.ndarray
        The point where both strips' x_stick_min lines meet, (2,): the one point every entry would have to
        reach.
    entries : selfalign.analysis.planar_alignment.Entries
        Start and end states.
    first : numpy.ndarray
        Index of the strip each part ends deepest in (the one that holds it), (k,).
    distance_to_corner : numpy.ndarray
        ``|x_end - corner|`` of every entry, (k,).
    stick_depth : float
        x_stick_min - x_mu of eq. (41) of each strip.
    spread_radius : float
        The largest distance of a stopped entry's end from the corner point (NaN if none stops).

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.analysis.planar_alignment import CornerAlignment, Entries
    >>> e = Entries(np.zeros((1, 2)), np.array([[0.04, 0.3]]), np.array([4]), np.ones(1, bool))
    >>> c = CornerAlignment((), np.array([0.04, 0.0]), e, np.array([0]), np.array([0.3]), 0.04)
    >>> c.spread_radius
    0.3
    """

    strips: tuple
    corner: np.ndarray
    entries: Entries
    first: np.ndarray
    distance_to_corner: np.ndarray
    stick_depth: float

    @property
    def spread_radius(self) -> float:
        """The largest distance of a stopped entry's end from the corner point (NaN if none stops)."""
        d = self.distance_to_corner[self.entries.stopped]
        return float(d.max()) if d.size else math.nan


def corner_alignment(profile: PlanarProfile, *, w: float, c_mu: float, half_angle: float, distance: float, offsets,
                     lateral, method: str = "exact", max_periods: int = 2000,
                     solver_options: dict | None = None) -> CornerAlignment:
    """Entries in steady drift onto the corner of two strips whose normals make +-``half_angle`` with the drift.

    The strips' edges pass through the origin; the low-friction region in front of them is the wedge
    n1.x < 0 and n2.x < 0 with its apex at the origin, pointing along the drift.  mu_bar is the larger of the
    two strips' coefficients.  The entries start ``distance`` (+ s ``|v_bar|`` dt) behind the apex along the drift,
    at lateral offsets across it.

    Parameters
    ----------
    profile : PlanarProfile
        The table motion; it must drift and 1 < max|Y''| <= c_mu.
    w, c_mu : float
        Width and friction ratio of both strips.
    half_angle : float
        Angle between the drift and each normal, radians in (0, 1.5].
    distance : float
        Start distance behind the apex; > 0.
    offsets : array_like
        Fractions s in [0, 1) of one period's advance.
    lateral : array_like
        Offsets across the drift.
    method : str, optional
        "exact" (default), "moreau" or "ivp".
    max_periods : int, optional
        Horizon of each entry.  Default 2000.
    solver_options : dict, optional
        Options of ``method``.

    Returns
    -------
    CornerAlignment
        The two strips, the point where their x_stick_min lines meet, the end of every entry, the strip
        that holds it and its distance from that point.

    Raises
    ------
    TypeError
        If ``profile`` is not a PlanarProfile or a number is not real.
    ValueError
        As :func:`~selfalign.line_alignment`, or ``half_angle`` outside (0, 1.5].
    RuntimeError
        If a run ends with an error of the solver.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.model.planar import PlanarProfile
    >>> from selfalign.analysis.planar_alignment import corner_alignment
    >>> fig18 = PlanarProfile(x=sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9))
    >>> c = corner_alignment(fig18, w=0.05, c_mu=2.5, half_angle=0.6, distance=0.1, offsets=[0.0],
    ...                      lateral=[-0.1, 0.1])
    >>> c.first.tolist(), bool(c.spread_radius > 0.1)
    ([1, 0], True)
    """
    profile = _check_profile(profile)
    method = _check_method(method)
    depth_min = stick_depth(profile.max_abs_acceleration, w, c_mu)
    max_periods = check_integer("max_periods", max_periods)
    half_angle = check_finite("half_angle", half_angle)
    if not 0.0 < half_angle <= 1.5:
        raise ValueError(f"half_angle must lie in (0, 1.5] radians, got {half_angle!r}")
    drift = steady_drift(profile, method=method, solver_options=solver_options)
    if drift.speed <= MIN_DRIFT:
        raise ValueError(f"the table motion does not drift (|v_bar| = {drift.speed:.3g}): no entry reaches the "
                         "corner")
    direction = drift.v_bar / drift.speed
    strips = tuple(strip_at(direction, a, x_mu=0.0, w=w, c_mu=c_mu) for a in (half_angle, -half_angle))
    normals = np.array([s.normal for s in strips])
    # The lines n_i.x = depth_min meet where both hold: solve the 2 x 2 system.
    corner = np.linalg.solve(normals, np.full(2, depth_min))
    starts = entry_starts(direction, direction, drift.speed * profile.dt, distance=distance, offsets=offsets,
                          lateral=lateral)
    entries = _entries(profile, drift, list(strips), starts, method, max_periods, solver_options,
                       lambda x: bool(np.any(np.abs(normals @ x - depth_min) <= AT_LIMIT_WIDTHS * w)))
    depths = entries.x_end @ normals.T
    return CornerAlignment(strips, corner, entries, np.argmax(depths, axis=1),
                           np.hypot(*(entries.x_end - corner).T), depth_min)
