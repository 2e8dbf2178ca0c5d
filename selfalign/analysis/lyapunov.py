"""Convergence of the relative velocity: the Lyapunov trace of Sect. 6.2 (eqs. 34-37, Fig. 13).

Two trajectories of v' in -Sign(v) - y''(t) (eq. 34, uniform surface) from the
initial velocities v10 and v20 at the same time, and the Lyapunov function
V = (v1 - v2)^2 / 2 (eq. 35).  Along solutions (eq. 36)

    V' = (v1 - v2)(v1' - v2') = -(v1 - v2)(s1 - s2),

where s_i in Sign(v_i) is the element of the set-valued sign that the motion
actually selects, i.e. the friction force divided by mu_bar: s = sign(v) in
slip and s = -y''(t) in stick (x'' = 0 there, eq. 6), which lies in [-1, 1]
exactly because stick needs |y''| <= 1.  Labels follow this selection (the
paper's v-hat_i): an interval is "=" where s1 = s2 and "!=" where s1 != s2.
Hence, exactly,

* "=": V' = 0 (both slip in the same direction, or both stick, which means
  v1 = v2 = 0; a stuck mass under the tie y'' = -+1 selects s = +-1 and equals
  a mass slipping in the direction +-1 -- then too x1'' = x2''),
* "!=": V' < 0 whenever V > 0, because Sign is monotone: v1 > v2 forces
  s1 >= s2, so s1 != s2 means s1 > s2 and (v1 - v2)(s1 - s2) > 0.

v = 0 is therefore labelled by what the mass does there, not by the value 0:
a mass sticking while the other slips is always "!=" except at that tie.

Everything is computed from the exact solver's arcs: the breakpoints are the
union of both trajectories' event times and period boundaries; between two
breakpoints each trajectory stays on one closed-form arc, so the labels and
x_i'' are fixed there and V is exact at every event.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from ..model import arcs as _arcs
from ..model.errors import check_finite
from ..model.friction import Uniform
from ..model.profiles import Profile
from ..model.scene import Record, Scene
from ..solvers.driver import simulate


@dataclass(frozen=True)
class LyapunovTrace:
    """Two velocity trajectories and V of eq. (35), the result of lyapunov_trace.

    V = (v1 - v2)^2 / 2 of two runs of the same profile on a uniform surface from the
    velocities v10 and v20 (Sect. 6.2).  The samples form a uniform grid of
    ``samples_per_period`` per period plus every breakpoint.  Between consecutive breakpoints
    lie the sub-intervals, each labelled by whether both runs select the same element of the
    Sign set; the intervals merge neighbouring sub-intervals with the same label.

    Parameters
    ----------
    t, v1, v2, V, dV : numpy.ndarray
        The samples (Attributes).
    sub_start, sub_end, sub_equal, s1, s2, dV_start, dV_end : numpy.ndarray
        The sub-intervals (Attributes).
    interval_start, interval_end, interval_equal, period_V : numpy.ndarray
        The merged intervals and V per period (Attributes).
    converged_time : float
        The first time from which v1 = v2 for good (Attributes).

    Attributes
    ----------
    t : numpy.ndarray
        Sample times.
    v1 : numpy.ndarray
        Velocity x' of the first run at ``t``.
    v2 : numpy.ndarray
        Velocity x' of the second run at ``t``.
    V : numpy.ndarray
        (v1 - v2)^2 / 2 at ``t`` (eq. 35).
    dV : numpy.ndarray
        The right derivative V'(t+) (eq. 36; the left one at the last sample).
    sub_start : numpy.ndarray
        Start of each sub-interval.
    sub_end : numpy.ndarray
        End of each sub-interval.
    sub_equal : numpy.ndarray
        Whether both runs select the same Sign element on it.
    s1 : numpy.ndarray
        The Sign element the first run selects on it.
    s2 : numpy.ndarray
        The Sign element the second run selects on it.
    dV_start : numpy.ndarray
        V'(start+) of each sub-interval.
    dV_end : numpy.ndarray
        V'(end-) of each sub-interval.
    interval_start : numpy.ndarray
        Start of each merged interval.
    interval_end : numpy.ndarray
        End of each merged interval.
    interval_equal : numpy.ndarray
        The label of each merged interval.
    period_V : numpy.ndarray
        V at the period boundaries.
    converged_time : float
        The first time from which v1 = v2 exactly for good (NaN if not within the horizon).

    See Also
    --------
    lyapunov_trace : Computes it.

    Examples
    --------
    >>> import selfalign as sa
    >>> trace = sa.lyapunov_trace(sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9), 0.0, 0.5, 5)
    >>> trace.period_V.round(6).tolist()
    [0.125, 0.0, 0.0, 0.0, 0.0, 0.0]
    >>> round(trace.converged_time, 6)
    0.760526
    """

    t: np.ndarray
    v1: np.ndarray
    v2: np.ndarray
    V: np.ndarray
    dV: np.ndarray
    sub_start: np.ndarray
    sub_end: np.ndarray
    sub_equal: np.ndarray
    s1: np.ndarray
    s2: np.ndarray
    dV_start: np.ndarray
    dV_end: np.ndarray
    interval_start: np.ndarray
    interval_end: np.ndarray
    interval_equal: np.ndarray
    period_V: np.ndarray
    converged_time: float


class _Arcs:
    """One trajectory's arcs as arrays, evaluated at arbitrary times inside the run."""

    def __init__(self, profile, arcs):
        dt = float(profile.dt)
        self.profile = profile
        # Zero-length arcs hold no time and start where their neighbour does.
        arcs = arcs[arcs["duration"] > 0.0]
        self.kind = arcs["kind"].astype(int)
        self.start = arcs["period"] * dt + arcs["tau"]
        self.tau = arcs["tau"].copy()
        self.duration = arcs["duration"].copy()
        self.v0 = arcs["v"].copy()
        self.acc = arcs["acc"].copy()
        self.table_acc = arcs["table_acc"].copy()       # NaN on a smooth profile
        self.mode = arcs["mode"].astype(int)

    def locate(self, t, right=True):
        """Index of the arc holding each time: the one starting there (``right``) or ending there."""
        side = "right" if right else "left"
        return np.clip(np.searchsorted(self.start, t, side=side) - 1, 0, self.start.size - 1)

    def state(self, t, right=True):
        """(v, x'', mode, y'') at times t on the arcs :meth:`locate` picks (uniform surface)."""
        i = self.locate(t, right)
        s = np.clip(t - self.start[i], 0.0, self.duration[i])
        kind, v0, acc, mode = self.kind[i], self.v0[i], self.acc[i], self.mode[i]
        sigma = mode.astype(float)
        # y'': the arc's constant value on a piecewise-constant profile, else the profile at the
        # absolute time t itself (the same argument for both trajectories, so equal slips give
        # bit-equal x'' and V' = 0 exactly on "=" intervals).
        ydd = np.where(np.isnan(self.table_acc[i]), np.asarray(self.profile.acceleration(t), dtype=float),
                       self.table_acc[i])
        smooth = kind == _arcs.SMOOTH
        # Piecewise-constant slip: v = v0 + acc s (eqs. 15-20); Fourier slip: closed form
        # v = v0 - sigma s - (y'(t) - y'(t0)); stick: v = 0, x'' = 0.
        v = np.where(kind == _arcs.STICK, 0.0, v0 + acc * s)
        if smooth.any():
            yd = self.profile.velocity
            v = np.where(smooth, v0 - sigma * s - (np.asarray(yd(t)) - np.asarray(yd(self.start[i]))), v)
        xdd = np.where(kind == _arcs.STICK, 0.0, np.where(smooth, -ydd - sigma, acc))
        return v, xdd, mode, ydd


