"""Closed-form steady state of the three-phase profile on a uniform surface (Sect. 5.1, 6.1).

Model (Sect. 3.2, mu_bar = 1): v = x' obeys v' in -y''(t) - Sign(v) with
y'' = 0 on the dwell [0, t1), -y2 on [t1, t2), +y3 on [t2, t3 = dt).  Write
L2 = t2 - t1, L3 = dt - t2 and u = y2 L2 = y3 L3 (the velocity swing,
eq. 63).  In each phase v is linear: forward slip (v > 0) has slope
-y'' - 1, backward slip (v < 0) slope -y'' + 1, and at v = 0 the mass sticks
iff |y''| <= 1 (a tie sticks), else it slips in the direction -sign(y'').
The steady state is unique (Sect. 6.2), so it suffices to exhibit one
periodic solution per case; the case itself is decided a priori by
:data:`selfalign.analysis.classification.DECISION_TREE`.  A useful identity: while v
keeps one sign from rest at t_a, v(t) = -(y'(t) - y'(t_a)) -+ (t - t_a), and
y' returns to its value after a full period.  Scaling t -> l t, x -> l^2 x
leaves the model invariant, so vbar(l dt, l^2 dy) = l vbar(dt, dy): vbar/dt
depends on (dt, dy) only through q.

Derivations (times are phases within the period; "rest at t" means v = 0):

Case 5, y2 <= 1 and y3 <= 1 (pure stick): v = 0 is consistent in every
phase.  vbar = 0, v0 = 0.

Case 1, y2 > 1 and y3 <= 1 (stick-slip, x' >= 0): from v >= 0 the mass can
never slip backward (that needs y'' > 1).  It cannot stay in forward slip
for a whole period either (v would drop by dt, eq. 37), and once at rest in
phase 3 or the dwell it sticks up to t1, so v(t1) = 0.  Forward slip then
runs with slope y2 - 1 to V2 = (y2 - 1) L2 at t2 and with slope -(1 + y3)
to rest at tc = t1 + F, F = L2 (y2 + y3) / (1 + y3) (eq. 21).  tc < t3
always (by the identity above v would reach -(t3 - t1) at t3): F + E =
t3 - t1 with E = u (y2 + y3) / (y2 y3 (1 + y3)) > 0, so the forward slip
started at t1 never wraps into the next period.  Stick on [tc, t3) and
[0, t1].  int v dt = V2 F / 2, v0 = 0.

Case 2, y2 <= 1 and y3 > 1 (stick-slip, x' <= 0): mirror image; v can never
become positive, cannot stay negative for a period, and any rest in the
dwell or phase 2 sticks up to t2, so v(t2) = 0.  Backward slip has slope
-(y3 - 1) in phase 3, reaching v(t3) = -W, W = (y3 - 1) L3, and wraps into
the next period with slope +1 in the dwell: rest at W if W <= t1, else
v(t1) = -(W - t1) and slope 1 + y2 in phase 2 gives rest at
t1 + (W - t1) / (1 + y2), always before t2.  With s1 = min(W, t1):
int v dt = -(W L3 / 2 + W s1 - s1^2 / 2 + (W - s1)^2 / (2 (1 + y2))), v0 = -W.

Case 3, y2 > 1, y3 > 1, v_back <= t1 (general stick-slip): stick is
possible only in the dwell, so a sticking steady state is at rest at t1 and
slips forward exactly as in case 1 up to the reversal at tc = t3 - E; it
then slips backward with slope -(y3 - 1) to v(t3) = -v_back,
v_back = D = (y3 - 1) E, and decelerates at 1 in the dwell, coming to rest
at D.  Consistent iff D <= t1.  int v dt = V2 F / 2 - D y3 E / 2, v0 = -D.

Case 4, y2 > 1, y3 > 1, D > t1 (slip-slip): no stick.  v(t1) < 0 (if it
were >= 0 the mass would stay forward all period), v crosses zero upwards in
phase 2 (slope y2 + 1, then y2 - 1) at ta and downwards in phase 3 (slope
-(1 + y3), then -(y3 - 1)) at tb (were either crossing missing, v would
keep one sign all period).  With v(0) = -b the one-period map is
b' = D + c4 (b - t1), c4 = (y2 - 1)(y3 - 1) / ((y2 + 1)(y3 + 1)) (eq. 33),
i.e. x'(t3) = c4 x'(0) + c5 with c5 = c4 t1 - D (eq. 32).  The fixed point
b = t1 + a, a = (D - t1) / (1 - c4) = (D - t1)(y2 + 1)(y3 + 1) / (2 (y2 + y3)),
is consistent (a > 0) exactly when D > t1, complementing case 3.
ta = t1 + a / (y2 + 1), V4 = (y2 - 1)(t2 - ta), tb = t2 + V4 / (1 + y3),
int v dt = -(a + b) t1 / 2 - a (ta - t1) / 2 + V4 (tb - ta) / 2 - b (t3 - tb) / 2,
v0 = -b.

Ties: |y''| = 1 sticks (case 1/2/5 boundaries belong to the sticking side).
The rule fixes labels only: at |y''| = 1 the slip slope from v = 0 is zero,
so stick and slip give the same motion.  D = t1 is case 3 (rest reached
exactly at t1, zero stick time); q = 1 (t1 = 0) is feasible.

Floquet (Sect. 6.1): the map of (x, x') at t = 0 over one period has
monodromy [[1, m12], [0, m22]] because x does not enter the dynamics.  A
velocity perturbation changes v by s(t) dv0 with s = 1 until the first
return to v = 0; a reversal at a crossing multiplies s by the ratio of the
slopes after/before it, a stick sets s = 0.  Hence m22 = 0 in cases 1, 2,
3, 5 and m22 = c4 in case 4, while m12 = int s dt: 0 in cases 1 and 5 (at
rest in the dwell), the time to rest in cases 2 and 3 (stick_start), and
ta + k2 (tb - ta) + c4 (t3 - tb), k2 = (y2 - 1)/(y2 + 1), in case 4.  Where
the one-period map has a kink (t1 = 0 in case 1 or in case 5 with y2 = 1,
D = t1) the right derivative (dv0 -> 0+) is returned; it matches the case
the tie rule assigns.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from .classification import DECISION_TREE, decision_quantities, profile_parameters

#: Normalisation of the objective function f = 1 / (c vbar^2) (eq. 11).
OBJECTIVE_SCALE = 1.0e4


@dataclass(frozen=True)
class SteadyState:
    """Steady state of the three-phase profile on a uniform surface.

    Floats from :func:`steady_state`, arrays from ``steady_state_grid``.
    ``vbar``: average velocity (eq. 10); ``f`` = 1 / (c vbar^2) (eq. 11, inf
    where vbar = 0); ``case``: Table 1 (0 = non-physical, then every other
    field is NaN); ``v0``: x' at the profile's t = 0; ``v_max``: the largest
    x' (at t2, 0 without forward slip).  Each motion mode occupies one
    interval [start, start + time) per period, taken modulo dt: ``*_start``
    is NaN when the mode never occurs, and ``*_time`` sums to dt.  The
    normalisation c of the objective is ``OBJECTIVE_SCALE`` = 1e4.

    Parameters
    ----------
    vbar, f, case, v0, v_max : float, int or numpy.ndarray
        The fields of the same names (Attributes): floats (``case`` an int) from
        :func:`~selfalign.steady_state`, arrays shaped like the broadcast inputs from
        ``steady_state_grid``.
    stick_start, stick_time, forward_start, forward_time : float or numpy.ndarray
        Likewise.
    backward_start, backward_time : float or numpy.ndarray
        Likewise.

    Attributes
    ----------
    vbar : float or numpy.ndarray
        Average velocity of the mass relative to the table (eq. 10).
    f : float or numpy.ndarray
        The objective 1 / (c vbar^2) (eq. 11); inf where vbar = 0.
    case : int or numpy.ndarray
        The case of Table 1 (0-5).
    v0 : float or numpy.ndarray
        x' at the profile's t = 0.
    v_max : float or numpy.ndarray
        The largest x' (at t2; 0 without forward slip).
    stick_start : float or numpy.ndarray
        Start of the stick interval within the period (NaN: never).
    stick_time : float or numpy.ndarray
        Length of the stick interval.
    forward_start : float or numpy.ndarray
        Start of the forward-slip interval (NaN: never).
    forward_time : float or numpy.ndarray
        Length of the forward-slip interval.
    backward_start : float or numpy.ndarray
        Start of the backward-slip interval (NaN: never).
    backward_time : float or numpy.ndarray
        Length of the backward-slip interval.

    See Also
    --------
    steady_state : Computes it for one profile.
    classify : The case alone.

    Examples
    --------
    >>> import selfalign as sa
    >>> state = sa.steady_state(sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9))
    >>> state.case, round(state.vbar, 6), round(state.f, 6)
    (1, 0.062297, 0.025767)
    >>> print(round(state.stick_time + state.forward_time + state.backward_time, 12))  # the period dt
    1.05
    """

    vbar: np.ndarray | float
    f: np.ndarray | float
    case: np.ndarray | int
    v0: np.ndarray | float
    v_max: np.ndarray | float
    stick_start: np.ndarray | float
    stick_time: np.ndarray | float
    forward_start: np.ndarray | float
    forward_time: np.ndarray | float
    backward_start: np.ndarray | float
    backward_time: np.ndarray | float


def _solve(dt, dy, y2, y3) -> dict[str, np.ndarray]:
    """Every steady-state quantity of the module docstring, selected by case."""
    qty = decision_quantities(dt, dy, y2, y3)
    case = DECISION_TREE.evaluate(qty)
    dt, y2, y3, t1, t2, u, D = (qty[k] for k in ("dt", "y2", "y3", "t1", "t2", "swing", "v_back"))
    nan = np.full(case.shape, np.nan)
    zero = np.zeros(case.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        L2, L3 = t2 - t1, dt - t2
        # Forward slip from rest at t1 (cases 1, 3).
        F = L2 * (y2 + y3) / (1.0 + y3)
        V2 = (y2 - 1.0) * L2
        E = u * (y2 + y3) / (y2 * y3 * (1.0 + y3))
        tc = t1 + F
        area_fwd = 0.5 * V2 * F
        # Case 2: backward slip from rest at t2, wrapping into the next dwell / phase 2.
        W = (y3 - 1.0) * L3
        s1 = np.minimum(W, t1)
        rest = W - s1
        stick2 = s1 + rest / (1.0 + y2)
        area2 = -(0.5 * W * L3 + W * s1 - 0.5 * s1 * s1 + 0.5 * rest * rest / (1.0 + y2))
        # Case 3: the case-1 forward slip, then backward slip until rest at D in the dwell.
        area3 = area_fwd - 0.5 * D * y3 * E
        # Case 4: fixed point of b' = D + c4 (b - t1) (eq. 32-33).
        c4 = (y2 - 1.0) * (y3 - 1.0) / ((y2 + 1.0) * (y3 + 1.0))
        a = (D - t1) * (y2 + 1.0) * (y3 + 1.0) / (2.0 * (y2 + y3))
        b = a + t1
        ta = t1 + a / (y2 + 1.0)
        V4 = (y2 - 1.0) * (t2 - ta)
        tb = t2 + V4 / (1.0 + y3)
        area4 = -0.5 * (a + b) * t1 - 0.5 * a * (ta - t1) + 0.5 * V4 * (tb - ta) - 0.5 * b * (dt - tb)
        m12_case4 = ta + (y2 - 1.0) / (y2 + 1.0) * (tb - ta) + c4 * (dt - tb)

    masks = [case == c for c in (1, 2, 3, 4, 5)]

    def pick(*per_case):
        """Select per point the value of its case (1-5); NaN for case 0."""
        return np.select(masks, per_case, np.nan)

    no_dwell = t1 == 0.0  # right derivative: x'(0) = 0+ slips forward at once if y2 >= 1
    out = {
        "case": case,
        "vbar": pick(area_fwd, area2, area3, area4, zero) / dt,
        "v0": pick(zero, -W, -D, -b, zero),
        "v_max": pick(V2, zero, V2, V4, zero),
        "stick_start": pick(tc, stick2, D, nan, zero),
        "stick_time": pick(dt - F, t2 - stick2, t1 - D, zero, dt),
        "forward_start": pick(t1, nan, t1, ta, nan),
        "forward_time": pick(F, zero, F, tb - ta, zero),
        "backward_start": pick(nan, t2, tc, tb, nan),
        "backward_time": pick(zero, L3 + stick2, E + D, dt - tb + ta, zero),
        "m12": pick(np.where(no_dwell, F, 0.0), stick2, D, m12_case4,
                    np.where(no_dwell & (y2 == 1.0), L2, 0.0)),
        "m22": pick(zero, zero, zero, c4, zero),
    }
    with np.errstate(divide="ignore"):
        out["f"] = 1.0 / (OBJECTIVE_SCALE * out["vbar"] ** 2)
    return out


def steady_state_grid(dt, dy, y2, y3) -> SteadyState:
    """Vectorised steady state over broadcast parameter arrays (case 0 where infeasible).

    Raises ValueError only for non-finite or non-positive inputs.
    """
    sol = _solve(dt, dy, y2, y3)
    return SteadyState(**{f.name: sol[f.name] for f in fields(SteadyState)})


def steady_state(profile_or_params) -> SteadyState:
    """Steady state of one ThreePhaseProfile (or (dt, dy, y2, y3) tuple / mapping), as floats.

    The closed form of Sects. 5.1 and 6.1 on a uniform surface (mu_bar = 1): the case of
    Table 1 is decided a priori (:func:`~selfalign.classify`) and one periodic solution is
    exhibited per case; it is the steady state, which is unique (Sect. 6.2).  The
    derivations are in the docstring of the module ``selfalign.analysis.steady_state``.
    Scaling t -> l t, x -> l^2 x leaves the model invariant, so
    vbar(l dt, l^2 dy) = l vbar(dt, dy).  ``selfalign.analysis.steady_state.steady_state_grid``
    computes whole grids.

    Parameters
    ----------
    profile_or_params : ThreePhaseProfile, dict or tuple
        A :class:`~selfalign.ThreePhaseProfile`, a mapping with the keys
        dt, dy, y2, y3 (a ``kind`` key, if any, must be "three_phase"), or a tuple or list
        (dt, dy, y2, y3).

    Returns
    -------
    SteadyState
        Floats (``case`` an int); for a non-physical profile (case 0) every other field is
        NaN.

    Raises
    ------
    TypeError
        If the argument is none of these, or a parameter is not a real number.
    ValueError
        If the tuple does not hold 4 parameters, the mapping names another kind or misses a
        key, or a parameter is not finite and > 0.

    See Also
    --------
    classify : The case of Table 1 alone.
    floquet : The stability of the steady state (Sect. 6.1).

    Examples
    --------
    The Fig. 18 profile (case 1) and a slip-slip profile of Fig. 9 (case 4):

    >>> import selfalign as sa
    >>> state = sa.steady_state(sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9))
    >>> print(state.case, round(state.vbar, 6), round(state.f, 6), state.v0)
    1 0.062297 0.025767 0.0
    >>> state = sa.steady_state((1.0, 0.084, 1.4, 1.3))
    >>> print(state.case, round(state.vbar, 6), round(state.v0, 6), state.stick_time)
    4 0.009778 -0.12723 0.0
    """
    grid = steady_state_grid(*profile_parameters(profile_or_params))
    values = {f.name: float(getattr(grid, f.name)) for f in fields(SteadyState)}
    values["case"] = int(grid.case)
    return SteadyState(**values)


def monodromy_grid(dt, dy, y2, y3) -> np.ndarray:
    """Monodromy matrices (..., 2, 2) of the period map of (x, x') at t = 0 (eqs. 25-33)."""
    sol = _solve(dt, dy, y2, y3)
    shape = sol["case"].shape
    feasible = sol["case"] > 0
    mono = np.empty(shape + (2, 2))
    mono[..., 0, 0] = np.where(feasible, 1.0, np.nan)
    mono[..., 1, 0] = np.where(feasible, 0.0, np.nan)
    mono[..., 0, 1] = sol["m12"]
    mono[..., 1, 1] = sol["m22"]
    return mono


def monodromy_analytic(profile_or_params) -> np.ndarray:
    """2x2 monodromy matrix at t = 0 of one profile (NaN for case 0)."""
    return monodromy_grid(*profile_parameters(profile_or_params))


def floquet_multipliers_analytic(profile_or_params) -> np.ndarray:
    """Floquet multipliers (1, lambda2): lambda2 = c4 (eq. 33) in case 4, else 0."""
    mono = monodromy_analytic(profile_or_params)
    return np.array([mono[0, 0], mono[1, 1]])


def _phase_step(v, accel, length):
    """Exact flow of v' in -accel - Sign(v) over a phase of constant y'' = accel.

    At most one return to v = 0 happens per phase; after it the mass sticks
    (|accel| <= 1) or slips in the direction -sign(accel).  Returns the end
    velocity and int v dt over the phase.
    """
    slope = np.where(v > 0.0, -accel - 1.0, np.where(v < 0.0, 1.0 - accel, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        t_zero = np.where(v == 0.0, 0.0, np.where(slope * v < 0.0, -v / slope, np.inf))
    hits = t_zero <= length
    tau1 = np.where(hits, t_zero, length)
    tau2 = length - tau1
    after = np.where(np.abs(accel) <= 1.0, 0.0, np.where(accel < 0.0, -accel - 1.0, 1.0 - accel))
    after = np.where(hits, after, 0.0)
    v_end = np.where(hits, after * tau2, v + slope * length)
    area = v * tau1 + 0.5 * slope * tau1 * tau1 + 0.5 * after * tau2 * tau2
    return v_end, area


def one_period_map(dt, dy, y2, y3, v0):
    """(x'(dt), x(dt) - x(0)) from x'(0) = v0, for any v0 (vectorised, exact).

    Makes no assumption on the case: used to verify the closed forms and to
    difference the period map.  NaN where the profile is infeasible or v0 is NaN.
    """
    v = np.asarray(v0, dtype=float)
    if np.isinf(v).any():
        raise ValueError("v0 must be finite (NaN entries propagate)")
    qty = decision_quantities(dt, dy, y2, y3)
    dt, y2, y3, t1, t2 = (qty[k] for k in ("dt", "y2", "y3", "t1", "t2"))
    v = v + 0.0 * dt
    displacement = 0.0
    for accel, length in ((0.0, t1), (-y2, t2 - t1), (y3, dt - t2)):
        v, area = _phase_step(v, accel, length)
        displacement = displacement + area
    return v, displacement
