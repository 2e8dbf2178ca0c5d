"""Periodic table-motion profiles y(t) (Sect. 4.4 and the Appendix).

Every profile is periodic with period ``dt`` and exposes vectorised
``position``, ``velocity`` and ``acceleration``.  Profiles whose acceleration
is piecewise constant (the three-phase profile of Sect. 4.4.3 and the
second-order polynomial profile of Sect. 4.2) share one representation,
:class:`PiecewiseConstantProfile`, which the exact solver integrates in
closed form.  The Fourier profile of Sect. 4.4.2 is smooth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import NonPhysicalProfile, check_finite, check_positive, check_real_array
from .registry import formula

#: The cases of Table 1 (the steady-state classification of a three-phase profile, Sect. 5).
CASE_LABELS = {
    0: "non-physical profile",
    1: "stick-slip, x' >= 0",
    2: "stick-slip, x' <= 0",
    3: "general stick-slip",
    4: "slip-slip",
    5: "pure stick",
}
#: Case code of a finite-jerk setting whose ramps do not fit its phases (FiniteJerkProfile refuses it).
RAMPS_TOO_LONG = -1
#: The parameters dt, dy, y2, y3 of a three-phase or polynomial profile lie in [1 / MAX_SCALE, MAX_SCALE].
#: They are in units of the friction scale (Sect. 3.2: accelerations in mu g, lengths in L, times in
#: sqrt(L / (mu g))), so 30 decades either way leave friction irrelevant or all-dominant; and the
#: closed forms of the steady state, the classification and the Floquet multipliers (Sects. 4.4.3,
#: 5, 6.1) multiply several of them: in 1,500 random feasible profiles with parameters up to 1e+-60
#: (the steady-state and positioning commands) none overflowed, up to 1e+-100 some did (numpy overflow
#: warnings and inf in place of numbers).
MAX_SCALE = 1e30


def check_scale(name: str, value) -> float:
    """``value`` as a float: a real number (TypeError otherwise) in [1 / MAX_SCALE, MAX_SCALE]."""
    value = check_positive(name, value)
    if not 1.0 / MAX_SCALE <= value <= MAX_SCALE:
        raise ValueError(f"{name} must lie in [{1.0 / MAX_SCALE:g}, {MAX_SCALE:g}] (dimensionless, in units of the "
                         f"friction scale of Sect. 3.2), got {value!r}")
    return value


class Profile:
    """Base class of the table motions: a periodic table displacement y(t) with period ``dt``.

    Every profile the solvers accept derives from it: :class:`~selfalign.ThreePhaseProfile`,
    :class:`~selfalign.PiecewiseConstantProfile`, :class:`~selfalign.FiniteJerkProfile`,
    :class:`~selfalign.PolynomialProfile` and :class:`~selfalign.FourierProfile`.  A profile gives
    y, y' and y'' at any time and the times where y'' switches.

    Attributes
    ----------
    dt : float
        The period Δt (dimensionless, Sect. 3.2).
    kind : str
        The profile's ``kind`` in scene files.
    piecewise_constant : bool
        True when y'' is constant between the times of ``switch_times``.

    Examples
    --------
    >>> import selfalign as sa
    >>> isinstance(sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9), sa.Profile)
    True
    """

    dt: float
    kind: str = "profile"
    #: True when y'' is constant between the times of ``switch_times``.
    piecewise_constant: bool = False

    def phase(self, t):
        """Time within the period, in [0, dt)."""
        tau = np.mod(np.asarray(t, dtype=float), self.dt)
        return np.where(tau >= self.dt, 0.0, tau)

    @property
    def max_abs_acceleration(self) -> float:
        raise NotImplementedError

    @property
    def velocity_swing(self) -> float:
        """The velocity scale of the motion, max y' - min y' (``|x'|`` stays below it in steady state)."""
        raise NotImplementedError

    def params(self) -> dict:
        """The defining parameters (stored as HDF5 attributes)."""
        raise NotImplementedError


class PiecewiseConstantProfile(Profile):
    """A periodic y(t) made of second-order polynomial pieces.

    Piece ``i`` spans ``[breaks[i], breaks[i+1])`` of the period and has
    constant table acceleration ``accels[i]``; ``y_start``, ``yd_start`` are
    y and y' at t = 0.  Pieces of zero length are dropped so that the
    solvers never see an empty interval.  y'' must have zero mean over the
    period, else the table velocity would drift (the sum of ``accels`` times the
    piece lengths may differ from 0 only by the rounding of the breaks).  y and y'
    are integrated piece by piece, so both are continuous.  The exact solver
    integrates such a profile in closed form; the three-phase profile
    (Sect. 4.4.3) and the second-order polynomial profile (Sect. 4.2) are of
    this kind.

    Parameters
    ----------
    breaks : array_like
        1-D, one entry more than ``accels``: finite, starting at 0, never
        decreasing and ending at the period dt > 0.
    accels : array_like
        The constant table acceleration y'' of each piece; finite.
    y_start : float
        Table position y at t = 0.
    yd_start : float
        Table velocity y' at t = 0.

    Attributes
    ----------
    dt : float
        The period, ``breaks[-1]``.
    breaks : numpy.ndarray
        The piece boundaries, from 0 to dt (pieces of zero length dropped).
    accels : numpy.ndarray
        y'' of each piece.
    piece_velocity : numpy.ndarray
        y' at the start of every piece and at the end of the period.
    piece_position : numpy.ndarray
        y at the start of every piece and at the end of the period.
    switch_times : numpy.ndarray
        Times within [0, dt) at which y'' jumps (piece starts after the first).
    max_abs_acceleration : float
        The largest ``|y''|``.
    velocity_swing : float
        max y' - min y': the velocity scale of the motion (``|x'|`` <= it in steady state).
    piecewise_constant : bool
        True: y'' is constant between the times of ``switch_times``.

    Raises
    ------
    TypeError
        If ``y_start`` or ``yd_start`` is not a real number, or ``breaks`` or ``accels``
        does not hold real numbers.
    ValueError
        If ``y_start`` or ``yd_start`` is not finite; if ``breaks`` is not 1-D with at
        least two entries and one more than ``accels``, is not finite, does not start at 0,
        decreases or does not end above 0; if ``accels`` is not finite; if y'' does not
        average to zero over the period; or if the table motion overflows double precision.

    See Also
    --------
    ThreePhaseProfile : The paper's three-phase profile (Sect. 4.4.3).
    PolynomialProfile : The second-order polynomial profile (Sect. 4.2).

    Examples
    --------
    A square wave of y'' (the piece of zero length at 0.5 is dropped):

    >>> import selfalign as sa
    >>> profile = sa.PiecewiseConstantProfile([0.0, 0.5, 0.5, 1.0], [2.0, 5.0, -2.0], y_start=0.0, yd_start=-0.5)
    >>> profile.accels.tolist(), profile.switch_times.tolist(), profile.dt
    ([2.0, -2.0], [0.5], 1.0)
    >>> profile.velocity([0.0, 0.25, 0.5, 0.75]).tolist()
    [-0.5, 0.0, 0.5, 0.0]
    >>> profile.max_abs_acceleration, profile.velocity_swing
    (2.0, 1.0)
    """

    piecewise_constant = True

    def __init__(self, breaks, accels, y_start: float, yd_start: float):
        y_start = check_finite("y_start", y_start)
        yd_start = check_finite("yd_start", yd_start)
        breaks = check_real_array("breaks", breaks)
        accels = check_real_array("accels", accels)
        if breaks.ndim != 1 or breaks.size < 2 or accels.shape != (breaks.size - 1,):
            raise ValueError("breaks must be 1-D with at least two entries and one entry more than accels")
        if not np.all(np.isfinite(breaks)) or breaks[0] != 0.0 or np.any(np.diff(breaks) < 0) \
                or breaks[-1] <= 0.0:
            raise ValueError("breaks must be finite, start at 0, never decrease and end at dt > 0, "
                             f"got {breaks.tolist()}")
        if not np.all(np.isfinite(accels)):
            raise ValueError(f"accels must be finite, got {accels.tolist()}")
        keep = np.diff(breaks) > 0
        self.breaks = np.concatenate([breaks[:1], breaks[1:][keep]])
        self.accels = accels[keep]
        self.dt = float(self.breaks[-1] - self.breaks[0])
        lengths = np.diff(self.breaks)
        # The table velocity is periodic only if y'' has zero mean: each break is known to
        # ~eps dt, so sum a_i L_i may differ from 0 by that much times sum |a_i|.
        impulse = float(np.sum(self.accels * lengths))
        allowed = 16.0 * np.finfo(float).eps * self.dt * float(np.sum(np.abs(self.accels)))
        if not abs(impulse) <= allowed:
            raise ValueError(f"y'' must average to zero over the period (else the table velocity drifts by "
                             f"sum(accels * lengths) = {impulse:.6g} per period); got breaks {self.breaks.tolist()} "
                             f"and accels {self.accels.tolist()}")
        # y' and y at the start of every piece (and at the end of the period).
        with np.errstate(over="ignore", invalid="ignore"):
            vel = yd_start + np.concatenate([[0.0], np.cumsum(self.accels * lengths)])
            pos = y_start + np.concatenate(
                [[0.0], np.cumsum(vel[:-1] * lengths + 0.5 * self.accels * lengths**2)]
            )
        if not (np.all(np.isfinite(vel)) and np.all(np.isfinite(pos))):
            raise ValueError(f"the table motion overflows double precision (velocities {vel.tolist()}, positions "
                             f"{pos.tolist()}); choose smaller accelerations or a shorter period")
        self.piece_velocity = vel
        self.piece_position = pos

    @property
    def switch_times(self) -> np.ndarray:
        """Times within [0, dt) at which y'' jumps (piece starts after the first)."""
        return self.breaks[1:-1].copy()

    @property
    def max_abs_acceleration(self) -> float:
        return float(np.max(np.abs(self.accels)))

    @property
    def velocity_swing(self) -> float:
        return float(np.ptp(self.piece_velocity))

    def piece_index(self, tau):
        """Index of the piece holding phase ``tau`` (right-continuous)."""
        idx = np.searchsorted(self.breaks, tau, side="right") - 1
        return np.clip(idx, 0, self.accels.size - 1)

    def _evaluate(self, t):
        tau = self.phase(t)
        i = self.piece_index(tau)
        return tau - self.breaks[i], i

    def position(self, t):
        s, i = self._evaluate(t)
        return self.piece_position[i] + self.piece_velocity[i] * s + 0.5 * self.accels[i] * s**2

    def velocity(self, t):
        s, i = self._evaluate(t)
        return self.piece_velocity[i] + self.accels[i] * s

    def acceleration(self, t):
        _, i = self._evaluate(t)
        return self.accels[i] + 0.0 * np.asarray(t, dtype=float)

    def params(self) -> dict:
        return {"kind": self.kind, "dt": self.dt, "breaks": self.breaks.tolist(),
                "accels": self.accels.tolist()}


@dataclass(frozen=True)
class ThreePhaseTimes:
    """Closed-form solution of the Appendix constraints (vectorised)."""

    t1: np.ndarray
    t2: np.ndarray
    t3: np.ndarray
    y_ini: np.ndarray
    yd_ini: np.ndarray
    t_top: np.ndarray      # t_{y'=0,1}: y' crosses zero downwards, y = dy (maximum)
    t_bottom: np.ndarray   # t_{y'=0,2}: y' crosses zero upwards, y = 0 (minimum)
    feasible: np.ndarray   # False for the paper's "case 0"


@formula(unnumbered="the Appendix's condition for real solutions of its seven constraints, stated in words: "
                    "beyond it lies case 0 of Table 1", kernel=False)
def three_phase_feasibility(dt, dy, y2, y3):
    """q = sqrt(8 dy (1/y2 + 1/y3)) / dt; a physical profile exists iff q <= 1."""
    k = 1.0 / np.asarray(y2, dtype=float) + 1.0 / np.asarray(y3, dtype=float)
    return np.sqrt(8.0 * np.asarray(dy, dtype=float) * k) / np.asarray(dt, dtype=float)


@formula(eqs=("64",), kernel=False)
def three_phase_times(dt, dy, y2, y3) -> ThreePhaseTimes:
    """Solve the seven Appendix constraints (Sect. 4.4.3) in closed form.

    Derivation (documented in docs/explanation/model.md): let u = y2 (t2 - t1) = y3 (t3 - t2)
    be the velocity swing (eq. 63) and k = 1/y2 + 1/y3, so t3 - t1 = u k.
    Zero mean velocity (periodic position, eq. 64) gives y'_ini = u^2 k / (2 dt),
    and the stroke condition (eq. 62) gives (u - y'_ini)^2 k / 2 = dy.  With
    q = sqrt(8 dy k) / dt and r = sqrt(1 - q) the admissible root is
    u = dt (1 - r) / k, so that

        t1 = dt r,   y'_ini = dt (1 - r)^2 / (2 k),   y_ini = y'_ini^2 / (2 y3).

    1 - r is evaluated as q / (1 + r), which does not cancel as q -> 0.  Because y'' has zero mean and the table
    first decelerates, y'_ini > 0 always: the Appendix's "second case"
    y'_ini < 0 cannot occur.  Case 0 is q > 1 (complex r).
    Inputs broadcast; infeasible entries are NaN.
    """
    dt, dy, y2, y3 = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (dt, dy, y2, y3)))
    k = 1.0 / y2 + 1.0 / y3
    q = three_phase_feasibility(dt, dy, y2, y3)
    feasible = q <= 1.0
    with np.errstate(invalid="ignore"):
        r = np.sqrt(np.where(feasible, 1.0 - q, np.nan))
    one_minus_r = q / (1.0 + r)
    swing = dt * one_minus_r / k
    t1 = dt * r
    t2 = t1 + swing / y2
    t3 = dt + 0.0 * t1
    yd_ini = dt * one_minus_r**2 / (2.0 * k)
    y_ini = yd_ini**2 / (2.0 * y3)
    return ThreePhaseTimes(t1=t1, t2=t2, t3=np.where(feasible, t3, np.nan), y_ini=y_ini,
                           yd_ini=yd_ini, t_top=t1 + yd_ini / y2, t_bottom=t3 - yd_ini / y3,
                           feasible=feasible)


