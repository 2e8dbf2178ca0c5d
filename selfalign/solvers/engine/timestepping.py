"""Moreau time-stepping (Sect. 5.2) with the table impulse of each step integrated exactly
(:mod:`selfalign.solvers.moreau`): the step's impulse solved exactly (soft threshold) or by the
paper's fixed-point iteration, and Stribeck friction solved per step.
"""

from __future__ import annotations

import math

from ...model import friction as F
from .. import records as R
from ..outcomes import HIGH, LOW, ZONE
from .codes import ARC_SMOOTH, DONE, EPS
from .compiled import jit
from .field import friction_at, next_boundary, on_stick, record_crossings, stop_at
from .recording import record_sample

#: Relaxation r of the paper's fixed-point iteration, in units of the friction bound h mu_bar:
#: s <- proj_[-1,1](s + r v_{k+1}(s)) with r = FP_RELAXATION / (h mu_bar), a contraction
#: with factor |1 - FP_RELAXATION| = 1/2 (1 would reach the soft threshold in one sweep).
FP_RELAXATION = 0.5


@jit
def _impulse(s, v_free, bound, fixed_point, fp_tol, fp_max_iter):
    """v_{k+1} = v* - bound s, s in Sign(v_{k+1}): exactly (the soft threshold of v* by
    bound) or by the paper's fixed-point iteration on the multiplier s."""
    if not fixed_point:
        if v_free > bound:
            return v_free - bound
        if v_free < -bound:
            return v_free + bound
        return 0.0
    m = 0.0
    r = FP_RELAXATION / bound
    change = 0.0
    converged = False
    for it in range(1, fp_max_iter + 1):
        m_new = min(1.0, max(-1.0, m + r * (v_free - bound * m)))
        change = abs(bound * (m_new - m))
        m = m_new
        s.fp_iterations += 1
        if change <= fp_tol:
            converged = True
            break
    if not converged:
        s.fp_unconverged += 1
        s.fp_max_change = max(s.fp_max_change, change)
    if abs(m) >= 1.0:
        return v_free - bound * m
    return 0.0


@jit
def _stribeck_speed(u, bound, ratio, v_s, delta):
    """The slip speed c > 0 of an implicit Moreau step under Stribeck friction: the root of
    c + bound f(c) = u, f = :func:`~selfalign.model.friction.stribeck_factor`, for a free
    speed u > bound r (else the step sticks).  f(0) = r and f >= 1 bracket it in
    (0, u - bound]; Newton's method kept inside the bracket (bisection where a Newton step
    leaves it) refines it to rounding.  The root is unique while h mu_bar max|f'| < 1."""
    lo = 0.0
    hi = u - bound
    c = hi
    for _ in range(200):
        e = F.stribeck_decay(c, v_s, delta) if c > 0.0 else 1.0
        g = c + bound * F.stribeck_factor(c, ratio, v_s, delta) - u
        if g == 0.0:
            return c
        if g > 0.0:
            hi = c
        else:
            lo = c
        slope = 1.0 - bound * (ratio - 1.0) * e * delta * (c / v_s) ** delta / c if c > 0.0 else 0.0
        c_new = c - g / slope if slope > 0.0 else 0.5 * (lo + hi)
        if not lo < c_new < hi:
            c_new = 0.5 * (lo + hi)
        if c_new == c or hi - lo <= 4.0 * EPS * hi:
            return c_new
        c = c_new
    return c


@jit
def _step_region(s, x):
    if not s.zone or x <= 0.0:
        return LOW
    return HIGH if x >= s.w else ZONE


@jit
def _richer_friction_step(s, v, v_free, h_mu, fixed_point, fp_tol, fp_max_iter):
    """The implicit friction step of a Moreau step under static/kinetic or Stribeck friction
    (mu_s / mu_k = r > 1 or v_s > 0): stick while the free velocity ``v_free`` stays in the window
    r h mu_bar of a mass that is stuck or comes to rest; else slip against h mu_bar, times f(v) of
    :func:`~selfalign.model.friction.stribeck_factor` for Stribeck friction."""
    r_static = s.static_ratio
    if r_static > 1.0 and v_free * v <= 0.0 and abs(v_free) <= h_mu * r_static:
        return 0.0                      # static friction holds a mass that is stuck or comes to rest
    if s.v_s > 0.0:
        if abs(v_free) <= h_mu * r_static:
            return 0.0
        return math.copysign(_stribeck_speed(abs(v_free), h_mu, r_static, s.v_s, s.delta), v_free)
    return _impulse(s, v_free, h_mu, fixed_point, fp_tol, fp_max_iter)