def _selected_sign(mode, ydd):
    """s in Sign(v) selected by the motion: the slip direction, or -y'' in stick (mu_bar = 1)."""
    return np.where(mode != 0, mode.astype(float), -ydd)


def _run(profile, v0, phase, periods):
    traj = simulate(Scene(profile, Uniform(), x0=0.0, v0=v0, phase=phase, periods=periods,
                          record=Record(arcs=True)), "exact")
    return _Arcs(profile, traj.arcs)


def _check(profile_or_scene, v10, v20, periods, phase, samples_per_period):
    if isinstance(profile_or_scene, Scene):
        if not isinstance(profile_or_scene.surface, Uniform):
            raise ValueError("the convergence analysis of Sect. 6.2 needs a uniform surface (mu_bar = 1); "
                             f"got {profile_or_scene.surface!r}")
        profile = profile_or_scene.profile
    elif isinstance(profile_or_scene, Profile):
        profile = profile_or_scene
    else:
        raise TypeError(f"lyapunov_trace needs a selfalign profile or Scene, got {type(profile_or_scene).__name__}")
    for name, value in (("v10", v10), ("v20", v20), ("phase", phase)):
        check_finite(name, value)
    if not 0.0 <= phase < 1.0:
        raise ValueError(f"phase must lie in [0, 1) (fraction of the period), got {phase!r}")
    for name, value, low in (("periods", periods, 1), ("samples_per_period", samples_per_period, 2)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise TypeError(f"{name} must be an integer, got {value!r} ({type(value).__name__})")
        if not isinstance(value, numbers.Integral) or value < low:
            raise ValueError(f"{name} must be an integer >= {low}, got {value!r}")
    return profile


def lyapunov_trace(profile_or_scene, v10: float, v20: float, periods: int, phase: float = 0.0,
                   samples_per_period: int = 200) -> LyapunovTrace:
    """V = (v1 - v2)^2 / 2 of two trajectories on a uniform surface (module docstring).

    Both start at time ``phase * dt`` (with a Scene, pass its ``phase``; only its
    profile is used here, see ``scene_trace``).

    The convergence analysis of Sect. 6.2 (eqs. 34-37, Fig. 13): two trajectories of
    v' in -Sign(v) - y''(t) (eq. 34) from the initial velocities v10 and v20, and the
    Lyapunov function V of eq. (35).  Along solutions V' = -(v1 - v2)(s1 - s2) (eq. 36),
    where s_i in Sign(v_i) is the element the motion selects: sign(v) in slip, -y''(t) in
    stick.  Intervals are labelled "=" where s1 = s2, so V' = 0, and "!=" where s1 != s2,
    so V' < 0 whenever V > 0.  Everything is computed from the exact solver's arcs: the
    breakpoints are both trajectories' event times and the period boundaries, and V is
    exact at every event (module docstring of ``selfalign.analysis.lyapunov``).

    Parameters
    ----------
    profile_or_scene : Profile or Scene
        The table motion, or a Scene on a uniform surface (only its profile is used).
    v10, v20 : float
        Initial relative velocities of the two trajectories; finite.
    periods : int
        Number of periods; >= 1.
    phase : float, optional
        Start time as a fraction of the period, in [0, 1).  Default 0.
    samples_per_period : int, optional
        Uniform samples per period besides the breakpoints; >= 2.  Default 200.

    Returns
    -------
    LyapunovTrace
        Samples ``t``, ``v1``, ``v2``, ``V`` and ``dV`` (the right derivative V'(t+), the
        left one at the last sample) on the uniform grid plus every breakpoint; the
        sub-intervals between breakpoints (``sub_start``, ``sub_end``, ``sub_equal``, the
        selected Sign elements ``s1``, ``s2``, and the one-sided derivatives ``dV_start``,
        ``dV_end``); ``interval_*``, which merge neighbouring sub-intervals with the same
        label; ``period_V``, V at the period boundaries; and ``converged_time``, the first
        time from which v1 = v2 exactly for good (NaN if not within the horizon).

    Raises
    ------
    TypeError
        If ``profile_or_scene`` is neither a profile nor a Scene, or ``v10``, ``v20``,
        ``phase``, ``periods`` or ``samples_per_period`` is not a number.
    ValueError
        If the Scene's surface is not uniform; ``v10``, ``v20`` or ``phase`` is not finite or
        ``phase`` lies outside [0, 1); ``periods`` is not an integer >= 1 or
        ``samples_per_period`` not an integer >= 2; or the exact solver cannot simulate the
        profile.
    KernelError
        If numba is missing or cannot compile the kernel (a RuntimeError).

    See Also
    --------
    floquet : The local stability of the steady state (Sect. 6.1).

    Examples
    --------
    The Fig. 18 profile: a mass at rest and one at v = 0.5 move in step from t = 0.76 on.

    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> trace = sa.lyapunov_trace(profile, 0.0, 0.5, periods=3)
    >>> trace.period_V.round(6).tolist(), round(trace.converged_time, 6)
    ([0.125, 0.0, 0.0, 0.0], 0.760526)
    >>> trace.interval_equal.tolist(), bool((trace.dV <= 0.0).all())
    ([False, True, False, True], True)
    """
    profile = _check(profile_or_scene, v10, v20, periods, phase, samples_per_period)
    dt = float(profile.dt)
    a, b = _run(profile, float(v10), phase, periods), _run(profile, float(v20), phase, periods)
    t0 = phase * dt
    boundaries = t0 + dt * np.arange(periods + 1)
    breaks = np.unique(np.concatenate([a.start, b.start, boundaries]))
    breaks = breaks[breaks <= boundaries[-1]]
    start, end = breaks[:-1], breaks[1:]
    mid = 0.5 * (start + end)

    # Labels from the arcs in force inside each sub-interval.
    _, _, m1, ydd = a.state(mid)
    _, _, m2, _ = b.state(mid)
    s1, s2 = _selected_sign(m1, ydd), _selected_sign(m2, ydd)
    equal = s1 == s2

    def derivative(t, right):
        """V' = (v1 - v2)(x1'' - x2'') (eq. 36) on the arcs starting (right) or ending at t."""
        va, xa, *_ = a.state(t, right)
        vb, xb, *_ = b.state(t, right)
        return (va - vb) * (xa - xb)

    dv_start, dv_end = derivative(start, True), derivative(end, False)

    grid = t0 + dt * np.arange(periods * samples_per_period + 1) / samples_per_period
    t = np.unique(np.concatenate([breaks, grid]))
    v1, *_ = a.state(t)
    v2, *_ = b.state(t)
    dV = derivative(t, True)
    dV[-1:] = derivative(t[-1:], False)
    V = 0.5 * (v1 - v2) ** 2

    # Merge neighbouring sub-intervals with equal labels.
    change = np.flatnonzero(np.diff(equal.astype(int))) + 1
    first = np.concatenate([[0], change])
    last = np.concatenate([change - 1, [equal.size - 1]])

    vb1, *_ = a.state(boundaries)
    vb2, *_ = b.state(boundaries)
    period_V = 0.5 * (vb1 - vb2) ** 2
    nonzero = np.flatnonzero(V != 0.0)
    if nonzero.size == 0:
        converged = float(t[0])
    elif nonzero[-1] < t.size - 1:
        converged = float(t[nonzero[-1] + 1])
    else:
        converged = float("nan")
    return LyapunovTrace(t=t, v1=v1, v2=v2, V=V, dV=dV, sub_start=start, sub_end=end, sub_equal=equal,
                         s1=s1, s2=s2, dV_start=dv_start, dV_end=dv_end, interval_start=start[first],
                         interval_end=end[last], interval_equal=equal[first], period_V=period_V,
                         converged_time=converged)


def scene_trace(scene: Scene, v20: float) -> LyapunovTrace:
    """The trace of a scene: trajectory 1 from its start.v0, trajectory 2 from ``v20``, both
    at its phase, over its ``periods`` with its ``samples_per_period``."""
    if scene.until != "periods":
        raise ValueError(f"scene {scene.name!r}: the convergence trace needs horizon.periods, not until: rest")
    return lyapunov_trace(scene, scene.v0, v20, int(scene.periods), scene.phase,
                          int(scene.record.samples_per_period))