class ThreePhaseProfile(PiecewiseConstantProfile):
    """The paper's three-phase table motion of Sect. 4.4.3 (Fig. 7).

    Three constant-acceleration intervals: 0 on [0, t1), -y2 on
    [t1, t2), +y3 on [t2, t3 = dt).  ``y2`` and ``y3`` are positive magnitudes.
    The switch times and the start state solve the seven constraints of the
    Appendix in closed form (``selfalign.model.profiles.three_phase_times``: zero-mean y''
    and y', the stroke ``dy``, min y = 0).  A physical profile exists
    iff the feasibility number q = sqrt(8 dy (1/y2 + 1/y3)) / dt is at most 1;
    beyond it lies case 0 of Table 1.  Every parameter is dimensionless, in units of
    the friction scale of Sect. 3.2, and lies in [1e-30, 1e30] (``MAX_SCALE``).  As a
    :class:`PiecewiseConstantProfile` it is integrated in closed form by the exact
    solver.

    Parameters
    ----------
    dt : float
        Period.
    dy : float
        Stroke, max y - min y.
    y2 : float
        Magnitude of the deceleration, y'' = -y2 on [t1, t2).
    y3 : float
        Magnitude of the acceleration, y'' = +y3 on [t2, dt).

    Attributes
    ----------
    dt : float
        The period.
    dy : float
        The stroke.
    y2 : float
        Magnitude of the deceleration phase.
    y3 : float
        Magnitude of the acceleration phase.
    t0 : float
        0, the start of the dwell.
    t1 : float
        End of the dwell: y'' jumps to -y2.
    t2 : float
        y'' jumps to +y3.
    t3 : float
        dt, the end of the period.
    y_ini : float
        y at t = 0.
    yd_ini : float
        y' at t = 0, and throughout the dwell; > 0.
    t_top : float
        The time at which y' crosses zero downwards (y = dy, the maximum).
    t_bottom : float
        The time at which y' crosses zero upwards (y = 0, the minimum).
    feasibility : float
        q = sqrt(8 dy (1/y2 + 1/y3)) / dt; case 0 is q > 1.
    breaks : numpy.ndarray
        [0, t1, t2, dt], the pieces of the :class:`PiecewiseConstantProfile` (a dwell of
        zero length, t1 = 0 at q = 1, is dropped).
    accels : numpy.ndarray
        [0, -y2, y3].
    kind : str
        ``"three_phase"``, the profile kind of scene files.

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If a parameter is not finite, not > 0 or outside [1e-30, 1e30], or if an
        acceleration phase loses its length in double precision.
    NonPhysicalProfile
        If no physical profile exists (case 0: 8 dy (1/y2 + 1/y3) > dt^2); the message
        names the largest stroke that is physical.

    See Also
    --------
    steady_state : Its steady state on a uniform surface (Sect. 5.1).
    classify : Its case of Table 1.

    Examples
    --------
    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)  # the Fig. 18 profile
    >>> print(round(profile.t1, 6), round(profile.t2, 6), profile.t3)
    0.159637 0.418129 1.05
    >>> print(round(profile.feasibility, 6), round(profile.yd_ini, 6))
    0.976885 0.241112
    >>> profile.acceleration([0.0, 0.3, 1.0]).tolist()
    [0.0, -2.2, 0.9]
    """

    kind = "three_phase"

    def __init__(self, dt: float, dy: float, y2: float, y3: float):
        dt, dy, y2, y3 = (check_scale(name, value) for name, value in (("dt", dt), ("dy", dy), ("y2", y2),
                                                                        ("y3", y3)))
        q = float(three_phase_feasibility(dt, dy, y2, y3))
        if q > 1.0:
            raise NonPhysicalProfile(
                f"no physical three-phase profile (case 0): 8*dy*(1/y2 + 1/y3) = "
                f"{(q * dt) ** 2:.6g} exceeds dt^2 = {dt * dt:.6g}; "
                f"need dy <= dt^2 / (8 (1/y2 + 1/y3)) = dy / q^2 = {dy / q ** 2:.6g}"
            )
        sol = three_phase_times(dt, dy, y2, y3)
        lengths = {"t1": float(sol.t1), "t2 - t1": float(sol.t2 - sol.t1), "dt - t2": float(dt - sol.t2)}
        bad = [f"{name} = {value!r}" for name, value in lengths.items()
               if not math.isfinite(value) or (value <= 0.0 and name != "t1") or value < 0.0]
        if bad:
            raise ValueError(f"three-phase profile dt = {dt!r}, dy = {dy!r}, y2 = {y2!r}, y3 = {y3!r} is beyond "
                             f"double precision: {', '.join(bad)} (every acceleration phase must keep a positive "
                             f"length)")
        self.dy, self.y2, self.y3 = float(dy), float(y2), float(y3)
        self.t0 = 0.0
        self.t1, self.t2, self.t3 = float(sol.t1), float(sol.t2), float(dt)
        self.y_ini, self.yd_ini = float(sol.y_ini), float(sol.yd_ini)
        self.t_top, self.t_bottom = float(sol.t_top), float(sol.t_bottom)
        super().__init__([0.0, self.t1, self.t2, self.t3], [0.0, -self.y2, self.y3],
                         self.y_ini, self.yd_ini)
        self.dt = float(dt)

    @property
    def feasibility(self) -> float:
        """q of ``three_phase_feasibility``; case 0 is q > 1."""
        return float(three_phase_feasibility(self.dt, self.dy, self.y2, self.y3))

    def params(self) -> dict:
        return {"kind": self.kind, "dt": self.dt, "dy": self.dy, "y2": self.y2, "y3": self.y3,
                "t1": self.t1, "t2": self.t2, "t3": self.t3, "y_ini": self.y_ini,
                "yd_ini": self.yd_ini}

    def __repr__(self):
        return f"ThreePhaseProfile(dt={self.dt!r}, dy={self.dy!r}, y2={self.y2!r}, y3={self.y3!r})"


