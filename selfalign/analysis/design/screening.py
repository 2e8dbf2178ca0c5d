"""Closed-form screening of the candidates at every mu of a dense sample (the package docstring,
"Search"), their ranking by a closed-form process time and the robustness margin."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model.design_spec import DENSE_MU, DesignSpec
from ...model.friction import stick_limits, transition_slope
from ...model.profiles import (
    three_phase_feasibility,
    three_phase_times,
)
from ..steady_state import steady_state_grid
from .candidates import Candidates, dimensionless, mu_values, scale

#: Relative mu deviations at which the robustness margin is evaluated (closed forms).
MARGIN_STEPS = np.linspace(0.0, 0.96, 49)


def stick_offset(spec: DesignSpec, cand: Candidates, mu: float) -> np.ndarray:
    """x_stick_min - x_mu (eq. 41, :data:`~selfalign.model.friction.stick_limits`) at ``mu``, in m."""
    rest_acceleration = scale(spec, mu).to_dimensionless(np.maximum(cand.y2, cand.y3), "acceleration")
    return stick_limits(rest_acceleration, spec.width, cand.c_mu)


def end_spread(spec: DesignSpec, cand: Candidates) -> np.ndarray:
    """Half the range of x_stick_min (eq. 41) over the mu range, in m: the robust positioning
    error of a design whose entries all accumulate (inf where the strip cannot hold the part)."""
    lo, hi = spec.mu_range
    with np.errstate(invalid="ignore"):
        spread = 0.5 * (stick_offset(spec, cand, lo) - stick_offset(spec, cand, hi))
    return np.where(np.isnan(spread), np.inf, spread)


@dataclass(frozen=True)
class Screen:
    """Closed-form conditions per candidate over the dense mu sample (see the module docstring).

    ``physical``, ``holds`` (the strip can hold the part at every mu), ``moves`` (forward at
    every mu; evaluated only where it holds, False elsewhere), ``shape`` (y2'' > y3'' where
    accumulation is asked for, else True), ``within`` (x_stick_min moves by at most the
    tolerance, accumulation only, else True); ``ok``: all
    of these; ``short_slip``: omega (t2 - t1) < pi / 2 at mu_max, omega = sqrt((c_mu - 1) mu g / w),
    necessary for the sufficient condition of Sect. 7.3 (cos(omega (t2 - t1)) > (y2'' - mu g) /
    (2 (y2'' + y3'')) > 0, eq. 59) and used to order the candidates, not to exclude any;
    ``vbar_min`` [m/s] the slowest steady state over mu; ``t_estimate`` [s] = (D + x_stick_min(mu_max)
    - tolerance) / vbar_min, the closed-form process time.
    """

    physical: np.ndarray
    moves: np.ndarray
    holds: np.ndarray
    shape: np.ndarray
    within: np.ndarray
    short_slip: np.ndarray
    vbar_min: np.ndarray
    t_estimate: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        return self.physical & self.moves & self.holds & self.shape & self.within


def _moves_and_holds(spec: DesignSpec, cand: Candidates, mus) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(moves at every mu, holds at every mu, slowest vbar [m/s]; -inf where it does not move or
    hold) of the physical candidates.  The extremes of ``mus`` come first and each mu evaluates
    only the candidates still alive, so most are dropped after one or two."""
    holds = stick_offset(spec, cand, float(np.min(mus))) < np.inf  # mu_bar >= max |y''| somewhere
    moves = holds.copy()
    vbar_min = np.where(holds, np.inf, -np.inf)
    mus = np.asarray(mus, dtype=float)
    ordered = np.concatenate([[mus.max(), mus.min()], mus[(mus != mus.max()) & (mus != mus.min())]])
    for mu in ordered:
        alive = np.flatnonzero(moves)
        if alive.size == 0:
            break
        ss = steady_state_grid(*dimensionless(spec, cand.take(alive), mu))
        v = ss.vbar * scale(spec, mu).unit("velocity")
        ok = (ss.case > 0) & (v > 0)
        moves[alive] = ok
        vbar_min[alive] = np.where(ok, np.minimum(vbar_min[alive], v), -np.inf)
    return moves, holds, vbar_min


def screen(spec: DesignSpec, cand: Candidates) -> Screen:
    """The closed-form conditions of every candidate (:class:`Screen`)."""
    physical = three_phase_feasibility(cand.period, cand.stroke, cand.y2, cand.y3) <= 1.0  # mu-free (q)
    n = len(cand)
    moves, holds, vbar_min = np.zeros(n, bool), np.zeros(n, bool), np.full(n, np.nan)
    idx = np.flatnonzero(physical)
    m, h, v = _moves_and_holds(spec, cand.take(idx), mu_values(spec, DENSE_MU))
    moves[idx], holds[idx], vbar_min[idx] = m, h, v
    shape = cand.y2 > cand.y3 if spec.accumulation else np.ones(n, bool)
    within = end_spread(spec, cand) <= spec.tolerance if spec.accumulation else np.ones(n, bool)
    # A lower bound of the process time: the part covers the distance and, in the strip, at least
    # x_stick_min (eq. 41) at mu_max less the tolerance, at no more than the slowest steady speed.
    inside = np.zeros(n)
    inside[moves] = stick_offset(spec, cand.take(moves), spec.mu_range[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        t_est = np.where(moves, (spec.distance + np.maximum(inside - spec.tolerance, 0.0)) / vbar_min, np.inf)
    return Screen(physical, moves, holds, shape, within, slip_phase(spec, cand) < 0.5 * math.pi, vbar_min, t_est)


def slip_frequency(spec: DesignSpec, c_mu):
    """omega = sqrt(b1) / T = sqrt((c_mu - 1) mu g / w) in rad/s at mu_max: the frequency of the
    harmonic slip of Sect. 7.3 (eq. 42) in the strip (b1 with the part's width as the unit of length)."""
    return np.sqrt(transition_slope(np.asarray(c_mu, dtype=float), 1.0)) / scale(spec, spec.mu_range[1]).T


def slip_phase(spec: DesignSpec, cand: Candidates) -> np.ndarray:
    """omega (t2 - t1) at mu_max (:func:`slip_frequency`): the phase of the harmonic slip over the
    y2'' window (the Appendix's times are scale-free)."""
    times = three_phase_times(cand.period, cand.stroke, cand.y2, cand.y3)
    return slip_frequency(spec, cand.c_mu) * (times.t2 - times.t1)


def robustness_margin(spec: DesignSpec, cand: Candidates) -> np.ndarray:
    """Largest relative deviation d (on :data:`MARGIN_STEPS`) such that the closed-form
    conditions (forward motion, a strip that holds, y2'' > y3'' with accumulation) hold at
    every mu in [mu (1 - d), mu (1 + d)] (``mu`` the spec's nominal value)."""
    margin = np.full(len(cand), -1.0)
    alive = np.ones(len(cand), bool)
    if spec.accumulation:
        alive &= cand.y2 > cand.y3
    for d in MARGIN_STEPS:
        idx = np.flatnonzero(alive)
        if idx.size == 0:
            break
        m, h, _ = _moves_and_holds(spec, cand.take(idx), np.array([spec.mu * (1 - d), spec.mu * (1 + d)]))
        alive[idx] = m & h
        margin[alive] = d
    return margin
