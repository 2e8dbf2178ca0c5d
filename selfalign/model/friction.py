"""Friction fields mu_bar(x) of the table surface (Sect. 3.3, eqs. 7-9).

Coefficients are dimensionless: the low-friction coefficient mu is the unit
(Sect. 3.2), so the uniform surface has mu_bar = 1.
"""

from __future__ import annotations

import numpy as np

from .errors import check_finite, check_positive


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

    @property
    def b1(self) -> float:
        """Slope of mu_bar in the transition region, (c_mu - 1) / w (eq. 42)."""
        return (self.c_mu - 1.0) / self.w

    @property
    def x_end(self) -> float:
        """End of the transition region, x_mu + w."""
        return self.x_mu + self.w

    def coefficient(self, x):
        """mu_bar(x) of eqs. (7)-(8)."""
        z = np.clip(np.asarray(x, dtype=float) - self.x_mu, 0.0, self.w)  # eq. (8)
        return 1.0 + (self.c_mu - 1.0) * z / self.w  # eq. (7) with mu = 1

    def x_stick_min(self, max_acceleration: float) -> float:
        """First position where permanent stick is possible, eq. (41).

        Returns ``-inf`` when max|y''| <= 1 (the mass can stick anywhere) and
        ``+inf`` when max|y''| > c_mu (it can stick nowhere).
        """
        if max_acceleration <= 1.0:
            return -np.inf
        if max_acceleration > self.c_mu:
            return np.inf
        return self.x_mu + self.w * (max_acceleration - 1.0) / (self.c_mu - 1.0)

    def params(self) -> dict:
        return {"kind": self.kind, "x_mu": self.x_mu, "w": self.w, "c_mu": self.c_mu}

    def __repr__(self):
        return f"StopZone(x_mu={self.x_mu!r}, w={self.w!r}, c_mu={self.c_mu!r})"