class PiecewiseLinearProfile(Profile):
    """A periodic y(t) made of third-order polynomial pieces: y'' linear in each piece.

    Piece ``i`` spans ``[breaks[i], breaks[i+1])`` with y'' = ``accels[i]`` + ``jerks[i]`` s,
    s the time since the piece start, running from ``accels[i]`` to ``ends[i]``; ``y_start``,
    ``yd_start`` are y and y' at t = 0.  Zero-length pieces are dropped.  y and y' are
    continuous (integrated piece by piece); y'' may jump at a break.  It is not piecewise
    constant: the exact solver runs it on its smooth stepper (docs/explanation/model.md).

    ``ends`` (default accels + jerks * lengths) are the values y'' reaches at the piece ends,
    and y'' never leaves [min(accels[i], ends[i]), max(accels[i], ends[i])] (it is clamped
    there): the break times are floats, so accels + jerks * lengths misses the level a ramp
    was built to reach by about |jerk| eps dt (5e-8 of the level for a ramp of 1e-9 dt), and
    overshooting the level would move y'' past a friction limit set equal to it.  The ends
    must lie within that rounding of accels + jerks * lengths.  max|y''| is the largest |accels|
    and |ends|, the bound every solver's rest-for-good test and stick test share.
    """

    def __init__(self, breaks, accels, jerks, y_start: float, yd_start: float, ends=None):
        y_start = check_finite("y_start", y_start)
        yd_start = check_finite("yd_start", yd_start)
        breaks, accels, jerks = (np.asarray(a, dtype=float) for a in (breaks, accels, jerks))
        if breaks.ndim != 1 or breaks.size < 2 or accels.shape != (breaks.size - 1,) or jerks.shape != accels.shape:
            raise ValueError("breaks must be 1-D with at least two entries and one entry more than accels and jerks")
        if not np.all(np.isfinite(breaks)) or breaks[0] != 0.0 or np.any(np.diff(breaks) < 0) or breaks[-1] <= 0.0:
            raise ValueError(f"breaks must be finite, start at 0, never decrease and end at dt > 0, "
                             f"got {breaks.tolist()}")
        if not (np.all(np.isfinite(accels)) and np.all(np.isfinite(jerks))):
            raise ValueError(f"accels and jerks must be finite, got {accels.tolist()} and {jerks.tolist()}")
        reached = accels + jerks * np.diff(breaks)
        if ends is None:
            ends = reached
        ends = np.asarray(ends, dtype=float)
        slack = 16.0 * np.finfo(float).eps * (np.abs(accels) + np.abs(jerks) * breaks[1:] + np.abs(reached))
        if ends.shape != accels.shape or not np.all(np.abs(ends - reached) <= slack):
            raise ValueError(f"ends must have one entry per piece, each the value accels + jerks * length reaches to "
                             f"the rounding of the break times, got {np.asarray(ends).tolist()} for "
                             f"{reached.tolist()}")
        keep = np.diff(breaks) > 0
        self.breaks = np.concatenate([breaks[:1], breaks[1:][keep]])
        self.accels, self.jerks, self.ends = accels[keep], jerks[keep], ends[keep]
        self.dt = float(self.breaks[-1])
        lengths = np.diff(self.breaks)
        impulse = self.accels * lengths + 0.5 * self.jerks * lengths**2
        allowed = 64.0 * np.finfo(float).eps * float(np.sum(np.abs(impulse)))
        if not abs(float(np.sum(impulse))) <= allowed:
            raise ValueError(f"y'' must average to zero over the period (else the table velocity drifts by "
                             f"{float(np.sum(impulse)):.6g} per period); got breaks {self.breaks.tolist()}, "
                             f"accels {self.accels.tolist()} and jerks {self.jerks.tolist()}")
        vel = yd_start + np.concatenate([[0.0], np.cumsum(impulse)])
        shift = vel[:-1] * lengths + self.accels * lengths**2 / 2.0 + self.jerks * lengths**3 / 6.0
        self.piece_velocity = vel
        self.piece_position = y_start + np.concatenate([[0.0], np.cumsum(shift)])

    @property
    def switch_times(self) -> np.ndarray:
        """Times within [0, dt) at which a new polynomial piece starts."""
        return self.breaks[1:-1].copy()

    @property
    def max_abs_acceleration(self) -> float:
        return float(max(np.max(np.abs(self.accels)), np.max(np.abs(self.ends))))

    @property
    def velocity_swing(self) -> float:
        """max y' - min y' over the breaks and the interior zeros of y''."""
        lengths = np.diff(self.breaks)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.where(self.jerks != 0.0, -self.accels / self.jerks, -1.0)
        inside = (s > 0.0) & (s < lengths)
        interior = (self.piece_velocity[:-1][inside] + self.accels[inside] * s[inside]
                    + 0.5 * self.jerks[inside] * s[inside] ** 2)
        return float(np.ptp(np.concatenate([self.piece_velocity, interior])))

    def _evaluate(self, t):
        tau = self.phase(t)
        i = np.clip(np.searchsorted(self.breaks, tau, side="right") - 1, 0, self.accels.size - 1)
        return tau - self.breaks[i], i

    def position(self, t):
        s, i = self._evaluate(t)
        return (self.piece_position[i] + self.piece_velocity[i] * s + self.accels[i] * s**2 / 2.0
                + self.jerks[i] * s**3 / 6.0)

    def velocity(self, t):
        s, i = self._evaluate(t)
        return self.piece_velocity[i] + self.accels[i] * s + 0.5 * self.jerks[i] * s**2

    def acceleration(self, t):
        s, i = self._evaluate(t)
        a, e = self.accels[i], self.ends[i]
        return np.clip(a + self.jerks[i] * s, np.minimum(a, e), np.maximum(a, e))

    def params(self) -> dict:
        return {"kind": "piecewise_linear", "dt": self.dt, "breaks": self.breaks.tolist(),
                "accels": self.accels.tolist(), "jerks": self.jerks.tolist(), "ends": self.ends.tolist()}


