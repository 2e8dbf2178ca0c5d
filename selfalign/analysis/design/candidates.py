"""The design grid and the scaling of an SI design to the model at a friction coefficient mu
(Sect. 3.2; the package docstring)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...model.design_spec import DesignSpec
from ...model.friction import FrictionLaw
from ...model.units import SIScale


@dataclass(frozen=True)
class Candidates:
    """Designs in SI as flat arrays: period [s], stroke [m], y2, y3 [m/s^2], c_mu."""

    period: np.ndarray
    stroke: np.ndarray
    y2: np.ndarray
    y3: np.ndarray
    c_mu: np.ndarray

    def take(self, index) -> Candidates:
        return Candidates(*(getattr(self, k)[index] for k in ("period", "stroke", "y2", "y3", "c_mu")))

    def __len__(self) -> int:
        return self.period.size


def search_grid(spec: DesignSpec) -> Candidates:
    """Every design of the search grid (:class:`~selfalign.model.design_spec.DesignGrid`)."""
    g = spec.grid
    lo, hi = spec.period
    periods = np.geomspace(lo, hi, g.periods) if lo < hi else np.array([lo])
    if spec.min_stroke is None:
        strokes = spec.max_stroke * np.arange(1, g.strokes + 1) / g.strokes
    else:
        strokes = np.unique(np.linspace(spec.min_stroke, spec.max_stroke, g.strokes))
    accels = spec.max_acceleration * np.arange(1, g.accelerations + 1) / g.accelerations
    c_values = np.array([spec.c_mu[0]]) if spec.c_mu_fixed else np.linspace(*spec.c_mu, g.c_mu)
    mesh = np.meshgrid(periods, strokes, accels, accels, c_values, indexing="ij")
    return Candidates(*(a.ravel() for a in mesh))


def scale(spec: DesignSpec, mu: float) -> SIScale:
    """The SI scale of the model at friction coefficient ``mu`` (L = the part's width)."""
    return SIScale(mu=float(mu), g=spec.g, L=spec.width)


def dimensionless(spec: DesignSpec, cand: Candidates, mu: float):
    """(dt, dy, y2, y3) of the SI designs as the model sees them at ``mu``."""
    s = scale(spec, mu)
    return (cand.period / s.T, cand.stroke / s.L, cand.y2 / s.unit("acceleration"),
            cand.y3 / s.unit("acceleration"))


def mu_values(spec: DesignSpec, n: int) -> np.ndarray:
    lo, hi = spec.mu_range
    return np.linspace(lo, hi, n) if hi > lo else np.full(n, lo)


def friction_at(spec: DesignSpec, mu: float) -> FrictionLaw:
    """The spec's friction law as the model sees it at ``mu``: its Stribeck velocity (m/s in the
    spec) in the velocity unit sqrt(mu g L)."""
    law = spec.friction
    if not law.stribeck:
        return law
    return FrictionLaw("stribeck", law.ratio, v_s=law.v_s / scale(spec, mu).unit("velocity"), delta=law.delta)


def ramp_at(spec: DesignSpec, mu: float) -> float:
    """The spec's y'' ramp time in the time unit T(mu) (0 for the paper's jumps)."""
    return 0.0 if spec.ramp is None else spec.ramp / scale(spec, mu).T
