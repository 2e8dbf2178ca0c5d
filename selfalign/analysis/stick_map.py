"""The stick-position mapping x_n -> x_{n+1} in the friction transition zone (Sect. 7.3).

A mass stuck at x_n in the transition zone x_mu <= x_n < x_f of a three-phase
profile (x_f = (b2 + y2)/b1, where mu_bar = y2) stays stuck through the dwell
[0, t1), starts to slip forward at t1 (y'' jumps to -y2, |y''| > mu_bar), moves
as the forced oscillator of eq. (42) through [t1, t2), switches forcing at t2
and sticks again where its velocity vanishes: x_{n+1} of eq. (59).

Erratum: eq. (54) of the paper prints d_{1,2} = x(t2 - t1) - b_{3,1}/b_1; the
centre of the oscillation after t2 is b_{3,2}/b_1, so d_{1,2} = x(t2 - t1) -
b_{3,2}/b_1.  Eq. (59) itself is right (it follows from the corrected form),
and so is its fixed point eq. (60).  Eq. (58) picks the arcsin branch, which
is the first zero of x' only while d_{1,2} > 0; the time is computed here
with atan2, valid for both signs.

The fixed point x_f = (b2 + y2)/b1 (eq. 60) equals x_stick_min of eq. (41)
only when y2 >= y3 (eq. 41 uses max(y2, y3)); for y3 > y2 it lies below
x_stick_min and is no end position (a mass stuck there slips backward in the
y3 phase).

Static friction mu_s = r mu_k (r > 1): a mass stuck at x_n slips at t1 only if
y2 > r mu_bar(x_n), i.e. x_n < x_s = x_mu + w (y2/r - 1)/(c_mu - 1)
(:func:`stick_map_slip_limit`), and the slip runs against the kinetic mu_bar, so eq. (59)
with the Coulomb constants (b1, b2, x_f) still gives x_{n+1} for x_n < x_s; from x_s on the
mass stays where it is.  The map is thus eq. (59) below x_s and the identity above.  Its only
fixed point in the zone, x_f, lies above x_s, and eq. (59) exceeds the identity below x_f:
a stick below x_s moves on by at least x_{n+1}(x_n) - x_n >= min over [x_n, x_s] > 0, so the
sticks pass x_s after finitely many steps and rest (:func:`stick_sequence`); no accumulation.

What the map means, precisely: x_{n+1} is the position of the first stick
event after t = 0 of a mass that is stuck at x_n at t = 0 (the start of the
dwell).  :func:`stick_map_simulated` measures exactly that with a solver;
``stick_map_validity`` tells where eq. (59) describes it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.errors import check_real_array
from ..model.friction import StopZone, level_position
from ..model.profiles import ThreePhaseProfile
from ..model.registry import formula


@dataclass(frozen=True)
class StickMapConstants:
    """b1, b2 of eq. (42), omega = sqrt(b1), the slip window T = t2 - t1 and the
    fixed point x_f = (b2 + y2) / b1 of eq. (60) (= x_stick_min iff y2 >= y3)."""

    b1: float
    b2: float
    omega: float
    slip_window: float
    fixed_point: float


def stick_map_constants(profile: ThreePhaseProfile, zone: StopZone) -> StickMapConstants:
    if not isinstance(profile, ThreePhaseProfile):
        raise TypeError("the closed-form stick map (eq. 59) is derived for a ThreePhaseProfile")
    if zone.c_mu <= 1.0:
        raise ValueError(f"the stick map needs c_mu > 1 (a transition zone with rising friction), got {zone.c_mu!r}")
    b1 = zone.b1
    b2 = b1 * zone.x_mu - 1.0  # the constant term of mu_bar in eq. (42)
    return StickMapConstants(b1=b1, b2=b2, omega=float(np.sqrt(b1)), slip_window=profile.t2 - profile.t1,
                             fixed_point=zone.x_mu + level_position(profile.y2, zone.w, zone.c_mu))


def _positions(x_n) -> np.ndarray:
    """x_n as a float array; TypeError unless its entries are real numbers, ValueError unless every
    entry is finite."""
    x_n = check_real_array("x_n", x_n)
    if not np.all(np.isfinite(x_n)):
        raise ValueError(f"x_n must be finite stick positions; got {x_n[~np.isfinite(x_n)].ravel()[:3].tolist()}")
    return x_n


@formula(eqs=("53", "54", "55"), kernel=False)
def _offsets(x_n, c: StickMapConstants, profile: ThreePhaseProfile):
    """(d_{1,2}, d_{2,2}) of eqs. (53)-(55), erratum applied, and the phase omega (t2 - t1)."""
    d11 = x_n - c.fixed_point  # d_{1,1} of eq. (49)
    phase = c.omega * c.slip_window
    return (profile.y2 + profile.y3) / c.b1 + d11 * np.cos(phase), -d11 * np.sin(phase), phase


@formula(eqs=("59",), kernel=False)
def stick_map(x_n, profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float):
    """x_{n+1}(x_n) of eq. (59), vectorised over ``x_n``.

    Valid while the assumptions of Sect. 7.3 hold (the mass slips forward
    from t1, the velocity stays positive until after t2, and it sticks
    again inside the transition zone during the y3'' part); use
    ``stick_map_validity`` to check them.
    A mass stuck at x_n in the transition zone x_mu <= x_n < x_f (where
    mu_bar = y2) stays stuck through the dwell [0, t1), slips forward at t1,
    moves as the forced oscillator of eq. (42) through [t1, t2), switches
    forcing at t2 and sticks again where its velocity vanishes: x_{n+1} is the
    position of the first stick event after t = 0 of a mass stuck at x_n at
    t = 0.  The map's fixed point is x_f = (b2 + y2) / b1 (eq. 60), which is
    x_stick_min of eq. (41) only when y2 >= y3, and its derivative there is
    cos(omega (t2 - t1)).  The paper's eq. (54) has an erratum (d_{1,2} uses
    b_{3,2}, not b_{3,1}); eq. (59) itself is right (module docstring of
    ``selfalign.analysis.stick_map``).

    Parameters
    ----------
    x_n : array_like
        Stick positions (absolute); finite.
    profile : ThreePhaseProfile
        The table motion (the closed form is derived for the three-phase profile).
    w : float
        Width of the body, the transition width (eqs. 7-9); > 0.
    c_mu : float
        Coefficient of the high-friction region; > 1.
    x_mu : float
        Start of the high-friction region.

    Returns
    -------
    numpy.ndarray or numpy.float64
        x_{n+1} of every x_n, shaped like ``x_n``.

    Raises
    ------
    TypeError
        If ``profile`` is not a ThreePhaseProfile, ``x_n`` does not hold real numbers, or
        ``w``, ``c_mu`` or ``x_mu`` is not a real number.
    ValueError
        If the zone is invalid (see :class:`~selfalign.StopZone`),
        ``c_mu`` <= 1, or an ``x_n`` is not finite.

    See Also
    --------
    positioning : Simulated entries into the zone, whose sticks this map describes.

    Examples
    --------
    The Fig. 18 profile on a zone of width 0.05: sticks accumulate at the fixed point
    x_f = x_mu + w (y2 - 1) / (c_mu - 1) = 0.54.

    >>> import selfalign as sa
    >>> profile = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    >>> x = [0.52]
    >>> for _ in range(4):
    ...     x.append(float(sa.stick_map(x[-1], profile, w=0.05, c_mu=2.5, x_mu=0.5)))
    >>> [round(value, 6) for value in x]
    [0.52, 0.538842, 0.539828, 0.539974, 0.539996]
    >>> sa.stick_map([0.52, 0.54], profile, w=0.05, c_mu=2.5, x_mu=0.5).round(6).tolist()
    [0.538842, 0.54]
    """
    c = stick_map_constants(profile, StopZone(x_mu=x_mu, w=w, c_mu=c_mu))
    d12, d22, _ = _offsets(_positions(x_n), c, profile)
    return c.fixed_point - (profile.y2 + profile.y3) / c.b1 + np.hypot(d12, d22)  # (b2 - y3)/b1 + ...


def stick_map_contraction(profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float) -> float:
    """d x_{n+1} / d x_n at the fixed point (from eq. 59: cos(omega (t2 - t1)))."""
    c = stick_map_constants(profile, StopZone(x_mu=x_mu, w=w, c_mu=c_mu))
    return float(np.cos(c.omega * c.slip_window))


def stick_map_threshold(profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float) -> float:
    """The x_n < x_f whose image is the fixed point: x_{n+1}(x_c) = x_f (middle line of Fig. 18).

    From eq. (59) with d = x_n - x_f and K = (y2 + y3)/b1: x_{n+1} = x_f iff
    (K + d cos)^2 + (d sin)^2 = K^2, i.e. d (d + 2 K cos(omega (t2 - t1))) = 0, so
    x_c = x_f - 2 K cos(omega (t2 - t1)).  Eq. (59) is convex in x_n, hence it maps
    (x_c, x_f) below x_f (accumulation) and x_n < x_c beyond it (rest there); the
    sufficient condition x_{n+1}(x_mu) < x_f of Sect. 7.3 is x_mu > x_c.
    """
    c = stick_map_constants(profile, StopZone(x_mu=x_mu, w=w, c_mu=c_mu))
    return c.fixed_point - 2.0 * (profile.y2 + profile.y3) / c.b1 * np.cos(c.omega * c.slip_window)


def stick_map_slip_limit(profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float,
                         ratio: float = 1.0) -> float:
    """x_s: a mass stuck at x_n >= x_s stays stuck under static friction mu_s = ``ratio`` mu_k
    (y2 <= r mu_bar(x_n)); x_s = x_mu + w (y2/r - 1)/(c_mu - 1), the fixed point x_f at r = 1."""
    if not ratio >= 1.0:
        raise ValueError(f"ratio (mu_s/mu_k) must be >= 1, got {ratio!r}")
    StopZone(x_mu=x_mu, w=w, c_mu=c_mu)  # validates the zone
    return x_mu + level_position(profile.y2 / ratio, w, c_mu)


@dataclass(frozen=True)
class StickSequence:
    """Stick positions x_0, x_1, ... of the map (eq. 59 below x_s, the identity above).
    ``rests``: the last one lies at or beyond x_s, where the mass stays for good;
    ``valid``: eq. (59)'s assumptions held at every step taken."""

    x: np.ndarray
    rests: bool
    valid: bool


