"""Planar motion: a table that moves in the plane, and strips of high friction (the paper's Sect. 8,
recommendation 4; docs/explanation/planar-model.md).

A point part (no rotation) has relative position x in R^2 and velocity v = x'; the table's
displacement Y(t) in R^2 is periodic.  Isotropic Coulomb friction bounds the friction force by
the disc of radius mu_bar(x) (the scale of Sect. 3.2):

    x'' = -Y''(t) + f,   f in -mu_bar(x) Sign2(x'),   Sign2(v) = v / |v| (v != 0), the unit disc (v = 0).

The part sticks while ``|Y''(t)| <= r mu_bar(x)`` (r = mu_s / mu_k, 1 under Coulomb friction) and
otherwise slides against its relative velocity with mu_bar(x).

* :class:`PlanarProfile`: Y(t) = R(angle) (P_x(t), P_y(t - offset dt)), two profiles of the 1-D model of
  one period, the second lagging by ``offset`` periods, turned by ``angle``.
* :class:`Strip`: the paper's stop zone (eqs. 7-9) along a unit normal n: friction 1 where n.x <= x_mu,
  c_mu where n.x >= x_mu + w, linear between (the part's extent along n is the body width w).
  Several strips combine by the largest coefficient (:func:`planar_coefficient`).
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .errors import check_finite, check_real
from .friction import StopZone, coefficient
from .profiles import PiecewiseConstantProfile, PiecewiseLinearProfile, Profile
from .registry import formula

#: Largest deviation of a strip normal's length from 1 that is accepted (and normalised away).
NORMAL_TOL = 1e-12
#: Largest relative difference of the periods of a planar profile's two components.
PERIOD_TOL = 1e-12
#: Columns of a strip row (:func:`strip_rows`): the normal, the zone's start, width and coefficient.
STRIP_NX, STRIP_NY, STRIP_XMU, STRIP_W, STRIP_CMU = range(5)
STRIP_COLUMNS = 5
#: Samples per period of the grid on which the largest |Y''| of a smooth component is bracketed before it
#: is refined by golden-section search (:attr:`PlanarProfile.max_abs_acceleration`).
MAX_GRID = 4096


@formula(unnumbered="the rotation of the plane by an angle theta, R = [[cos, -sin], [sin, cos]] "
                    "(docs/explanation/planar-model.md)", kernel=False)
def rotation(theta: float) -> np.ndarray:
    """The 2 x 2 matrix that turns a vector of the plane by ``theta`` radians (counter-clockwise)."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def _vector(name: str, value) -> tuple[float, float]:
    """``value`` as a tuple of two finite floats: TypeError unless it is a pair of real numbers,
    ValueError unless both are finite."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise TypeError(f"{name} must be a pair of real numbers (x, y), got {value!r}")
    return check_finite(f"{name}[0]", value[0]), check_finite(f"{name}[1]", value[1])


class Strip:
    """A strip of high friction on the table: the paper's stop zone (eqs. 7-9) along a unit normal.

    The coefficient at the part's position x is that of a stop zone at the distance n.x along the
    normal n: 1 where n.x <= x_mu, rising linearly over the body width w to c_mu at n.x = x_mu + w,
    and c_mu beyond (the half-plane n.x >= x_mu + w has high friction).  With n = (1, 0) it is the
    1-D :class:`~selfalign.StopZone` along the first axis.

    Parameters
    ----------
    normal : tuple of float
        The unit normal n = (nx, ny), pointing into the high friction; its length must be 1 to
        1e-12 (``NORMAL_TOL``); it is stored normalised.
    x_mu : float
        Where the transition starts, as a distance along n from the origin; as for ``StopZone``.
    w : float
        Width of the transition, the part's extent along n; > 0.
    c_mu : float
        Coefficient of the high friction, in units of mu; >= 1.

    Attributes
    ----------
    normal : tuple of float
        The unit normal (nx, ny).
    x_mu : float
        Where the transition starts, along n.
    w : float
        The transition width.
    c_mu : float
        The high coefficient.
    zone : StopZone
        The 1-D stop zone along the normal.
    kind : str
        ``"strip"``, the surface kind of scene files.

    Raises
    ------
    TypeError
        If ``normal`` is not a pair of real numbers, or ``x_mu``, ``w`` or ``c_mu`` is not a real number.
    ValueError
        If a number is not finite, the normal is zero or not of length 1 (to 1e-12), ``w`` <= 0,
        ``c_mu`` < 1, or ``|x_mu| > 2**32 w`` (as for ``StopZone``).

    See Also
    --------
    StopZone : The 1-D stop zone.
    PlanarProfile : The table motion in the plane.

    Examples
    --------
    >>> import selfalign as sa
    >>> strip = sa.Strip(normal=(0.6, 0.8), x_mu=0.5, w=0.05, c_mu=2.5)
    >>> strip.coefficient([[0.0, 0.0], [0.315, 0.42], [0.36, 0.48]]).round(6).tolist()
    [1.0, 1.75, 2.5]
    >>> sa.Strip(normal=(1.0, 1.0), x_mu=0.5, w=0.05, c_mu=2.5)
    Traceback (most recent call last):
    ...
    ValueError: normal must be a unit vector (length 1 to 1e-12), got (1.0, 1.0) of length 1.41421...
    """

    kind = "strip"

    def __init__(self, normal, x_mu: float, w: float, c_mu: float):
        nx, ny = _vector("normal", normal)
        length = math.hypot(nx, ny)
        if not abs(length - 1.0) <= NORMAL_TOL:
            raise ValueError(f"normal must be a unit vector (length 1 to {NORMAL_TOL:g}), got {(nx, ny)!r} of length "
                             f"{length!r}" + (" (a zero normal has no direction)" if length == 0.0 else ""))
        self.normal = (nx / length, ny / length) if length != 1.0 else (nx, ny)
        self.zone = StopZone(x_mu, w, c_mu)
        self.x_mu, self.w, self.c_mu = self.zone.x_mu, self.zone.w, self.zone.c_mu

    def distance(self, x) -> np.ndarray:
        """n.x for positions ``x`` of shape (..., 2)."""
        x = np.asarray(x, dtype=float)
        return x[..., 0] * self.normal[0] + x[..., 1] * self.normal[1]

    def coefficient(self, x) -> np.ndarray:
        """mu_bar of this strip at positions ``x`` of shape (..., 2) (eqs. 7-9 along the normal)."""
        return self.zone.coefficient(self.distance(x))

    def rotated(self, theta: float) -> "Strip":
        """The strip turned about the origin by ``theta`` radians."""
        n = rotation(check_finite("theta", theta)) @ np.array(self.normal)
        return Strip((float(n[0]), float(n[1])), self.x_mu, self.w, self.c_mu)

    def params(self) -> dict:
        return {"kind": self.kind, "normal": list(self.normal), "x_mu": self.x_mu, "w": self.w, "c_mu": self.c_mu}

    def __repr__(self):
        return f"Strip(normal={self.normal!r}, x_mu={self.x_mu!r}, w={self.w!r}, c_mu={self.c_mu!r})"

    def __eq__(self, other):
        return isinstance(other, Strip) and self.params() == other.params()

    def __hash__(self):
        return hash((self.kind, self.normal, self.x_mu, self.w, self.c_mu))


def check_strips(surface) -> tuple[Strip, ...]:
    """The strips of a planar surface: ``Uniform()`` (none), one :class:`Strip`, or a non-empty list or tuple of
    them.  TypeError naming ``surface`` otherwise."""
    from .friction import Uniform

    if isinstance(surface, Uniform):
        return ()
    if isinstance(surface, Strip):
        return (surface,)
    if isinstance(surface, (list, tuple)) and surface and all(isinstance(s, Strip) for s in surface):
        return tuple(surface)
    raise TypeError(f"surface of a planar scene must be Uniform(), a Strip or a non-empty list of Strips, got "
                    f"{surface!r:.80}")


def strip_rows(strips) -> np.ndarray:
    """The strips as a float array of shape (K, 5), columns (nx, ny, x_mu, w, c_mu) (:data:`STRIP_NX`, ...), the
    form the compiled solvers read; K = 0 is a uniform surface."""
    rows = np.zeros((len(strips), STRIP_COLUMNS))
    for i, strip in enumerate(strips):
        rows[i] = (*strip.normal, strip.x_mu, strip.w, strip.c_mu)
    return rows


@formula(unnumbered="eqs. 7-9 along the normal of each strip, the largest of them (1 on a uniform surface): "
                    "docs/explanation/planar-model.md")
def planar_coefficient(px: float, py: float, rows) -> float:
    """mu_bar at the position (px, py) on the strips ``rows`` (:func:`strip_rows`): the largest of the
    strips' coefficients, eqs. (7)-(9) at xi = n.x - x_mu; 1 without strips."""
    mu = 1.0
    for k in range(rows.shape[0]):
        xi = rows[k, STRIP_NX] * px + rows[k, STRIP_NY] * py - rows[k, STRIP_XMU]
        mu = max(mu, coefficient(xi, rows[k, STRIP_W], rows[k, STRIP_CMU]))
    return mu