@dataclass(frozen=True)
class FiniteJerkTimes:
    """Closed-form solution of the Appendix constraints with linear ramps (vectorised).

    ``t1``, ``t2``, ``t3`` are the ramp centres (the paper's switch times as the ramps
    vanish); ``yd_ini`` is y' on the zero-acceleration plateau, ``y_start`` and
    ``yd_start`` are y and y' at t = 0 (the centre of the third ramp).
    """

    t1: np.ndarray
    t2: np.ndarray
    t3: np.ndarray
    yd_ini: np.ndarray
    y_start: np.ndarray
    yd_start: np.ndarray
    t_top: np.ndarray
    t_bottom: np.ndarray
    q: np.ndarray          # the feasibility measure; a physical profile needs 0 < q <= 1
    valid: np.ndarray      # q in (0, 1], every ramp inside its phase and y' = 0 on the plateaus


@formula(unnumbered="finite jerk is beyond the paper (its recommendation (2), Sect. 8): the Appendix's "
                    "constraints with linear ramps of y''", kernel=False)
def finite_jerk_times(dt, dy, y2, y3, ramp_a, ramp_b, ramp_c) -> FiniteJerkTimes:
    """Switch times of the three-phase profile whose y'' ramps linearly over ``ramp_a`` (0 to -y2),
    ``ramp_b`` (-y2 to +y3) and ``ramp_c`` (+y3 to 0), each ramp centred on its switch time.

    Derivation (docs/explanation/model.md): a ramp of length T and jump J centred on
    a switch has the step's velocity change, so y' equals the paper's y' outside the ramps;
    inside it differs by J (s + T/2)^2 / (2 T) before the centre and J (s - T/2)^2 / (2 T)
    after it, which shifts y by J T^2 / 24 per ramp.  With u = y2 (t2 - t1) = y3 (t3 - t2)
    and k = 1/y2 + 1/y3 as in :func:`three_phase_times`, E = (-y2 ramp_a^2 + (y2 + y3) ramp_b^2
    - y3 ramp_c^2) / 24 and D = (y2 + y3) ramp_b^2 / 24:

        zero-mean y' (periodic y):     yd_ini dt - u^2 k / 2 + E = 0,
        stroke (y' = 0 on plateaus):   (u - yd_ini)^2 k / 2 - D = dy.

    So u - yd_ini = G = sqrt(2 (dy + D) / k) and u solves k u^2 / (2 dt) - u + G - E / dt = 0:
    with q = 2 k (G - E / dt) / dt and r = sqrt(1 - q), u = dt (1 - r) / k and t1 = dt r.
    All ramps zero gives E = D = 0 and q = sqrt(8 dy k) / dt, the paper's profile.
    """
    dt, dy, y2, y3, ta, tb, tc = np.broadcast_arrays(
        *(np.asarray(a, dtype=float) for a in (dt, dy, y2, y3, ramp_a, ramp_b, ramp_c)))
    k = 1.0 / y2 + 1.0 / y3
    shift = (-y2 * ta**2 + (y2 + y3) * tb**2 - y3 * tc**2) / 24.0
    dip = (y2 + y3) * tb**2 / 24.0
    depth = np.sqrt(2.0 * (dy + dip) / k)
    q = 2.0 * k * (depth - shift / dt) / dt
    feasible = (q <= 1.0) & (q > 0.0)
    with np.errstate(invalid="ignore"):
        r = np.sqrt(np.where(feasible, 1.0 - q, np.nan))
    swing = dt * (q / (1.0 + r)) / k
    t1 = dt * r
    t2 = t1 + swing / y2
    yd_ini = (swing**2 * k / 2.0 - shift) / dt
    t_top, t_bottom = t1 + yd_ini / y2, dt - yd_ini / y3
    with np.errstate(invalid="ignore"):
        valid = (feasible & (t1 - (ta + tc) / 2.0 >= 0.0) & (t_top - t1 >= ta / 2.0) & (t2 - t_top >= tb / 2.0)
                 & (t_bottom - t2 >= tb / 2.0) & (dt - t_bottom >= tc / 2.0))
    return FiniteJerkTimes(t1=t1, t2=t2, t3=dt + 0.0 * t1, yd_ini=yd_ini,
                           y_start=yd_ini**2 / (2.0 * y3) - y3 * tc**2 / 48.0, yd_start=yd_ini - y3 * tc / 8.0,
                           t_top=t_top, t_bottom=t_bottom, q=q, valid=valid)


