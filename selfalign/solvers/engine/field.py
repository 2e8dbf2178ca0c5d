"""The friction field (eqs. 7-9) and the stick outcomes every stepper shares: mu_bar at x, the
region of an arc, whether a stuck mass is held for good, the bookkeeping of a stick event
(REST, ACCUMULATION, FIRST_STICK), boundary crossings, and the period running totals.
"""

from __future__ import annotations

import math

from ...model import arcs as A
from ...model import friction as F
from .. import records as R
from ..outcomes import HIGH, LOW, ZONE
from .codes import ARC_SMOOTH, ARC_STICK, DONE, INF, STOP_ACCUMULATION, STOP_FIRST_STICK, STOP_NONFINITE, STOP_REST
from .compiled import inlined, jit
from .recording import normalised_time


@jit
def friction_at(s, zone, xi):
    """mu_bar at xi (eqs. 7-9; 1 on a uniform surface).  ``zone``: whether the member's surface
    is a stop zone, ``s.zone`` or a compile-time constant where a stepper is specialised on it."""
    if not zone:
        return 1.0
    return F.coefficient(xi, s.w, s.c_mu)


@jit
def region_of(s, zone, xi, mode):
    """Region of an arc starting at xi in ``mode`` (tie rule 5); ``zone`` as in :func:`friction_at`."""
    if not zone:
        return LOW
    if xi < 0.0 or (xi == 0.0 and mode <= 0):
        return LOW
    if xi > s.w or (xi == s.w and mode >= 0):
        return HIGH
    return ZONE


@jit
def holds_for_good(s, mu):
    """Whether friction mu_bar holds a stuck mass for good: r mu_bar >= max|y''| (exact
    solvers; r = mu_s / mu_k, 1 for the paper's Coulomb law).  Moreau passes its own test,
    the step's (:func:`period_moreau`)."""
    return s.static_ratio * mu >= s.rest_acc


@jit
def on_stick(s, xi, mu, n, tau, until, holds):
    """Bookkeeping at a stick event at xi (friction mu); a non-zero result ends the run.

    REST where ``holds`` (the friction holds the mass for good, :func:`holds_for_good`);
    ACCUMULATION (until='rest') at a stick in the transition zone above the previous one
    and within acc_tol of x_stick_min; FIRST_STICK for until='stick'.
    """
    s.sticks += 1
    if s.zone and xi >= 0.0:
        s.zone_sticks += 1
        if s.first_stick_n < 0:
            s.first_stick_xi, s.first_stick_n, s.first_stick_tau = xi, n, tau
    if holds:
        s.at_rest = True
        if until != R.UNTIL_PERIODS:
            return STOP_REST
        return DONE
    if until == R.UNTIL_REST and s.zone and 0.0 <= xi <= s.w:
        if s.nh >= 1 and xi > s.h1 and s.xs - xi <= s.acc_tol:
            if s.nh >= 2 and s.h1 > s.h2:
                s.contraction = (xi - s.h1) / (s.h1 - s.h2)
            s.last_stick = xi
            return STOP_ACCUMULATION
        s.h2 = s.h1
        s.h1 = xi
        s.nh = min(s.nh + 1, 2)
    if until == R.UNTIL_STICK:
        return STOP_FIRST_STICK
    return DONE


@inlined
def next_boundary(bnd, cross):
    """The lowest boundary not crossed yet (inf if none): an arc that ends below it crosses
    nothing, so the steppers call :func:`record_crossings` only for an arc that reaches it."""
    lowest = INF
    for j in range(bnd.shape[0]):
        if cross[j].period < 0 and bnd[j] < lowest:     # NaN: a boundary that does not exist
            lowest = bnd[j]
    return lowest


@jit
def record_crossings(s, bnd, cross, kind, om, xi0, v0, acc0, xi1, v1, n, tau, dur):
    """First crossings of the boundaries ``bnd`` by an arc from (xi0, v0) to (xi1, v1) of
    duration ``dur`` starting at (n, tau): the time in closed form on exact arcs, at the
    step end on smooth arcs and Moreau steps.  Returns the next boundary (:func:`next_boundary`)."""
    for j in range(bnd.shape[0]):
        c = cross[j]
        if c.period >= 0 or not xi1 >= bnd[j]:      # NaN: a boundary that does not exist
            continue
        if xi0 >= bnd[j]:
            sc, vc = 0.0, v0
        elif kind == ARC_SMOOTH or kind == ARC_STICK:
            sc, vc = dur, v1
        else:
            sc = min(A.crossing_time(kind, om, v0, acc0, xi0 - bnd[j]), dur)
            vc = v1 if sc == dur else A.step(kind, om, v0, acc0, sc)[1]
        c.period = n
        c.tau = tau + sc
        c.v = vc
        c.sticks = s.zone_sticks
    return next_boundary(bnd, cross)


@jit
def load_period(s):
    """(x, v, mode, period, events, path, xi_max) of the member record at a period start, and
    zeroed running totals of the period (dxp, lo, hi, regions, stalled): :func:`save_period`'s inverse."""
    return s.xi, s.v, s.mode, s.n, s.events, s.path, s.xi_max, 0.0, 0.0, 0.0, 0, 0


@jit
def save_period(s, events, path, xi_max, dxp, lo, hi, regions):
    """Write a period's running totals back to the member record."""
    s.events, s.path, s.xi_max = events, path, xi_max
    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, regions


@jit
def stop_at(s, code, xi, v, mode, n, tau, dt):
    """Stop inside a period with result ``code`` at state (xi, v, mode) and time (n, tau)."""
    s.xi, s.v, s.mode = xi, v, mode
    s.stop_n, s.stop_tau = normalised_time(n, tau, dt)
    return code


@jit
def stop_nonfinite(s, xi, v, mode, n):
    """Stop with STOP_NONFINITE at the last finite state, (xi, v, mode) at the start (n, tau0) of
    the period in which x or v stopped being finite."""
    s.xi, s.v, s.mode, s.n = xi, v, mode, n
    s.stop_n, s.stop_tau = n, s.tau0
    return STOP_NONFINITE


@jit
def stop_in_period(s, start, code, xi, v, mode, n, tau, dt):
    """:func:`stop_at` for a stepper that advances several periods per call: ``start`` is
    (xi, v, mode, n) at the start of the current period n, the state :func:`stop_nonfinite`
    goes back to if (xi, v) is not finite."""
    if not (math.isfinite(xi) and math.isfinite(v)):
        return stop_nonfinite(s, start[0], start[1], start[2], start[3])
    s.n = start[3]
    return stop_at(s, code, xi, v, mode, n, tau, dt)
