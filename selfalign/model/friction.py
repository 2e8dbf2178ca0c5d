"""Friction fields mu_bar(x) of the table surface (Sect. 3.3, eqs. 7-9) and the stick rule.

Coefficients are dimensionless: the low-friction coefficient mu is the unit
(Sect. 3.2), so the uniform surface has mu_bar = 1.  Positions in the formulas are
relative to the start of the high-friction region, xi = x - x_mu.

The scalar formulas (:func:`coefficient`, :func:`decide_mode`, :func:`stick_limit`)
are the only place the friction law is written; the classes below and the compiled
event kernel call them.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import check_finite, check_positive
from .registry import formula


@formula
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


@formula
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


@formula
def stick_limit(max_acceleration: float, w: float, c_mu: float) -> float:
    """x_stick_min - x_mu of eq. (41): where mu_bar first reaches max|y''| (eq. 40).

    ``-inf`` when max|y''| <= 1 (the mass can stick anywhere) and ``+inf`` when
    max|y''| > c_mu (it can stick nowhere for good).
    """
    if max_acceleration <= 1.0:
        return -math.inf
    if max_acceleration > c_mu:
        return math.inf
    return w * (max_acceleration - 1.0) / (c_mu - 1.0)


class Uniform:
    """Uniform Coulomb friction, mu_bar(x) = 1 everywhere."""

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
    x_mu + w (eq. 9) and stays there.
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

    @property
    def b1(self) -> float:
        """Slope of mu_bar in the transition region, (c_mu - 1) / w (eq. 42)."""
        return (self.c_mu - 1.0) / self.w

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
        """First position where permanent stick is possible, eq. (41) (:func:`stick_limit`).

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