#: The shortest ramp a finite-jerk profile takes, as a fraction of its period: 16 eps.  Its
#: ramps are centred on switch times t <= dt and end at the floats t -+ ramp / 2, each rounded
#: by up to eps dt / 2, so a ramp's represented length is off by up to eps dt: at 16 eps dt by
#: at most 1/16 of itself, and below eps dt it may have no length at all (t -+ ramp / 2 round
#: to t) or, at a few ulps, a jerk off by a factor of two.  A ramp that short is the paper's jump
#: (ThreePhaseProfile; ``ramp: 0`` in a scene file).
MIN_RAMP_FRACTION = 2.0 ** -48


def ramp_times(dt: float, y2: float, y3: float, ramp: float | None = None, jerk: float | None = None) -> tuple:
    """(ramp_a, ramp_b, ramp_c) of the three switches: all ``ramp``, or |jump| / ``jerk``.

    Each ramp must be at least :data:`MIN_RAMP_FRACTION` dt and shorter than dt (whether the
    three fit their phases is :func:`finite_jerk_times`' test): a ValueError names ``ramp`` or
    ``jerk`` and the values allowed otherwise, before any arithmetic on the ramps can overflow."""
    if (ramp is None) == (jerk is None):
        raise ValueError(f"give exactly one of ramp (a ramp time > 0) and jerk (the largest |d y''/dt| > 0), "
                         f"got ramp = {ramp!r}, jerk = {jerk!r}")
    shortest = MIN_RAMP_FRACTION * dt
    why = (f"a ramp shorter than 2^-48 dt = {shortest!r} is lost in the rounding of its break times (the paper's "
           f"jumps are ThreePhaseProfile, ramp 0), one of dt = {dt!r} or more does not fit the period")
    if ramp is not None:
        ramp = check_positive("ramp", ramp)
        if not shortest <= ramp < dt:
            raise ValueError(f"ramp must lie in [{shortest!r}, {dt!r}) ({why}), got {ramp!r}")
        return ramp, ramp, ramp
    jerk = check_positive("jerk", jerk)
    ramps = (y2 / jerk, (y2 + y3) / jerk, y3 / jerk)
    if not (min(ramps) >= shortest and ramps[1] < dt):
        raise ValueError(f"jerk must lie in ((y2 + y3) / dt, min(y2, y3) / {shortest!r}] = ({(y2 + y3) / dt!r}, "
                         f"{min(y2, y3) / shortest!r}] so that every ramp |jump| / jerk fits ({why}), got {jerk!r}")
    return ramps


