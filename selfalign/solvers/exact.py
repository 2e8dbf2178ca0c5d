"""The exact event-driven solver (``method="exact"``): the profile rows it runs on.

Model (Sect. 3.2, eqs. 6 and 38): x'' + y''(t) in -mu_bar(x) Sign(x').  The stepping
itself is compiled (:mod:`selfalign.solvers.engine`, its tie rules and outcome
decisions are documented there); this module turns a profile into the kernel's row.

Piecewise-constant profiles (ThreePhaseProfile, PolynomialProfile, any
PiecewiseConstantProfile) are integrated in closed form between events
(:mod:`selfalign.model.arcs`): a quadratic where mu_bar is constant (eqs. 15-20), a
harmonic oscillator for forward slip in the transition zone (eqs. 42-44, omega =
sqrt(b1)), its hyperbolic counterpart for backward slip there, and stick (x constant,
eqs. 22-24).  Events, located in closed form: SWITCH (a profile break; a stuck mass
starts to slip only there), STICK / REVERSAL (v reaches 0: eq. 21; eq. 47 generalised
with atan2; the exponential form for hyperbolic arcs), ZONE (the mass crosses x_mu or
x_mu + w).  Crossing times come from quadratics in the cancellation-free "citardauq"
form; the earliest candidate within the current piece is taken.

Smooth profiles (Fourier, and the piecewise-linear y'' of a finite-jerk profile), uniform
friction only: during a slip in direction s,
x' = v0 - s (t - t0) - (y'(t) - y'(t0)) and x follows in closed form.  The events
(v = 0, and |y''| crossing 1 while stuck) are bracketed on a fixed grid of
64 (order + 1) points per period (Fourier) or the breaks and 16 points per piece
(piecewise-linear y'', where x' is a quadratic in t within a piece, so a zero of x' between
grid points is found at its minimum; on a Fourier profile what can be missed is bounded in
:func:`selfalign.solvers.engine.smooth._slip_minimum`).  They are refined with Brent's method to
|error| <= 2 eps dt + 4 eps t (eps = 2.2e-16).  A piecewise-linear row carries each piece's
end value of y'' too: y'' is kept between a piece's start and end values.
"""

from __future__ import annotations

import numpy as np

from ..model.profiles import FourierProfile, PiecewiseLinearProfile
from . import records as R


def profile_row(profile) -> tuple[int, np.ndarray]:
    """(kernel method code, profile row) of ``profile`` for the exact solver."""
    amax = profile.max_abs_acceleration
    head = R.profile_header(profile.dt, amax, profile.velocity_swing, amax)
    if isinstance(profile, FourierProfile):
        return R.EXACT_SMOOTH, R.fourier_row(head, profile.cos_coeffs, profile.sin_coeffs, profile.omega)
    if isinstance(profile, PiecewiseLinearProfile):
        return R.EXACT_SMOOTH, R.linear_row(head, profile.breaks, profile.accels, profile.jerks,
                                            profile.piece_velocity[:-1], profile.piece_position[:-1], profile.ends)
    return R.EXACT_PIECEWISE, R.piecewise_row(head, profile.breaks, profile.accels)


def piecewise_rows(breaks: np.ndarray, accels: np.ndarray, velocity: np.ndarray | None = None) -> np.ndarray:
    """Profile rows of many piecewise-constant profiles at once (vectorised sweeps).

    ``breaks`` (P, m+1) from 0 to each period, ``accels`` (P, m); zero-length pieces are
    dropped row by row, as :class:`~selfalign.model.profiles.PiecewiseConstantProfile`
    does.  ``velocity`` (P, m+1): y' at the breaks (for the velocity swing); if None it is
    integrated from 0 (the swing does not depend on the start value).
    """
    breaks, accels = np.atleast_2d(breaks).astype(float), np.atleast_2d(accels).astype(float)
    lengths = np.diff(breaks, axis=1)
    if velocity is None:
        velocity = np.concatenate([np.zeros((breaks.shape[0], 1)), np.cumsum(accels * lengths, axis=1)], axis=1)
    dt = breaks[:, -1]
    amax = np.max(np.abs(accels), axis=1)
    swing = np.ptp(velocity, axis=1)
    keep = lengths > 0.0
    m = keep.sum(axis=1)
    mmax = int(m.max()) if m.size else accels.shape[1]
    width = R.col_level(mmax, mmax)
    rows = np.full((breaks.shape[0], width), np.nan)
    rows[:, R.DT], rows[:, R.AMAX], rows[:, R.SWING], rows[:, R.REST_ACC] = dt, amax, swing, amax
    rows[:, R.DATA] = m
    if np.all(keep):
        k = accels.shape[1]
        rows[:, R.col_break(0):R.col_break(k + 1)] = breaks
        rows[:, R.col_level(k, 0):R.col_level(k, k)] = accels
        return rows
    for i in range(breaks.shape[0]):
        b = np.concatenate([breaks[i, :1], breaks[i, 1:][keep[i]]])
        a = accels[i][keep[i]]
        rows[i, R.col_break(0):R.col_break(a.size + 1)] = b
        rows[i, R.col_level(a.size, 0):R.col_level(a.size, a.size)] = a
    return rows