def stick_sequence(x0: float, profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float,
                   ratio: float = 1.0, max_sticks: int = 1000) -> StickSequence:
    """The stick positions from a mass stuck at ``x0`` at t = 0 under static friction
    mu_s = ``ratio`` mu_k: eq. (59) while x_n < x_s (:func:`stick_map_slip_limit`), until a
    stick lands at or beyond x_s (rest), eq. (59) leaves its assumptions
    (``stick_map_validity``) or ``max_sticks`` steps are taken (at r = 1 the sticks
    accumulate at x_f and never reach it)."""
    x_s = stick_map_slip_limit(profile, w=w, c_mu=c_mu, x_mu=x_mu, ratio=ratio)
    kw = {"w": w, "c_mu": c_mu, "x_mu": x_mu}
    x = [float(x0)]
    while x[-1] < x_s and len(x) <= max_sticks:
        if not stick_map_validity(x[-1], profile, **kw, ratio=ratio).valid:
            return StickSequence(np.array(x), rests=False, valid=False)
        x.append(float(stick_map(x[-1], profile, **kw)))
    return StickSequence(np.array(x), rests=x[-1] >= x_s, valid=True)


@dataclass(frozen=True)
class StickMapValidity:
    """Which assumptions of eq. (59) hold at each x_n (boolean arrays shaped like x_n).

    ``in_zone``: x_mu <= x_n <= x_mu + w.  ``slips_at_t1``: y2 > r mu_bar(x_n),
    i.e. x_n < x_s (x_f at r = 1, :func:`stick_map_slip_limit`).  ``moving_at_t2``: the slip does not end before t2,
    omega (t2 - t1) < pi.  ``stays_in_zone``: x_{n+1} <= x_mu + w (x grows
    monotonically during the slip, so the whole slip is harmonic).
    ``stops_in_phase3``: v reaches 0 before the period ends, t2 + tau_stop <= dt.
    ``sticks``: y3 <= r mu_bar(x_{n+1}), so v = 0 is a stick, not a reversal.
    ``valid``: all of them.  ``stop_time``: t2 + tau_stop (phase of the new stick).
    """

    in_zone: np.ndarray
    slips_at_t1: np.ndarray
    moving_at_t2: np.ndarray
    stays_in_zone: np.ndarray
    stops_in_phase3: np.ndarray
    sticks: np.ndarray
    stop_time: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        return (self.in_zone & self.slips_at_t1 & self.moving_at_t2 & self.stays_in_zone
                & self.stops_in_phase3 & self.sticks)