class FiniteJerkProfile(PiecewiseLinearProfile):
    """The three-phase profile (Sect. 4.4.3) with finite jerk: y'' ramps between its levels.

    y'' moves linearly between the levels 0, -y2, +y3 over a ramp of time ``ramp`` at each
    switch (or ``|jump| / jerk``), the ramps centred on the switch times of
    ``selfalign.model.profiles.finite_jerk_times``, which keep the Appendix's constraints
    (zero-mean y'' and y', the stroke dy, min y = 0).  t = 0 is the centre of the ramp from
    +y3 to 0; as the ramps vanish this is the paper's profile.

    Each ramp ends on its level exactly, so max ``|y''|`` = max(y2, y3) is the largest y'' the
    solvers see.  A ramp must be at least ``MIN_RAMP_FRACTION`` dt (3.6e-15 dt, a jerk at most
    min(y2, y3) / that): a shorter one is below the rounding of its break times and is refused
    rather than silently made the paper's jump, which is :class:`ThreePhaseProfile`, a
    different solver path.  Scene files give it as a three-phase profile with ``ramp`` or
    ``jerk``.

    Parameters
    ----------
    dt : float
        Period.
    dy : float
        Stroke, max y - min y.
    y2 : float
        Magnitude of the deceleration level, y'' = -y2.
    y3 : float
        Magnitude of the acceleration level, y'' = +y3.
    ramp : float or None
        Time of each ramp of y''; give exactly one of ``ramp`` and ``jerk``.
    jerk : float or None
        The slope of every ramp, the largest ``|d y''/dt|``; each ramp then takes its jump
        divided by ``jerk``.

    Attributes
    ----------
    dt : float
        The period.
    dy : float
        The stroke.
    y2 : float
        Magnitude of the deceleration level.
    y3 : float
        Magnitude of the acceleration level.
    ramp : float or None
        The ramp time given.
    jerk : float or None
        The jerk given.
    ramps : tuple of float
        Times of the ramps into -y2, into +y3 and from +y3 to 0.
    t1 : float
        Centre of the ramp from 0 to -y2.
    t2 : float
        Centre of the ramp from -y2 to +y3.
    t3 : float
        dt, the end of the period.
    yd_ini : float
        y' on the dwell at y'' = 0.
    kind : str
        ``"three_phase"``, the profile kind of scene files.

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If a parameter is not finite, not > 0 or outside [1e-30, 1e30], if not exactly one of
        ``ramp`` and ``jerk`` is given, if a ramp is shorter than ``MIN_RAMP_FRACTION`` dt, or
        if the ramps are too long for the profile.
    NonPhysicalProfile
        If no physical profile exists with these ramps (the stroke cannot be reached in one
        period).

    See Also
    --------
    ThreePhaseProfile : The paper's profile, whose y'' jumps.

    Examples
    --------
    >>> import selfalign as sa
    >>> profile = sa.FiniteJerkProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9, ramp=0.01)
    >>> profile
    FiniteJerkProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9, ramp=0.01)
    >>> print(round(profile.t1, 6), round(profile.t2, 6), profile.ramps)
    0.159377 0.417945 (0.01, 0.01, 0.01)
    >>> traj = sa.simulate(sa.Scene(profile, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5), until="rest"))
    >>> print(traj.status, traj.x_end)
    accumulation 0.54
    """

    kind = "three_phase"

    def __init__(self, dt: float, dy: float, y2: float, y3: float, ramp: float | None = None,
                 jerk: float | None = None):
        dt, dy, y2, y3 = (check_scale(name, value) for name, value in (("dt", dt), ("dy", dy), ("y2", y2),
                                                                        ("y3", y3)))
        ta, tb, tc = ramp_times(dt, y2, y3, ramp, jerk)
        sol = finite_jerk_times(dt, dy, y2, y3, ta, tb, tc)
        if not 0.0 < float(sol.q) <= 1.0:
            raise NonPhysicalProfile(f"no physical finite-jerk three-phase profile: dt = {dt!r}, dy = {dy!r}, "
                                     f"y2 = {y2!r}, y3 = {y3!r} with ramps {ta!r}, {tb!r}, {tc!r} need 0 < q <= 1, "
                                     f"got q = {float(sol.q):.6g} (the stroke cannot be reached in one period)")
        if not bool(sol.valid):
            raise ValueError(f"ramps ({ta!r}, {tb!r}, {tc!r}) are too long for the three-phase profile dt = {dt!r}, "
                             f"dy = {dy!r}, y2 = {y2!r}, y3 = {y3!r}: every ramp must end before the next starts "
                             f"and the table velocity must reach 0 on the -y2 and +y3 plateaus")
        self.dy, self.y2, self.y3 = float(dy), float(y2), float(y3)
        self.ramp, self.jerk = ramp, jerk
        self.ramps = (float(ta), float(tb), float(tc))
        self.t1, self.t2, self.t3 = float(sol.t1), float(sol.t2), float(dt)
        self.yd_ini, self.t_top, self.t_bottom = float(sol.yd_ini), float(sol.t_top), float(sol.t_bottom)
        ha, hb, hc = ta / 2.0, tb / 2.0, tc / 2.0
        t1, t2 = self.t1, self.t2
        breaks = [0.0, hc, t1 - ha, t1 + ha, t2 - hb, t2 + hb, dt - hc, dt]
        accels = [y3 / 2.0, 0.0, 0.0, -y2, -y2, y3, y3]
        jerks = [-y3 / tc, 0.0, -y2 / ta, 0.0, (y2 + y3) / tb, 0.0, -y3 / tc]
        ends = [0.0, 0.0, -y2, -y2, y3, y3, y3 / 2.0]       # each ramp ends on its level exactly
        super().__init__(breaks, accels, jerks, float(sol.y_start), float(sol.yd_start), ends=ends)
        self.dt = float(dt)

    def params(self) -> dict:
        given = {"ramp": float(self.ramp)} if self.ramp is not None else {"jerk": float(self.jerk)}
        return {"kind": self.kind, "dt": self.dt, "dy": self.dy, "y2": self.y2, "y3": self.y3, **given,
                "t1": self.t1, "t2": self.t2, "t3": self.t3, "yd_ini": self.yd_ini}

    def __repr__(self):
        given = f"ramp={self.ramp!r}" if self.ramp is not None else f"jerk={self.jerk!r}"
        return f"FiniteJerkProfile(dt={self.dt!r}, dy={self.dy!r}, y2={self.y2!r}, y3={self.y3!r}, {given})"