def _piece_values(profile: Profile, start: float, end: float) -> tuple[float, float]:
    """y'' of a piecewise-polynomial ``profile`` at both ends of [start, end] (within one of its pieces, a
    subinterval of [0, dt]), as the limits from inside: y'' is affine there."""
    i = int(np.clip(np.searchsorted(profile.breaks, 0.5 * (start + end), side="right") - 1, 0,
                    profile.accels.size - 1))
    if isinstance(profile, PiecewiseConstantProfile):
        return float(profile.accels[i]), float(profile.accels[i])
    a, e, j = profile.accels[i], profile.ends[i], profile.jerks[i]
    low, high = min(a, e), max(a, e)
    return tuple(float(min(max(a + j * (t - profile.breaks[i]), low), high)) for t in (start, end))


class PlanarProfile:
    """The motion of a table in the plane: two periodic profiles of one period, one per axis.

    Y(t) = R(angle) (P_x(t), P_y(t - offset dt)): the y motion lags the x motion by ``offset``
    periods, and the pair is turned by ``angle`` (R the rotation).  With
    ``y=None`` the table moves along one line, at ``angle`` to the first axis.  Any profile of the
    1-D model serves as a component (three-phase, piecewise-constant, polynomial, finite jerk,
    Fourier); an elliptical orbit is two harmonic profiles a quarter period apart.

    Parameters
    ----------
    x : Profile
        The motion along the first axis (before the rotation).
    y : Profile, optional
        The motion along the second axis, of the same period (relative 1e-12).  Default None: none.
    offset : float, optional
        The lag of the y motion, in periods, in [0, 1).  Default 0.
    angle : float, optional
        The rotation of the motion, in radians; finite.  Default 0.

    Attributes
    ----------
    dt : float
        The period (that of ``x``).
    piecewise_constant : bool
        True when Y'' is constant between the times of ``switch_times`` (both components piecewise constant).
    switch_times : numpy.ndarray
        The times within (0, dt) where either component's y'' switches or bends (sorted, unique).
    max_abs_acceleration : float
        The largest ``|Y''(t)|`` over the period: exact for piecewise-constant and piecewise-linear components,
        to ~1e-15 relative for Fourier ones (a grid and golden-section search).
    kind : str
        ``"planar"``, the profile kind of scene files.

    Raises
    ------
    TypeError
        If ``x`` or ``y`` is not a profile, or ``offset`` or ``angle`` is not a real number.
    ValueError
        If the periods differ, ``offset`` lies outside [0, 1), or ``angle`` is not finite.

    See Also
    --------
    Strip : A strip of high friction in the plane.
    Scene : Takes a planar profile with x0, v0 of two entries.

    Examples
    --------
    Two three-phase profiles a quarter period apart, and an elliptical orbit:

    >>> import selfalign as sa
    >>> p = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> planar = sa.PlanarProfile(x=p, y=p, offset=0.25)
    >>> planar.acceleration([0.2, 0.5]).round(6).tolist()
    [[-2.2, 0.9], [0.9, -2.2]]
    >>> round(planar.max_abs_acceleration, 6)
    2.376973
    >>> orbit = sa.PlanarProfile(x=sa.FourierProfile(1.0, [1.0], [0.0]), y=sa.FourierProfile(1.0, [0.0], [0.5]))
    >>> orbit.position([0.0, 0.25]).round(6).tolist()
    [[1.0, 0.0], [0.0, 0.5]]
    >>> sa.PlanarProfile(x=p, y=sa.ThreePhaseProfile(dt=1.1, dy=0.084, y2=2.2, y3=0.9))
    Traceback (most recent call last):
    ...
    ValueError: y.dt = 1.1 differs from x.dt = 1.05: the two components of a planar profile share one period
    """

    kind = "planar"

    def __init__(self, x: Profile, y: Profile | None = None, *, offset: float = 0.0, angle: float = 0.0):
        for name, value in (("x", x), ("y", y)):
            if not isinstance(value, Profile) and not (name == "y" and value is None):
                raise TypeError(f"{name} must be a selfalign profile{' or None' if name == 'y' else ''}, got "
                                f"{type(value).__name__}")
        if y is not None and not abs(y.dt - x.dt) <= PERIOD_TOL * x.dt:
            raise ValueError(f"y.dt = {y.dt!r} differs from x.dt = {x.dt!r}: the two components of a planar "
                             f"profile share one period")
        self.x, self.y = x, y
        self.offset = check_finite("offset", offset)
        if not 0.0 <= self.offset < 1.0:
            raise ValueError(f"offset must lie in [0, 1) (the lag of the y motion in periods), got {offset!r}")
        self.angle = check_finite("angle", angle)
        self.dt = float(x.dt)
        self.matrix = rotation(self.angle)
        self.piecewise_constant = x.piecewise_constant and (y is None or y.piecewise_constant)

    def _stack(self, t, what: str) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        first = np.asarray(getattr(self.x, what)(t), dtype=float)
        second = (np.zeros_like(first) if self.y is None
                  else np.asarray(getattr(self.y, what)(t - self.offset * self.dt), dtype=float))
        return first[..., None] * self.matrix[:, 0] + second[..., None] * self.matrix[:, 1]

    def position(self, t) -> np.ndarray:
        """Y(t), shape ``t.shape + (2,)``."""
        return self._stack(t, "position")

    def velocity(self, t) -> np.ndarray:
        """Y'(t), shape ``t.shape + (2,)``."""
        return self._stack(t, "velocity")

    def acceleration(self, t) -> np.ndarray:
        """Y''(t), shape ``t.shape + (2,)`` (right-continuous at switches)."""
        return self._stack(t, "acceleration")

    @property
    def switch_times(self) -> np.ndarray:
        """Times in (0, dt) where y'' of either component switches or bends (the y component's period start
        at ``offset * dt`` included), sorted and unique."""
        times = [np.asarray(getattr(self.x, "switch_times", np.zeros(0)), dtype=float)]
        if self.y is not None and isinstance(self.y, (PiecewiseConstantProfile, PiecewiseLinearProfile)):
            shifted = np.concatenate([self.y.switch_times, [0.0]]) + self.offset * self.dt
            times.append(np.where(shifted >= self.dt, shifted - self.dt, shifted))
        merged = np.unique(np.concatenate(times))
        return merged[(merged > 0.0) & (merged < self.dt)]

    def pieces(self) -> tuple[np.ndarray, np.ndarray]:
        """The pieces of one period between the switch times: (starts (n,), accelerations (n, 2)); piece i spans
        [starts[i], starts[i + 1]) (the last one ends at dt) and Y'' is the constant vector accelerations[i] there.
        Only for a piecewise-constant profile (ValueError otherwise)."""
        if not self.piecewise_constant:
            raise ValueError(f"pieces(): the components {self._names()} are not all piecewise constant")
        starts = np.concatenate([[0.0], self.switch_times])
        ends = np.concatenate([starts[1:], [self.dt]])
        return starts, np.array([self._piece_acceleration(a, b)[0] for a, b in zip(starts, ends)])

    def _piece_acceleration(self, start: float, end: float) -> tuple[np.ndarray, np.ndarray]:
        """Y'' at both ends of [start, end], a piece between switch times, as the limits from inside."""
        first = _piece_values(self.x, start, end)
        if self.y is None:
            second = (0.0, 0.0)
        else:
            shift = self.offset * self.dt
            lo = start - shift if start >= shift else start - shift + self.dt
            second = _piece_values(self.y, lo, lo + (end - start))
        return tuple(self.matrix @ np.array([first[k], second[k]]) for k in (0, 1))

    def _names(self) -> list:
        return [type(self.x).__name__] + ([] if self.y is None else [type(self.y).__name__])

    @property
    def max_abs_acceleration(self) -> float:
        polynomial = (PiecewiseConstantProfile, PiecewiseLinearProfile)
        if isinstance(self.x, polynomial) and (self.y is None or isinstance(self.y, polynomial)):
            starts = np.concatenate([[0.0], self.switch_times])
            ends = np.concatenate([starts[1:], [self.dt]])
            # Y'' is affine on every piece, so its length is largest at an end.
            return float(max(max(np.hypot(*a), np.hypot(*b)) for a, b in
                             (self._piece_acceleration(s, e) for s, e in zip(starts, ends))))
        return self._smooth_maximum()

    def _smooth_maximum(self) -> float:
        """max |Y''| when a component is a Fourier profile: the largest of a grid of :data:`MAX_GRID` samples per
        period (and the switch times of the other component), refined by golden-section search around it."""
        grid = np.concatenate([np.linspace(0.0, self.dt, MAX_GRID, endpoint=False), self.switch_times])
        size = np.hypot(*np.moveaxis(self.acceleration(grid), -1, 0))
        best = float(np.max(size))
        step = self.dt / MAX_GRID

        def norm(t):
            return float(np.hypot(*self.acceleration(t)))
        for k in np.argsort(size)[-3:]:
            a, b = grid[k] - step, grid[k] + step
            ratio = (math.sqrt(5.0) - 1.0) / 2.0
            for _ in range(80):
                c, d = b - ratio * (b - a), a + ratio * (b - a)
                if norm(c) >= norm(d):
                    b = d
                else:
                    a = c
            best = max(best, norm(0.5 * (a + b)))
        return best

    def rotated(self, theta: float) -> "PlanarProfile":
        """The same motion turned by a further ``theta`` radians."""
        return PlanarProfile(self.x, self.y, offset=self.offset, angle=self.angle + check_finite("theta", theta))

    def params(self) -> dict:
        return {"kind": self.kind, "x": self.x.params(), "y": None if self.y is None else self.y.params(),
                "offset": self.offset, "angle": self.angle}

    def __repr__(self):
        return f"PlanarProfile(x={self.x!r}, y={self.y!r}, offset={self.offset!r}, angle={self.angle!r})"

    def __eq__(self, other):
        return isinstance(other, PlanarProfile) and self.params() == other.params()

    def __hash__(self):
        return hash((self.kind, self.offset, self.angle))


def check_planar_state(name: str, value) -> tuple[float, float]:
    """A start position or velocity of a planar scene: a pair of finite real numbers, as a tuple of floats."""
    if isinstance(value, numbers.Real):
        check_real(name, value)
        raise TypeError(f"{name} of a planar scene must be a pair (x, y), got the number {value!r}")
    return _vector(name, value)


