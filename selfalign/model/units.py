"""Conversion between SI units and the dimensionless model of Sect. 3.2.

With a characteristic length L and T = sqrt(L / (mu g)) (Sect. 3.2):
x = x~ / L, t = t~ / T, so velocities scale by L / T and accelerations by
L / T^2 = mu g.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import check_positive


@dataclass(frozen=True)
class SIScale:
    """Friction coefficient ``mu``, gravity ``g`` [m/s^2] and length scale ``L`` [m].

    The conversion between SI units and the dimensionless model of Sect. 3.2: with the
    characteristic length L and time T = sqrt(L / (mu g)), x = x~ / L and t = t~ / T, so
    velocities scale by L / T and accelerations by L / T^2 = mu g.  A quantity of dimension
    length^a time^b has the unit L^a T^b (``DIMENSIONS``); every unit must be a finite
    positive double, so that conversions never divide by 0.  Scene files in SI units
    (``units: si``) are converted with it.

    Parameters
    ----------
    mu : float
        The (low) friction coefficient; > 0.
    g : float
        Gravitational acceleration [m/s^2]; > 0.
    L : float
        Characteristic length [m]; > 0.

    Attributes
    ----------
    mu : float
        The friction coefficient.
    g : float
        Gravitational acceleration [m/s^2].
    L : float
        Characteristic length [m].
    T : float
        Characteristic time sqrt(L / (mu g)) [s].
    DIMENSIONS : dict
        Dimension exponents (length, time) of each kind of quantity: "length", "time",
        "velocity", "acceleration", "jerk" and "dimensionless".

    Raises
    ------
    TypeError
        If ``mu``, ``g`` or ``L`` is not a real number.
    ValueError
        If one of them is not finite and > 0, or if they give no finite positive unit of some
        kind of quantity (a scale too far from the problem's).

    See Also
    --------
    Scene : Carries the SI scale of a scene file in ``si``.

    Examples
    --------
    A plastic part 2 mm wide on steel, mu = 0.2:

    >>> import selfalign as sa
    >>> si = sa.SIScale(mu=0.2, g=9.81, L=2e-3)
    >>> print(f"T = {si.T:.6f} s, acceleration unit {si.unit('acceleration'):.4f} m/s^2")
    T = 0.031928 s, acceleration unit 1.9620 m/s^2
    >>> print(round(si.to_dimensionless(4.0, "acceleration"), 6), round(si.to_si(1.05, "time"), 6))
    2.038736 0.033524
    """

    mu: float
    g: float
    L: float

    def __post_init__(self):
        for name in ("mu", "g", "L"):
            check_positive(f"si.{name}", getattr(self, name))
        for kind in self.DIMENSIONS:   # every unit a finite positive double, so conversions never divide by 0
            try:
                unit = self.unit(kind)
            except (OverflowError, ZeroDivisionError):
                unit = math.nan
            if not (math.isfinite(unit) and unit > 0.0):
                raise ValueError(f"si: mu = {self.mu!r}, g = {self.g!r}, L = {self.L!r} give no finite unit of {kind} "
                                 f"(L^a (L / (mu g))^(b/2), Sect. 3.2); choose a scale nearer the problem's")

    @property
    def T(self) -> float:
        """Characteristic time sqrt(L / (mu g)) [s]."""
        return math.sqrt(self.L / (self.mu * self.g))

    #: dimension exponents (length, time) of each kind of quantity
    DIMENSIONS = {"length": (1, 0), "time": (0, 1), "velocity": (1, -1),
                  "acceleration": (1, -2), "jerk": (1, -3), "dimensionless": (0, 0)}

    def unit(self, kind: str) -> float:
        """The SI value of one dimensionless unit of ``kind``."""
        try:
            length, time = self.DIMENSIONS[kind]
        except KeyError:
            raise ValueError(f"unknown quantity kind {kind!r}; allowed: {sorted(self.DIMENSIONS)}") from None
        return self.L**length * self.T**time

    def to_dimensionless(self, value, kind: str):
        return value / self.unit(kind)

    def to_si(self, value, kind: str):
        return value * self.unit(kind)

    def params(self) -> dict:
        return {"mu": self.mu, "g": self.g, "L": self.L, "T": self.T}