def stick_map_validity(x_n, profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float,
                       ratio: float = 1.0) -> StickMapValidity:
    """Check the assumptions of eq. (59) at ``x_n`` (see :class:`StickMapValidity`) under static
    friction mu_s = ``ratio`` mu_k (1: the paper's Coulomb friction)."""
    zone = StopZone(x_mu=x_mu, w=w, c_mu=c_mu)
    c = stick_map_constants(profile, zone)
    x_n = _positions(x_n)
    d12, d22, phase = _offsets(x_n, c, profile)
    x_next = stick_map(x_n, profile, w=w, c_mu=c_mu, x_mu=x_mu)
    moving = bool(0.0 < phase < np.pi)
    # Time from t2 to v = 0 on the second harmonic arc: eq. (58) with atan2.
    stop_time = profile.t2 + np.arctan2(d22, d12) / c.omega
    return StickMapValidity(
        in_zone=(x_n >= x_mu) & (x_n <= zone.x_end),
        slips_at_t1=x_n < stick_map_slip_limit(profile, w=w, c_mu=c_mu, x_mu=x_mu, ratio=ratio),
        moving_at_t2=np.full(x_n.shape, moving),
        stays_in_zone=x_next <= zone.x_end,
        stops_in_phase3=stop_time <= profile.dt,
        sticks=profile.y3 <= ratio * zone.coefficient(x_next),
        stop_time=stop_time,
    )


