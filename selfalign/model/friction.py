"""Friction fields mu_bar(x) of the table surface (Sect. 3.3, eqs. 7-9) and the stick rule.

Coefficients are dimensionless: the low-friction coefficient mu is the unit
(Sect. 3.2), so the uniform surface has mu_bar = 1.  Positions in the formulas are
relative to the start of the high-friction region, xi = x - x_mu.

The scalar formulas (:func:`coefficient`, :func:`transition_slope`, :func:`decide_mode`,
:func:`level_position`, ``stick_limit``, :func:`static_stick_limit`, :func:`stribeck_factor`)
are the only place the friction law is written; the classes below, :data:`stick_limits` and
:data:`static_stick_limits` (elementwise) and the compiled event kernel call them.

The field mu_bar(x) is the kinetic coefficient.  A :class:`FrictionLaw` adds what the
paper leaves out (its recommendation (3), Sect. 8): a static coefficient mu_s = r mu_k (r = ``mu_s_over_mu_k``
>= 1, the same ratio on both sides of the stop zone, which scales both), so a stuck
mass stays stuck while |y''| <= r mu_bar(x) and slips against mu_bar(x); and optionally
the Stribeck (velocity-weakening) law mu(v) = mu_k + (mu_s - mu_k) exp(-(|v|/v_s)^delta)
of Armstrong-Helouvry, Dupont & Canudas de Wit, Automatica 30 (1994) 1083-1138, in the
form of Olsson et al., Eur. J. Control 4 (1998) 176-195.  The default law
(r = 1) is the paper's Coulomb friction.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import check_finite, check_positive
from .registry import formula


@formula(eqs=("7", "8", "9"))
def coefficient(xi: float, w: float, c_mu: float) -> float:
    """mu_bar at xi = x - x_mu for a body of width ``w`` (eqs. 7-9, mu = 1).

    The overlap with the high-friction region is z = min(max(xi, 0), w) (eq. 8) and
    mu_bar = (w + (c_mu - 1) z) / w (eq. 7), i.e. 1 before the region, c_mu once the
    body lies on it entirely, and linear in between (eq. 9).  The two ends are exact.
    """
    if xi <= 0.0:
        return 1.0
    if xi >= w:
        return c_mu
    return 1.0 + (c_mu - 1.0) * (xi / w)


@formula(unnumbered="b1 = (c_mu - 1) / w, the slope of eq. (9), named in the text of eq. (42)")
def transition_slope(c_mu: float, w: float) -> float:
    """b1 = (c_mu - 1) / w: the slope of mu_bar in the transition zone (eq. 9), the stiffness of the
    forced oscillator of eq. (42)."""
    return (c_mu - 1.0) / w


@formula(unnumbered="the stick condition |y''| < 1 of Sect. 3.2, stated in words after eq. (6), with the tie "
                    "|y''| = mu_bar sticking (the set-valued Sign of eq. 2 allows it)")
def decide_mode(a: float, mu: float) -> int:
    """Mode at zero relative velocity under table acceleration ``a`` (Sect. 3.2).

    Stick (0) iff |a| <= mu: the friction force can balance the inertial force
    (the tie |a| = mu sticks, which the set-valued Sign of eq. 2 allows).  Otherwise
    slip in the direction -sign(a): forward (+1) if a < -mu, backward (-1) if a > mu.
    """
    if a > mu:
        return -1
    if a < -mu:
        return 1
    return 0


_BEYOND = "the Stribeck law is beyond the paper (its recommendation (3), enhanced friction models)"


@formula(unnumbered=_BEYOND)
def stribeck_decay(speed: float, v_s: float, delta: float) -> float:
    """exp(-(|v| / v_s)^delta) at slip speed |v|: 1 at rest, falling to 0 for |v| >> v_s (the
    weight of the static excess in :func:`stribeck_factor`)."""
    return math.exp(-((speed / v_s) ** delta))


@formula(unnumbered=_BEYOND)
def stribeck_factor(speed: float, ratio: float, v_s: float, delta: float) -> float:
    """mu(v) / mu_k = 1 + (r - 1) exp(-(|v| / v_s)^delta) at slip speed |v| (Stribeck law).

    r at v = 0 (the static coefficient), decreasing to 1 (kinetic) for |v| >> v_s.
    """
    return 1.0 + (ratio - 1.0) * stribeck_decay(speed, v_s, delta)


@formula(eqs=("40", "60"))
def level_position(acceleration: float, w: float, c_mu: float) -> float:
    """xi = x - x_mu at which the transition zone's mu_bar (eq. 9, continued as a line) equals
    ``acceleration``: w (acceleration - 1) / (c_mu - 1).

    It solves eq. (40) for max|y''|, and for y2'' it is the fixed point x_f - x_mu =
    (b2 + y2'') / b1 - x_mu of the stick map (eq. 60).  No clamping: below 1 it lies before
    the zone, above c_mu beyond it (``stick_limit`` clamps).
    """
    return w * (acceleration - 1.0) / (c_mu - 1.0)


@formula(eqs=("41",))
def stick_limit(max_acceleration: float, w: float, c_mu: float) -> float:
    """x_stick_min - x_mu of eq. (41): where mu_bar first reaches max|y''| (eq. 40, :func:`level_position`).

    ``-inf`` when max|y''| <= 1 (the mass can stick anywhere) and ``+inf`` when
    max|y''| > c_mu (it can stick nowhere for good).
    """
    if max_acceleration <= 1.0:
        return -math.inf
    if max_acceleration > c_mu:
        return math.inf
    return level_position(max_acceleration, w, c_mu)


@formula(unnumbered="eq. (41) under static friction mu_s = r mu_k, beyond the paper (its recommendation (3), "
                    "enhanced friction models)")
def static_stick_limit(rest_acceleration: float, ratio: float, w: float, c_mu: float) -> float:
    """x_stick_min - x_mu under static friction mu_s = ``ratio`` mu_k: permanent stick needs
    r mu_bar >= max|y''| (``rest_acceleration``), so it is ``stick_limit`` (eq. 41) of
    max|y''| / r.  At r = 1 (the paper's Coulomb law) it is eq. (41) itself."""
    return stick_limit(rest_acceleration / ratio, w, c_mu)


#: ``stick_limit`` elementwise on broadcast arrays (the design search and the positioning grid).
stick_limits = np.vectorize(stick_limit, otypes=[float])
#: :func:`static_stick_limit` elementwise on broadcast arrays (the positioning grid).
static_stick_limits = np.vectorize(static_stick_limit, otypes=[float])

#: Largest |x_mu| / w of a stop zone: positions are reported as x_mu + xi, and doubles near
#: |x_mu| = 2**32 w are 2**-20 w apart, so beyond it they resolve the transition width w of
#: eqs. (7-9) in fewer than a million steps (x_mu = 1e308 with w = 0.05: not at all).
MAX_ZONE_POSITION = 2.0**32


def check_zone_position(x_mu, w) -> None:
    """ValueError unless every |x_mu| <= :data:`MAX_ZONE_POSITION` w (scalars or arrays)."""
    x_mu, w = np.broadcast_arrays(np.asarray(x_mu, dtype=float), np.asarray(w, dtype=float))
    bad = np.abs(x_mu) / MAX_ZONE_POSITION > w
    if np.any(bad):
        x, width = float(x_mu[bad].ravel()[0]), float(w[bad].ravel()[0])
        raise ValueError(f"stop zone x_mu = {x!r} is more than 2**32 times its width w = {width!r} from 0: doubles "
                         f"there are {np.spacing(abs(x)):.3g} apart and cannot resolve the transition of width w "
                         f"(eqs. 7-9) in the positions x_mu + xi; put the origin near the zone (positions are "
                         f"relative)")


class Uniform:
    """Uniform Coulomb friction, mu_bar(x) = 1 everywhere.

    The table surface without a stop zone: the low-friction coefficient mu is the unit
    (Sect. 3.2), so the coefficient is 1 at every position.  The steady state, its
    classification and its stability (Sects. 5 and 6) are taken on this surface.  All
    instances are equal.

    Attributes
    ----------
    kind : str
        ``"uniform"``, the surface kind of scene files.
    position_dependent : bool
        False: mu_bar does not depend on x.

    See Also
    --------
    StopZone : A surface with a high-friction region.
    Scene : Takes the surface (the default is ``Uniform()``).

    Examples
    --------
    >>> import selfalign as sa
    >>> surface = sa.Uniform()
    >>> surface.coefficient([-1.0, 0.0, 2.5]).tolist()
    [1.0, 1.0, 1.0]
    >>> surface == sa.Uniform(), surface.params()
    (True, {'kind': 'uniform'})
    """

    kind = "uniform"
    position_dependent = False

    def coefficient(self, x):
        return np.ones_like(np.asarray(x, dtype=float))

    def params(self) -> dict:
        return {"kind": self.kind}

    def __repr__(self):
        return "Uniform()"

    def __eq__(self, other):
        return isinstance(other, Uniform)

    def __hash__(self):
        return hash(self.kind)


class StopZone:
    """A high-friction region starting at ``x_mu`` with coefficient ``c_mu`` (times mu).

    A body of width ``w`` sees the weighted coefficient of eq. (7) with the
    overlap z of eq. (8): mu_bar rises linearly from 1 at x_mu to c_mu at
    x_mu + w (eq. 9) and stays there.  Before x_mu the surface has the
    low-friction coefficient mu, the unit (Sect. 3.2).

    Parameters
    ----------
    x_mu : float
        Start of the high-friction region (dimensionless position).  At most
        ``MAX_ZONE_POSITION`` = 2**32 times ``w`` from 0: positions are reported as x_mu + xi,
        and farther out doubles cannot resolve the transition of width w (put the origin near
        the zone; positions are relative).
    w : float
        Width of the body, which is the width of the transition (eqs. 7-9); > 0.
    c_mu : float
        Coefficient of the high-friction region in units of mu; >= 1 (1: friction 1
        everywhere, a uniform surface with its origin at x_mu).

    Attributes
    ----------
    x_mu : float
        Start of the high-friction region.
    w : float
        Width of the transition, the body's width.
    c_mu : float
        Coefficient of the high-friction region, in units of mu.
    b1 : float
        Slope of mu_bar in the transition region, (c_mu - 1) / w (eq. 42).
    x_end : float
        End of the transition region, x_mu + w.
    kind : str
        ``"stop_zone"``, the surface kind of scene files.
    position_dependent : bool
        True: mu_bar depends on x.

    Raises
    ------
    TypeError
        If ``x_mu``, ``w`` or ``c_mu`` is not a real number (int, float or numpy scalar; bool is
        refused).
    ValueError
        If one of them is not finite, ``w`` <= 0, ``c_mu`` < 1, the transition slope
        (c_mu - 1) / w overflows, or ``|x_mu| > 2**32 w``.

    See Also
    --------
    Uniform : The surface without a stop zone.
    positioning : Where the steady-state entries into a stop zone end (Sect. 7).

    Examples
    --------
    >>> import selfalign as sa
    >>> zone = sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)
    >>> zone.coefficient([0.4, 0.525, 0.6]).round(6).tolist()
    [1.0, 1.75, 2.5]
    >>> print(round(zone.b1, 6), round(zone.x_end, 6))
    30.0 0.55

    x_stick_min of eq. (41), where permanent stick becomes possible, for max ``|y''|`` = 2.2:

    >>> print(round(zone.x_stick_min(2.2), 6), zone.x_stick_min(0.9), zone.x_stick_min(3.0))
    0.54 -inf inf
    """

    kind = "stop_zone"
    position_dependent = True

    def __init__(self, x_mu: float, w: float, c_mu: float):
        self.x_mu = check_finite("x_mu", x_mu)
        self.w = check_positive("w", w)
        self.c_mu = check_finite("c_mu", c_mu)
        if self.c_mu < 1.0:
            raise ValueError(f"c_mu must be >= 1 (the zone has higher friction), got {c_mu!r}")
        if not math.isfinite(self.b1):
            raise ValueError(f"the transition slope (c_mu - 1) / w overflows for c_mu = {c_mu!r}, w = {w!r}")
        check_zone_position(self.x_mu, self.w)

    @property
    def b1(self) -> float:
        """Slope of mu_bar in the transition region, (c_mu - 1) / w (eq. 42)."""
        return transition_slope(self.c_mu, self.w)

    @property
    def x_end(self) -> float:
        """End of the transition region, x_mu + w."""
        return self.x_mu + self.w

    def coefficient(self, x):
        """mu_bar(x) of eqs. (7)-(9) (:func:`coefficient`), elementwise."""
        x = np.asarray(x, dtype=float)
        values = [coefficient(xi, self.w, self.c_mu) for xi in (x - self.x_mu).ravel().tolist()]
        return np.asarray(values, dtype=float).reshape(x.shape)

    def x_stick_min(self, max_acceleration: float) -> float:
        """First position where permanent stick is possible, eq. (41) (``stick_limit``).

        Returns ``-inf`` when max|y''| <= 1 (the mass can stick anywhere) and
        ``+inf`` when max|y''| > c_mu (it can stick nowhere).
        """
        return self.x_mu + stick_limit(float(max_acceleration), self.w, self.c_mu)

    def params(self) -> dict:
        return {"kind": self.kind, "x_mu": self.x_mu, "w": self.w, "c_mu": self.c_mu}

    def __repr__(self):
        return f"StopZone(x_mu={self.x_mu!r}, w={self.w!r}, c_mu={self.c_mu!r})"

    def __eq__(self, other):
        return isinstance(other, StopZone) and self.params() == other.params()

    def __hash__(self):
        return hash((self.kind, self.x_mu, self.w, self.c_mu))


FRICTION_KINDS = ("coulomb", "static_kinetic", "stribeck")


class FrictionLaw:
    """How friction depends on the state beyond mu_bar(x): Coulomb, static/kinetic or Stribeck.

    The paper's Coulomb law is the default.  Static/kinetic friction holds a stick with
    ``mu_s_over_mu_k`` = r > 1 times the kinetic friction mu_bar(x) and slips at mu_bar(x);
    Stribeck friction also falls from r mu_bar at zero relative velocity to mu_bar as the
    relative velocity grows, over the Stribeck velocity ``v_s`` with exponent ``delta``
    (the module docstring of ``selfalign.model.friction`` has the law).  Velocities are
    dimensionless (Sect. 3.2).  A :class:`Scene` takes it as ``friction``, scene files as the
    ``friction`` block.

    Parameters
    ----------
    kind : str
        "coulomb" (the default), "static_kinetic" or "stribeck".
    mu_s_over_mu_k : float
        The ratio r >= 1 of static to kinetic friction; 1 with "coulomb".
    v_s : float or None
        The Stribeck velocity, > 0; required with "stribeck" and refused otherwise.
    delta : float
        The Stribeck exponent, > 0 (2 by default); used with "stribeck" only.

    Attributes
    ----------
    kind : str
        The kind of law.
    ratio : float
        r = mu_s / mu_k.
    v_s : float
        The Stribeck velocity (0 unless "stribeck").
    delta : float
        The Stribeck exponent (0 unless "stribeck").
    stribeck : bool
        Whether the law is Stribeck's.

    Raises
    ------
    TypeError
        If ``mu_s_over_mu_k``, ``v_s`` or ``delta`` is not a real number.
    ValueError
        If ``kind`` is unknown, r is not finite or < 1 (or not 1 with "coulomb"), or ``v_s``
        is missing with "stribeck", given with another kind, or not > 0.

    See Also
    --------
    Scene : Takes the law as ``friction``.
    positioning : Takes the law as ``friction``.

    Examples
    --------
    >>> import selfalign as sa
    >>> sa.FrictionLaw("static_kinetic", 1.3)
    FrictionLaw(kind='static_kinetic', mu_s_over_mu_k=1.3)
    >>> law = sa.FrictionLaw("stribeck", 1.3, v_s=0.1)
    >>> law.factor([0.0, 0.1, 1.0]).round(4).tolist()  # mu(v) / mu_k
    [1.3, 1.1104, 1.0]
    >>> try:
    ...     sa.FrictionLaw("static_kinetic", 0.5)
    ... except ValueError as exc:
    ...     print(exc)
    friction.mu_s_over_mu_k must be >= 1 (static friction is at least kinetic), got 0.5
    """

    def __init__(self, kind: str = "coulomb", mu_s_over_mu_k: float = 1.0, v_s: float | None = None,
                 delta: float = 2.0):
        if kind not in FRICTION_KINDS:
            raise ValueError(f"friction.kind must be one of {list(FRICTION_KINDS)}, got {kind!r}")
        ratio = check_finite("friction.mu_s_over_mu_k", mu_s_over_mu_k)
        if ratio < 1.0:
            raise ValueError(f"friction.mu_s_over_mu_k must be >= 1 (static friction is at least kinetic), "
                             f"got {mu_s_over_mu_k!r}")
        if kind == "coulomb" and ratio != 1.0:
            raise ValueError(f"friction.mu_s_over_mu_k = {mu_s_over_mu_k!r} needs kind static_kinetic or stribeck")
        if kind == "stribeck":
            if v_s is None:
                raise ValueError("friction.v_s (the Stribeck velocity) is required with kind stribeck")
            v_s = check_positive("friction.v_s", v_s)
            delta = check_positive("friction.delta", delta)
        elif v_s is not None:
            raise ValueError(f"friction.v_s is a parameter of kind stribeck, not of {kind}")
        self.kind, self.ratio = kind, ratio
        self.v_s = v_s if kind == "stribeck" else 0.0
        self.delta = float(delta) if kind == "stribeck" else 0.0

    @property
    def stribeck(self) -> bool:
        return self.kind == "stribeck"

    def factor(self, v):
        """mu(v) / mu_k: 1 (Coulomb, static/kinetic in slip) or ``stribeck_factor``, elementwise."""
        v = np.asarray(v, dtype=float)
        if not self.stribeck:
            return np.ones_like(v)
        values = [stribeck_factor(abs(u), self.ratio, self.v_s, self.delta) for u in v.ravel().tolist()]
        return np.asarray(values, dtype=float).reshape(v.shape)

    def params(self) -> dict:
        out = {"kind": self.kind}
        if self.kind != "coulomb":
            out["mu_s_over_mu_k"] = self.ratio
        if self.stribeck:
            out.update(v_s=self.v_s, delta=self.delta)
        return out

    def __repr__(self):
        return "FrictionLaw(" + ", ".join(f"{k}={v!r}" for k, v in self.params().items()) + ")"

    def __eq__(self, other):
        return isinstance(other, FrictionLaw) and self.params() == other.params()

    def __hash__(self):
        return hash(tuple(self.params().items()))