class PolynomialProfile(PiecewiseConstantProfile):
    """The second-order polynomial profile of Sect. 4.2 (Fig. 3).

    The paper only sketches it; our definition: a slow forward stroke of
    duration ``forward_fraction * dt`` and a fast return stroke, each made of
    two parabolas (accelerate, then decelerate with equal magnitude), so y'
    is continuous and zero at the stroke ends.  Stroke ``dy`` is exact, y has
    zero mean over a period (y runs from -dy/2 to +dy/2) and is periodic.
    Accelerations: +-4 dy / (f dt)^2 forward, -+4 dy / ((1 - f) dt)^2 back.

    Parameters
    ----------
    dt : float
        Period, in [1e-30, 1e30] (dimensionless, ``MAX_SCALE``).
    dy : float
        Stroke, in [1e-30, 1e30].
    forward_fraction : float, optional
        f, the fraction of the period taken by the forward stroke; in (0, 1).  Default 0.8.

    Attributes
    ----------
    dt : float
        The period.
    dy : float
        The stroke.
    forward_fraction : float
        The fraction of the period taken by the forward stroke.
    breaks : numpy.ndarray
        The boundaries of the four parabolas, the pieces of the
        :class:`PiecewiseConstantProfile`.
    accels : numpy.ndarray
        y'' of each parabola.
    kind : str
        ``"polynomial"``, the profile kind of scene files.

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If ``dt`` or ``dy`` is not finite, not > 0 or outside [1e-30, 1e30], or
        ``forward_fraction`` is not finite or outside (0, 1).

    See Also
    --------
    ThreePhaseProfile : The profile the paper optimises (Sect. 4.4.3).

    Examples
    --------
    >>> import selfalign as sa
    >>> profile = sa.PolynomialProfile(dt=1.0, dy=0.1)
    >>> profile.breaks.tolist()
    [0.0, 0.4, 0.8, 0.9, 1.0]
    >>> profile.accels.round(6).tolist()
    [0.625, -0.625, -10.0, 10.0]
    >>> profile.position([0.0, 0.8]).round(6).tolist()
    [-0.05, 0.05]
    """

    kind = "polynomial"

    def __init__(self, dt: float, dy: float, forward_fraction: float = 0.8):
        dt, dy = check_scale("dt", dt), check_scale("dy", dy)
        forward_fraction = check_finite("forward_fraction", forward_fraction)
        if not 0.0 < forward_fraction < 1.0:
            raise ValueError(f"forward_fraction must lie in (0, 1), got {forward_fraction!r}")
        self.dy, self.forward_fraction = float(dy), float(forward_fraction)
        t_fwd = forward_fraction * dt
        t_back = dt - t_fwd
        a_fwd = 4.0 * dy / t_fwd**2
        a_back = 4.0 * dy / t_back**2
        breaks = [0.0, t_fwd / 2, t_fwd, t_fwd + t_back / 2, dt]
        super().__init__(breaks, [a_fwd, -a_fwd, -a_back, a_back], -dy / 2.0, 0.0)
        self.dt = float(dt)

    def params(self) -> dict:
        return {"kind": self.kind, "dt": self.dt, "dy": self.dy,
                "forward_fraction": self.forward_fraction}

    def __repr__(self):
        return (f"PolynomialProfile(dt={self.dt!r}, dy={self.dy!r}, "
                f"forward_fraction={self.forward_fraction!r})")