def stick_map_simulated(x_n, profile: ThreePhaseProfile, *, w: float, c_mu: float, x_mu: float,
                        method: str = "batch"):
    """x_{n+1} measured by a solver: the first stick after t = 0 of a mass stuck at x_n at t = 0.

    ``method="batch"`` runs all x_n together with :func:`selfalign.simulate_batch`;
    ``method="exact"`` runs one :func:`selfalign.simulate` per x_n and reads the first
    STICK event of its event log.  A mass at rest for good at x_n maps to x_n; NaN
    where no stick follows within two periods.
    """
    if method not in ("batch", "exact"):
        raise ValueError(f"method must be 'batch' or 'exact', got {method!r}")
    if not isinstance(profile, ThreePhaseProfile):
        raise TypeError("stick_map_simulated needs a ThreePhaseProfile")
    x_n = _positions(x_n)
    StopZone(x_mu=x_mu, w=w, c_mu=c_mu)  # validates the zone before any run
    if method == "batch":
        from ..solvers.driver import simulate_batch
        from ..solvers.outcomes import Reason

        res = simulate_batch(profile, x_n.ravel(), 0.0, 0.0, x_mu=x_mu, w=w, c_mu=c_mu, until="stick", max_periods=2)
        found = (res.reason == Reason.REST) | (res.reason == Reason.FIRST_STICK)
        return np.where(found, res.x_end, np.nan).reshape(x_n.shape)

    from ..model.scene import Record, Scene
    from ..solvers.driver import simulate
    from ..solvers.outcomes import EventKind, Status

    out = np.full(x_n.size, np.nan)
    zone = StopZone(x_mu=x_mu, w=w, c_mu=c_mu)
    for i, x in enumerate(x_n.ravel()):
        traj = simulate(Scene(profile, zone, x0=float(x), v0=0.0, phase=0.0, periods=2,
                              record=Record(events=True)), method="exact")
        sticks = traj.events[traj.events["kind"] == EventKind.STICK]
        if sticks.size:
            out[i] = sticks["x"][0]
        elif traj.status is Status.REST or traj.info.get("at_rest"):
            out[i] = x
    return out.reshape(x_n.shape)