@jit
def period_moreau(s, row, run, bnd, cross, record, buffers, scratch, periods):
    """Advance member ``s`` one period with N Moreau steps (:mod:`selfalign.solvers.moreau`)."""
    until, fixed_point, fp_tol, fp_max_iter = run.until, run.fixed_point, run.fp_tol, run.fp_max_iter
    samples, sample_steps = buffers[2], buffers[3]
    dt = row[R.DT]
    nsteps = R.data_size(row)
    h = row[R.MOREAU_STEP]
    largest = row[R.MOREAU_LARGEST]
    half = 0.5 * h
    tau0 = s.tau0
    xi, v, n = s.xi, s.v, s.n
    r_static = s.static_ratio      # stick window r h mu_bar; slip against h mu_bar (Stribeck: h mu_bar f(v))
    # The paper's law takes the step of :func:`_impulse` alone; the richer laws are a separate
    # call so that they add nothing to the loop of the Coulomb step.
    coulomb = r_static == 1.0 and not s.v_s > 0.0
    dxp = 0.0
    lo = 0.0
    hi = 0.0
    regions = 0
    s.fresh = False
    nxt = 0            # next dense-output sample (index into sample_steps)
    lowest = next_boundary(bnd, cross)
    k = 0
    while k < nsteps:
        if v == 0.0:
            # Stuck: a step is the identity while |impulse| <= h mu_bar (v* = -impulse lies in
            # the stick window), so jump to the first step that can start a slip.
            bound = h * friction_at(s, s.zone, xi) * r_static
            k_next = k
            while k_next < nsteps and abs(row[R.col_impulse(k_next)]) <= bound:
                k_next += 1
            regions |= 1 << _step_region(s, xi)
            if record:
                while nxt < sample_steps.shape[0] and sample_steps[nxt] < k_next:
                    record_sample(samples, s, n, tau0 + sample_steps[nxt] * h, xi, 0.0, 0)
                    nxt += 1
            k = k_next
            if k >= nsteps:
                break
        if record and nxt < sample_steps.shape[0] and sample_steps[nxt] == k:
            record_sample(samples, s, n, tau0 + k * h, xi, v, (v > 0.0) - (v < 0.0))
            nxt += 1
        x_mid = xi + half * v
        mu = friction_at(s, s.zone, x_mid)
        regions |= 1 << _step_region(s, x_mid)
        v_free = v - row[R.col_impulse(k)]
        if coulomb:
            v_new = _impulse(s, v_free, h * mu, fixed_point, fp_tol, fp_max_iter)
        else:
            v_new = _richer_friction_step(s, v, v_free, h * mu, fixed_point, fp_tol, fp_max_iter)
        x_new = x_mid + half * v_new
        s.steps += 1
        dx = x_new - xi
        dxp += dx
        if dxp > hi:
            hi = dxp
        elif dxp < lo:
            lo = dxp
        s.path += abs(dx)
        s.xi_max = max(s.xi_max, x_new)
        if x_new >= lowest:
            lowest = record_crossings(s, bnd, cross, ARC_SMOOTH, 0.0, xi, v, 0.0, x_new, v_new, n, tau0 + k * h, h)
        was_moving = v != 0.0
        xi, v = x_new, v_new
        k += 1
        if v == 0.0 and was_moving:
            mu_x = friction_at(s, s.zone, xi)
            code = on_stick(s, xi, mu_x, n, tau0 + k * h, until, h * mu_x * r_static >= largest)
            if code != DONE:
                s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, regions
                return stop_at(s, code, xi, 0.0, 0, n, tau0 + k * h, dt)
    s.xi, s.v, s.n = xi, v, n + 1
    s.mode = (v > 0.0) - (v < 0.0)
    s.dxp, s.lo, s.hi, s.regions = dxp, lo, hi, regions
    return DONE