class FourierProfile(Profile):
    """y(t) = sum_k a_k cos(2 pi k t / dt) + b_k sin(2 pi k t / dt), k = 1..N (Sect. 4.4.2).

    Zero mean by construction.  ``stroke``, ``peak_velocity`` and
    ``peak_acceleration`` are the constraint quantities of the shape
    optimisation, evaluated on a fine grid refined by Newton steps.  The
    profile is smooth; the exact solver simulates it on a uniform surface,
    Moreau and ivp on a stop zone too.

    Parameters
    ----------
    dt : float
        Period; > 0.
    cos_coeffs : array_like
        a_1 .. a_N, 1-D and finite.
    sin_coeffs : array_like
        b_1 .. b_N, 1-D, finite and as long as ``cos_coeffs``.

    Attributes
    ----------
    dt : float
        The period.
    cos_coeffs : numpy.ndarray
        a_1 .. a_N, as a float array.
    sin_coeffs : numpy.ndarray
        b_1 .. b_N, as a float array.
    order : int
        N, the number of harmonics.
    omega : numpy.ndarray
        The angular frequencies 2 pi k / dt, k = 1..N.
    stroke : float
        max y - min y.
    peak_velocity : float
        The largest ``|y'|``.
    peak_acceleration : float
        The largest ``|y''|``.
    max_abs_acceleration : float
        The largest ``|y''|``, the same as ``peak_acceleration``.
    velocity_swing : float
        max y' - min y'.
    kind : str
        ``"fourier"``, the profile kind of scene files.

    Raises
    ------
    TypeError
        If ``dt`` is not a real number, or the coefficients do not hold real numbers.
    ValueError
        If ``dt`` is not finite and > 0, the coefficients are not 1-D arrays of equal
        length, or a coefficient is not finite.

    See Also
    --------
    ThreePhaseProfile : The piecewise-constant optimum of Sect. 4.4.3.

    Examples
    --------
    One harmonic, y(t) = 0.05 sin(2 pi t):

    >>> import selfalign as sa
    >>> profile = sa.FourierProfile(1.0, [0.0], [0.05])
    >>> profile
    FourierProfile(dt=1.0, order=1)
    >>> print(round(profile.stroke, 6), round(profile.peak_velocity, 6), round(profile.peak_acceleration, 6))
    0.1 0.314159 1.973921
    """

    kind = "fourier"

    def __init__(self, dt: float, cos_coeffs, sin_coeffs):
        self.dt = check_positive("dt", dt)
        self.cos_coeffs = check_real_array("cos_coeffs", cos_coeffs)
        self.sin_coeffs = check_real_array("sin_coeffs", sin_coeffs)
        if self.cos_coeffs.shape != self.sin_coeffs.shape or self.cos_coeffs.ndim != 1:
            raise ValueError("cos_coeffs and sin_coeffs must be 1-D arrays of equal length")
        if not (np.all(np.isfinite(self.cos_coeffs)) and np.all(np.isfinite(self.sin_coeffs))):
            raise ValueError("Fourier coefficients must be finite")
        self.order = self.cos_coeffs.size
        self.omega = 2.0 * np.pi * np.arange(1, self.order + 1) / self.dt
        self._extremes_cache: dict[int, tuple[float, float]] = {}
        self._grid = None

    switch_times = np.empty(0)

    def _derivatives(self, t, orders) -> list:
        """The time derivatives of y of the given orders at t (vectorised), one cos/sin per harmonic.

        Summed harmonic by harmonic in a fixed order with elementwise numpy (no matrix
        product, which would go through BLAS and round differently on other CPUs).
        """
        if isinstance(t, float):
            # One time: Python floats and math.cos/sin, which give the bits of numpy's (both
            # are the C library's), without numpy's per-call cost in the Newton steps below.
            cos, sin, totals = math.cos, math.sin, [0.0 for _ in orders]
        else:
            t = np.asarray(t, dtype=float)
            cos, sin, totals = np.cos, np.sin, [np.zeros(t.shape) for _ in orders]
        for a, b, w in zip(self.cos_coeffs.tolist(), self.sin_coeffs.tolist(), self.omega.tolist()):
            c, s = cos(w * t), sin(w * t)
            # d^n/dt^n of a cos + b sin: the pair rotates by a quarter turn per derivative.
            even, odd = a * c + b * s, b * c - a * s
            values = (even, odd, -even, -odd)
            for i, n in enumerate(orders):
                totals[i] = totals[i] + w**n * values[n % 4]
        return totals

    def _derivative(self, t, n: int):
        """n-th time derivative of y at t (vectorised)."""
        return self._derivatives(t, (n,))[0]

    def position(self, t):
        return self._derivative(t, 0)

    def velocity(self, t):
        return self._derivative(t, 1)

    def acceleration(self, t):
        return self._derivative(t, 2)

    def _extremes(self, n: int) -> tuple[float, float]:
        """(min, max) of the n-th derivative (n = 0, 1, 2) over a period: the best of a grid of
        64 (order + 1) times, refined by Newton on the (n+1)-th derivative.  Computed once per
        profile (the coefficients do not change); one grid evaluation serves all three orders."""
        if n not in self._extremes_cache:
            if self._grid is None:
                grid = np.linspace(0.0, self.dt, 64 * self.order + 64, endpoint=False)
                self._grid = grid, self._derivatives(grid, (0, 1, 2))
            grid, values = self._grid
            self._extremes_cache[n] = self._refine_extremes(n, grid, values[n])
        return self._extremes_cache[n]

    def _refine_extremes(self, n: int, grid: np.ndarray, values: np.ndarray) -> tuple[float, float]:
        step_limit = self.dt / grid.size
        results = []
        for idx in (np.argmin(values), np.argmax(values)):
            t = float(grid[idx])
            for _ in range(20):  # Newton on the derivative of the n-th derivative
                d1, d2 = self._derivatives(t, (n + 1, n + 2))
                if d2 == 0:
                    break
                step = d1 / d2
                t = t - min(max(step, -step_limit), step_limit)
                if abs(step) < 1e-15 * self.dt:
                    break
            results.append(self._derivative(t, n))
        return min(results[0], values.min()), max(results[1], values.max())

    @property
    def stroke(self) -> float:
        lo, hi = self._extremes(0)
        return hi - lo

    @property
    def peak_velocity(self) -> float:
        lo, hi = self._extremes(1)
        return max(-lo, hi)

    @property
    def peak_acceleration(self) -> float:
        lo, hi = self._extremes(2)
        return max(-lo, hi)

    @property
    def max_abs_acceleration(self) -> float:
        return self.peak_acceleration

    @property
    def velocity_swing(self) -> float:
        lo, hi = self._extremes(1)
        return hi - lo

    def params(self) -> dict:
        return {"kind": self.kind, "dt": self.dt, "cos_coeffs": self.cos_coeffs.tolist(),
                "sin_coeffs": self.sin_coeffs.tolist()}

    def __repr__(self):
        return f"FourierProfile(dt={self.dt!r}, order={self.order})"
